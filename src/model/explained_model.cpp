#include "model/explained_model.h"

#include <algorithm>

#include "core/error.h"

namespace gyrosid {

std::vector<std::string> explained_features(const std::vector<Term>& terms, const CalibrationModel* prior) {
  std::vector<std::string> f{"measured_rate", "temperature"};
  auto add = [&](const std::string& name) {
    if (std::find(f.begin(), f.end(), name) == f.end()) f.push_back(name);
  };
  for (const auto& t : terms) {
    for (const auto& c : t->channels()) add(c);
  }
  if (prior) {
    for (const auto& c : prior->features()) add(c);
  }
  return f;
}

ExplainedModel::ExplainedModel(TermScaling scaling, double lag_tau_s, std::vector<Term> terms, Eigen::VectorXd coefficients,
                               std::unique_ptr<CalibrationModel> prior, double prior_gain)
    : CalibrationModel(explained_features(terms, prior.get()), ModelTarget::error),
      scaling_(scaling),
      lag_tau_s_(lag_tau_s),
      terms_(std::move(terms)),
      coefficients_(std::move(coefficients)),
      prior_(std::move(prior)),
      prior_gain_(prior_gain) {
  const int cols = total_columns(terms_);
  if (cols != coefficients_.size()) fail("explained model: ", coefficients_.size(), " coefficients for ", cols, " term columns");
  if (lag_tau_s_ < 0) fail("explained model: negative thermal lag");
  if (prior_ && prior_->target() != ModelTarget::error) fail("explained model: the prior model must predict the rate error");
}

Signals ExplainedModel::signals_of(const Dataset& data) const {
  Signals s;
  s.t_s = data.t_s;
  if (s.t_s.size() != static_cast<std::size_t>(data.size())) {
    s.t_s.resize(static_cast<std::size_t>(data.size()));
    for (std::size_t i = 0; i < s.t_s.size(); ++i) s.t_s[i] = static_cast<double>(i);
  }
  for (std::size_t f = 0; f < data.features.size(); ++f) {
    const auto col = data.x.col(static_cast<Eigen::Index>(f));
    if (data.features[f] == "measured_rate") s.rate = col;
    else if (data.features[f] == "temperature") s.temp_c = col;
    else s.channels[data.features[f]] = col;
  }
  if (s.rate.size() != data.size() || s.temp_c.size() != data.size()) {
    fail("explained model: the data need measured_rate and temperature");
  }
  return s;
}

Dataset ExplainedModel::prior_dataset(const Dataset& data) const {
  Dataset d = data;
  d.features = prior_->features();
  d.x.resize(data.size(), static_cast<Eigen::Index>(d.features.size()));
  for (std::size_t f = 0; f < d.features.size(); ++f) {
    const auto it = std::find(data.features.begin(), data.features.end(), d.features[f]);
    if (it == data.features.end()) fail("explained model: the prior model's input '", d.features[f], "' is missing");
    d.x.col(static_cast<Eigen::Index>(f)) = data.x.col(static_cast<Eigen::Index>(it - data.features.begin()));
  }
  return d;
}

// The terms describe the error as a function of the true rate; the model sees the measured one. The true
// rate solves w = m - e(w) - g prior(m); fixed-point iteration converges at once for errors of ppm size.
Eigen::VectorXd ExplainedModel::predict(const Dataset& data) const {
  Signals s = signals_of(data);
  const Eigen::VectorXd measured = s.rate;
  const CoilTemperature coil = coil_temperature(s, lag_tau_s_);
  const Eigen::VectorXd offset = prior_ ? Eigen::VectorXd(prior_gain_ * prior_->predict(prior_dataset(data))) : Eigen::VectorXd::Zero(measured.size());
  Eigen::VectorXd error = offset;
  for (int iteration = 0; iteration < kInversionSteps; ++iteration) {
    s.rate = measured - error;
    error = design_matrix(terms_, s, coil, scaling_) * coefficients_ + offset;
  }
  return error;
}

double ExplainedModel::predict(const double* x) const {
  Signals s;
  s.t_s = {0.0};
  s.temp_c = Eigen::VectorXd::Constant(1, x[1]);
  for (std::size_t f = 2; f < features_.size(); ++f) s.channels[features_[f]] = Eigen::VectorXd::Constant(1, x[f]);
  const CoilTemperature coil{s.temp_c, Eigen::VectorXd::Zero(1)};
  double offset = 0.0;
  if (prior_) {
    std::vector<double> px;
    for (const auto& name : prior_->features()) {
      const auto it = std::find(features_.begin(), features_.end(), name);
      px.push_back(x[it - features_.begin()]);
    }
    offset = prior_gain_ * prior_->predict(px.data());
  }
  double error = offset;
  for (int iteration = 0; iteration < kInversionSteps; ++iteration) {
    s.rate = Eigen::VectorXd::Constant(1, x[0] - error);
    error = offset;
    Eigen::Index at = 0;
    for (const auto& t : terms_) {
      if (t->memory() == TermMemory::none) error += (term_columns(t, s, coil, scaling_).row(0) * coefficients_.segment(at, t.size()))(0);
      at += t.size();
    }
  }
  return error;
}

nlohmann::json ExplainedModel::parameters_json() const {
  nlohmann::json terms = nlohmann::json::array();
  for (const auto& t : terms_) terms.push_back(t.to_json());
  nlohmann::json j = {{"scaling", scaling_.to_json()},
                      {"lag_tau_s", lag_tau_s_},
                      {"terms", terms},
                      {"coefficients", std::vector<double>(coefficients_.data(), coefficients_.data() + coefficients_.size())},
                      {"prior_gain", prior_gain_}};
  j["prior"] = prior_ ? prior_->to_json() : nlohmann::json();
  return j;
}

std::unique_ptr<ExplainedModel> ExplainedModel::from_json(const nlohmann::json& j, const std::string& source) {
  std::vector<Term> terms;
  for (const auto& t : j.at("terms")) terms.push_back(Term::from_json(t));
  const auto c = j.at("coefficients").get<std::vector<double>>();
  std::unique_ptr<CalibrationModel> prior;
  if (j.contains("prior") && !j["prior"].is_null()) prior = model_from_json(j["prior"], source + " (prior)");
  return std::make_unique<ExplainedModel>(TermScaling::from_json(j.at("scaling")), j.at("lag_tau_s").get<double>(), std::move(terms),
                                          Eigen::Map<const Eigen::VectorXd>(c.data(), static_cast<Eigen::Index>(c.size())),
                                          std::move(prior), j.value("prior_gain", 1.0));
}

void ExplainedModel::export_c_body(CExport& out) const {
  if (prior_) fail("C export: this explained model contains a prior model; export the prior separately");
  if (lag_tau_s_ > 0) fail("C export: the thermal lag needs the temperature history; not exportable as a stateless function");
  out.array("beta", coefficients_.data(), static_cast<std::size_t>(coefficients_.size()));
  const std::string p = out.prefix;
  std::ostringstream body;
  body << std::hexfloat;
  body << "static double " << p << "_error(const double* x, double w) {\n"
       << "  const double dT = (x[1] - " << scaling_.t_ref_c << ") / " << scaling_.t_scale_c << ";\n"
       << "  const double u = w / " << scaling_.rate_scale_radps << ";\n"
       << "  double e = 0.0;\n";
  int first = 0, index = 0;
  for (const auto& t : terms_) {
    TermCode code{out, body, coefficients_.segment(first, t.size()), [&, first](int k) { return str_cat(p, "_beta[", first + k, "]"); },
                  [&](const std::string& name) {
                    const auto it = std::find(features_.begin(), features_.end(), name);
                    return str_cat("x[", it - features_.begin(), "]");
                  },
                  str_cat("t", index++, "_")};
    if (const std::string why = t->export_c(code); !why.empty()) fail("C export: ", why);
    first += t.size();
  }
  body << "  (void)u;\n  (void)dT;\n  return e;\n}\n\n"
       << "/* The terms are functions of the true rate: solve w = m - e(w) by fixed-point iteration. */\n"
       << "double " << p << "_predict(const double* x) {\n  double e = 0.0;\n  int k;\n"
       << "  for (k = 0; k < " << kInversionSteps << "; ++k) e = " << p << "_error(x, x[0] - e);\n  return e;\n}\n";
  out.source << "\n" << body.str();
}

}  // namespace gyrosid
