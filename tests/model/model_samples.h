// A small instance of every model kind, built directly from planted parameters (no fitting), for the
// property suites that run over every registered kind. A new kind adds its maker here; the suite fails for a
// registered kind without one.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>

#include "core/random.h"
#include "core/units.h"
#include "model/classical_model.h"
#include "model/explained_model.h"
#include "model/greybox_model.h"
#include "model/hybrid_model.h"
#include "model/terms/term_kinds.h"
#include "model/rbf_network.h"
#include "model/triad_model.h"
#include "solvers/calibrate.h"

namespace gyrosid::testing_support {

inline std::unique_ptr<CalibrationModel> sample_rbf() {
  auto net = std::make_unique<RbfNetwork>(default_features(), ModelTarget::error,
                                          Normalizer{Eigen::Vector2d(0.01, 20.0), Eigen::Vector2d(1.7, 40.0)});
  RandomStream r(3, "rbf");
  const int m = 9;
  net->centres.resize(m, 2), net->widths.resize(m, 2), net->weights.resize(m);
  for (int j = 0; j < m; ++j) {
    net->centres(j, 0) = -1 + 2 * r.uniform(), net->centres(j, 1) = -1 + 2 * r.uniform();
    net->widths(j, 0) = 0.2 + r.uniform(), net->widths(j, 1) = 0.2 + r.uniform();
    net->weights(j) = 1e-3 * r.normal();
  }
  net->bias = -7e-5;
  return net;
}

inline std::unique_ptr<CalibrationModel> sample_classical() {
  auto m = std::make_unique<ClassicalModel>(default_features(), ModelTarget::error);
  m->rate_scale = 1.7, m->temperature_reference = 21.5, m->temperature_scale = 39.0;
  m->bias = Eigen::Vector4d(-7e-5, 1e-5, -3e-6, 2e-7);
  m->sf_temperature = Eigen::Vector3d(0, 1e-4, -2e-5);
  m->sf_rate = Eigen::Vector4d(1e-4, 2e-5, -7e-4, 3e-5);
  m->sf_cross = (Eigen::MatrixXd(2, 3) << 3e-5, -2e-4, 1e-5, -1e-5, 5e-5, 0.0).finished();  // v^i u^k w, i = 1, 2
  return m;
}

inline std::unique_ptr<CalibrationModel> sample_greybox() {
  GyroErrorModel e;
  e.bias_radps = units::dph_to_radps(-15.0);
  e.bias_temperature_radps = {{0.0, units::dph_to_radps(0.2), units::dph_to_radps(-0.004)}, 25.0};
  e.scale_factor_rate = {{50e-6, 0.0, -3e-5}, 0.0};
  const std::vector<double> temps{-20, 0, 20, 40, 60}, rates{-1.7, -0.7, -0.2, 0.2, 0.7, 1.7};
  Eigen::MatrixXd v(5, 6);
  RandomStream r(5, "greybox");
  for (Eigen::Index i = 0; i < v.size(); ++i) v(i) = 2e-4 * r.normal();
  e.scale_factor_surface = SplineSurface(temps, rates, v, OutsideGridPolicy::clamp);
  e.scale_factor_asymmetry = 3e-4;
  e.shupe_rad_per_c = 1e-4;
  return std::make_unique<GreyboxModel>(default_features(), e, 0.0);
}

// A greybox model as a fit under a lot prior leaves it (greybox_fit.h): the coefficients of its physics terms
// written into the error model by hand (the bias polynomial's powers of dT / t_scale, the surface's node
// values, Shupe, asymmetry as a/2 of |w|), with a posterior over them.
inline std::unique_ptr<CalibrationModel> sample_greybox_posterior() {
  const std::vector<double> temps{-20, 0, 20, 40, 60}, rates_dps{-100, -40, -10, 10, 40, 100};
  std::vector<Term> terms{bias_term(), temperature_polynomial({1, 2, 3}), scale_factor_surface(temps, rates_dps), shupe_term(), asymmetry_term()};
  TermScaling scaling;
  scaling.t_ref_c = 20.0, scaling.t_scale_c = 40.0, scaling.rate_scale_radps = 1.7;
  RandomStream r(9, "greybox posterior");
  Eigen::VectorXd c(4 + 30 + 2);
  c.head(4) << units::dph_to_radps(-15.0), units::dph_to_radps(4.0), units::dph_to_radps(-1.5), units::dph_to_radps(0.6);
  for (Eigen::Index i = 4; i < 34; ++i) c(i) = 2e-4 * r.normal();
  c(34) = units::dph_to_radps(2.0) * 60.0, c(35) = 1.5e-4;
  GyroErrorModel e;
  e.bias_temperature_radps = {{c(0), c(1) / 40.0, c(2) / 1600.0, c(3) / 64000.0}, 20.0};
  std::vector<double> rates;
  for (double w : rates_dps) rates.push_back(units::dps_to_radps(w));
  e.scale_factor_surface = SplineSurface(temps, rates, Eigen::Map<const Eigen::Matrix<double, 5, 6, Eigen::RowMajor>>(c.data() + 4), OutsideGridPolicy::clamp);
  e.shupe_rad_per_c = c(34), e.scale_factor_asymmetry = 2.0 * c(35);
  Eigen::MatrixXd l = Eigen::MatrixXd::Zero(36, 36);
  for (Eigen::Index i = 0; i < 36; ++i)
    for (Eigen::Index k = 0; k <= i; ++k) l(i, k) = (i == k ? 1.0 : 0.2 * r.normal()) * 0.05 * std::abs(c(i));
  WeightPosterior posterior;
  posterior.root = l;
  posterior.noise_sigma_radps = units::dph_to_radps(10.0);
  return std::make_unique<GreyboxModel>(default_features(), e, 0.0, GreyboxPosterior{scaling, terms, c, std::move(posterior)});
}

inline std::unique_ptr<CalibrationModel> sample_explained() {
  std::vector<Term> terms{bias_term(), temperature_polynomial({1, 2}), asymmetry_term(),
                          scale_factor_polynomial({{0, 0}, {1, 0}, {0, 2}}),
                          scale_factor_surface({-20, 10, 40, 60}, {-100, -30, 0, 20, 100}), temperature_spline({-30, 5, 25, 32, 50, 70})};
  TermScaling scaling;
  scaling.t_ref_c = 20.0, scaling.t_scale_c = 40.0, scaling.rate_scale_radps = 1.7;
  Eigen::VectorXd beta(29);
  beta << units::dph_to_radps(-12.0), units::dph_to_radps(3.0), units::dph_to_radps(-1.0), 2e-4, 1e-4, -5e-5, 3e-4, Eigen::VectorXd::Zero(22);
  RandomStream r(7, "explained surface");
  for (Eigen::Index i = 7; i < 27; ++i) beta(i) = 1e-4 * r.normal();
  for (Eigen::Index i = 27; i < 29; ++i) beta(i) = units::dph_to_radps(2.0) * r.normal();  // the bias spline's truncated cubics
  return std::make_unique<ExplainedModel>(scaling, 0.0, terms, beta);
}

// Physics (bias cubic, a scale-factor polynomial, asymmetry) plus four nodes on (true rate, temperature), with
// a posterior over all twelve weights.
inline std::unique_ptr<CalibrationModel> sample_hybrid() {
  std::vector<Term> terms{bias_term(), temperature_polynomial({1, 2, 3}), scale_factor_polynomial({{0, 0}, {1, 0}, {0, 2}}), asymmetry_term()};
  TermScaling scaling;
  scaling.t_ref_c = 20.0, scaling.t_scale_c = 40.0, scaling.rate_scale_radps = 1.7;
  Eigen::VectorXd beta(8);
  beta << units::dph_to_radps(-12.0), units::dph_to_radps(3.0), units::dph_to_radps(-1.0), units::dph_to_radps(0.2), 2e-4, 1e-4, -5e-5, 3e-4;
  RbfNetwork rbf(default_features(), ModelTarget::error, Normalizer{Eigen::Vector2d(0.0, 20.0), Eigen::Vector2d(1.7, 40.0)});
  RandomStream r(7, "hybrid");
  rbf.centres.resize(4, 2), rbf.widths.resize(4, 2), rbf.weights.resize(4);
  for (int j = 0; j < 4; ++j) {
    rbf.centres(j, 0) = -1 + 2 * r.uniform(), rbf.centres(j, 1) = -1 + 2 * r.uniform();
    rbf.widths(j, 0) = 0.1 + 0.3 * r.uniform(), rbf.widths(j, 1) = 0.3 + r.uniform();
    rbf.weights(j) = units::dph_to_radps(3.0) * r.normal();
  }
  Eigen::MatrixXd l = Eigen::MatrixXd::Zero(12, 12);
  for (int i = 0; i < 12; ++i)
    for (int k = 0; k <= i; ++k) l(i, k) = (i == k ? 1.0 : 0.3 * r.normal()) * units::dph_to_radps(0.1);
  WeightPosterior posterior;
  posterior.root = l;
  posterior.noise_sigma_radps = units::dph_to_radps(10.0);
  return std::make_unique<HybridModel>(scaling, terms, beta, std::move(rbf), std::move(posterior));
}

// The rbf sample as a relative error: its output multiplied by the measured rate (RbfNetwork::output_factor).
inline std::unique_ptr<CalibrationModel> sample_relative_rbf() {
  auto net = sample_rbf();
  auto& rbf = dynamic_cast<RbfNetwork&>(*net);
  rbf.weights *= 1e3, rbf.bias *= 1e3;  // dimensionless (a few 1e-3) rather than rad/s
  rbf.output_factor = 0;
  return net;
}

// Samples of options a kind's plain sample does not use, run through the same suite: name -> kind.
inline const std::map<std::string, std::string>& sample_variants() {
  static const std::map<std::string, std::string> variants{{"rbf_relative", "rbf"}, {"greybox_posterior", "greybox"}};
  return variants;
}

// Every registered kind's sample, by kind name (and every variant's, by its name), with the samples of the
// kinds registered whole from outside the library (register_model_kind, solvers/calibrate.h).
inline std::map<std::string, ModelSample> model_samples() {
  std::map<std::string, ModelSample> samples{
      {"rbf", sample_rbf}, {"classical", sample_classical}, {"greybox", sample_greybox}, {"explained", sample_explained},
      {"hybrid", sample_hybrid}, {"rbf_relative", sample_relative_rbf},
      {"greybox_posterior", sample_greybox_posterior}};
  samples.insert(registered_model_samples().begin(), registered_model_samples().end());
  return samples;
}

// A triad: misalignment, a bias cubic per gyro, g-sensitivity, and a classical surface on gyro z only.
inline TriadModel sample_triad() {
  TriadModel m;
  m.misalignment << -3e-4, -1e-3, 3e-3, 8e-4, 5e-4, 1.4e-3, 4e-4, -1e-3, 1e-4;
  m.bias.reference_c = 20.0;
  m.bias.scale_c = 30.0;
  for (int a = 0; a < 3; ++a) m.bias.coefficients[static_cast<std::size_t>(a)] = Eigen::Vector3d(units::dph_to_radps(-15 + a), units::dph_to_radps(2.0), units::dph_to_radps(-0.5));
  m.g_sensitivity = Eigen::Matrix3d::Identity() * units::dph_to_radps(0.3);
  (*m.g_sensitivity)(0, 2) = units::dph_to_radps(-0.2);
  auto surface = std::make_shared<ClassicalModel>(default_features(), ModelTarget::error);
  surface->bias = Eigen::VectorXd::Zero(1);
  surface->sf_temperature = Eigen::Vector2d(0.0, 1e-5);
  surface->sf_rate = Eigen::Vector3d(0.0, 0.0, -2e-4);
  m.surfaces[2] = surface;
  return m;
}

// Every kind's sample as what a model file holds (sensor_model.h): the single-gyro kinds' and the triad's.
using SensorModelSample = std::function<std::unique_ptr<SensorModel>()>;
inline std::map<std::string, SensorModelSample> sensor_model_samples() {
  std::map<std::string, SensorModelSample> out;
  for (auto& [name, make] : model_samples()) out[name] = [make] { return std::unique_ptr<SensorModel>(make()); };
  out["triad"] = [] { return std::make_unique<TriadModel>(sample_triad()); };
  return out;
}

}  // namespace gyrosid::testing_support
