// Distribution functions used for confidence intervals and tests (Allan deviation intervals, Ljung-Box,
// Anderson-Darling, likelihood-ratio tests, a lot's noise screen).
#pragma once

namespace gyrosid::stats {

double normal_cdf(double x);
double normal_quantile(double p);  // inverse of normal_cdf, p in (0, 1)

// Regularised lower incomplete gamma P(a, x) (series for x < a + 1, continued fraction otherwise).
double regularized_gamma_p(double a, double x);

// Regularised incomplete beta I_x(a, b) (Lentz's continued fraction on the side where it converges fast).
double regularized_beta(double a, double b, double x);
// Two-sided tail P(|T| >= |t|) of Student's t with `dof` degrees of freedom: I_{dof/(dof+t^2)}(dof/2, 1/2).
double student_t_two_sided(double t, double dof);

double chi2_cdf(double x, double dof);
double chi2_quantile(double p, double dof);  // x with chi2_cdf(x, dof) = p

}  // namespace gyrosid::stats
