#include "plot_command.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#include "trocar/core/error.h"
#include "trocar/runtime/recording.h"

namespace trocar::cli {
namespace {

namespace fs = std::filesystem;

struct PlotOptions {
  std::string recording;
  std::string out;
};

// The seed's Fig. 5.4/5.5: time per iteration of each module over the run.
void plot_timing(const PlotOptions& o) {
  const Recording rec = read_recording(o.recording, false);
  if (!rec.end)
    std::cerr << "trocar: warning: " << o.recording << ": byte " << rec.complete_bytes
              << ": the recording ends early (no end record); plotting its " << rec.steps.size() << " steps\n";
  const fs::path out = o.out.empty() ? fs::path(o.recording).parent_path() / "timing" : fs::path(o.out);
  fs::create_directories(out);
  {
    std::ofstream steps(out / "steps.dat");
    steps << "# step time_s";
    for (const char* n : kStepTimingNames) steps << " " << n << "_us";
    steps << "\n";
    for (const StepRecord& s : rec.steps) {
      steps << s.step << " " << double(s.time_ns) * 1e-9;
      for (float t : s.timing_us) steps << " " << t;
      steps << "\n";
    }
    std::ofstream ticks(out / "ticks.dat");
    ticks << "# tick time_s period_us compute_us\n";
    for (const TickRecord& t : rec.ticks)
      ticks << t.tick << " " << double(t.time_ns) * 1e-9 << " " << t.period_us << " " << t.compute_us << "\n";
  }
  std::ofstream gp(out / "timing.gp");
  const auto plot = [&](const char* terminal, const char* ext) {
    gp << "set terminal " << terminal << " size 1000,600\n"
       << "unset logscale y\nset xrange [0:*]\n"
       << "set output 'physics_timing." << ext << "'\n"
       << "set title 'Physics: time per step of each module (the seed, Fig. 5.4)'\n"
       << "set xlabel 'time (s)'\nset ylabel 'time per step (us)'\nset key outside right\nset grid\n"
       << "plot 'steps.dat' using 2:3 with lines title 'broad phase', '' using 2:4 with lines title 'narrow phase', "
          "'' using 2:5 with lines title 'response', '' using 2:6 with lines title 'deformation', "
          "'' using 2:8 with lines lw 2 title 'whole step'\n"
       << "set output 'haptic_timing." << ext << "'\n"
       << "set title 'Haptic loop: period and compute per tick (the seed, Fig. 5.5)'\n"
       << "set ylabel 'us (log scale)'\nset logscale y\n"
       << "plot 'ticks.dat' using 2:3 with lines title 'period', '' using 2:4 with lines title 'tick compute'\n";
  };
  plot("svg dynamic", "svg");
  plot("pngcairo", "png");
  gp.close();
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0)
    throw Error("gnuplot not found: the data and timing.gp are in " + out.string() + " (install gnuplot-nox)");
  const std::string cmd = "cd '" + out.string() + "' && gnuplot timing.gp";
  if (std::system(cmd.c_str()) != 0) throw Error("gnuplot failed on " + (out / "timing.gp").string());
  std::printf("plot timing: %zu steps, %zu ticks -> %s/{physics,haptic}_timing.{svg,png}\n", rec.steps.size(),
              rec.ticks.size(), out.string().c_str());
}

}  // namespace

void add_plot_command(CLI::App& app, int& /*exit_code*/) {
  auto o = std::make_shared<PlotOptions>();
  CLI::App* plot = app.add_subcommand("plot", "Plots of a recorded session");
  plot->require_subcommand(1);
  CLI::App* timing = plot->add_subcommand("timing", "Time per iteration of each module over the run (SVG and PNG)");
  timing->add_option("recording", o->recording, "Session recording")->required();
  timing->add_option("--out", o->out, "Output folder (default: timing/ beside the recording)");
  timing->callback([o]() { plot_timing(*o); });
}

}  // namespace trocar::cli
