// Throughput of the sensor simulation and of the Allan deviation.
//   build/tests/benchmarks/bench_sensor --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include "core/random.h"
#include "noise/allan.h"
#include "sensor/sensor_config.h"
#include "sim/simulate.h"

namespace {

using namespace gyrosid;

// Simulating the reference FOG along the dual scan (11,110 samples, exact thermal lag, surface, noise).
void BM_SimulateDualScan(benchmark::State& state) {
  const SensorSpec sensor = load_sensor_file("builtin:sensors/open_loop_fog.yaml");
  TrajectorySpec trajectory = load_trajectory_file("builtin:trajectories/dual_scan.yaml");
  trajectory.sampling = Sampling{static_cast<std::size_t>(state.range(0)), 0.0};
  for (auto _ : state) {
    Simulation s = simulate(sensor, trajectory, 1);
    benchmark::DoNotOptimize(s.recording.rows());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_SimulateDualScan)->Arg(11110)->Arg(111100)->Unit(benchmark::kMillisecond);

// Overlapping Allan deviation of N white-noise samples (10 points per decade up to N/3).
void BM_AllanDeviation(benchmark::State& state) {
  RandomStream random(1, "bench");
  std::vector<double> rate(static_cast<std::size_t>(state.range(0)));
  for (double& r : rate) r = random.normal();
  for (auto _ : state) {
    auto curve = overlapping_allan_deviation(rate, 0.01);
    benchmark::DoNotOptimize(curve.data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_AllanDeviation)->Arg(100000)->Arg(3600000)->Unit(benchmark::kMillisecond);

}  // namespace
