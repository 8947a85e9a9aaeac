#include "core/parallel.h"

#include <algorithm>
#include <cstdlib>
#include <exception>
#include <thread>
#include <vector>

namespace gyrosid {

namespace {
int threads_override = 0;
}  // namespace

void set_worker_threads(int threads) { threads_override = threads > 0 ? threads : 0; }

int worker_threads() {
  if (threads_override > 0) return threads_override;
  if (const char* env = std::getenv("GYROSID_THREADS")) {
    const int n = std::atoi(env);
    if (n >= 1) return n;
  }
  return std::max(1u, std::thread::hardware_concurrency());
}

void parallel_for(std::ptrdiff_t count, const std::function<void(std::ptrdiff_t, std::ptrdiff_t)>& body,
                  std::ptrdiff_t min_chunk) {
  if (count <= 0) return;
  const std::ptrdiff_t threads = std::min<std::ptrdiff_t>(worker_threads(), std::max<std::ptrdiff_t>(1, count / std::max<std::ptrdiff_t>(1, min_chunk)));
  if (threads <= 1) {
    body(0, count);
    return;
  }
  std::vector<std::thread> pool;
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(threads));
  const std::ptrdiff_t chunk = (count + threads - 1) / threads;
  for (std::ptrdiff_t t = 0; t < threads; ++t) {
    const std::ptrdiff_t begin = t * chunk, end = std::min(count, begin + chunk);
    if (begin >= end) break;
    pool.emplace_back([&, t, begin, end] {
      try {
        body(begin, end);
      } catch (...) {
        errors[static_cast<std::size_t>(t)] = std::current_exception();
      }
    });
  }
  for (auto& th : pool) th.join();
  for (auto& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace gyrosid
