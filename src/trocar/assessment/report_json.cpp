// The assessment as JSON and the expert reference file (docs/assessment.md).
#include "trocar/assessment/report_json.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "trocar/core/error.h"

namespace trocar {
namespace {

nlohmann::json vec3(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

[[noreturn]] void bad(const std::filesystem::path& file, const std::string& why) {
  throw FileError(file.string(), FileLocation::none(), why);
}

}  // namespace

nlohmann::json assessment_json(const SessionTrace& trace, const Assessment& a) {
  nlohmann::json metrics = nlohmann::json::array();
  for (const MetricScore& s : a.metrics) {
    nlohmann::json m = {{"id", s.metric.id},
                        {"name", s.metric.name},
                        {"unit", s.metric.unit},
                        {"domain", to_string(s.metric.domain)},
                        {"lower_is_better", s.metric.lower_is_better},
                        {"scored", s.metric.scored},
                        {"value", s.metric.value}};
    if (s.has_reference) {
      m["expert"] = {{"mean", s.expert.mean}, {"sd", s.expert.sd}, {"best_quartile", s.expert.best_quartile},
                     {"sessions", s.expert.sessions}};
      m["limit"] = s.limit;
      m["pass"] = s.pass;
    }
    metrics.push_back(m);
  }
  nlohmann::json goals = nlohmann::json::array();
  for (const GoalsScore& g : a.goals) goals.push_back({{"domain", to_string(g.domain)}, {"score", g.score}, {"mean_z", g.mean_z}});
  nlohmann::json events = nlohmann::json::array();
  for (const TraceEvent& e : trace.events)
    events.push_back({{"time_s", e.time}, {"kind", e.kind}, {"error", e.error}, {"place_m", vec3(e.place)},
                      {"zone", e.zone}, {"text", e.text}});
  nlohmann::json out = {{"scene", trace.scene},
                        {"duration_s", trace.time.empty() ? 0.0 : trace.time.back()},
                        {"pass", a.pass},
                        {"assessable", a.assessable},
                        {"unstable_at_s", trace.unstable_at},
                        {"failed_metrics", a.failed},
                        {"errors", a.errors},
                        {"task_complete", a.task_complete},
                        {"goals", goals},
                        {"metrics", metrics},
                        {"events", events}};
  if (trace.task.present) {
    nlohmann::json steps = nlohmann::json::array();
    for (const TraceStep& s : trace.task.steps) steps.push_back({{"name", s.name}, {"done_at_s", s.done_at}});
    out["task"] = {{"steps", steps},
                   {"tacks", trace.task.tacks},
                   {"fixed_tacks", trace.task.fixed_tacks},
                   {"zone_tacks", trace.task.zone_tacks},
                   {"tissue_only_tacks", trace.task.tissue_only_tacks},
                   {"coverage", trace.task.coverage},
                   {"sac_fraction", trace.task.sac_fraction}};
  }
  return out;
}

nlohmann::json reference_json(const ExpertReference& r) {
  nlohmann::json sessions = nlohmann::json::array();
  for (std::size_t i = 0; i < r.metrics.size(); ++i) {
    nlohmann::json values = nlohmann::json::object();
    for (const Metric& m : r.metrics[i])
      if (m.scored) values[m.id] = m.value;
    sessions.push_back({{"session", i < r.sessions.size() ? r.sessions[i] : std::string()}, {"metrics", values}});
  }
  nlohmann::json stats = nlohmann::json::array();
  for (const ExpertStats& e : r.stats)
    stats.push_back({{"id", e.id}, {"mean", e.mean}, {"sd", e.sd}, {"best_quartile", e.best_quartile},
                     {"sessions", e.sessions}});
  return {{"schema", 1}, {"kind", "trocar expert reference"}, {"sessions", sessions}, {"metrics", stats}};
}

ExpertReference read_reference(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) bad(file, "cannot read");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    bad(file, std::string("not JSON: ") + e.what());
  }
  if (!j.is_object() || j.value("kind", "") != "trocar expert reference") bad(file, "\"kind\" is not \"trocar expert reference\"");
  if (!j.contains("metrics") || !j["metrics"].is_array()) bad(file, "\"metrics\" must be an array");
  ExpertReference r;
  for (std::size_t i = 0; i < j["metrics"].size(); ++i) {
    const nlohmann::json& m = j["metrics"][i];
    const std::string where = "metrics[" + std::to_string(i) + "]";
    if (!m.is_object() || !m.contains("id") || !m["id"].is_string()) bad(file, where + ".id must be a string");
    ExpertStats e;
    e.id = m["id"].get<std::string>();
    for (const char* key : {"mean", "sd", "best_quartile"}) {
      if (!m.contains(key) || !m[key].is_number()) bad(file, where + "." + key + " must be a number");
    }
    e.mean = m["mean"].get<double>();
    e.sd = m["sd"].get<double>();
    e.best_quartile = m["best_quartile"].get<double>();
    if (!std::isfinite(e.mean) || !std::isfinite(e.sd) || e.sd < 0) bad(file, where + ": mean and sd must be finite, sd ≥ 0");
    e.sessions = m.value("sessions", std::size_t{0});
    r.stats.push_back(e);
  }
  if (j.contains("sessions") && j["sessions"].is_array())
    for (const nlohmann::json& s : j["sessions"]) r.sessions.push_back(s.value("session", ""));
  return r;
}

}  // namespace trocar
