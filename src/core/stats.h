// Distribution functions used for confidence intervals and tests (Allan deviation intervals, Ljung-Box,
// Anderson-Darling, likelihood-ratio tests).
#pragma once

namespace gyrosid::stats {

double normal_cdf(double x);
double normal_quantile(double p);  // inverse of normal_cdf, p in (0, 1)

// Regularised lower incomplete gamma P(a, x) (series for x < a + 1, continued fraction otherwise).
double regularized_gamma_p(double a, double x);

double chi2_cdf(double x, double dof);
double chi2_quantile(double p, double dof);  // x with chi2_cdf(x, dof) = p

}  // namespace gyrosid::stats
