// Candidate node centres for forward selection: all training points, or a space-filling subset chosen by
// greedy farthest-point sampling (deterministic: starts from the point nearest the centroid, ties to the
// lower index). A candidate set bounds the N x M candidate matrix of the OLS family (M = N for 11,110 samples
// would be a 1 GB matrix - where the thesis's Matlab ran out of memory).
#pragma once

#include <Eigen/Core>

#include "model/gaussian_node.h"

#include <string>
#include <vector>

namespace gyrosid {

// Row indices of x (normalised inputs) to use as candidates; count <= 0 or >= N selects every distinct row.
// Duplicate rows are never returned twice.
std::vector<Eigen::Index> select_candidates(const Eigen::MatrixXd& x, int count);

// The rows `rows` of x, as a matrix.
Eigen::MatrixXd rows_of(const Eigen::MatrixXd& x, const std::vector<Eigen::Index>& rows);

// Widths of every node: `width` for all inputs, or `per_input` when given (one per input).
Eigen::RowVectorXd node_widths(double width, const std::vector<double>& per_input, Eigen::Index dimension);

// Parses "0.2,0.5" into {0.2, 0.5}; Error naming `what` on bad input.
std::vector<double> parse_list(const std::string& text, const std::string& what);
// For validate(): "" when `text` parses as a list of positive numbers, else the message naming option `key`.
std::string check_positive_list(const std::string& text, const std::string& key);

}  // namespace gyrosid
