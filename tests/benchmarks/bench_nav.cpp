// Strapdown INS throughput and Monte Carlo criterion-of-fit cost.
//   build/tests/benchmarks/bench_nav --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include "nav/criterion_of_fit.h"
#include "nav/monte_carlo.h"
#include "nav/strapdown.h"
#include "sensor/sensor_config.h"
#include "sim/simulate.h"
#include "solvers/calibrate.h"

namespace {

using namespace gyrosid;

// The 2-h UAV flight at 100 Hz (750,000 steps) through the INS, single thread. Target: >= 3 M steps/s
// (the whole flight in under 0.25 s).
void BM_InsLongFlight(benchmark::State& state) {
  static const FlightTrajectory f = generate_flight(builtin_flight("long"), 100.0);
  for (auto _ : state) {
    nav::StrapdownIns ins(f.initial(), f.dt_s);
    for (std::size_t k = 0; k < f.steps(); ++k) ins.step(f.dtheta[k], f.dv[k]);
    benchmark::DoNotOptimize(ins.state().lat);
  }
  state.counters["steps_per_s"] = benchmark::Counter(static_cast<double>(f.steps()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_InsLongFlight)->Unit(benchmark::kMillisecond);

// 1000 Monte Carlo runs of the short flight with the calibration held fixed (an RBF trained by the
// ceres solver on the noise-free dual scan), on all cores. Target: under 10 s on 2 cores.
void BM_MonteCarloShort1000(benchmark::State& state) {
  static const FlightTrajectory f = generate_flight(builtin_flight("short"), 100.0);
  static const SensorSpec sensor = load_sensor_file("builtin:sensors/open_loop_fog.yaml");
  static const CalibrationResult model = [] {
    TrajectorySpec t = load_trajectory_file("builtin:trajectories/dual_scan.yaml");
    const Simulation s = simulate(without_noise(sensor), t, 1);
    CalibrationRequest r;
    r.solver = "ceres";
    r.options = {{"init.max_nodes", "60"}};
    return calibrate(s.recording, r);
  }();
  const nav::CofEvaluator cof(f, as_triad(sensor), model.model.get(), nav::CofOptions{});
  nav::MonteCarloOptions o;
  o.runs = 1000;
  for (auto _ : state) {
    const auto r = nav::monte_carlo([&](int i) { return cof.decompose(cof.run(nav::CompensationMode::model, true, static_cast<std::uint64_t>(i)).error_ned); }, o);
    benchmark::DoNotOptimize(r.sigma_m);
  }
  state.counters["nodes"] = static_cast<double>(model.summary.details["nodes"].get<int>());
}
BENCHMARK(BM_MonteCarloShort1000)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace
