// A toy model kind added from the test binaries alone, proving the extension point register_model_kind
// (solvers/calibrate.h): a kind is a CalibrationModel (prediction, JSON, C export), an options struct, a
// fitter, and one registration call - its loader, help, fitter and sample for the suites.
// The property suites then run over it like over the library's own: test_model_properties.cpp over the
// kinds (JSON, C export compiled, compensation), test_fitter_properties.cpp over the fitters (help, options,
// a fit to the dual scan that removes the error and loads back).
//
// poly2d: the rate error as a polynomial of total degree D in u = w / w_s and v = (T - T_0) / T_s,
// e(w, T) = sum over i + j <= D of c_k u^i v^j (k in order of i + j, then of j), the coefficients by
// column-pivoted QR on the scaled columns (no normal equations).
#include <Eigen/QR>

#include <cmath>

#include "core/error.h"
#include "model/fit_notes.h"
#include "model/model_kinds.h"
#include "model_samples.h"
#include "solvers/calibrate.h"

namespace gyrosid {
namespace {

class Poly2dModel : public CalibrationModel {
 public:
  Poly2dModel(int degree, double rate_scale, double t_ref, double t_scale, Eigen::VectorXd c)
      : CalibrationModel(default_features(), ModelTarget::error), degree_(degree), rate_scale_(rate_scale), t_ref_(t_ref), t_scale_(t_scale),
        c_(std::move(c)) {
    if (c_.size() != columns(degree_)) fail("poly2d: degree ", degree_, " needs ", columns(degree_), " coefficients, not ", c_.size());
  }

  static Eigen::Index columns(int degree) { return (degree + 1) * (degree + 2) / 2; }
  // The row of monomials u^i v^j at (w, T), in the coefficients' order.
  static Eigen::RowVectorXd monomials(int degree, double u, double v) {
    Eigen::RowVectorXd row(columns(degree));
    Eigen::Index k = 0;
    for (int total = 0; total <= degree; ++total)
      for (int j = 0; j <= total; ++j) row(k++) = std::pow(u, total - j) * std::pow(v, j);
    return row;
  }

  std::string_view kind() const override { return "poly2d"; }
  using CalibrationModel::predict;
  double predict(const double* x) const override { return monomials(degree_, x[0] / rate_scale_, (x[1] - t_ref_) / t_scale_).dot(c_); }
  nlohmann::json parameters_json() const override {
    return {{"degree", degree_}, {"rate_scale_radps", rate_scale_}, {"t_ref_c", t_ref_}, {"t_scale_c", t_scale_},
            {"coefficients", std::vector<double>(c_.data(), c_.data() + c_.size())}};
  }
  void export_c_body(CExport& out) const override {
    out.array("c", c_.data(), static_cast<std::size_t>(c_.size()));
    const std::string p = out.prefix;
    out.source << std::hexfloat << "\n/* poly2d: sum over i + j <= " << degree_ << " of c_k u^i v^j. */\n"
               << "double " << p << "_predict(const double* x) {\n"
               << "  const double u = x[0] / " << rate_scale_ << ", v = (x[1] - " << t_ref_ << ") / " << t_scale_ << ";\n"
               << "  double e = 0.0;\n  int total, j, k = 0;\n"
               << "  for (total = 0; total <= " << degree_ << "; ++total)\n"
               << "    for (j = 0; j <= total; ++j) e += " << p << "_c[k++] * pow(u, total - j) * pow(v, j);\n"
               << "  return e;\n}\n"
               << std::defaultfloat;
  }
  static std::unique_ptr<CalibrationModel> from_json(const ModelFile& f) {
    const nlohmann::json& p = f.parameters();
    const auto c = p.at("coefficients").get<std::vector<double>>();
    return std::make_unique<Poly2dModel>(p.at("degree").get<int>(), p.at("rate_scale_radps").get<double>(), p.at("t_ref_c").get<double>(),
                                         p.at("t_scale_c").get<double>(), Eigen::Map<const Eigen::VectorXd>(c.data(), static_cast<Eigen::Index>(c.size())));
  }

 private:
  int degree_;
  double rate_scale_, t_ref_, t_scale_;
  Eigen::VectorXd c_;
};

struct Poly2dOptions {
  int degree = 6;
  OptionTable table() {
    OptionTable t("poly2d");
    t.integer("degree", &degree, 1, 10, "total degree of the polynomial in (w, T)");
    return t;
  }
  std::string validate() const { return ""; }
};

class Poly2dFitter : public GyroModelFitter {
 public:
  explicit Poly2dFitter(Poly2dOptions o) : o_(o) {}
  std::vector<std::string> default_features() const override { return gyrosid::default_features(); }
  std::unique_ptr<CalibrationModel> fit(const Recording& recording, const std::vector<std::string>& features, SolveSummary& summary) override {
    const Dataset d = make_dataset(recording, features, ModelTarget::error);
    const double rate_scale = std::max(d.x.col(0).cwiseAbs().maxCoeff(), 1e-9);
    const double t_lo = d.x.col(1).minCoeff(), t_hi = d.x.col(1).maxCoeff();
    const double t_ref = 0.5 * (t_lo + t_hi), t_scale = std::max(0.5 * (t_hi - t_lo), 1.0);
    Eigen::MatrixXd a(d.size(), Poly2dModel::columns(o_.degree));
    for (Eigen::Index i = 0; i < d.size(); ++i) a.row(i) = Poly2dModel::monomials(o_.degree, d.x(i, 0) / rate_scale, (d.x(i, 1) - t_ref) / t_scale);
    Eigen::VectorXd c;
    summary = timed_solve("poly2d", [&](SolveMonitor& monitor) {
      c = a.colPivHouseholderQr().solve(d.target);
      monitor.evaluation();
      monitor.iteration(0.5 * (a * c - d.target).squaredNorm());
      SolveOutcome outcome{Termination::converged, "linear least squares by column-pivoted QR", nlohmann::json::object()};
      FitNotes notes;
      notes.parameters = static_cast<int>(c.size());
      write_fit_notes(notes, outcome.details);
      return outcome;
    });
    return std::make_unique<Poly2dModel>(o_.degree, rate_scale, t_ref, t_scale, c);
  }

 private:
  Poly2dOptions o_;
};

// A sample built from planted coefficients (no fit), for the kinds' suite.
std::unique_ptr<CalibrationModel> sample_poly2d() {
  Eigen::VectorXd c(Poly2dModel::columns(3));
  c << -7e-5, 2e-4, 1e-5, -3e-6, 4e-6, 2e-7, 5e-7, -1e-7, 3e-8, -2e-8;
  return std::make_unique<Poly2dModel>(3, 1.7, 21.5, 39.0, c);
}

// The registration line, run before gtest lists or instantiates the tests.
const bool poly2d_registered = [] {
  register_model_kind({"poly2d", "toy: a polynomial of total degree D in (w, T)", Poly2dModel::from_json,
                       [] { return "poly2d - toy: a polynomial of total degree D in (w, T):\n" + Poly2dOptions{}.table().help(); },
                       [](const CalibrationRequest& r) -> std::unique_ptr<ModelFitter> {
                         Poly2dOptions o;
                         o.table().apply(r.options);
                         return std::make_unique<Poly2dFitter>(o);
                       },
                       sample_poly2d});
  return true;
}();

}  // namespace
}  // namespace gyrosid
