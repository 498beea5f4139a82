#include "trocar/electrosurgery/smoke.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace trocar {

namespace {

/// splitmix64 (Steele, Lea & Flood, OOPSLA 2014): one add, two multiplies and three shifts a
/// word, every bit well mixed, any seed (0 included) fine. Integer arithmetic only, so the same
/// on every platform.
std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/// 1 / the standard deviation of a sum of four independent uniform integers on 0 … 65535:
/// each has variance (M² − 1)/12 with M = 65536. sqrt and / are correctly rounded (IEEE 754),
/// so the constant has the same bits everywhere.
const Real kSumOfFourScale = std::sqrt(3.0 / (65536.0 * 65536.0 - 1.0));

/// ∫₀^h e^{−c s} ds = h (1 − e^{−c h}) / (c h) for c ≥ 0 (h at c = 0, 0 at c = ∞); expm1 keeps
/// it exact for small c h.
Real decay_integral(Real c, Real h) {
  if (c == 0) return h;
  if (std::isinf(c)) return 0;
  return -std::expm1(-c * h) / c;
}

bool non_negative(Real x) { return std::isfinite(x) && x >= 0; }
/// A time constant: > 0, infinity allowed (the process off).
bool time_constant(Real x) { return !std::isnan(x) && x > 0; }

void check(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(std::string("SmokeSettings: ") + what);
}

}  // namespace

SmokeField::SmokeField(const SmokeSettings& settings, std::uint64_t seed) : settings_(settings), rng_(seed) {
  const SmokeSettings& s = settings_;
  check(s.capacity > 0 && s.capacity <= std::numeric_limits<std::uint32_t>::max(), "capacity must be 1 … 2³²−1");
  check(non_negative(s.particles_per_joule), "particles_per_joule must be finite and ≥ 0");
  check(std::isfinite(s.rise_speed), "rise_speed must be finite");
  check(non_negative(s.buoyancy_time), "buoyancy_time must be finite and ≥ 0 (0: no buoyancy)");
  check(time_constant(s.drag_time), "drag_time must be > 0 (infinity: no drag)");
  check(non_negative(s.diffusion), "diffusion must be finite and ≥ 0");
  check(non_negative(s.position_jitter) && non_negative(s.velocity_jitter), "jitters must be finite and ≥ 0");
  check(std::isfinite(s.birth_radius) && s.birth_radius > 0, "birth_radius must be finite and > 0");
  check(non_negative(s.growth_rate), "growth_rate must be finite and ≥ 0");
  check(std::isfinite(s.max_radius) && s.max_radius >= s.birth_radius, "max_radius must be finite and ≥ birth_radius");
  check(s.birth_opacity > 0 && s.birth_opacity <= 1, "birth_opacity must be in (0, 1]");
  check(time_constant(s.fade_half_life), "fade_half_life must be > 0 (infinity: no fade)");
  check(time_constant(s.venting_time), "venting_time must be > 0");
  check(time_constant(s.suction_time), "suction_time must be > 0");
  check(non_negative(s.min_opacity) && s.min_opacity < s.birth_opacity, "min_opacity must be in [0, birth_opacity)");
  pool_.resize(s.capacity);
  scratch_.resize(s.capacity);
}

Real SmokeField::gaussian() {
  // Four 16-bit uniforms from one splitmix64 word, summed (Irwin–Hall, n = 4) and scaled to unit
  // variance: integer arithmetic and one correctly rounded multiply, so bit-identical everywhere
  // (Box–Muller's log and cos are not correctly rounded, and may differ in the last bit between C
  // libraries). The sum is bounded at ±3.46 σ and its excess kurtosis is −0.3; the random walk
  // sums many steps (any step distribution of the right variance is Gaussian after a few, by the
  // central limit theorem) and the birth jitter has no use for outliers.
  const std::uint64_t w = splitmix64(rng_);
  const std::int64_t sum = static_cast<std::int64_t>(w & 0xffff) + static_cast<std::int64_t>((w >> 16) & 0xffff) +
                           static_cast<std::int64_t>((w >> 32) & 0xffff) + static_cast<std::int64_t>(w >> 48);
  return static_cast<Real>(sum - 131070) * kSumOfFourScale;  // the mean of the sum is 4 · 32767.5
}

void SmokeField::emit(const Vec3& at, const Vec3& up, Real energy_joules) {
  if (!(energy_joules > 0) || !std::isfinite(energy_joules)) return;
  const SmokeSettings& s = settings_;
  // Floor with a carried remainder that starts at 0.5: the count after any sequence of calls is
  // round(Σ energy · rate), so one call emits round(energy · rate) and a thousand small ones the
  // same as their sum (to the rounding of the running sum). Capped at 2⁵³ (exact in a double).
  const Real total = std::min(carry_ + energy_joules * s.particles_per_joule, 9007199254740992.0);
  const Real whole = std::floor(total);
  carry_ = total - whole;
  const auto n = static_cast<std::size_t>(whole);
  if (n == 0) return;
  emitted_ += n;
  // More than the pool in one call: the first ones would be replaced by the last at once.
  const std::size_t born = std::min(n, pool_.size());
  // When full, the newcomers take the slots of the faintest in place (slot order), rather than
  // the pool shifting down to append them: shifting 4096 particles of 96 bytes doubled the cost
  // of an emission into a full pool (19 µs against 10 µs, bench_electrosurgery), for an order
  // (by birth) that nothing needs: the renderer sorts by depth.
  std::size_t reuse = 0;
  if (born > pool_.size() - size_) {
    reuse = born - (pool_.size() - size_);
    if (reuse >= size_) {
      size_ = 0;  // everything goes
      reuse = 0;
    } else {
      make_room(reuse);
    }
  }

  const Real up_norm = up.norm();
  const Vec3 unit_up = up_norm > 0 ? Vec3(up / up_norm) : Vec3::Zero();
  // The lift whose terminal velocity against the drag is the rise speed (0 without buoyancy).
  const Real lift = s.buoyancy_time > 0 ? s.rise_speed / s.drag_time : 0;
  for (std::size_t k = 0; k < born; ++k) {
    SmokeParticle& p = pool_[k < reuse ? scratch_[k] : size_++];
    p.position = at;
    if (s.position_jitter > 0) {
      const Real x = gaussian(), y = gaussian(), z = gaussian();
      p.position += s.position_jitter * Vec3(x, y, z);
    }
    p.velocity = s.rise_speed * unit_up;
    if (s.velocity_jitter > 0) {
      const Real x = gaussian(), y = gaussian(), z = gaussian();
      p.velocity += s.velocity_jitter * Vec3(x, y, z);
    }
    p.lift = lift * unit_up;
    p.age = 0;
    p.radius = s.birth_radius;
    p.opacity = s.birth_opacity;
  }
}

void SmokeField::make_room(std::size_t count) {
  // The `count` faintest, ties broken by the older, then by the lower slot: a strict total
  // order, so the set chosen is unique, whatever the algorithm that finds it. In still air every
  // particle fades alike, so the faintest are the oldest; a suction tip makes some fainter
  // sooner, and those go first.
  const auto fainter = [this](std::uint32_t a, std::uint32_t b) {
    const SmokeParticle &pa = pool_[a], &pb = pool_[b];
    if (pa.opacity != pb.opacity) return pa.opacity < pb.opacity;
    if (pa.age != pb.age) return pa.age > pb.age;
    return a < b;
  };
  if (count <= 32) {
    // The usual case (a millisecond of cutting adds a few): one scan keeping the count faintest
    // sorted in scratch_. In still air nothing after the first `count` is fainter, so it is a
    // plain read of the opacities; at worst count insertions per particle.
    for (std::uint32_t i = 0; i < count; ++i) {
      std::size_t j = i;
      for (; j > 0 && fainter(i, scratch_[j - 1]); --j) scratch_[j] = scratch_[j - 1];
      scratch_[j] = i;
    }
    for (std::size_t i = count; i < size_; ++i) {
      const auto candidate = static_cast<std::uint32_t>(i);
      if (!fainter(candidate, scratch_[count - 1])) continue;
      std::size_t j = count - 1;
      for (; j > 0 && fainter(candidate, scratch_[j - 1]); --j) scratch_[j] = scratch_[j - 1];
      scratch_[j] = candidate;
    }
  } else {
    // Many at once: introselect, O(size). nth_element's algorithm differs between standard
    // libraries, but under a strict total order the first `count` are the same set.
    for (std::size_t i = 0; i < size_; ++i) scratch_[i] = static_cast<std::uint32_t>(i);
    const auto first = scratch_.begin();
    std::nth_element(first, first + static_cast<std::ptrdiff_t>(count - 1),
                     first + static_cast<std::ptrdiff_t>(size_), fainter);
  }
  // The slots in ascending order, for emit to fill: distinct integers, so any sort agrees.
  std::sort(scratch_.begin(), scratch_.begin() + static_cast<std::ptrdiff_t>(count));
}

void SmokeField::step(Real dt) {
  if (!(dt > 0) || !std::isfinite(dt)) return;
  const SmokeSettings& s = settings_;
  // The exact propagator of  a' = −a/τ_b,  v' = a − v/τ_d  over dt (smoke.h), per step:
  //   a ← γ a,  v ← α v + β a,  with α = e^{−dt/τ_d}, γ = e^{−dt/τ_b},
  //   β = ∫₀^dt e^{−(dt−u)/τ_d} e^{−u/τ_b} du = e^{−min(1/τ_d, 1/τ_b) dt} ∫₀^dt e^{−|1/τ_d − 1/τ_b| s} ds
  // (the second form has no cancellation, and is right at τ_d = τ_b too). The position moves by
  // ∫ v = δ v + ε a with δ = ∫₀^dt e^{−s/τ_d} ds and ε = ∫₀^dt β(s) ds. ε's closed form is a
  // divided difference that cancels as τ_d → τ_b, so it is integrated instead by 4-point
  // Gauss–Legendre of the exact β(s): β is entire, and the rule's error, about 1e-9 (dt/τ)⁷
  // relative, is below rounding at any dt under a tenth of the time constants and 1e-9 at dt = τ.
  // A coasting puff thus travels exactly v τ_d in all and a buoyant one w (τ_d + τ_b), at any dt.
  const Real drag = 1 / s.drag_time;  // 0 when the drag time is infinite
  const Real alpha = std::exp(-drag * dt);
  const Real delta = decay_integral(drag, dt);
  Real beta = 0, gamma = 0, epsilon = 0;
  if (s.buoyancy_time > 0) {
    const Real cool = 1 / s.buoyancy_time;
    const Real slow = std::min(drag, cool), gap = std::abs(drag - cool);
    const auto beta_at = [&](Real t) { return std::exp(-slow * t) * decay_integral(gap, t); };
    gamma = std::exp(-cool * dt);
    beta = beta_at(dt);
    constexpr Real kNode[2] = {0.3399810435848562648, 0.8611363115940525752};
    constexpr Real kWeight[2] = {0.6521451548625461426, 0.3478548451374538574};
    for (int k = 0; k < 2; ++k)
      epsilon += kWeight[k] * (beta_at(dt * (1 - kNode[k]) / 2) + beta_at(dt * (1 + kNode[k]) / 2));
    epsilon *= dt / 2;
  }
  const Real sigma = std::sqrt(2 * s.diffusion * dt);
  const Real fade_rate = std::log(2.0) / s.fade_half_life + (venting_ ? 1 / s.venting_time : 0);
  const Real fade = std::exp(-fade_rate * dt);
  const Real grow = s.growth_rate * dt;

  // One pass: advance, and compact the survivors in place (order kept).
  std::size_t kept = 0;
  for (std::size_t i = 0; i < size_; ++i) {
    SmokeParticle& p = pool_[i];
    p.position += delta * p.velocity + epsilon * p.lift;
    if (sigma > 0) {
      const Real x = gaussian(), y = gaussian(), z = gaussian();
      p.position += sigma * Vec3(x, y, z);
    }
    p.velocity = alpha * p.velocity + beta * p.lift;
    p.lift *= gamma;
    p.age += dt;
    if (p.radius < s.max_radius) {
      const Real radius = std::min(p.radius + grow, s.max_radius);
      const Real dilution = p.radius / radius;  // α r² kept as the puff expands
      p.opacity *= fade * dilution * dilution;
      p.radius = radius;
    } else {
      p.opacity *= fade;
    }
    if (p.opacity < s.min_opacity) continue;  // the random draws were made all the same
    if (kept != i) pool_[kept] = p;
    ++kept;
  }
  size_ = kept;
}

void SmokeField::suction(const Vec3& tip, Real radius, Real dt) {
  if (!(dt > 0) || !(radius > 0) || !std::isfinite(dt)) return;
  const Real factor = std::exp(-dt / settings_.suction_time);
  const Real r2 = radius * radius;
  for (std::size_t i = 0; i < size_; ++i) {
    SmokeParticle& p = pool_[i];
    if ((p.position - tip).squaredNorm() <= r2) p.opacity *= factor;
  }
  remove_faint();
}

void SmokeField::remove_faint() {
  const Real threshold = settings_.min_opacity;
  std::size_t kept = 0;
  for (std::size_t i = 0; i < size_; ++i) {
    if (pool_[i].opacity < threshold) continue;
    if (kept != i) pool_[kept] = pool_[i];
    ++kept;
  }
  size_ = kept;
}

Real SmokeField::optical_depth(const Vec3& from, const Vec3& to) const {
  const Vec3 d = to - from;
  const Real length = d.norm();
  if (!(length > 0)) return 0;
  const Vec3 u = d / length;
  Real depth = 0;
  for (std::size_t i = 0; i < size_; ++i) {
    const SmokeParticle& p = pool_[i];
    const Vec3 m = p.position - from;
    const Real along = m.dot(u);                       // the closest point of the line, from `from`
    const Real off2 = (m - along * u).squaredNorm();   // the centre's distance² to the line
    const Real half2 = p.radius * p.radius - off2;     // (half the chord)²: no cancellation at the centre
    if (!(half2 > 0)) continue;
    const Real half = std::sqrt(half2);
    const Real chord = std::min(along + half, length) - std::max(along - half, Real(0));
    if (chord > 0) depth += p.opacity * chord / (2 * p.radius);
  }
  return depth;
}

Real SmokeField::total_cover() const {
  Real cover = 0;
  for (std::size_t i = 0; i < size_; ++i) cover += pool_[i].opacity * pool_[i].radius * pool_[i].radius;
  return cover;
}

}  // namespace trocar
