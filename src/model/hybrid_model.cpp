#include "model/hybrid_model.h"

#include "core/error.h"
#include "core/units.h"
#include "model/explained_model.h"
#include "model/terms/term_kinds.h"

namespace gyrosid {

bool hybrid_supports(const Term& term) { return term->memory() == TermMemory::none && term->channels().empty(); }

HybridModel::HybridModel(TermScaling scaling, std::vector<Term> terms, Eigen::VectorXd coefficients, RbfNetwork rbf,
                         std::optional<WeightPosterior> posterior)
    : CalibrationModel(default_features(), ModelTarget::error),
      scaling_(scaling),
      terms_(std::move(terms)),
      coefficients_(std::move(coefficients)),
      rbf_(std::move(rbf)),
      posterior_(std::move(posterior)) {
  Eigen::Index cols = 0;
  for (const auto& t : terms_) {
    if (!hybrid_supports(t)) fail("hybrid model: the term '", t.kind(), "' is not a static physics term");
    std::optional<SplineSurface> surface;
    if (const auto* grid = t.as<ScaleFactorSurface>()) {
      const auto nt = static_cast<Eigen::Index>(grid->temps_c().size()), nw = static_cast<Eigen::Index>(grid->rates_dps().size());
      if (cols + nt * nw <= coefficients_.size()) {
        // Column (i, j) is the surface through a unit value at node (i, j), stored row-major (physics_terms.cpp).
        const Eigen::MatrixXd values = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
            coefficients_.data() + cols, nt, nw);
        surface = SplineSurface(grid->temps_c(), grid->rates_dps(), values, OutsideGridPolicy::clamp);
      }
    }
    surfaces_.push_back(std::move(surface));
    cols += t.size();
  }
  if (cols != coefficients_.size()) fail("hybrid model: ", coefficients_.size(), " coefficients for ", cols, " term columns");
  if (rbf_.dimension() != 2) fail("hybrid model: the RBF part takes (rate, temperature)");
  if (posterior_ && posterior_->size() != rbf_.nodes() + cols) {
    fail("hybrid model: posterior of ", posterior_->size(), " weights for ", rbf_.nodes(), " nodes and ", cols, " coefficients");
  }
}

Eigen::MatrixXd HybridModel::physics_columns(const Eigen::VectorXd& w, const Eigen::VectorXd& temp_c) const {
  Signals s;
  s.t_s.assign(static_cast<std::size_t>(w.size()), 0.0);
  s.rate = w;
  s.temp_c = temp_c;
  const CoilTemperature coil{temp_c, Eigen::VectorXd::Zero(w.size())};  // steady state: coil = probe
  return design_matrix(terms_, s, coil, scaling_);
}

double HybridModel::physics_at(double w, double temp_c) const {
  double e = 0.0;
  Eigen::Index at = 0;
  for (std::size_t k = 0; k < terms_.size(); ++k) {
    const Term& t = terms_[k];
    if (surfaces_[k]) {
      e += w * (*surfaces_[k])(temp_c, units::radps_to_dps(w)).value;
    } else {
      Signals s;
      s.t_s = {0.0};
      s.rate = Eigen::VectorXd::Constant(1, w);
      s.temp_c = Eigen::VectorXd::Constant(1, temp_c);
      const CoilTemperature coil{s.temp_c, Eigen::VectorXd::Zero(1)};
      e += (term_columns(t, s, coil, scaling_).row(0) * coefficients_.segment(at, t.size()))(0);
    }
    at += t.size();
  }
  return e;
}

double HybridModel::error_at(double w, double temp_c) const {
  const double x[2] = {w, temp_c};
  return physics_at(w, temp_c) + rbf_.predict(x);
}

double HybridModel::true_rate(const double* x) const {
  double e = 0.0;
  for (int k = 0; k < ExplainedModel::kInversionSteps; ++k) e = error_at(x[0] - e, x[1]);
  return x[0] - e;
}

double HybridModel::predict(const double* x) const {
  double e = 0.0;
  for (int k = 0; k < ExplainedModel::kInversionSteps; ++k) e = error_at(x[0] - e, x[1]);
  return e;
}

Eigen::MatrixXd HybridModel::regressors(const Eigen::MatrixXd& x) const {
  if (!posterior_) return CalibrationModel::regressors(x);
  Eigen::MatrixXd wt(x.rows(), 2);
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const double xi[2] = {x(i, 0), x(i, 1)};
    wt(i, 0) = true_rate(xi), wt(i, 1) = x(i, 1);
  }
  const Eigen::Index m = rbf_.nodes();
  Eigen::MatrixXd h(x.rows(), m + coefficients_.size());
  h.leftCols(m) = rbf_.basis(rbf_.normalizer.apply(wt));
  h.rightCols(coefficients_.size()) = physics_columns(wt.col(0), wt.col(1));
  return h;
}

nlohmann::json HybridModel::parameters_json() const {
  nlohmann::json terms = nlohmann::json::array();
  for (const auto& t : terms_) terms.push_back(t.to_json());
  nlohmann::json j = {{"scaling", scaling_.to_json()},
                      {"terms", terms},
                      {"coefficients", std::vector<double>(coefficients_.data(), coefficients_.data() + coefficients_.size())},
                      {"rbf", rbf_.parameters_json()}};
  if (posterior_) j["posterior"] = posterior_->to_json();
  return j;
}

std::unique_ptr<HybridModel> HybridModel::from_json(const nlohmann::json& j, std::vector<std::string> features, ModelTarget target,
                                                    const std::string& source) {
  if (features != default_features() || target != ModelTarget::error) fail(source, ": a hybrid model maps (measured_rate, temperature) to the error");
  std::vector<Term> terms;
  for (const auto& t : j.at("terms")) terms.push_back(Term::from_json(t));
  const auto c = j.at("coefficients").get<std::vector<double>>();
  auto rbf = RbfNetwork::from_json(j.at("rbf"), default_features(), ModelTarget::error);
  Eigen::Index cols = 0;
  for (const auto& t : terms) cols += t.size();
  std::optional<WeightPosterior> posterior;
  if (j.contains("posterior")) posterior = WeightPosterior::from_json(j["posterior"], rbf->nodes() + cols, source);
  return std::make_unique<HybridModel>(TermScaling::from_json(j.at("scaling")), std::move(terms),
                                       Eigen::Map<const Eigen::VectorXd>(c.data(), static_cast<Eigen::Index>(c.size())), std::move(*rbf),
                                       std::move(posterior));
}

void HybridModel::export_c_body(CExport& out) const {
  // The physics part through the explained model's exporter (its static <prefix>_physics_error(x, w)), the
  // RBF part through the network's (<prefix>_rbf_predict(x)); here the sum at the inverted true rate.
  CExport physics, rbf;
  physics.prefix = out.prefix + "_physics";
  rbf.prefix = out.prefix + "_rbf";
  ExplainedModel(scaling_, 0.0, terms_, coefficients_).export_c_body(physics);
  rbf_.export_c_body(rbf);
  const std::string p = out.prefix;
  out.source << physics.source.str() << rbf.source.str() << "\n/* e(w, T) = physics + RBF at the true rate w, which solves w = m - e(w, T). */\n"
             << "double " << p << "_predict(const double* x) {\n"
             << "  double e = 0.0, xw[2];\n  int k;\n"
             << "  for (k = 0; k < " << ExplainedModel::kInversionSteps << "; ++k) {\n"
             << "    xw[0] = x[0] - e;\n    xw[1] = x[1];\n"
             << "    e = " << physics.prefix << "_error(x, xw[0]) + " << rbf.prefix << "_predict(xw);\n"
             << "  }\n  return e;\n}\n";
}

}  // namespace gyrosid
