#include "trocar/scene/anatomy_generators.h"

#include "trocar/core/error.h"
#include "trocar/mesh/anatomy.h"
#include "trocar/mesh/instruments.h"

namespace trocar {
namespace {

std::size_t count(const JsonReader& spec, std::string_view key, std::int64_t fallback, std::int64_t min,
                  std::int64_t max) {
  return static_cast<std::size_t>(spec.has(key) ? spec.at(key).integer(min, max) : fallback);
}

Real length_or(const JsonReader& spec, std::string_view key, Real fallback) {
  return spec.has(key) ? spec.at(key).number_above(0) : fallback;
}

/// Runs a generator, reporting its size errors at the spec's key path.
template <class F>
auto checked(const JsonReader& spec, F&& make) {
  try {
    return make();
  } catch (const Error& e) {
    spec.fail(e.what());
  }
}

std::size_t segments4(const JsonReader& spec, std::int64_t fallback) {
  const std::size_t s = count(spec, "segments", fallback, 8, 1024);
  if (s % 4 != 0) spec.at("segments").fail("must be a multiple of 4");
  return s;
}

}  // namespace

TriMesh generate_hernia_peritoneum(const JsonReader& spec) {
  spec.expect_keys({"generate", "width", "height", "sac_radius", "sac_depth", "segments", "sac_rings", "sheet_rings"});
  const Real w = spec.at("width").number_above(0), h = spec.at("height").number_above(0);
  const Real r = spec.at("sac_radius").number_above(0), d = spec.at("sac_depth").number_above(0);
  if (r >= std::min(w, h) / 2) spec.at("sac_radius").fail("must be < min(width, height)/2");
  const std::size_t s = segments4(spec, 32);
  const std::size_t ks = count(spec, "sac_rings", 6, 1, 256), ka = count(spec, "sheet_rings", 8, 1, 256);
  return checked(spec, [&] { return make_hernia_peritoneum(w, h, r, d, s, ks, ka); });
}

TriMesh generate_abdominal_wall(const JsonReader& spec) {
  spec.expect_keys({"generate", "width", "height", "thickness", "hole_radius", "segments", "rings"});
  const Real w = spec.at("width").number_above(0), h = spec.at("height").number_above(0);
  const Real r = spec.at("hole_radius").number_above(0);
  if (r >= std::min(w, h) / 2) spec.at("hole_radius").fail("must be < min(width, height)/2");
  const Real t = spec.has("thickness") ? spec.at("thickness").number_at_least(0) : 0;
  const std::size_t s = segments4(spec, 32), rings = count(spec, "rings", 6, 1, 256);
  return checked(spec, [&] { return make_abdominal_wall(w, h, t, r, s, rings); });
}

TriMesh generate_liver_lobe(const JsonReader& spec) {
  spec.expect_keys({"generate", "length", "width", "thickness", "subdivisions", "flatten", "taper"});
  const Real l = spec.at("length").number_above(0), w = spec.at("width").number_above(0);
  const Real t = spec.at("thickness").number_above(0);
  const int n = static_cast<int>(count(spec, "subdivisions", 3, 0, 6));
  const Real flatten = spec.number_or("flatten", 0.5), taper = spec.number_or("taper", 0.3);
  if (!(flatten > 0 && flatten <= 1)) spec.at("flatten").fail("must be in (0, 1]");
  if (!(taper >= 0 && taper < 1)) spec.at("taper").fail("must be in [0, 1)");
  return checked(spec, [&] { return make_liver_lobe(l, w, t, n, flatten, taper); });
}

TriMesh generate_grasper(const JsonReader& spec) {
  spec.expect_keys({"generate", "shaft_radius", "shaft_length", "jaw_length", "jaw_width", "jaw_thickness",
                    "jaw_gap", "segments"});
  GrasperSize size;
  size.shaft_radius = length_or(spec, "shaft_radius", size.shaft_radius);
  size.shaft_length = length_or(spec, "shaft_length", size.shaft_length);
  size.jaw_length = length_or(spec, "jaw_length", size.jaw_length);
  size.jaw_width = length_or(spec, "jaw_width", size.jaw_width);
  size.jaw_thickness = length_or(spec, "jaw_thickness", size.jaw_thickness);
  if (spec.has("jaw_gap")) size.jaw_gap = spec.at("jaw_gap").number_at_least(0);
  size.segments = count(spec, "segments", static_cast<std::int64_t>(size.segments), 3, 1024);
  return checked(spec, [&] { return make_grasper(size).mesh; });
}

TriMesh generate_hook_probe(const JsonReader& spec) {
  spec.expect_keys({"generate", "shaft_radius", "shaft_length", "hook_radius", "stem_length", "hook_length",
                    "segments"});
  HookSize size;
  size.shaft_radius = length_or(spec, "shaft_radius", size.shaft_radius);
  size.shaft_length = length_or(spec, "shaft_length", size.shaft_length);
  size.hook_radius = length_or(spec, "hook_radius", size.hook_radius);
  size.stem_length = length_or(spec, "stem_length", size.stem_length);
  size.hook_length = length_or(spec, "hook_length", size.hook_length);
  size.segments = count(spec, "segments", static_cast<std::int64_t>(size.segments), 3, 1024);
  return checked(spec, [&] { return make_hook_probe(size).mesh; });
}

TriMesh generate_tacker(const JsonReader& spec) {
  spec.expect_keys({"generate", "shaft_radius", "shaft_length", "bevel", "segments"});
  TackerSize size;
  size.shaft_radius = length_or(spec, "shaft_radius", size.shaft_radius);
  size.shaft_length = length_or(spec, "shaft_length", size.shaft_length);
  size.bevel = length_or(spec, "bevel", size.bevel);
  size.segments = count(spec, "segments", static_cast<std::int64_t>(size.segments), 3, 1024);
  return checked(spec, [&] { return make_tacker(size).mesh; });
}

TriMesh generate_suction_irrigator(const JsonReader& spec) {
  spec.expect_keys({"generate", "shaft_radius", "shaft_length", "tip_round", "round_rings", "segments"});
  SuctionIrrigatorSize size;
  size.shaft_radius = length_or(spec, "shaft_radius", size.shaft_radius);
  size.shaft_length = length_or(spec, "shaft_length", size.shaft_length);
  size.tip_round = length_or(spec, "tip_round", size.tip_round);
  size.round_rings = count(spec, "round_rings", static_cast<std::int64_t>(size.round_rings), 1, 64);
  size.segments = count(spec, "segments", static_cast<std::int64_t>(size.segments), 3, 1024);
  return checked(spec, [&] { return make_suction_irrigator(size).mesh; });
}

}  // namespace trocar
