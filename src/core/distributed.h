// Index-parallel work whose result per index is a fixed-size row of doubles (a Monte Carlo run's error
// components, a sweep point's figures), computed by this process's threads or - when a distributor is
// installed, as `gyrosid-mpi` does - across processes. Every caller receives every row, in index order, so
// what follows (stopping rules, statistics) runs identically everywhere and the result does not depend on how
// many threads or processes computed it.
#pragma once

#include <functional>
#include <memory>
#include <vector>

namespace gyrosid {

// fill(index, row): writes the `width` values of one index into row. Called concurrently for different indices.
using RowFill = std::function<void(int index, double* row)>;

class RowDistributor {
 public:
  virtual ~RowDistributor() = default;
  virtual int processes() const = 0;
  virtual int rank() const = 0;
  // Rows [begin, end) into out ((end - begin) x width, row-major), on every process.
  virtual void compute(int begin, int end, int width, const RowFill& fill, double* out) = 0;
};

// Installs a process-wide distributor (nullptr: back to this process's threads).
void set_row_distributor(std::unique_ptr<RowDistributor> distributor);

// Rows [begin, end) of `width` values each, row-major, by the installed distributor or by parallel_for.
std::vector<double> map_rows(int begin, int end, int width, const RowFill& fill);

// Indices computed at once: processes x worker threads (batch sizes scale with it).
int parallel_width();
// Only the first process writes result files and prints (write_file_atomic skips writes elsewhere).
bool is_output_process();

}  // namespace gyrosid
