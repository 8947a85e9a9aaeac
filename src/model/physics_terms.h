// Named physical error terms of one gyro, each a family of regressor columns along a recording - the one
// vocabulary of the grey-box fit (greybox_fit.h), the explained-physics model (explained_model.h) and the
// missing-physics finder (src/explain). The rate error is linear in the columns:
//
//   e(t) = sum_terms sum_columns beta_c x_c(t)                                           (rad/s)
//
// A term is a small immutable object (TermBasis) that computes its columns, names them, says whether they
// need the past, writes itself as C99 and round-trips through JSON - as PySINDy's feature libraries
// compute, name and concatenate theirs. The kinds (model/terms/) are the thesis's unified model (eq 3.48):
// bias, bias polynomial in T, scale factor as a polynomial or a bicubic surface over (T, omega); and the
// effects it left out (s3.3-3.4): Shupe (eq 3.3), heating/cooling hysteresis, warm-up, ageing, scale-factor
// asymmetry, recorded channels (specific force and its square, magnetic field, the other axes' rates).
// term_kinds() lists them; a new kind is one class and one entry there.
//
// Temperature terms use the coil temperature: the probe's through a first-order lag of time constant tau
// when a thermal lag is modelled (thesis s4.4), else the probe's. Inputs are scaled for conditioning:
// dT = (T - t_ref) / t_scale, u = omega / rate_scale.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "core/registry.h"

namespace gyrosid {

struct CExport;

// The inputs the terms are built from, one gyro along a recording (SI; channels as recorded).
struct Signals {
  std::vector<double> t_s;
  Eigen::VectorXd rate;    // true rate, rad/s
  Eigen::VectorXd temp_c;  // probe temperature
  std::map<std::string, Eigen::VectorXd> channels;

  Eigen::Index size() const { return rate.size(); }
  const Eigen::VectorXd& channel(const std::string& name) const;  // Error naming the channel when absent
};

struct TermScaling {
  double t_ref_c = 25.0, t_scale_c = 50.0;
  double rate_scale_radps = 1.0;
  // Hysteresis: the branch switches where the smoothed |dT/dt| exceeds this (deg C/s).
  double hysteresis_threshold_c_per_s = 0.05 / 60.0;
  nlohmann::json to_json() const;
  static TermScaling from_json(const nlohmann::json& j);
  static TermScaling of(const Signals& s);  // centred and scaled to the recording's range
};

// Coil temperature and its rate along the signals: the probe through a first-order lag (tau > 0, exact for
// the linearly interpolated probe) or the probe itself with its rate by local linear regression over
// +-30 s (a quantised probe's sample-to-sample difference is noise).
struct CoilTemperature {
  Eigen::VectorXd temp_c, rate_c_per_s;
};
CoilTemperature coil_temperature(const Signals& s, double lag_tau_s);

// The heating/cooling branch (+-1/2) from the temperature change over +-30 s against the scaling's
// threshold rate, held through plateaus; before the first ramp, the first branch seen.
Eigen::VectorXd thermal_branch(const Signals& s, const CoilTemperature& coil, const TermScaling& scaling);

// What a term's columns are computed from.
struct TermInputs {
  const Signals& signals;
  const CoilTemperature& coil;
  const TermScaling& scaling;
};

// What a term's columns depend on besides the current sample: nothing, the time since the first sample
// (warm-up, ageing) or the temperature history (its rate, its heating/cooling branch). Terms with memory
// are zero in steady state and cannot be exported as a stateless C function.
enum class TermMemory { none, time, temperature_history };

// A term inside the explained model's generated C function `error(x, w)`, where w (the true rate, rad/s),
// dT and u are defined and the inputs are x[]: the term appends statements `e += ...` to `body`, with
// `coefficient(k)` the C expression of its k-th coefficient; helper data and functions go to `out`. The
// input named "temperature" is the probe temperature.
struct TermCode {
  CExport& out;
  std::ostringstream& body;
  Eigen::VectorXd values;                      // the term's coefficients (data-driven helpers: a spline)
  std::function<std::string(int)> coefficient;
  std::function<std::string(const std::string&)> input;  // a named channel's input x[i]
  std::string stem;                                      // unique identifier stem for the term's helpers
};

// A nonlinear parameter inside a term's columns: the warm-up's time constant (tau_s), the hysteresis's
// transition width (width_c), a change point's time (t_s). Scale parameters are positive and refined on a
// log scale; a location (a time) is refined by scanning.
struct TermParameter {
  std::string name;
  double value = 0.0;
  bool scale = true;
};

class TermBasis : public std::enable_shared_from_this<TermBasis> {
 public:
  virtual ~TermBasis() = default;

  virtual std::string_view kind() const = 0;
  virtual int size() const = 0;
  virtual std::vector<std::string> column_names() const = 0;
  // The columns along the inputs into `out` (N x size()).
  virtual void columns(const TermInputs& in, Eigen::Ref<Eigen::MatrixXd> out) const = 0;
  // The kind's own JSON fields (orders, channels, grid, tau_s); "kind" is added by Term::to_json.
  virtual void parameters_json(nlohmann::json& j) const { (void)j; }

  virtual TermMemory memory() const { return TermMemory::none; }
  virtual bool uses_temperature() const { return false; }
  virtual std::vector<std::string> channels() const { return {}; }
  // The term restricted to some of its columns (ascending indices; null when none is left) - for terms whose
  // columns stand alone (polynomial orders). Others (a surface's grid, a single column) stay whole.
  virtual std::shared_ptr<const TermBasis> subset(const std::vector<int>& columns) const;
  // A nonlinear parameter inside the columns, if the kind has one.
  virtual std::optional<TermParameter> parameter() const { return std::nullopt; }
  virtual std::shared_ptr<const TermBasis> with_parameter(double value) const;
  // Appends the C99 statements; returns an empty string, or why the term cannot be exported.
  virtual std::string export_c(TermCode& code) const = 0;
};

// A term as a value: cheap to copy, immutable.
class Term {
 public:
  explicit Term(std::shared_ptr<const TermBasis> basis);

  const TermBasis* operator->() const { return basis_.get(); }
  const TermBasis& basis() const { return *basis_; }
  std::string_view kind() const { return basis_->kind(); }
  int size() const { return basis_->size(); }
  std::vector<std::string> column_names() const { return basis_->column_names(); }
  template <typename T>
  const T* as() const {
    return dynamic_cast<const T*>(basis_.get());
  }
  std::optional<Term> subset(const std::vector<int>& columns) const;
  std::optional<TermParameter> parameter() const { return basis_->parameter(); }
  Term with_parameter(double value) const { return Term(basis_->with_parameter(value)); }

  nlohmann::json to_json() const;
  static Term from_json(const nlohmann::json& j);

 private:
  std::shared_ptr<const TermBasis> basis_;
};

// Every term kind, loadable by name from its JSON fields (model files keep {"kind": ..., fields}).
using TermKindRegistry = Registry<TermBasis, const nlohmann::json&>;
const TermKindRegistry& term_kinds();

// Columns of one term (N x term.size()), and of every term side by side.
Eigen::MatrixXd term_columns(const Term& term, const Signals& s, const CoilTemperature& coil, const TermScaling& scaling);
Eigen::MatrixXd design_matrix(const std::vector<Term>& terms, const Signals& s, const CoilTemperature& coil,
                              const TermScaling& scaling);
int total_columns(const std::vector<Term>& terms);

}  // namespace gyrosid
