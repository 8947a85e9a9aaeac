#include "solvers/triad/triad_kind.h"

#include "core/error.h"
#include "core/format.h"
#include "core/triad_axes.h"
#include "core/units.h"
#include "solvers/nls/nls_solver.h"
#include "solvers/triad/triad_file.h"
#include "solvers/triad/triad_fit.h"

namespace gyrosid {
namespace {

// What the command prints of a triad fit: how it was estimated, and per gyro its row of M (1e-6; "n/d" where
// the data do not determine an entry), its bias at the reference temperature and its residual rms.
std::vector<std::string> statement_of(const TriadFit& fit) {
  const TriadFitOptions& o = fit.options;
  std::vector<std::string> lines{str_cat("  ", o.estimation == "auto" ? "auto (" + fit.estimation_chosen + " returned)" : o.estimation,
                                         ", surfaces ", o.surfaces, ", least squares by ", o.solver)};
  for (int i = 0; i < 3; ++i) {
    const auto row = static_cast<std::size_t>(i);
    std::string line = str_cat("  gyro ", kTriadAxes[i], ": M row [");
    for (int j = 0; j < 3; ++j) {
      const bool known = fit.uncertainty.misalignment_known[row][static_cast<std::size_t>(j)];
      line += str_cat(j ? ", " : "", known ? str_cat(format_significant(fit.model.misalignment(i, j) * 1e6, 5), " +- ",
                                                      format_significant(fit.uncertainty.misalignment_sigma(i, j) * 1e6, 2))
                                           : std::string("n/d"));
    }
    lines.push_back(str_cat(line, "] (1e-6, rad off the diagonal), bias ", format_significant(units::radps_to_dph(fit.model.bias.coefficients[row](0)), 5),
                            " deg/h, residual rms ", format_significant(fit.residual_rms_dph[row], 4), " deg/h"));
  }
  if (!fit.notes.empty()) lines.push_back(str_cat("  ", fit.notes.size(), " note(s) in the model file (observable.notes), e.g.: ", fit.notes.front()));
  return lines;
}

class TriadFitter : public ModelFitter {
 public:
  TriadFitter(TriadFitOptions options, OptionMap given) : options_(std::move(options)), given_(std::move(given)) {}

  ModelFit fit_model(const Recording& recording, const CalibrationRequest&) override {
    TriadFit fit = fit_triad(make_triad_data(recording), options_, recording.meta("reference").value_or(""));
    const nlohmann::json file = triad_fit_json(fit, {{"recording", recording.source()}, {"samples", recording.rows()}, {"options", given_}});
    ModelFit out;
    out.statement = statement_of(fit);
    for (const auto& h : fit.hold_stillness.not_still()) out.warnings.push_back(str_cat(recording.source(), ": ", fit.hold_stillness.describe(h)));
    out.summary = fit.summary;
    out.model = std::make_unique<TriadModel>(std::move(fit.model));
    out.extra = fields_beside(file, *out.model);
    return out;
  }

 private:
  TriadFitOptions options_;
  OptionMap given_;  // the options as given, for the file's training
};

}  // namespace

std::unique_ptr<ModelFitter> triad_fitter(const CalibrationRequest& r) {
  if (!r.features.empty()) fail("triad: the inputs are each gyro's output, the reference rates and the temperatures; --features applies to single-gyro models");
  refuse_rbf_fields(r, false);
  OptionMap given = r.options;
  if (r.solver != CalibrationRequest{}.solver) given["solver"] = r.solver;
  TriadFitOptions o;
  o.table().apply(given);
  if (const std::string p = o.validate(); !p.empty()) fail("triad: ", p);
  return std::make_unique<TriadFitter>(std::move(o), std::move(given));
}

std::string triad_help() {
  TriadFitOptions o;
  std::string out = "triad - misalignment/scale-factor matrix M, bias b(T), optional G and per-gyro surfaces (--set key=value):\n" + o.table().help();
  out += "\nLeast-squares back-ends (--solver; their options as --set nls.<key>=<value>):\n";
  for (const auto& e : nls_solvers().entries()) out += e.help() + "\n";
  return out;
}

}  // namespace gyrosid
