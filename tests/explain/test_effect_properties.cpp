// One property suite run over every registered effect (explain/effect.h), as Sophus runs one suite over
// every group: on a standard recording rich enough to test every effect, each effect proposes a candidate,
// its columns are finite, its planted parameters are recovered exactly from noise-free data, its
// parameters and its term round-trip through JSON, it describes itself and its separating experiments, and
// its term's C export (where it has one) agrees with the C++ evaluation.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/QR>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "core/random.h"
#include "core/units.h"
#include "explain/baseline.h"
#include "explain/effect.h"
#include "explain/linear_fit.h"
#include "explain/selection.h"
#include "model/terms/term_kinds.h"
#include "model/explained_model.h"
#include "report/explain_json.h"

namespace gyrosid::explain {
namespace {

namespace fs = std::filesystem;
using units::kPi;

// A triad recording (the x gyro explained) of 4 h at 1 Hz: temperature cycles -20..40 C with ramps at
// 3 C/min and plateaus, rates of both signs and several magnitudes, specific force, a magnetometer, a
// supply voltage and the other axes turning - every effect of the library is testable on it.
ExplainInput standard_input() {
  const std::size_t n = 14400;
  Recording rec("standard recording");
  std::vector<double> t(n), temp(n), wx(n), wy(n), wz(n), ax(n), ay(n), az(n), mag(n), supply(n), zero(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    t[i] = static_cast<double>(i);
    const double c = std::fmod(t[i], 3600.0);  // ramp up 1200 s, plateau 600 s, ramp down 1200 s, plateau 600 s
    temp[i] = c < 1200 ? -20 + 0.05 * c : c < 1800 ? 40 : c < 3000 ? 40 - 0.05 * (c - 1800) : -20;
    wx[i] = 80 * std::sin(2 * kPi * t[i] / 300) + 20 * std::sin(2 * kPi * t[i] / 47);
    wy[i] = 50 * std::sin(2 * kPi * t[i] / 97);
    wz[i] = 40 * std::cos(2 * kPi * t[i] / 151);
    ax[i] = units::kStandardGravity * std::sin(2 * kPi * t[i] / 1800);
    ay[i] = 0.5 * units::kStandardGravity * std::cos(2 * kPi * t[i] / 2700);
    az[i] = units::kStandardGravity * (0.8 + 0.2 * std::sin(2 * kPi * t[i] / 1100));
    mag[i] = 20 * std::cos(2 * kPi * t[i] / 700) + 5;
    supply[i] = 5 + 0.2 * std::sin(2 * kPi * t[i] / 1300);
  }
  rec.set_column("t_s", t);
  rec.set_column("ref_rate_x_dps", wx);
  rec.set_column("ref_rate_y_dps", wy);
  rec.set_column("ref_rate_z_dps", wz);
  rec.set_column("temp_c", temp);
  for (const char* g : {"gyro_x_dps", "gyro_y_dps", "gyro_z_dps"}) rec.set_column(g, zero);
  rec.set_column("accel_x_mps2", ax);
  rec.set_column("accel_y_mps2", ay);
  rec.set_column("accel_z_mps2", az);
  rec.set_column("mag_x_ut", mag);
  rec.set_column("supply_v", supply);
  InputOptions o;
  o.axis = "x";
  return load_input(rec, o);
}

const ExplainInput& input() {
  static const ExplainInput in = standard_input();
  return in;
}

const std::vector<Term>& base_terms() {
  static const std::vector<Term> base = baseline_family(BaselineForm::polynomial, input().signals);
  return base;
}

const TermScaling& scaling() {
  static const TermScaling s = TermScaling::of(input().signals);
  return s;
}

class EffectProperties : public ::testing::TestWithParam<std::string> {
 protected:
  const Effect& effect() const { return find_effect(GetParam()); }
  std::vector<Candidate> candidates() const {
    const CandidateContext context(base_terms(), 0.0, input());
    return effect().propose(context).candidates;
  }
  // Planted coefficients of the base (deg/h per column unit): a smooth error of a few deg/h.
  Eigen::VectorXd base_beta() const {
    RandomStream r(11, "base");
    Eigen::VectorXd b(total_columns(base_terms()));
    for (Eigen::Index i = 0; i < b.size(); ++i) b(i) = 3.0 * r.normal();
    return b;
  }
  double nonlinear_value(const Candidate& c) const { return c.tau_grid_s.empty() ? NAN : c.tau_grid_s[c.tau_grid_s.size() / 2]; }
};

TEST(Effects, TheLibraryHoldsEveryRegisteredEffectOnce) {
  ASSERT_EQ(effect_library().size(), effect_registry().entries().size());
  for (std::size_t i = 0; i < effect_library().size(); ++i) EXPECT_EQ(effect_library()[i]->id(), effect_registry().entries()[i].name);
  EXPECT_THAT([] { find_effect("no_such_effect"); }, ::testing::ThrowsMessage<Error>(::testing::HasSubstr("known: temperature_bias")));
}

TEST_P(EffectProperties, DescribesItselfAndItsSeparatingExperiments) {
  const Effect& e = effect();
  EXPECT_GT(e.description().size(), 40u);
  EXPECT_EQ(e.description().back(), '.');
  EXPECT_FALSE(e.parameters_help().empty());
  EXPECT_FALSE(effect_registry().at(GetParam()).help().empty());
  for (const Effect* other : effect_library()) {
    if (other == &e) continue;
    const std::string s = separating_experiment(e, *other);
    EXPECT_FALSE(s.empty());
    EXPECT_EQ(s, separating_experiment(*other, e)) << e.id() << " / " << other->id();  // each pair is written once
  }
}

TEST_P(EffectProperties, IsTestableOnTheStandardRecordingAndItsColumnsAreFinite) {
  const std::vector<Candidate> cs = candidates();
  ASSERT_FALSE(cs.empty()) << GetParam() << ": " << effect().propose(CandidateContext(base_terms(), 0.0, input())).untestable;
  const Eigen::VectorXd beta = base_beta();
  for (const Candidate& c : cs) {
    EXPECT_EQ(c.effect, &effect());
    const std::vector<double> taus = c.nonlinear == NonlinearParameter::none ? std::vector<double>{NAN} : c.tau_grid_s;
    ASSERT_FALSE(taus.empty());
    for (double tau : taus) {
      const Eigen::MatrixXd x = effect().columns(c, tau, ModelColumns{base_terms(), 0.0, beta, input().signals, scaling()});
      EXPECT_EQ(x.rows(), input().size());
      EXPECT_GE(x.cols(), 1);
      EXPECT_TRUE(x.allFinite()) << GetParam() << " at tau " << tau;
      EXPECT_GT(x.norm(), 0.0) << GetParam() << " at tau " << tau;
    }
  }
}

// Noise-free data with the effect planted (at the middle of its parameter grid): fitting the base plus the
// effect recovers the planted coefficients, hence the planted physical parameters, to round-off.
TEST_P(EffectProperties, RecoversItsPlantedParametersFromNoiseFreeData) {
  const ExplainInput& in = input();
  const Eigen::VectorXd beta_base = base_beta();
  const ModelSpec base{base_terms(), 0.0};
  for (const Candidate& c : candidates()) {
    const double tau = nonlinear_value(c);
    const ModelSpec with = with_effect(base, c, tau);
    Eigen::VectorXd beta = Eigen::VectorXd::Zero(total_columns(with.terms));
    beta.head(beta_base.size()) = beta_base;
    RandomStream r(13, GetParam());
    for (Eigen::Index i = beta_base.size(); i < beta.size(); ++i) beta(i) = 2.0 + r.uniform();
    const Eigen::VectorXd y = model_columns(with, in.signals, scaling()) * beta;
    const WhitenedFit fit = fit_whitened(model_columns(with, in.signals, scaling()), y);
    EXPECT_LT(std::sqrt(fit.rss / static_cast<double>(y.size())), 1e-9 * y.cwiseAbs().maxCoeff()) << GetParam();
    if (c.nonlinear == NonlinearParameter::coil_lag) {
      // The lag has no coefficient of its own: the base's coefficients come back at the planted lag, and the
      // lag's Gauss-Newton column at tau explains exactly the difference the lag makes.
      EXPECT_LT((fit.beta - beta).cwiseAbs().maxCoeff(), 1e-6 * beta.cwiseAbs().maxCoeff());
      const Eigen::VectorXd lagged = model_columns(with, in.signals, scaling()) * beta_base;
      const Eigen::MatrixXd column = effect().columns(c, tau, ModelColumns{base.terms, 0.0, beta_base, in.signals, scaling()});
      EXPECT_LT((model_columns(base, in.signals, scaling()) * beta_base + column - lagged).norm(), 1e-9 * lagged.norm());
      continue;
    }
    const Term& term = with.terms.back();
    const Eigen::VectorXd planted = beta.tail(term.size()), found = fit.beta.tail(term.size()), sd = Eigen::VectorXd::Zero(term.size());
    const auto truth = effect().parameters(term, planted, sd, scaling()), got = effect().parameters(term, found, sd, scaling());
    ASSERT_EQ(truth.size(), got.size());
    ASSERT_FALSE(truth.empty()) << GetParam() << " reports no physical parameter";
    for (std::size_t k = 0; k < truth.size(); ++k) {
      EXPECT_EQ(truth[k].name, got[k].name);
      EXPECT_NEAR(got[k].value, truth[k].value, 1e-6 * std::max(1.0, std::abs(truth[k].value))) << GetParam() << " " << truth[k].name;
    }
  }
}

TEST_P(EffectProperties, ItsParametersAndItsTermRoundTripThroughJson) {
  for (const Candidate& c : candidates()) {
    if (!c.term) continue;
    const Term term = c.nonlinear == NonlinearParameter::term_parameter ? c.term->with_parameter(nonlinear_value(c)) : *c.term;
    // The term: the same kind and the same columns after a JSON round trip.
    const Term back = Term::from_json(nlohmann::json::parse(term.to_json().dump()));
    EXPECT_EQ(back.kind(), term.kind());
    const CoilTemperature coil = coil_temperature(input().signals, 0.0);
    EXPECT_EQ(term_columns(back, input().signals, coil, scaling()), term_columns(term, input().signals, coil, scaling()));
    // Its physical parameters inside explain.json.
    const Eigen::VectorXd beta = Eigen::VectorXd::LinSpaced(term.size(), 0.5, 1.7), sd = Eigen::VectorXd::Constant(term.size(), 0.01);
    ExplainSummary s;
    FoundEffect found;
    found.id = GetParam(), found.description = effect().description(), found.parameters = effect().parameters(term, beta, sd, scaling());
    s.effects.push_back(found);
    const ExplainSummary read = explain_summary_from_json(nlohmann::json::parse(to_json(s).dump()));
    ASSERT_EQ(read.effects.size(), 1u);
    auto sorted = [](std::vector<PhysicalParameter> p) {
      std::sort(p.begin(), p.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
      return p;
    };
    const auto want = sorted(s.effects[0].parameters), got = sorted(read.effects[0].parameters);
    ASSERT_EQ(want.size(), got.size());
    for (std::size_t k = 0; k < want.size(); ++k) {
      EXPECT_EQ(got[k].name, want[k].name);
      EXPECT_EQ(got[k].value, want[k].value);
      EXPECT_EQ(got[k].reference, want[k].reference);
      if (!want[k].reference) {
        EXPECT_EQ(got[k].low, want[k].low);
        EXPECT_EQ(got[k].high, want[k].high);
      }
    }
  }
}

// The term's C export, compiled, against the explained model's C++ evaluation; terms with memory refuse with a
// message naming them.
TEST_P(EffectProperties, ItsExportAgreesWithTheCppEvaluation) {
  const fs::path dir = fs::temp_directory_path() / ("gyrosid_effect_export_" + GetParam());
  fs::create_directories(dir);
  for (const Candidate& c : candidates()) {
    if (!c.term) {
      ExplainedModel lagged(scaling(), 300.0, {base_terms().front()}, Eigen::VectorXd::Constant(1, 1e-5));
      EXPECT_THROW(lagged.export_c(dir, "lagged"), Error);
      continue;
    }
    const Term term = c.nonlinear == NonlinearParameter::term_parameter ? c.term->with_parameter(nonlinear_value(c)) : *c.term;
    const Eigen::VectorXd beta = Eigen::VectorXd::LinSpaced(term.size(), 1e-5, 3e-5);
    const ExplainedModel model(scaling(), 0.0, {term}, beta);
    if (term->memory() != TermMemory::none) {
      EXPECT_THAT([&] { model.export_c(dir, "m"); }, ::testing::ThrowsMessage<Error>(::testing::HasSubstr(std::string(term.kind()))));
      continue;
    }
    model.export_c(dir, "m");
    const std::size_t inputs = model.features().size();
    std::ofstream driver(dir / "main.c");
    driver << "#include <stdio.h>\n#include \"m.h\"\nint main(void) {\n  double x[" << inputs << "];\n  int i;\n  for (;;) {\n"
           << "    for (i = 0; i < " << inputs << "; ++i) if (scanf(\"%lf\", &x[i]) != 1) return 0;\n"
           << "    printf(\"%.17g\\n\", m_predict(x));\n  }\n}\n";
    driver.close();
    const std::string exe = (dir / "m").string();
    ASSERT_EQ(std::system(("cc -std=c99 -O2 -o " + exe + " " + (dir / "m.c").string() + " " + (dir / "main.c").string() + " -lm").c_str()), 0);
    RandomStream r(17, GetParam());
    std::vector<std::vector<double>> points;
    std::ofstream in_file(dir / "in.txt");
    in_file.precision(17);
    for (int k = 0; k < 40; ++k) {
      std::vector<double> x{units::dps_to_radps(-110 + 220 * r.uniform()), -30 + 80 * r.uniform()};
      for (std::size_t f = 2; f < inputs; ++f) x.push_back(10 * r.normal());
      for (double v : x) in_file << v << " ";
      in_file << "\n";
      points.push_back(x);
    }
    in_file.close();
    FILE* pipe = popen((exe + " < " + (dir / "in.txt").string()).c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    for (const auto& x : points) {
      double got = 0.0;
      ASSERT_EQ(std::fscanf(pipe, "%lf", &got), 1);
      EXPECT_NEAR(got, model.predict(x.data()), 1e-12 * std::max(1e-6, std::abs(model.predict(x.data())))) << GetParam();
    }
    pclose(pipe);
  }
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(EveryEffect, EffectProperties, ::testing::ValuesIn(effect_registry().names()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

// The kink of a scale-factor asymmetry (|omega|) is what a spline surface over omega bends to follow and a
// smooth polynomial cannot: planted on the standard recording, it is far stronger against the polynomial core
// than against the surface, and its share outside the surface's span is the projection computed directly.
TEST(Absorption, ASurfaceAbsorbsAnAsymmetryThatAPolynomialCoreDoesNot) {
  const ModelSpec full{baseline_family(BaselineForm::surface, input().signals), 0.0};
  const ModelSpec core{baseline_family(BaselineForm::polynomial, input().signals), 0.0};
  ASSERT_TRUE(full.terms.back().as<ScaleFactorSurface>());
  const std::vector<Candidate> asym = find_effect("scale_factor_asymmetry").propose(CandidateContext(full.terms, 0.0, input())).candidates;
  ASSERT_EQ(asym.size(), 1u);
  const Eigen::VectorXd none = Eigen::VectorXd::Zero(total_columns(full.terms));
  const Eigen::MatrixXd c = candidate_columns(asym[0], NAN, full, none, input().signals, scaling());
  RandomStream rng(5, "absorption");
  Eigen::VectorXd y = c.col(0) * (36.0 / c.col(0).cwiseAbs().maxCoeff());  // 36 deg/h at the largest rate
  for (Eigen::Index i = 0; i < y.size(); ++i) y(i) += 10.0 * rng.normal();
  NoiseModel white;
  white.white_var = 100.0;
  const Whitener w = training_whitener(input(), white);
  const AbsorptionTest t = absorption_tests(asym, full, core, input(), y, scaling(), w).at(0);
  EXPECT_GT(t.delta_bic_core, t.delta_bic_full + 10.0);
  EXPECT_GT(t.delta_bic_core, 10.0);
  // Independently: the whitened column's residual after a Householder least-squares fit on the full model.
  const Eigen::MatrixXd xw = w.apply(model_columns(full, input().signals, scaling()));
  const Eigen::VectorXd cw = w.apply(c).col(0);
  const Eigen::VectorXd outside = cw - xw * xw.colPivHouseholderQr().solve(cw);
  EXPECT_NEAR(t.unique_fraction, outside.norm() / cw.norm(), 1e-6);
  EXPECT_LT(t.unique_fraction, 0.5);
}

}  // namespace
}  // namespace gyrosid::explain
