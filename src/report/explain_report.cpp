#include "report/explain_report.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"
#include "core/gnuplot.h"
#include "core/units.h"
#include "report/explain_json.h"
#include "report/plots.h"

namespace gyrosid {
namespace {

using explain::ExplainResult;

// Centred moving average over +-half_s seconds (the residual's structure, not its noise).
Eigen::VectorXd smoothed(const std::vector<double>& t, const Eigen::VectorXd& v, double half_s) {
  const std::size_t n = t.size();
  Eigen::VectorXd out(v.size());
  std::size_t lo = 0, hi = 0;
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    while (hi < n && t[hi] <= t[i] + half_s) sum += v(static_cast<Eigen::Index>(hi++));
    while (t[lo] < t[i] - half_s) sum -= v(static_cast<Eigen::Index>(lo++));
    out(static_cast<Eigen::Index>(i)) = sum / static_cast<double>(hi - lo);
  }
  return out;
}

void plot_residual_time(const ExplainResult& r, const std::filesystem::path& png) {
  const auto& t = r.input.signals.t_s;
  const double half = std::max(30.0, 30.0 * r.input.dt_s);
  const Eigen::VectorXd before = smoothed(t, r.residual_before_dph, half), after = smoothed(t, r.residual_after_dph, half);
  const std::size_t stride = std::max<std::size_t>(1, t.size() / 4000);
  std::vector<std::vector<double>> rows, held;
  for (std::size_t i = 0; i < t.size(); i += stride) {
    const auto k = static_cast<Eigen::Index>(i);
    rows.push_back({t[i] / 3600.0, before(k), after(k)});
    held.push_back({t[i] / 3600.0, r.input.heldout[i] ? 1.0 : 0.0});
  }
  const double lo = std::min(before.minCoeff(), after.minCoeff()), hi = std::max(before.maxCoeff(), after.maxCoeff());
  render_png(png, datablock("r", rows) + datablock("h", held) +
                      str_cat("set title 'Residual (recording - model), ", format_significant(2 * half, 2),
                              "-s moving average; shaded: held-out blocks'\nset xlabel 'time (h)'\nset ylabel 'residual (deg/h)'\nset grid\n",
                              "set yrange [", lo - 0.1 * (hi - lo + 1e-9), ":", hi + 0.1 * (hi - lo + 1e-9), "]\nset key top right\n",
                              "plot $h using 1:($2 > 0 ? ", hi + 0.1 * (hi - lo + 1e-9), " : 1/0) with impulses lc rgb '#e8e8e8' notitle, ",
                              "$r using 1:2 with lines lw 2 title 'before (simulation re-estimated)', ",
                              "$r using 1:3 with lines lw 2 title 'after (effects added)'\n"));
}

void plot_residual_grid(const ExplainResult& r, const std::filesystem::path& png) {
  const auto& s = r.input.signals;
  const double half = std::max(30.0, 30.0 * r.input.dt_s);
  const Eigen::VectorXd before = smoothed(s.t_s, r.residual_before_dph, half), after = smoothed(s.t_s, r.residual_after_dph, half);
  const Eigen::VectorXd branch = thermal_branch(s, coil_temperature(s, 0.0), TermScaling{});
  const std::size_t stride = std::max<std::size_t>(1, s.t_s.size() / 6000);
  std::vector<std::vector<double>> rows[4];
  for (std::size_t i = 0; i < s.t_s.size(); i += stride) {
    const auto k = static_cast<Eigen::Index>(i);
    const int b = branch(k) >= 0 ? 0 : 1;
    const double rate = units::radps_to_dps(s.rate(k));
    rows[b].push_back({s.temp_c(k), rate, before(k)});
    rows[2 + b].push_back({s.temp_c(k), rate, after(k)});
  }
  const double lim = std::max(before.cwiseAbs().maxCoeff(), 1e-9);
  const char* titles[] = {"before, heating", "before, cooling", "after, heating", "after, cooling"};
  std::string script = str_cat("set multiplot layout 2,2 title 'Smoothed residual over (T, omega) (deg/h)'\n",
                               "set palette defined (-1 'blue', 0 'white', 1 'red')\nset cbrange [", -lim, ":", lim, "]\n",
                               "set xlabel 'temperature (C)'\nset ylabel 'rate (deg/s)'\nset grid\n");
  for (int p = 0; p < 4; ++p) {
    if (rows[p].empty()) rows[p].push_back({0.0, 0.0, 0.0});
    script += datablock(str_cat("g", p), rows[p]) + str_cat("set title ", gnuplot_quote(titles[p]), "\nplot $g", p,
                                                               " using 1:2:3 with points pt 7 ps 0.4 lc palette notitle\n");
  }
  render_png(png, script + "unset multiplot\n", PngSize{1280, 960});
}

void plot_correlations(const ExplainResult& r, const std::filesystem::path& png) {
  std::string blocks, plots;
  double threshold = 0.0;
  int i = 0;
  for (const auto& c : r.summary.after.channels) {
    std::vector<std::vector<double>> rows;
    for (std::size_t k = 0; k < c.lag_s.size(); ++k) rows.push_back({c.lag_s[k], c.r[k]});
    blocks += datablock(str_cat("c", i), rows);
    plots += str_cat(i ? ", " : "", "$c", i, " using 1:2 with lines lw 2 title ", gnuplot_quote(c.channel));
    threshold = c.threshold;
    ++i;
  }
  if (i == 0) return;
  render_png(png, blocks + str_cat("set title 'Correlation of the whitened residual (after) with each channel; dashed: significance'\n",
                                   "set xlabel 'lag (s)'\nset ylabel 'correlation'\nset grid\nset key outside right\n",
                                   "plot ", plots, ", ", threshold, " with lines dt 2 lc rgb 'black' notitle, ", -threshold,
                                   " with lines dt 2 lc rgb 'black' notitle\n"),
             PngSize{1200, 640});
}

std::string parameters_text(std::vector<explain::PhysicalParameter> params) {
  std::sort(params.begin(), params.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  std::string out;
  for (const auto& p : params) {
    out += (out.empty() ? "" : "; ") + p.name + " = " + format_significant(p.value, 4);
    if (!p.reference) out += " [" + format_significant(p.low, 3) + ", " + format_significant(p.high, 3) + "]";
  }
  return out;
}

std::string ordinal(int n) {
  static const char* words[] = {"zeroth", "first", "second", "third", "fourth", "fifth", "sixth", "seventh", "eighth", "ninth", "tenth"};
  return n >= 0 && n <= 10 ? words[n] : str_cat(n, "th");
}

// Which blocks were held out, as explain_input.h's rule: block b when b % every == 2 % every.
// " (stage a s, stage b s, ...)": where the run time went, in the order the stages ran.
std::string stage_times_text(const explain::StageTimes& t) {
  std::string out;
  for (const auto& [stage, s] : t.seconds) out += str_cat(out.empty() ? " (" : ", ", stage, " ", format_significant(s, 2), " s");
  return out.empty() ? out : out + ")";
}

std::string heldout_text(int every) { return str_cat("every ", ordinal(every), " from the ", ordinal(2 % every + 1), " held out"); }

void effects_markdown(const explain::ExplainSummary& j, std::ostringstream& md) {
  md << "## Effects found\n\n";
  if (j.effects.empty()) md << "None.\n\n";
  for (const auto& e : j.effects) {
    md << "### " << e.id << "\n\n" << e.description << "\n\n"
       << "- parameters (95 % intervals): " << parameters_text(e.parameters) << "\n"
       << "- dBIC " << format_significant(e.delta_bic, 4) << ", bootstrap p " << format_significant(e.p_value, 3) << ", stability "
       << format_significant(e.stability, 2) << ", held-out: "
       << (e.support_z ? str_cat("the blocks do not hold it; on its own support (predictive z ", format_significant(*e.support_z, 3), ") confirmed")
           : !e.heldout_z ? "not testable there"
           : e.heldout_confirmed() ? "confirmed"
                                   : "not confirmed");
    if (e.heldout_excess_removed) md << ", " << format_significant(100.0 * *e.heldout_excess_removed, 3) << " % of the held-out excess over the noise floor removed";
    md << "\n";
    for (const auto& s : e.separating) {
      const bool weaker = std::find(e.weaker_alternatives.begin(), e.weaker_alternatives.end(), s.alternative) != e.weaker_alternatives.end();
      md << (weaker ? "- a weaker alternative explanation is " + s.alternative + " (clearly less likely here); to rule it out: "
                    : "- **cannot be told apart from " + s.alternative + "** by this recording; to separate them: ")
         << s.experiment << "\n";
    }
    md << "\n";
  }
}

void absorbed_markdown(const explain::ExplainSummary& j, std::ostringstream& md) {
  if (j.absorbed_alternatives.empty()) return;
  md << "## Alternative explanations of part of the simulation's structure\n\n";
  for (const auto& a : j.absorbed_alternatives) {
    md << "- " << a.id << ": " << a.reason << "\n";
    if (!a.separating_experiment.empty()) md << "  To separate them: " << a.separating_experiment << ".\n";
  }
  md << "\n";
}

void unexplained_markdown(const explain::ExplainSummary& j, std::ostringstream& md) {
  md << "## Unexplained structure after the refit\n\n";
  if (j.unexplained.empty()) md << "None significant.\n\n";
  for (const auto& u : j.unexplained) {
    md << "- " << to_string(u.kind) << (u.channel ? " with `" + *u.channel + "`" : "") << ", t " << format_significant(u.t_start_s, 5) << " .. "
       << format_significant(u.t_end_s, 5) << " s, statistic " << format_significant(u.statistic, 3);
    if (u.kind == explain::UnexplainedKind::temperature_rate_cell) {
      md << ", T " << nlohmann::json(u.temp_c).dump() << " C, rate " << nlohmann::json(u.rate_dps).dump() << " deg/s, "
         << (u.heating ? "heating" : "cooling");
    }
    md << "\n";
  }
}

void selection_markdown(const explain::ExplainSummary& j, std::ostringstream& md) {
  md << "## Selection\n\nEvery candidate at every forward step (dBIC, bootstrap p; * significant after Holm):\n\n";
  int step = 0;
  for (const auto& row : j.selection.steps) {
    md << "- step " << ++step << ":";
    for (const auto& c : row) {
      md << " " << c.id << " ";
      if (c.columns == 0) md << "(absorbed)";
      else md << format_significant(c.delta_bic, 3) << "/" << format_significant(c.p_value, 2) << (c.significant ? "*" : "");
      md << ";";
    }
    md << "\n";
  }
  for (const auto& d : j.demoted) md << "- demoted " << d.id << " (dBIC " << format_significant(d.delta_bic, 3) << "): " << d.reason << "\n";
  for (const auto& u : j.selection.untestable) md << "- not testable: " << u << "\n";
}

std::string report_markdown(const ExplainResult& r) {
  const explain::ExplainSummary& j = r.summary;
  std::ostringstream md;
  md << "# gyrosid explain: " << j.recording.source << "\n\n"
     << "**Verdict: " << to_string(j.verdict) << "**. Simulation: " << j.simulation << ". " << j.recording.samples << " samples over "
     << format_significant(j.recording.duration_s / 3600.0, 3) << " h; " << j.recording.blocks << " blocks ("
     << (j.recording.thermal_cycles ? "whole thermal cycles" : "equal spans of time") << "), " << heldout_text(j.recording.heldout_every)
     << (j.recording.heldout_outside_support
             ? str_cat(" (", j.recording.heldout_outside_support, " held-out samples lie outside the training blocks' support - the "
                       "simulation or the refitted model extrapolates there - and confirm nothing)")
             : std::string())
     << ". Run time " << format_significant(j.run_time_s, 3) << " s" << stage_times_text(j.stage_times) << ".\n\n";
  if (!j.recording.temperature_recorded) md << "The recording has no temperature: it is held, and no temperature effect can be tested.\n\n";
  if (!j.recording.decimation.is_null()) md << "Explained at block means: " << j.recording.decimation.at("statement").get<std::string>() << "\n\n";
  const auto& fit = j.fit;
  md << "## Fit (residual rms, deg/h)\n\n| | training | held-out |\n|---|---|---|\n"
     << "| simulation as given | " << format_significant(fit.rms_simulation_dph, 4) << " | |\n"
     << "| before (its coefficients re-estimated) | " << format_significant(fit.rms_before_dph, 4) << " | "
     << format_significant(fit.heldout_rms_before_dph, 4) << " |\n"
     << "| after (effects added, refitted) | " << format_significant(fit.rms_after_dph, 4) << " | " << format_significant(fit.heldout_rms_after_dph, 4)
     << " |\n"
     << "| noise floor (the noise model alone) | " << format_significant(j.noise.floor_dph, 4) << " | |\n\n";
  effects_markdown(j, md);
  absorbed_markdown(j, md);
  unexplained_markdown(j, md);
  md << "\n## Noise terms of the residual\n\n";
  const nlohmann::json noise = to_json(j)["noise"];
  for (const auto& t : noise["terms"]) md << "- " << t["id"].get<std::string>() << ": " << t["coefficients"].dump() << " - " << t["description"].get<std::string>() << "\n";
  md << "\nWhitening model of the residual (white + random walk + Gauss-Markov, from its Allan deviation): " << noise["whitening_model"].dump()
     << ". Whiteness after whitening (Ljung-Box, " << j.after.ljung_box_lags << " lags): p = " << format_significant(j.after.ljung_box_p, 3) << ".\n\n";
  selection_markdown(j, md);
  md << "\n## Plots\n\n![residual in time](residual_time.png)\n\n![residual over (T, omega)](residual_grid.png)\n\n"
     << "![correlations](correlations.png)\n\n";
  if (!j.after.allan.empty()) md << "![Allan deviation of the residual](allan.png)\n";
  return md.str();
}

// residuals.csv's heldout column: 0 training, 1 held out (confirms), 2 held out outside the training support
// of the simulation or the refitted model. Its heldout_scored column is 1 on exactly the rows the held-out
// proof scores (ExplainInput::confirms): the held-out rms in explain.json is over those rows. (Each effect's
// held-out gain is over the rows where neither model of its own comparison extrapolates, judge.h.)
int heldout_code(const explain::ExplainInput& in, Eigen::Index i) {
  if (!in.heldout[static_cast<std::size_t>(i)]) return 0;
  return in.confirms(i) ? 1 : 2;
}

}  // namespace

void write_explain_outputs(const ExplainResult& r, const std::filesystem::path& dir) {
  write_file_atomic(dir / "explain.json", to_json(r.summary).dump(2) + "\n");
  write_file_atomic(dir / "residuals.csv", [&](std::ostream& out) {
    out << "t_s,residual_before_dph,residual_after_dph,heldout,heldout_scored\n";
    for (Eigen::Index i = 0; i < r.input.size(); ++i) {
      out << format_number(r.input.signals.t_s[static_cast<std::size_t>(i)]) << ',' << format_number(r.residual_before_dph(i)) << ','
          << format_number(r.residual_after_dph(i)) << ',' << heldout_code(r.input, i) << ','
          << (r.input.confirms(i) ? 1 : 0) << '\n';
    }
  });
  save_model(dir / "model.json", *r.model, {{"training", {{"recording", r.input.source}, {"explain", r.summary.simulation}}}});
  plot_residual_time(r, dir / "residual_time.png");
  plot_residual_grid(r, dir / "residual_grid.png");
  plot_correlations(r, dir / "correlations.png");
  if (!r.summary.after.allan.empty()) plot_allan(dir / "allan.png", r.summary.after.allan, r.summary.after.allan_fit, "Allan deviation of the residual after the refit", "deg/h");
  write_file_atomic(dir / "report.md", report_markdown(r));
}

}  // namespace gyrosid
