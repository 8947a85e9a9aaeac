// gyrosid calibrate --model triad: the job of pipeline/triad_job.h, its model file written and its estimates printed.
#include "cli/triad_commands.h"

#include <iostream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"
#include "core/recording.h"
#include "core/triad_axes.h"
#include "core/units.h"
#include "pipeline/triad_job.h"
#include "solvers/nls/nls_solver.h"

namespace gyrosid::cli {

std::string triad_help() {
  TriadFitOptions o;
  std::string out = "triad - misalignment/scale-factor matrix M, bias b(T), optional G and per-gyro surfaces (--set key=value):\n" + o.table().help();
  out += "\nLeast-squares back-ends (--solver; their options as --set nls.<key>=<value>):\n";
  for (const auto& e : nls_solvers().entries()) out += e.help() + "\n";
  return out;
}

void calibrate_triad(const TriadCalibrateRequest& r) {
  OptionMap map = parse_options(r.set);
  if (!r.solver.empty()) map["solver"] = r.solver;
  if (!r.surfaces.empty()) map["surfaces"] = r.surfaces;
  if (!r.estimation.empty()) map["estimation"] = r.estimation;
  const TriadCalibration c = gyrosid::calibrate_triad(read_recording(r.recording), map);
  write_file_atomic(r.out, c.file.dump(1) + "\n");

  const TriadFitOptions& o = c.options;
  const TriadFit& fit = c.fit;
  const std::string estimation = o.estimation == "auto" ? "auto (" + fit.estimation_chosen + " returned)" : o.estimation;
  std::cout << "wrote " << r.out << ": triad model, " << estimation << ", surfaces " << o.surfaces << ", " << o.solver << " "
            << to_string(fit.summary.termination) << ", " << format_significant(fit.summary.time_s, 3) << " s\n";
  for (int i = 0; i < 3; ++i) {
    std::cout << "  gyro " << kTriadAxes[i] << ": M row [";
    for (int j = 0; j < 3; ++j) {
      const bool known = fit.uncertainty.misalignment_known[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
      std::cout << (j ? ", " : "")
                << (known ? format_significant(fit.model.misalignment(i, j) * 1e6, 5) + " +- " + format_significant(fit.uncertainty.misalignment_sigma(i, j) * 1e6, 2) : "n/d");
    }
    std::cout << "] (1e-6, rad off the diagonal), bias " << format_significant(units::radps_to_dph(fit.model.bias.coefficients[static_cast<std::size_t>(i)](0)), 5)
              << " deg/h, residual rms " << format_significant(fit.residual_rms_dph[static_cast<std::size_t>(i)], 4) << " deg/h\n";
  }
  for (const auto& h : fit.hold_stillness.not_still()) std::cerr << "warning: " << r.recording << ": " << fit.hold_stillness.describe(h) << "\n";
  if (!fit.notes.empty()) std::cout << "  " << fit.notes.size() << " note(s) in " << r.out << " (observable.notes), e.g.: " << fit.notes.front() << "\n";
}

}  // namespace gyrosid::cli
