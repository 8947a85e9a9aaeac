// gyrosid surface: the model's estimated error surface against the sensor's true one (thesis Tables
// 5.2/5.3, figs 5.6-5.8).
#include <array>
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>

#include "cli/app.h"
#include "core/builtin_configs.h"
#include "core/error.h"
#include "core/format.h"
#include "pipeline/surface_job.h"
#include "report/surface_report.h"
#include "solvers/common/candidates.h"

namespace gyrosid::cli {
namespace {

struct SurfaceOptions {
  std::string model, sensor = kDefaultSensor, out, temp_range, rate_range, points;
};

// "lo,hi" as two numbers; none for an empty option.
std::optional<std::array<double, 2>> two_numbers(const std::string& text, const char* what, const char* expected) {
  if (text.empty()) return std::nullopt;
  const auto v = parse_list(text, what);
  if (v.size() != 2) fail(what, ": expected two values ", expected);
  return std::array<double, 2>{v[0], v[1]};
}

SurfaceJobInput job_input(const SurfaceOptions& o) {
  SurfaceJobInput in;
  in.model = o.model, in.sensor = o.sensor;
  in.temp_range_c = two_numbers(o.temp_range, "--temp-range", "lo,hi");
  in.rate_range_dps = two_numbers(o.rate_range, "--rate-range", "lo,hi");
  if (const auto points = two_numbers(o.points, "--points", "(temperatures,rates)")) {
    for (double n : *points) {
      if (!(n >= 2 && n <= 10000 && n == std::floor(n))) fail("--points: expected whole numbers from 2 to 10000, found ", n);
    }
    in.points = std::array<int, 2>{static_cast<int>((*points)[0]), static_cast<int>((*points)[1])};
  }
  return in;
}

void run_surface(const SurfaceOptions& o) {
  const SurfaceJobInput in = job_input(o);
  const SurfaceJobResult r = run_surface_job(in);
  const SurfaceGridSpec& grid = r.grid;
  const SurfaceComparison& c = r.comparison;
  write_surface_report(o.out, surface_json(in.model, in.sensor, *r.model, grid, c), *r.model, c);
  std::cout << "wrote " << o.out << "/surface.json, surface.csv and plots; estimated - true over T ["
            << grid.temp_min_c << ", " << grid.temp_max_c << "] C x omega [" << grid.rate_min_dps << ", " << grid.rate_max_dps
            << "] deg/s: mean " << format_significant(c.stats.mean_dph, 3) << ", sigma " << format_significant(c.stats.sigma_dph, 3)
            << ", max " << format_significant(c.stats.max_dph, 3) << ", min " << format_significant(c.stats.min_dph, 3)
            << ", rms " << format_significant(c.stats.rms_dph, 3) << " deg/h";
  if (c.sigma_dph.size() > 0) {
    std::cout << "; predictive sigma rms " << format_significant(c.sigma_stats.rms_sigma_dph, 3) << " deg/h, 95 % band covers "
              << format_significant(100 * c.sigma_stats.coverage_95, 3) << " % of the grid";
  }
  std::cout << "\n";
}

}  // namespace

void register_surface(CLI::App& app, Action& action) {
  auto o = std::make_shared<SurfaceOptions>();
  CLI::App* cmd = app.add_subcommand("surface", "Estimated vs true error surface of a model on a dense (T, omega) grid");
  cmd->add_option("--model", o->model, "Model file written by calibrate")->required();
  cmd->add_option("--sensor", o->sensor, "Sensor config holding the true error model")->capture_default_str();
  cmd->add_option("--temp-range", o->temp_range, "lo,hi in C (default: the training temperatures within the sensor's grid)");
  cmd->add_option("--rate-range", o->rate_range, "lo,hi in deg/s (default -100,100)");
  cmd->add_option("--points", o->points, "grid points: temperatures,rates (default 81,101)");
  cmd->add_option("--out", o->out, "Output directory: surface.json, surface.csv, PNG plots (sigma.png: the predictive sigma map of a model with a posterior)")->required();
  cmd->footer("Statistics of estimated - true, in deg/h, as the thesis's Tables 5.2/5.3: mean, sigma, max, min (and rms).");
  cmd->callback([o, &action] { action = [o] { run_surface(*o); }; });
}

}  // namespace gyrosid::cli
