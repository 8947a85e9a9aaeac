#include "solvers/common/candidates.h"

#include <cstdlib>
#include <limits>
#include <set>
#include <sstream>

#include "core/error.h"

namespace gyrosid {

std::vector<Eigen::Index> select_candidates(const Eigen::MatrixXd& x, int count) {
  const Eigen::Index n = x.rows();
  std::vector<Eigen::Index> out;
  if (n == 0) return out;
  if (count <= 0 || count >= n) {
    // Every distinct row, in order.
    std::set<std::vector<double>> seen;
    for (Eigen::Index i = 0; i < n; ++i) {
      std::vector<double> row(static_cast<std::size_t>(x.cols()));
      for (Eigen::Index k = 0; k < x.cols(); ++k) row[static_cast<std::size_t>(k)] = x(i, k);
      if (seen.insert(row).second) out.push_back(i);
    }
    return out;
  }
  const Eigen::RowVectorXd centroid = x.colwise().mean();
  Eigen::Index first = 0;
  (x.rowwise() - centroid).rowwise().squaredNorm().minCoeff(&first);
  Eigen::VectorXd dist = (x.rowwise() - x.row(first)).rowwise().squaredNorm();
  out.push_back(first);
  while (static_cast<int>(out.size()) < count) {
    Eigen::Index next = 0;
    const double far = dist.maxCoeff(&next);
    if (far <= 0.0) break;  // every remaining row duplicates a chosen one
    out.push_back(next);
    dist = dist.cwiseMin((x.rowwise() - x.row(next)).rowwise().squaredNorm());
  }
  return out;
}

Eigen::MatrixXd rows_of(const Eigen::MatrixXd& x, const std::vector<Eigen::Index>& rows) {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(rows.size()), x.cols());
  for (std::size_t j = 0; j < rows.size(); ++j) out.row(static_cast<Eigen::Index>(j)) = x.row(rows[j]);
  return out;
}

Eigen::RowVectorXd node_widths(double width, const std::vector<double>& per_input, Eigen::Index d) {
  Eigen::RowVectorXd r = Eigen::RowVectorXd::Constant(d, width);
  if (!per_input.empty()) {
    if (static_cast<Eigen::Index>(per_input.size()) != d) {
      fail("widths: ", per_input.size(), " values given for ", d, " inputs");
    }
    for (Eigen::Index k = 0; k < d; ++k) r(k) = per_input[static_cast<std::size_t>(k)];
  }
  for (Eigen::Index k = 0; k < d; ++k)
    if (!(r(k) > 0)) fail("widths must be positive");
  return r;
}

std::vector<double> parse_list(const std::string& text, const std::string& what) {
  std::vector<double> out;
  if (text.empty()) return out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0') fail(what, ": '", item, "' is not a number (expected a comma-separated list)");
    out.push_back(v);
  }
  return out;
}

std::string check_positive_list(const std::string& text, const std::string& key) {
  try {
    for (double v : parse_list(text, "option '" + key + "'")) {
      if (!(v > 0)) return str_cat("option '", key, "': every value must be positive, got ", v);
    }
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace gyrosid
