#include "solvers/common/terminations.h"

namespace gyrosid {

Termination termination_of(ceres::TerminationType type) {
  switch (type) {
    case ceres::CONVERGENCE:
    case ceres::USER_SUCCESS: return Termination::converged;
    case ceres::NO_CONVERGENCE: return Termination::iteration_limit;
    default: return Termination::failed;
  }
}

Termination termination_of(Ipopt::SolverReturn status) {
  switch (status) {
    case Ipopt::SUCCESS:
    case Ipopt::STOP_AT_ACCEPTABLE_POINT: return Termination::converged;
    case Ipopt::MAXITER_EXCEEDED:
    case Ipopt::CPUTIME_EXCEEDED: return Termination::iteration_limit;
    case Ipopt::STOP_AT_TINY_STEP: return Termination::no_progress;
    default: return Termination::failed;
  }
}

}  // namespace gyrosid
