#include "mesh_command.h"

#include "mesh_build_command.h"

#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "trocar/core/error.h"
#include "trocar/mesh/generate.h"
#include "trocar/mesh/io/mesh_io.h"
#include "trocar/mesh/repair.h"
#include "trocar/mesh/validate.h"

namespace trocar::cli {
namespace {

using nlohmann::json;

json vec_json(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

json report_json(const MeshReport& r) {
  json j;
  j["vertices"] = r.vertices;
  j["triangles"] = r.triangles;
  j["edges"] = r.edges;
  j["bounds"] = r.bounds.is_empty() ? json(nullptr)
                                    : json{{"min", vec_json(r.bounds.min)}, {"max", vec_json(r.bounds.max)}};
  j["area"] = r.area;
  j["volume"] = r.signed_volume;
  j["closed"] = r.closed;
  j["manifold"] = r.manifold;
  j["orientation"] = orientation_name(r.orientation);
  j["components"] = r.components;
  j["euler_characteristic"] = r.euler_characteristic;
  j["defects"] = {
      {"boundary_edges", r.boundary_edges},
      {"nonmanifold_edges", r.nonmanifold_edges},
      {"nonmanifold_vertices", r.nonmanifold_vertices},
      {"degenerate_triangles", r.degenerate_triangles},
      {"duplicate_triangles", r.duplicate_triangles},
      {"duplicate_vertices", r.duplicate_vertices},
      {"near_duplicate_vertices", r.near_duplicate_vertices},
      {"unused_vertices", r.unused_vertices},
      {"nonfinite_vertices", r.nonfinite_vertices},
      {"nonfinite_triangles", r.nonfinite_triangles},
      {"out_of_range_triangles", r.out_of_range_triangles},
      {"inconsistent_edges", r.inconsistent_edges},
  };
  j["issues"] = r.defects();
  return j;
}

std::string fmt(const char* format, double a) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, a);
  return buffer;
}

std::string vec_text(const Vec3& v) {
  return "[" + fmt("%.6g", v.x()) + ", " + fmt("%.6g", v.y()) + ", " + fmt("%.6g", v.z()) + "]";
}

void print_report_text(std::ostream& out, const MeshReport& r) {
  const auto line = [&out](const char* key, const std::string& value) {
    out << "  " << key << std::string(24 - std::string(key).size(), ' ') << value << "\n";
  };
  const auto yes = [](bool b) { return std::string(b ? "yes" : "no"); };
  line("vertices", std::to_string(r.vertices));
  line("triangles", std::to_string(r.triangles));
  line("edges", std::to_string(r.edges));
  if (r.bounds.is_empty()) {
    line("bounding box", "empty");
  } else {
    const Vec3 size = r.bounds.size();
    line("bounding box", vec_text(r.bounds.min) + " .. " + vec_text(r.bounds.max));
    line("size", fmt("%.6g", size.x()) + " x " + fmt("%.6g", size.y()) + " x " + fmt("%.6g", size.z()));
  }
  line("area", fmt("%.9g", r.area));
  line("volume", fmt("%.9g", r.signed_volume) + (r.closed ? "" : " (open: not meaningful)"));
  line("closed", yes(r.closed));
  line("manifold", yes(r.manifold));
  line("orientation", orientation_name(r.orientation));
  line("components", std::to_string(r.components));
  line("euler characteristic", std::to_string(r.euler_characteristic));
  line("boundary edges", std::to_string(r.boundary_edges));
  line("non-manifold edges", std::to_string(r.nonmanifold_edges));
  line("non-manifold vertices", std::to_string(r.nonmanifold_vertices));
  line("degenerate triangles", std::to_string(r.degenerate_triangles));
  line("duplicate triangles", std::to_string(r.duplicate_triangles));
  line("duplicate vertices", std::to_string(r.duplicate_vertices));
  line("near-duplicate vertices", std::to_string(r.near_duplicate_vertices));
  line("unused vertices", std::to_string(r.unused_vertices));
  line("non-finite vertices", std::to_string(r.nonfinite_vertices));
  line("out-of-range triangles", std::to_string(r.out_of_range_triangles));
  line("inconsistent edges", std::to_string(r.inconsistent_edges));
  const std::vector<std::string> issues = r.defects();
  if (issues.empty()) {
    line("defects", "none");
  } else {
    for (const std::string& issue : issues) line("defect", issue);
  }
}

// ---- mesh info ---------------------------------------------------------------------------

struct InfoArgs {
  std::vector<std::string> files;
  bool json = false;
};

void run_info(const InfoArgs& args, int& exit_code) {
  json all = json::array();
  for (const std::string& file : args.files) {
    try {
      const TriMesh mesh = load_mesh(file);
      const MeshReport report = validate(mesh);
      const char* format = format_name(format_from_path(file));
      if (args.json) {
        json j = report_json(report);
        j["file"] = file;
        j["format"] = format;
        all.push_back(std::move(j));
      } else {
        std::cout << file << "\n  format                  " << format << "\n";
        print_report_text(std::cout, report);
      }
    } catch (const Error& e) {
      exit_code = 1;
      if (args.json) {
        all.push_back({{"file", file}, {"error", e.what()}});
      } else {
        std::cerr << "trocar: error: " << e.what() << "\n";
      }
    }
  }
  if (args.json) std::cout << all.dump(2) << "\n";
}

// ---- mesh repair -------------------------------------------------------------------------

struct RepairArgs {
  std::string input;
  std::string output;
  RepairOptions options;
  bool keep_inward = false;
};

void run_repair(RepairArgs& args) {
  TriMesh mesh = load_mesh(args.input);
  if (args.keep_inward) args.options.orient_outward = false;
  const MeshReport before = validate(mesh);
  const RepairReport report = repair(mesh, args.options);
  save_mesh(mesh, args.output);
  const MeshReport after = validate(mesh);
  std::cout << args.input << " -> " << args.output << "\n";
  std::cout << "  vertices   " << report.vertices_before << " -> " << report.vertices_after << "\n";
  std::cout << "  triangles  " << report.triangles_before << " -> " << report.triangles_after << "\n";
  const std::vector<std::string> lines = report.summary();
  if (lines.empty()) std::cout << "  unchanged\n";
  for (const std::string& l : lines) std::cout << "  " << l << "\n";
  std::cout << "  defects before: " << before.defects().size() << ", after: " << after.defects().size()
            << (after.closed ? " (closed" : " (open") << (after.manifold ? ", manifold)" : ", not manifold)")
            << "\n";
  for (const std::string& d : after.defects()) std::cout << "  remaining: " << d << "\n";
}

// ---- mesh generate -----------------------------------------------------------------------

struct GenerateArgs {
  std::string output;
  Real radius = 0.05;
  int subdivisions = 3;
  Real width = 0.2, height = 0.2, bulge = 0;
  std::size_t nx = 40, ny = 40;
  Real length = 0.3;
  std::size_t segments = 24, rings = 6;
  bool open = false;
  std::vector<Real> size{0.1, 0.1, 0.1};
  bool quiet = false;
};

void write_generated(const TriMesh& mesh, const GenerateArgs& args, const char* kind) {
  save_mesh(mesh, args.output);
  if (!args.quiet)
    std::cout << "generated " << kind << ": " << mesh.vertex_count() << " vertices, "
              << mesh.triangle_count() << " triangles -> " << args.output << "\n";
}

void add_generate(CLI::App& mesh_app, std::shared_ptr<GenerateArgs> a) {
  CLI::App* gen = mesh_app.add_subcommand("generate", "Make geometry in code (sizes in metres) and write it");
  gen->require_subcommand(1);
  const auto common = [a](CLI::App* sub) {
    sub->add_option("-o,--output", a->output, "Output file (.obj or .stl)")->required();
    sub->add_flag("-q,--quiet", a->quiet, "Print nothing on success");
  };
  CLI::App* ico = gen->add_subcommand("icosphere", "Subdivided icosahedron: 20·4^n triangles");
  ico->add_option("--radius", a->radius, "Radius (m)")->check(CLI::PositiveNumber)->capture_default_str();
  ico->add_option("--subdivisions", a->subdivisions, "Subdivision level")->check(CLI::Range(0, 8))->capture_default_str();
  common(ico);
  ico->callback([a] { write_generated(make_icosphere(a->radius, a->subdivisions), *a, "icosphere"); });

  CLI::App* sheet = gen->add_subcommand("sheet", "Open rectangular grid in the xy plane, optional bulge in z");
  sheet->add_option("--width", a->width, "Size along x (m)")->check(CLI::PositiveNumber)->capture_default_str();
  sheet->add_option("--height", a->height, "Size along y (m)")->check(CLI::PositiveNumber)->capture_default_str();
  sheet->add_option("--nx", a->nx, "Cells along x")->check(CLI::Range(1, 4096))->capture_default_str();
  sheet->add_option("--ny", a->ny, "Cells along y")->check(CLI::Range(1, 4096))->capture_default_str();
  sheet->add_option("--bulge", a->bulge, "Height of the central bulge (m)")->capture_default_str();
  common(sheet);
  sheet->callback([a] { write_generated(make_sheet(a->width, a->height, a->nx, a->ny, a->bulge), *a, "sheet"); });

  CLI::App* capsule = gen->add_subcommand("capsule", "Capsule along +z (instrument shaft with rounded ends)");
  capsule->add_option("--radius", a->radius, "Radius (m)")->check(CLI::PositiveNumber)->capture_default_str();
  capsule->add_option("--length", a->length, "Length of the straight part (m)")->check(CLI::NonNegativeNumber)->capture_default_str();
  capsule->add_option("--segments", a->segments, "Segments around the axis")->check(CLI::Range(3, 4096))->capture_default_str();
  capsule->add_option("--rings", a->rings, "Latitude bands per hemisphere")->check(CLI::Range(1, 1024))->capture_default_str();
  common(capsule);
  capsule->callback([a] { write_generated(make_capsule(a->radius, a->length, a->segments, a->rings), *a, "capsule"); });

  CLI::App* cylinder = gen->add_subcommand("cylinder", "Cylinder along +z, z in [0, length]");
  cylinder->add_option("--radius", a->radius, "Radius (m)")->check(CLI::PositiveNumber)->capture_default_str();
  cylinder->add_option("--length", a->length, "Length (m)")->check(CLI::PositiveNumber)->capture_default_str();
  cylinder->add_option("--segments", a->segments, "Segments around the axis")->check(CLI::Range(3, 4096))->capture_default_str();
  cylinder->add_flag("--open", a->open, "Leave the ends open (a tube)");
  common(cylinder);
  cylinder->callback([a] { write_generated(make_cylinder(a->radius, a->length, a->segments, !a->open), *a, "cylinder"); });

  CLI::App* box = gen->add_subcommand("box", "Axis-aligned box centred at the origin");
  box->add_option("--size", a->size, "Edge lengths x y z (m)")->expected(3)->check(CLI::PositiveNumber)->capture_default_str();
  common(box);
  box->callback([a] { write_generated(make_box(a->size[0], a->size[1], a->size[2]), *a, "box"); });
}

}  // namespace

void add_mesh_command(CLI::App& app, int& exit_code) {
  CLI::App* mesh = app.add_subcommand("mesh", "Inspect, repair, generate and build (from volumes) triangle meshes");
  mesh->require_subcommand(1);

  auto info_args = std::make_shared<InfoArgs>();
  CLI::App* info = mesh->add_subcommand("info", "Print format, counts, bounds, area, volume and every defect");
  info->add_option("files", info_args->files, "Mesh files (.obj .stl .ply .wrl .vtk)")->required();
  info->add_flag("--json", info_args->json, "Machine-readable output: a JSON list, one object per file");
  info->callback([info_args, &exit_code] { run_info(*info_args, exit_code); });

  auto repair_args = std::make_shared<RepairArgs>();
  CLI::App* rep = mesh->add_subcommand("repair", "Weld, drop bad triangles and small parts, orient outward");
  rep->add_option("input", repair_args->input, "Mesh to repair")->required();
  rep->add_option("output", repair_args->output, "Where to write the result (.obj or .stl)")->required();
  rep->add_option("--merge-tol", repair_args->options.merge_tolerance_abs,
                  "Merge vertices closer than this (file units; 0 = identical only)")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  rep->add_option("--merge-tol-rel", repair_args->options.merge_tolerance_rel,
                  "Merge tolerance as a fraction of the bounding-box diagonal")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  rep->add_option("--min-component-triangles", repair_args->options.min_component_triangles,
                  "Drop connected parts with fewer triangles")->capture_default_str();
  rep->add_option("--min-component-area", repair_args->options.min_component_area_fraction,
                  "Drop connected parts below this fraction of the total area")
      ->check(CLI::Range(0.0, 1.0))->capture_default_str();
  rep->add_flag("--keep-inward", repair_args->keep_inward, "Do not flip inside-out closed parts");
  rep->callback([repair_args] { run_repair(*repair_args); });

  add_generate(*mesh, std::make_shared<GenerateArgs>());
  add_mesh_build_commands(*mesh, exit_code);
}

}  // namespace trocar::cli
