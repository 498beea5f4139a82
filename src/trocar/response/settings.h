#pragma once
/// Collision-response settings and the method switch (scene key `response`, docs/scene.md
/// "collision and response", docs/response.md).
#include <cstdint>
#include <optional>
#include <string_view>

#include "trocar/core/types.h"

namespace trocar {

/// Which response computes the depth (scene `response.method`; docs/response.md).
enum class ResponseMethod : std::uint8_t {
  kObb,        ///< "obb": the seed's response, docs/response.md steps 1–10 (OBB depth PD, D)
  kPrimitive,  ///< "primitive": depth of the instrument triangle's deepest vertex below the tissue
               ///< plane (the two triangles alone); force along n_in and the tissue triangle
               ///< moved apart by that depth (position correction), primitive by primitive
  kNormal,     ///< "normal": depth of the instrument's deepest vertex along n_in; force along n_in
  kProject,    ///< "project": the seed's D as a force and also as a position correction
  /// "sdf" (the default): contact as a position constraint against the instrument's own signed
  /// distance, with friction, after the tissue's integration (response/contact_projection.h);
  /// no penalty force enters the tissue's solve. The reported force is the constraint's.
  kSdf,
};

/// "obb", "primitive", "normal", "project" or "sdf".
const char* response_method_name(ResponseMethod method);
/// The method named `name` (exact, lower case), or nothing.
std::optional<ResponseMethod> parse_response_method(std::string_view name);

/// Parameters of the response methods (scene key `response`; docs/scene.md "collision and
/// response" lists the defaults).
struct ResponseSettings {
  /// See ResponseMethod. sdf: of the methods, the most runs of the robustness suite within the
  /// contact targets and the step budget (docs/robustness.md); the shipped scenes name theirs.
  ResponseMethod method = ResponseMethod::kSdf;
  Real stiffness = 2000;       ///< K in eq. 3.9 (N/m)
  Real damping = 5;            ///< μ in eq. 3.9 (N·s/m)
  Real max_force = 10;         ///< clamp on |instrument force| for the device (N); ≤ 0: no clamp
  /// Below this relative speed at P (m/s) the contact is resting and D is PD projected on n_in.
  Real resting_speed = 1e-6;
  /// Jaw closure (0..1) at or above which jaw triangles grasp the tissue they touch.
  Real grasp_closure = 0.9;
  bool pierce_filter = true;   ///< step 9: discard contacts whose tissue has the top vertex inside
  /// obb and project: cap |D| at the instrument triangle's depth below the tissue plane, so the
  /// force falls to zero as the contact opens (docs/response.md "Depth cap"); false runs the
  /// seed's step 7 verbatim, whose force jumps from 0 to K·(distance to the box's side) at first
  /// touch and makes a held instrument chatter.
  bool depth_cap = true;
  /// project and primitive: the position correction is scaled by
  /// clamp(v_instrument·n_in / correction_speed, 0, 1), v_instrument the instrument's own
  /// velocity at P, so a resting or withdrawing instrument is answered by the penalty force
  /// alone (which settles) and one driving into the tissue at ≥ correction_speed also projects
  /// the tissue out (docs/response.md "Gated correction"). m/s; 0: always the full correction
  /// (the ungated baseline, which chatters under a held instrument).
  Real correction_speed = 0.05;
  /// sdf: the skin (m) the tissue is kept outside the instrument's surface.
  Real contact_margin = 5e-5;
  /// sdf: static friction coefficient μs (tangential motion relative to the instrument is removed
  /// while it is ≤ μs × the normal correction); 0 turns friction off.
  Real friction_static = 0.6;
  /// sdf: rounds of the face pushes and the vertex projection after the first projection (≥ 1).
  int projection_rounds = 3;
  /// sdf: kinetic friction coefficient μk (sliding motion shortened by μk × the normal correction).
  Real friction_kinetic = 0.6;
};

}  // namespace trocar
