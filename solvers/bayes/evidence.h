// The evidence (log marginal likelihood) of a Bayesian linear model with Gaussian RBF columns, the core of
// the `bayes` solver and of the hybrid model (MacKay 1992; Tipping 2001; Bishop, PRML s3.5):
//
//   y = F v + Phi w + e,   e ~ N(0, Sigma_0 / beta),   w ~ N(0, I / alpha),   v flat (improper uniform)
//
// with y and the columns whitened by the noise model (Sigma_0 = I for white noise; noise/state_space.h for
// coloured). F holds the columns with a flat prior (the constant, the hybrid's physics terms); they are
// integrated out exactly by projecting onto the complement of their span (thin QR of F, P columns):
//
//   Phi_p = Q Phi,  y_p = Q y,  Q = I - Q_F Q_F',   N' = N - P
//   S = Phi_p' Phi_p = V diag(lambda) V',  A = alpha I + beta S,  m = beta A^-1 Phi_p' y_p
//   2 log p(y) = M log alpha + N' log beta - beta E_D - alpha |m|^2 - sum log(alpha + beta lambda_i)
//                - N' log 2 pi - 2 log|R_F| - log|Sigma_0|,      E_D = |y_p - Phi_p m|^2
//
// For fixed columns, (alpha, beta) maximise this by MacKay's fixed point (gamma = sum beta lambda/(alpha +
// beta lambda); alpha = gamma/|m|^2; beta = (N' - gamma)/E_D), O(M) per step in the eigenbasis of S. The
// gradient with respect to Phi at that optimum (envelope theorem) is
//
//   dL/dPhi = beta (e m' - Phi_p A^-1),   e = y_p - Phi_p m,
//
// and through the Gaussian columns dL/d log r_k = sum_ij G_ij Phi_ij 2 u_ijk^2 (model/gaussian_node.h), with
// G = W' dL/dPhi_w the whitener's adjoint for coloured noise. Cost O(N M^2) per evaluation; no N x N matrix.
#pragma once

#include <Eigen/Core>

#include <optional>

#include "noise/state_space.h"

namespace gyrosid {

inline constexpr double kLog2Pi = 1.8378770664093454836;  // log(2 pi), of every Gaussian log density

// Precision bounds keep the eigen-solution meaningful: alpha / beta above round-off of S's largest
// eigenvalue, and beta below the scale at which E_D is round-off (targets have unit RMS).
struct EvidenceBounds {
  double min_log_alpha = std::log(1e-9), max_log_alpha = std::log(1e9);
  double min_log_beta = std::log(1e-6), max_log_beta = std::log(1e12);
};

struct Precisions {
  double log_alpha = 0.0, log_beta = 0.0;
};

// The fixed (flat-prior) part of a problem and the target, whitened and ready for projection. Depends on the
// noise model only, not on the widths.
class FixedPart {
 public:
  // f: N x P fixed columns, y: N target, both in recording rows; whitener: nullptr for white noise.
  FixedPart(const Eigen::MatrixXd& f, const Eigen::VectorXd& y, const Whitener* whitener);

  Eigen::Index samples() const { return y_p_.size(); }
  Eigen::Index columns() const { return q_.cols(); }
  const Whitener* whitener() const { return whitener_; }
  // Whitens (if coloured) and projects columns off the fixed span, in place: Q W x.
  void project(Eigen::MatrixXd& x) const;
  const Eigen::VectorXd& y_projected() const { return y_p_; }
  // Q_F' (W y) and R_F: the fixed weights given the RBF weights w are R_F^-1 (qy - Q_F' W Phi w).
  const Eigen::MatrixXd& q() const { return q_; }
  const Eigen::MatrixXd& r() const { return r_; }
  const Eigen::VectorXd& qy() const { return qy_; }
  // -2 log|R_F| - log|Sigma_0|: the evidence's terms that depend on the noise model but not on the RBF part.
  double log_determinant_terms() const { return log_det_terms_; }

 private:
  const Whitener* whitener_;
  Eigen::MatrixXd q_, r_;
  Eigen::VectorXd qy_, y_p_;
  double log_det_terms_ = 0.0;
};

// The evidence of the RBF part for one set of (projected) columns, with (alpha, beta) at their optimum.
class RbfEvidence {
 public:
  // phi_p: N x M columns already through FixedPart::project.
  RbfEvidence(const Eigen::MatrixXd& phi_p, const FixedPart& fixed);

  // Maximises over (alpha, beta) from `start` (MacKay's fixed point); returns the log evidence.
  double optimise(Precisions start, const EvidenceBounds& bounds = {});
  // The log evidence at given precisions (no optimisation).
  double log_evidence(const Precisions& p) const;

  const Precisions& precisions() const { return at_; }
  double value() const { return value_; }
  double gamma() const;                    // effective number of RBF parameters
  Eigen::VectorXd mean() const;            // m, the RBF weights' posterior mean
  Eigen::MatrixXd covariance() const;      // A^-1 (M x M)
  // dL/dPhi_p = beta (e m' - Phi_p A^-1) (N x M), at the current precisions; y_p = FixedPart::y_projected().
  Eigen::MatrixXd gradient_wrt_columns(const Eigen::MatrixXd& phi_p, const Eigen::VectorXd& y_p) const;

 private:
  struct Terms {
    double e_d, e_w, log_det, gamma;
  };
  Terms terms(double alpha, double beta) const;

  Eigen::Index n_;   // N' = N - P
  Eigen::VectorXd lambda_, bt_, c_;  // eigenvalues of S, V' Phi_p' y_p, bt^2/lambda (0 where lambda ~ 0)
  Eigen::MatrixXd v_;
  double r0_ = 0.0;  // |y_p|^2 outside the span of Phi_p
  double fixed_terms_ = 0.0;
  Precisions at_;
  double value_ = -INFINITY;
};

// Gradient of the log evidence with respect to the log widths shared by every node (per input), from
// dL/dPhi (N x M, recording rows, after the whitener's adjoint) and the unwhitened columns phi.
Eigen::VectorXd log_width_gradient(const Eigen::MatrixXd& dl_dphi, const Eigen::MatrixXd& phi, const Eigen::MatrixXd& x,
                                   const Eigen::MatrixXd& centres, const Eigen::RowVectorXd& widths);

}  // namespace gyrosid
