#include "design/design_space.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/format.h"
#include "core/units.h"

namespace gyrosid::design {

void DesignSpaceOptions::bind(OptionTable& t) {
  t.integer("space.segments", &segments, 1, 40, "programme segments (ramps or plateaus, each with its rate programme)")
      .real("space.temp_min_c", &temp_min_c, -273.0, 1000.0, "lowest chamber temperature of the design (default: domain - margin)")
      .real("space.temp_max_c", &temp_max_c, -273.0, 1000.0, "highest chamber temperature of the design (default: domain + margin)")
      .real("space.temperature_margin_c", &temperature_margin_c, 0.0, 200.0, "chamber bounds beyond the envelope's temperatures")
      .real("space.max_rate_dps", &max_rate_dps, 0.0, 1e4, "table rate bound (default: the envelope's)", true)
      .real("space.min_period_s", &min_period_s, 1.0, 1e5, "shortest rate cycle")
      .real("space.max_period_s", &max_period_s, 1.0, 1e6, "longest rate cycle")
      .real("space.preferred_period_s", &preferred_period_s, 1.0, 1e5, "rate cycle of a rounded smooth (ipopt) solution")
      .real("space.min_share", &min_share, 0.0, 0.5, "shortest segment as a fraction of the budget", true)
      .real("space.rate_hz", &rate_hz, 0.0, 1000.0, "sampling rate of the designed trajectory", true)
      .real("space.chamber_rate_limit_c_per_min", &chamber.rate_limit_c_per_min, 0.0, 1e3, "chamber rate limit", true)
      .real("space.chamber_cooling_limit_c_per_min", &chamber.cooling_limit_c_per_min, 0.0, 1e3,
            "chamber cooling rate limit (default: the heating limit, space.chamber_rate_limit_c_per_min)", true)
      .real("space.table_max_acceleration_dps2", &table_max_acceleration_dps2, 0.0, 1e6,
            "table angular acceleration limit (default: none; a triangle's cycles are cut to keep its slope below it)", true)
      .real("space.table_max_rate_dps", &table_max_rate_dps, 0.0, 1e5, "the table's rate limit (default: none; caps the design's rates)", true)
      .real("space.chamber_min_c", &chamber.min_c, -273.0, 1000.0, "chamber range, low end")
      .real("space.chamber_max_c", &chamber.max_c, -273.0, 1000.0, "chamber range, high end")
      .real("space.latitude_deg", &latitude_deg, -90.0, 90.0, "latitude of the rate table");
}

void DesignSpaceOptions::take(const Equipment& e) {
  chamber = e.chamber;
  if (std::isfinite(e.table.max_acceleration_radps2)) table_max_acceleration_dps2 = units::radps_to_dps(e.table.max_acceleration_radps2);
  if (std::isfinite(e.table_max_rate_radps)) table_max_rate_dps = units::radps_to_dps(e.table_max_rate_radps);
}

std::string DesignSpaceOptions::validate() const {
  if (!(budget_min > 0)) return str_cat("budget ", budget_min, " min must be positive");
  if (!(min_period_s < max_period_s)) return "space.min_period_s must be below space.max_period_s";
  if (preferred_period_s < min_period_s || preferred_period_s > max_period_s) return "space.preferred_period_s must lie within [min_period_s, max_period_s]";
  if (min_share * segments >= 1.0) return str_cat("space.min_share x space.segments = ", min_share * segments, " must be below 1");
  if (!(chamber.min_c < chamber.max_c)) return "space.chamber_min_c must be below space.chamber_max_c";
  if (positions.empty()) return "the design needs at least one mount position";
  if (!std::isnan(start_c) && (start_c < chamber.min_c || start_c > chamber.max_c)) {
    return str_cat("the start temperature ", start_c, " C is outside the chamber range [", chamber.min_c, ", ", chamber.max_c, "] C");
  }
  for (int p : positions) {
    if (p < 1 || p > 6) return str_cat("mount position ", p, " is not one of Table 2.1's positions 1..6");
  }
  return "";
}

DesignSpace::DesignSpace(DesignSpaceOptions o, double lo, double hi, double w_max) : o_(std::move(o)) {
  if (auto p = o_.validate(); !p.empty()) fail("design: ", p);
  t_lo_ = std::max(o_.chamber.min_c, std::isnan(o_.temp_min_c) ? lo - o_.temperature_margin_c : o_.temp_min_c);
  t_hi_ = std::min(o_.chamber.max_c, std::isnan(o_.temp_max_c) ? hi + o_.temperature_margin_c : o_.temp_max_c);
  if (!(t_hi_ > t_lo_)) fail("design: the chamber range [", o_.chamber.min_c, ", ", o_.chamber.max_c, "] C misses the design's temperatures");
  w_max_ = std::isnan(o_.max_rate_dps) ? w_max : units::dps_to_radps(o_.max_rate_dps);
  if (!std::isnan(o_.table_max_rate_dps)) w_max_ = std::min(w_max_, units::dps_to_radps(o_.table_max_rate_dps));
}

namespace {

// One segment's box coordinates (design_space.h: share, target T, rate a, rate b, log10 period, phase, and
// the index into the allowed positions when there is more than one).
struct BoxSegment {
  double share = 0.0, target_c = 0.0, rate_a = 0.0, rate_b = 0.0, log_period = 0.0, phase = 0.0, position = 0.0;
};

// The box vector v = [T_0, segment 0, segment 1, ...] read and written by name.
class BoxLayout {
 public:
  explicit BoxLayout(const DesignSpaceOptions& o) : segments_(o.segments), positions_(o.positions.size() > 1) {}
  Eigen::Index size() const { return 1 + segments_ * width(); }
  static constexpr Eigen::Index kStart = 0;  // T_0
  BoxSegment read(const Eigen::VectorXd& v, int i) const {
    const auto s = v.segment(first(i), width());
    return {s(0), s(1), s(2), s(3), s(4), s(5), positions_ ? s(6) : 0.0};
  }
  void write(Eigen::VectorXd& v, int i, const BoxSegment& b) const {
    auto s = v.segment(first(i), width());
    s.head(6) << b.share, b.target_c, b.rate_a, b.rate_b, b.log_period, b.phase;
    if (positions_) s(6) = b.position;
  }

 private:
  Eigen::Index width() const { return positions_ ? 7 : 6; }
  Eigen::Index first(int i) const { return 1 + i * width(); }
  int segments_;
  bool positions_;
};

}  // namespace

int DesignSpace::box_dimension() const { return static_cast<int>(BoxLayout(o_).size()); }

Eigen::VectorXd DesignSpace::box_lower() const {
  const BoxLayout box(o_);
  Eigen::VectorXd v(box.size());
  v(BoxLayout::kStart) = t_lo_;
  for (int i = 0; i < o_.segments; ++i) box.write(v, i, {o_.min_share, t_lo_, -w_max_, -w_max_, std::log10(o_.min_period_s), 0.0, 0.0});
  return v;
}

Eigen::VectorXd DesignSpace::box_upper() const {
  const BoxLayout box(o_);
  Eigen::VectorXd v(box.size());
  v(BoxLayout::kStart) = t_hi_;
  for (int i = 0; i < o_.segments; ++i) {
    box.write(v, i, {1.0, t_hi_, w_max_, w_max_, std::log10(o_.max_period_s), 1.0, static_cast<double>(o_.positions.size()) - 1e-9});
  }
  return v;
}

namespace {

// A triangle between low and high, or a dwell when they (nearly) coincide.
RateProfile rate_programme(double low, double high, double cycles, double phase, double w_max) {
  if (high - low < 1e-3 * w_max) return RateProfile::constant(0.5 * (low + high));
  return RateProfile::triangle(low, high, cycles, phase - std::floor(phase));
}

}  // namespace

TableProfile DesignSpace::assemble(double start_c, const std::vector<ProfileSegment>& segments) const {
  TableProfile p;
  p.name = str_cat("design ", format_significant(o_.budget_min, 4), " min");
  p.kind = "programme";
  p.latitude_rad = units::deg_to_rad(o_.latitude_deg);
  p.limits = o_.chamber;
  if (!std::isnan(o_.table_max_acceleration_dps2)) p.table_limits.max_acceleration_radps2 = units::dps_to_radps(o_.table_max_acceleration_dps2);
  double prev = std::isnan(o_.start_c) ? std::clamp(start_c, t_lo_, t_hi_) : o_.start_c;  // a pinned start: v(0) unused
  for (ProfileSegment s : segments) {
    // The chamber moves towards the target no faster than its heating or cooling limit.
    s.chamber_start_c = prev;
    s.chamber_end_c = o_.chamber.reach_c(prev, std::clamp(s.chamber_end_c, t_lo_, t_hi_), s.duration_s);
    // A triangle no steeper than the table's acceleration limit: at most duration a / (2 (high - low)) cycles.
    if (s.rate.shape == RateProfile::Shape::triangle) {
      s.rate.cycles = std::min(s.rate.cycles, s.duration_s * p.table_limits.max_acceleration_radps2 / (2.0 * (s.rate.high_radps - s.rate.low_radps)));
    }
    s.label = s.chamber_end_c == prev ? str_cat("plateau ", format_significant(prev, 3), " C")
                                      : str_cat("ramp ", format_significant(prev, 3), " -> ", format_significant(s.chamber_end_c, 3), " C");
    prev = s.chamber_end_c;
    p.segments.push_back(std::move(s));
  }
  if (auto problem = p.check_limits(); !problem.empty()) fail("design: internal error, infeasible programme: ", problem);
  return p;
}

TableProfile DesignSpace::decode_box(const Eigen::VectorXd& v) const {
  const BoxLayout box(o_);
  if (v.size() != box.size()) fail("design: ", v.size(), " variables for a box of ", box.size());
  double total = 0.0;
  for (int i = 0; i < o_.segments; ++i) total += std::max(box.read(v, i).share, o_.min_share);
  std::vector<ProfileSegment> segments;
  for (int i = 0; i < o_.segments; ++i) {
    const BoxSegment s = box.read(v, i);
    ProfileSegment seg;
    seg.duration_s = budget_s() * std::max(s.share, o_.min_share) / total;
    seg.chamber_end_c = s.target_c;
    const double a = std::clamp(s.rate_a, -w_max_, w_max_), b = std::clamp(s.rate_b, -w_max_, w_max_);
    const double period = std::pow(10.0, std::clamp(s.log_period, std::log10(o_.min_period_s), std::log10(o_.max_period_s)));
    seg.rate = rate_programme(std::min(a, b), std::max(a, b), seg.duration_s / period, s.phase, w_max_);
    const auto index = std::min(static_cast<std::size_t>(std::max(0.0, s.position)), o_.positions.size() - 1);
    seg.position = o_.positions[index];
    segments.push_back(seg);
  }
  return assemble(v(BoxLayout::kStart), segments);
}

Eigen::VectorXd DesignSpace::encode_box(const TableProfile& p) const {
  if (static_cast<int>(p.segments.size()) != o_.segments) fail("design: a programme of ", p.segments.size(), " segments in a space of ", o_.segments);
  const BoxLayout box(o_);
  Eigen::VectorXd v(box.size());
  v(BoxLayout::kStart) = p.segments.front().chamber_start_c;
  // Shares are relative: scale them so that the shortest segment keeps its share above min_share.
  double shortest = INFINITY;
  for (const auto& seg : p.segments) shortest = std::min(shortest, seg.duration_s / budget_s());
  const double share_scale = std::max(1.0, o_.min_share / shortest);
  for (int i = 0; i < o_.segments; ++i) {
    const ProfileSegment& seg = p.segments[static_cast<std::size_t>(i)];
    const bool tri = seg.rate.shape == RateProfile::Shape::triangle;
    const double period = tri && seg.rate.cycles > 0 ? seg.duration_s / seg.rate.cycles : o_.preferred_period_s;
    const auto it = std::find(o_.positions.begin(), o_.positions.end(), seg.position);
    box.write(v, i, {share_scale * seg.duration_s / budget_s(), seg.chamber_end_c, tri ? seg.rate.low_radps : seg.rate.value_radps,
                     tri ? seg.rate.high_radps : seg.rate.value_radps, std::log10(std::clamp(period, o_.min_period_s, o_.max_period_s)),
                     tri ? seg.rate.phase : 0.0, it == o_.positions.end() ? 0.0 : static_cast<double>(it - o_.positions.begin()) + 0.5});
  }
  return v.cwiseMax(box_lower()).cwiseMin(box_upper());
}

TableProfile DesignSpace::decode_smooth(const SmoothProgramme& x) const {
  const std::size_t k = x.duration_s.size();
  double total = 0.0;
  for (double d : x.duration_s) total += std::max(d, 1.0);
  std::vector<ProfileSegment> segments;
  for (std::size_t i = 0; i < k; ++i) {
    ProfileSegment seg;
    seg.duration_s = budget_s() * std::max(x.duration_s[i], 1.0) / total;
    seg.chamber_end_c = x.end_c[i];
    const double low = std::clamp(std::min(x.low_radps[i], x.high_radps[i]), -w_max_, w_max_);
    const double high = std::clamp(std::max(x.low_radps[i], x.high_radps[i]), -w_max_, w_max_);
    const double cycles = std::max(1.0, std::round(seg.duration_s / o_.preferred_period_s));
    seg.rate = rate_programme(low, high, cycles, 0.5 * static_cast<double>(i % 2), w_max_);
    seg.position = o_.positions.front();
    segments.push_back(seg);
  }
  return assemble(x.start_c, segments);
}

SmoothProgramme DesignSpace::smooth_of(const TableProfile& p) const {
  SmoothProgramme x;
  x.start_c = p.segments.front().chamber_start_c;
  for (const auto& s : p.segments) {
    const bool tri = s.rate.shape == RateProfile::Shape::triangle;
    x.duration_s.push_back(s.duration_s);
    x.end_c.push_back(s.chamber_end_c);
    x.low_radps.push_back(tri ? s.rate.low_radps : s.rate.value_radps);
    x.high_radps.push_back(tri ? s.rate.high_radps : s.rate.value_radps);
  }
  return x;
}

TableProfile DesignSpace::initial() const {
  // Sweeps between the ends of the chamber bounds (down first: the flights start warm), equal durations,
  // full-range rate cycles with the phase alternating as in the thesis's dual scan.
  std::vector<ProfileSegment> segments;
  for (int i = 0; i < o_.segments; ++i) {
    ProfileSegment seg;
    seg.duration_s = budget_s() / o_.segments;
    seg.chamber_end_c = i % 2 == 0 ? t_lo_ : t_hi_;
    seg.rate = rate_programme(-w_max_, w_max_, std::max(1.0, std::round(seg.duration_s / o_.preferred_period_s)),
                              0.5 * (i % 2), w_max_);
    seg.position = o_.positions.front();
    segments.push_back(seg);
  }
  return assemble(t_hi_, segments);
}

}  // namespace gyrosid::design
