#pragma once
/// The penetration study (docs/penetration-study.md): residual penetration and tunneling of the
/// shipped scenes' instruments against instrument speed × response method × detection period.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "trocar/core/types.h"
#include "trocar/response/settings.h"

namespace trocar {

/// A response variant of the sweep: a method, with or without the depth cap (obb, project) and
/// the gate on the position correction (project, primitive).
struct PenetrationVariant {
  ResponseMethod method = ResponseMethod::kObb;
  bool depth_cap = true;
  bool gated = true;
  /// "obb", …; "obb-uncapped" for the seed's step 7 verbatim; "project-ungated" and
  /// "primitive-ungated" for the full correction at every contact.
  std::string name() const;
};

/// One point of the sweep.
struct PenetrationRow {
  std::string scene;            ///< scene file stem
  std::string method;           ///< PenetrationVariant::name()
  Real period_ms = 1;           ///< detection period (ms)
  Real speed = 0;               ///< instrument speed on every moving segment (m/s)
  std::size_t steps = 0;        ///< steps simulated
  Real penetration_max = 0;     ///< m, max over steps
  Real penetration_p99 = 0;     ///< m, p99 over the steps with a vertex inside (0 if none)
  std::uint64_t tunneling = 0;  ///< Σ tunneling events
  std::uint64_t applied = 0;    ///< Σ applied contacts
  bool stable = true;           ///< every step stable (core/stability.h)
};

/// The sweep: scenes (file stems in the scenes folder) × variants × periods (s) × speeds (m/s).
struct PenetrationSweep {
  std::vector<std::string> scenes;
  std::vector<PenetrationVariant> variants;
  std::vector<Real> periods;
  std::vector<Real> speeds;
  /// probe_press_slide and stab; 7 variants; 1, 2, 5 ms; 0.01–2 m/s.
  static PenetrationSweep full();
  /// probe_press_slide; obb and primitive; 1 and 5 ms; 0.5 m/s (CI).
  static PenetrationSweep quick();
  std::size_t size() const { return scenes.size() * variants.size() * periods.size() * speeds.size(); }
};

/// One run: the scene with every moving keyframe segment re-timed to `speed`, the variant's
/// response and detection every `period` s, for the motion and then 50 ms held.
PenetrationRow run_penetration_point(const std::filesystem::path& scene_file, const PenetrationVariant& variant,
                                     Real period, Real speed);

/// Runs the sweep over `scenes_dir`/NAME.json, calling `progress(row, done, total)` after each
/// run. Throws trocar::Error when a scene file is missing.
std::vector<PenetrationRow> run_penetration_sweep(
    const PenetrationSweep& sweep, const std::filesystem::path& scenes_dir,
    const std::function<void(const PenetrationRow&, std::size_t, std::size_t)>& progress = {});

/// Writes penetration.csv, plots.gp (and, when gnuplot is on the PATH, the SVG plots) and
/// summary.md into `out`; `wall_s` is printed in the summary. Returns whether plots were drawn.
bool write_penetration_report(const std::filesystem::path& out, const std::vector<PenetrationRow>& rows,
                              const std::vector<PenetrationVariant>& variants, double wall_s);

/// Depth in millimetres, 3 significant digits.
std::string millimetres(Real metres);

}  // namespace trocar
