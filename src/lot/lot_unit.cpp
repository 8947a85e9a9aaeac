#include "lot/lot_unit.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>

#include "core/distributed.h"
#include "core/error.h"
#include "core/format.h"
#include "core/progress.h"
#include "core/units.h"
#include "model/dataset.h"
#include "model/greybox_fit.h"
#include "noise/identify.h"
#include "solvers/calibrate.h"

namespace gyrosid {
namespace {

double white_noise_dph_at_1hz(const Dataset& data, const GreyboxEstimate& fit, const Eigen::VectorXd& residual_dph) {
  const double dt = median_sample_interval(data.t_s);
  const NoiseIdentification id = identify_noise(std::span<const double>(residual_dph.data(), static_cast<std::size_t>(residual_dph.size())), dt);
  for (const NoiseParameter& p : id.parameters) {
    if (p.name == "N" && p.value > 0.0) return p.value;
  }
  return units::radps_to_dph(fit.residual_sd_radps) * std::sqrt(dt);
}

// A unit as a row of doubles for the distributed batches: theta (p), its variances (p), the white noise, the
// recording's length, its misfit by rate (`bins`) and its conditional scores (`scores`); a failed unit is a row
// of NaN.
void write_row(const LotUnit& u, Eigen::Index p, Eigen::Index bins, Eigen::Index scores, double* row) {
  Eigen::Map<Eigen::VectorXd>(row, p) = u.theta;
  Eigen::Map<Eigen::VectorXd>(row + p, p) = u.theta_variance;
  row[2 * p] = u.white_dph_at_1hz;
  row[2 * p + 1] = u.recording_min;
  Eigen::Map<Eigen::VectorXd>(row + 2 * p + 2, bins) = u.misfit;
  if (scores > 0) Eigen::Map<Eigen::VectorXd>(row + 2 * p + 2 + bins, scores) = u.conditional_z;
}

LotUnit read_row(const double* row, Eigen::Index p, Eigen::Index bins, Eigen::Index scores, const std::string& name) {
  LotUnit u{name, Eigen::Map<const Eigen::VectorXd>(row, p), Eigen::Map<const Eigen::VectorXd>(row + p, p), row[2 * p], row[2 * p + 1], {},
            Eigen::Map<const Eigen::VectorXd>(row + 2 * p + 2, bins)};
  if (scores > 0) u.conditional_z = Eigen::Map<const Eigen::VectorXd>(row + 2 * p + 2 + bins, scores);
  return u;
}

// Rows of `width` numbers, one per path, in index order, appended to a spool: in batches over
// core/distributed.h (threads or MPI processes), each finished batch appended to the checkpoint's spool of
// `series` and counted in its record, and, on resume, the counted rows taken from it. fill(k, row) may throw:
// the row is then NaN on the process that computed it, and every process names the failure by running fill
// again itself.
RowSpool batched_rows(const std::vector<std::string>& paths, int width, const std::string& label, Checkpoint* checkpoint,
                      const std::string& series, const std::function<void(std::size_t, double*)>& fill) {
  const int count = static_cast<int>(paths.size());
  const bool saved = checkpoint && checkpoint->enabled();
  const nlohmann::json record = saved ? checkpoint->record(series) : nlohmann::json();
  const std::size_t resumed = record.is_object() ? record.value("rows", std::size_t{0}) : 0;
  if (resumed > paths.size() || (record.is_object() && record.value("width", width) != width)) {
    fail("the checkpoint's ", series, " do not fit ", count, " units of ", width, " numbers: start afresh without --resume");
  }
  RowSpool rows = saved ? RowSpool(static_cast<std::size_t>(width), checkpoint->spool_file(series), resumed) : RowSpool(static_cast<std::size_t>(width));
  Progress progress(label, paths.size());
  std::atomic<std::size_t> done{rows.rows()};
  while (rows.rows() < paths.size()) {
    // Batches grow with the units done (an eighth of them): O(log N) barriers and checkpoint saves.
    const int have = static_cast<int>(rows.rows());
    const int want = std::min(count, have + std::max({8, 2 * parallel_width(), have / 8}));
    const std::vector<double> batch = map_rows(have, want, width, [&](int i, double* row) {
      try {
        fill(static_cast<std::size_t>(i), row);
      } catch (const std::exception&) {
        std::fill(row, row + width, std::numeric_limits<double>::quiet_NaN());  // named below, on every process
      }
      progress.update(++done);
    });
    for (int i = have; i < want; ++i) {
      if (!std::isnan(batch[static_cast<std::size_t>((i - have) * width)])) continue;
      const auto k = static_cast<std::size_t>(i);
      std::vector<double> row(static_cast<std::size_t>(width));
      try {
        fill(k, row.data());
      } catch (const std::exception& e) {
        fail(paths[k], ": ", e.what());
      }
      fail(paths[k], ": the unit failed on another process");
    }
    rows.append(batch);  // then counted: a kill between the two leaves rows the resume cuts off
    if (saved) checkpoint->save_record(series, {{"rows", rows.rows()}, {"width", width}});
  }
  progress.finish();
  return rows;
}

}  // namespace

CalibratedUnits::CalibratedUnits(std::vector<std::string> names, Eigen::Index p, Eigen::Index bins, Eigen::Index scores, RowSpool rows)
    : names_(std::move(names)), p_(p), bins_(bins), scores_(scores), rows_(std::move(rows)) {}

LotUnit CalibratedUnits::at(std::size_t i) const {
  std::vector<double> row(rows_.width());
  rows_.read(i, row.data());
  return read_row(row.data(), p_, bins_, scores_, names_.at(i));
}

CalibratedUnits calibrate_units(const std::vector<std::string>& paths, const GreyboxOptions& structure, const std::string& label,
                                Checkpoint* checkpoint, const std::string& series, const LotModel* scored_against) {
  const auto p = static_cast<Eigen::Index>(greybox_coordinates(structure).size());
  const auto bins = static_cast<Eigen::Index>(std::max<std::size_t>(misfit_rate_edges_dps(structure).size(), 1) - 1);
  const auto scores = static_cast<Eigen::Index>(scored_against ? single_coordinate_terms(scored_against->coordinates).size() : 0);
  const auto width = static_cast<int>(2 * p + 2 + bins + scores);
  RowSpool rows = batched_rows(paths, width, label, checkpoint, series, [&](std::size_t k, double* row) {
    const Recording recording = read_recording(paths[k]);  // read once for both
    LotUnit unit = calibrate_unit(recording, paths[k], structure);
    if (scores > 0) unit.conditional_z = conditional_z(recording, *scored_against);
    write_row(unit, p, bins, scores, row);
  });
  return CalibratedUnits(paths, p, bins, scores, std::move(rows));
}

Eigen::VectorXd conditional_z(const Recording& recording, const LotModel& lot) {
  const std::vector<std::string> terms = single_coordinate_terms(lot.coordinates);
  const Dataset data = make_dataset(recording, greybox_features(lot.structure), ModelTarget::error);
  const GreyboxPrior prior = lot.prior();
  Eigen::VectorXd z(static_cast<Eigen::Index>(terms.size()));
  for (std::size_t k = 0; k < terms.size(); ++k) {
    const auto g = static_cast<Eigen::Index>(
        std::find_if(lot.coordinates.begin(), lot.coordinates.end(), [&](const GreyboxCoordinate& c) { return c.group == terms[k]; }) - lot.coordinates.begin());
    GreyboxPrior freed = prior;
    freed.covariance(g, g) *= 1e6;  // no prior on the term; the others' marginal unchanged
    const GreyboxEstimate fit = estimate_greybox(data, lot.structure, &freed);
    z(static_cast<Eigen::Index>(k)) = (fit.theta(g) - lot.mean(g)) / std::sqrt(fit.theta_covariance(g, g) + prior.covariance(g, g));
  }
  return z;
}

std::vector<Eigen::VectorXd> conditional_scores(const std::vector<std::string>& paths, const LotModel& lot, const std::string& label,
                                                Checkpoint* checkpoint, const std::string& series, const std::function<LotModel(std::size_t)>& lot_of) {
  const int width = static_cast<int>(single_coordinate_terms(lot.coordinates).size());
  if (width == 0) return std::vector<Eigen::VectorXd>(paths.size());
  const RowSpool rows = batched_rows(paths, width, label, checkpoint, series, [&](std::size_t k, double* row) {
    Eigen::Map<Eigen::VectorXd>(row, width) = conditional_z(read_recording(paths[k]), lot_of ? lot_of(k) : lot);
  });
  std::vector<Eigen::VectorXd> z(paths.size(), Eigen::VectorXd(width));
  for (std::size_t k = 0; k < paths.size(); ++k) rows.read(k, z[k].data());
  return z;
}

std::vector<double> surface_grid_rates_dps(const SplineSurface& surface) {
  std::vector<double> rates;
  for (double w : surface.y()) rates.push_back(std::round(units::radps_to_dps(w) * 1e9) / 1e9);
  return rates;
}

LotUnit calibrate_unit(const Recording& recording, const std::string& name, const GreyboxOptions& structure, SolveSummary* summary) {
  const Dataset data = make_dataset(recording, greybox_features(structure), ModelTarget::error);
  GreyboxEstimate fit = estimate_greybox(data, structure, nullptr, summary);
  LotUnit unit{name, std::move(fit.theta), fit.theta_covariance.diagonal(), 0.0, 0.0, {}, {}};
  const Eigen::VectorXd residual_dph = (data.target - fit.model->predict(data)) * units::radps_to_dph(1.0);
  unit.white_dph_at_1hz = white_noise_dph_at_1hz(data, fit, residual_dph);
  const Eigen::VectorXd rate_dps = (data.reference.allFinite() ? data.reference : data.measured) * units::radps_to_dps(1.0);
  unit.misfit = misfit_by_rate(residual_dph, rate_dps, misfit_rate_edges_dps(structure));
  if (data.size() > 1) unit.recording_min = (data.t_s.back() - data.t_s.front()) / 60.0;
  return unit;
}

LotUnit unit_of_model(const GreyboxModel& model, const std::string& name, const GreyboxOptions& structure) {
  const auto& surface = model.errors().scale_factor_surface;
  if (!surface || surface->x() != structure.surface_temperatures_c || surface_grid_rates_dps(*surface) != structure.surface_rates_dps) {
    fail(name, ": a lot's units need the scale-factor surface on the lot's grid (temperatures ", format_numbers(structure.surface_temperatures_c),
         " C; rates ", format_numbers(structure.surface_rates_dps), " dps)");
  }
  return {name, greybox_theta(model.errors(), model.lag_tau_s(), structure), Eigen::VectorXd(), 0.0, 0.0, {}, {}};
}

std::vector<LotUnit> units_of_models(const std::vector<std::string>& paths, OptionMap& structure) {
  std::vector<std::unique_ptr<GreyboxModel>> models;
  for (const auto& path : paths) {
    std::unique_ptr<CalibrationModel> m = load_model(path);
    auto* g = dynamic_cast<GreyboxModel*>(m.get());
    if (!g) fail(path, ": a lot learns from greybox models; this is a ", m->kind(), " model");
    m.release();
    models.emplace_back(g);
  }
  const GyroErrorModel& first = models.front()->errors();
  if (!first.scale_factor_surface) fail(paths.front(), ": a lot needs the scale-factor surface form");
  structure["bias_order"] = std::to_string(std::max<int>(0, static_cast<int>(first.bias_temperature_radps.coefficients.size()) - 1));
  structure["surface_temperatures_c"] = format_numbers(first.scale_factor_surface->x(), ",");
  structure["surface_rates_dps"] = format_numbers(surface_grid_rates_dps(*first.scale_factor_surface), ",");
  for (const auto& m : models) {
    if (m->errors().shupe_rad_per_c != 0.0) structure["shupe"] = "true";
    if (m->errors().scale_factor_asymmetry != 0.0) structure["asymmetry"] = "true";
    if (m->errors().g_sensitivity.any()) structure["g_sensitivity"] = "true";
    if (m->lag_tau_s() > 0.0) structure["thermal_lag"] = "true";
  }
  const GreyboxOptions o = greybox_options(structure);
  std::vector<LotUnit> units;
  for (std::size_t i = 0; i < paths.size(); ++i) units.push_back(unit_of_model(*models[i], paths[i], o));
  return units;
}

}  // namespace gyrosid
