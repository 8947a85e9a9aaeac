// The lot as the members of a prior over sensors (sensor/sensor_prior.h, format gyrosid-prior/1), so that
// `gyrosid design --prior lot.json` designs for a unit of the lot: the population's unscented points in its
// modes - the mean and mu +- sqrt(k + 1) m_i along each of the k leading modes m_i = S w_i (at most
// max_modes), weighted 1 / (k + 1) and 1 / (2 (k + 1)), which reproduce the population's mean and its
// covariance within the modes exactly (Julier & Uhlmann 1997 with kappa = 1).
// Each member is a sensor config written from its coordinates: the bias values through the polynomial of the
// lot's order about 25 C, the surface on the lot's grid, Shupe, asymmetry, g-sensitivity, the coil lag; white
// noise at the lot's median. What a calibration cannot see - the package's lag behind the chamber - is the
// stated `package_tau_s`.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

#include "lot/lot_model.h"

namespace gyrosid {

struct LotMemberOptions {
  double package_tau_s = 300.0;  // chamber -> probe first-order lag of the members (the reference sensor's)
  int max_modes = 6;
  std::string validate() const;
};

// [{sensor: {kind: gyro, ...}, weight: w}, ...], the mean first.
nlohmann::json lot_members(const LotModel& lot, const LotMemberOptions& options = {});

// The lot file `gyrosid lot learn` writes: a prior over sensors (format, name - "lot of N units" when empty -,
// the members above) with the lot's `population` beside them.
nlohmann::json lot_prior_file(const LotModel& lot, const std::string& name, const LotMemberOptions& options = {});

// The sensor config (gyrosid's YAML keys, as JSON) of a point theta of the lot's coordinates.
nlohmann::json lot_sensor_config(const LotModel& lot, const Eigen::VectorXd& theta, const std::string& name, const LotMemberOptions& options);

}  // namespace gyrosid
