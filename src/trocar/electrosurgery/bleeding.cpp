#include "trocar/electrosurgery/bleeding.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <unordered_map>

namespace trocar {

Real nusselt_speed(const FilmProperties& p, Real gravity, Real slope, Real thickness) {
  return p.density * gravity * slope * thickness * thickness / (3 * p.viscosity);
}

// ---------------------------------------------------------------------------------------------
// BloodFilm

BloodFilm::BloodFilm(std::span<const Triangle> triangles, std::span<const Vec3> rest_positions,
                     const FilmProperties& properties)
    : properties_(properties) {
  build(triangles, rest_positions);
  film_.assign(rest_positions.size(), 0.0);
  blood_.assign(rest_positions.size(), 0.0);
  arrived_.assign(rest_positions.size(), 0.0);
  stain_.assign(rest_positions.size(), 0.0);
}

void BloodFilm::build(std::span<const Triangle> triangles, std::span<const Vec3> rest_positions) {
  const std::size_t n = rest_positions.size();
  triangles_.assign(triangles.begin(), triangles.end());
  rest_.assign(rest_positions.begin(), rest_positions.end());
  area_.assign(n, 0.0);
  edges_.clear();
  border_.clear();
  // Edge → its index in edges_, with how many triangles use it and the first one's orientation.
  struct Seen {
    std::uint32_t index, count;
    BorderEdge first;
  };
  std::unordered_map<std::uint64_t, Seen> seen;
  seen.reserve(3 * triangles.size());
  for (const Triangle& t : triangles) {
    if (t[0] >= n || t[1] >= n || t[2] >= n) continue;
    const Vec3 cross = (rest_positions[t[1]] - rest_positions[t[0]]).cross(rest_positions[t[2]] - rest_positions[t[0]]);
    const Real twice_area = cross.norm();
    for (int k = 0; k < 3; ++k) area_[t[k]] += twice_area / 6.0;
    for (int k = 0; k < 3; ++k) {
      // The edge opposite corner k, and its share of the dual: ½ cot(angle at k) L.
      const std::uint32_t o = t[k], a = t[(k + 1) % 3], b = t[(k + 2) % 3];
      const Vec3 u = rest_positions[a] - rest_positions[o], v = rest_positions[b] - rest_positions[o];
      const Real length = (rest_positions[b] - rest_positions[a]).norm();
      const Real width = twice_area > 0 ? 0.5 * u.dot(v) / twice_area * length : 0.0;
      const std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
      const auto [it, inserted] = seen.try_emplace(key, Seen{static_cast<std::uint32_t>(edges_.size()), 0, {a, b, o}});
      if (inserted) edges_.push_back({std::min(a, b), std::max(a, b), 0.0});
      edges_[it->second.index].width += width;
      ++it->second.count;
    }
  }
  // A non-Delaunay edge (α + β > π) has a negative cotangent weight: clamped, so that no flux ever
  // runs against its drop (the scheme stays monotone; exactness for linear heights is lost there).
  // A weight within rounding of 0 (a right angle opposite the edge on both sides, as on a square
  // grid's diagonals) is 0: no flux of the order of 1e-16 should wet a vertex that no blood reaches.
  // Edges of no width carry nothing: dropped, so step() does not visit them.
  std::erase_if(edges_, [&](const Edge& e) {
    return !(e.width > 1e-9 * (rest_positions[e.a] - rest_positions[e.b]).norm());
  });
  for (const auto& [key, s] : seen)
    if (s.count == 1) border_.push_back(s.first);
  // The map's order is unspecified: sort, so the result does not depend on the library.
  std::sort(border_.begin(), border_.end(),
            [](const BorderEdge& x, const BorderEdge& y) { return x.a != y.a ? x.a < y.a : x.b < y.b; });
  depth_.assign(n, 0.0);
  up_.assign(n, 0.0);
  down_.assign(n, 0.0);
  normal_.assign(n, Vec3::Zero());
  border_width_.assign(n, 0.0);
  out_.assign(n, 0.0);
  scale_.assign(n, 0.0);
  mobile_.assign(n, 0.0);
  drive_.assign(n, 0.0);
  surface_.assign(n, 0.0);
  fraction_.assign(n, 0.0);
  drip_.assign(n, 0.0);
  drip_blood_.assign(n, 0.0);
  dripping_ = false;
  // Each vertex's edges (compressed rows), for the active set's walks.
  adjacency_offset_.assign(n + 1, 0);
  for (const Edge& e : edges_) ++adjacency_offset_[e.a + 1], ++adjacency_offset_[e.b + 1];
  for (std::size_t i = 0; i < n; ++i) adjacency_offset_[i + 1] += adjacency_offset_[i];
  adjacency_.assign(2 * edges_.size(), 0);
  {
    std::vector<std::uint32_t> next(adjacency_offset_.begin(), adjacency_offset_.end() - 1);
    for (std::size_t e = 0; e < edges_.size(); ++e) {
      adjacency_[next[edges_[e].a]++] = static_cast<std::uint32_t>(e);
      adjacency_[next[edges_[e].b]++] = static_cast<std::uint32_t>(e);
    }
  }
  active_.clear();
  active_.reserve(n);
  in_set_.assign(n, 0);
  expanded_.assign(n, 0);
  moving_.clear();
  moving_.reserve(edges_.size());
  length_.assign(edges_.size(), 0.0);
}

void BloodFilm::add_mixture(std::uint32_t vertex, Real volume, Real blood) {
  if (!(volume > 0)) return;
  blood = std::clamp(blood, 0.0, volume);
  if (vertex >= film_.size() || !(area_[vertex] > 0)) {
    dripped_ += volume;
    dripped_blood_ += blood;
    return;
  }
  film_[vertex] += volume;
  blood_[vertex] += blood;
  wet_ = touched_ = true;
  arrive(vertex, volume, blood);
  stain_[vertex] = 1 - std::exp(-arrived_[vertex] / properties_.stain_thickness);
}

void BloodFilm::arrive(std::size_t i, Real volume, Real blood) {
  const Real saline = volume - blood;
  if (saline > 0) arrived_[i] *= std::exp(-saline / area_[i] / properties_.wash_thickness);
  arrived_[i] += blood / area_[i];
}

Real BloodFilm::take(std::size_t i, Real volume) {
  const Real blood = film_[i] > 0 ? blood_[i] * std::min(1.0, volume / film_[i]) : 0.0;
  film_[i] -= volume;
  blood_[i] = std::max(0.0, blood_[i] - blood);  // ≥ 0 against rounding
  return blood;
}

void BloodFilm::shed(std::size_t i, Real volume, Real blood) {
  dripped_ += volume;
  dripped_blood_ += blood;
  drip_[i] += volume;
  drip_blood_[i] += blood;
  dripping_ = true;
}

void BloodFilm::clear_drips() {
  if (!dripping_) return;
  std::fill(drip_.begin(), drip_.end(), 0.0);
  std::fill(drip_blood_.begin(), drip_blood_.end(), 0.0);
  dripping_ = false;
}

Real BloodFilm::thickness(std::size_t vertex) const {
  return area_[vertex] > 0 ? film_[vertex] / area_[vertex] : 0.0;
}

Real BloodFilm::blood_thickness(std::size_t vertex) const {
  return area_[vertex] > 0 ? blood_[vertex] / area_[vertex] : 0.0;
}

Real BloodFilm::volume() const {
  Real sum = 0;
  for (Real v : film_) sum += v;
  return sum;
}

Real BloodFilm::blood_volume() const {
  Real sum = 0;
  for (Real v : blood_) sum += v;
  return sum;
}

void BloodFilm::expand(std::uint32_t i) {
  if (!in_set_[i]) in_set_[i] = 1, active_.push_back(i);
  expanded_[i] = 1;
  for (std::uint32_t k = adjacency_offset_[i]; k < adjacency_offset_[i + 1]; ++k) {
    const Edge& e = edges_[adjacency_[k]];
    const std::uint32_t j = e.a == i ? e.b : e.a;
    if (!in_set_[j]) in_set_[j] = 1, active_.push_back(j);
  }
}

void BloodFilm::shed_overhangs() {
  // Beneath a surface facing down at cos φ to gravity, a film thicker than h_max / √cos φ drips.
  // Only the active set can hold film (step() builds it before the first call).
  const Real h_max = properties_.max_thickness;
  for (const std::uint32_t i : active_) {
    if (!(down_[i] > 0)) continue;
    const Real limit = h_max / std::sqrt(down_[i]) * area_[i];
    if (film_[i] > limit) {
      const Real excess = film_[i] - limit;
      shed(i, excess, take(i, excess));
    }
  }
}

void BloodFilm::update_stain() {
  const Real scale = properties_.stain_thickness;
  for (std::size_t i = 0; i < stain_.size(); ++i) stain_[i] = 1 - std::exp(-arrived_[i] / scale);
}

void BloodFilm::step(std::span<const Vec3> positions, const Vec3& gravity, Real dt) {
  last_substeps_ = 1;
  const std::size_t n = film_.size();
  const Real g = gravity.norm();
  if (!(dt > 0) || !(g > 0) || positions.size() < n) return;
  const FilmProperties& p = properties_;
  const Real h_r = p.residual_thickness, h_max = p.max_thickness;
  // A film no thicker than the residual layer anywhere: nothing to do (the usual case).
  if (!wet_) return;
  bool mobile = false;
  for (std::size_t i = 0; i < n && !mobile; ++i) mobile = film_[i] > h_r * area_[i];
  if (!mobile) return;

  // The geometry of this step: heights along gravity, which way each vertex faces, edge lengths,
  // and the open border's outflow widths.
  const Vec3 down = gravity / g;
  // 1/(m·s): q = k s h³, k = ρ g / (3 μ) with μ the mixture's (blood fraction f: linear in f).
  const Real k_blood = p.density * g / (3 * p.viscosity), k_saline = p.density * g / (3 * p.saline_viscosity);
  std::fill(normal_.begin(), normal_.end(), Vec3::Zero());
  for (const Triangle& t : triangles_) {
    if (t[0] >= n || t[1] >= n || t[2] >= n) continue;
    const Vec3 nrm = (positions[t[1]] - positions[t[0]]).cross(positions[t[2]] - positions[t[0]]);
    for (int c = 0; c < 3; ++c) normal_[t[c]] += nrm;
  }
  for (std::size_t i = 0; i < n; ++i) {
    depth_[i] = down.dot(positions[i]);
    const Real norm = normal_[i].norm();
    const Real c = norm > 0 ? normal_[i].dot(down) / norm : 0.0;
    up_[i] = std::max(0.0, -c);
    down_[i] = std::max(0.0, c);
    border_width_[i] = 0;
  }
  for (const BorderEdge& e : border_) {
    // Outward in-plane normal of the border edge, times its length: (x_b − x_a) × n̂ (the triangle
    // lies to the left of a → b seen from its normal). Each end takes half the edge.
    const Vec3 edge = positions[e.b] - positions[e.a];
    const Vec3 nrm = edge.cross(positions[e.c] - positions[e.a]);
    const Real norm = nrm.norm();
    if (!(norm > 0)) continue;
    const Real s = 0.5 * edge.cross(nrm / norm).dot(down);
    border_width_[e.a] += s;
    border_width_[e.b] += s;
  }
  for (Real& w : border_width_) w = std::max(w, 0.0);
  for (std::size_t e = 0; e < edges_.size(); ++e) length_[e] = (positions[edges_[e].a] - positions[edges_[e].b]).norm();

  // The active set: the wet vertices and their neighbours (a dry vertex away from the film can
  // neither give nor take this substep). Each substep visits only it: the cost follows the wet
  // region, not the surface.
  for (const std::uint32_t i : active_) in_set_[i] = expanded_[i] = 0;
  active_.clear();
  for (std::size_t i = 0; i < n; ++i)
    if (film_[i] > 0) expand(static_cast<std::uint32_t>(i));

  shed_overhangs();  // what a wound added beneath an overhang
  Real remaining = dt;
  int substeps = 0;
  while (remaining > 0 && substeps < p.max_substeps) {
    // Per vertex at the start of the substep: its mobile film (m³), its Nusselt flux per width and
    // slope k h_m³ (m²/s), and the height of its free surface along gravity, where the film counts:
    // the excess over what surface tension holds, on a surface facing up (excess × cos φ).
    const std::size_t m = active_.size();  // vertices that become wet this substep give from the next
    bool any = false;
    for (std::size_t a_i = 0; a_i < m; ++a_i) {
      const std::uint32_t i = active_[a_i];
      out_[i] = 0;
      const Real a = area_[i];
      mobile_[i] = a > 0 ? std::max(0.0, film_[i] - h_r * a) : 0.0;
      const Real h_m = a > 0 ? mobile_[i] / a : 0.0;
      fraction_[i] = film_[i] > 0 ? std::min(1.0, blood_[i] / film_[i]) : 0.0;
      const Real viscosity = p.saline_viscosity + (p.viscosity - p.saline_viscosity) * fraction_[i];
      const Real k = fraction_[i] == 1 ? k_blood : fraction_[i] == 0 ? k_saline : p.density * g / (3 * viscosity);
      drive_[i] = k * h_m * h_m * h_m;
      any |= drive_[i] > 0;
      surface_[i] = depth_[i] - (a > 0 && up_[i] > 0 ? up_[i] * std::max(0.0, film_[i] / a - h_max) : 0.0);
    }
    if (!any) break;
    // Fluxes (upwind: each donor to its lower neighbours; an edge flows one way, so it is visited
    // once) and the open border's run-off.
    moving_.clear();
    for (std::size_t a_i = 0; a_i < m; ++a_i) {
      const std::uint32_t from = active_[a_i];
      if (!(drive_[from] > 0)) continue;
      for (std::uint32_t k = adjacency_offset_[from]; k < adjacency_offset_[from + 1]; ++k) {
        const std::uint32_t e = adjacency_[k];
        const Edge& edge = edges_[e];
        const std::uint32_t to = edge.a == from ? edge.b : edge.a;
        const Real drop = surface_[to] - surface_[from];  // > 0: `to` is lower
        if (!(drop > 0) || !(length_[e] > 0)) continue;
        const Real q = drive_[from] * edge.width * drop / length_[e];
        out_[from] += q;
        // Levelling: a transfer of v lowers the drop by v (up_a/A_a + up_b/A_b) while either end is
        // over h_max; give at most half of what would level them, so a puddle does not slosh.
        Real cap = std::numeric_limits<Real>::infinity();
        if (film_[from] > h_max * area_[from] || film_[to] > h_max * area_[to]) {
          const Real sigma = up_[from] / area_[from] + (area_[to] > 0 ? up_[to] / area_[to] : 0.0);
          if (sigma > 0) cap = 0.5 * drop / sigma;
        }
        moving_.push_back({from, to, q, cap});
      }
      if (border_width_[from] > 0) out_[from] += drive_[from] * border_width_[from];
    }
    // The substep: no donor gives more than `courant` of its mobile film (the last allowed substep
    // takes what is left of dt, and the proportional limit below holds it to what the donor has).
    Real rate = 0;
    for (std::size_t a_i = 0; a_i < m; ++a_i) {
      const std::uint32_t i = active_[a_i];
      if (out_[i] > 0) rate = std::max(rate, out_[i] / mobile_[i]);
    }
    if (!(rate > 0)) break;
    Real h = remaining;
    if (substeps + 1 < p.max_substeps && rate * h > p.courant) h = p.courant / rate;
    if (h >= remaining * (1 - 1e-12)) h = remaining;
    // Border run-off first, then the edges; each donor's outflows scaled by the same factor so that
    // together they never exceed its mobile film.
    for (std::size_t a_i = 0; a_i < m; ++a_i) {
      const std::uint32_t i = active_[a_i];
      if (!(out_[i] > 0)) continue;
      scale_[i] = std::min(1.0, mobile_[i] / (out_[i] * h));
      if (!(border_width_[i] > 0)) continue;
      const Real v = std::min(drive_[i] * border_width_[i] * h * scale_[i], mobile_[i]);
      shed(i, v, take(i, v));
    }
    for (const Transfer& t : moving_) {
      const Real v = std::min(t.rate * h * scale_[t.from], t.cap);
      // Blood in the donor's proportion at the substep's start (its outflows together never
      // exceed its mobile film, so never its blood).
      const Real b = std::min(blood_[t.from], v * fraction_[t.from]);
      film_[t.from] -= v;
      blood_[t.from] = std::max(0.0, blood_[t.from] - b);
      film_[t.to] += v;
      blood_[t.to] += b;
      arrive(t.to, v, b);
      if (!expanded_[t.to]) expand(t.to);
    }
    shed_overhangs();
    remaining = h == remaining ? 0.0 : remaining - h;
    ++substeps;
  }
  last_substeps_ = std::max(1, substeps);
  update_stain();
  wet_ = std::any_of(film_.begin(), film_.end(), [](Real v) { return v > 0; });
}

Real BloodFilm::remove_within(std::span<const Vec3> positions, const Vec3& centre, Real radius, Real max_volume,
                              Real* blood) {
  if (blood) *blood = 0;
  if (!(max_volume > 0) || !(radius > 0) || !wet_) return 0.0;
  const std::size_t n = std::min(film_.size(), positions.size());
  const Real r2 = radius * radius;
  Real within = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (film_[i] > 0 && (positions[i] - centre).squaredNorm() <= r2) within += film_[i];
  if (!(within > 0)) return 0.0;
  const Real fraction = std::min(1.0, max_volume / within);
  Real removed = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!(film_[i] > 0) || (positions[i] - centre).squaredNorm() > r2) continue;
    const Real v = fraction < 1 ? film_[i] * fraction : film_[i];
    const Real b = take(i, v);
    if (blood) *blood += b;
    removed += v;
  }
  wet_ = std::any_of(film_.begin(), film_.end(), [](Real v) { return v > 0; });
  return removed;
}

void BloodFilm::remap(std::span<const std::uint32_t> vertex_origin, std::span<const Triangle> triangles,
                      std::span<const Vec3> rest_positions) {
  const std::size_t old_n = film_.size(), n = vertex_origin.size();
  const std::vector<Real> old_film = std::move(film_), old_blood = std::move(blood_),
                          old_arrived = std::move(arrived_), old_stain = std::move(stain_);
  // Pending drips have left the surface already: they stay where they were counted (dripped).
  clear_drips();
  build(triangles, rest_positions);
  // The new area of each old vertex's copies, and how many there are.
  std::vector<Real> copy_area(old_n, 0.0);
  std::vector<std::uint32_t> copies(old_n, 0);
  for (std::size_t v = 0; v < n; ++v)
    if (vertex_origin[v] < old_n) {
      copy_area[vertex_origin[v]] += area_[v];
      ++copies[vertex_origin[v]];
    }
  film_.assign(n, 0.0);
  blood_.assign(n, 0.0);
  arrived_.assign(n, 0.0);
  stain_.assign(n, 0.0);
  for (std::size_t v = 0; v < n; ++v) {
    const std::uint32_t o = vertex_origin[v];
    if (o >= old_n) continue;
    const Real share = copy_area[o] > 0 ? area_[v] / copy_area[o] : 1.0 / copies[o];
    film_[v] = copies[o] == 1 ? old_film[o] : old_film[o] * share;
    blood_[v] = copies[o] == 1 ? old_blood[o] : old_blood[o] * share;
    arrived_[v] = old_arrived[o];
    stain_[v] = old_stain[o];
  }
  for (std::size_t o = 0; o < old_n; ++o)
    if (copies[o] == 0) dripped_ += old_film[o], dripped_blood_ += old_blood[o];
  // A copy without area cannot hold its share: it drips (add's rule).
  for (std::size_t v = 0; v < n; ++v)
    if (film_[v] > 0 && !(area_[v] > 0)) {
      dripped_ += film_[v];
      dripped_blood_ += blood_[v];
      film_[v] = blood_[v] = 0;
    }
  wet_ = std::any_of(film_.begin(), film_.end(), [](Real v) { return v > 0; });
}

// ---------------------------------------------------------------------------------------------
// Vessels

Real vessel_speed(const BleedingProperties& p, const VesselSpec& vessel) {
  return vessel.artery ? p.artery_speed : p.vein_speed;
}

Real bleeding_rate(const BleedingProperties& p, const VesselSpec& vessel, Real seal_progress) {
  const Real open = 1 - std::clamp(seal_progress, 0.0, 1.0);
  return vessel_speed(p, vessel) * std::numbers::pi * vessel.diameter * vessel.diameter / 4 * open * open;
}

Real seal_threshold(const BleedingProperties& p, const VesselSpec& vessel) {
  const Real ratio = vessel.diameter / p.seal_reference_diameter;
  return p.seal_damage * std::max(1.0, ratio * ratio);
}

Real seal_limit(const BleedingProperties& p, EnergyModality modality) {
  return modality == EnergyModality::kBipolar ? p.bipolar_limit : p.monopolar_limit;
}

// ---------------------------------------------------------------------------------------------
// Bleeding

namespace {
bool closed(WoundState s) { return s == WoundState::kSealed || s == WoundState::kClipped; }
}  // namespace

Bleeding::Bleeding(const BleedingProperties& properties) : properties_(properties) {
  wounds_.reserve(properties.wound_capacity);
}

std::size_t Bleeding::add_tissue(std::span<const Triangle> triangles, std::span<const Vec3> rest_positions,
                                 const FilmProperties& film) {
  films_.emplace_back(triangles, rest_positions, film);
  return films_.size() - 1;
}

void Bleeding::remap_tissue(std::size_t tissue, std::span<const std::uint32_t> vertex_origin,
                            std::span<const Triangle> triangles, std::span<const Vec3> rest_positions) {
  BloodFilm& film = films_[tissue];
  const std::vector<Vec3> old_rest(film.rest_positions().begin(), film.rest_positions().end());
  film.remap(vertex_origin, triangles, rest_positions);
  for (Wound& w : wounds_) {
    if (w.tissue != tissue) continue;
    std::uint32_t to = std::numeric_limits<std::uint32_t>::max();
    for (std::size_t v = 0; v < vertex_origin.size(); ++v)
      if (vertex_origin[v] == w.vertex) {
        to = static_cast<std::uint32_t>(v);
        break;
      }
    if (to == std::numeric_limits<std::uint32_t>::max() && w.vertex < old_rest.size()) {
      Real best = std::numeric_limits<Real>::infinity();
      for (std::size_t v = 0; v < film.size(); ++v) {
        const Real d = (film.rest_positions()[v] - old_rest[w.vertex]).squaredNorm();
        if (d < best && film.area()[v] > 0) {
          best = d;
          to = static_cast<std::uint32_t>(v);
        }
      }
    }
    w.vertex = to;  // none left: add() lets its blood drip into the pool
  }
}

std::size_t Bleeding::open_wound(std::size_t tissue, std::uint32_t vertex, const VesselSpec& vessel, Real time) {
  Wound w;
  w.tissue = tissue;
  w.vertex = vertex;
  w.vessel = vessel;
  w.opened = time;
  wounds_.push_back(w);
  return wounds_.size() - 1;
}

Real Bleeding::rate(std::size_t wound) const {
  const Wound& w = wounds_[wound];
  if (closed(w.state)) return 0.0;
  return bleeding_rate(properties_, w.vessel, w.damage / seal_threshold(properties_, w.vessel));
}

void Bleeding::step(std::span<const std::span<const Vec3>> positions, const Vec3& gravity, Real dt) {
  if (!(dt > 0)) return;
  const Real t1 = time_ + dt;
  for (std::size_t i = 0; i < wounds_.size(); ++i) {
    Wound& w = wounds_[i];
    if (closed(w.state) || w.tissue >= films_.size()) continue;
    const Real from = std::max(time_, w.opened);
    if (!(t1 > from)) continue;
    const Real volume = rate(i) * (t1 - from);
    films_[w.tissue].add(w.vertex, volume);
    w.emitted += volume;
    emitted_ += volume;
  }
  for (std::size_t t = 0; t < films_.size() && t < positions.size(); ++t)
    if (!positions[t].empty()) films_[t].step(positions[t], gravity, dt);
  time_ = t1;
}

WoundState Bleeding::coagulate(std::size_t wound, Real damage, Real dt, EnergyModality modality) {
  Wound& w = wounds_[wound];
  if (closed(w.state)) return w.state;
  w.energy_time += std::max(0.0, dt);
  if (w.vessel.diameter > seal_limit(properties_, modality)) {
    w.state = WoundState::kNeedsClip;  // the energy shrinks the wall but cannot close this lumen
    return w.state;
  }
  w.damage = std::max(w.damage, damage);
  if (w.damage >= seal_threshold(properties_, w.vessel)) {
    w.state = WoundState::kSealed;
    w.closed = std::max(time_, w.opened);
  }
  return w.state;
}

void Bleeding::clip(std::size_t wound) {
  Wound& w = wounds_[wound];
  if (closed(w.state)) return;
  w.state = WoundState::kClipped;
  w.closed = std::max(time_, w.opened);
}

Real Bleeding::suction(std::size_t tissue, std::span<const Vec3> positions, const Vec3& tip, Real radius, Real rate,
                       Real dt) {
  Real blood = 0;
  const Real removed = films_[tissue].remove_within(positions, tip, radius, rate * dt, &blood);
  suctioned_ += removed;
  suctioned_blood_ += blood;
  return removed;
}

void Bleeding::irrigate(std::size_t tissue, std::uint32_t vertex, Real volume) {
  if (!(volume > 0) || tissue >= films_.size()) return;
  films_[tissue].add_saline(vertex, volume);
  irrigated_ += volume;
}

std::optional<Real> Bleeding::time_to_haemostasis(std::size_t wound) const {
  const Wound& w = wounds_[wound];
  if (!closed(w.state)) return std::nullopt;
  return w.closed - w.opened;
}

Real Bleeding::volume() const {
  Real sum = 0;
  for (const BloodFilm& f : films_) sum += f.volume();
  return sum;
}

Real Bleeding::blood_volume() const {
  Real sum = 0;
  for (const BloodFilm& f : films_) sum += f.blood_volume();
  return sum;
}

Real Bleeding::pool() const {
  Real sum = 0;
  for (const BloodFilm& f : films_) sum += f.dripped();
  return sum;
}

Real Bleeding::pool_blood() const {
  Real sum = 0;
  for (const BloodFilm& f : films_) sum += f.dripped_blood();
  return sum;
}

}  // namespace trocar
