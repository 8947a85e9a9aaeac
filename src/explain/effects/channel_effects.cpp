// Effects that follow recorded channels: g- and g^2-sensitivity (specific force), magnetic sensitivity,
// cross-axis coupling (the other axes' rates), and any auxiliary channel - the last not physics: a residual
// that follows a supply voltage is localised, not named.
#include "core/units.h"
#include "explain/effects/effects.h"
#include "model/terms/term_kinds.h"

namespace gyrosid::explain::effects {
namespace {

std::string axis_of(const std::string& channel) {
  for (const char* a : {"_x_", "_y_", "_z_"}) {
    if (channel.find(a) != std::string::npos) return std::string(1, a[1]);
  }
  return channel;
}

// One parameter per channel: name(channel), value(coefficient).
template <typename Name, typename Value>
std::vector<PhysicalParameter> per_channel(const Term& t, const Eigen::VectorXd& beta, const Eigen::VectorXd& sigma, Name name, Value value) {
  std::vector<PhysicalParameter> out;
  const auto channels = t->channels();
  for (std::size_t c = 0; c < channels.size(); ++c) {
    const auto k = static_cast<Eigen::Index>(c);
    out.push_back(PhysicalParameter::estimate(name(channels[c]), value(beta(k)), value(sigma(k))));
  }
  return out;
}

constexpr const char* kTiltVsTemperature =
    "change the tilt at constant temperature (a multi-position sequence on one plateau): g-sensitivity "
    "follows the tilt, a temperature bias does not";

class GSensitivity : public Effect {
 public:
  explicit GSensitivity(bool squared) : squared_(squared) {}
  std::string_view id() const override { return squared_ ? "g2_sensitivity" : "g_sensitivity"; }
  std::string_view description() const override {
    return squared_ ? "A bias proportional to the square of the specific force (g^2-sensitivity, anisoelasticity), from "
                      "unequal compliance of the mount along different axes."
                    : "A bias proportional to the specific force along the sensor axes (g-sensitivity), from mass unbalance "
                      "and strain in the coil mount.";
  }
  std::string_view parameters_help() const override {
    return squared_ ? "k_<axis>_dph_per_g2: bias per squared specific force along each axis" : "k_<axis>_dph_per_g: bias per specific force along each axis";
  }
  Proposal propose(const CandidateContext& c) const override {
    const auto accel = c.new_varying_channels(c.in.accel, 0.01 * units::kStandardGravity);
    if (accel.empty()) return {{}, c.in.accel.empty() ? "no specific force recorded" : "the specific force does not vary"};
    return {{candidate(channel_term(accel, squared_))}, ""};
  }
  std::vector<PhysicalParameter> parameters(const Term& t, const Eigen::VectorXd& beta, const Eigen::VectorXd& sigma,
                                            const TermScaling&) const override {
    constexpr double g = units::kStandardGravity, g2 = g * g;
    if (squared_) {
      return per_channel(t, beta, sigma, [](const std::string& c) { return "k_" + axis_of(c) + "_dph_per_g2"; }, [](double x) { return x * g2; });
    }
    return per_channel(t, beta, sigma, [](const std::string& c) { return "k_" + axis_of(c) + "_dph_per_g"; }, [](double x) { return x * g; });
  }
  std::string separating_experiment(std::string_view other) const override { return other == "temperature_bias" ? kTiltVsTemperature : ""; }

 private:
  bool squared_;
};

class MagneticSensitivity : public Effect {
 public:
  std::string_view id() const override { return "magnetic_sensitivity"; }
  std::string_view description() const override {
    return "A bias proportional to the magnetic field: the Faraday effect in a fibre coil, magnetic coupling into "
           "the drive or sense electronics of a MEMS gyro.";
  }
  std::string_view parameters_help() const override { return "k_<channel>_dph_per_ut: bias per microtesla of each magnetic channel (mag..._ut)"; }
  Proposal propose(const CandidateContext& c) const override {
    const auto mag = c.new_varying_channels(c.in.magnetic, 1e-3);
    if (mag.empty()) return {{}, c.in.magnetic.empty() ? "no magnetic channel recorded (name it mag..._ut)" : "the field does not vary"};
    return {{candidate(channel_term(mag))}, ""};
  }
  std::vector<PhysicalParameter> parameters(const Term& t, const Eigen::VectorXd& beta, const Eigen::VectorXd& sigma,
                                            const TermScaling&) const override {
    return per_channel(t, beta, sigma, [](const std::string& c) { return "k_" + c.substr(0, c.size() - 3) + "_dph_per_ut"; },
                       [](double x) { return x; });
  }
  std::string separating_experiment(std::string_view other) const override {
    if (other == "temperature_bias" || other == "aging_trend") {
      return "change the magnetic field at constant temperature (turn the unit in the Earth's field or drive a "
             "Helmholtz coil): a magnetic sensitivity follows the field";
    }
    return "";
  }
};

class CrossAxisCoupling : public Effect {
 public:
  std::string_view id() const override { return "cross_axis_coupling"; }
  std::string_view description() const override {
    return "The gyro senses part of the rates about the other axes (cross-axis coupling: its input axis is "
           "misaligned).";
  }
  std::string_view parameters_help() const override { return "k_<axis>_mrad: the input axis's lean towards each other axis (mrad)"; }
  Proposal propose(const CandidateContext& c) const override {
    const auto cross = c.new_varying_channels(c.in.cross_axis, units::dps_to_radps(1.0));
    if (cross.empty()) return {{}, c.in.cross_axis.empty() ? "not a triad recording" : "the other axes do not turn"};
    return {{candidate(channel_term(cross))}, ""};
  }
  std::vector<PhysicalParameter> parameters(const Term& t, const Eigen::VectorXd& beta, const Eigen::VectorXd& sigma,
                                            const TermScaling&) const override {
    return per_channel(t, beta, sigma, [](const std::string& c) { return "k_" + axis_of(c) + "_mrad"; }, [](double x) { return 1e3 * x * kDphPerRadps; });
  }
};

// Every auxiliary channel (a supply voltage, ...) on its own: where a residual may live.
class AuxiliaryChannel : public Effect {
 public:
  std::string_view id() const override { return "auxiliary_channel"; }
  std::string_view description() const override { return "The residual follows a recorded channel that no named physics accounts for."; }
  std::string_view parameters_help() const override { return "k_dph_per_<unit>: bias per unit of the channel (its name's suffix)"; }
  bool is_physics() const override { return false; }
  Proposal propose(const CandidateContext& c) const override {
    Proposal p;
    for (const auto& aux : c.new_varying_channels(c.in.aux, 0.0)) p.candidates.push_back(candidate(channel_term({aux})));
    return p;
  }
  std::vector<PhysicalParameter> parameters(const Term& t, const Eigen::VectorXd& beta, const Eigen::VectorXd& sigma,
                                            const TermScaling&) const override {
    const std::string c = t->channels().front();
    const auto underscore = c.rfind('_');
    return {PhysicalParameter::estimate("k_dph_per_" + (underscore == std::string::npos ? std::string("unit") : c.substr(underscore + 1)),
                                        beta(0), sigma(0))};
  }
};

}  // namespace

std::unique_ptr<Effect> g_sensitivity() { return std::make_unique<GSensitivity>(false); }
std::unique_ptr<Effect> g2_sensitivity() { return std::make_unique<GSensitivity>(true); }
std::unique_ptr<Effect> magnetic_sensitivity() { return std::make_unique<MagneticSensitivity>(); }
std::unique_ptr<Effect> cross_axis_coupling() { return std::make_unique<CrossAxisCoupling>(); }
std::unique_ptr<Effect> auxiliary_channel() { return std::make_unique<AuxiliaryChannel>(); }

}  // namespace gyrosid::explain::effects
