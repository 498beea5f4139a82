#include "robustness_command.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "trocar/core/error.h"
#include "trocar/study/robustness.h"
#include "trocar/study/robustness_report.h"

namespace trocar::cli {
namespace {

namespace fs = std::filesystem;

struct RobustnessArgs {
  std::vector<std::string> organs;       ///< folders of organ meshes (default: ../shared/data/meshes if there)
  std::string out = "study-robustness";
  std::vector<std::string> solvers;      ///< --solvers (alias --methods); default xpbd sdf
  std::vector<std::string> materials;    ///< default light-soft medium heavy-stiff
  std::vector<std::string> instruments;  ///< default every instrument (hook-mesh when its file is there)
  std::vector<std::string> motions;      ///< default every motion
  bool no_generated = false;
  /// One small generated organ; light-soft and heavy-stiff, hook, press and poke-1, xpbd and sdf
  /// (CI). Lists given alongside replace these defaults.
  bool quick = false;
  std::uint64_t seed = 1;
};

/// The shared meshes beside the checkout or the working directory, if any.
std::vector<fs::path> default_organ_dirs() {
  std::vector<fs::path> out;
  for (const fs::path& p : {fs::path("../shared/data/meshes"), fs::path(TROCAR_SOURCE_SCENES) / "../../shared/data/meshes"}) {
    std::error_code ec;
    if (fs::is_directory(p, ec)) {
      out.push_back(fs::weakly_canonical(p, ec));
      break;
    }
  }
  return out;
}

/// `names` joined with ", ".
std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

/// One run to do: indices into the organs, instruments and solvers, a motion and a material name.
struct SuiteCase {
  std::size_t organ = 0;
  std::string material;
  std::size_t instrument = 0;
  SuiteMotion motion = SuiteMotion::kPress;
  std::size_t solver = 0;
};

void run_robustness(const RobustnessArgs& a) {
  // The lists: given, else --quick's, else the full suite's.
  const auto pick = [&](const std::vector<std::string>& given, std::vector<std::string> quick,
                        std::vector<std::string> full) {
    if (!given.empty()) return given;
    return a.quick ? quick : full;
  };
  const std::vector<std::string> solver_names = pick(a.solvers, {"xpbd", "sdf"}, {"xpbd", "sdf"});
  const std::vector<std::string> material_names =
      pick(a.materials, {"light-soft", "heavy-stiff"}, suite_contact_material_names());
  const std::vector<std::string> instrument_names = pick(a.instruments, {"hook"}, suite_instrument_names());
  std::vector<std::string> every_motion;
  for (const SuiteMotion m : all_suite_motions()) every_motion.emplace_back(suite_motion_name(m));
  const std::vector<std::string> motion_names = pick(a.motions, {"press", "poke-1"}, every_motion);

  std::vector<SuiteSolver> solvers;
  for (const std::string& name : solver_names) {
    const std::optional<SuiteSolver> s = parse_suite_solver(name);
    if (!s) throw Error("--solvers: unknown solver \"" + name + "\" (known: " + joined(suite_solver_names()) + ")");
    solvers.push_back(*s);
  }
  const std::vector<std::string> known_materials = suite_material_names();
  for (const std::string& name : material_names)
    if (std::find(known_materials.begin(), known_materials.end(), name) == known_materials.end())
      throw Error("--materials: unknown material \"" + name + "\" (known: " + joined(known_materials) + ")");
  std::vector<SuiteMotion> motions;
  for (const std::string& name : motion_names) {
    const std::optional<SuiteMotion> m = parse_suite_motion(name);
    if (!m) throw Error("--motions: unknown motion \"" + name + "\" (known: " + joined(every_motion) + ")");
    motions.push_back(*m);
  }

  std::vector<fs::path> dirs(a.organs.begin(), a.organs.end());
  for (const fs::path& d : dirs) {
    std::error_code ec;
    if (!fs::is_directory(d, ec)) throw Error("--organs: no such folder " + d.string());
  }
  const std::vector<fs::path> shared = default_organ_dirs();
  if (dirs.empty()) dirs = shared;

  // Instruments: hook-mesh is left out when no folder holds its file. The probe motions run with
  // every selected instrument but the grasper (with the grasper when it is the only one);
  // grasp-lift always with the grasper.
  const std::vector<std::string> known_instruments = suite_instrument_names();
  std::vector<fs::path> instrument_dirs = dirs;
  instrument_dirs.insert(instrument_dirs.end(), shared.begin(), shared.end());
  std::vector<SuiteInstrument> instruments;
  std::vector<std::size_t> pushers;
  bool grasper_selected = false;
  for (const std::string& name : instrument_names) {
    if (std::find(known_instruments.begin(), known_instruments.end(), name) == known_instruments.end())
      throw Error("--instruments: unknown instrument \"" + name + "\" (known: " + joined(known_instruments) + ")");
    if (name == "grasper") {
      grasper_selected = true;
      continue;
    }
    std::optional<SuiteInstrument> tool = suite_instrument(name, instrument_dirs);
    if (!tool) continue;  // hook-mesh without ../shared
    pushers.push_back(instruments.size());
    instruments.push_back(std::move(*tool));
  }
  const std::size_t grasper = instruments.size();
  instruments.push_back(*suite_instrument("grasper"));
  if (pushers.empty() && grasper_selected) pushers.push_back(grasper);

  std::vector<SuiteOrgan> organs;
  if (a.quick) {
    std::vector<SuiteOrgan> family = generated_organs(a.seed);
    organs.push_back(std::move(family.front()));
  } else {
    for (const fs::path& d : dirs)
      for (SuiteOrgan& o : organs_in(d, "shared")) organs.push_back(std::move(o));
    if (!a.no_generated)
      for (SuiteOrgan& o : generated_organs(a.seed)) organs.push_back(std::move(o));
  }
  if (organs.empty()) throw Error("no organs (give --organs DIR or drop --no-generated)");

  // organ × material × instrument × motion × solver; grasp-lift with the grasper after the
  // instruments; the rest check (light-stiff, first instrument) after the materials.
  std::vector<SuiteCase> cases;
  const bool rest = std::find(motions.begin(), motions.end(), SuiteMotion::kRest) != motions.end();
  const bool grasp = std::find(motions.begin(), motions.end(), SuiteMotion::kGraspLift) != motions.end();
  const bool probe_motions = std::any_of(motions.begin(), motions.end(), [](SuiteMotion m) {
    return m != SuiteMotion::kRest && m != SuiteMotion::kGraspLift;
  });
  if (probe_motions && pushers.empty())
    throw Error("--instruments: none available for the probe motions (hook-mesh needs " +
                std::string(kSuiteHookMeshFile) + " in ../shared/data/meshes or an --organs folder)");
  for (std::size_t o = 0; o < organs.size(); ++o) {
    for (const std::string& material : material_names) {
      for (const std::size_t i : pushers)
        for (const SuiteMotion m : motions) {
          if (m == SuiteMotion::kRest || m == SuiteMotion::kGraspLift) continue;
          for (std::size_t s = 0; s < solvers.size(); ++s) cases.push_back({o, material, i, m, s});
        }
      if (grasp)
        for (std::size_t s = 0; s < solvers.size(); ++s)
          cases.push_back({o, material, grasper, SuiteMotion::kGraspLift, s});
    }
    if (rest)
      for (std::size_t s = 0; s < solvers.size(); ++s)
        cases.push_back({o, kSuiteRestMaterial, pushers.empty() ? grasper : pushers.front(), SuiteMotion::kRest, s});
  }

  const fs::path out = a.out;
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) throw Error("cannot create " + out.string() + ": " + ec.message());
  const auto start = std::chrono::steady_clock::now();
  std::vector<SuiteRun> runs;
  for (const SuiteCase& c : cases) {
    const SuiteOrgan& organ = organs[c.organ];
    runs.push_back(run_suite_case(organ, c.motion, suite_material(c.material, organ), instruments[c.instrument],
                                  solvers[c.solver]));
    const SuiteRun& r = runs.back();
    std::cout << "[" << runs.size() << "/" << cases.size() << "] " << robustness_run_line(r) << std::endl;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const bool plots = write_robustness_report(out, runs, wall);
  std::cout << "wrote " << (out / "robustness.csv").string() << " and " << (out / "robustness.md").string()
            << (plots ? " with SVG plots" : " (gnuplot not found: no plots; plots.gp written)") << "\n";
}

}  // namespace

void add_robustness_command(CLI::App& study) {
  auto a = std::make_shared<RobustnessArgs>();
  CLI::App* cmd = study.add_subcommand(
      "robustness",
      "Every organ x material x instrument x motion x solver: step time, CG iterations, substeps, constraint "
      "error, penetration, tunneling, energy drift at rest");
  cmd->add_option("--organs", a->organs, "Folder(s) of organ meshes (default: ../shared/data/meshes when present)");
  cmd->add_option("--out", a->out, "Output folder (robustness.csv, robustness.md, SVG plots)")->capture_default_str();
  cmd->add_option("--solvers,--methods", a->solvers,
                  "Solvers: xpbd (contact inside the solver) or a response method on implicit Euler: sdf project "
                  "obb primitive normal (default: xpbd sdf)");
  cmd->add_option("--materials", a->materials,
                  "Materials: light-soft medium heavy-stiff light-stiff preset (default: light-soft medium "
                  "heavy-stiff; the rest check always uses light-stiff)");
  cmd->add_option("--instruments", a->instruments,
                  "Instruments: hook hook-mesh grasper probe10 (default: all; hook-mesh only where "
                  "../shared/data/meshes has it; grasp-lift always uses the grasper)");
  cmd->add_option("--motions", a->motions,
                  "Motions (default: press slide poke-0.2 poke-1 poke-2 deep-press grasp-lift rest)");
  cmd->add_option("--seed", a->seed, "Seed of the generated organ family")->capture_default_str();
  cmd->add_flag("--no-generated", a->no_generated, "Leave out the generated organ family");
  cmd->add_flag("--quick", a->quick,
                "One small generated organ; light-soft and heavy-stiff, hook, press and poke-1, xpbd and sdf "
                "(for CI; lists given alongside replace these)");
  cmd->callback([a] { run_robustness(*a); });
}

}  // namespace trocar::cli
