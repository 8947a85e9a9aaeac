// The plots a person would rather look at than read: error surfaces over (T, omega) (thesis figs 3.6,
// 3.12), trajectory coverage of the (T, omega) domain (figs 4.6, 4.9) and Allan deviation with fitted noise
// lines. PNG via gnuplot.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <array>

#include "model/surface_comparison.h"
#include "noise/allan.h"
#include "noise/identify.h"

namespace gyrosid {

// A plotted surface's grid: coarser than a comparison's, for a mesh one can read.
inline const SurfaceGridSpec kPlotSurfaceGrid{.temp_points = 41, .rate_points = 81};

// 3-D surface with a contour map underneath of error(T, omega) in the unit named by `z_label`.
void plot_surface(const std::filesystem::path& png, const std::function<double(double temp_c, double rate_dps)>& error,
                  const SurfaceGridSpec& grid, const std::string& title, const std::string& z_label);

// The same from values on a grid: z(i, j) at (temps[i], rates[j]).
void plot_grid_surface(const std::filesystem::path& png, const std::vector<double>& temps_c,
                       const std::vector<double>& rates_dps, const Eigen::MatrixXd& z, const std::string& title,
                       const std::string& z_label);

// Node placement over a contour map of a surface (thesis fig 5.7): nodes given as (rate_dps, temp_c).
void plot_nodes(const std::filesystem::path& png, const std::vector<double>& temps_c, const std::vector<double>& rates_dps,
                const Eigen::MatrixXd& z, const std::vector<std::array<double, 2>>& nodes, const std::string& title);

// Samples over the (T, omega) plane; the first and last `highlight` samples in red and green as in the
// thesis's figures.
void plot_coverage(const std::filesystem::path& png, const std::vector<double>& temp_c,
                   const std::vector<double>& rate_dps, const std::string& title, std::size_t highlight = 100);

// Allan deviation with its confidence band, the identified model's total with its own band over the taus
// the fit claims (shaded between the band's limits), and each term. `unit` names the rate unit of the curve
// (e.g. "deg/h"); the model is in that unit (see CompositeNoise).
void plot_allan(const std::filesystem::path& png, const std::vector<AllanPoint>& curve, const NoiseIdentification& fit,
                const std::string& title, const std::string& unit);

}  // namespace gyrosid
