// A calibration model of one gyro (a SensorModel, sensor_model.h): maps the gyro's measured inputs (features,
// see dataset.h) to its rate error - which compensation subtracts (thesis figs 4.17/4.19) - or directly to the
// corrected rate (fig 4.18).
//
// Every model saves to JSON (format "gyrosid-model/1", loading back to the same numbers) and exports to
// dependency-free C99 for an embedded navigation processor.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "model/dataset.h"
#include "model/sensor_model.h"
#include "model/weight_posterior.h"

namespace gyrosid {

// C99 export under construction: a header with the declarations and a source with the data and code.
struct CExport {
  std::string prefix;  // C identifier prefix, e.g. "gyro_x"
  std::ostringstream header;
  std::ostringstream source;

  // `static const double <prefix>_<name>[] = {...};` with every digit needed to round-trip.
  void array(const std::string& name, const double* values, std::size_t count);
  std::string id(const std::string& name) const { return prefix + "_" + name; }
};

// Outputs and their posterior standard deviations (rad/s), one per input row.
struct PredictionWithSigma {
  Eigen::VectorXd value, sigma;
};

class CalibrationModel : public SensorModel {
 public:
  int gyros() const final { return 1; }
  const std::vector<std::string>& features() const { return features_; }
  ModelTarget target() const { return target_; }

  // Model output for one sample of inputs x[0..d-1] (SI units, the order of features()): the rate error or
  // the corrected rate, rad/s. Stateless: a model with dynamics (a thermal lag) evaluates in steady state.
  virtual double predict(const double* x) const = 0;
  // Outputs along a recording (models with dynamics run them over time); default: sample by sample.
  virtual Eigen::VectorXd predict(const Dataset& data) const;
  // True when predict(data) at a sample depends on that sample's inputs alone (no dynamics over time): the
  // model can then be applied to a recording a chunk at a time. A model that overrides predict(data) says no.
  virtual bool pointwise() const { return true; }

  // Predictive uncertainty, for models linear in weights that carry a Gaussian posterior over them
  // (model/weight_posterior.h): the rbf network trained by `bayes`, the hybrid, the classical model.
  // posterior() is nullptr for a model fitted without one.
  virtual const WeightPosterior* posterior() const { return nullptr; }
  // Regressor rows h(x_i) (N x posterior()->size()) at inputs x (N x d, SI, features() order, steady state
  // like predict(x)), with predict(x_i) = h(x_i)' (posterior mean). Error for a model without a posterior.
  virtual Eigen::MatrixXd regressors(const Eigen::MatrixXd& x) const;
  // predict(x_i) and sigma_i = sqrt(h(x_i)' P h(x_i)), the standard deviation of the estimate (not of the
  // sensor's noise) at every row of x. Error naming the model kind when it has no posterior.
  PredictionWithSigma predict_with_sigma(const Eigen::MatrixXd& x) const;

  // Model-specific JSON (the common fields are added by to_json()).
  virtual nlohmann::json parameters_json() const = 0;
  // Body of `double <prefix>_predict(const double* x)` plus any data it needs, into out.source.
  virtual void export_c_body(CExport& out) const = 0;

  nlohmann::json to_json() const final;
  // Writes <prefix>.h and <prefix>.c into `dir` (atomically). The header declares
  //   double <prefix>_predict(const double* x);          model output, rad/s
  //   double <prefix>_compensate(const double* x, double measured_radps);
  void export_c(const std::filesystem::path& dir, const std::string& prefix) const final;
  // compensate_recording(*this, ...) and compensate_file(*this, ...) of compensate_recording.h.
  CompensatedRecording compensate_recording(Recording recording) const final;
  CompensatedRecording compensate_file(const std::filesystem::path& input, const std::filesystem::path& output,
                                       const std::string& axis) const final;

 protected:
  CalibrationModel(std::vector<std::string> features, ModelTarget target)
      : features_(std::move(features)), target_(target) {}
  std::vector<std::string> features_;
  ModelTarget target_;
};

// The compensated rate of every sample: measured - predicted error, or the predicted corrected rate.
Eigen::VectorXd compensate(const CalibrationModel& model, const Dataset& data);

// A single-gyro model file; a triad's is refused, naming the file (sensor_model.h loads and saves any kind).
std::unique_ptr<CalibrationModel> model_from_json(const nlohmann::json& j, const std::string& source);
std::unique_ptr<CalibrationModel> load_model(const std::filesystem::path& path);

}  // namespace gyrosid
