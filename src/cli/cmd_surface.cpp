// gyrosid surface: the model's estimated error surface against the sensor's true one (thesis Tables
// 5.2/5.3, figs 5.6-5.8).
#include <cmath>
#include <fstream>
#include <iostream>
#include <memory>

#include "cli/app.h"
#include "core/builtin_configs.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"
#include "core/units.h"
#include "model/rbf_network.h"
#include "model/surface_comparison.h"
#include "report/plots.h"
#include "sensor/error_surface.h"
#include "sensor/sensor_config.h"
#include "solvers/common/candidates.h"

namespace gyrosid::cli {
namespace {

struct SurfaceOptions {
  std::string model, sensor = kDefaultSensor, out, temp_range, rate_range, points;
};

// The comparison grid: the options where given, else the temperatures the model was trained on (within the
// sensor's surface grid) and the thesis's rates.
SurfaceGridSpec surface_grid(const SurfaceOptions& o, const GyroSensor& truth, const nlohmann::json& model_json) {
  SurfaceGridSpec grid = comparison_grid(truth, {model_json.value("training", nlohmann::json::object())});
  auto pair = [](const std::string& text, const char* what, double& lo, double& hi) {
    if (text.empty()) return;
    const auto v = parse_list(text, what);
    if (v.size() != 2) fail(what, ": expected two values lo,hi");
    lo = v[0], hi = v[1];
  };
  pair(o.temp_range, "--temp-range", grid.temp_min_c, grid.temp_max_c);
  pair(o.rate_range, "--rate-range", grid.rate_min_dps, grid.rate_max_dps);
  if (!o.points.empty()) {
    const auto v = parse_list(o.points, "--points");
    if (v.size() != 2) fail("--points: expected two values (temperatures,rates)");
    for (double n : v) {
      if (!(n >= 2 && n <= 10000 && n == std::floor(n))) fail("--points: expected whole numbers from 2 to 10000, found ", n);
    }
    grid.temp_points = static_cast<int>(v[0]), grid.rate_points = static_cast<int>(v[1]);
  }
  return grid;
}

void write_surface_csv(const std::filesystem::path& path, const SurfaceComparison& c) {
  const Eigen::MatrixXd diff = c.difference_dph();
  write_file_atomic(path, [&](std::ostream& out) {
    const bool sigma = c.sigma_dph.size() > 0;
    out << "temp_c,rate_dps,measured_rate_dps,true_dph,estimated_dph,difference_dph" << (sigma ? ",sigma_dph" : "") << "\n";
    for (std::size_t i = 0; i < c.temps_c.size(); ++i)
      for (std::size_t j = 0; j < c.rates_dps.size(); ++j) {
        const auto ii = static_cast<Eigen::Index>(i), jj = static_cast<Eigen::Index>(j);
        const double measured = c.rates_dps[j] + c.true_dph(ii, jj) / units::kSecondsPerHour;  // true rate + true error (deg/h -> deg/s)
        out << format_number(c.temps_c[i]) << ',' << format_number(c.rates_dps[j]) << ',' << format_number(measured) << ','
            << format_number(c.true_dph(ii, jj)) << ',' << format_number(c.estimated_dph(ii, jj)) << ',' << format_number(diff(ii, jj));
        if (sigma) out << ',' << format_number(c.sigma_dph(ii, jj));
        out << '\n';
      }
  });
}

void plot_surfaces(const std::filesystem::path& dir, const SurfaceComparison& c, const CalibrationModel& model) {
  plot_grid_surface(dir / "true_surface.png", c.temps_c, c.rates_dps, c.true_dph, "True error surface", "error (deg/h)");
  plot_grid_surface(dir / "estimated_surface.png", c.temps_c, c.rates_dps, c.estimated_dph,
                    "Estimated error surface (" + std::string(model.kind()) + ")", "error (deg/h)");
  plot_grid_surface(dir / "difference.png", c.temps_c, c.rates_dps, c.difference_dph(),
                    "Estimated - true (rms " + format_significant(c.stats.rms_dph, 3) + " deg/h)", "difference (deg/h)");
  if (c.sigma_dph.size() > 0) {
    plot_grid_surface(dir / "sigma.png", c.temps_c, c.rates_dps, c.sigma_dph,
                      "Predictive sigma of the estimate (rms " + format_significant(c.sigma_stats.rms_sigma_dph, 3) + " deg/h; 95 % band covers " +
                          format_significant(100 * c.sigma_stats.coverage_95, 3) + " % of |estimated - true|)",
                      "sigma (deg/h)");
  }
  const auto* rbf = dynamic_cast<const RbfNetwork*>(&model);
  if (!rbf) return;
  // Node centres back in physical units (rate in deg/s, temperature in C) where the inputs allow.
  const auto& f = rbf->features();
  if (f.size() < 2 || f[0] != "measured_rate" || f[1] != "temperature") return;
  std::vector<std::array<double, 2>> nodes;
  for (Eigen::Index n = 0; n < rbf->nodes(); ++n) {
    const double w = rbf->centres(n, 0) * rbf->normalizer.scale(0) + rbf->normalizer.offset(0);
    const double t = rbf->centres(n, 1) * rbf->normalizer.scale(1) + rbf->normalizer.offset(1);
    nodes.push_back({units::radps_to_dps(w), t});
  }
  plot_nodes(dir / "nodes.png", c.temps_c, c.rates_dps, c.estimated_dph, nodes, "Node placement on the estimated surface");
}

void run_surface(const SurfaceOptions& o) {
  const auto model = load_model(o.model);
  nlohmann::json model_json;
  {
    std::ifstream in(o.model);
    in >> model_json;
  }
  const SensorSpec spec = load_sensor_file(o.sensor);
  const GyroSensor& truth = representative_gyro(spec);
  const SurfaceGridSpec grid = surface_grid(o, truth, model_json);
  const SurfaceComparison c = compare_surfaces(*model, truth, grid);
  const std::filesystem::path dir = o.out;
  write_surface_csv(dir / "surface.csv", c);
  nlohmann::json j = {{"model", o.model}, {"kind", model->kind()}, {"sensor", o.sensor},
                      {"grid", {{"temp_c", {grid.temp_min_c, grid.temp_max_c}}, {"rate_dps", {grid.rate_min_dps, grid.rate_max_dps}},
                                {"points", {grid.temp_points, grid.rate_points}}}},
                      {"difference", c.stats.to_json()}};
  if (c.sigma_dph.size() > 0) j["sigma"] = c.sigma_stats.to_json();
  if (const auto* rbf = dynamic_cast<const RbfNetwork*>(model.get())) j["nodes"] = rbf->nodes();
  write_file_atomic(dir / "surface.json", j.dump(2) + "\n");
  plot_surfaces(dir, c, *model);
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
