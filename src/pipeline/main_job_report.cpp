// report.md and summary.json of the main job, from its typed result (the only place they are written).
#include <cmath>
#include <sstream>

#include "core/atomic_file.h"
#include "core/format.h"
#include "pipeline/main_job.h"
#include "core/version.h"
#include "model/fit_notes.h"
#include "report/cof_json.h"
#include "report/html.h"

namespace gyrosid {
namespace {

std::string cell(double v) { return format_significant(v, 3); }

nlohmann::json uncompensated_json(const nav::CofRun& run) {
  nlohmann::json j = {{"end_error_m", run.end_error_m}};
  if (!std::isnan(run.error_after_1h_m)) j["error_after_1h_m"] = run.error_after_1h_m;
  return j;
}

std::string model_size(const SolveSummary& fit) { return fit_notes_of(fit.details).size(); }

void surfaces_section(std::ostream& md, const MainJobResult& r) {
  md << "## Models against the true error surface (cf. Tables 5.2/5.3)\n\n"
     << "Estimated minus true rate error over T " << cell(r.rbf.surface.temps_c.front()) << ".." << cell(r.rbf.surface.temps_c.back())
     << " C x omega -100..100 deg/s, deg/h.\n\n"
     << "| model | config | parameters | fit time (s) | mean | sigma | max | min | rms |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const CalibratedModel* c : {&r.classical, &r.rbf}) {
    const auto& s = c->surface.stats;
    md << "| " << c->label << " | `" << c->config << "` | " << model_size(c->result.summary) << " | " << cell(c->result.summary.time_s)
       << " | " << cell(s.mean_dph) << " | " << cell(s.sigma_dph) << " | " << cell(s.max_dph) << " | " << cell(s.min_dph) << " | "
       << cell(s.rms_dph) << " |\n";
  }
  md << "\n![classical](surfaces/classical_difference.png)\n\n![rbf](surfaces/rbf_difference.png)\n\n";
  for (const CalibratedModel* c : {&r.classical, &r.rbf}) {
    if (c->surface.sigma_dph.size() == 0) continue;
    const auto& s = c->surface.sigma_stats;
    md << "The " << c->label << " model's predictive sigma (its posterior): rms " << cell(s.rms_sigma_dph) << " deg/h, max "
       << cell(s.max_sigma_dph) << " deg/h; the 95 % band covers " << cell(100 * s.coverage_95) << " % of |estimated - true|.\n\n![" << c->label
       << " sigma](surfaces/" << c->label << "_sigma.png)\n\n";
  }
}

void criterion_section(std::ostream& md, const MainJobOptions& o, const MainJobResult& r) {
  md << "## Criterion of fit (cf. Table 5.4)\n\n"
     << "Both compensations, and the raw gyros for scale, through the same strapdown INS as the error-free reference "
     << "(thesis fig 5.3); flights from " << cell(o.start_temp_c) << " C, rates clipped to +-100 deg/s, noise off. "
     << "Short and medium flights are scored at their end, the long one after 1 h (s5.3.3); metres.\n\n"
     << "| flight | duration (s) | uncompensated | classical | RBF | classical / RBF |\n|---|---|---|---|---|---|\n";
  for (const auto& s : r.flights) {
    const double c = nav::score_m(s.classical.run), b = nav::score_m(s.rbf.run);
    md << "| " << s.flight << " | " << cell(s.rbf.duration_s()) << " | " << cell(nav::score_m(s.rbf.uncompensated)) << " | " << cell(c)
       << " | " << cell(b) << " | " << cell(c / b) << " |\n";
  }
  md << "\n";
  for (const auto& s : r.flights) md << "![" << s.flight << "](cof/" << s.flight << "_error_growth.png)\n";
  md << "\nPer-run outputs (cof.json, ground track, error growth) under `cof/<flight>/<model>/`.\n\n";
}

void monte_carlo_section(std::ostream& md, const MainJobResult& r) {
  md << "## Monte Carlo on the short flight (cf. s5.5, fig 5.18)\n\n"
     << "New sensor noise every run; runs until the Anderson-Darling test accepts normality of every error component "
     << "at 95 % (at least 25). The reference rows are the thesis's: white noise alone, and a bias equal to the noise's "
     << "1-Hz sigma, neither compensated.\n\n"
     << "| compensation | runs | normal | mean (m) | sigma (m) | sigma increase over noise alone (m) |\n|---|---|---|---|---|---|\n";
  for (const auto& c : r.short_monte_carlo) {
    md << "| " << c.request.model << " | " << c.mc->runs << " | " << (c.mc->normal ? "yes" : "no") << " | " << cell(c.mc->mean_m) << " | "
       << cell(c.mc->sigma_m) << " | " << cell(c.mc_reference ? c.mc_reference->sigma_increase_m : 0.0) << " |\n";
  }
  const nav::CofReport& rbf = r.short_monte_carlo.back();
  if (rbf.mc_reference) {
    const auto& n = rbf.mc_reference->just_noise;
    md << "| just noise | " << n.runs << " | " << (n.normal ? "yes" : "no") << " | " << cell(n.mean_m) << " | " << cell(n.sigma_m) << " | |\n"
       << "| bias " << cell(rbf.mc_reference->bias_dph) << " deg/h | 1 | | " << cell(rbf.mc_reference->bias_end_error_m) << " | | |\n";
  }
  md << "\n![Monte Carlo, RBF](cof/short_monte_carlo/rbf/monte_carlo.png)\n\n";
}

void noise_section(std::ostream& md, const MainJobResult& r) {
  const NoiseIdentification& n = r.allan.noise;
  md << "## Noise (static run, " << r.static_description << ")\n\n"
     << "Identified model " << n.structure.name() << ", fitted from " << format_significant(n.fit_tau_low_s, 3) << " to "
     << format_significant(n.fit_tau_high_s, 3) << " s (chi2 " << format_significant(n.chi2, 3) << " on " << n.dof << " degrees of freedom).\n\n"
     << "| term | fitted | 95 % interval | unit |\n|---|---|---|---|\n";
  for (const auto& t : quoted_terms(n)) {
    md << "| " << t.meaning << " " << t.name << " | " << format_significant(t.value) << " | " << format_significant(t.low, 3) << " - "
       << format_significant(t.high, 3) << " | " << t.unit << " |\n";
  }
  md << "\n![Allan deviation](allan/allan.png)\n";
}

// How to get the same report again, and where its inputs and products are.
void provenance_section(std::ostream& md, const MainJobOptions& o) {
  std::string command = "gyrosid run --out " + o.out.string() + " --sensor " + o.sensor + " --trajectory " + o.trajectory +
                        " --soak " + o.soak + " --static-trajectory " + o.static_trajectory + " --classical-config " +
                        o.classical_config + " --rbf-config " + o.rbf_config_used() + " --flights";
  for (const auto& f : o.flights) command += " " + f;
  command += " --start-temp-c " + format_number(o.start_temp_c) + " --seed " + std::to_string(o.seed) + (o.noisy ? " --noisy" : "");
  md << "\n## Provenance\n\n"
     << "- gyrosid " << version_string() << "\n"
     << "- reproduce: `" << command << "` (same inputs and seed, same numbers)\n"
     << "- configs: sensor `" << o.sensor << "`, RBF trajectory `" << o.trajectory << "`, soak `" << o.soak << "`, static run `"
     << o.static_trajectory << "`, calibrations `" << o.classical_config << "` and `" << o.rbf_config_used() << "`\n"
     << "- recordings: [dual scan](data/dual_scan.csv), [classical soak](data/classical_soak.csv)\n"
     << "- models: [classical](models/classical.json), [RBF](models/rbf.json) (for gyrosid compensate, cof, export)\n"
     << "- figures: [summary.json](summary.json), per-flight [cof.json](cof/) files\n";
}

nlohmann::json summary_json(const MainJobOptions& o, const MainJobResult& r) {
  nlohmann::json mc = nlohmann::json::object();
  for (const auto& c : r.short_monte_carlo) mc[c.request.model] = cof_json(c)["monte_carlo"];
  nlohmann::json j = {{"sensor", o.sensor}, {"calibration_noise", o.noisy}, {"seed", o.seed}, {"run_time_s", r.run_time_s},
                      {"start_temp_c", o.start_temp_c}, {"monte_carlo_short", mc}};
  for (const CalibratedModel* c : {&r.classical, &r.rbf}) {
    j["models"][c->label] = {{"config", c->config}, {"surface", c->surface.stats.to_json()}, {"summary", c->result.summary}};
    if (c->surface.sigma_dph.size() > 0) j["models"][c->label]["sigma"] = c->surface.sigma_stats.to_json();
  }
  for (const auto& s : r.flights) {
    j["criterion_of_fit"][s.flight] = {{"uncompensated", uncompensated_json(s.rbf.uncompensated)},
                                       {"classical", cof_json(s.classical)},
                                       {"rbf", cof_json(s.rbf)},
                                       {"ratio", nav::score_m(s.classical.run) / nav::score_m(s.rbf.run)}};
  }
  return j;
}

}  // namespace

void write_main_job_report(const MainJobOptions& o, const MainJobResult& r) {
  std::ostringstream md;
  md << "# gyrosid main job\n\n"
     << "The thesis's pipeline (du Plessis 2013, ch. 5) on the built-in default configuration: sensor `" << o.sensor
     << "`, seed " << o.seed << ", calibration recordings " << (o.noisy ? "with" : "without") << " sensor noise"
     << (o.noisy ? "" : " (as the thesis's Table 5.4; `--noisy` for the other case)") << ". Run time "
     << format_number(std::round(r.run_time_s * 10) / 10) << " s.\n\n"
     << "## Calibration data\n\n"
     << "- dual scan: " << r.dual_description << " (`data/dual_scan.csv`)\n"
     << "- classical soak: " << r.soak_description << " (`data/classical_soak.csv`)\n\n"
     << "![error surface](error_surface.png)\n\n![coverage](coverage.png)\n\n";
  surfaces_section(md, r);
  criterion_section(md, o, r);
  monte_carlo_section(md, r);
  noise_section(md, r);
  provenance_section(md, o);
  write_file_atomic(o.out / "summary.json", summary_json(o, r).dump(2) + "\n");
  write_file_atomic(o.out / "report.md", md.str());
  write_file_atomic(o.out / "index.html", markdown_to_html(md.str(), "gyrosid main job"));
}

}  // namespace gyrosid
