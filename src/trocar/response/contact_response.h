#pragma once
/// The per-contact kernel of the seed's collision response (steps 1–9 of docs/response.md "The
/// kernel, step by step").
#include <array>
#include <cstdint>
#include <span>

#include "trocar/core/obb.h"
#include "trocar/core/types.h"
#include "trocar/response/settings.h"

namespace trocar {

/// One instrument triangle A and one tissue triangle B, world frame, with vertex velocities.
struct ContactTriangles {
  std::array<Vec3, 3> a;   ///< instrument triangle A1 A2 A3 (m)
  std::array<Vec3, 3> va;  ///< velocities of A's vertices (m/s)
  std::array<Vec3, 3> b;   ///< tissue triangle B1 B2 B3, counter-clockwise seen from outside (m)
  std::array<Vec3, 3> vb;  ///< velocities of B's vertices (m/s)
};

/// What happened to a contact.
enum class ContactStatus : std::uint8_t {
  kApplied,           ///< a force was computed (possibly zero when damping cancels it)
  kPierced,           ///< step 9: the top vertex is inside this tissue triangle's plane; discarded
  kDegenerateTissue,  ///< the tissue triangle has no area (no normal); no force
  kCoplanar,          ///< every |d_i| is within the tri–tri tolerance of the plane; no force
  kNoCrossing,        ///< no instrument vertex strictly inside, or none outside; no force
  kMissed,            ///< the trace MN does not meet the tissue triangle; no force
  kGrasped,           ///< (solver) the tissue triangle is held by the jaws; no penalty
  kCount,             ///< number of statuses
};

/// Lower-case name of a status ("applied", "pierced", ...).
const char* contact_status_name(ContactStatus status);

/// Everything the kernel found for one contact (all zero but `status` unless kApplied, except
/// normal_in, which is set whenever the tissue triangle has area).
struct ContactResponse {
  ContactStatus status = ContactStatus::kNoCrossing;  ///< see ContactStatus
  std::uint8_t inside_count = 0;  ///< instrument vertices strictly inside the tissue (1 or 2)
  std::uint8_t lone_vertex = 0;   ///< original index of A3 after relabelling (step 2)
  bool moved_to_edge = false;     ///< step 4: N was outside B and P was moved along MN
  Vec3 normal_in = Vec3::Zero();  ///< n_in, unit, into the tissue (step 1)
  Vec3 m = Vec3::Zero();          ///< M: edge A1A3 ∩ tissue plane (m)
  Vec3 n = Vec3::Zero();          ///< N: edge A2A3 ∩ tissue plane (m)
  Vec3 point = Vec3::Zero();      ///< P, on both triangles (m)
  Vec3 weights_a = Vec3::Zero();  ///< P's barycentric coordinates in A (original vertex order)
  Vec3 weights_b = Vec3::Zero();  ///< P's barycentric coordinates in B, ≥ 0, sum 1
  Vec3 penetration = Vec3::Zero();  ///< PD = Pd1 + Pd2 + Pd3 (eq. 3.7) (m); obb/project only
  Vec3 relative_velocity = Vec3::Zero();  ///< v_rel = V_I − V_T at P (m/s)
  Vec3 deformation = Vec3::Zero();  ///< D (eq. 3.8, or the baseline's depth·n_in) (m)
  Real depth = 0;                   ///< |D| (m)
  bool depth_capped = false;        ///< obb/project: |D| was cut to the triangle's depth (depth cap)
  Vec3 force = Vec3::Zero();        ///< F on the tissue at P (N), = f·n_in with f ≥ 0
};

/// The seed's response for one contact (steps 1–9 of docs/response.md "The kernel, step by step";
/// grasping is the solver's). `box` is the instrument's OBB in the world (fitted once, carried by
/// the pose); `top` the world position of its top vertex, or nullptr to skip the pierced-organ
/// filter; `instrument_positions` the instrument's world vertices (read by the `normal` method
/// only; empty: A's three vertices). No allocation; never NaN for finite input (docs/response.md).
ContactResponse respond_contact(const ContactTriangles& tri, const Obb& box, const Vec3* top,
                                std::span<const Vec3> instrument_positions,
                                const ResponseSettings& settings);

/// Step 5 alone: PD = Σ_k Pd_k for P in `box` and the tissue's inner normal n_in (any length:
/// only the signs of a_k·n_in are used). For each axis
/// a_k the ray from P along s_k·a_k, s_k = sign(a_k·n_in), leaves the box at distance
/// t_k = h_k − s_k·(a_k·(P − c)) (the slab exit; clamped at 0 for P a hair outside), so
/// Pd_k = t_k·s_k·a_k; an axis with a_k·n_in = 0 contributes nothing.
Vec3 obb_penetration(const Obb& box, const Vec3& p, const Vec3& n_in);

}  // namespace trocar
