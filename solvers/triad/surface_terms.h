// How one gyro's error surface e_i(T, g) enters the triad's joint least-squares problem (triad_problem.h):
// as linear columns (classical: its coefficients) and/or as Gaussian nodes (RBF: packed [c, log r, w]
// blocks, model/gaussian_node.h). Terms whose columns would duplicate the triad's own parameters leave them
// out: the classical term has no bias polynomial (b_i(T) is the triad's) and no constant scale factor
// (that is M_ii), so the joint problem stays identifiable.
#pragma once

#include <Eigen/Core>

#include <memory>
#include <vector>

#include "model/classical_model.h"
#include "model/rbf_network.h"

namespace gyrosid {

class SurfaceTerm {
 public:
  virtual ~SurfaceTerm() = default;

  // Linear part: columns at one sample (measured rate rad/s, temperature deg C), and their start values.
  virtual int linear_size() const { return 0; }
  virtual void linear_columns(double rate, double temp_c, double* out) const;
  virtual std::vector<double> linear_start() const { return {}; }

  // Nonlinear part: node j's packed block; output w phi(x) of one node at the input vector x, with its
  // gradient by the block when `gradient` is not null.
  virtual int nodes() const { return 0; }
  virtual int node_size() const { return 0; }
  virtual std::vector<double> node_start(int j) const;
  virtual int input_size() const { return 0; }
  virtual void inputs(double rate, double temp_c, double* x) const;
  virtual double node_output(const double* x, const double* block, double* gradient) const;
  // P (rows x nodes) and t: the joint cost gains |P w - t|^2 for the node weights w (the last entry of each
  // block) - the surface fitter's own regularisation and what holds the surface's share of the triad's
  // columns; P empty when there is none.
  virtual const Eigen::MatrixXd& weight_penalty() const;
  virtual const Eigen::VectorXd& weight_target() const;

  // The fitted surface as a single-gyro model (features measured_rate, temperature; target error).
  virtual std::shared_ptr<CalibrationModel> model(const std::vector<double>& linear,
                                                  const std::vector<std::vector<double>>& nodes) const = 0;
  virtual std::vector<std::string> linear_names() const;
};

// The classical surface [s_T(T) + s_w(g)] g of thesis s5.3.2 without its bias polynomial and constant
// scale factor; rate and temperature scaling from the training samples.
std::unique_ptr<SurfaceTerm> classical_term(const ClassicalOptions& options, const Eigen::VectorXd& rates,
                                            const Eigen::VectorXd& temps);
// An RBF network's nodes, started from `start` (its constant must be zero: the triad's bias holds it, or M_ii
// when its output is multiplied by the measured rate), with the weight penalty |P w - t|^2 (P empty: none; t
// empty: zero). A network with an output factor (rbf_network.h) must take it from the measured rate: its
// nodes' columns are then g phi_j(T, g).
std::unique_ptr<SurfaceTerm> rbf_term(const RbfNetwork& start, Eigen::MatrixXd penalty = {}, Eigen::VectorXd target = {});

// Orr's global ridge as the OLS fitter applied it (solvers/ols/forward_selection.h): lambda |g|^2 on the
// weights g of the selected columns orthogonalised in selection order, H = W U with U unit upper triangular,
// so g = U w. From the Householder QR H = Q R of the node columns H at the fitter's training inputs (N x m),
// U = diag(R)^-1 R and P = sqrt(lambda) U; lambda in the units of the joint cost. Empty for lambda <= 0 or no
// nodes.
Eigen::MatrixXd ols_ridge_penalty(const Eigen::MatrixXd& h, double lambda);

// Rows that measure an RBF surface's share of columns the triad owns (gyro i's own rate, its bias polynomial):
// weight * a_j' H / |a_j| for each column a_j of `owned` (N x p, at the training samples), H the surface's node
// columns there (N x m, as the joint problem's rows see them). An RBF of the rate can mimic M_ii g and one of temperature b(T): left free,
// M_ii and b trade against combinations of weights the noise chooses (the surface then interpolates and
// extrapolates badly). Held at their start values (t = rows * w0) with a weight far above the data's, the
// surface keeps the share the sequential fit gave it and M_ii and b keep theirs.
Eigen::MatrixXd owned_column_rows(const Eigen::MatrixXd& h, const Eigen::MatrixXd& owned, double weight);

}  // namespace gyrosid
