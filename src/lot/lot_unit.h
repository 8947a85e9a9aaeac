// A unit as the lot sees it (lot_model.h): calibrated with the lot's grey-box structure from its recording -
// its coordinates, their covariance and its white noise - or read from a calibrated model file (its
// coordinates only: a model file keeps no covariance and no noise).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/checkpoint.h"
#include "core/recording.h"
#include "core/row_spool.h"
#include "core/solve_summary.h"
#include "lot/lot_model.h"
#include "model/greybox_model.h"

namespace gyrosid {

// A calibrated model's scale-factor surface rates in deg/s, rounded at 1e-9 deg/s (the rad/s round trip's last
// bits): its grid as a structure's surface_rates_dps writes it.
std::vector<double> surface_grid_rates_dps(const SplineSurface& surface);

// White noise: noise/identify.h (the one noise estimator) on the fit's residual in deg/h; its N term, or,
// where the identified structure has none, the residual's sd per sample times sqrt(dt).
LotUnit calibrate_unit(const Recording& recording, const std::string& name, const GreyboxOptions& structure,
                       SolveSummary* summary = nullptr);

// The units calibrate_units computed, on disk: a spool row per unit (theta, its variances, the white noise, the
// recording's length, the misfit by rate, the conditional scores), read back one at a time and named by the recordings' paths. A lot
// of any size is learned from them in the memory of its model.
class CalibratedUnits final : public LotUnits {
 public:
  CalibratedUnits(std::vector<std::string> names, Eigen::Index p, Eigen::Index bins, Eigen::Index scores, RowSpool rows);
  std::size_t size() const override { return names_.size(); }
  LotUnit at(std::size_t i) const override;

 private:
  std::vector<std::string> names_;
  Eigen::Index p_, bins_, scores_;
  RowSpool rows_;
};

// Every recording's unit (named by its path), in index order: in batches over core/distributed.h's rows -
// this process's threads, or `gyrosid-mpi`'s processes, each unit computed from its own recording alone, so
// the units do not depend on how many threads or processes computed them. Each finished batch is appended to a
// spool: with an enabled checkpoint, its spool_file(series), and a resumed run takes the saved units and computes
// the rest. Error naming the recording of the first unit that fails. With `scored_against` (a lot whose structure
// is `structure`), each unit's conditional_z against it is computed in the same pass over its recording.
CalibratedUnits calibrate_units(const std::vector<std::string>& paths, const GreyboxOptions& structure, const std::string& label,
                                Checkpoint* checkpoint = nullptr, const std::string& series = "units",
                                const LotModel* scored_against = nullptr);

// The conditional scores of lot_model.h, one per single_coordinate_terms(lot.coordinates): the recording refitted
// with the lot's prior freed on each such term in turn.
Eigen::VectorXd conditional_z(const Recording& recording, const LotModel& lot);
// conditional_z of every recording, batched and checkpointed as calibrate_units (empty vectors when the lot's
// structure has no such term).
// `lot_of(k)` (optional): the lot recording k is scored against (default: `lot`), e.g. the lot without that unit.
std::vector<Eigen::VectorXd> conditional_scores(const std::vector<std::string>& paths, const LotModel& lot, const std::string& label,
                                                Checkpoint* checkpoint = nullptr, const std::string& series = "conditional",
                                                const std::function<LotModel(std::size_t)>& lot_of = nullptr);

LotUnit unit_of_model(const GreyboxModel& model, const std::string& name, const GreyboxOptions& structure);

// Already-calibrated grey-box units (model files): the structure from the first - its bias order and surface
// grid, and a term wherever some unit has it - written into `structure` as `calibrate --set` keys. Error
// naming a file that is no grey-box model, or a first without the scale-factor surface.
std::vector<LotUnit> units_of_models(const std::vector<std::string>& paths, OptionMap& structure);

}  // namespace gyrosid
