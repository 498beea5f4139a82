#pragma once
/// The penetration and tunneling metrics: a measuring instrument beside the step, not part of it
/// (docs/architecture.md, "One step", and docs/scene.md, "What a step measures"). Turning it off changes no state.
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "trocar/collision/contact.h"
#include "trocar/geometry/signed_distance.h"
#include "trocar/response/tissue_response.h"
#include "trocar/mesh/sheet_boundary.h"
#include "trocar/sim/world.h"

namespace trocar {

/// What the meter measured in one step.
struct PenetrationReading {
  /// Deepest instrument vertex inside any closed tissue (m, ≥ 0), signed distance to the
  /// deformed surface with angle-weighted pseudonormals.
  Real penetration_max = 0;
  /// Instrument vertices inside a tissue (summed over instrument–tissue pairs).
  std::uint32_t vertices_inside = 0;
  /// Tunneling events (see PenetrationMeter).
  std::uint32_t tunneling_events = 0;
};

/// Penetration: for each closed tissue whose bounding box (grown by 1 nm against rounding) holds
/// some instrument vertex, the tissue's MeshDistance is refitted to the deformed positions once
/// per step and every instrument vertex in that box is queried, seeded with the triangle that
/// vertex was nearest to last time; a vertex outside that box is outside the tissue (outside the
/// hull of its vertices; its distance is recorded as +inf: only the sign of an outside vertex's
/// distance enters the metrics). The queries go in batches of nearby vertices
/// (MeshDistance::signed_distances; each result is the vertex's own exact query).
/// depth = max(0, −signed distance). Open tissues (sheets) have no inside: a vertex's state there
/// is its side (sheet_crossing.cpp).
///
/// Tunneling, per instrument vertex and tissue: (a) the vertex was outside at the end of the
/// previous step, is inside now, is inside the surface as it stood when this step's detection ran
/// (before this step's deformation: the instrument's own motion carried it across, not the tissue
/// springing over it after the response), and no contact of this step involves it (no detected
/// triangle pair with an incident instrument triangle, and its tissue's response did not answer
/// it itself): it crossed the surface unseen, between detections or too fast for the discrete
/// test; or (b) its depth first exceeds the instrument's thickness (counted when it goes from
/// ≤ thickness to > thickness).
///
/// No allocation after construction.
class PenetrationMeter {
 public:
  /// Sizes everything for `world` (which must outlive the meter and keep its sizes). A disabled
  /// meter measures nothing and holds no distance structures.
  PenetrationMeter(const World& world, bool enabled);

  bool enabled() const { return enabled_; }
  /// Tissue t's model changed (a cut): rebuilds its distance structures and forgets what each
  /// instrument vertex was last measured against it (its side is unknown until measured again, so
  /// a surface that changed under a vertex is never counted as tunneling). Allocates.
  void remodel(std::size_t t);
  /// Before the step's deformation: keeps the tissues' surfaces as the detection saw them.
  void capture_start();
  /// After the step: measures every instrument against every tissue. `contacts` are the step's
  /// detected pairs, `responses` the tissues' responses (their own hits), `max_speed` the
  /// fastest tissue vertex (m/s), dt the step (s).
  PenetrationReading measure(std::span<const Contact> contacts,
                             std::span<const std::unique_ptr<TissueResponse>> responses, Real max_speed, Real dt);

 private:
  std::size_t pair(std::size_t instrument, std::size_t tissue) const { return instrument * tissues_ + tissue; }
  void measure_tissue(std::size_t tissue, std::span<const Contact> contacts, const TissueResponse& response,
                      Real max_speed, Real dt);
  /// Queries the instrument's vertices in inside_box (the tissue's box, grown by 1 nm; for a
  /// sheet, by the step's motion too).
  void measure_pair(std::size_t instrument, std::size_t tissue, const Aabb& inside_box, bool sheet);
  /// For an open tissue (sheet_crossing.cpp): counts vertex v's tunneling event if it changed
  /// sides of the sheet on its own this step without a contact, and returns the distance to
  /// keep for it (NaN, side unknown, when its closest feature is on the sheet's border).
  Real sheet_side(const InstrumentBody& body, std::size_t instrument, std::size_t tissue, std::uint32_t v,
                  const SignedDistanceResult& r);
  /// Tissue t's surface as this step's detection saw it (start_distances_, refitted to
  /// start_positions_ once per tissue measurement when it differs).
  const MeshDistance& start_surface(std::size_t tissue);
  /// Counts vertex v of an instrument, at signed distance d < 0 inside a tissue, and its
  /// tunneling event if any.
  void count_inside(const InstrumentBody& body, std::size_t instrument, std::size_t tissue, std::uint32_t v, Real d);

  const World& world_;
  bool enabled_ = false;
  std::size_t tissues_ = 0;
  PenetrationReading reading_;
  std::vector<std::unique_ptr<MeshDistance>> distances_;  ///< per tissue (null when not measured)
  std::vector<SheetBoundary> sheets_;  ///< per tissue: the border of an open one (empty when closed)
  std::vector<Real> reach_;            ///< per instrument: farthest vertex from its pose origin (m)
  /// Per measured tissue: its positions before this step's deformation (the surface the
  /// detection saw) and a MeshDistance for them, used only when a tunneling candidate asks. The
  /// two MeshDistances swap at each refit, so this one holds the previous refit's surface; it
  /// is refitted only when that is not bit-identical to start_positions_ (e.g. after a step
  /// without measurement, or positions changed between steps).
  std::vector<std::vector<Vec3>> start_positions_;
  std::vector<std::unique_ptr<MeshDistance>> start_distances_;
  /// Per (instrument, tissue) pair: last signed distance of each instrument vertex (m);
  /// NaN before the first measurement, +inf outside the tissue's box.
  std::vector<std::vector<Real>> previous_distance_;
  /// Per (instrument, tissue) pair: the tissue triangle each instrument vertex was last nearest
  /// to (MeshDistance::kNoTriangle if none), the seed of its next query.
  std::vector<std::vector<std::uint32_t>> nearest_triangle_;
  std::vector<std::vector<std::uint8_t>> touched_;  ///< per instrument: vertex in a contact now
  /// Per (instrument, tissue) pair, open tissues only: 1 while an instrument vertex is on the far
  /// side of the sheet from where it came (it crossed the sheet's interior, side known on both
  /// steps), so its distance to the sheet is a penetration depth; 0 once it crosses back or its
  /// side becomes unknown (sheet_crossing.cpp).
  std::vector<std::vector<std::uint8_t>> through_;
  bool start_refitted_ = false;  ///< start_distances_ of the tissue being measured is current
  /// Per instrument: its vertex ids in a spatially coherent order (the penetration queries go in
  /// batches of consecutive vertices in the tissue's box).
  std::vector<std::vector<std::uint32_t>> query_order_;
  MeshDistance::BatchScratch query_scratch_;  ///< candidate triangles of one query batch
};

}  // namespace trocar
