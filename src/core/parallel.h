// Splits [0, count) into contiguous chunks run on up to worker_threads() threads: set_worker_threads(n)
// (`gyrosid --threads n`), else GYROSID_THREADS from the environment, else hardware_concurrency(). Each index is processed exactly once and chunks never share outputs, so results are
// bit-identical whatever the thread count.
#pragma once

#include <cstddef>
#include <functional>

namespace gyrosid {

int worker_threads();
void set_worker_threads(int threads);  // 0: back to the environment / hardware default
void parallel_for(std::ptrdiff_t count, const std::function<void(std::ptrdiff_t begin, std::ptrdiff_t end)>& body,
                  std::ptrdiff_t min_chunk = 1);

}  // namespace gyrosid
