#pragma once
/// What the trainee must do (scene key "task", docs/procedure.md): the tissues and landmarks the
/// steps are tested on, and the thresholds of the completion tests and of the error rules. Plain
/// data; a Procedure (procedure.h) resolves the names against a World and evaluates it.
#include <string>
#include <vector>

#include "trocar/core/types.h"

namespace trocar {

/// The hernia repair task. Lengths in metres, areas in m², forces in newtons, times in seconds.
/// Landmarks it reads (Scene::landmarks): "wall_point" and "wall_normal" (the wall's plane; the
/// normal points into the abdominal cavity), "defect_centre", the MPO's corners ("mpo_0",
/// "mpo_1", ... in order around it; optional) and the tack landmarks.
struct TaskSpec {
  std::string name = "hernia repair";  ///< shown as the panel's title
  std::string sac;                     ///< the hernia sac's tissue name
  std::string mesh;                    ///< the prosthetic mesh's tissue name
  std::vector<std::string> vessels;    ///< tissues that must not be grasped
  /// When set, only tacks into this tissue count for "mesh fixed" (others are still recorded).
  std::string wall_tissue;

  /// (1) sac reduced: this fraction of the sac's surface area on the cavity side of the wall plane.
  Real reduced_fraction = 0.9;
  /// (2) mesh placed: the mesh covers the MPO and a disc of defect_radius + overlap about the
  /// defect's centre (projected onto the wall plane). 3 cm beyond the defect: the rule
  /// (the guideline text reached gives no number; docs/procedure.md).
  Real overlap = 0.03;
  Real defect_radius = 0.01;       ///< the defect's radius (m); EHS size 1–2 is ≤ 1.5–3 cm across
  Real coverage_spacing = 0.0025;  ///< spacing of the coverage test's sample grid (m)
  /// Largest folded (flipped) mesh area the mesh may have and still lie flat: 2 cm².
  Real max_fold_area = 2e-4;
  /// (3) mesh fixed: at least this many tacks through the mesh into tissue, still holding...
  int min_tacks = 4;
  /// ...with one within tack_radius of each of these landmarks, and none in a named zone.
  std::vector<std::string> tack_landmarks = {"tack_cooper", "tack_medial", "tack_lateral"};
  Real tack_radius = 0.015;

  /// Tacker: reach (m) and the attachment's pull-out force (N, Byrd et al. 2011, Hernia 15:553).
  Real tack_reach = 0.002;
  Real tack_pullout = 28.6;

  /// Errors: a zone touched with more than this instrument force (N): the simulator force-error
  /// threshold derived from Rodrigues et al. 2012, Surg Endosc 26:1005.
  Real zone_force = 1.5;
  /// A touching episode ends when the instrument has been out of the zone this long (s), so that
  /// a contact flickering for a step or two is one episode, not many.
  Real zone_release = 0.1;
  /// The mesh is dropped when, after the last instrument lets go of it and with no tack holding
  /// it, its centroid falls this far along gravity (m) before it is grasped again.
  Real drop_distance = 0.03;
};

}  // namespace trocar
