#include "score_command.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cli_support.h"
#include "trocar/assessment/learning_curve_html.h"
#include "trocar/assessment/metrics.h"
#include "trocar/assessment/proficiency.h"
#include "trocar/assessment/report_html.h"
#include "trocar/assessment/report_json.h"
#include "trocar/assessment/session_trace.h"
#include "trocar/core/error.h"
#include "trocar/procedure/procedure.h"
#ifdef TROCAR_HAVE_RENDER
#include "trocar/render/frame_recorder.h"
#endif

namespace trocar::cli {
namespace {

namespace fs = std::filesystem;

struct ScoreOptions {
  std::string recording;
  std::string expert;           // a folder of expert recordings or a reference file (JSON)
  std::string output;           // the HTML report (default: the recording's name with .html)
  std::string write_reference;  // write the reference of --expert's recordings to this file
  std::string history;          // a folder of one trainee's recordings: the learning curve
  bool quiet = false;
};

/// The session recordings (*.trec) in `dir`, by name.
std::vector<fs::path> recordings_in(const fs::path& dir) {
  if (!fs::is_directory(dir)) throw Error(dir.string() + ": no such folder");
  std::vector<fs::path> out;
  for (const fs::directory_entry& e : fs::directory_iterator(dir))
    if (e.is_regular_file() && e.path().extension() == ".trec") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  if (out.empty()) throw Error(dir.string() + ": no session recordings (*.trec)");
  return out;
}

/// The metrics of a recording (replayed); warns when the replay does not reproduce it.
std::vector<Metric> metrics_of(const fs::path& recording, bool quiet, SessionTrace* trace_out = nullptr,
                               ReplayObserver* also = nullptr) {
  TracedSession s = trace_recording(recording, also);
  if (!s.replay.matches() && !quiet)
    std::fprintf(stderr, "score: %s: the replay %s (the metrics are the replay's)\n", recording.c_str(),
                 s.replay.verdict().c_str());
  std::vector<Metric> m = measure(s.trace);
  if (trace_out) *trace_out = std::move(s.trace);
  return m;
}

ExpertReference load_reference(const fs::path& expert, bool quiet) {
  if (fs::is_regular_file(expert)) return read_reference(expert);
  if (!fs::is_directory(expert)) throw Error("--expert " + expert.string() + ": no such file or folder");
  ExpertReference r;
  for (const fs::path& f : recordings_in(expert)) {
    SessionTrace trace;
    std::vector<Metric> metrics = metrics_of(f, quiet, &trace);
    if (trace.unstable_at >= 0) {  // the blow-up's numbers would set the experts' level
      std::fprintf(stderr, "score: expert session %s left out: its simulation blew up at %.3f s\n", f.c_str(),
                   trace.unstable_at);
      continue;
    }
    if (!trace.task.complete()) {  // a repair left halfway is not the level a trainee must reach
      std::fprintf(stderr, "score: expert session %s left out: its task was not completed\n", f.c_str());
      continue;
    }
    if (!quiet) std::fprintf(stderr, "score: expert session %s\n", f.c_str());
    r.sessions.push_back(f.filename().string());
    r.metrics.push_back(std::move(metrics));
  }
  if (r.metrics.empty()) throw Error("--expert " + expert.string() + ": no expert session to learn from");
  r.stats = expert_reference(r.metrics);
  return r;
}

std::string format_value(const Metric& m) {
  char text[64];
  std::snprintf(text, sizeof text, "%.4g%s%s", m.value, m.unit.empty() ? "" : " ", m.unit.c_str());
  return text;
}

void print_summary(const Assessment& a, const SessionTrace& trace) {
  if (!a.assessable)
    std::printf("%s: NOT ASSESSABLE — the simulation blew up at %.3f s (a simulator failure)\n", trace.scene.c_str(),
                trace.unstable_at);
  std::printf("%s: %s — %d scored metric%s below the expert level, %d error%s, task %s\n", trace.scene.c_str(),
              a.pass ? "PASS" : "FAIL", a.failed, a.failed == 1 ? "" : "s", a.errors, a.errors == 1 ? "" : "s",
              a.task_complete ? "complete" : "incomplete");
  for (const MetricScore& s : a.metrics) {
    if (!s.metric.scored) continue;
    if (s.has_reference)
      std::printf("  %-45s %14s   expert %.4g ± %.4g, pass mark %.4g: %s\n", s.metric.name.c_str(),
                  format_value(s.metric).c_str(), s.expert.mean, s.expert.sd, s.limit, s.pass ? "pass" : "FAIL");
    else
      std::printf("  %-45s %14s\n", s.metric.name.c_str(), format_value(s.metric).c_str());
  }
  for (const GoalsScore& g : a.goals)
    if (g.score > 0) std::printf("  GOALS %-20s %d / 5\n", to_string(g.domain), g.score);
}

/// The learning curve of the recordings in `dir` (in name order: the attempts).
void learning_curve(const ScoreOptions& o) {
  ExpertReference reference;
  if (!o.expert.empty()) reference = load_reference(o.expert, o.quiet);
  std::vector<Attempt> attempts;
  for (const fs::path& f : recordings_in(o.history)) {
    if (!o.quiet) std::fprintf(stderr, "score: attempt %zu: %s\n", attempts.size() + 1, f.c_str());
    SessionTrace trace;
    std::vector<Metric> metrics = metrics_of(f, o.quiet, &trace);
    const Assessment a = assess(trace, metrics, reference.stats);
    attempts.push_back({f.filename().string(), std::move(metrics), a.pass, a.errors});
  }
  const fs::path html = o.output.empty() ? fs::path(o.history) / "learning_curve.html" : fs::path(o.output);
  write_atomically(html, learning_curve_html(attempts, reference.stats, "Learning curve: " + o.history));
  if (!o.quiet) {
    int passed = 0;
    for (const Attempt& a : attempts) passed += a.pass;
    std::printf("learning curve: %zu attempts, %d passed overall: %s\n", attempts.size(), passed, html.c_str());
  }
}

void score(const ScoreOptions& o) {
  if (!o.history.empty()) {
    if (!o.recording.empty() || !o.write_reference.empty()) throw Error("--history goes without a RECORDING or --write-reference");
    learning_curve(o);
    return;
  }
  if (!o.write_reference.empty()) {
    const ExpertReference reference = o.expert.empty() ? ExpertReference{} : load_reference(o.expert, o.quiet);
    if (reference.metrics.empty()) throw Error("--write-reference needs --expert FOLDER of session recordings");
    write_atomically(o.write_reference, reference_json(reference).dump(1) + "\n");
    if (!o.quiet)
      std::printf("reference: %s (%zu expert sessions, %zu metrics)\n", o.write_reference.c_str(),
                  reference.metrics.size(), reference.stats.size());
    if (o.recording.empty()) return;
    score_session(o.recording, o.write_reference, o.output, o.quiet);
    return;
  }
  if (o.recording.empty()) throw Error("a RECORDING to score is needed");
  score_session(o.recording, o.expert, o.output, o.quiet);
}

#ifdef TROCAR_HAVE_RENDER
/// Renders the scope's view at the moment of each error the replayed procedure logs (with the task
/// panel), into `dir`, for the report's timeline. A build or a machine without EGL gets a report
/// without frames and a note why.
class ErrorFrames final : public ReplayObserver {
 public:
  ErrorFrames(fs::path dir, bool quiet) : dir_(std::move(dir)), quiet_(quiet) {}
  void start(const Scene& scene, const Simulation& sim, const Procedure* /*procedure*/) override {
    settings_.dir = dir_;
    settings_.camera = select_camera(scene.cameras, sim.world(), "scope");
    settings_.textures = scene.textures;
    settings_.tissue_appearance = scene.tissue_appearance;
    settings_.rigid_appearance = scene.rigid_appearance;
  }
  void step(const Simulation& sim, const Procedure* procedure, const StepRecord& /*record*/) override {
    if (!procedure || failed_) return;
    const auto events = procedure->events();
    if (events.size() == seen_) return;
    const TaskView view = procedure->view();
    for (; seen_ < events.size(); ++seen_) {
      if (!events[seen_].error || !ready(sim)) continue;
      char name[32];
      std::snprintf(name, sizeof name, "error_%02zu.png", frames_.size() + 1);
      recorder_->render_to(sim, &view, dir_ / name);
      frames_.push_back({events[seen_].time, (dir_.filename() / name).string(), events[seen_].text});
    }
  }
  const std::vector<ReportFrame>& frames() const { return frames_; }

 private:
  /// The renderer, made at the first error (no error: no folder, no EGL context).
  bool ready(const Simulation& sim) {
    if (recorder_) return true;
    try {
      recorder_ = std::make_unique<FrameRecorder>(sim.world(), settings_);
    } catch (const Error& e) {
      failed_ = true;
      if (!quiet_) std::fprintf(stderr, "score: no frames of the errors (%s)\n", e.what());
    }
    return recorder_ != nullptr;
  }
  fs::path dir_;
  bool quiet_;
  FrameSettings settings_;
  bool failed_ = false;
  std::unique_ptr<FrameRecorder> recorder_;
  std::size_t seen_ = 0;
  std::vector<ReportFrame> frames_;
};
#endif

}  // namespace

void score_session(const std::string& recording, const std::string& expert, const std::string& output, bool quiet) {
  ExpertReference reference;
  if (!expert.empty()) reference = load_reference(expert, quiet);
  // Not RECORDING.json by default: a recording made beside its scene (scene.json → scene.trec)
  // would have its scene overwritten.
  const fs::path html = output.empty() ? fs::path(recording).replace_extension(".report.html") : fs::path(output);
  const fs::path json = fs::path(html).replace_extension(".json");
  SessionTrace trace;
  std::vector<ReportFrame> frames;
#ifdef TROCAR_HAVE_RENDER
  // The frames go beside the report, in REPORT_frames/ (the page names them relative to itself).
  const fs::path frames_dir = html.parent_path() / (html.stem().string() + "_frames");
  ErrorFrames error_frames(frames_dir, quiet);
  const std::vector<Metric> metrics = metrics_of(recording, quiet, &trace, &error_frames);
  frames = error_frames.frames();
#else
  const std::vector<Metric> metrics = metrics_of(recording, quiet, &trace);
#endif
  const Assessment assessment = assess(trace, metrics, reference.stats);
  const std::string title = "Assessment of " + fs::path(recording).filename().string();
  write_atomically(html, assessment_html(trace, assessment, MetricSettings{}, frames, title));
  write_atomically(json, assessment_json(trace, assessment).dump(1) + "\n");
  if (!quiet) {
    print_summary(assessment, trace);
    std::printf("report: %s (numbers in %s)\n", html.c_str(), json.c_str());
  }
}

void add_score_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<ScoreOptions>();
  CLI::App* cmd = app.add_subcommand("score", "Assess a trainee's session recording against expert sessions (HTML report)");
  cmd->add_option("recording", o->recording, "Session recording (trocar run --session, or --realtime --record)");
  cmd->add_option("--expert", o->expert,
                  "Expert sessions: a folder of recordings (*.trec) or a reference file (--write-reference)");
  cmd->add_option("-o,--output", o->output, "The HTML report (default: RECORDING.report.html; its JSON beside it, X.json for X.html)");
  cmd->add_option("--write-reference", o->write_reference,
                  "Write the reference of --expert's recordings (their metrics, mean, SD, best quartile) to this file");
  cmd->add_option("--history", o->history,
                  "A folder of one trainee's recordings (*.trec, in name order): write their learning curve "
                  "(-o, default FOLDER/learning_curve.html)");
  cmd->add_flag("--quiet,-q", o->quiet, "Print nothing but errors");
  cmd->callback([o, &exit_code]() {
    score(*o);
    (void)exit_code;
  });
}

}  // namespace trocar::cli
