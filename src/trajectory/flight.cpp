#include "trajectory/flight.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/earth_model.h"
#include "core/error.h"
#include "core/format.h"
#include "core/units.h"

namespace gyrosid {
namespace {

using units::deg_to_rad;
constexpr double kPi = units::kPi;

// Smooth unit pulse over [0, T]: integrates to 1, zero (with zero slope) at both ends.
double pulse(double tau, double T) { return (1.0 - std::cos(2.0 * kPi * tau / T)) / T; }

// Derivative of the smooth step over [0, r] (integrates to 1).
double step_rate(double tau, double r) { return (tau < 0 || tau > r) ? 0.0 : 0.5 * kPi / r * std::sin(kPi * tau / r); }

struct Commands {
  double v_dot = 0, gamma_dot = 0, phi_dot = 0;
  bool coordinated = false;  // heading rate from the bank
  double load_factor = 0;    // > 0: pull-up, gamma_dot from the load factor
};

Commands command(const FlightSegment& s, double tau, double bank_at_start) {
  Commands c;
  const double T = s.duration_s;
  switch (s.kind) {
    case FlightSegmentKind::straight: break;
    case FlightSegmentKind::accelerate: {
      const double r = std::min(0.5, T / 4.0);
      const double envelope = tau < r ? 0.5 * (1 - std::cos(kPi * tau / r))
                              : tau > T - r ? 0.5 * (1 - std::cos(kPi * (T - tau) / r)) : 1.0;
      c.v_dot = s.accel_mps2 * envelope;
      break;
    }
    case FlightSegmentKind::climb: c.gamma_dot = deg_to_rad(std::abs(s.angle_deg)) * pulse(tau, T); break;
    case FlightSegmentKind::dive: c.gamma_dot = -deg_to_rad(std::abs(s.angle_deg)) * pulse(tau, T); break;
    case FlightSegmentKind::roll: c.phi_dot = deg_to_rad(s.angle_deg) * pulse(tau, T); break;
    case FlightSegmentKind::level_turn: {
      const double r = std::min(1.0, T / 4.0);
      const double delta = deg_to_rad(s.bank_deg) - bank_at_start;
      c.phi_dot = delta * (step_rate(tau, r) - step_rate(tau - (T - r), r));
      c.coordinated = true;
      break;
    }
    case FlightSegmentKind::s_turn: {
      // bank - bank0 = b sin(pi k tau / T) sin(pi tau / T): alternating, smooth at both ends.
      const double b = deg_to_rad(s.bank_deg), k = s.turns, w = kPi / T;
      c.phi_dot = b * w * (k * std::cos(k * w * tau) * std::sin(w * tau) + std::sin(k * w * tau) * std::cos(w * tau));
      c.coordinated = true;
      break;
    }
    case FlightSegmentKind::pull_up:
      c.load_factor = 1.0 + (s.load_factor - 1.0) * 0.5 * (1.0 - std::cos(2.0 * kPi * tau / T));
      break;
  }
  return c;
}

// The integrated state y = [lat, lon, h, V, gamma, chi, phi, dtheta(3), dv(3)], by name: the point-mass
// flight's position, speed, path angle, heading and bank, and the IMU's increments over the current step.
enum StateIndex : Eigen::Index { kLat, kLon, kHeight, kSpeed, kPathAngle, kHeading, kBank, kDeltaTheta, kDeltaV = kDeltaTheta + 3, kStateSize = kDeltaV + 3 };
using State = Eigen::Matrix<double, kStateSize, 1>;

struct Rates {
  State dy;
  Eigen::Vector3d w_ib_b, f_b;
};

}  // namespace

std::string FlightSegment::validate() const {
  if (!(duration_s > 0)) return "duration_s must be positive";
  if (kind == FlightSegmentKind::level_turn && !(std::abs(bank_deg) < 89.9)) return "level_turn bank_deg must be within +-89.9";
  if (kind == FlightSegmentKind::s_turn && (turns < 1 || std::abs(bank_deg) >= 89.9)) return "s_turn needs turns >= 1 and |bank_deg| < 89.9";
  if (kind == FlightSegmentKind::pull_up && !(load_factor > 0)) return "pull_up load_factor must be positive";
  return "";
}

double FlightProfile::duration_s() const {
  double d = 0;
  for (const auto& s : segments) d += s.duration_s;
  return d;
}

std::string FlightProfile::validate() const {
  if (segments.empty()) return "a flight needs at least one segment";
  if (!(initial.speed_mps > 0)) return "initial speed must be positive";
  if (!(std::abs(initial.flight_path_deg) < 85)) return "initial flight-path angle must be within +-85 deg";
  for (std::size_t i = 0; i < segments.size(); ++i) {
    if (auto p = segments[i].validate(); !p.empty()) return str_cat("segment ", i + 1, ": ", p);
  }
  return "";
}

NavState FlightTrajectory::initial() const {
  if (truth.empty()) fail(name, ": no initial state");
  return truth.front();
}

FlightTrajectory generate_flight(const FlightProfile& p, double rate_hz, int substeps) {
  if (auto e = p.validate(); !e.empty()) fail("flight '", p.name, "': ", e);
  if (substeps <= 0) substeps = p.substeps;
  if (!(rate_hz > 0) || substeps < 1) fail("flight '", p.name, "': rate_hz and substeps must be positive");
  const double dt = 1.0 / rate_hz, h = dt / substeps;
  const std::size_t steps = static_cast<std::size_t>(std::llround(p.duration_s() * rate_hz));

  std::vector<double> start(p.segments.size() + 1, 0.0), bank0(p.segments.size() + 1, deg_to_rad(p.initial.bank_deg));
  for (std::size_t s = 0; s < p.segments.size(); ++s) {
    start[s + 1] = start[s] + p.segments[s].duration_s;
    bank0[s + 1] = bank0[s] + (p.segments[s].kind == FlightSegmentKind::roll ? deg_to_rad(p.segments[s].angle_deg) : 0.0);
  }

  auto rates = [&](double t, const State& y) {
    std::size_t s = 0;
    while (s + 1 < p.segments.size() && t >= start[s + 1]) ++s;
    const double tau = std::clamp(t - start[s], 0.0, p.segments[s].duration_s);
    const Commands c = command(p.segments[s], tau, bank0[s]);
    const double lat = y(kLat), hh = y(kHeight), v = y(kSpeed), g = y(kPathAngle), chi = y(kHeading), phi = y(kBank);
    const earth::EarthRadii r = earth::radii(lat);
    const double grav = earth::normal_gravity(lat, hh);
    const double gamma_dot = c.load_factor > 0 ? grav * (c.load_factor - std::cos(g)) / v : c.gamma_dot;
    const double chi_dot = c.coordinated ? grav * std::tan(phi) / v : 0.0;
    const double cg = std::cos(g), sg = std::sin(g), cc = std::cos(chi), sc = std::sin(chi);
    const Eigen::Vector3d v_n(v * cg * cc, v * cg * sc, -v * sg);
    const Eigen::Vector3d v_dot = c.v_dot * Eigen::Vector3d(cg * cc, cg * sc, -sg) +
                                  v * gamma_dot * Eigen::Vector3d(-sg * cc, -sg * sc, -cg) +
                                  v * chi_dot * Eigen::Vector3d(-cg * sc, cg * cc, 0.0);
    const Eigen::Vector3d w_ie = earth::earth_rate_n(lat), w_en = earth::transport_rate_n(lat, hh, v_n, r);
    const Eigen::Matrix3d c_n_b = euler_to_quaternion(phi, g, chi).toRotationMatrix();
    const Eigen::Vector3d f_n = v_dot + (2.0 * w_ie + w_en).cross(v_n) - earth::gravity_n(lat, hh);
    const double sp = std::sin(phi), cp = std::cos(phi);
    const Eigen::Vector3d w_nb_b(c.phi_dot - chi_dot * sg, gamma_dot * cp + chi_dot * cg * sp, -gamma_dot * sp + chi_dot * cg * cp);
    Rates out;
    out.f_b = c_n_b.transpose() * f_n;
    out.w_ib_b = w_nb_b + c_n_b.transpose() * (w_ie + w_en);
    out.dy << /* in StateIndex order */ v_n.x() / (r.meridian + hh), v_n.y() / ((r.transverse + hh) * std::cos(lat)), -v_n.z(), c.v_dot, gamma_dot,
        chi_dot, c.phi_dot, out.w_ib_b, out.f_b;
    return out;
  };

  FlightTrajectory f;
  f.name = p.name;
  f.dt_s = dt;
  State y = State::Zero();
  y(kLat) = deg_to_rad(p.initial.lat_deg), y(kLon) = deg_to_rad(p.initial.lon_deg), y(kHeight) = p.initial.h_m;
  y(kSpeed) = p.initial.speed_mps, y(kPathAngle) = deg_to_rad(p.initial.flight_path_deg), y(kHeading) = deg_to_rad(p.initial.heading_deg);
  y(kBank) = deg_to_rad(p.initial.bank_deg);
  auto record = [&](double t) {
    NavState s;
    s.lat = y(kLat), s.lon = y(kLon), s.h = y(kHeight);
    const double v = y(kSpeed), g = y(kPathAngle), chi = y(kHeading);
    s.v_n = Eigen::Vector3d(v * std::cos(g) * std::cos(chi), v * std::cos(g) * std::sin(chi), -v * std::sin(g));
    s.q_n_b = euler_to_quaternion(y(kBank), g, chi);
    f.t_s.push_back(t);
    f.truth.push_back(s);
  };
  f.t_s.reserve(steps + 1), f.truth.reserve(steps + 1), f.dtheta.reserve(steps), f.dv.reserve(steps);
  record(0.0);
  double t = 0.0;
  for (std::size_t k = 0; k < steps; ++k) {
    y.segment<6>(kDeltaTheta).setZero();  // the increments start again each step
    for (int sub = 0; sub < substeps; ++sub) {
      const double t0 = dt * static_cast<double>(k) + h * sub;
      const State k1 = rates(t0, y).dy;
      const State k2 = rates(t0 + 0.5 * h, y + 0.5 * h * k1).dy;
      const State k3 = rates(t0 + 0.5 * h, y + 0.5 * h * k2).dy;
      const State k4 = rates(t0 + h, y + h * k3).dy;
      y += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    t = dt * static_cast<double>(k + 1);
    f.dtheta.push_back(y.segment<3>(kDeltaTheta));
    f.dv.push_back(y.segment<3>(kDeltaV));
    record(t);
    if (!(y(kSpeed) > 1.0)) fail("flight '", p.name, "': speed fell to ", y(kSpeed), " m/s at t = ", t, " s");
  }
  return f;
}

std::vector<double> flight_temperature_c(const FlightTrajectory& f, double start_temp_c) {
  std::vector<double> out;
  out.reserve(f.truth.size());
  const double h0 = f.truth.front().h;
  for (const auto& s : f.truth) out.push_back(start_temp_c - 0.0065 * (s.h - h0));
  return out;
}

// --- built-ins and YAML --------------------------------------------------------------------------------

namespace {

FlightSegment seg(FlightSegmentKind kind, double duration) {
  FlightSegment s;
  s.kind = kind;
  s.duration_s = duration;
  return s;
}
FlightSegment with(FlightSegment s, double FlightSegment::*field, double value) {
  s.*field = value;
  return s;
}

}  // namespace

std::vector<std::string> builtin_flight_names() { return {"short", "medium", "long"}; }

FlightProfile builtin_flight(std::string_view name) {
  using K = FlightSegmentKind;
  FlightProfile p;
  p.name = std::string(name);
  if (name == "short") {
    // Air-to-air missile turn-around (thesis C.2 "aps TurnAround48g"): Mach 2, roll into an 88.8-deg
    // bank for a 48-g coordinated half turn, roll out, a fast aileron roll, deceleration and a dive.
    p.description = "10 s air-to-air missile: 48-g turn-around, fast roll, dive";
    p.initial.speed_mps = 680.0;
    p.segments = {seg(K::straight, 0.5), with(seg(K::level_turn, 4.8), &FlightSegment::bank_deg, 88.8),
                  seg(K::straight, 0.5), with(seg(K::roll, 1.0), &FlightSegment::angle_deg, 360.0),
                  with(seg(K::accelerate, 2.0), &FlightSegment::accel_mps2, -80.0),
                  with(seg(K::dive, 1.2), &FlightSegment::angle_deg, 10.0)};
  } else if (name == "medium") {
    // Medium-range missile (thesis C.3 "aps vl668"): steep launch and boost, pitch-over, cruise with
    // S-turns, terminal dive.
    p.description = "50 s medium-range missile: boost, pitch-over, S-turns, dive";
    p.initial.speed_mps = 60.0;
    p.initial.flight_path_deg = 60.0;
    p.segments = {with(seg(K::accelerate, 4.0), &FlightSegment::accel_mps2, 150.0),
                  with(seg(K::dive, 8.0), &FlightSegment::angle_deg, 55.0), seg(K::straight, 5.0),
                  with(with(seg(K::s_turn, 15.0), &FlightSegment::bank_deg, 45.0), &FlightSegment::load_factor, 1.0),
                  seg(K::straight, 6.0), with(seg(K::dive, 6.0), &FlightSegment::angle_deg, 25.0), seg(K::straight, 6.0)};
    p.segments[3].turns = 3;
  } else if (name == "long") {
    // Reconnaissance UAV (thesis C.4 "aps UAVref", 125 min): climb to about 6 km, racetrack legs,
    // an S-turn search, descent.
    p.description = "125 min UAV: climb to 6 km, racetracks, S-turns, descent";
    p.initial.speed_mps = 40.0;
    p.substeps = 2;  // rates of a few deg/s: RK4 at 200 Hz is far below the INS's own error
    p.segments = {with(seg(K::climb, 30.0), &FlightSegment::angle_deg, 6.0), seg(K::straight, 1300.0),
                  with(seg(K::dive, 30.0), &FlightSegment::angle_deg, 6.0)};
    for (int i = 0; i < 4; ++i) {
      p.segments.push_back(seg(K::straight, 600.0));
      p.segments.push_back(with(seg(K::level_turn, 30.0), &FlightSegment::bank_deg, 25.0));
    }
    FlightSegment search = with(seg(K::s_turn, 600.0), &FlightSegment::bank_deg, 20.0);
    search.turns = 8;
    p.segments.push_back(search);
    p.segments.push_back(with(seg(K::dive, 30.0), &FlightSegment::angle_deg, 5.0));
    p.segments.push_back(seg(K::straight, 1300.0));
    p.segments.push_back(with(seg(K::climb, 30.0), &FlightSegment::angle_deg, 5.0));
    p.segments.push_back(seg(K::straight, 7500.0 - p.duration_s()));
  } else {
    fail("unknown built-in flight '", name, "'; known: ", join(builtin_flight_names()), " (or a .yaml or .csv file)");
  }
  return p;
}

FlightProfile load_flight_profile(const ConfigNode& node) {
  node.allow_only({"name", "description", "initial", "segments", "substeps"});
  FlightProfile p;
  p.name = node.text("name", "flight");
  p.description = node.text("description", "");
  p.substeps = node.integer("substeps", 10);
  if (auto i = node.find("initial")) {
    i->allow_only({"lat_deg", "lon_deg", "h_m", "speed_mps", "flight_path_deg", "heading_deg", "bank_deg"});
    p.initial.lat_deg = i->number("lat_deg", p.initial.lat_deg);
    p.initial.lon_deg = i->number("lon_deg", p.initial.lon_deg);
    p.initial.h_m = i->number("h_m", p.initial.h_m);
    p.initial.speed_mps = i->number("speed_mps", p.initial.speed_mps);
    p.initial.flight_path_deg = i->number("flight_path_deg", 0.0);
    p.initial.heading_deg = i->number("heading_deg", 0.0);
    p.initial.bank_deg = i->number("bank_deg", 0.0);
  }
  const ConfigNode segs = node["segments"];
  for (std::size_t k = 0; k < segs.size(); ++k) {
    const ConfigNode s = segs.at(k);
    s.allow_only({"kind", "duration_s", "accel_mps2", "angle_deg", "bank_deg", "load_factor", "turns"});
    FlightSegment f;
    f.kind = parse_enum<FlightSegmentKind>(s.text("kind"), s.where("kind"));
    f.duration_s = s.number("duration_s");
    f.accel_mps2 = s.number("accel_mps2", 0.0);
    f.angle_deg = s.number("angle_deg", 0.0);
    f.bank_deg = s.number("bank_deg", 0.0);
    f.load_factor = s.number("load_factor", 1.0);
    f.turns = static_cast<int>(s.integer("turns", 2));
    if (auto e = f.validate(); !e.empty()) fail(s.where(), ": ", e);
    p.segments.push_back(f);
  }
  if (auto e = p.validate(); !e.empty()) fail(node.where(), ": ", e);
  return p;
}

FlightTrajectory load_flight_csv(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, ": cannot open flight trajectory");
  std::stringstream text;
  text << in.rdbuf();
  return parse_flight_csv(text.str(), path);
}

FlightTrajectory parse_flight_csv(const std::string& text, const std::string& path) {
  // A flight CSV is a plain table (no gyro columns, so not a recording); C-locale numbers, nan allowed.
  std::istringstream in(text);
  std::string line;
  std::vector<std::string> names;
  std::vector<std::vector<double>> rows;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    if (names.empty()) {
      names = cells;
      continue;
    }
    if (cells.size() != names.size()) fail(path, ":", line_no, ": row has ", cells.size(), " cells, the header has ", names.size());
    std::vector<double> row;
    for (std::size_t c = 0; c < cells.size(); ++c) {
      char* end = nullptr;
      const double v = parse_c_double(cells[c].c_str(), &end);
      if (cells[c].empty() || *end != '\0') fail(path, ":", line_no, ": column '", names[c], "': '", cells[c], "' is not a number");
      row.push_back(v);
    }
    rows.push_back(row);
  }
  auto col = [&](const std::string& name) -> int {
    for (std::size_t c = 0; c < names.size(); ++c)
      if (names[c] == name) return static_cast<int>(c);
    return -1;
  };
  for (const char* required : {"t_s", "omega_x_dps", "omega_y_dps", "omega_z_dps", "f_x_mps2", "f_y_mps2", "f_z_mps2",
                               "lat_deg", "lon_deg", "h_m", "v_n_mps", "v_e_mps", "v_d_mps", "roll_deg", "pitch_deg", "yaw_deg"}) {
    if (col(required) < 0) fail(path, ": missing column '", required, "'");
  }
  if (rows.size() < 2) fail(path, ": a flight needs at least two rows");
  FlightTrajectory f;
  f.name = path;
  const int tc = col("t_s");
  f.dt_s = rows[1][static_cast<std::size_t>(tc)] - rows[0][static_cast<std::size_t>(tc)];
  auto state_at = [&](const std::vector<double>& r) {
    NavState s;
    s.lat = deg_to_rad(r[static_cast<std::size_t>(col("lat_deg"))]);
    s.lon = deg_to_rad(r[static_cast<std::size_t>(col("lon_deg"))]);
    s.h = r[static_cast<std::size_t>(col("h_m"))];
    s.v_n = Eigen::Vector3d(r[static_cast<std::size_t>(col("v_n_mps"))], r[static_cast<std::size_t>(col("v_e_mps"))], r[static_cast<std::size_t>(col("v_d_mps"))]);
    s.q_n_b = euler_to_quaternion(deg_to_rad(r[static_cast<std::size_t>(col("roll_deg"))]), deg_to_rad(r[static_cast<std::size_t>(col("pitch_deg"))]),
                                  deg_to_rad(r[static_cast<std::size_t>(col("yaw_deg"))]));
    return s;
  };
  bool full_truth = true;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    f.t_s.push_back(r[static_cast<std::size_t>(tc)]);
    if (i > 0) {
      const double step = f.t_s[i] - f.t_s[i - 1];
      if (!(std::abs(step - f.dt_s) <= 1e-6 * f.dt_s)) fail(path, ": row ", i + 1, ": the flight must be uniformly sampled (step ", step, " s)");
      f.dtheta.push_back(Eigen::Vector3d(r[static_cast<std::size_t>(col("omega_x_dps"))], r[static_cast<std::size_t>(col("omega_y_dps"))],
                                         r[static_cast<std::size_t>(col("omega_z_dps"))]) * deg_to_rad(1.0) * f.dt_s);
      f.dv.push_back(Eigen::Vector3d(r[static_cast<std::size_t>(col("f_x_mps2"))], r[static_cast<std::size_t>(col("f_y_mps2"))],
                                     r[static_cast<std::size_t>(col("f_z_mps2"))]) * f.dt_s);
    }
    bool has = true;
    for (const char* c : {"lat_deg", "h_m"}) has = has && !std::isnan(r[static_cast<std::size_t>(col(c))]);
    if (has) f.truth.push_back(state_at(r));
    else full_truth = false;
  }
  if (f.truth.empty()) fail(path, ": the first row must hold the initial state");
  if (!full_truth) f.truth.resize(1);
  return f;
}

}  // namespace gyrosid
