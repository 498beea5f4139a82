// Bleeding: the blood film's flow against thin-film theory and its invariants, wounds against
// their hand-computed rates, haemostasis by coagulation and clips (docs/electrosurgery.md,
// "Bleeding").
#include "trocar/electrosurgery/bleeding.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

namespace trocar {
namespace {

const Vec3 kGravity(0, 0, -9.81);

// A grid of nu × nv cells of `spacing` over (u, v), each cell split in two counter-clockwise in
// (u, v); `place` puts (u, v) in the world (the normal is +w when it keeps orientation).
struct Sheet {
  int nu = 0, nv = 0;
  std::vector<Vec3> x;
  std::vector<Triangle> triangles;
  std::uint32_t at(int i, int j) const { return static_cast<std::uint32_t>(j * (nu + 1) + i); }
};

Sheet grid(int nu, int nv, Real spacing, const std::function<Vec3(Real, Real)>& place) {
  Sheet s;
  s.nu = nu;
  s.nv = nv;
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i) s.x.push_back(place(spacing * i, spacing * j));
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      s.triangles.push_back({s.at(i, j), s.at(i + 1, j), s.at(i + 1, j + 1)});
      s.triangles.push_back({s.at(i, j), s.at(i + 1, j + 1), s.at(i, j + 1)});
    }
  return s;
}

// A plane inclined by θ, falling along +u: (u, v) → (u cos θ, v, −u sin θ); its normal
// (sin θ, 0, cos θ) faces up.
std::function<Vec3(Real, Real)> incline(Real theta) {
  return [theta](Real u, Real v) { return Vec3(u * std::cos(theta), v, -u * std::sin(theta)); };
}

TEST(BloodFilm, RunsDownATiltedPlaneAndNeverUp) {
  // 31 × 31 vertices, 2 mm apart, on a plane inclined 15° whose fall line is 30° off the grid's
  // rows (the film must cross edges of both directions): z = −tan 15° (u cos 30° + v sin 30°).
  const Real slope = std::tan(15 * std::numbers::pi / 180);
  const Real c = std::cos(std::numbers::pi / 6), s = std::sin(std::numbers::pi / 6);
  const Sheet sheet = grid(30, 30, 2e-3, [&](Real u, Real v) { return Vec3(u, v, -slope * (u * c + v * s)); });
  BloodFilm film(sheet.triangles, sheet.x);
  const std::uint32_t source = sheet.at(5, 5);
  film.add(source, 1e-8);  // 2.5 mm over its 4 mm², below max_thickness
  const Real z0 = sheet.x[source].z();
  auto centroid = [&] {
    Real zv = 0;
    for (std::size_t i = 0; i < film.size(); ++i) zv += film.film()[i] * sheet.x[i].z();
    return zv / film.volume();
  };
  Real previous = centroid();
  EXPECT_DOUBLE_EQ(previous, z0);
  for (int step = 0; step < 1000; ++step) {
    film.step(sheet.x, kGravity, 1e-3);
    for (std::size_t i = 0; i < film.size(); ++i) {
      if (film.film()[i] > 0) {
        ASSERT_LE(sheet.x[i].z(), z0 + 1e-15) << "blood above its source at " << i;
      }
    }
    const Real now = centroid();
    ASSERT_LE(now, previous + 1e-18) << step;  // the film's centre only falls
    previous = now;
  }
  EXPECT_LT(previous, z0 - 1e-3);  // it fell at least 1 mm (4 mm along the slope; 1.6 mm when written)
  EXPECT_LT(film.dripped(), 1e-20);  // and not yet off the bottom border (the test's premise)
  EXPECT_NEAR(film.volume() / 1e-8, 1.0, 1e-12);
}

TEST(BloodFilm, NothingFlowsOnAHorizontalSheet) {
  // Any film below the maximum thickness, even uneven, stays put on a level face-up sheet; its
  // borders are level too, so nothing runs off (a "local low point" rule would drain them all).
  const Sheet sheet = grid(10, 10, 2e-3, [](Real u, Real v) { return Vec3(u, v, 0); });
  BloodFilm film(sheet.triangles, sheet.x);
  for (std::uint32_t i = 0; i < film.size(); ++i)
    film.add(i, film.area()[i] * 1e-4 * (1 + (i * 7) % 25));  // 0.1–2.5 mm, uneven
  const std::vector<Real> before(film.film().begin(), film.film().end());
  for (int step = 0; step < 200; ++step) film.step(sheet.x, kGravity, 1e-3);
  for (std::size_t i = 0; i < film.size(); ++i) EXPECT_EQ(film.film()[i], before[i]) << i;
  EXPECT_EQ(film.dripped(), 0.0);
}

// A strip 0.3 m long (150 cells of 2 mm) and 4 mm wide (2 cells) on a 30° incline (s = 0.5), fed
// evenly across its top row at Q for `seconds`. Returns the front's speed between `t_a` and
// `seconds` (m/s, along the slope, where the centre line's thickness falls through half the
// plateau's) and the plateau's thickness at 40 mm and 80 mm down.
struct Front {
  Real speed, plateau_40, plateau_80, dripped;
};
Front run_strip(const FilmProperties& p, Real Q, Real plateau, Real t_a, Real seconds) {
  const Sheet strip = grid(150, 2, 2e-3, incline(std::numbers::pi / 6));
  BloodFilm film(strip.triangles, strip.x, p);
  Real top_area = 0;
  for (int j = 0; j <= 2; ++j) top_area += film.area()[strip.at(0, j)];
  const Real level = 0.5 * plateau;
  auto front = [&] {
    for (int i = 1; i <= 150; ++i) {
      const Real a = film.thickness(strip.at(i - 1, 1)), b = film.thickness(strip.at(i, 1));
      if (a >= level && b < level) return 2e-3 * (i - 1 + (a - level) / (a - b));
    }
    return -1.0;
  };
  const Real dt = 1e-3;
  const int steps = static_cast<int>(std::lround(seconds / dt)), at_a = static_cast<int>(std::lround(t_a / dt));
  Real xa = 0;
  for (int step = 1; step <= steps; ++step) {
    for (int j = 0; j <= 2; ++j) film.add(strip.at(0, j), Q * dt * film.area()[strip.at(0, j)] / top_area);
    film.step(strip.x, kGravity, dt);
    if (step == at_a) xa = front();
  }
  return {(front() - xa) / (seconds - t_a), film.thickness(strip.at(20, 1)), film.thickness(strip.at(40, 1)),
          film.dripped()};
}

TEST(BloodFilm, FrontRunsDownAnInclineAtTheNusseltSpeed) {
  // Fed at Q = 1.5845e-8 m³/s (about 1 ml/min) over W = 4 mm, the film downstream of the source is a
  // plateau whose flux per width q = Q / W = 3.9612e-6 m²/s is the Nusselt flux k s H³,
  // k = ρ g / (3 μ) = 1060 · 9.81 / (3 · 3.5e-3) = 9.90343e5 /(m·s): the mobile thickness
  // H = (q / (k s))^(1/3) = 0.2 mm, moving at the mean speed u = k s H² = 0.019807 m/s. The front
  // is a shock into dry tissue, which keeps the residual h_r = 20 µm behind it: by conservation
  // it runs at q / (H + h_r) = u H / (H + h_r) = 0.018006 m/s. At 8 Q the plateau is twice as
  // thick (q ∝ H³), 0.4 mm, its mean speed 4 u = 0.079228 m/s and the front's 0.075455 m/s.
  const FilmProperties p;
  const Real k = p.density * 9.81 / (3 * p.viscosity);
  const Real H = 2e-4, W = 4e-3;
  const Real Q = k * 0.5 * H * H * H * W;
  EXPECT_NEAR(Q, 1.58455e-8, 1e-12);
  EXPECT_NEAR(nusselt_speed(p, 9.81, 0.5, H), 0.0198069, 1e-6);
  EXPECT_NEAR(nusselt_speed(p, 9.81, 0.5, 2 * H), 0.0792275, 1e-6);
  const Real h_r = p.residual_thickness;
  const Front slow = run_strip(p, Q, H + h_r, 2.0, 6.0);         // front at 36 mm, then 108 mm
  const Front fast = run_strip(p, 8 * Q, 2 * H + h_r, 1.0, 3.0);  // 75 mm, then 226 mm
  const Real expected_slow = nusselt_speed(p, 9.81, 0.5, H) * H / (H + h_r);
  const Real expected_fast = nusselt_speed(p, 9.81, 0.5, 2 * H) * 2 * H / (2 * H + h_r);
  EXPECT_NEAR(expected_slow, 0.0180063, 1e-6);
  EXPECT_NEAR(expected_fast, 0.0754548, 1e-6);
  // First-order upwinding smears the front over a few cells but keeps its speed (it conserves
  // volume): 1 % (0.01 % off when written; a flux law of another power of h, or a dual width off
  // by a factor, misses by tens of %).
  EXPECT_NEAR(slow.speed / expected_slow, 1.0, 0.01);
  EXPECT_NEAR(fast.speed / expected_fast, 1.0, 0.01);
  // Behind it, the plateau stands at the Nusselt thickness (+ the residual layer): 0.1 %.
  EXPECT_NEAR(slow.plateau_40 / (H + h_r), 1.0, 1e-3);
  EXPECT_NEAR(slow.plateau_80 / (H + h_r), 1.0, 1e-3);
  EXPECT_NEAR(fast.plateau_40 / (2 * H + h_r), 1.0, 1e-3);
  EXPECT_NEAR(fast.plateau_80 / (2 * H + h_r), 1.0, 1e-3);
  EXPECT_EQ(slow.dripped, 0.0);  // neither front has reached the bottom (0.3 m)
  EXPECT_EQ(fast.dripped, 0.0);
}

TEST(BloodFilm, ABowlPoolsAtItsLowestVertex) {
  // 13 × 13 vertices 4 mm apart, z = c r² with the rim (r = 24 mm) 6 mm above the centre.
  const Real c = 6e-3 / (24e-3 * 24e-3);
  const Sheet bowl = grid(12, 12, 4e-3, [&](Real u, Real v) {
    const Real x = u - 24e-3, y = v - 24e-3;
    return Vec3(x, y, c * (x * x + y * y));
  });
  BloodFilm film(bowl.triangles, bowl.x);
  const std::uint32_t centre = bowl.at(6, 6), wound = bowl.at(2, 5);
  const Real volume = 4e-8;  // 40 µl: 2.5 mm over the centre's 16 mm², below max_thickness
  film.add(wound, volume);
  Real share = 0;
  for (int step = 1; step <= 15000; ++step) {  // 60 s
    film.step(bowl.x, kGravity, 4e-3);
    if (step % 250 == 0) {
      const Real now = film.film()[centre] / volume;
      EXPECT_GE(now, share) << step;  // it keeps collecting
      share = now;
    }
  }
  // Everything but the wet track's residual and its slowly draining remainder (a thin film drains
  // as t^(−1/2): 70 µm on the track after 60 s) is in the lowest vertex (83 % when written), 20×
  // thicker than anywhere else (30× when written).
  EXPECT_GT(share, 0.8);
  for (std::size_t i = 0; i < film.size(); ++i) {
    if (i != centre) {
      EXPECT_LT(film.thickness(i), film.thickness(centre) / 20) << i;
    }
  }
  EXPECT_EQ(film.dripped(), 0.0);
  EXPECT_NEAR(film.volume() / volume, 1.0, 1e-12);
}

TEST(BloodFilm, APuddleOverTheMaximumThicknessLevelsOut) {
  // On a level face-up sheet, 5 mm at one vertex: the 2 mm over max_thickness (3 mm) is liquid and
  // runs to the neighbours; 3 mm stays (surface tension holds it), nothing leaves the surface.
  const Sheet sheet = grid(10, 10, 2e-3, [](Real u, Real v) { return Vec3(u, v, 0); });
  BloodFilm film(sheet.triangles, sheet.x);
  const std::uint32_t centre = sheet.at(5, 5);
  film.add(centre, 5e-3 * film.area()[centre]);
  for (int step = 0; step < 100; ++step) film.step(sheet.x, kGravity, 1e-3);
  EXPECT_NEAR(film.thickness(centre), 3e-3, 3e-5);
  EXPECT_EQ(film.dripped(), 0.0);
  EXPECT_NEAR(film.volume() / (5e-3 * film.area()[centre]), 1.0, 1e-12);
  for (std::size_t i = 0; i < film.size(); ++i) EXPECT_LE(film.thickness(i), 3e-3 + 3e-5);
}

TEST(BloodFilm, BeneathAnOverhangTheExcessOverTheMaximumThicknessDrips) {
  // A level sheet facing down (v mirrored: its normal is −z). 5 mm at one vertex: 2 mm of it falls,
  // 3 mm hangs (cos φ = 1: the limit is max_thickness); 1 mm elsewhere hangs on.
  const Sheet sheet = grid(6, 6, 2e-3, [](Real u, Real v) { return Vec3(u, -v, 0); });
  BloodFilm film(sheet.triangles, sheet.x);
  const std::uint32_t a = sheet.at(3, 3), b = sheet.at(1, 4);
  const Real area = film.area()[a];
  EXPECT_NEAR(area, 4e-6, 1e-18);
  film.add(a, 5e-3 * area);
  film.add(b, 1e-3 * area);
  film.step(sheet.x, kGravity, 1e-3);
  EXPECT_NEAR(film.thickness(a), 3e-3, 1e-15);
  EXPECT_NEAR(film.dripped(), 2e-3 * area, 1e-20);
  EXPECT_EQ(film.thickness(b), 1e-3);
}

TEST(BloodFilm, WithoutSalineTheStainIsMonotoneAndZeroWhereNoBloodCame) {
  const Sheet sheet = grid(20, 20, 2e-3, incline(0.4));
  BloodFilm film(sheet.triangles, sheet.x);
  const std::uint32_t wound = sheet.at(4, 10);
  std::vector<Real> previous(film.size(), 0.0);
  for (int step = 0; step < 1500; ++step) {
    if (step < 500) film.add(wound, 2e-11);  // 20 µl/s for 0.5 s
    film.step(sheet.x, kGravity, 1e-3);
    for (std::size_t i = 0; i < film.size(); ++i) {
      ASSERT_GE(film.stain()[i], previous[i]) << i;
      ASSERT_LE(film.stain()[i], 1.0);
      previous[i] = film.stain()[i];
    }
  }
  // The track (the fall line below the wound) is stained; above it and beside it, nothing.
  EXPECT_GT(film.stain()[wound], 0.99);
  EXPECT_GT(film.stain()[sheet.at(12, 10)], 0.5);
  int clean = 0;
  for (int j = 0; j <= 20; ++j)
    for (int i = 0; i <= 20; ++i)
      if (i < 4 || j != 10) {
        EXPECT_EQ(film.stain()[sheet.at(i, j)], 0.0) << i << ", " << j;
        ++clean;
      }
  EXPECT_GT(clean, 400);
  // Suction takes the blood, not the stain.
  const Real stained = film.stain()[sheet.at(12, 10)];
  film.remove_within(sheet.x, sheet.x[sheet.at(12, 10)], 1e-2, 1.0);
  EXPECT_EQ(film.film()[sheet.at(12, 10)], 0.0);
  EXPECT_EQ(film.stain()[sheet.at(12, 10)], stained);
}

TEST(BloodFilm, SalineArrivingWashesTheStainByTheStatedFactor) {
  // One vertex of a flat sheet (no flow): blood of 40 µm over its area, then 0.5 mm of saline.
  const Sheet sheet = grid(4, 4, 2e-3, [](Real u, Real v) { return Vec3(u, v, 0); });
  FilmProperties p;
  BloodFilm film(sheet.triangles, sheet.x, p);
  const std::uint32_t v = sheet.at(2, 2);
  const Real area = film.area()[v];
  EXPECT_NEAR(area, 4e-6, 1e-18);  // six triangles of 2 mm² around an interior vertex, a third each
  film.add(v, 40e-6 * area);
  EXPECT_NEAR(film.stain()[v], 1 - std::exp(-40e-6 / p.stain_thickness), 1e-12);
  film.add_saline(v, 0.5e-3 * area);
  // D = 40 µm · e^(−0.5 mm / 0.1 mm); stain 1 − e^(−D / 50 µm).
  const Real d = 40e-6 * std::exp(-0.5e-3 / p.wash_thickness);
  EXPECT_NEAR(film.arrived()[v], d, 1e-15);
  EXPECT_NEAR(film.stain()[v], 1 - std::exp(-d / p.stain_thickness), 1e-12);
  EXPECT_NEAR(film.blood()[v], 40e-6 * area, 1e-24);
  EXPECT_NEAR(film.film()[v], 540e-6 * area, 1e-24);
}

TEST(BloodFilm, SuctionTakesBloodInProportionToTheMixture) {
  const Sheet sheet = grid(4, 4, 2e-3, [](Real u, Real v) { return Vec3(u, v, 0); });
  BloodFilm film(sheet.triangles, sheet.x);
  const std::uint32_t v = sheet.at(2, 2);
  film.add(v, 3e-9);
  film.add_saline(v, 1e-9);
  Real blood = 0;
  // Half of the 4e-9 within reach: 1.5e-9 of blood with it.
  EXPECT_NEAR(film.remove_within(sheet.x, sheet.x[v], 1e-3, 2e-9, &blood), 2e-9, 1e-24);
  EXPECT_NEAR(blood, 1.5e-9, 1e-24);
  EXPECT_NEAR(film.blood()[v], 1.5e-9, 1e-24);
  EXPECT_NEAR(film.film()[v], 2e-9, 1e-24);
}

TEST(BloodFilm, SalineRunsFasterThanBloodAndEachIsConserved) {
  // The same volume, once blood and once saline, down a 20° plane: the Nusselt speed goes as 1/μ,
  // so saline (0.7 mPa·s) runs ahead of blood (3.5 mPa·s). Then a mixture: each part conserved.
  const Sheet sheet = grid(40, 6, 2e-3, incline(20 * std::numbers::pi / 180));
  const std::uint32_t source = sheet.at(2, 3);
  const auto mean_drop = [&](const BloodFilm& f) {
    Real zv = 0, v = 0;
    for (std::size_t i = 0; i < f.size(); ++i) zv += f.film()[i] * sheet.x[i].z(), v += f.film()[i];
    return sheet.x[source].z() - zv / v;
  };
  BloodFilm blood(sheet.triangles, sheet.x), saline(sheet.triangles, sheet.x);
  blood.add(source, 8e-10);  // 0.2 mm over its 4 mm²
  saline.add_saline(source, 8e-10);
  for (int step = 0; step < 200; ++step) {
    blood.step(sheet.x, kGravity, 1e-3);
    saline.step(sheet.x, kGravity, 1e-3);
  }
  EXPECT_GT(mean_drop(saline), 2 * mean_drop(blood));
  EXPECT_EQ(saline.blood_volume(), 0.0);

  BloodFilm mix(sheet.triangles, sheet.x);
  Real blood_in = 0, saline_in = 0;
  for (int step = 0; step < 3000; ++step) {
    if (step < 1000) mix.add(source, 1e-11), blood_in += 1e-11;
    if (step >= 500 && step < 2000) mix.add_saline(sheet.at(1, 3), 3e-11), saline_in += 3e-11;
    mix.step(sheet.x, kGravity, 1e-3);
    for (std::size_t i = 0; i < mix.size(); ++i) {
      ASSERT_GE(mix.blood()[i], 0.0);
      ASSERT_LE(mix.blood()[i], mix.film()[i] * (1 + 1e-9) + 1e-30);
    }
  }
  EXPECT_GT(mix.dripped(), 0.5 * (blood_in + saline_in));  // most ran off the bottom border
  EXPECT_NEAR((mix.blood_volume() + mix.dripped_blood()) / blood_in, 1.0, 1e-12);
  EXPECT_NEAR((mix.volume() + mix.dripped()) / (blood_in + saline_in), 1.0, 1e-12);
}

// A topology change as a cut makes one: the grid's row j = `row` is split (the triangles below it
// take copies of its vertices, appended after the others), and the triangles of the corner cell
// (0, 0) are removed (its corner vertex 0 goes; the others are renumbered down by one).
struct Cut {
  std::vector<std::uint32_t> origin;
  std::vector<Triangle> triangles;
  std::vector<Vec3> rest;
};

Cut split_row_and_drop_corner(const Sheet& s, int row) {
  Cut cut;
  const std::uint32_t n = static_cast<std::uint32_t>(s.x.size());
  // Old → new for the kept vertices (0 dropped), then the copies of the row.
  std::vector<std::uint32_t> index(n);
  for (std::uint32_t v = 1; v < n; ++v) {
    index[v] = v - 1;
    cut.origin.push_back(v);
  }
  std::vector<std::uint32_t> copy(n, 0);
  for (int i = 0; i <= s.nu; ++i) {
    copy[s.at(i, row)] = static_cast<std::uint32_t>(cut.origin.size());
    cut.origin.push_back(s.at(i, row));
  }
  for (std::size_t t = 2; t < s.triangles.size(); ++t) {  // 0 and 1: the corner cell
    const bool below = static_cast<int>(t / 2) / s.nu < row;
    Triangle tri = s.triangles[t];
    for (auto& v : tri) v = below && static_cast<int>(v) / (s.nu + 1) == row ? copy[v] : index[v];
    cut.triangles.push_back(tri);
  }
  for (std::uint32_t o : cut.origin) cut.rest.push_back(s.x[o]);
  return cut;
}

TEST(BloodFilm, RemapConservesVolume) {
  const Sheet sheet = grid(6, 6, 2e-3, [](Real u, Real v) { return Vec3(u, v, 0); });
  BloodFilm film(sheet.triangles, sheet.x);
  for (std::uint32_t i = 0; i < film.size(); ++i) film.add(i, 1e-10 * (1 + i % 5));
  const Real before = film.volume();
  const Real corner = film.film()[0];
  const std::uint32_t split = sheet.at(3, 3);
  const Real split_film = film.film()[split], split_stain = film.stain()[split];
  const Cut cut = split_row_and_drop_corner(sheet, 3);
  film.remap(cut.origin, cut.triangles, cut.rest);
  ASSERT_EQ(film.size(), 49u - 1 + 7);
  EXPECT_NEAR((film.volume() + film.dripped()) / before, 1.0, 1e-15);
  EXPECT_EQ(film.dripped(), corner);  // the dropped corner's blood fell
  // The split vertex's two copies (new 23 and 48 + 3) share its film by area: half each here,
  // the same thickness on both sides, and its stain.
  const std::uint32_t above = split - 1, below = 48 + 3;
  EXPECT_EQ(cut.origin[above], split);
  EXPECT_EQ(cut.origin[below], split);
  EXPECT_NEAR(film.area()[above], 2e-6, 1e-18);
  EXPECT_NEAR(film.area()[below], 2e-6, 1e-18);
  EXPECT_NEAR(film.film()[above], 0.5 * split_film, 1e-25);
  EXPECT_NEAR(film.film()[above] + film.film()[below], split_film, 1e-25);
  EXPECT_EQ(film.stain()[below], split_stain);
  // And it still flows: tilt the cut sheet; the two pieces drain separately, conserving.
  std::vector<Vec3> tilted = cut.rest;
  for (Vec3& x : tilted) x.z() = -0.5 * x.x();
  for (int step = 0; step < 300; ++step) film.step(tilted, kGravity, 1e-3);
  EXPECT_GT(film.dripped(), corner);
  EXPECT_NEAR((film.volume() + film.dripped()) / before, 1.0, 1e-13);
}

// ---------------------------------------------------------------------------------------------
// Wounds and haemostasis

struct OneSheet {
  Sheet sheet = grid(8, 8, 2e-3, incline(0.3));
  Bleeding bleeding;
  std::vector<std::span<const Vec3>> positions;
  OneSheet() {
    bleeding.add_tissue(sheet.triangles, sheet.x);
    positions.emplace_back(sheet.x);
  }
  void run(Real seconds, Real dt = 0.01) {
    const int steps = static_cast<int>(std::lround(seconds / dt));
    for (int s = 0; s < steps; ++s) bleeding.step(positions, kGravity, dt);
  }
};

TEST(Bleeding, AWoundBleedsItsRateTimesTheTimeItIsOpen) {
  // A 2 mm artery: Q = 0.15 m/s · π (1 mm)² = 4.712389e-7 m³/s (28 ml/min), opened at 12.5 ms,
  // mid-step: by 1 s it has bled Q · 0.9875 s = 4.653484e-7 m³.
  OneSheet s;
  const VesselSpec artery{2e-3, true};
  EXPECT_NEAR(bleeding_rate(s.bleeding.properties(), artery), 4.712389e-7, 1e-13);
  const std::size_t w = s.bleeding.open_wound(0, s.sheet.at(1, 4), artery, 0.0125);
  s.run(1.0);
  EXPECT_NEAR(s.bleeding.time(), 1.0, 1e-12);
  EXPECT_NEAR(s.bleeding.emitted() / 4.653484e-7, 1.0, 1e-6);
  EXPECT_EQ(s.bleeding.wounds()[w].emitted, s.bleeding.emitted());
  EXPECT_EQ(s.bleeding.state(w), WoundState::kBleeding);
  EXPECT_FALSE(s.bleeding.time_to_haemostasis(w).has_value());
  // A 1 mm vein: 0.03 m/s · π (0.5 mm)² = 2.356194e-8 m³/s.
  EXPECT_NEAR(bleeding_rate(s.bleeding.properties(), VesselSpec{1e-3, false}), 2.356194e-8, 1e-14);
  EXPECT_NEAR((s.bleeding.volume() + s.bleeding.pool()) / s.bleeding.emitted(), 1.0, 1e-12);
}

TEST(Bleeding, ASmallVesselSealsAtItsDamageThresholdAndStops) {
  // A 1.5 mm artery: Q₀ = 0.15 π (0.75 mm)² = 2.650719e-7 m³/s; it seals at Ω = (1.5 mm / 1 mm)² =
  // 2.25 under the hook (within its 2 mm).
  OneSheet s;
  const VesselSpec vessel{1.5e-3, true};
  const BleedingProperties& p = s.bleeding.properties();
  EXPECT_DOUBLE_EQ(seal_threshold(p, vessel), 2.25);
  EXPECT_DOUBLE_EQ(seal_threshold(p, VesselSpec{0.5e-3, false}), 1.0);
  const std::size_t w = s.bleeding.open_wound(0, s.sheet.at(2, 4), vessel, 0.0);
  s.run(0.5);
  // Ω = 1 closes the lumen by σ = 1 / 2.25: it bleeds (1 − σ)² = 0.308642 of Q₀ for 0.1 s.
  EXPECT_EQ(s.bleeding.coagulate(w, 1.0, 0.05), WoundState::kBleeding);
  EXPECT_NEAR(s.bleeding.rate(w) / 2.650719e-7, 0.308642, 1e-6);
  s.run(0.1);
  EXPECT_EQ(s.bleeding.coagulate(w, 2.2499, 0.05), WoundState::kBleeding);
  EXPECT_EQ(s.bleeding.coagulate(w, 2.25, 0.05), WoundState::kSealed);
  EXPECT_EQ(s.bleeding.rate(w), 0.0);
  const Real emitted = s.bleeding.emitted();
  EXPECT_NEAR(emitted / (2.650719e-7 * (0.5 + 0.308642 * 0.1)), 1.0, 1e-6);
  ASSERT_TRUE(s.bleeding.time_to_haemostasis(w).has_value());
  EXPECT_NEAR(*s.bleeding.time_to_haemostasis(w), 0.6, 1e-12);
  EXPECT_NEAR(s.bleeding.wounds()[w].energy_time, 0.15, 1e-15);
  s.run(1.0);
  EXPECT_EQ(s.bleeding.emitted(), emitted);
  EXPECT_NEAR(*s.bleeding.time_to_haemostasis(w), 0.6, 1e-12);
  // 2 mm is the hook's limit: it still seals (at Ω = 4).
  const std::size_t w2 = s.bleeding.open_wound(0, s.sheet.at(2, 2), VesselSpec{2e-3, false}, s.bleeding.time());
  EXPECT_EQ(s.bleeding.coagulate(w2, 3.99, 0.01), WoundState::kBleeding);
  EXPECT_EQ(s.bleeding.coagulate(w2, 4.0, 0.01), WoundState::kSealed);
  EXPECT_NEAR(*s.bleeding.time_to_haemostasis(w2), 0.0, 1e-15);
}

TEST(Bleeding, AFourMillimetreVesselNeedsAClip) {
  // 4 mm artery: Q = 0.15 π (2 mm)² = 1.884956e-6 m³/s (113 ml/min). The hook cannot seal it at any
  // damage; bipolar sealing (up to 7 mm) could, at Ω = 16.
  OneSheet s;
  const VesselSpec vessel{4e-3, true};
  const std::size_t w = s.bleeding.open_wound(0, s.sheet.at(1, 4), vessel, 0.0);
  s.run(0.2);
  EXPECT_EQ(s.bleeding.coagulate(w, 1e6, 0.2), WoundState::kNeedsClip);
  EXPECT_NEAR(s.bleeding.rate(w) / 1.884956e-6, 1.0, 1e-6);  // no narrowing either
  s.run(0.3);
  EXPECT_EQ(s.bleeding.coagulate(w, 1e9, 0.2), WoundState::kNeedsClip);
  EXPECT_NEAR(s.bleeding.emitted() / (1.884956e-6 * 0.5), 1.0, 1e-6);
  EXPECT_FALSE(s.bleeding.time_to_haemostasis(w).has_value());
  s.bleeding.clip(w);
  EXPECT_EQ(s.bleeding.state(w), WoundState::kClipped);
  const Real emitted = s.bleeding.emitted();
  s.run(0.5);
  EXPECT_EQ(s.bleeding.emitted(), emitted);
  EXPECT_NEAR(*s.bleeding.time_to_haemostasis(w), 0.5, 1e-12);
  // The same vessel under bipolar vessel sealing.
  const std::size_t b = s.bleeding.open_wound(0, s.sheet.at(1, 2), vessel, s.bleeding.time());
  EXPECT_EQ(s.bleeding.coagulate(b, 15.9, 0.1, EnergyModality::kBipolar), WoundState::kBleeding);
  EXPECT_EQ(s.bleeding.coagulate(b, 16.0, 0.1, EnergyModality::kBipolar), WoundState::kSealed);
  // 8 mm is beyond even bipolar.
  const std::size_t big = s.bleeding.open_wound(0, s.sheet.at(1, 6), VesselSpec{8e-3, true}, s.bleeding.time());
  EXPECT_EQ(s.bleeding.coagulate(big, 1e9, 0.1, EnergyModality::kBipolar), WoundState::kNeedsClip);
}

TEST(Bleeding, VolumeIsConservedAcrossWoundsFlowDripsSuctionAndACut) {
  // Three tissues: a 30° strip that runs off its bottom border, a bowl that fills and overflows its
  // levelled puddle, a ceiling that drips. Wounds, suction on the bowl, a cut through the strip.
  Bleeding bleeding;
  Sheet strip = grid(40, 4, 2e-3, incline(std::numbers::pi / 6));
  const Real c = 4e-3 / (12e-3 * 12e-3);
  const Sheet bowl = grid(6, 6, 4e-3, [&](Real u, Real v) {
    const Real x = u - 12e-3, y = v - 12e-3;
    return Vec3(x, y, c * (x * x + y * y));
  });
  const Sheet ceiling = grid(5, 5, 2e-3, [](Real u, Real v) { return Vec3(u, -v, 0.1); });
  bleeding.add_tissue(strip.triangles, strip.x);
  bleeding.add_tissue(bowl.triangles, bowl.x);
  bleeding.add_tissue(ceiling.triangles, ceiling.x);
  const std::size_t a = bleeding.open_wound(0, strip.at(2, 2), VesselSpec{1e-3, true}, 0.0);
  const std::size_t v = bleeding.open_wound(1, bowl.at(1, 3), VesselSpec{2e-3, false}, 0.2);
  bleeding.open_wound(2, ceiling.at(2, 2), VesselSpec{1e-3, false}, 0.1);
  const std::size_t corner = bleeding.open_wound(0, strip.at(0, 0), VesselSpec{0.5e-3, false}, 1.0);
  std::vector<Vec3> strip_x = strip.x;
  std::vector<std::span<const Vec3>> positions{strip_x, bowl.x, ceiling.x};
  const Real dt = 1e-3;
  for (int step = 1; step <= 5000; ++step) {
    if (step == 2500) {
      const Cut cut = split_row_and_drop_corner(strip, 2);
      bleeding.remap_tissue(0, cut.origin, cut.triangles, cut.rest);
      strip_x = cut.rest;
      positions[0] = strip_x;
      EXPECT_EQ(bleeding.wounds()[a].vertex, strip.at(2, 2) - 1);  // its place, renumbered past vertex 0
      // The corner vertex went with its cell: its wound moves to the nearest vertex left, old 1 or
      // old 41 (both 2 mm away, to rounding), now 0 or 40.
      const std::uint32_t moved = bleeding.wounds()[corner].vertex;
      EXPECT_TRUE(moved == 0u || moved == 40u) << moved;
    }
    if (step % 10 == 0) bleeding.suction(1, bowl.x, bowl.x[bowl.at(3, 3)], 5e-3, 2e-8, 10 * dt);
    if (step >= 3000 && step < 3500) bleeding.irrigate(1, bowl.at(2, 2), 1e-10);
    if (step == 4000) bleeding.coagulate(v, 5.0, dt);
    bleeding.step(positions, kGravity, dt);
  }
  EXPECT_EQ(bleeding.state(v), WoundState::kSealed);
  EXPECT_GT(bleeding.pool(), 0.1 * bleeding.emitted());
  EXPECT_GT(bleeding.suctioned(), 0.0);
  EXPECT_GT(bleeding.film(2).dripped(), 0.0);
  EXPECT_GT(bleeding.volume(), 0.0);
  EXPECT_GT(bleeding.suctioned_blood(), 0.0);
  EXPECT_LT(bleeding.suctioned_blood(), bleeding.suctioned());  // saline with it
  EXPECT_NEAR(bleeding.irrigated(), 500 * 1e-10, 1e-18);
  const Real total = bleeding.volume() + bleeding.pool() + bleeding.suctioned();
  EXPECT_NEAR(total / (bleeding.emitted() + bleeding.irrigated()), 1.0, 1e-9);
  const Real blood = bleeding.blood_volume() + bleeding.pool_blood() + bleeding.suctioned_blood();
  EXPECT_NEAR(blood / bleeding.emitted(), 1.0, 1e-9);
}

}  // namespace
}  // namespace trocar
