#include "core/distributed.h"

#include "core/parallel.h"

namespace gyrosid {

namespace {
std::unique_ptr<RowDistributor>& installed() {
  static std::unique_ptr<RowDistributor> d;
  return d;
}
}  // namespace

void set_row_distributor(std::unique_ptr<RowDistributor> distributor) { installed() = std::move(distributor); }

std::vector<double> map_rows(int begin, int end, int width, const RowFill& fill) {
  std::vector<double> out(static_cast<std::size_t>(std::max(0, end - begin) * width));
  if (end <= begin) return out;
  if (installed()) {
    installed()->compute(begin, end, width, fill, out.data());
  } else {
    parallel_for(end - begin, [&](std::ptrdiff_t b, std::ptrdiff_t e) {
      for (std::ptrdiff_t i = b; i < e; ++i) fill(begin + static_cast<int>(i), out.data() + i * width);
    });
  }
  return out;
}

int parallel_width() { return (installed() ? installed()->processes() : 1) * worker_threads(); }

bool is_output_process() { return !installed() || installed()->rank() == 0; }

}  // namespace gyrosid
