// Orthogonal least-squares forward selection of RBF centres (Chen, Cowan & Grant 1991) with Orr's global
// ridge regression (Orr 1995, "Regularisation in the selection of RBF centres"), the engine of the `ols`
// solver and the inner fit of `nlopt`.
//
// With the selected columns orthogonalised (w_k, d_k = w_k'w_k, c_k = w_k'y), the regularised cost
// e'e + lambda g'g is minimised by g_k = c_k / (d_k + lambda), and adding candidate j lowers it by
// (h_j' r)^2 / (h_j' h_j - |Q' h_j|^2 + lambda), r the unregularised residual - Chen's error-reduction ratio
// when lambda = 0. Per step one product H'q updates every candidate: O(N M) time, O(N M) memory for the
// candidate matrix H, never an N x N matrix. The chosen column is orthogonalised by modified Gram-Schmidt,
// twice (stable even for nearly dependent columns); candidates whose orthogonal remainder is below
// `collinear_tolerance` of their norm are skipped.
//
// Model-selection criteria with gamma = sum_k d_k / (d_k + lambda) effective parameters, N samples
// (Orr 1996, s5): UEV = e'e/(N - gamma), FPE = e'e (N + gamma)/(N (N - gamma)), GCV = N e'e/(N - gamma)^2,
// BIC = e'e (N + (ln N - 1) gamma)/(N (N - gamma)), LOO = mean((e_i / (1 - h_ii))^2),
// h_ii = sum_k w_ik^2/(d_k + lambda). Selection stops when the criterion has not improved for `patience`
// steps and the network is cut back to the best step. lambda is re-estimated after every step by the GCV
// fixed point lambda = e'e sum_k d_k/(d_k + lambda)^2 / ((N - gamma) sum_k g_k^2/(d_k + lambda)).
#pragma once

#include <Eigen/Core>

#include <array>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/enum_names.h"
#include "core/solve_summary.h"

namespace gyrosid {

enum class SelectionCriterion { bic, gcv, uev, fpe, loo };

template <>
struct EnumNames<SelectionCriterion> {
  static constexpr std::string_view kNoun = "model-selection criterion";
  static constexpr std::array<std::pair<SelectionCriterion, std::string_view>, 5> kTable{
      {{SelectionCriterion::bic, "bic"}, {SelectionCriterion::gcv, "gcv"}, {SelectionCriterion::uev, "uev"},
       {SelectionCriterion::fpe, "fpe"}, {SelectionCriterion::loo, "loo"}}};
};

struct ForwardSelectionOptions {
  SelectionCriterion criterion = SelectionCriterion::bic;
  Eigen::RowVectorXd widths;  // per input, normalised units
  int candidates = 1000;      // <= 0: every distinct training point
  int max_nodes = 500;
  double lambda = 1e-6;       // global ridge, in units of the (unit-RMS) target squared
  bool reestimate_lambda = true;
  int patience = 3;           // steps without improvement before stopping
  double collinear_tolerance = 1e-9;
};

struct ForwardSelectionResult {
  Eigen::MatrixXd centres;  // k x d
  Eigen::VectorXd weights;  // k, target units
  double lambda = 0.0;
  double criterion = 0.0;   // at the kept step
  double rss = 0.0;
  double effective_parameters = 0.0;
  std::vector<double> criterion_history;  // per selection step
  Termination termination = Termination::iteration_limit;
  std::string stop_reason;  // criterion_minimum | max_nodes | candidates_exhausted
  int steps = 0;            // nodes added before stopping (>= kept nodes)
  int skipped_collinear = 0;
  int candidates = 0;
};

ForwardSelectionResult forward_select(const Eigen::MatrixXd& x, const Eigen::VectorXd& y,
                                      const ForwardSelectionOptions& options);

// The value of `criterion` for a regularised linear fit with residual sum of squares rss, gamma effective
// parameters, n samples (LOO needs the residuals; not covered here).
double selection_criterion(SelectionCriterion criterion, double rss, double gamma, double n);

}  // namespace gyrosid
