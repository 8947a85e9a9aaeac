#include "report/surface_report.h"

#include "core/atomic_file.h"
#include "core/format.h"
#include "core/units.h"
#include "model/rbf_network.h"
#include "report/plots.h"

namespace gyrosid {
namespace {

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

}  // namespace

nlohmann::json surface_json(const std::string& model_file, const std::string& sensor, const CalibrationModel& model, const SurfaceGridSpec& grid,
                            const SurfaceComparison& c) {
  nlohmann::json j = {{"model", model_file}, {"kind", model.kind()}, {"sensor", sensor},
                      {"grid", {{"temp_c", {grid.temp_min_c, grid.temp_max_c}}, {"rate_dps", {grid.rate_min_dps, grid.rate_max_dps}},
                                {"points", {grid.temp_points, grid.rate_points}}}},
                      {"difference", c.stats.to_json()}};
  if (c.sigma_dph.size() > 0) j["sigma"] = c.sigma_stats.to_json();
  if (const auto* rbf = dynamic_cast<const RbfNetwork*>(&model)) j["nodes"] = rbf->nodes();
  return j;
}

void write_surface_report(const std::filesystem::path& dir, const nlohmann::json& summary, const CalibrationModel& model, const SurfaceComparison& c) {
  write_surface_csv(dir / "surface.csv", c);
  write_file_atomic(dir / "surface.json", summary.dump(2) + "\n");
  plot_surfaces(dir, c, model);
}

}  // namespace gyrosid
