#include "mpi/mpi_rows.h"

#include <algorithm>
#include <thread>
#include <vector>

#include "core/error.h"
#include "core/parallel.h"

namespace gyrosid {

MpiRowDistributor::MpiRowDistributor(MPI_Comm comm) : comm_(comm) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
}

void MpiRowDistributor::compute(int begin, int end, int width, const RowFill& fill, double* out) {
  const int count = end - begin;
  // Block p holds indices [first(p), first(p + 1)): the first count % size blocks one longer.
  auto first = [&](int p) { return begin + p * (count / size_) + std::min(p, count % size_); };
  std::vector<int> counts(static_cast<std::size_t>(size_)), offsets(static_cast<std::size_t>(size_));
  for (int p = 0; p < size_; ++p) {
    counts[static_cast<std::size_t>(p)] = (first(p + 1) - first(p)) * width;
    offsets[static_cast<std::size_t>(p)] = (first(p) - begin) * width;
  }
  const int mine_begin = first(rank_), mine = first(rank_ + 1) - mine_begin;
  std::vector<double> block(static_cast<std::size_t>(std::max(1, mine * width)));
  parallel_for(mine, [&](std::ptrdiff_t b, std::ptrdiff_t e) {
    for (std::ptrdiff_t i = b; i < e; ++i) fill(mine_begin + static_cast<int>(i), block.data() + i * width);
  });
  const int status = MPI_Allgatherv(block.data(), mine * width, MPI_DOUBLE, out, counts.data(), offsets.data(), MPI_DOUBLE, comm_);
  if (status != MPI_SUCCESS) fail("MPI_Allgatherv failed (status ", status, ")");
}

int threads_per_process(MPI_Comm comm) {
  MPI_Comm node;
  MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
  int on_node = 1;
  MPI_Comm_size(node, &on_node);
  MPI_Comm_free(&node);
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()) / on_node);
}

}  // namespace gyrosid
