#include "core/solve_summary.h"

#include <sys/resource.h>

#include <chrono>
#include <fstream>

namespace gyrosid {

bool reset_peak_rss() {
  // Writing "5" to clear_refs resets the peak RSS (VmHWM) to the current RSS (Linux >= 4.0).
  std::ofstream out("/proc/self/clear_refs");
  if (!out) return false;
  out << "5";
  out.flush();
  return static_cast<bool>(out);
}

double peak_rss_mb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;  // kB
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux reports KiB
}

namespace detail {

namespace {
double now_s() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }
}  // namespace

SolveClock::SolveClock() : memory_reset(reset_peak_rss()), start_s(now_s()) {}
double SolveClock::seconds() const { return now_s() - start_s; }

SolveSummary finish_summary(std::string solver, const SolveClock& clock, SolveMonitor& monitor, SolveOutcome outcome) {
  SolveSummary s;
  s.solver = std::move(solver);
  s.termination = outcome.termination;
  s.message = std::move(outcome.message);
  s.details = std::move(outcome.details);
  s.cost_history = monitor.history();
  s.iterations = static_cast<int>(s.cost_history.size());
  s.evaluations = monitor.evaluations();
  if (!s.cost_history.empty()) {
    s.initial_cost = s.cost_history.front();
    s.final_cost = s.cost_history.back();
  }
  s.time_s = clock.seconds();
  s.peak_rss_mb = peak_rss_mb();
  if (!clock.memory_reset) s.details["peak_rss_scope"] = "process";
  return s;
}

}  // namespace detail

nlohmann::json number_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

namespace {
double number_or_nan(const nlohmann::json& j, const char* key) {
  return j.contains(key) && j.at(key).is_number() ? j.at(key).get<double>() : NAN;
}
}  // namespace

void to_json(nlohmann::json& j, const SolveSummary& s) {
  nlohmann::json history = nlohmann::json::array();
  for (double c : s.cost_history) history.push_back(number_or_null(c));
  j = {{"solver", s.solver},
       {"termination", to_string(s.termination)},
       {"usable", s.usable()},
       {"message", s.message},
       {"iterations", s.iterations},
       {"evaluations", s.evaluations},
       {"initial_cost", number_or_null(s.initial_cost)},
       {"final_cost", number_or_null(s.final_cost)},
       {"cost_history", history},
       {"time_s", s.time_s},
       {"peak_rss_mb", s.peak_rss_mb},
       {"details", s.details}};
}

SolveSummary solve_summary_from_json(const nlohmann::json& j) {
  SolveSummary s;
  s.solver = j.at("solver").get<std::string>();
  s.termination = parse_enum<Termination>(j.at("termination").get<std::string>(), "solver summary");
  s.message = j.value("message", "");
  s.iterations = j.value("iterations", 0);
  s.evaluations = j.value("evaluations", 0);
  for (const auto& c : j.value("cost_history", nlohmann::json::array())) s.cost_history.push_back(c.is_number() ? c.get<double>() : NAN);
  s.initial_cost = number_or_nan(j, "initial_cost");
  s.final_cost = number_or_nan(j, "final_cost");
  s.time_s = j.value("time_s", 0.0);
  s.peak_rss_mb = j.value("peak_rss_mb", 0.0);
  s.details = j.value("details", nlohmann::json::object());
  return s;
}

}  // namespace gyrosid
