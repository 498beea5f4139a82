// Where drips land: on the highest surface under their fall line, or in the pool; volumes and
// their blood conserved (docs/electrosurgery.md, "Bleeding").
#include "trocar/electrosurgery/drip_landing.h"

#include <gtest/gtest.h>

#include <functional>
#include <vector>

namespace trocar {
namespace {

const Vec3 kGravity(0, 0, -9.81);

struct Flat {
  std::vector<Vec3> x;
  std::vector<Triangle> triangles;
  int n = 0;
  std::uint32_t at(int i, int j) const { return static_cast<std::uint32_t>(j * (n + 1) + i); }
};

// n × n cells of `spacing` at height z, centred on (cx, cy); `up`: its normal faces +z.
Flat flat(int n, Real spacing, Real cx, Real cy, Real z, bool up) {
  Flat f;
  f.n = n;
  const Real half = 0.5 * n * spacing;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) f.x.emplace_back(cx - half + spacing * i, cy - half + spacing * j, z);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const std::uint32_t a = f.at(i, j), b = f.at(i + 1, j), c = f.at(i + 1, j + 1), d = f.at(i, j + 1);
      if (up) {
        f.triangles.push_back({a, b, c});
        f.triangles.push_back({a, c, d});
      } else {
        f.triangles.push_back({a, c, b});
        f.triangles.push_back({a, d, c});
      }
    }
  return f;
}

// A ceiling (facing down) with more blood at its centre than surface tension holds: it drips.
struct Scene {
  Flat ceiling = flat(4, 2e-3, 0, 0, 0.05, false);
  Flat upper = flat(4, 2e-3, 0, 0, 0.02, true);   // a shelf under the ceiling's centre
  Flat lower = flat(10, 2e-3, 0, 0, 0.0, true);   // the floor, wider
  std::vector<BloodFilm> films;
  std::vector<std::span<const Vec3>> positions;
  Scene() {
    films.emplace_back(ceiling.triangles, ceiling.x);
    films.emplace_back(upper.triangles, upper.x);
    films.emplace_back(lower.triangles, lower.x);
    positions = {ceiling.x, upper.x, lower.x};
  }
  std::vector<BloodFilm*> pointers() { return {&films[0], &films[1], &films[2]}; }
};

TEST(DripLanding, ADripLandsOnTheHighestSurfaceUnderItAndNowhereElse) {
  Scene s;
  const std::uint32_t centre = s.ceiling.at(2, 2);
  const Real area = s.films[0].area()[centre];
  s.films[0].add(centre, 5e-3 * area);        // 5 mm: over the 3 mm a ceiling holds
  s.films[0].add_saline(centre, 1e-3 * area);
  s.films[0].step(s.ceiling.x, kGravity, 1e-3);
  const Real dripped = s.films[0].dripped(), dripped_blood = s.films[0].dripped_blood();
  EXPECT_NEAR(dripped, 3e-3 * area, 1e-9 * area);  // 6 mm on a horizontal ceiling keeps 3 mm
  EXPECT_NEAR(dripped_blood, dripped * 5.0 / 6.0, 1e-12 * dripped);
  ASSERT_TRUE(s.films[0].dripping());

  DripLanding landing;
  const auto films = s.pointers();
  const LandingTally tally = landing.land(films, s.positions, kGravity);
  EXPECT_EQ(tally.landed, dripped);
  EXPECT_EQ(tally.landed_blood, dripped_blood);
  EXPECT_EQ(tally.pooled, 0.0);
  // Straight down onto the shelf's centre vertex (directly under it), not the floor beneath.
  EXPECT_EQ(s.films[1].film()[s.upper.at(2, 2)], dripped);
  EXPECT_EQ(s.films[1].blood()[s.upper.at(2, 2)], dripped_blood);
  EXPECT_EQ(s.films[2].volume(), 0.0);
  EXPECT_FALSE(s.films[0].dripping());
  // Nothing pending: a second call lands nothing.
  const LandingTally again = landing.land(films, s.positions, kGravity);
  EXPECT_EQ(again.landed + again.pooled, 0.0);
}

TEST(DripLanding, BesideTheShelfItFallsToTheFloorAndOffEverythingIntoThePool) {
  Scene s;
  // The ceiling's corner (4 mm, 4 mm) is outside the shelf (±4 mm) by less than the radius; move
  // the shelf away so the corner's line misses it, and the floor's edge at ±10 mm.
  for (Vec3& x : s.upper.x) x.x() += 0.02;
  for (Vec3& x : s.lower.x) x.x() += 0.006;  // the floor spans x ∈ [−4, 16] mm
  const std::uint32_t corner = s.ceiling.at(0, 0);       // (−4, −4) mm: over the floor's edge
  const std::uint32_t other = s.ceiling.at(4, 4);        // (4, 4) mm: over the floor
  DripLanding landing(LandingSettings{0.001, 0.001, 32});
  s.films[0].add(corner, 1e-8);
  s.films[0].add(other, 1e-8);
  // Shed them as an overhang does: step with the ceiling holding nothing (max thickness 0 would
  // be unphysical); instead, mark them dripping by hand through a film that holds less.
  FilmProperties thin;
  thin.max_thickness = 1e-5;
  BloodFilm ceiling(s.ceiling.triangles, s.ceiling.x, thin);
  ceiling.add(corner, 1e-8);
  ceiling.add(other, 1e-8);
  ceiling.step(s.ceiling.x, kGravity, 1e-3);
  ASSERT_TRUE(ceiling.dripping());
  const Real shed = ceiling.dripped();
  std::vector<BloodFilm*> films{&ceiling, &s.films[1], &s.films[2]};
  const LandingTally tally = landing.land(films, s.positions, kGravity);
  EXPECT_NEAR(tally.landed + tally.pooled, shed, 1e-12 * shed);
  EXPECT_GT(tally.landed, 0.0);
  EXPECT_NEAR(s.films[2].volume(), tally.landed, 1e-12 * shed);  // the floor took what landed
  EXPECT_EQ(s.films[1].volume(), 0.0);                           // the shelf is elsewhere
  // (4, 4) mm lands on the floor vertex (4, 4) mm; (−4, −4) mm is over the floor's edge vertex
  // x = −4 mm: it lands too. Move the floor 2 mm further and the corner falls into the pool.
  for (Vec3& x : s.lower.x) x.x() += 0.002;
  ceiling.add(corner, 1e-8);
  ceiling.step(s.ceiling.x, kGravity, 1e-3);
  const Real before = s.films[2].volume();
  const LandingTally second = landing.land(films, s.positions, kGravity);
  EXPECT_GT(second.pooled, 0.0);
  EXPECT_LT(second.landed, 1e-9 * second.pooled);  // the other corner's rounding
  EXPECT_NEAR(s.films[2].volume(), before, 1e-9 * second.pooled);
}

TEST(DripLanding, ManyDripsMergeIntoAtMostTheStatedLinesAndAllArrive) {
  Scene s;
  FilmProperties thin;
  thin.max_thickness = 1e-5;
  BloodFilm ceiling(s.ceiling.triangles, s.ceiling.x, thin);
  Real added = 0;
  for (std::uint32_t v = 0; v < ceiling.size(); ++v) ceiling.add(v, 1e-9 * (1 + v)), added += 1e-9 * (1 + v);
  ceiling.step(s.ceiling.x, kGravity, 1e-3);
  const Real shed = ceiling.dripped();
  ASSERT_GT(shed, 0.5 * added);
  DripLanding landing(LandingSettings{0.004, 0.001, 3});
  std::vector<BloodFilm*> films{&ceiling, &s.films[1], &s.films[2]};
  const LandingTally tally = landing.land(films, s.positions, kGravity);
  EXPECT_NEAR(tally.landed + tally.pooled, shed, 1e-12 * shed);
  EXPECT_EQ(tally.pooled, 0.0);  // every line is over the shelf or the floor
  int wet = 0;
  for (int k = 1; k <= 2; ++k)
    for (Real v : s.films[k].film()) wet += v > 0;
  EXPECT_GE(wet, 1);
  EXPECT_LE(wet, 3);  // three lines at most
  EXPECT_NEAR(s.films[1].volume() + s.films[2].volume(), tally.landed, 1e-12 * shed);
}

TEST(DripLanding, WithoutGravityOrPlaceEverythingPools) {
  Scene s;
  FilmProperties thin;
  thin.max_thickness = 1e-5;
  BloodFilm ceiling(s.ceiling.triangles, s.ceiling.x, thin);
  ceiling.add(s.ceiling.at(2, 2), 1e-8);
  ceiling.step(s.ceiling.x, kGravity, 1e-3);
  const Real shed = ceiling.dripped();
  std::vector<BloodFilm*> films{&ceiling, &s.films[1], &s.films[2]};
  DripLanding landing;
  const LandingTally none = landing.land(films, s.positions, Vec3::Zero());
  EXPECT_EQ(none.pooled, shed);
  EXPECT_FALSE(ceiling.dripping());
  // Positions that are not the ceiling's: its drips cannot be placed.
  ceiling.add(s.ceiling.at(2, 2), 1e-8);
  ceiling.step(s.ceiling.x, kGravity, 1e-3);
  std::vector<std::span<const Vec3>> wrong{std::span<const Vec3>(), s.upper.x, s.lower.x};
  const LandingTally lost = landing.land(films, wrong, kGravity);
  EXPECT_GT(lost.pooled, 0.0);
  EXPECT_EQ(lost.landed, 0.0);
}

}  // namespace
}  // namespace trocar
