#include "report/design_report.h"

#include <algorithm>
#include <sstream>

#include "core/atomic_file.h"
#include "core/format.h"
#include "core/gnuplot.h"
#include "core/units.h"
#include "trajectory/equipment.h"
#include "trajectory/programme.h"

namespace gyrosid {

nlohmann::json prediction_json(const design::Prediction& p) {
  nlohmann::json flights = nlohmann::json::object();
  for (const auto& f : p.flights) {
    flights[f.flight] = {{"cof_m", f.cof_m},
                         {"cof_noise_m", f.cof_noise_m},
                         {"cof_noise_mean_m", f.cof_noise_mean_m},
                         {"cof_posterior_m", f.cof_posterior_m},
                         {"cof_bias_m", f.cof_bias_m},
                         {"horizon_s", f.horizon_s},
                         {"surface_rms_dph", f.surface_rms_dph},
                         {"surface_bias_dph", f.surface_bias_dph},
                         {"surface_noise_dph", f.surface_noise_dph}};
    // m and S Sigma S' themselves, so that a check can test the seeds' error vectors against them
    const Eigen::Matrix3d& c = f.noise_covariance_ned_m2;
    flights[f.flight]["bias_ned_m"] = {f.bias_ned_m(0), f.bias_ned_m(1), f.bias_ned_m(2)};
    flights[f.flight]["noise_covariance_ned_m2"] = {{c(0, 0), c(0, 1), c(0, 2)}, {c(1, 0), c(1, 1), c(1, 2)}, {c(2, 0), c(2, 1), c(2, 2)}};
  }
  nlohmann::json j = {{"criterion", std::string(to_string(p.criterion))},
                      {"objective", p.objective},
                      {"duration_min", p.duration_min},
                      {"observations", p.observations},
                      {"flights", flights}};
  if (p.uniform_surface_rms_dph) j["uniform"] = {{"surface_rms_dph", *p.uniform_surface_rms_dph}};
  if (p.network) {
    // The hybrid's network the prediction was made with: as the calibration's evidence would choose it along
    // the trajectory (widths normalised by the trajectory's range, as in a model.json's summary).
    const design::NetworkNodes& n = *p.network;
    j["network"] = {{"nodes", n.centres.rows()},
                    {"widths", {n.widths(0), n.widths(1)}},
                    {"width_rate_dps", units::radps_to_dps(n.widths(0) * n.scale(0))},
                    {"width_temperature_c", n.widths(1) * n.scale(1)},
                    {"prior_sd_dph", units::radps_to_dph(n.prior_sd_radps)},
                    {"effective_parameters", n.effective_parameters}};
  }
  if (!p.effects.empty()) {
    nlohmann::json effects = nlohmann::json::object();
    for (std::size_t i = 0; i < p.effects.size(); ++i) {
      nlohmann::json corr = nlohmann::json::object();
      for (std::size_t k = 0; k < p.effects.size(); ++k) {
        if (k != i) corr[p.effects[k].name] = p.effect_correlation(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k));
      }
      effects[p.effects[i].name] = {{"sd", p.effects[i].sd}, {"unit", p.effects[i].unit}, {"correlation", corr}};
    }
    j["effects"] = effects;
  }
  return j;
}

nlohmann::json design_json(const design::DesignResult& r, const nlohmann::json& provenance) {
  nlohmann::json segments = nlohmann::json::array();
  for (const auto& seg : r.trajectory.profile.segments) segments.push_back(seg.label);
  return {{"format", "gyrosid-design/1"},
          {"duration_min", r.trajectory.profile.duration_min()},
          {"objective", r.predicted.objective},
          {"criterion", std::string(to_string(r.predicted.criterion))},
          {"predicted", prediction_json(r.predicted)},
          {"initial", {{"segments", r.initial.segments.size()}, {"predicted", prediction_json(r.initial_predicted)}}},
          {"segments", segments},
          {"solver_summary", r.summary},
          {"provenance", provenance}};
}

namespace {

// Weighted mean, least and largest of `values`.
nlohmann::json spread(const std::vector<double>& values, const std::vector<double>& weights) {
  double sum = 0.0, w = 0.0;
  for (std::size_t k = 0; k < values.size(); ++k) sum += weights[k] * values[k], w += weights[k];
  return {{"mean", sum / w}, {"min", *std::min_element(values.begin(), values.end())}, {"max", *std::max_element(values.begin(), values.end())}};
}

}  // namespace

nlohmann::json prior_json(const std::string& name, const std::string& source, const std::vector<PriorMemberPredictions>& members) {
  nlohmann::json j = {{"name", name}, {"source", source}, {"members", nlohmann::json::array()}, {"flights", nlohmann::json::object()}};
  std::vector<double> weights;
  for (const auto& m : members) {
    nlohmann::json compared = nlohmann::json::object();
    for (const auto& [trajectory, p] : m.compared) compared[trajectory] = prediction_json(p);
    j["members"].push_back({{"name", m.name}, {"origin", m.origin}, {"weight", m.weight}, {"predicted", prediction_json(m.design)}, {"compared", compared}});
    weights.push_back(m.weight);
  }
  const auto& flights = members.front().design.flights;
  for (std::size_t f = 0; f < flights.size(); ++f) {
    std::vector<double> cof;
    for (const auto& m : members) cof.push_back(m.design.flights[f].cof_m);
    nlohmann::json flight = {{"design_cof_m", spread(cof, weights)}, {"gain_over", nlohmann::json::object()}};
    for (std::size_t t = 0; t < members.front().compared.size(); ++t) {
      std::vector<double> gain;
      for (const auto& m : members) gain.push_back(m.compared[t].second.flights[f].cof_m / m.design.flights[f].cof_m);
      flight["gain_over"][members.front().compared[t].first] = spread(gain, weights);
    }
    j["flights"][flights[f].flight] = flight;
  }
  return j;
}

void plot_design_coverage(const std::filesystem::path& png, const design::Observations& o, const design::Envelope& e,
                          const std::string& title) {
  std::vector<std::vector<double>> samples, envelope;
  const Eigen::Index stride = std::max<Eigen::Index>(1, o.size() / 20000);
  for (Eigen::Index i = 0; i < o.size(); i += stride) samples.push_back({units::radps_to_dps(o.inputs.rate(i)), o.inputs.temp_c(i)});
  for (const auto& p : e.temperature_rate_points()) envelope.push_back({p[1], p[0]});
  const double w = units::radps_to_dps(e.domain.rate_max_radps);
  std::string script = datablock("samples", samples) + datablock("envelope", envelope);
  script += str_cat("set title ", gnuplot_quote(title), "\n",
                    "set xlabel 'measured rate (deg/s)'\nset ylabel 'temperature at the sensor probe (C)'\nset grid\n",
                    "set key outside right\n",
                    "set object 1 rect from ", -w, ",", e.domain.temp_min_c, " to ", w, ",", e.domain.temp_max_c,
                    " fs empty border rgb '#808080' dt 2\n",
                    "plot $envelope using 1:2 with points pt 5 ps 0.6 lc rgb '#c8c8c8' title 'envelope', \\\n",
                    "     $samples using 1:2 with points pt 7 ps 0.25 lc rgb '#2050a0' title 'trajectory samples (", o.size(), ")', \\\n",
                    "     NaN with lines dt 2 lc rgb '#808080' title 'domain'\n");
  render_png(png, script);
}

namespace {

std::string fmt(double v, int digits = 3) { return format_significant(v, digits); }

void prediction_rows(std::ostringstream& out, const std::string& name, const design::Prediction& p) {
  out << "| " << name << " | " << fmt(p.duration_min, 4);
  for (const auto& f : p.flights) out << " | " << fmt(f.cof_m) << " | " << fmt(f.surface_rms_dph);
  if (p.uniform_surface_rms_dph) out << " | " << fmt(*p.uniform_surface_rms_dph);
  out << " | " << fmt(p.objective, 4) << " |\n";
}

// The design's cof_m on each member of the prior and its gain over each compared trajectory there.
void prior_rows(std::ostringstream& out, const std::vector<PriorMemberPredictions>& members) {
  const auto& head = members.front();
  out << "\n## Over the prior (" << members.size() << " sensors)\n\nThe design's predicted criterion of fit on each member, and "
         "its gain cof_m(trajectory) / cof_m(design) over each compared trajectory there (> 1: the design is better).\n\n| member | weight";
  for (const auto& f : head.design.flights) {
    out << " | " << f.flight << " cof_m";
    for (const auto& [name, p] : head.compared) out << " | " << f.flight << " gain over " << name;
  }
  out << " |\n|---|---";
  for (std::size_t i = 0; i < head.design.flights.size() * (1 + head.compared.size()); ++i) out << "|---";
  out << "|\n";
  for (const auto& m : members) {
    out << "| " << m.name << " | " << fmt(m.weight);
    for (std::size_t f = 0; f < m.design.flights.size(); ++f) {
      out << " | " << fmt(m.design.flights[f].cof_m);
      for (const auto& [name, p] : m.compared) out << " | " << fmt(p.flights[f].cof_m / m.design.flights[f].cof_m);
    }
    out << " |\n";
  }
}

}  // namespace

std::string design_report_markdown(const DesignReportInput& in) {
  std::ostringstream out;
  const design::Prediction* head = in.result ? &in.result->predicted : (in.compared.empty() ? nullptr : &in.compared.front().second);
  out << "# " << (in.result ? "Calibration trajectory design" : "Predicted accuracy of calibration trajectories") << "\n\n";
  out << "Model `" << in.model << "`, sensor `" << in.sensor << "`" << (in.result ? ", solver `" + in.solver + "`" : "")
      << ". Made by `" << in.command << "`.\n\n";
  out << "Predictions are linearised: the model's parameter covariance from the Fisher information of the trajectory "
         "with the sensor's noise, pushed through the strapdown INS to the criterion of fit (position error at the end "
         "of each flight, after 1 h for longer flights, flight noise off) and to the RMS error of the surface over the "
         "flight's (T, w) samples. `cof_m` is the expected criterion including the model's own bias on noise-free data.\n\n";
  if (!head) return out.str();
  out << "| trajectory | minutes";
  for (const auto& f : head->flights) out << " | " << f.flight << " cof_m | " << f.flight << " surface_rms_dph";
  if (head->uniform_surface_rms_dph) out << " | uniform surface_rms_dph";
  out << " | objective (" << to_string(head->criterion) << ") |\n|---|---";
  for (std::size_t i = 0; i < head->flights.size(); ++i) out << "|---|---";
  out << (head->uniform_surface_rms_dph ? "|---" : "") << "|---|\n";
  if (in.result) {
    prediction_rows(out, "**design**", in.result->predicted);
    prediction_rows(out, "starting programme", in.result->initial_predicted);
  }
  for (const auto& [name, p] : in.compared) prediction_rows(out, name, p);
  if (!head->effects.empty()) {
    out << "\n## Grey-box effects\n\nPosterior standard deviations and correlations (separable when |correlation| is well below 1):\n\n"
        << "| effect | sd | unit |";
    for (const auto& e : head->effects) out << " corr " << e.name << " |";
    out << "\n|---|---|---|";
    for (std::size_t i = 0; i < head->effects.size(); ++i) out << "---|";
    out << "\n";
    for (std::size_t i = 0; i < head->effects.size(); ++i) {
      out << "| " << head->effects[i].name << " | " << fmt(head->effects[i].sd) << " | " << head->effects[i].unit << " |";
      for (std::size_t k = 0; k < head->effects.size(); ++k) out << " " << fmt(head->effect_correlation(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)), 2) << " |";
      out << "\n";
    }
  }
  if (in.result) {
    const auto& p = in.result->trajectory.profile;
    out << "\n## Programme (" << fmt(p.duration_min(), 4) << " min, " << p.segments.size() << " segments)\n\n"
        << "| # | segment | minutes | chamber C | table rate deg/s | cycles | position |\n|---|---|---|---|---|---|---|\n";
    for (std::size_t i = 0; i < p.segments.size(); ++i) {
      const auto& s = p.segments[i];
      const bool tri = s.rate.shape == RateProfile::Shape::triangle;
      out << "| " << i + 1 << " | " << s.label << " | " << fmt(s.duration_s / 60.0) << " | " << fmt(s.chamber_start_c) << " -> "
          << fmt(s.chamber_end_c) << " | "
          << (tri ? fmt(units::radps_to_dps(s.rate.low_radps)) + " .. " + fmt(units::radps_to_dps(s.rate.high_radps))
                  : fmt(units::radps_to_dps(s.rate.value_radps)))
          << " | " << (tri ? fmt(s.rate.cycles) : "dwell") << " | " << s.position << " |\n";
    }
    if (!in.prior.empty()) prior_rows(out, in.prior);
    const SolveSummary& s = in.result->summary;
    out << "\n## Solver\n\n`" << s.solver << "`: " << to_string(s.termination) << " (" << s.message << "), " << s.iterations
        << " iterations, " << s.evaluations << " objective evaluations, " << fmt(s.time_s) << " s, peak "
        << fmt(s.peak_rss_mb) << " MB; objective " << fmt(s.initial_cost, 4) << " -> " << fmt(in.result->predicted.objective, 4)
        << ".\n\nSimulate it: `gyrosid simulate --trajectory trajectory.yaml --sensor " << in.sensor << " --out rec.csv`\n";
  }
  return out.str();
}

void write_designed_programme(const std::filesystem::path& dir, const TrajectorySpec& trajectory, const nlohmann::json& design_file) {
  write_file_atomic(dir / "trajectory.yaml", programme_yaml(trajectory));
  write_file_atomic(dir / "setpoints.csv", setpoint_table_csv(trajectory.profile));
  write_file_atomic(dir / "design.json", design_file.dump(2) + "\n");
}

nlohmann::json evaluation_json(const DesignReportInput& report, const std::vector<std::string>& evaluated, const nlohmann::json& provenance) {
  nlohmann::json j = {{"format", "gyrosid-design-evaluation/1"}, {"provenance", provenance}, {"trajectories", nlohmann::json::object()}};
  const std::size_t first = report.compared.size() - evaluated.size();
  for (std::size_t i = first; i < report.compared.size(); ++i) j["trajectories"][evaluated[i - first]] = prediction_json(report.compared[i].second);
  return j;
}

}  // namespace gyrosid
