#include "core/bounded_search.h"

#include <nlopt.hpp>

namespace gyrosid {

Termination termination_of(nlopt_result result) {
  switch (result) {
    case NLOPT_SUCCESS:
    case NLOPT_STOPVAL_REACHED:
    case NLOPT_FTOL_REACHED:
    case NLOPT_XTOL_REACHED: return Termination::converged;
    case NLOPT_MAXEVAL_REACHED: return Termination::evaluation_limit;
    case NLOPT_MAXTIME_REACHED: return Termination::iteration_limit;
    case NLOPT_ROUNDOFF_LIMITED: return Termination::no_progress;
    default: return Termination::failed;
  }
}

Termination termination_of(const BoundedSearchResult& search) {
  return search.threw ? Termination::no_progress : termination_of(search.result);
}

BoundedSearchResult minimize_bounded(const std::function<double(const std::vector<double>&)>& objective, std::vector<double> start,
                                     const std::vector<double>& lower, const std::vector<double>& upper,
                                     const BoundedSearchOptions& o) {
  return minimize_bounded(ObjectiveWithGradient([&](const std::vector<double>& x, std::vector<double>&) { return objective(x); }),
                          std::move(start), lower, upper, o);
}

BoundedSearchResult minimize_bounded(const ObjectiveWithGradient& objective, std::vector<double> start,
                                     const std::vector<double>& lower, const std::vector<double>& upper,
                                     const BoundedSearchOptions& o) {
  BoundedSearchResult r;
  const ObjectiveWithGradient tracked = [&](const std::vector<double>& x, std::vector<double>& gradient) {
    const double value = objective(x, gradient);
    ++r.evaluations;
    if (value < r.value) r.value = value, r.x = x;
    return value;
  };
  nlopt::opt opt(o.algorithm.c_str(), static_cast<unsigned>(start.size()));
  opt.set_lower_bounds(lower);
  opt.set_upper_bounds(upper);
  opt.set_maxeval(o.max_evaluations);
  if (o.xtol_rel > 0) opt.set_xtol_rel(o.xtol_rel);
  if (o.xtol_abs > 0) opt.set_xtol_abs(o.xtol_abs);
  if (o.initial_step > 0) opt.set_initial_step(o.initial_step);
  opt.set_min_objective([](const std::vector<double>& x, std::vector<double>& gradient, void* f) {
    return (*static_cast<const ObjectiveWithGradient*>(f))(x, gradient);
  }, const_cast<ObjectiveWithGradient*>(&tracked));
  if (o.seed) nlopt::srand(*o.seed);
  double value = 0.0;
  try {
    r.result = static_cast<nlopt_result>(opt.optimize(start, value));
    r.message = nlopt_result_to_string(r.result);
  } catch (const std::exception& e) {
    r.threw = true;
    r.message = std::string("stopped: ") + e.what();
  }
  if (r.x.empty()) r.x = start;
  return r;
}

}  // namespace gyrosid
