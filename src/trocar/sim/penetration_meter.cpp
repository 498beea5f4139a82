#include "trocar/sim/penetration_meter.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>

namespace trocar {
namespace {

constexpr Real kUnknown = std::numeric_limits<Real>::quiet_NaN();     ///< no measurement yet
constexpr Real kOutside = std::numeric_limits<Real>::infinity();      ///< outside the tissue's box
/// Growth of a tissue's bounding box before it decides that a vertex is outside the tissue (m):
/// far above the rounding of a signed distance (~1e-17 m at organ scale), far below a contact.
constexpr Real kBoxSlack = 1e-9;

/// Instrument vertices waiting to be queried together (MeshDistance::signed_distances): one
/// tree walk per batch instead of per vertex. 16 nearby vertices per walk measured best on the
/// probe–liver press (4: no gain, 32: none over 16).
struct QueryBatch {
  static constexpr std::size_t kSize = 16;
  std::array<Vec3, kSize> points;
  std::array<std::uint32_t, kSize> hints;     ///< nearest triangle last time, then now
  std::array<std::uint32_t, kSize> vertices;  ///< instrument vertex ids
  std::array<SignedDistanceResult, kSize> results;
  std::size_t count = 0;
};

/// Vertex ids in a spatially coherent order, so that consecutive vertices make compact batches:
/// recursive median splits along the longest axis of the points' box (ties by id).
void coherent_order(std::span<const Vec3> points, std::span<std::uint32_t> ids) {
  if (ids.size() <= 2) return;
  Aabb box;
  for (const std::uint32_t v : ids) box.expand(points[v]);
  Eigen::Index axis = 0;
  box.size().maxCoeff(&axis);
  const auto mid = ids.begin() + static_cast<std::ptrdiff_t>(ids.size() / 2);
  std::nth_element(ids.begin(), mid, ids.end(), [&](std::uint32_t a, std::uint32_t b) {
    return points[a][axis] < points[b][axis] || (points[a][axis] == points[b][axis] && a < b);
  });
  coherent_order(points, ids.first(ids.size() / 2));
  coherent_order(points, ids.subspan(ids.size() / 2));
}

/// True when some point lies in box.
bool any_inside(std::span<const Vec3> points, const Aabb& box) {
  return std::any_of(points.begin(), points.end(), [&](const Vec3& p) { return box.contains(p); });
}

/// True when a and b hold the same vertices, bit for bit.
bool same_bits(std::span<const Vec3> a, std::span<const Vec3> b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size_bytes()) == 0;
}


}  // namespace

PenetrationMeter::PenetrationMeter(const World& world, bool enabled)
    : world_(world), enabled_(enabled), tissues_(world.tissues.size()) {
  const std::size_t ni = world_.instruments.size();
  const std::size_t nt = tissues_;
  distances_.resize(nt);
  start_distances_.resize(nt);
  start_positions_.resize(nt);
  sheets_.resize(nt);
  if (!enabled_) return;
  for (std::size_t t = 0; t < nt; ++t) {
    const TissueBody& tissue = *world_.tissues[t];
    if (tissue.settings.triangles.empty()) continue;
    distances_[t] = std::make_unique<MeshDistance>(tissue.state.positions, tissue.settings.triangles);
    start_distances_[t] = std::make_unique<MeshDistance>(tissue.state.positions, tissue.settings.triangles);
    start_positions_[t] = tissue.state.positions;
    if (!tissue.settings.closed) sheets_[t] = SheetBoundary(tissue.state.positions, tissue.settings.triangles);
  }
  reach_.resize(ni);
  for (std::size_t i = 0; i < ni; ++i) {
    const Instrument& instrument = world_.instruments[i].instrument;
    for (const Vec3& p : instrument.world_positions())
      reach_[i] = std::max(reach_[i], (p - instrument.pose().translation).norm());
  }
  previous_distance_.resize(ni * nt);
  through_.resize(ni * nt);
  nearest_triangle_.resize(ni * nt);
  touched_.resize(ni);
  query_order_.resize(ni);
  for (std::size_t i = 0; i < ni; ++i) {
    const std::span<const Vec3> points = world_.instruments[i].instrument.world_positions();
    const std::size_t nv = points.size();
    touched_[i].assign(nv, 0);
    query_order_[i].resize(nv);
    std::iota(query_order_[i].begin(), query_order_[i].end(), std::uint32_t{0});
    coherent_order(points, query_order_[i]);
    for (std::size_t t = 0; t < nt; ++t) {
      previous_distance_[pair(i, t)].assign(nv, kUnknown);
      through_[pair(i, t)].assign(nv, 0);
      nearest_triangle_[pair(i, t)].assign(nv, MeshDistance::kNoTriangle);
    }
  }
  std::size_t most_triangles = 0;
  for (std::size_t t = 0; t < nt; ++t)
    if (distances_[t]) most_triangles = std::max(most_triangles, world_.tissues[t]->settings.triangles.size());
  query_scratch_ = MeshDistance::BatchScratch(most_triangles);
}

void PenetrationMeter::remodel(std::size_t t) {
  if (!enabled_ || t >= tissues_) return;
  const TissueBody& tissue = *world_.tissues[t];
  distances_[t].reset();
  start_distances_[t].reset();
  sheets_[t] = SheetBoundary();
  start_positions_[t].clear();
  if (!tissue.settings.triangles.empty()) {
    distances_[t] = std::make_unique<MeshDistance>(tissue.state.positions, tissue.settings.triangles);
    start_distances_[t] = std::make_unique<MeshDistance>(tissue.state.positions, tissue.settings.triangles);
    start_positions_[t] = tissue.state.positions;
    if (!tissue.settings.closed) sheets_[t] = SheetBoundary(tissue.state.positions, tissue.settings.triangles);
  }
  for (std::size_t i = 0; i < world_.instruments.size(); ++i) {
    std::fill(previous_distance_[pair(i, t)].begin(), previous_distance_[pair(i, t)].end(), kUnknown);
    std::fill(through_[pair(i, t)].begin(), through_[pair(i, t)].end(), std::uint8_t{0});
    std::fill(nearest_triangle_[pair(i, t)].begin(), nearest_triangle_[pair(i, t)].end(), MeshDistance::kNoTriangle);
  }
}

void PenetrationMeter::capture_start() {
  for (std::size_t t = 0; t < tissues_; ++t)
    if (distances_[t]) {
      const std::vector<Vec3>& x = world_.tissues[t]->state.positions;
      std::copy(x.begin(), x.end(), start_positions_[t].begin());
    }
}

PenetrationReading PenetrationMeter::measure(std::span<const Contact> contacts,
                                             std::span<const std::unique_ptr<TissueResponse>> responses,
                                             Real max_speed, Real dt) {
  reading_ = PenetrationReading{};
  for (std::size_t t = 0; t < tissues_; ++t)
    if (distances_[t]) measure_tissue(t, contacts, *responses[t], max_speed, dt);
  return reading_;
}

void PenetrationMeter::measure_tissue(std::size_t t, std::span<const Contact> contacts, const TissueResponse& response,
                                      Real max_speed, Real dt) {
  const std::size_t ni = world_.instruments.size();
  const TissueBody& tissue = *world_.tissues[t];
  const bool sheet = !tissue.settings.closed;
  // A point outside the box of a closed surface's vertices is outside the surface. Near a
  // sheet, the box grows by how far any vertex can have moved this step and the last (the
  // instrument's rigid motion, the fastest tissue vertex) and by the instrument's thickness:
  // a vertex that crossed the sheet is then measured on both sides of it.
  const Aabb tissue_box = Aabb::of_points(tissue.state.positions).inflated(kBoxSlack);
  bool refitted = false;
  start_refitted_ = false;
  for (std::size_t i = 0; i < ni; ++i) {
    const InstrumentBody& body = world_.instruments[i];
    const Instrument& instrument = body.instrument;
    const Real moved = (instrument.linear_velocity().norm() + instrument.angular_velocity().norm() * reach_[i] +
                        max_speed) * dt;
    const Aabb inside_box = sheet ? tissue_box.inflated(2 * moved + body.thickness) : tissue_box;
    // No vertex in the box: all outside, no refit and no query (an instrument on its way in).
    // A vertex through a sheet is measured wherever it is.
    const std::vector<std::uint8_t>& through = through_[pair(i, t)];
    const bool any_through = sheet && std::find(through.begin(), through.end(), 1) != through.end();
    if (!any_through && (!inside_box.overlaps(instrument.world_obb().bounds()) ||
                         !any_inside(instrument.world_positions(), inside_box))) {
      std::fill(previous_distance_[pair(i, t)].begin(), previous_distance_[pair(i, t)].end(),
                sheet ? kUnknown : kOutside);
      continue;
    }
    if (!refitted) {
      // The surface of the last refit, normally this step's start surface, becomes the
      // tunneling check's MeshDistance: most steps with candidates then need no second refit.
      std::swap(distances_[t], start_distances_[t]);
      distances_[t]->refit(tissue.state.positions);
      refitted = true;
    }
    // Instrument vertices of this step's contacts with this tissue (contacts are sorted by
    // object pair, a short run).
    std::vector<std::uint8_t>& touched = touched_[i];
    std::fill(touched.begin(), touched.end(), std::uint8_t{0});
    for (const Contact& c : contacts) {
      if (c.kind != ContactKind::kInstrumentTissue || c.object_a != i || c.object_b != ni + t) continue;
      for (std::uint32_t v : body.instrument.triangles()[c.triangle_a]) touched[v] = 1;
    }
    // Vertices whose contact the tissue's response found and answered itself.
    const std::span<const std::uint8_t> hits = response.instrument_hits(i);
    for (std::size_t v = 0; v < hits.size() && v < touched.size(); ++v) touched[v] |= hits[v];
    measure_pair(i, t, inside_box, sheet);
  }
}

void PenetrationMeter::measure_pair(std::size_t i, std::size_t t, const Aabb& inside_box, bool sheet) {
  const InstrumentBody& body = world_.instruments[i];
  std::span<const Vec3> points = body.instrument.world_positions();
  std::vector<Real>& previous = previous_distance_[pair(i, t)];
  std::vector<std::uint32_t>& nearest = nearest_triangle_[pair(i, t)];
  const auto record = [&](std::uint32_t v, const SignedDistanceResult& r) {
    if (sheet) {
      previous[v] = sheet_side(body, i, t, v, r);
      return;
    }
    if (r.distance < 0) count_inside(body, i, t, v, r.distance);
    previous[v] = r.distance;
  };
  QueryBatch batch;
  const auto flush = [&] {
    const std::size_t n = batch.count;
    distances_[t]->signed_distances(std::span(batch.points).first(n), std::span(batch.hints).first(n),
                                    std::span(batch.results).first(n), query_scratch_);
    for (std::size_t k = 0; k < n; ++k) {
      nearest[batch.vertices[k]] = batch.hints[k];
      record(batch.vertices[k], batch.results[k]);
    }
    batch.count = 0;
  };
  const std::vector<std::uint8_t>& through = through_[pair(i, t)];
  for (const std::uint32_t v : query_order_[i]) {
    if (!inside_box.contains(points[v]) && !(sheet && through[v] != 0)) {
      previous[v] = sheet ? kUnknown : kOutside;
      continue;
    }
    batch.points[batch.count] = points[v];
    batch.hints[batch.count] = nearest[v];
    batch.vertices[batch.count] = v;
    if (++batch.count == QueryBatch::kSize) flush();
  }
  if (batch.count > 0) flush();
}

const MeshDistance& PenetrationMeter::start_surface(std::size_t t) {
  if (!start_refitted_) {
    // Normally still the previous refit's surface, which is this step's start (simulation.h).
    if (!same_bits(start_distances_[t]->positions(), start_positions_[t]))
      start_distances_[t]->refit(start_positions_[t]);
    start_refitted_ = true;
  }
  return *start_distances_[t];
}

void PenetrationMeter::count_inside(const InstrumentBody& body, std::size_t i, std::size_t t, std::uint32_t v, Real d) {
  const Real prev = previous_distance_[pair(i, t)][v];
  ++reading_.vertices_inside;
  reading_.penetration_max = std::max(reading_.penetration_max, -d);
  bool crossed = false;
  if (prev > 0 && touched_[i][v] == 0) {
    // Did the vertex's own motion carry it across, i.e. is it inside the surface as the
    // detection saw it? Otherwise the tissue moved over it after the response (a
    // spring-back onto the tool, answered by the next detection), not a miss.
    const Vec3& p = body.instrument.world_positions()[v];
    crossed = start_surface(t).signed_distance(p, nearest_triangle_[pair(i, t)][v]).distance < 0;
  }
  if (crossed) {
    ++reading_.tunneling_events;  // (a) crossed the surface with no contact seen
  } else if (-d > body.thickness && !(-prev > body.thickness)) {
    ++reading_.tunneling_events;  // (b) deeper than the instrument is thick
  }
}

}  // namespace trocar
