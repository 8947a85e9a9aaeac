#include "explain/simulation.h"

#include "core/error.h"
#include "explain/linear_fit.h"
#include "model/explained_model.h"
#include "model/terms/term_kinds.h"

namespace gyrosid::explain {
namespace {

// The baseline family fitted on a calibration recording: what it could identify is the simulation's
// structure, what it could not (e.g. temperature terms from one plateau) stays a candidate.
Simulation fit_baseline_recording(const std::string& path, BaselineForm form, const InputOptions& input_options) {
  const ExplainInput cal = load_input(read_recording(path), input_options);
  const TermScaling cal_scaling = TermScaling::of(cal.signals);
  const std::vector<Term> family = baseline_family(form, cal.signals);
  const Eigen::MatrixXd x = design_matrix(family, cal.signals, coil_temperature(cal.signals, 0.0), cal_scaling);
  const WhitenedFit f = fit_whitened(x, cal.error);
  Simulation sim;
  std::vector<double> coefs;
  int at = 0;
  for (const auto& t : family) {
    std::vector<int> identifiable;
    for (int c = 0; c < t.size(); ++c) {
      if (f.kept[static_cast<std::size_t>(at + c)]) identifiable.push_back(c);
    }
    if (const std::optional<Term> kept = t.subset(identifiable)) {
      // A term that stays whole keeps every coefficient (0 where the recording cannot identify it).
      if (kept->size() == t.size()) {
        for (int c = 0; c < t.size(); ++c) coefs.push_back(f.beta(at + c));
      } else {
        for (int c : identifiable) coefs.push_back(f.beta(at + c));
      }
      sim.base.terms.push_back(*kept);
    }
    at += t.size();
  }
  sim.prior = std::make_unique<ExplainedModel>(cal_scaling, 0.0, sim.base.terms,
                                               Eigen::Map<const Eigen::VectorXd>(coefs.data(), static_cast<Eigen::Index>(coefs.size())));
  sim.description = str_cat("baseline family fitted on ", path);
  return sim;
}

}  // namespace

Dataset dataset_of(const ExplainInput& in, const std::vector<std::string>& features) {
  Dataset d;
  d.features = features;
  d.t_s = in.signals.t_s;
  d.measured = in.signals.rate;
  d.reference = in.signals.rate;
  d.target = in.error;
  d.x.resize(in.size(), static_cast<Eigen::Index>(features.size()));
  const CoilTemperature probe = coil_temperature(in.signals, 0.0);
  for (std::size_t f = 0; f < features.size(); ++f) {
    const auto col = static_cast<Eigen::Index>(f);
    if (features[f] == "measured_rate") d.x.col(col) = in.signals.rate;
    else if (features[f] == "temperature") d.x.col(col) = in.signals.temp_c;
    else if (features[f] == "temperature_rate") d.x.col(col) = probe.rate_c_per_s;
    else d.x.col(col) = in.signals.channel(features[f]);
  }
  return d;
}

Simulation make_simulation(ExplainInput& in, const std::string& model_path, const std::string& baseline_path, BaselineForm form,
                           const InputOptions& input_options) {
  Simulation sim;
  if (!model_path.empty()) {
    sim.prior = load_model(model_path);
    if (sim.prior->target() != ModelTarget::error) fail(model_path, ": explain needs a model of the rate error (target error)");
    sim.base.terms = structure_of(*sim.prior, form, in.signals, &sim.base.lag_tau_s);
    sim.description = str_cat("model ", model_path, " (", sim.prior->kind(), ")");
  } else if (!baseline_path.empty()) {
    sim = fit_baseline_recording(baseline_path, form, input_options);
  } else {
    sim.base.terms = baseline_family(form, in.signals);
    sim.description = str_cat("baseline family (bias cubic in T, scale factor as a ",
                              sim.base.terms.back().as<ScaleFactorSurface>() ? "bicubic surface over (T, omega)" : "polynomial of order 3 in T and omega",
                              ") fitted on the training blocks");
  }
  if (sim.prior) {
    in.signals.channels[kPriorChannel] = sim.prior->predict(dataset_of(in, sim.prior->features()));
    sim.base.terms.push_back(channel_term({kPriorChannel}));
  }
  return sim;
}

}  // namespace gyrosid::explain
