// Training time of every RBF solver against the number of samples N (noise-free dense test trajectory of
// the reference sensor, resampled to N). Peak memory per solver and N is measured in separate processes by
// experiments/solver_scaling (a process's peak RSS cannot be attributed to one benchmark inside another).
//   build/tests/benchmarks/bench_solvers --benchmark_filter=ols
#include <benchmark/benchmark.h>

#include <map>

#include "sim/simulate.h"
#include "solvers/solver.h"

namespace {

using namespace gyrosid;

const RbfProblem& problem(std::size_t n) {
  static std::map<std::size_t, RbfProblem> cache;
  auto it = cache.find(n);
  if (it == cache.end()) {
    const SensorSpec sensor = without_noise(load_sensor_file("builtin:sensors/open_loop_fog.yaml"));
    TrajectorySpec t = load_trajectory_file("builtin:trajectories/test_4x16.yaml");
    t.sampling = Sampling{n, 0.0};
    const Simulation s = simulate(sensor, t, 1);
    it = cache.emplace(n, make_rbf_problem(make_dataset(s.recording, default_features(), ModelTarget::error),
                                           NormalizationKind::range)).first;
  }
  return it->second;
}

void train(benchmark::State& state, const std::string& solver, const OptionMap& options) {
  const RbfProblem& p = problem(static_cast<std::size_t>(state.range(0)));
  int nodes = 0;
  for (auto _ : state) {
    RbfNetwork net = p.empty_network();
    nodes = gyrosid::train(*make_solver(solver, options), p, net).details["nodes"].get<int>();
  }
  state.counters["nodes"] = nodes;
  state.counters["samples_per_s"] = benchmark::Counter(static_cast<double>(state.range(0)), benchmark::Counter::kIsIterationInvariantRate);
}

void sizes(benchmark::internal::Benchmark* b) {
  for (long n : {1000, 3000, 10000, 30000, 100000}) b->Arg(n);
  b->Unit(benchmark::kMillisecond)->Iterations(1);
}

BENCHMARK_CAPTURE(train, ols, std::string("ols"), OptionMap{{"width", "0.25"}})->Apply(sizes);
BENCHMARK_CAPTURE(train, lrols_loo, std::string("lrols_loo"), OptionMap{{"width", "0.25"}})->Apply(sizes);
BENCHMARK_CAPTURE(train, ofs_loo, std::string("ofs_loo"), OptionMap{{"max_nodes", "60"}})->Apply(sizes);
BENCHMARK_CAPTURE(train, nlopt, std::string("nlopt"), OptionMap{{"evaluations", "20"}})->Apply(sizes);
BENCHMARK_CAPTURE(train, ceres, std::string("ceres"), OptionMap{{"init.max_nodes", "60"}, {"max_iterations", "30"}})->Apply(sizes);
BENCHMARK_CAPTURE(train, ipopt, std::string("ipopt"), OptionMap{{"nodes", "60"}, {"max_iterations", "30"}})->Apply(sizes);

}  // namespace
