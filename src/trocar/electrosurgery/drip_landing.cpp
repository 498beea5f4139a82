#include "trocar/electrosurgery/drip_landing.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace trocar {

DripLanding::DripLanding(const LandingSettings& settings) : settings_(settings) {
  columns_.reserve(std::max<std::size_t>(1, settings_.max_columns));
}

LandingTally DripLanding::land(std::span<BloodFilm* const> films, std::span<const std::span<const Vec3>> positions,
                               const Vec3& gravity) {
  LandingTally tally;
  const Real g = gravity.norm();
  const Vec3 down = g > 0 ? Vec3(gravity / g) : Vec3::Zero();
  const auto horizontal = [&](const Vec3& x) -> Vec3 { return x - down.dot(x) * down; };
  const Real r2 = settings_.radius * settings_.radius;
  const std::size_t most = std::max<std::size_t>(1, settings_.max_columns);
  columns_.clear();

  // The fall lines: each pending drip joins a line within the radius, or starts one, or (all
  // lines taken) joins the nearest.
  for (std::size_t k = 0; k < films.size(); ++k) {
    BloodFilm* film = films[k];
    if (film == nullptr || !film->dripping()) continue;
    const bool placed = k < positions.size() && positions[k].size() == film->size() && g > 0;
    const auto drips = film->pending_drips();
    const auto blood = film->pending_blood();
    for (std::size_t i = 0; i < drips.size(); ++i) {
      if (!(drips[i] > 0)) continue;
      if (!placed) {
        tally.pooled += drips[i];
        tally.pooled_blood += blood[i];
        continue;
      }
      const Vec3& x = positions[k][i];
      const Vec3 h = horizontal(x);
      Column* into = nullptr;
      Real nearest = std::numeric_limits<Real>::infinity();
      for (Column& c : columns_) {
        const Real d2 = (horizontal(c.at) - h).squaredNorm();
        if (d2 < nearest) nearest = d2, into = &c;
      }
      if (into == nullptr || (nearest > r2 && columns_.size() < most)) {
        Column c{x, down.dot(x), drips[i], blood[i]};
        c.source = k;
        c.from = x;
        columns_.push_back(c);
        continue;
      }
      const Real total = into->volume + drips[i];
      into->at = (into->at * into->volume + x * drips[i]) / total;
      into->start = std::max(into->start, down.dot(x));
      into->volume = total;
      into->blood += blood[i];
    }
    film->clear_drips();
  }
  if (columns_.empty()) return tally;
  for (Column& c : columns_) c.line = horizontal(c.at);

  // Under each line, over every surface, the vertex that minimises its depth plus its horizontal
  // distance from the line: on a level surface the nearest vertex, and of two surfaces stacked
  // more than `radius` apart the upper one (ties: the first found).
  for (std::size_t k = 0; k < films.size(); ++k) {
    const BloodFilm* film = films[k];
    if (film == nullptr || k >= positions.size() || positions[k].size() != film->size()) continue;
    const auto area = film->area();
    for (std::size_t v = 0; v < film->size(); ++v) {
      if (!(area[v] > 0)) continue;
      const Vec3& x = positions[k][v];
      const Real depth = down.dot(x);
      const Vec3 h = horizontal(x);
      for (Column& c : columns_) {
        if (!(depth > c.start + settings_.clearance)) continue;
        if (k == c.source && (x - c.from).squaredNorm() < 4 * r2) continue;  // where it left
        const Real d2 = (h - c.line).squaredNorm();
        if (d2 > r2) continue;
        const Real score = depth + std::sqrt(d2);
        if (c.found && !(score < c.best)) continue;
        c.best = score;
        c.film = k;
        c.vertex = static_cast<std::uint32_t>(v);
        c.found = true;
      }
    }
  }
  for (const Column& c : columns_) {
    if (c.found) {
      films[c.film]->add_mixture(c.vertex, c.volume, c.blood);
      tally.landed += c.volume;
      tally.landed_blood += c.blood;
    } else {
      tally.pooled += c.volume;
      tally.pooled_blood += c.blood;
    }
  }
  return tally;
}

}  // namespace trocar
