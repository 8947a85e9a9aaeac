#include "lot/screen.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <map>

#include "core/error.h"
#include "core/format.h"
#include "core/stats.h"

namespace gyrosid {
namespace {

// Where a coordinate's contribution is counted: its group, or a surface region (grid temperature, rate sign).
std::string region_of(const GreyboxCoordinate& c) {
  if (c.group != "surface") return c.group;
  return str_cat("surface at ", format_number(c.temp_c), " C, ", c.rate_dps > 0 ? "positive" : "negative", " rates");
}

// The unit's largest departure within a region, for the reason's text.
std::string largest_departure(const LotModel& lot, const Eigen::VectorXd& r, const Eigen::VectorXd& sd, const std::string& region) {
  Eigen::Index best = -1;
  for (Eigen::Index j = 0; j < r.size(); ++j) {
    if (region_of(lot.coordinates[static_cast<std::size_t>(j)]) != region) continue;
    if (best < 0 || std::abs(r(j) / sd(j)) > std::abs(r(best) / sd(best))) best = j;
  }
  const GreyboxCoordinate& c = lot.coordinates[static_cast<std::size_t>(best)];
  return str_cat(c.name, " ", format_significant(lot.mean(best) + r(best), 3), " ", c.unit, " against the lot's ", format_significant(lot.mean(best), 3),
                 " +- ", format_significant(sd(best), 3));
}

// Each region's share of the distance r' w (w = total^-1 r): its contributions r_j w_j summed, the negative
// ones (a region pulling against another) as zero, over their total - shares in [0, 1] that sum to 1.
std::map<std::string, double> region_shares(const LotModel& lot, const Eigen::VectorXd& r, const Eigen::VectorXd& w,
                                            std::map<std::string, std::string>& group_of) {
  std::map<std::string, double> share;
  double positive = 0.0;
  for (Eigen::Index j = 0; j < r.size(); ++j) {
    const GreyboxCoordinate& c = lot.coordinates[static_cast<std::size_t>(j)];
    share[region_of(c)] += r(j) * w(j);
    group_of[region_of(c)] = c.group;
  }
  for (auto& [region, s] : share) positive += s = std::max(s, 0.0);
  for (auto& [region, s] : share) s /= std::max(positive, 1e-300);
  return share;
}

// The p-values of a unit's tests: the lot's (`lot_tests`, the omnibus first), then its conditional ones, then
// the misfit's when `misfit_bin` >= 0 (its bin of largest contribution).
struct TestPValues {
  const std::vector<double>& p;
  std::size_t lot_tests = 0, conditional_tests = 0;
  Eigen::Index misfit_bin = -1;
};

std::string misfit_reason(const MisfitPopulation& m, const LotUnit& unit, Eigen::Index b, double p) {
  const auto i = static_cast<std::size_t>(b);
  return str_cat("misfit at rates ", format_number(m.rate_edges_dps[i]), "..", format_number(m.rate_edges_dps[i + 1]),
                 " deg/s: its own test p = ", format_significant(p, 3), " (the fit's mean residual there ", format_significant(unit.misfit(b), 3),
                 " standard errors against the lot's ", format_significant(m.mean(b), 3), " +- ", format_significant(m.sd(b), 3),
                 ": a shape the lot's structure does not hold)");
}

// Why a unit is out of family in its physics: a term's own test first (for the surface: its region of
// largest share), then a conditional test, then the misfit's (its rate band), else the regions holding a fifth of
// the distance (at least the largest). Each test is Bonferroni-corrected over all of them and the noise (2 tests).
void physics_reasons(const LotModel& lot, const LotUnit& unit, const Eigen::VectorXd& r, const Eigen::VectorXd& sd, const TestPValues& t,
                     double alpha, const std::map<std::string, double>& share,
                     const std::map<std::string, std::string>& group_of, ScreenResult& out) {
  const double tests = static_cast<double>(t.p.size());
  std::vector<std::pair<double, std::string>> ranked;
  for (const auto& [region, s] : share) ranked.push_back({-s, region});
  std::sort(ranked.begin(), ranked.end());
  for (std::size_t k = 1; k < t.lot_tests; ++k) {
    if (2.0 * tests * t.p[k] >= alpha) continue;
    std::string region = lot.tests[k];
    for (const auto& [minus, name] : ranked) {
      if (group_of.at(name) == lot.tests[k]) {
        region = name;
        break;
      }
    }
    out.reasons.push_back(str_cat(region, ": its own test p = ", format_significant(t.p[k], 3), " (", largest_departure(lot, r, sd, region), ")"));
  }
  for (std::size_t k = 0; k < t.conditional_tests; ++k) {
    const double p_k = t.p[t.lot_tests + k];
    if (2.0 * tests * p_k >= alpha) continue;
    out.reasons.push_back(str_cat(lot.conditional_terms[k], " given the rest of the lot: p = ", format_significant(p_k, 3), " (z = ",
                                  format_significant(unit.conditional_z(static_cast<Eigen::Index>(k)), 3), " of the lot's spread and the recording's)"));
  }
  if (t.misfit_bin >= 0 && 2.0 * tests * t.p.back() < alpha) out.reasons.push_back(misfit_reason(lot.misfit, unit, t.misfit_bin, t.p.back()));
  if (!out.reasons.empty()) return;
  for (const auto& [minus, region] : ranked) {
    if (-minus < 0.2 && !out.reasons.empty()) break;
    out.reasons.push_back(str_cat(region, ": ", format_significant(100.0 * -minus, 3), " % of the distance (", largest_departure(lot, r, sd, region), ")"));
  }
}

}  // namespace

std::string ScreenOptions::validate() const {
  if (!(alpha > 0.0 && alpha < 1.0)) return "alpha must be in (0, 1)";
  return "";
}

ScreenResult screen_unit(const LotModel& lot, const LotUnit& unit, const ScreenOptions& o) {
  if (auto p = o.validate(); !p.empty()) fail("lot screen: ", p);
  const auto p = static_cast<Eigen::Index>(lot.coordinates.size());
  if (unit.theta.size() != p) fail("lot screen: unit '", unit.name, "' has ", unit.theta.size(), " coordinates where the lot has ", p);
  ScreenResult out;
  const Eigen::MatrixXd sigma = lot.covariance();
  Eigen::MatrixXd total = sigma;
  if (unit.theta_variance.size() > 0) total.diagonal() += unit.theta_variance;
  const Eigen::LLT<Eigen::MatrixXd> llt(total);
  if (llt.info() != Eigen::Success) fail("lot screen: the lot's covariance plus the unit's is not positive definite");
  const Eigen::VectorXd r = unit.theta - lot.mean;
  const Eigen::VectorXd w = llt.solve(r);
  const std::vector<double> d2 = lot_distances(r, sigma, unit.theta_variance, lot.coordinates, lot.tests);
  out.distance2 = d2[0];
  std::vector<double> p_test;
  for (std::size_t k = 0; k < d2.size(); ++k) {
    p_test.push_back(lot.nulls[k].p_value(d2[k]));
    out.tests[lot.tests[k]] = {{"distance2", d2[k]}, {"p_value", p_test.back()}};
  }
  const Eigen::VectorXd& conditional_z = unit.conditional_z;
  const bool conditional = conditional_z.size() > 0 && !lot.conditional_terms.empty();
  if (conditional && conditional_z.size() != static_cast<Eigen::Index>(lot.conditional_terms.size())) {
    fail("lot screen: unit '", unit.name, "' has ", conditional_z.size(), " conditional scores where the lot has ", lot.conditional_terms.size(), " tests");
  }
  const std::size_t conditional_tests = conditional ? lot.conditional_terms.size() : 0;
  for (std::size_t k = 0; k < conditional_tests; ++k) {
    const double z = conditional_z(static_cast<Eigen::Index>(k));
    p_test.push_back(lot.conditional_nulls[k].p_value(z * z));
    out.tests[lot.conditional_terms[k] + " given the rest"] = {{"z", z}, {"p_value", p_test.back()}};
  }
  Eigen::Index misfit_bin = -1;
  if (lot.misfit.learned() && unit.misfit.size() == lot.misfit.mean.size()) {
    const double d2_misfit = lot.misfit.distance2(unit.misfit, &misfit_bin);
    if (misfit_bin >= 0) {
      p_test.push_back(lot.misfit.null.p_value(d2_misfit));
      out.tests["misfit"] = {{"distance2", d2_misfit}, {"p_value", p_test.back()}};
    }
  }
  const double tests = static_cast<double>(p_test.size());
  out.p_physics = std::min(1.0, tests * *std::min_element(p_test.begin(), p_test.end()));

  double noise_z = 0.0;
  if (lot.noise_units >= 2 && unit.white_dph_at_1hz > 0.0) {
    noise_z = (std::log(unit.white_dph_at_1hz) - lot.log_noise_mean) / (lot.log_noise_sd * std::sqrt(1.0 + 1.0 / lot.noise_units));
    // A new draw from a normal known by n units' mean and sd: (x - mean) / (sd sqrt(1 + 1/n)) ~ t_{n-1}, not N(0, 1):
    // with five units the normal's 1 % point, 2.58, is t_4's 6 % (a lot of six real units, experiments/production_lot).
    out.p_noise = stats::student_t_two_sided(noise_z, lot.noise_units - 1.0);
  }
  out.p_value = std::min(1.0, 2.0 * std::min(out.p_physics, out.p_noise));
  out.out_of_family = out.p_value < o.alpha;
  if (lot.recording_min > 0.0 && unit.recording_min > 0.0 && std::abs(unit.recording_min / lot.recording_min - 1.0) > 0.2) {
    out.warning = str_cat("the lot's null was calibrated on ", format_significant(lot.recording_min, 3), "-min recordings and this one is ",
                          format_significant(unit.recording_min, 3), " min: its false-alarm rate is not calibrated (screen the lot's own programme)");
  }

  std::map<std::string, std::string> group_of;  // region -> its coordinates' group
  const std::map<std::string, double> share = region_shares(lot, r, w, group_of);
  out.contributions = share;
  if (out.out_of_family && 2.0 * out.p_physics < o.alpha) {
    physics_reasons(lot, unit, r, total.diagonal().cwiseSqrt(), {p_test, d2.size(), conditional_tests, misfit_bin}, o.alpha, share, group_of, out);
  }
  if (out.out_of_family && 2.0 * out.p_noise < o.alpha) {
    out.reasons.push_back(str_cat("noise: white ", format_significant(unit.white_dph_at_1hz, 3), " dph at 1 Hz, ",
                                  format_significant(unit.white_dph_at_1hz / std::exp(lot.log_noise_mean), 3), "x the lot's median (z = ", format_significant(noise_z, 3), ")"));
  }
  return out;
}

nlohmann::json ScreenResult::to_json() const {
  return {{"out_of_family", out_of_family}, {"p_value", p_value}, {"p_physics", p_physics}, {"p_noise", p_noise},
          {"distance2", distance2}, {"tests", tests}, {"reasons", reasons}, {"contributions", contributions}, {"warning", warning}};
}

}  // namespace gyrosid
