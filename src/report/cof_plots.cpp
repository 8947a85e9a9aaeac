#include "report/cof_plots.h"

#include "report/cof_json.h"
#include <cmath>

#include "core/atomic_file.h"
#include "core/earth_model.h"
#include "core/error.h"
#include "core/format.h"
#include "core/gnuplot.h"
#include "report/cof_json.h"

namespace gyrosid {

void plot_error_growth(const std::filesystem::path& png, const std::string& title,
                       const std::vector<std::pair<std::string, const nav::CofRun*>>& runs) {
  std::string blocks, plots;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    std::vector<std::vector<double>> rows;
    for (const auto& p : runs[i].second->growth) rows.push_back({p[0], std::max(p[1], 1e-9)});
    const std::string name = str_cat("g", i);
    blocks += datablock(name, rows);
    plots += str_cat(i ? ", " : "", "$", name, " using 1:2 with lines lw 2 title ", gnuplot_quote(runs[i].first));
  }
  render_png(png, blocks + str_cat("set title ", gnuplot_quote(title), "\nset xlabel 'time (s)'\n",
                                   "set ylabel 'position error (m)'\nset logscale y\nset format y '%.0e'\nset grid\nset key left top\nplot ", plots, "\n"));
}

void write_cof_outputs(const nav::CofReport& r, const std::filesystem::path& dir) {
  write_file_atomic(dir / "cof.json", cof_json(r).dump(2) + "\n");

  // Ground track, north/east from the start, km.
  std::vector<std::vector<double>> track;
  const NavState& s0 = r.reference.front();
  const std::size_t stride = std::max<std::size_t>(1, r.reference.size() / 4000);
  for (std::size_t k = 0; k < r.reference.size(); k += stride) {
    const Eigen::Vector3d d = earth::ned_offset(s0.lat, s0.lon, s0.h, r.reference[k].lat, r.reference[k].lon, r.reference[k].h);
    track.push_back({d.y() / 1000.0, d.x() / 1000.0, r.reference[k].h / 1000.0});
  }
  render_png(dir / "ground_track.png",
             datablock("track", track) + str_cat("set title ", gnuplot_quote("Ground track: " + r.request.trajectory),
                                                 "\nset xlabel 'east (km)'\nset ylabel 'north (km)'\nset size ratio -1\nset grid\n"
                                                 "set cblabel 'height (km)'\nset palette rgb 33,13,10\n"
                                                 "plot $track using 1:2:3 with lines lw 2 lc palette notitle\n"));

  plot_error_growth(dir / "error_growth.png", "Position error against the reference INS",
                    {{"uncompensated", &r.uncompensated},
                     {"compensated (" + r.request.model + ")", &r.run}});

  if (r.mc) {
    const char* names[] = {"along-track", "cross-track (horizontal)", "cross-track (vertical)"};
    std::string script = "set multiplot layout 1,3 title " +
                         gnuplot_quote(str_cat("Monte Carlo end errors, ", r.mc->runs, " runs")) + "\nset style fill solid 0.6\nset grid\n";
    for (int c = 0; c < 3; ++c) {
      std::vector<double> x;
      for (const auto& s : r.mc->samples) x.push_back(s(c));
      const double lo = *std::min_element(x.begin(), x.end()), hi = *std::max_element(x.begin(), x.end());
      const int bins = std::max(5, static_cast<int>(std::sqrt(static_cast<double>(x.size()))));
      const double w = hi > lo ? (hi - lo) / bins : 1.0;
      std::vector<int> count(static_cast<std::size_t>(bins), 0);
      for (double v : x) ++count[static_cast<std::size_t>(std::clamp(static_cast<int>((v - lo) / w), 0, bins - 1))];
      std::vector<std::vector<double>> rows;
      for (int b = 0; b < bins; ++b) rows.push_back({lo + (b + 0.5) * w, static_cast<double>(count[static_cast<std::size_t>(b)])});
      script += datablock(str_cat("h", c), rows) +
                str_cat("set title ", gnuplot_quote(names[c]), "\nset xlabel 'error (m)'\nset ylabel 'runs'\n",
                        "plot $h", c, " using 1:2:(", w, ") with boxes notitle\n");
    }
    render_png(dir / "monte_carlo.png", script + "unset multiplot\n", PngSize{1440, 480});
  }
}

}  // namespace gyrosid
