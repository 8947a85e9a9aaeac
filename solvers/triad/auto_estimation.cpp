#include "solvers/triad/auto_estimation.h"

#include <cmath>

#include <Eigen/Eigenvalues>

#include "core/error.h"
#include "core/format.h"
#include "core/stats.h"
#include "core/triad_axes.h"

namespace gyrosid {

nlohmann::json CouplingTest::json() const {
  return {{"statistic", statistic},
          {"dof", dof},
          {"critical", critical},
          {"level", level},
          {"entries", entries},
          {"rejected", rejected},
          {"definition", "T = d' V_joint^+ d, d = vec(M_joint - M_sequential) over the entries both fits determined; the sequential fit's "
                         "restriction (M separable from the surfaces) rejected when T > chi^2_{1-level}(dof) (solvers/triad/auto_estimation.h)"}};
}

CouplingTest coupling_test(const TriadFit& joint, const TriadFit& sequential, double level) {
  std::vector<int> at;  // vec(M) indices 3 i + j
  CouplingTest t;
  t.level = level;
  const auto& cov = joint.uncertainty.misalignment_covariance;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const auto ai = static_cast<std::size_t>(i), aj = static_cast<std::size_t>(j);
      if (!joint.uncertainty.misalignment_known[ai][aj] || !sequential.uncertainty.misalignment_known[ai][aj]) continue;
      if (!std::isfinite(cov(3 * i + j, 3 * i + j))) continue;
      at.push_back(3 * i + j);
      t.entries.push_back(std::string("M_") + kTriadAxes[i] + kTriadAxes[j]);
    }
  }
  if (at.empty()) fail("triad: estimation=auto: no entry of M was determined (with a covariance) by both the joint and the sequential fit");
  const auto n = static_cast<Eigen::Index>(at.size());
  Eigen::VectorXd d(n);
  Eigen::MatrixXd v(n, n);
  for (Eigen::Index a = 0; a < n; ++a) {
    const int ka = at[static_cast<std::size_t>(a)];
    d(a) = joint.model.misalignment(ka / 3, ka % 3) - sequential.model.misalignment(ka / 3, ka % 3);
    for (Eigen::Index b = 0; b < n; ++b) v(a, b) = cov(ka, at[static_cast<std::size_t>(b)]);
  }
  if (!v.allFinite()) fail("triad: estimation=auto: the joint fit's covariance of M is incomplete");
  // The pseudo-inverse on V's numerical range: a direction the joint fit leaves (nearly) undetermined carries
  // no test.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(v);
  const Eigen::VectorXd lambda = eig.eigenvalues();
  const Eigen::VectorXd projected = eig.eigenvectors().transpose() * d;
  const double floor = 1e-12 * lambda.maxCoeff();
  for (Eigen::Index k = 0; k < n; ++k) {
    if (!(lambda(k) > floor)) continue;
    t.statistic += projected(k) * projected(k) / lambda(k);
    ++t.dof;
  }
  if (t.dof == 0) fail("triad: estimation=auto: the joint fit's covariance of M is zero");
  t.critical = stats::chi2_quantile(1.0 - level, t.dof);
  t.rejected = t.statistic > t.critical;
  return t;
}

namespace {

// `f` as estimation=auto's result: the options asked for, which fit it is (summary details) and why (first note).
TriadFit as_auto(TriadFit f, const TriadFitOptions& options, const char* chosen, const std::string& why) {
  f.options = options;
  f.summary.details["estimation"] = "auto";
  f.estimation_chosen = chosen;
  f.summary.details["estimation_chosen"] = chosen;
  f.notes.insert(f.notes.begin(), "estimation=auto: " + why);
  return f;
}

}  // namespace

TriadFit fit_triad_auto(const TriadData& data, const TriadFitOptions& options, const std::string& reference_metadata) {
  TriadFitOptions joint_options = options, sequential_options = options;
  joint_options.estimation = "joint";
  sequential_options.estimation = "sequential";
  if (options.surfaces == "none") {
    return as_auto(fit_triad(data, joint_options, reference_metadata), options, "joint",
                   "without surfaces the joint and the sequential fit are the same problem - the joint fit returned");
  }
  if (triad_reference_mode(options, reference_metadata) == "angle") {
    return as_auto(fit_triad(data, joint_options, reference_metadata), options, "joint",
                   "with an angle reference only the joint fit has surfaces - the joint fit returned");
  }
  TriadFit joint = fit_triad(data, joint_options, reference_metadata);
  TriadFit sequential = fit_triad(data, sequential_options, reference_metadata);
  const double time_s = joint.summary.time_s + sequential.summary.time_s;
  CouplingTest test;
  try {
    test = coupling_test(joint, sequential, options.coupling_test_level);
  } catch (const Error& e) {  // no determined entry of M to compare: keep the fit that needs no restriction
    joint.summary.time_s = time_s;
    return as_auto(std::move(joint), options, "joint", str_cat("the test could not be made (", e.what(), ") - the joint fit returned"));
  }
  TriadFit chosen = std::move(test.rejected ? joint : sequential);
  chosen.summary.time_s = time_s;
  chosen.summary.details["coupling_test"] = test.json();
  const std::string why = str_cat(
      test.rejected ? "the joint fit returned - the sequential fit's M differs from it by T = " : "the sequential fit returned - its M agrees with the joint fit's, T = ",
      format_significant(test.statistic, 3), test.rejected ? " > " : " <= ", format_significant(test.critical, 3), " (chi^2, ", test.dof, " dof, level ",
      test.level, test.rejected ? "): the surfaces couple with M on this programme" : "): the programme separates M from the surfaces, and the restricted fit is the more efficient");
  return as_auto(std::move(chosen), options, test.rejected ? "joint" : "sequential", why);
}

}  // namespace gyrosid
