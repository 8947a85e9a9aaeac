// Each back-end's own stopping codes mapped onto the shared Termination (core/solve_summary.h), in one place,
// so an NLopt "XTOL_REACHED", a Ceres CONVERGENCE and an Ipopt SUCCESS all read "converged".
#pragma once

#include <ceres/types.h>
#include <coin/IpAlgTypes.hpp>
#include "core/bounded_search.h"  // termination_of(nlopt_result), beside the NLopt search it serves
#include "core/solve_summary.h"

namespace gyrosid {

// CONVERGENCE, USER_SUCCESS -> converged; NO_CONVERGENCE (iteration or time cap) -> iteration_limit;
// FAILURE, USER_FAILURE -> failed.
Termination termination_of(ceres::TerminationType type);
// SUCCESS, STOP_AT_ACCEPTABLE_POINT -> converged; MAXITER_EXCEEDED, CPUTIME_EXCEEDED -> iteration_limit;
// STOP_AT_TINY_STEP -> no_progress; everything else -> failed.
Termination termination_of(Ipopt::SolverReturn status);

}  // namespace gyrosid
