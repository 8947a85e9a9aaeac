#include "model/gaussian_node.h"

#include "core/parallel.h"

namespace gyrosid {

double node_output(const double* x, NodeBlock<const double> node, double* gradient) {
  const Eigen::Index d = node.d;
  const double* c = node.centre();
  const double* rho = node.log_width();
  double z = 0.0;
  for (Eigen::Index k = 0; k < d; ++k) {
    const double u = (x[k] - c[k]) / std::exp(rho[k]);
    z += u * u;
  }
  const double phi = std::exp(-z), w = node.weight(), wphi = w * phi;
  if (gradient) {
    const NodeBlock<double> g{gradient, d};
    for (Eigen::Index k = 0; k < d; ++k) {
      const double r = std::exp(rho[k]), u = (x[k] - c[k]) / r;
      g.centre()[k] = wphi * 2.0 * u / r;
      g.log_width()[k] = wphi * 2.0 * u * u;
    }
    g.weight() = phi;
  }
  return wphi;
}

Eigen::MatrixXd gaussian_columns(const Eigen::MatrixXd& x, const Eigen::MatrixXd& centres, const Eigen::MatrixXd& widths) {
  const Eigen::Index n = x.rows(), m = centres.rows(), d = x.cols();
  Eigen::MatrixXd h(n, m);
  // Row-major copies so each sample, centre and width row is contiguous.
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> xr = x, cr = centres, wr = widths;
  parallel_for(m, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    for (Eigen::Index j = begin; j < end; ++j) {
      for (Eigen::Index i = 0; i < n; ++i) h(i, j) = gaussian(xr.row(i).data(), cr.row(j).data(), wr.row(j).data(), d);
    }
  }, 16);
  return h;
}

Eigen::MatrixXd gaussian_columns(const Eigen::MatrixXd& x, const Eigen::MatrixXd& centres, const Eigen::RowVectorXd& widths) {
  return gaussian_columns(x, centres, Eigen::MatrixXd(widths.replicate(centres.rows(), 1)));
}

}  // namespace gyrosid
