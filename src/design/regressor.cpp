#include "design/regressor.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.h"
#include "core/format.h"
#include "core/units.h"
#include "model/gaussian_node.h"
#include "model/greybox_fit.h"
#include "model/terms/term_kinds.h"

namespace gyrosid::design {

std::string Domain::validate() const {
  if (!(temp_max_c > temp_min_c)) return str_cat("domain temperatures [", temp_min_c, ", ", temp_max_c, "] C are empty");
  if (!(rate_max_radps > 0)) return "domain rate range must be positive";
  return "";
}

void ModelOptions::bind(OptionTable& t) {
  t.integer("model.rbf_temperature_nodes", &rbf_temperature_nodes, 2, 60, "rbf: dictionary nodes along temperature")
      .integer("model.rbf_rate_nodes", &rbf_rate_nodes, 2, 60, "rbf: dictionary nodes along rate")
      .real("model.rbf_width", &rbf_width, 0.0, 10.0, "rbf: node width on inputs normalised to [-1, 1] over the domain", true)
      .integer("model.bias_order", &bias_order, 0, 8, "greybox: bias polynomial order in coil temperature")
      .integer("model.grid_temperatures", &grid_temperatures, 2, 20, "greybox: scale-factor grid temperatures (even over the domain)")
      .text("model.grid_temperatures_c", &grid_temperatures_c, "greybox: explicit grid temperatures, comma-separated (overrides grid_temperatures)")
      .text("model.grid_rates_dps", &grid_rates_dps, "greybox: scale-factor grid rates, comma-separated deg/s (kept within the domain)")
      .flag("model.shupe", &shupe, "greybox: Shupe term k_S dT/dt")
      .flag("model.hysteresis", &hysteresis, "greybox: hysteresis between heating and cooling")
      .flag("model.thermal_lag", &thermal_lag, "greybox: coil lag behind the probe (linearised)")
      .real("model.shupe_prior_dph_per_c_per_min", &shupe_prior_dph_per_c_per_min, 0.0, 1e6, "greybox: prior sd of the Shupe coefficient", true)
      .real("model.hysteresis_prior_dph", &hysteresis_prior_dph, 0.0, 1e6, "greybox: prior sd of the hysteresis step", true)
      .real("model.thermal_lag_prior_s", &thermal_lag_prior_s, 0.0, 1e6, "greybox: prior sd of the coil lag", true)
      .integer("model.classical_bias_order", &classical_bias_order, 0, 8, "classical: bias order in temperature")
      .integer("model.classical_sf_temperature_order", &classical_sf_temperature_order, 0, 6, "classical: scale-factor order in temperature")
      .integer("model.classical_sf_rate_order", &classical_sf_rate_order, 0, 10, "classical: scale-factor order in rate")
      .integer("model.hybrid_sf_temperature_order", &hybrid_sf_temperature_order, 0, 6, "hybrid: physics scale factor w dT^i u^j, i up to this")
      .integer("model.hybrid_sf_rate_order", &hybrid_sf_rate_order, 0, 8, "hybrid: ... and j up to this")
      .real("model.network_prior_scale", &network_prior_scale, 0.0, 1e6,
            "hybrid: the network's prior sd as a multiple of what the physics leaves of the sensor's error", true)
      .text("model.network", &network, "hybrid: the network predictions are made with: evidence (as the calibration would choose it along the trajectory) or dictionary")
      .text("model.network_prior", &network_prior, "hybrid: the dictionary's prior in the objective: residual (one scale over the domain) or evidence (alpha by the expected evidence on each candidate)")
      .integer("model.network_nodes", &network_nodes, 1, 2000, "hybrid, network=evidence: centres among the trajectory's inputs")
      .text("model.network_widths", &network_widths, "hybrid, network=evidence: the network's widths RATE,TEMPERATURE (normalised as the calibration's) given, not searched")
      .real("model.network_prior_sd_dph", &network_prior_sd_dph, 0.0, 1e6, "hybrid, network=evidence: the weights' prior sd given (0: by the expected evidence)");
}

namespace {

std::vector<double> parse_list(const std::string& text, const char* key) {
  std::vector<double> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0') fail("option '", key, "': '", item, "' is not a number");
    out.push_back(v);
  }
  return out;
}

}  // namespace

std::string ModelOptions::validate() const {
  if (network != "evidence" && network != "dictionary") return "option 'model.network' must be evidence or dictionary";
  if (network_prior != "residual" && network_prior != "evidence") return "option 'model.network_prior' must be residual or evidence";
  if (!network_widths.empty()) {
    const auto w = parse_list(network_widths, "model.network_widths");
    if (w.size() != 2 || !(w[0] > 0 && w[1] > 0)) return "option 'model.network_widths' must be two positive widths: RATE,TEMPERATURE";
  }
  const auto rates = parse_list(grid_rates_dps, "model.grid_rates_dps");
  for (std::size_t i = 1; i < rates.size(); ++i) {
    if (!(rates[i] > rates[i - 1])) return "option 'model.grid_rates_dps' must be strictly increasing";
  }
  if (rates.size() < 2) return "option 'model.grid_rates_dps' needs at least two rates";
  if (!grid_temperatures_c.empty()) {
    const auto temps = parse_list(grid_temperatures_c, "model.grid_temperatures_c");
    for (std::size_t i = 1; i < temps.size(); ++i) {
      if (!(temps[i] > temps[i - 1])) return "option 'model.grid_temperatures_c' must be strictly increasing";
    }
    if (temps.size() < 2) return "option 'model.grid_temperatures_c' needs at least two temperatures";
  }
  return "";
}

Eigen::RowVectorXd ModelOptions::given_network_widths() const {
  if (network_widths.empty()) return {};
  const auto w = parse_list(network_widths, "model.network_widths");
  return Eigen::Map<const Eigen::RowVectorXd>(w.data(), static_cast<Eigen::Index>(w.size()));
}

namespace {

// Classical and grey-box: named physics terms (model/physics_terms.h) plus, for the grey-box, the
// linearised thermal-lag column.
class PhysicsRegressor : public Regressor {
 public:
  PhysicsRegressor(ModelFamily family, std::vector<Term> terms, TermScaling scaling, double coil_tau_s,
                   std::optional<GyroErrorModel> lag_nominal)
      : family_(family), terms_(std::move(terms)), scaling_(scaling), tau_(coil_tau_s), lag_(std::move(lag_nominal)) {}

  ModelFamily family() const override { return family_; }
  std::vector<std::string> names() const override {
    std::vector<std::string> out;
    for (const auto& t : terms_) {
      for (auto& n : t.column_names()) out.push_back(n);
    }
    if (lag_) out.emplace_back("thermal_lag");
    return out;
  }
  std::vector<int> groups() const override {
    std::vector<int> out;
    int g = 0;
    for (const auto& t : terms_) out.insert(out.end(), static_cast<std::size_t>(t.size()), g++);
    if (lag_) out.push_back(g);
    return out;
  }
  std::vector<std::pair<std::string, Eigen::Index>> effects() const override {
    std::vector<std::pair<std::string, Eigen::Index>> out;
    Eigen::Index at = 0;
    for (const auto& t : terms_) {
      if (t.kind() == "shupe" || t.kind() == "hysteresis") out.emplace_back(std::string(t.kind()), at);
      at += t.size();
    }
    if (lag_) out.emplace_back("thermal_lag", at);
    return out;
  }

  Eigen::MatrixXd columns(const Signals& s) const override {
    const CoilTemperature coil = coil_temperature(s, tau_);
    const Eigen::MatrixXd terms = design_matrix(terms_, s, coil, scaling_);
    if (!lag_) return terms;
    Eigen::MatrixXd a(s.size(), terms.cols() + 1);
    a.leftCols(terms.cols()) = terms;
    // d error / d tau = (d error / d T_coil) (d T_coil / d tau), both by central differences (tau >= 0).
    const double dtau = std::max(1.0, 0.01 * tau_);
    const double lo = std::max(0.0, tau_ - dtau), hi = tau_ + dtau;
    const Eigen::VectorXd dcoil = (coil_temperature(s, hi).temp_c - coil_temperature(s, lo).temp_c) / (hi - lo);
    for (Eigen::Index i = 0; i < s.size(); ++i) {
      GyroEnvironment env;
      env.temp_rate_c_per_s = coil.rate_c_per_s(i);
      const double w = s.rate(i), step = 0.05;
      env.temp_c = coil.temp_c(i) + step;
      const double up = lag_->forward(w, env);
      env.temp_c = coil.temp_c(i) - step;
      const double down = lag_->forward(w, env);
      a(i, terms.cols()) = (up - down) / (2.0 * step) * dcoil(i);
    }
    return a;
  }

 private:
  ModelFamily family_;
  std::vector<Term> terms_;
  TermScaling scaling_;
  double tau_;
  std::optional<GyroErrorModel> lag_;
};

// Fixed dictionary of Gaussian nodes on a grid over the domain, plus a constant.
class RbfDictionary : public Regressor {
 public:
  RbfDictionary(const ModelOptions& o, const Domain& d) : domain_(d) {
    const int nt = o.rbf_temperature_nodes, nw = o.rbf_rate_nodes;
    centres_.resize(nt * nw, 2);
    for (int i = 0; i < nt; ++i)
      for (int j = 0; j < nw; ++j) centres_.row(i * nw + j) << -1.0 + 2.0 * j / (nw - 1), -1.0 + 2.0 * i / (nt - 1);
    width_ = Eigen::RowVectorXd::Constant(2, o.rbf_width);
  }
  ModelFamily family() const override { return ModelFamily::rbf; }
  std::vector<std::string> names() const override {
    std::vector<std::string> out;
    const double mid = 0.5 * (domain_.temp_min_c + domain_.temp_max_c), half = 0.5 * (domain_.temp_max_c - domain_.temp_min_c);
    for (Eigen::Index j = 0; j < centres_.rows(); ++j) {
      out.push_back(str_cat("node(", format_significant(mid + half * centres_(j, 1), 3), " C, ",
                            format_significant(units::radps_to_dps(domain_.rate_max_radps * centres_(j, 0)), 3), " dps)"));
    }
    out.emplace_back("bias");
    return out;
  }
  std::vector<int> groups() const override {
    std::vector<int> out(static_cast<std::size_t>(centres_.rows()), 0);
    out.push_back(1);
    return out;
  }
  Eigen::MatrixXd columns(const Signals& s) const override {
    const double mid = 0.5 * (domain_.temp_min_c + domain_.temp_max_c), half = 0.5 * (domain_.temp_max_c - domain_.temp_min_c);
    Eigen::MatrixXd x(s.size(), 2);
    x.col(0) = s.rate / domain_.rate_max_radps;
    x.col(1) = (s.temp_c.array() - mid) / half;
    Eigen::MatrixXd a(s.size(), centres_.rows() + 1);
    a.leftCols(centres_.rows()) = gaussian_columns(x, centres_, width_);
    a.col(centres_.rows()).setOnes();
    return a;
  }

 private:
  Domain domain_;
  Eigen::MatrixXd centres_;  // normalised (w, T)
  Eigen::RowVectorXd width_;
};

// The network the calibration would fit along one trajectory (evidence_network.h): its nodes, no constant.
class NetworkRegressor : public Regressor {
 public:
  explicit NetworkRegressor(NetworkNodes nodes) : nodes_(std::move(nodes)) {}
  ModelFamily family() const override { return ModelFamily::rbf; }
  std::vector<std::string> names() const override {
    std::vector<std::string> out;
    for (Eigen::Index j = 0; j < nodes_.centres.rows(); ++j) {
      out.push_back(str_cat("node(", format_significant(nodes_.offset(1) + nodes_.scale(1) * nodes_.centres(j, 1), 3), " C, ",
                            format_significant(units::radps_to_dps(nodes_.offset(0) + nodes_.scale(0) * nodes_.centres(j, 0)), 3), " dps)"));
    }
    return out;
  }
  std::vector<int> groups() const override { return std::vector<int>(static_cast<std::size_t>(nodes_.centres.rows()), 0); }
  Eigen::MatrixXd columns(const Signals& s) const override { return nodes_.columns(s); }

 private:
  NetworkNodes nodes_;
};

// The hybrid: physics columns (flat prior) then the network's nodes - the dictionary's without its constant
// (the physics has the bias), or the nodes the calibration would fit - one group with a learned prior.
class HybridRegressor : public Regressor {
 public:
  HybridRegressor(std::unique_ptr<Regressor> physics, std::unique_ptr<Regressor> rbf, bool rbf_has_constant)
      : physics_(std::move(physics)), rbf_(std::move(rbf)), nodes_(rbf_->size() - (rbf_has_constant ? 1 : 0)) {}
  ModelFamily family() const override { return ModelFamily::hybrid; }
  std::vector<std::string> names() const override {
    std::vector<std::string> out = physics_->names();
    const std::vector<std::string> nodes = rbf_->names();
    out.insert(out.end(), nodes.begin(), nodes.begin() + nodes_);
    return out;
  }
  std::vector<int> groups() const override {
    std::vector<int> out = physics_->groups();
    const int g = out.empty() ? 0 : *std::max_element(out.begin(), out.end()) + 1;
    out.insert(out.end(), static_cast<std::size_t>(nodes_), g);
    return out;
  }
  std::vector<int> residual_groups() const override { return {groups().back()}; }
  Eigen::MatrixXd columns(const Signals& s) const override {
    const Eigen::MatrixXd p = physics_->columns(s);
    Eigen::MatrixXd a(s.size(), p.cols() + nodes_);
    a.leftCols(p.cols()) = p;
    a.rightCols(nodes_) = rbf_->columns(s).leftCols(nodes_);
    return a;
  }

 private:
  std::unique_ptr<Regressor> physics_, rbf_;
  Eigen::Index nodes_;
};

std::vector<int> orders(int from, int to) {
  std::vector<int> out;
  for (int k = from; k <= to; ++k) out.push_back(k);
  return out;
}

}  // namespace

TermScaling domain_scaling(const Domain& d) {
  TermScaling s;
  s.t_ref_c = 0.5 * (d.temp_min_c + d.temp_max_c);
  s.t_scale_c = std::max(1.0, 0.5 * (d.temp_max_c - d.temp_min_c));
  s.rate_scale_radps = d.rate_max_radps;
  return s;
}

SurfaceGrid greybox_grid(const ModelOptions& o, const Domain& d) {
  SurfaceGrid g;
  if (!o.grid_temperatures_c.empty()) {
    g.temperatures_c = parse_list(o.grid_temperatures_c, "model.grid_temperatures_c");
  } else {
    for (int i = 0; i < o.grid_temperatures; ++i) {
      g.temperatures_c.push_back(d.temp_min_c + (d.temp_max_c - d.temp_min_c) * i / (o.grid_temperatures - 1));
    }
  }
  const double limit = units::radps_to_dps(d.rate_max_radps) * (1.0 + 1e-9);
  for (double r : parse_list(o.grid_rates_dps, "model.grid_rates_dps")) {
    if (std::abs(r) <= limit) g.rates_dps.push_back(r);
  }
  if (g.rates_dps.size() < 2) fail("design model: fewer than two grid rates within the domain's +-", limit, " deg/s");
  return g;
}

GreyboxOptions greybox_options(const ModelOptions& o, const Domain& d) {
  const SurfaceGrid grid = greybox_grid(o, d);
  GreyboxOptions g;
  g.bias_order = o.bias_order;
  g.surface_temperatures_c = grid.temperatures_c;
  g.surface_rates_dps = grid.rates_dps;
  g.shupe = o.shupe;
  return g;
}

// The hybrid's noise options for the sensor's noise: noise=given with its white density, Gauss-Markov process
// and rate random walk (solvers/bayes/bayes_fit.h units), so that the calibration whitens as the prediction
// did. noise=auto estimates a model from the recording instead: on experiments/trajectory_design's second
// sensor (Gauss-Markov 3 deg/h, tau 600 s; random walk 0.5 deg/h/rt(h)) it took the slow drift for a random
// walk of 4-15 deg/h/rt(h), discarded the low-frequency information the bias needs, and left the criterion of
// fit up to 9x over the prediction (the 8-h soak); given the sensor's model, the soak and the dual scan came
// within 1.4x of theirs.
namespace {
std::string hybrid_noise_options(const NoiseSpec& n, std::string* why_auto) {
  if (n.markov.size() > 1) {
    *why_auto = str_cat("the sensor's noise has ", n.markov.size(), " Gauss-Markov processes (bias instability's included); the hybrid takes one");
  } else if (!(n.white_psd > 0)) {
    *why_auto = "the sensor's noise has no white part; the hybrid's given noise needs one";
  }
  if (!why_auto->empty()) return "noise: auto";
  std::string s = "noise: given, given_white_dph_at_1hz: " + format_number(units::radps_to_dph(std::sqrt(n.white_psd)));
  if (n.rrw_psd > 0) s += ", given_rrw_dph_rt_h: " + format_number(units::rad_s_rt_s_to_dph_rt_h(std::sqrt(n.rrw_psd)));
  if (!n.markov.empty()) {
    s += ", given_gm_sigma_dph: " + format_number(units::radps_to_dph(n.markov[0].sigma_radps)) + ", given_gm_tau_s: " + format_number(n.markov[0].tau_s);
  }
  return s;
}
}  // namespace

std::string calibration_yaml(ModelFamily family, const ModelOptions& o, const Domain& d, const NoiseSpec& noise) {
  std::ostringstream out;
  const bool lot = family == ModelFamily::greybox && o.calibration_prior;
  out << "# The calibration this design assumed:\n";
  if (lot) {  // the lot fixes the structure below (calibrate takes no --config beside --prior)
    out << "#   gyrosid calibrate --recording rec.csv --prior " << o.calibration_prior->source << " --out model.json\n";
  } else {
    out << "#   gyrosid calibrate --config calibration.yaml --recording rec.csv --out model.json\n";
  }
  switch (family) {
    case ModelFamily::hybrid: {
      std::string why_auto;
      const std::string noise_options = hybrid_noise_options(noise, &why_auto);
      out << "# (the design's objective used a fixed dictionary of Gaussian nodes as a proxy for the network)\n"
          << (why_auto.empty() ? "# noise: the sensor config's noise model, with which the prediction was made\n"
                               : "# noise: estimated from the recording (" + why_auto + "): the prediction assumed the sensor config's\n")
          << "model: hybrid\noptions: {" << noise_options << ", bias_order: " << o.bias_order << ", sf_temperature_order: "
          << o.hybrid_sf_temperature_order << ", sf_rate_order: " << o.hybrid_sf_rate_order << "}\n";
      break;
    }
    case ModelFamily::rbf:
      out << "# (the design's objective used a fixed dictionary of Gaussian nodes as a proxy for this network)\n"
          << "model: rbf\nsolver: ols\noptions: {criterion: bic, width: " << format_number(o.rbf_width) << ", reestimate_lambda: true}\n";
      break;
    case ModelFamily::classical:
      out << "model: classical\noptions: {bias_order: " << o.classical_bias_order << ", sf_temperature_order: "
          << o.classical_sf_temperature_order << ", sf_rate_order: " << o.classical_sf_rate_order << "}\n";
      break;
    case ModelFamily::greybox: {
      const SurfaceGrid g = greybox_grid(o, d);
      out << "model: greybox\noptions:\n  bias_order: " << o.bias_order << "\n  surface_temperatures_c: \"" << format_numbers(g.temperatures_c, ",")
          << "\"\n  surface_rates_dps: \"" << format_numbers(g.rates_dps, ",") << "\"\n  shupe: " << (o.shupe ? "true" : "false")
          << "\n  thermal_lag: " << (o.thermal_lag ? "true" : "false") << "\n";
      if (o.hysteresis) out << "# (hysteresis: fit with gyrosid explain; the grey-box fit has no hysteresis term)\n";
      break;
    }
  }
  return out.str();
}

std::unique_ptr<Regressor> make_regressor(ModelFamily family, const ModelOptions& o, const Domain& d,
                                          const GyroErrorModel& nominal, double coil_tau_s, const NetworkNodes* network) {
  if (auto p = o.validate(); !p.empty()) fail("design model: ", p);
  if (auto p = d.validate(); !p.empty()) fail("design: ", p);
  switch (family) {
    case ModelFamily::rbf: return std::make_unique<RbfDictionary>(o, d);
    case ModelFamily::classical: {
      // ClassicalModel (model/classical_model.h): b(T) + (s_T(T) + s_w(w)) w.
      std::vector<Term> terms{bias_term()};
      if (o.classical_bias_order > 0) terms.push_back(temperature_polynomial(orders(1, o.classical_bias_order)));
      ScaleFactorPolynomial::Orders sf;
      for (int i = 1; i <= o.classical_sf_temperature_order; ++i) sf.push_back({i, 0});
      for (int j = 0; j <= o.classical_sf_rate_order; ++j) sf.push_back({0, j});
      terms.push_back(scale_factor_polynomial(sf));
      return std::make_unique<PhysicsRegressor>(family, terms, domain_scaling(d), 0.0, std::nullopt);
    }
    case ModelFamily::hybrid: {
      // HybridOptions::terms (solvers/bayes/hybrid_fit.h): b + b(T) + w dT^i u^j.
      std::vector<Term> terms{bias_term()};
      if (o.bias_order > 0) terms.push_back(temperature_polynomial(orders(1, o.bias_order)));
      ScaleFactorPolynomial::Orders sf;
      for (int i = 0; i <= o.hybrid_sf_temperature_order; ++i)
        for (int j = 0; j <= o.hybrid_sf_rate_order; ++j) sf.push_back({i, j});
      terms.push_back(scale_factor_polynomial(sf));
      auto physics = std::make_unique<PhysicsRegressor>(family, terms, domain_scaling(d), 0.0, std::nullopt);
      if (network) return std::make_unique<HybridRegressor>(std::move(physics), std::make_unique<NetworkRegressor>(*network), false);
      return std::make_unique<HybridRegressor>(std::move(physics), std::make_unique<RbfDictionary>(o, d), true);
    }
    case ModelFamily::greybox: {
      // The grey-box fit's own structure (model/greybox_fit.h) with the grid over the domain, plus hysteresis.
      std::vector<Term> terms = greybox_terms(greybox_options(o, d));
      if (o.hysteresis) terms.push_back(hysteresis_term());
      return std::make_unique<PhysicsRegressor>(family, terms, domain_scaling(d), coil_tau_s,
                                                o.thermal_lag ? std::optional<GyroErrorModel>(nominal) : std::nullopt);
    }
  }
  fail("design: unknown model family");
}

}  // namespace gyrosid::design
