// What every Ipopt least-squares solve in gyrosid shares (the RBF trainer and the NLS back-end): the
// application's settings and the run.
#pragma once

#include <coin/IpIpoptApplication.hpp>
#include <coin/IpTNLP.hpp>

#include <string>

namespace gyrosid {

struct IpoptLeastSquaresSettings {
  int print_level = 0;
  bool exact_hessian = true;  // the NLP's Gauss-Newton Hessian; false: Ipopt's limited-memory quasi-Newton
  int max_iterations = 200;
  double tolerance = 1e-8;
};

// Runs Ipopt on `nlp`. Bounds are rarely active at a least-squares minimum: the barrier starts small (1e-8) and
// decreases monotonically, so it does not hold the iterates away from the minimum. Error "<who>: initialisation
// failed" when Ipopt cannot start.
Ipopt::ApplicationReturnStatus solve_with_ipopt(const Ipopt::SmartPtr<Ipopt::TNLP>& nlp, const IpoptLeastSquaresSettings& s, const std::string& who);

}  // namespace gyrosid
