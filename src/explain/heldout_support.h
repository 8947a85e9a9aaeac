// Held-out samples outside the training blocks' support: where a model's prediction is an extrapolation. A
// flexible baseline (a spline surface over (T, omega)) fitted on the training blocks is undetermined at
// (T, omega) pairs they did not visit; its error on held-out samples there belongs to the model, not to
// missing physics, and no effect can remove it. Such samples neither confirm effects nor count in the
// held-out fit; explain reports how many there were.
//
// The measure is a held-out sample's leverage under the ordinary least-squares fit of the model's columns
// on the training rows, h = x' (X'X)^+ x (Cook & Weisberg 1982, Residuals and Influence in Regression,
// s2.1): its prediction variance in units of the noise variance. Over the training rows h averages p/n (p
// the rank); a held-out sample above `ratio` times that mean is outside the support. Directions the
// training rows do not determine (singular values below 1e-6 of the largest, columns scaled to unit norm)
// count at that floor: a held-out sample with any component along them is outside the support.
//
// Coverage is judged with the inputs of every model a comparison scores (HeldoutSupport), not with the
// baseline's alone: an effect that moves the model's inputs - a thermal lag evaluates every temperature
// term at the lagged temperature - or adds a regressor takes held-out samples the baseline's columns cover
// to values the training rows never spanned. Scored there, the model with the effect extrapolates and a
// right effect loses its held-out proof; so a held-out sample confirms only inside the support of the
// baseline's columns and of each model compared, and both sides of a comparison are scored on those rows.
//
// A location the training rows cannot place is outside the support too (issue 34, class 3): a change point
// whose time lies in a held-out run fits the training rows equally anywhere in that run, so the run's rows
// would score where the search happened to put it, not whether the change is real (a step 1,000 deg/h high
// inside the third eighth of a static log scored held-out z -11 and was demoted). Those rows are left out;
// the held-out blocks after the change confirm its height.
#pragma once

#include <Eigen/Core>

#include <deque>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "explain/effect.h"
#include "explain/explain_input.h"

namespace gyrosid::explain {

// `x`: the model's columns on every sample; `heldout`: 1 for held-out samples. Returns 1 for the held-out
// samples outside the training rows' support (0 for every training sample).
std::vector<char> outside_training_support(const Eigen::MatrixXd& x, const std::vector<char>& heldout, double ratio);

// The held-out samples a comparison of models may score on one recording: outside_training_support of the
// baseline's columns and of each model's, or'ed. One QR per model; a model judged again (the same terms and
// lag) reuses its mask.
class HeldoutSupport {
 public:
  HeldoutSupport(const ExplainInput& in, const ModelSpec& base, const TermScaling& scaling, double ratio);

  const std::vector<char>& baseline() const { return base_; }
  // 1 for the held-out samples outside the training support of the baseline's columns or of any of `models`'.
  std::vector<char> outside(const std::vector<const ModelSpec*>& models);

 private:
  const std::vector<char>& of(const ModelSpec& model);

  const ExplainInput& in_;
  TermScaling scaling_;
  double ratio_;
  std::vector<char> base_;
  std::deque<std::pair<nlohmann::json, std::vector<char>>> cache_;  // (model's terms and lag, its mask); stable references
};

}  // namespace gyrosid::explain
