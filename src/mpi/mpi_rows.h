// The MPI row distributor of `gyrosid-mpi` (core/distributed.h): a batch of indices is cut into contiguous
// blocks, one per process, each block computed by that process's threads, and every block gathered onto every
// process (MPI_Allgatherv), so all processes hold the same rows in index order and continue identically.
// The result equals the single-process one bit for bit: each row depends only on its index.
#pragma once

#include <mpi.h>

#include "core/distributed.h"

namespace gyrosid {

class MpiRowDistributor : public RowDistributor {
 public:
  explicit MpiRowDistributor(MPI_Comm comm);
  int processes() const override { return size_; }
  int rank() const override { return rank_; }
  void compute(int begin, int end, int width, const RowFill& fill, double* out) override;

 private:
  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
};

// Worker threads for this process: the node's cores shared among the processes placed on the node.
int threads_per_process(MPI_Comm comm);

}  // namespace gyrosid
