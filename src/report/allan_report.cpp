#include "report/allan_report.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"
#include "report/plots.h"

namespace gyrosid {
namespace {

// From deg/h-based units: Q (deg/h) s = arcsec; N (deg/h) sqrt(s) / 60 = deg/sqrt(h); K (deg/h)/sqrt(s) * 60 =
// (deg/h)/sqrt(h); R (deg/h)/s * 3600 = (deg/h)/h.
struct Quote {
  const char* name;
  const char* meaning;
  const char* unit;
  double factor;
};
Quote quote_of(const std::string& parameter) {
  if (parameter == "Q") return {"Q", "quantization", "arcsec", 1.0};
  if (parameter == "F") return {"F", "low-pass filter (Allan variance -3 F^2 / tau^2)", "arcsec", 1.0};
  if (parameter == "N") return {"N", "angle random walk", "deg/sqrt(h)", 1.0 / 60.0};
  if (parameter == "B") return {"B", "bias instability (flicker)", "deg/h", 1.0};
  if (parameter == "K") return {"K", "rate random walk", "(deg/h)/sqrt(h)", 60.0};
  if (parameter == "R") return {"R", "rate ramp", "(deg/h)/h", 3600.0};
  if (parameter.ends_with(" tau")) return {"", "Gauss-Markov correlation time", "s", 1.0};
  return {"", "Gauss-Markov sigma", "deg/h", 1.0};
}

nlohmann::json noise_json(const AllanReport& r) {
  const NoiseIdentification& n = r.noise;
  nlohmann::json terms = nlohmann::json::array();
  for (const auto& t : quoted_terms(n)) {
    terms.push_back({{"name", t.name}, {"meaning", t.meaning}, {"unit", t.unit}, {"value", t.value}, {"sigma", t.sigma}, {"low", t.low}, {"high", t.high}});
  }
  nlohmann::json gm = nlohmann::json::array();
  for (const auto& g : n.model.gauss_markov) gm.push_back({{"sigma_dph", g.sigma}, {"tau_s", g.tau_s}});
  nlohmann::json candidates = nlohmann::json::array();
  for (std::size_t i = 0; i < std::min<std::size_t>(8, n.candidates.size()); ++i) {
    candidates.push_back({{"model", n.candidates[i].structure.name()}, {"chi2", n.candidates[i].chi2}, {"criterion", n.candidates[i].criterion}});
  }
  nlohmann::json points = nlohmann::json::array();
  for (const auto& p : n.points) {
    points.push_back({{"tau_s", p.tau_s}, {"adev_dph", std::sqrt(p.allan_variance)}, {"fit_dph", std::sqrt(p.fitted)}, {"z", p.z}, {"in_band", p.in_band}});
  }
  nlohmann::json model = {{"quantization", n.model.quantization}, {"filter", n.model.filter}, {"white", n.model.white},
                          {"flicker", n.model.flicker},           {"random_walk", n.model.random_walk}, {"ramp", n.model.ramp}, {"gauss_markov", gm},
                          {"unit", "deg/h-based: Q, F (deg/h) s; N (deg/h) sqrt(s); B deg/h; K (deg/h)/sqrt(s); R (deg/h)/s; Gauss-Markov deg/h, s"}};
  return {{"model", n.structure.name()},
          {"composite", model},
          {"terms", terms},
          {"gauss_markov", gm},
          {"fit_band_s", {n.fit_tau_low_s, n.fit_tau_high_s}},
          {"left_out", n.left_out},
          {"robust", n.robust},
          {"chi2", n.chi2},
          {"dof", n.dof},
          {"p_value", n.p_value},
          {"dispersion", n.dispersion},
          {"criterion", "least chi2 + p ln(samples) over every structure of Q, N, B, K, R and up to the allowed Gauss-Markov terms"},
          {"candidates", candidates},
          {"octave_points", points},
          {"warnings", n.warnings}};
}

// The curve's minimum and the fitted deviation there (the IEEE reading of bias instability: the minimum /
// sqrt(2 ln 2 / pi)).
// The curve's own minimum over the taus the fit claims (up to fit_tau_high_s, a tenth of the record by default):
// beyond them an estimate rests on a few independent averages and its dips are chance, not a floor.
nlohmann::json minimum_json(const AllanReport& r) {
  const double hi = r.noise.fit_tau_high_s > 0.0 ? r.noise.fit_tau_high_s * (1.0 + 1e-9) : std::numeric_limits<double>::infinity();
  auto it = r.curve.end();
  for (auto p = r.curve.begin(); p != r.curve.end() && p->tau_s <= hi; ++p) {
    if (it == r.curve.end() || p->adev < it->adev) it = p;
  }
  if (it == r.curve.end()) return nullptr;
  const double fitted = std::sqrt(r.noise.allan_variance(it->tau_s));
  return {{"tau_s", it->tau_s}, {"adev_dph", it->adev}, {"ci_low_dph", it->ci_low}, {"ci_high_dph", it->ci_high}, {"fit_dph", fitted},
          {"bias_instability_from_minimum_dph", it->adev / std::sqrt(kFlickerAllanFactor)}};
}

}  // namespace

std::vector<QuotedTerm> quoted_terms(const NoiseIdentification& noise) {
  std::vector<QuotedTerm> out;
  for (const auto& p : noise.parameters) {
    const Quote q = quote_of(p.name);
    out.push_back({*q.name ? q.name : p.name, q.meaning, q.unit, p.value * q.factor, p.sigma * q.factor, p.low * q.factor, p.high * q.factor});
  }
  return out;
}

AllanReport write_allan(const std::filesystem::path& dir, const std::vector<double>& rate_dph, double dt_s, const AllanOptions& options,
                        const NoiseIdOptions& noise_options, const std::string& title, nlohmann::json provenance) {
  AllanReport r;
  const AllanPhase phase(rate_dph, dt_s);
  r.curve = overlapping_allan_deviation(phase, options);
  r.noise = identify_noise(phase, noise_options);
  std::vector<double> fit(r.curve.size());
  double ss = 0.0;
  int in_band = 0;
  for (std::size_t i = 0; i < r.curve.size(); ++i) {
    const AllanPoint& p = r.curve[i];
    const double v = r.noise.allan_variance(p.tau_s);
    fit[i] = v > 0 ? std::sqrt(v) : std::nan("");  // a filter term's model is negative far below the band
    if (p.tau_s < r.noise.fit_tau_low_s * (1 - 1e-9) || p.tau_s > r.noise.fit_tau_high_s * (1 + 1e-9) || !(p.adev > 0)) continue;
    ss += std::pow(fit[i] * fit[i] / (p.adev * p.adev) - 1.0, 2), ++in_band;
    if (fit[i] < p.ci_low || fit[i] > p.ci_high) r.outside_band_tau_s.push_back(p.tau_s);
  }
  if (!r.outside_band_tau_s.empty()) {
    std::vector<std::string> taus;
    for (double t : r.outside_band_tau_s) taus.push_back(format_significant(t, 3));
    r.outside_band_note = str_cat("the fitted deviation lies outside the data's ", format_significant(100 * options.confidence, 3), " % band at ",
                                  r.outside_band_tau_s.size(), " of ", in_band, " taus in the fit band (a correct model misses each about ",
                                  format_significant(100 * (1 - options.confidence), 2), " % of the time; neighbouring taus together): ",
                                  join(taus, ", "), " s");
  }
  write_file_atomic(dir / "allan.csv", [&](std::ostream& out) {
    out << "tau_s,adev_dph,ci_low_dph,ci_high_dph,edf,terms,noise_alpha,fit_dph\n";
    for (std::size_t i = 0; i < r.curve.size(); ++i) {
      const AllanPoint& p = r.curve[i];
      out << format_number(p.tau_s) << ',' << format_number(p.adev) << ',' << format_number(p.ci_low) << ',' << format_number(p.ci_high) << ','
          << format_number(p.edf) << ',' << p.terms << ',' << p.alpha << ',' << format_number(fit[i]) << '\n';
    }
  });
  const CompositeNoise& m = r.noise.model;
  nlohmann::json j = std::move(provenance);
  j["sample_interval_s"] = dt_s;
  j["samples"] = rate_dph.size();
  j["confidence"] = options.confidence;
  j["coefficients"] = {
      {"quantization_arcsec", m.quantization},     {"arw_deg_rt_h", m.white / 60.0},         {"white_dph_at_1hz", m.white},
      {"bias_instability_dph", m.flicker},         {"rrw_dph_rt_h", m.random_walk * 60.0},   {"rate_ramp_dph_per_h", m.ramp * 3600.0},
  };
  j["noise"] = noise_json(r);
  j["fit_band_s"] = {r.noise.fit_tau_low_s, r.noise.fit_tau_high_s};
  j["allan_minimum"] = minimum_json(r);
  j["fit_relative_rms_residual"] = in_band > 0 ? std::sqrt(ss / in_band) : 0.0;
  j["fit_outside_data_band_tau_s"] = r.outside_band_tau_s;
  j["fit_outside_data_band"] = r.outside_band_note;
  write_file_atomic(dir / "allan.json", j.dump(2) + "\n");
  plot_allan(dir / "allan.png", r.curve, r.noise, title, "deg/h");
  return r;
}

CompositeNoise load_identified_noise(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) fail(path.string(), ": cannot open (an allan.json written by gyrosid allan)");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    fail(path.string(), ": not JSON: ", e.what());
  }
  if (!j.contains("noise") || !j["noise"].contains("composite")) {
    fail(path.string(), ": no noise.composite - not an allan.json of this gyrosid (rerun gyrosid allan)");
  }
  const auto& c = j["noise"]["composite"];
  auto number = [&](const char* key) {
    if (!c.contains(key) || !c[key].is_number() || !(c[key].get<double>() >= 0)) fail(path.string(), ": noise.composite.", key, " must be a number >= 0");
    return c[key].get<double>();
  };
  CompositeNoise m;
  m.quantization = number("quantization"), m.filter = number("filter"), m.white = number("white"), m.flicker = number("flicker");
  m.random_walk = number("random_walk"), m.ramp = number("ramp");
  if (!c.contains("gauss_markov") || !c["gauss_markov"].is_array()) fail(path.string(), ": noise.composite.gauss_markov must be a list");
  for (const auto& g : c["gauss_markov"]) {
    if (!g.contains("sigma_dph") || !g.contains("tau_s") || !g["sigma_dph"].is_number() || !g["tau_s"].is_number() || !(g["tau_s"].get<double>() > 0)) {
      fail(path.string(), ": noise.composite.gauss_markov: each needs sigma_dph and tau_s > 0");
    }
    m.gauss_markov.push_back({g["sigma_dph"].get<double>(), g["tau_s"].get<double>()});
  }
  return m;
}

void write_kalibr_noise_yaml(const std::filesystem::path& path, const CompositeNoise& fit, double update_rate_hz, const std::string& source) {
  constexpr double kRadPerDeg = 3.14159265358979323846 / 180.0;
  // fit is in deg/h-based units: white in (deg/h) sqrt(s), random_walk in (deg/h)/sqrt(s).
  const double noise_density = fit.white / 3600.0 * kRadPerDeg;      // rad/s * sqrt(s) = rad/s/sqrt(Hz)
  const double random_walk = fit.random_walk / 3600.0 * kRadPerDeg;  // rad/s / sqrt(s) = rad/s^2/sqrt(Hz)
  std::ostringstream out;
  out << "# Kalibr IMU noise model (imu.yaml), gyro terms from gyrosid's noise identification of " << source << "\n"
      << "# Continuous-time densities, as Kalibr expects; the discrete white-noise sigma at update_rate is\n"
      << "# gyroscope_noise_density * sqrt(update_rate), the discrete bias step gyroscope_random_walk / sqrt(update_rate).\n"
      << "# Accelerometer terms are not written: this recording characterises the gyro only.\n";
  if (fit.flicker > 0 || !fit.gauss_markov.empty() || fit.quantization > 0) {
    out << "# Not representable in Kalibr's model and left out: " << fit.describe("deg/h") << " (the terms beyond N and K).\n";
  }
  out << "#Gyroscopes\n"
      << "gyroscope_noise_density: " << format_number(noise_density) << "  # rad/s/sqrt(Hz) = N "
      << format_significant(fit.white / 60.0) << " deg/sqrt(h) * (pi/180) / 60\n"
      << "gyroscope_random_walk: " << format_number(random_walk) << "  # rad/s^2/sqrt(Hz) = K "
      << format_significant(fit.random_walk * 60.0) << " (deg/h)/sqrt(h) * (pi/180) / 3600 / 60\n"
      << "update_rate: " << format_number(update_rate_hz) << "  # Hz, the recording's sample rate\n";
  write_file_atomic(path, out.str());
}

}  // namespace gyrosid
