#include "explain/simulation.h"

#include <cmath>

#include "core/error.h"
#include "core/format.h"
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
  std::string why;
  const std::vector<Term> family = baseline_family(choose_baseline_form(form, cal, &why), cal.signals);
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
  sim.description = str_cat("baseline family fitted on ", path, why.empty() ? "" : str_cat(" (", why, ")"));
  return sim;
}

// Legendre polynomials P_1..P_order of the time mapped onto [-1, 1] over the record, on the given rows, by
// Bonnet's recursion (k + 1) P_{k+1} = (2k + 1) x P_k - k P_{k-1}.
Eigen::MatrixXd legendre_in_time(const std::vector<double>& t_s, const std::vector<Eigen::Index>& rows, int order) {
  const double t0 = t_s.front(), span = std::max(t_s.back() - t0, 1e-9);
  Eigen::ArrayXd x(static_cast<Eigen::Index>(rows.size()));
  for (std::size_t k = 0; k < rows.size(); ++k) x(static_cast<Eigen::Index>(k)) = 2.0 * (t_s[static_cast<std::size_t>(rows[k])] - t0) / span - 1.0;
  Eigen::MatrixXd out(x.size(), order);
  Eigen::ArrayXd previous = Eigen::ArrayXd::Ones(x.size()), current = x;
  for (int k = 1; k <= order; ++k) {
    out.col(k - 1) = current.matrix();
    Eigen::ArrayXd next = ((2.0 * k + 1.0) * x * current - k * previous) / (k + 1.0);
    previous = std::move(current), current = std::move(next);
  }
  return out;
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

BaselineForm choose_baseline_form(BaselineForm form, const ExplainInput& in, std::string* why) {
  if (form != BaselineForm::automatic) return form;
  const std::vector<Term> surface = baseline_family(BaselineForm::surface, in.signals);
  if (!surface.back().as<ScaleFactorSurface>()) return BaselineForm::polynomial;  // the data span too little for a grid
  const std::vector<Term> polynomial = baseline_family(BaselineForm::polynomial, in.signals);
  std::vector<Eigen::Index> rows;
  for (Eigen::Index i = 0; i < in.size(); ++i) {
    if (in.diagnosed(i)) rows.push_back(i);
  }
  const auto n = static_cast<double>(rows.size());
  const TermScaling scaling = TermScaling::of(in.signals);
  const CoilTemperature coil = coil_temperature(in.signals, 0.0);
  const Eigen::VectorXd y = in.error(rows);
  // Slow structure in time (drift, warm-up, wander) is in both fits: otherwise the surface, whose columns
  // follow the rate programme's slow pattern, wins by absorbing it (an ageing trend of 1 sigma made it win by
  // 797 on the independent generator).
  const Eigen::MatrixXd nuisance = legendre_in_time(in.signals.t_s, rows, 6);
  // BIC = n ln(rss / n) + k ln n of the least-squares fit on the training rows (k: its rank).
  auto bic = [&](const std::vector<Term>& family) {
    const Eigen::MatrixXd columns = design_matrix(family, in.signals, coil, scaling)(rows, Eigen::all);
    Eigen::MatrixXd xy(columns.rows(), columns.cols() + nuisance.cols());
    xy << columns, nuisance;
    const WhitenedFit f = fit_whitened(xy, y);
    return n * std::log(f.rss / n) + f.rank * std::log(n);
  };
  const double gain = bic(polynomial) - bic(surface);
  *why = str_cat("the surface's BIC is ", format_significant(std::abs(gain), 3), gain > 0 ? " below" : " above",
                 " the polynomial's on the training rows");
  return gain > 0 ? BaselineForm::surface : BaselineForm::polynomial;
}

Simulation make_simulation(ExplainInput& in, const std::string& model_path, const std::string& baseline_path, BaselineForm form,
                           const InputOptions& input_options) {
  Simulation sim;
  if (!model_path.empty()) {
    sim.prior = load_model(model_path);
    if (sim.prior->target() != ModelTarget::error) fail(model_path, ": explain needs a model of the rate error (target error)");
    std::string why;
    std::optional<std::vector<Term>> own = structure_of(*sim.prior, &sim.base.lag_tau_s);
    sim.base.terms = own ? std::move(*own) : baseline_family(choose_baseline_form(form, in, &why), in.signals);
    sim.description = str_cat("model ", model_path, " (", sim.prior->kind(), ")", why.empty() ? "" : str_cat("; ", why));
  } else if (!baseline_path.empty()) {
    sim = fit_baseline_recording(baseline_path, form, input_options);
  } else {
    std::string why;
    sim.base.terms = baseline_family(choose_baseline_form(form, in, &why), in.signals);
    sim.description = str_cat("baseline family (bias cubic in T, scale factor as a ",
                              sim.base.terms.back().as<ScaleFactorSurface>() ? "bicubic surface over (T, omega)" : "polynomial of order 3 in T and omega",
                              ") fitted on the training blocks", why.empty() ? "" : str_cat("; ", why));
  }
  if (sim.prior) {
    in.signals.channels[kPriorChannel] = sim.prior->predict(dataset_of(in, sim.prior->features()));
    sim.base.terms.push_back(channel_term({kPriorChannel}));
  }
  return sim;
}

}  // namespace gyrosid::explain
