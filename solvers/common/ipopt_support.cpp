#include "solvers/common/ipopt_support.h"

#include "core/error.h"

namespace gyrosid {

Ipopt::ApplicationReturnStatus solve_with_ipopt(const Ipopt::SmartPtr<Ipopt::TNLP>& nlp, const IpoptLeastSquaresSettings& s, const std::string& who) {
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  app->Options()->SetIntegerValue("print_level", s.print_level);
  app->Options()->SetStringValue("sb", "yes");
  app->Options()->SetStringValue("hessian_approximation", s.exact_hessian ? "exact" : "limited-memory");
  app->Options()->SetIntegerValue("max_iter", s.max_iterations);
  app->Options()->SetNumericValue("tol", s.tolerance);
  app->Options()->SetStringValue("mu_strategy", "monotone");
  app->Options()->SetNumericValue("mu_init", 1e-8);
  if (app->Initialize() != Ipopt::Solve_Succeeded) fail(who, ": initialisation failed");
  return app->OptimizeTNLP(nlp);
}

}  // namespace gyrosid
