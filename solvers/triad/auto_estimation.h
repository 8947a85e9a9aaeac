// estimation=auto (triad_fit.h): the triad fitted both ways, and the joint fit returned only where the data
// reject the sequential fit's restriction.
//
// The sequential fit is the joint problem restricted: M (and G) from the rows without surfaces, the surfaces
// fitted to what that leaves. Where the programme separates M from the surfaces (balanced turns: every gyro's
// own-rate surface is orthogonal to the other axes' columns) the restriction holds, both estimators are
// consistent and the restricted one is the more efficient - the joint fit then pays for its coupled
// parameters: 0.01-0.6 % on the criterion of fit of balanced programmes (experiments/triad_misalignment,
// 20-40 seeds). Where the surfaces project onto M's columns (one body diagonal, rate-nonlinear gyros) the
// sequential M takes the nonlinearity as misalignment and only the joint fit is consistent. A specification
// test in the manner of Hausman (1978) tells the two apart from the recording itself:
//   d = vec(M_joint - M_sequential) over the entries both fits determined,
//   T = d' V_joint^+ d,  dof = rank of V_joint on those entries,  reject the restriction if T > chi^2_{1-level}(dof).
// Hausman's statistic has V_joint - V_sequential in place of V_joint: where the restricted fit is the efficient
// one that difference is the variance of d, and V_joint >= it, so this T is conservative - it rejects a true
// restriction with probability at most `level`. (The sequential first stage leaves the surfaces out of its rows,
// so it is efficient only approximately; measured on the study's 20 seeds of balanced programmes the largest
// |d_k| / sigma_k is 0.7 against 30-38 on the one-diagonal programme, and `run.py auto` kept the sequential fit
// in 200 of 200 balanced fits and returned the joint one in 40 of 40 one-diagonal FOG fits.)
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "solvers/triad/triad_fit.h"

namespace gyrosid {

struct CouplingTest {
  double statistic = 0.0;              // T
  int dof = 0;                         // rank of V_joint on the compared entries
  double critical = 0.0;               // chi^2_{1-level}(dof)
  double level = 0.0;
  std::vector<std::string> entries;    // the compared entries of M (M_xy, ...)
  bool rejected = false;               // T > critical: the surfaces couple with M, the joint fit is returned
  nlohmann::json json() const;
};

// The test above on two fits of the same recording. Fails when no entry of M was determined by both, or the
// joint fit has no covariance.
CouplingTest coupling_test(const TriadFit& joint, const TriadFit& sequential, double level);

// Both fits of `data` (options.estimation = joint, sequential), the test, and the chosen fit with the test in its
// notes and summary details (estimation_chosen, coupling_test); its time_s the two fits' together. With
// surfaces=none the two are one fit, and with an angle reference only the joint one exists: that fit, noted.
// Where the test cannot be made (no entry of M determined by both fits, e.g. every sigma above max_sigma) the
// joint fit, noted.
TriadFit fit_triad_auto(const TriadData& data, const TriadFitOptions& options, const std::string& reference_metadata);

}  // namespace gyrosid
