#include "report/plots.h"

#include <cmath>
#include <numbers>

#include "core/error.h"
#include "core/format.h"
#include "core/gnuplot.h"
#include "noise/processes.h"

namespace gyrosid {

void plot_grid_surface(const std::filesystem::path& png, const std::vector<double>& temps, const std::vector<double>& rates,
                       const Eigen::MatrixXd& z, const std::string& title, const std::string& z_label) {
  std::vector<std::vector<double>> rows;
  for (std::size_t i = 0; i < temps.size(); ++i) {
    for (std::size_t j = 0; j < rates.size(); ++j) {
      rows.push_back({rates[j], temps[i], z(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j))});
    }
    rows.push_back({});  // blank line between grid rows (pm3d scan)
  }
  std::string script = datablock("surface", rows);
  script += str_cat("set title ", gnuplot_quote(title), "\n",
                    "set xlabel 'omega (deg/s)'\nset ylabel 'temperature (C)'\nset zlabel ", gnuplot_quote(z_label),
                    " rotate parallel\n",
                    "set pm3d at s\nset palette rgb 33,13,10\nset view 55,35\nset ticslevel 0\n"
                    "set contour base\nset cntrparam levels 12\nunset key\nset grid\n"
                    "splot $surface using 1:2:3 with pm3d\n");
  render_png(png, script);
}

void plot_surface(const std::filesystem::path& png, const std::function<double(double, double)>& error,
                  const SurfaceGridSpec& g, const std::string& title, const std::string& z_label) {
  const std::vector<double> temps = g.temperatures_c(), rates = g.rates_dps();
  Eigen::MatrixXd z(g.temp_points, g.rate_points);
  for (int i = 0; i < g.temp_points; ++i)
    for (int j = 0; j < g.rate_points; ++j) z(i, j) = error(temps[static_cast<std::size_t>(i)], rates[static_cast<std::size_t>(j)]);
  plot_grid_surface(png, temps, rates, z, title, z_label);
}

void plot_nodes(const std::filesystem::path& png, const std::vector<double>& temps, const std::vector<double>& rates,
                const Eigen::MatrixXd& z, const std::vector<std::array<double, 2>>& nodes, const std::string& title) {
  std::vector<std::vector<double>> grid, points;
  for (std::size_t i = 0; i < temps.size(); ++i) {
    for (std::size_t j = 0; j < rates.size(); ++j) {
      grid.push_back({rates[j], temps[i], z(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j))});
    }
    grid.push_back({});
  }
  for (const auto& n : nodes) points.push_back({n[0], n[1]});
  std::string script = datablock("grid", grid) + datablock("nodes", points);
  script += str_cat("set title ", gnuplot_quote(title), "\n",
                    "set xlabel 'omega (deg/s)'\nset ylabel 'temperature (C)'\nset view map\nset pm3d map\n"
                    "set palette rgb 33,13,10\nset contour base\nset cntrparam levels 15\nunset clabel\n"
                    "set xrange [", rates.front(), ":", rates.back(), "]\nset yrange [", temps.front(), ":", temps.back(), "]\n",
                    "set key outside bottom\n",
                    "splot $grid using 1:2:3 with pm3d notitle, \\\n",
                    "      $nodes using 1:2:(0) with points pt 7 ps 0.7 lc rgb 'black' title '", nodes.size(), " nodes'\n");
  render_png(png, script);
}

void plot_coverage(const std::filesystem::path& png, const std::vector<double>& temp_c,
                   const std::vector<double>& rate_dps, const std::string& title, std::size_t highlight) {
  if (temp_c.size() != rate_dps.size()) fail("plot_coverage: ", temp_c.size(), " temperatures for ", rate_dps.size(), " rates");
  std::vector<std::vector<double>> all, first, last;
  const std::size_t n = temp_c.size();
  for (std::size_t i = 0; i < n; ++i) {
    all.push_back({rate_dps[i], temp_c[i]});
    if (i < highlight) first.push_back({rate_dps[i], temp_c[i]});
    if (i + highlight >= n) last.push_back({rate_dps[i], temp_c[i]});
  }
  std::string script = datablock("all", all) + datablock("first", first) + datablock("last", last);
  script += str_cat("set title ", gnuplot_quote(title), "\n",
                    "set xlabel 'omega (deg/s)'\nset ylabel 'temperature at the sensor (C)'\nset grid\nset key outside right\n",
                    "plot $all using 1:2 with points pt 7 ps 0.25 lc rgb '#3060a0' title 'samples (", n, ")', \\\n",
                    "     $first using 1:2 with points pt 6 ps 0.8 lc rgb 'red' title 'first ", first.size(), "', \\\n",
                    "     $last using 1:2 with points pt 6 ps 0.8 lc rgb '#00a000' title 'last ", last.size(), "'\n");
  render_png(png, script);
}

void plot_allan(const std::filesystem::path& png, const std::vector<AllanPoint>& curve, const NoiseIdentification& fit,
                const std::string& title, const std::string& unit) {
  const CompositeNoise& m = fit.model;
  // Columns: tau, adev, ci low, ci high, fitted total, its band low/high, then one per term.
  std::vector<std::vector<double>> data;
  double lo = INFINITY, hi = 0.0;
  for (const auto& p : curve) {
    if (!(p.adev > 0)) continue;
    const double v = fit.allan_variance(p.tau_s), sd = fit.allan_variance_sigma(p.tau_s);
    // The band on the deviation: log-normal, sqrt(v) exp(+-1.96 sd / 2v).
    const double spread = v > 0 ? std::exp(1.96 * sd / (2.0 * v)) : 1.0;
    std::vector<double> row = {p.tau_s, p.adev, p.ci_low, p.ci_high, std::sqrt(v), std::sqrt(v) / spread, std::sqrt(v) * spread};
    row.push_back(std::sqrt(3.0) * m.quantization / p.tau_s);
    row.push_back(m.white / std::sqrt(p.tau_s));
    row.push_back(std::sqrt(kFlickerAllanFactor) * m.flicker);
    row.push_back(m.random_walk * std::sqrt(p.tau_s / 3.0));
    row.push_back(m.ramp * p.tau_s / std::sqrt(2.0));
    for (const auto& gm : m.gauss_markov) row.push_back(std::sqrt(gauss_markov_allan_variance(gm.sigma, gm.tau_s, p.tau_s)));
    data.push_back(row);
    lo = std::min(lo, p.ci_low > 0 ? p.ci_low : p.adev);
    hi = std::max(hi, p.ci_high);
  }
  if (data.empty()) fail(png.string(), ": no positive Allan deviation to plot");
  std::string script = datablock("allan", data);
  script += str_cat("set title ", gnuplot_quote(title), "\n",
                    "set logscale xy\nset grid xtics ytics mxtics mytics\nset format x '%g'\nset format y '%g'\n",
                    "set yrange [", lo / 2.0, ":", hi * 2.0, "]\n",
                    "set xlabel 'averaging time tau (s)'\nset ylabel ", gnuplot_quote("Allan deviation (" + unit + ")"), "\n",
                    "set key bottom left\n");
  if (fit.fit_tau_high_s > 0) {
    script += str_cat("set object 1 rect from first ", fit.fit_tau_low_s, ", graph 0 to first ", fit.fit_tau_high_s,
                      ", graph 1 behind fc rgb '#f4f4f4' fs solid noborder\n");
  }
  script += str_cat("plot $allan using 1:3:4 with filledcurves fc rgb '#d0e0f0' title 'data confidence interval', \\\n",
                    "     $allan using 1:2 with linespoints pt 7 ps 0.5 lc rgb '#1050a0' title 'overlapping ADEV', \\\n",
                    "     $allan using 1:6 with lines lw 1 dt 3 lc rgb 'black' notitle, \\\n",
                    "     $allan using 1:7 with lines lw 1 dt 3 lc rgb 'black' title 'fitted total, 95 % band', \\\n",
                    "     $allan using 1:5 with lines lw 2 lc rgb 'black' title ", gnuplot_quote("fitted " + fit.structure.name() + " (fit band shaded)"));
  const std::vector<std::pair<double, std::string>> terms = {
      {m.quantization, "quantization Q"}, {m.white, "angle random walk N"}, {m.flicker, "bias instability B"},
      {m.random_walk, "rate random walk K"}, {std::abs(m.ramp), "rate ramp R"}};
  const char* colours[] = {"#a000a0", "#d04000", "#008000", "#a06000", "#606060", "#0090c0", "#c00060", "#6040c0"};
  for (std::size_t k = 0; k < terms.size(); ++k) {
    if (terms[k].first > 0) {
      script += str_cat(", \\\n     $allan using 1:", 8 + k, " with lines dt 2 lc rgb '", colours[k], "' title ", gnuplot_quote(terms[k].second));
    }
  }
  for (std::size_t g = 0; g < m.gauss_markov.size(); ++g) {
    script += str_cat(", \\\n     $allan using 1:", 13 + g, " with lines dt 2 lc rgb '", colours[5 + g % 3], "' title ",
                      gnuplot_quote(str_cat("Gauss-Markov, tau ", format_significant(m.gauss_markov[g].tau_s, 3), " s")));
  }
  script += "\n";
  render_png(png, script);
}

}  // namespace gyrosid
