// Non-negative least squares, min ||A x - b||_2 subject to x >= 0 (Lawson & Hanson 1974, ch. 23), for the
// small dense problems of noise-coefficient fitting. Each passive-set solve uses Householder QR.
#pragma once

#include <Eigen/Dense>

namespace gyrosid {

Eigen::VectorXd nnls(const Eigen::MatrixXd& a, const Eigen::VectorXd& b);

}  // namespace gyrosid
