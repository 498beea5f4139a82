#include "trocar/render/effects_view.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <unordered_map>

namespace trocar {
namespace {

/// The rest position's bits, for exact matching.
struct PositionKey {
  std::uint64_t x, y, z;
  bool operator==(const PositionKey&) const = default;
};
struct PositionHash {
  std::size_t operator()(const PositionKey& k) const {
    std::uint64_t h = 1469598103934665603ull;
    for (const std::uint64_t w : {k.x, k.y, k.z}) h = (h ^ w) * 1099511628211ull;
    return std::size_t(h ^ (h >> 29));
  }
};
PositionKey key_of(const Vec3& p) {
  PositionKey k{};
  // +0.0 for −0.0: the same place.
  const double x = p.x() + 0.0, y = p.y() + 0.0, z = p.z() + 0.0;
  std::memcpy(&k.x, &x, 8);
  std::memcpy(&k.y, &y, 8);
  std::memcpy(&k.z, &z, 8);
  return k;
}

/// The longest dt one BloodFilm::step is given (s), and how many such steps a frame takes at
/// most (a frame further than that from the last one flows only that long: the films stay
/// conservative, they just lag).
constexpr Real kBloodChunk = 1.0 / 30;
constexpr int kBloodChunks = 16;

}  // namespace

std::vector<std::uint32_t> match_rest_positions(std::span<const Vec3> before, std::span<const Vec3> now) {
  std::vector<std::uint32_t> origin;
  if (before.empty()) return origin;
  std::unordered_map<PositionKey, std::uint32_t, PositionHash> where;
  where.reserve(before.size());
  for (std::size_t v = 0; v < before.size(); ++v) where.try_emplace(key_of(before[v]), std::uint32_t(v));
  origin.resize(now.size());
  for (std::size_t v = 0; v < now.size(); ++v) {
    const auto it = where.find(key_of(now[v]));
    if (it != where.end()) {
      origin[v] = it->second;
      continue;
    }
    // Not a copy (a model that moved its vertices): the nearest old vertex.
    Real best = std::numeric_limits<Real>::infinity();
    std::uint32_t nearest = 0;
    for (std::size_t o = 0; o < before.size(); ++o) {
      const Real d = (before[o] - now[v]).squaredNorm();
      if (d < best) best = d, nearest = std::uint32_t(o);
    }
    origin[v] = nearest;
  }
  return origin;
}

EffectsView::EffectsView(std::vector<Vec3> gravity, const SmokeSettings& smoke, const FilmProperties& film,
                         std::uint64_t seed)
    : gravity_(std::move(gravity)), smoke_settings_(smoke), film_properties_(film), seed_(seed) {
  for (Vec3& g : gravity_)
    if (!(g.norm() > 0)) g = Vec3(0, 0, -9.81);
}

void EffectsView::clear() {
  time_.reset();
  films_.clear();
  film_versions_.clear();
  wound_fed_.clear();
  vapour_seen_.clear();
  smoke_.reset();
  fed_ = lost_ = spilled_ = irrigated_ = landed_ = landed_blood_ = suctioned_ = suctioned_blood_ = 0;
}

const BloodFilm* EffectsView::film(std::size_t t) const { return t < films_.size() ? films_[t].get() : nullptr; }

Real EffectsView::volume() const {
  Real v = 0;
  for (const auto& f : films_)
    if (f) v += f->volume();
  return v;
}

Real EffectsView::blood_volume() const {
  Real v = 0;
  for (const auto& f : films_)
    if (f) v += f->blood_volume();
  return v;
}

Real EffectsView::pool() const {
  Real v = lost_ + spilled_ - landed_;
  for (const auto& f : films_)
    if (f) v += f->dripped();
  return v;
}

Real EffectsView::pool_blood() const {
  Real v = lost_ - landed_blood_;
  for (const auto& f : films_)
    if (f) v += f->dripped_blood();
  return v;
}

void EffectsView::ensure_films(std::span<const TissueModel> models) {
  if (films_.size() < models.size()) {
    films_.resize(models.size());
    film_versions_.resize(models.size(), 0);
  }
  for (std::size_t t = 0; t < models.size(); ++t)
    if (!films_[t]) {
      films_[t] = std::make_unique<BloodFilm>(models[t].triangles, models[t].rest, film_properties_);
      film_versions_[t] = models[t].version;
    }
}

void EffectsView::irrigate(const ViewSnapshot& snap, Real dt) {
  for (const InstrumentView& inst : snap.instruments) {
    if (!inst.irrigation || !(inst.suction_spec.irrigation_flow > 0)) continue;
    const Real volume = inst.suction_spec.irrigation_flow * dt;
    // The jet lands on the nearest vertex ahead of the tip along the shaft, within the reach and
    // the jet's radius of its axis (over every surface).
    const Real reach = inst.suction_spec.irrigation_reach, r2 = inst.suction_spec.jet_radius * inst.suction_spec.jet_radius;
    std::size_t hit_tissue = films_.size();
    std::uint32_t hit_vertex = 0;
    Real nearest = reach;
    for (std::size_t t = 0; t < films_.size() && t < snap.tissues.size(); ++t) {
      if (!films_[t] || snap.tissues[t].size() != films_[t]->size()) continue;
      const auto area = films_[t]->area();
      for (std::size_t v = 0; v < snap.tissues[t].size(); ++v) {
        const Vec3 d = snap.tissues[t][v] - inst.tip;
        const Real along = d.dot(inst.forward);
        if (!(along >= 0) || along > nearest || !(area[v] > 0)) continue;
        if (d.squaredNorm() - along * along > r2) continue;
        nearest = along;
        hit_tissue = t;
        hit_vertex = static_cast<std::uint32_t>(v);
      }
    }
    irrigated_ += volume;
    if (hit_tissue >= films_.size()) {
      spilled_ += volume;  // nothing ahead within reach: the jet runs off out of sight
      continue;
    }
    // It splashes over the jet's cross-section around where it hits: the vertices of that surface
    // within the jet's radius of the hit vertex, in proportion to their areas.
    BloodFilm& film = *films_[hit_tissue];
    const std::vector<Vec3>& x = snap.tissues[hit_tissue];
    const Vec3 hit = x[hit_vertex];
    const auto area = film.area();
    Real total = 0;
    for (std::size_t v = 0; v < x.size(); ++v)
      if ((x[v] - hit).squaredNorm() <= r2) total += area[v];
    for (std::size_t v = 0; v < x.size(); ++v)
      if (area[v] > 0 && (x[v] - hit).squaredNorm() <= r2)
        film.add_saline(static_cast<std::uint32_t>(v), volume * (area[v] / total));
  }
}

void EffectsView::draw_in(const ViewSnapshot& snap, Real dt, bool fluid, bool smoke) {
  for (const InstrumentView& inst : snap.instruments) {
    if (!inst.suction) continue;
    // Fluid: up to the valve's flow over dt, from every surface within its radius, in tissue order.
    Real budget = fluid ? inst.suction_spec.suction_flow * dt : 0.0;
    for (std::size_t t = 0; t < films_.size() && t < snap.tissues.size() && budget > 0; ++t) {
      if (!films_[t] || snap.tissues[t].size() != films_[t]->size()) continue;
      Real blood = 0;
      const Real removed =
          films_[t]->remove_within(snap.tissues[t], inst.tip, inst.suction_spec.suction_radius, budget, &blood);
      suctioned_ += removed;
      suctioned_blood_ += blood;
      budget -= removed;
    }
    if (smoke && smoke_) smoke_->suction(inst.tip, inst.suction_spec.smoke_radius, dt);
  }
}

Real EffectsView::update(const ViewSnapshot& snap, std::span<const TissueModel> models, const EffectsSwitches& on) {
  // A jump back in time, or fewer wounds than already fed: the simulation was reset.
  if ((time_ && snap.time < *time_) || snap.wounds.size() < wound_fed_.size()) clear();
  const Real dt = time_ ? snap.time - *time_ : 0.0;
  time_ = snap.time;

  // Films follow their tissue's model: a cut moves the blood to the new vertices (rest positions
  // are copied exactly by a cut; the blood of removed vertices falls off into the pool).
  for (std::size_t t = 0; t < films_.size() && t < models.size(); ++t)
    if (films_[t] && film_versions_[t] != models[t].version) {
      const std::vector<std::uint32_t> origin = match_rest_positions(films_[t]->rest_positions(), models[t].rest);
      films_[t]->remap(origin, models[t].triangles, models[t].rest);
      film_versions_[t] = models[t].version;
    }

  if (on.blood) {
    wound_fed_.resize(snap.wounds.size(), 0.0);
    for (std::size_t w = 0; w < snap.wounds.size(); ++w) {
      const ViewSnapshot::WoundView& wound = snap.wounds[w];
      const Real more = wound.emitted - wound_fed_[w];
      if (!(more > 0)) continue;
      wound_fed_[w] = wound.emitted;
      fed_ += more;
      if (wound.tissue >= models.size()) {
        lost_ += more;
        continue;
      }
      ensure_films(models);
      films_[wound.tissue]->add(wound.vertex, more);  // a bad vertex: dripped
    }
    if (dt > 0) {
      for (const InstrumentView& inst : snap.instruments)
        if (inst.irrigation) ensure_films(models);
      irrigate(snap, dt);
      film_pointers_.clear();
      film_positions_.clear();
      for (std::size_t t = 0; t < films_.size(); ++t) {
        const bool placed = films_[t] && t < snap.tissues.size() && snap.tissues[t].size() == films_[t]->size();
        film_pointers_.push_back(films_[t].get());
        film_positions_.push_back(placed ? std::span<const Vec3>(snap.tissues[t]) : std::span<const Vec3>());
        if (!placed) continue;
        const Vec3 g = t < gravity_.size() ? gravity_[t] : Vec3(0, 0, -9.81);
        const int chunks = std::min(kBloodChunks, std::max(1, int(std::ceil(dt / kBloodChunk - 1e-9))));
        const Real step = std::min(dt, kBloodChunk * kBloodChunks) / chunks;
        for (int k = 0; k < chunks; ++k) films_[t]->step(snap.tissues[t], g, step);
      }
      // What ran off or dripped falls onto the surfaces below (the first tissue's gravity: one
      // scene, one gravity).
      const LandingTally landed = landing_.land(film_pointers_, film_positions_,
                                                gravity_.empty() ? Vec3(0, 0, -9.81) : gravity_[0]);
      landed_ += landed.landed;
      landed_blood_ += landed.landed_blood;
    }
  }

  // Smoke: each electrode's new vaporisation energy, emitted where it boils tissue.
  vapour_seen_.resize(snap.vapour.size(), 0.0);
  for (std::size_t i = 0; i < snap.vapour.size(); ++i) {
    const VapourSource& source = snap.vapour[i];
    const Real more = source.energy - vapour_seen_[i];
    vapour_seen_[i] = source.energy;
    if (!on.smoke || !(more > 0)) continue;
    if (!smoke_) smoke_ = std::make_unique<SmokeField>(smoke_settings_, seed_);
    const Real up_norm = source.up.norm();
    smoke_->emit(source.at, up_norm > 0 ? Vec3(source.up / up_norm) : Vec3::UnitZ(), more);
  }
  if (smoke_ && on.smoke) {
    smoke_->set_venting(on.venting);
    if (dt > 0) smoke_->step(dt);
  }
  if (dt > 0) draw_in(snap, dt, on.blood, on.smoke);
  return dt;
}

bool EffectsView::fill(const ViewSnapshot& snap, std::size_t t, std::size_t vertex_count, bool blood,
                       std::vector<float>& out) const {
  const std::vector<float>* burn = t < snap.tissue_effects.size() ? &snap.tissue_effects[t] : nullptr;
  if (burn && burn->size() != 4 * vertex_count) burn = nullptr;  // not this model's
  const BloodFilm* f = blood ? film(t) : nullptr;
  if (f && (f->size() != vertex_count || !f->touched())) f = nullptr;
  if (!burn && !f) return false;
  if (burn) out.assign(burn->begin(), burn->end());
  else out.assign(4 * vertex_count, 0.0f);
  if (f) {
    const auto stain = f->stain();
    for (std::size_t v = 0; v < vertex_count; ++v) {
      out[4 * v + 2] = float(std::min<Real>(1, f->blood_thickness(v) / kFullFilm));
      out[4 * v + 3] = float(stain[v]);
    }
  }
  return true;
}

}  // namespace trocar
