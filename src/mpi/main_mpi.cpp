// gyrosid-mpi: the gyrosid command spread over MPI processes. Monte Carlo runs (and every other index-parallel
// batch going through core/distributed.h) are shared among the processes; the first process writes every
// result and prints, the others stay silent; results equal those of `gyrosid` bit for bit.
//
//   mpirun -np 4 gyrosid-mpi cof --model rbf.json --trajectory long --monte-carlo 10000 --out cof_long/
#include <mpi.h>

#include <cstdio>
#include <memory>

#include "cli/app.h"
#include "core/parallel.h"
#include "mpi/mpi_rows.h"

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  gyrosid::set_worker_threads(gyrosid::threads_per_process(MPI_COMM_WORLD));  // --threads still overrides
  gyrosid::set_row_distributor(std::make_unique<gyrosid::MpiRowDistributor>(MPI_COMM_WORLD));
  if (rank != 0) {
    // Only the first process reports; the others compute. (Errors are the same on every process.)
    if (!std::freopen("/dev/null", "w", stdout) || !std::freopen("/dev/null", "w", stderr)) return 3;
  }
  const int status = gyrosid::cli::main(argc, argv);
  gyrosid::set_row_distributor(nullptr);
  MPI_Finalize();
  return status;
}
