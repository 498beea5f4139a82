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
  fed_ = lost_ = 0;
}

const BloodFilm* EffectsView::film(std::size_t t) const { return t < films_.size() ? films_[t].get() : nullptr; }

Real EffectsView::volume() const {
  Real v = 0;
  for (const auto& f : films_)
    if (f) v += f->volume();
  return v;
}

Real EffectsView::dripped() const {
  Real v = lost_;
  for (const auto& f : films_)
    if (f) v += f->dripped();
  return v;
}

BloodFilm* EffectsView::ensure_film(std::size_t t, const TissueModel& model) {
  if (films_.size() <= t) {
    films_.resize(t + 1);
    film_versions_.resize(t + 1, 0);
  }
  if (!films_[t]) {
    films_[t] = std::make_unique<BloodFilm>(model.triangles, model.rest, film_properties_);
    film_versions_[t] = model.version;
  }
  return films_[t].get();
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
      ensure_film(wound.tissue, models[wound.tissue])->add(wound.vertex, more);  // a bad vertex: dripped
    }
    if (dt > 0)
      for (std::size_t t = 0; t < films_.size() && t < snap.tissues.size(); ++t) {
        if (!films_[t] || snap.tissues[t].size() != films_[t]->size()) continue;
        const Vec3 g = t < gravity_.size() ? gravity_[t] : Vec3(0, 0, -9.81);
        const int chunks = std::min(kBloodChunks, std::max(1, int(std::ceil(dt / kBloodChunk - 1e-9))));
        const Real step = std::min(dt, kBloodChunk * kBloodChunks) / chunks;
        for (int k = 0; k < chunks; ++k) films_[t]->step(snap.tissues[t], g, step);
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
  return dt;
}

bool EffectsView::fill(const ViewSnapshot& snap, std::size_t t, std::size_t vertex_count, bool blood,
                       std::vector<float>& out) const {
  const std::vector<float>* burn = t < snap.tissue_effects.size() ? &snap.tissue_effects[t] : nullptr;
  if (burn && burn->size() != 4 * vertex_count) burn = nullptr;  // not this model's
  const BloodFilm* f = blood ? film(t) : nullptr;
  if (f && f->size() != vertex_count) f = nullptr;
  if (!burn && !f) return false;
  if (burn) out.assign(burn->begin(), burn->end());
  else out.assign(4 * vertex_count, 0.0f);
  if (f) {
    const auto stain = f->stain();
    for (std::size_t v = 0; v < vertex_count; ++v) {
      out[4 * v + 2] = float(std::min<Real>(1, f->thickness(v) / kFullFilm));
      out[4 * v + 3] = float(stain[v]);
    }
  }
  return true;
}

}  // namespace trocar
