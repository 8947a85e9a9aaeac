#include "solvers/triad/triad_fit.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <vector>

#include "core/error.h"
#include "model/fit_notes.h"
#include "core/recording.h"
#include "core/stats.h"
#include "core/triad_axes.h"
#include "core/units.h"
#include "model/classical_model.h"
#include "model/gaussian_node.h"
#include "model/rbf_network.h"
#include "solvers/calibrate.h"
#include "solvers/nls/nls_covariance.h"
#include "solvers/nls/nls_solver.h"
#include "solvers/solver.h"
#include "solvers/triad/auto_estimation.h"
#include "solvers/triad/gravity_turns.h"
#include "solvers/triad/triad_problem.h"

namespace gyrosid {

OptionTable TriadFitOptions::table() {
  OptionTable t("triad");
  t.choice("surfaces", &surfaces, {"none", "classical", "greybox", "rbf"}, "each gyro's remaining error surface e_i(T, g)")
      .choice("estimation", &estimation, {"joint", "sequential", "auto"}, "joint: one problem for everything; sequential: M and b first and the surfaces after; auto: both, and the joint fit returned only where a test rejects the sequential fit's restriction (M separable from the surfaces) - on balanced programmes the restricted fit is the more efficient (solvers/triad/auto_estimation.h)")
      .real("coupling_test_level", &coupling_test_level, 1e-9, 0.5, "estimation=auto: the test's level, at most the chance of returning the joint fit where the sequential fit's restriction holds")
      .choice("solver", &solver, nls_solvers().names(), "least-squares back-end (solvers/nls)")
      .integer("bias_order", &bias_order, 0, 6, "order of each gyro's bias polynomial in temperature")
      .flag("g_sensitivity", &g_sensitivity, "estimate the g-sensitivity matrix G (needs accel_{x,y,z}_mps2)")
      .choice("reference", &reference, {"auto", "rate", "angle", "gravity"}, "rate: per-sample reference rates; angle: each position_id segment known by its integral (Ferraris); gravity: hand turns (position_id 0) known by the gravity directions of the holds around them (IMU-TK); auto: from the metadata 'reference'")
      .real("max_sigma", &max_sigma, 0.0, 1.0, "M and G entries with a larger sigma are reported as not determined", true)
      .real("collinearity", &collinearity, 1e-12, 0.5, "a surface coefficient this close (sine) to the span of M, b, G is held at nominal")
      .text("surface_solver", &surface_solver, "RBF solver of the RBF surfaces (sequential fit, joint start)")
      .choice("surface_input", &surface_input, {"smoothed", "measured"}, "the rate the surfaces are fitted at: smoothed = each output with its white noise averaged down where the reference holds still (surface_window); measured = the recorded outputs, noise included (errors in variables)")
      .integer("surface_window", &surface_window, 0, 100000, "surface_input=smoothed: half-width (samples) of the centred window")
      .choice("sequential_scale", &sequential_scale, {"triad", "surface"}, "sequential classical surfaces: triad = the second stage re-estimates M_ii (against the reference rate) and b with the surfaces, off-diagonals and G held - the joint fit's parametrisation; surface = the surface fitter's own constant scale factor on the measured output (its residual is then (1 - s_0) times the output residual)")
      .choice("rbf_joint", &rbf_joint, {"weights", "nodes"}, "joint rbf surfaces: weights moves the weights of the sequential fit's nodes (its centres and widths held: its cost can only fall); nodes moves centres and widths too")
      .choice("rbf_diagonal", &rbf_diagonal, {"mean", "zero_rate"}, "rbf surfaces: what M_ii carries - mean = the first stage's mean scale factor over the turns, the surface's share of M_ii's column held; zero_rate = the zero-rate scale factor, the surface's mean slope at zero rate held at 0 (the off-diagonals then the zero-rate cross gains: much better on a FOG's short and medium flights from balanced programmes, much worse from unbalanced ones)")
      .choice("rbf_bias", &rbf_bias, {"held", "free"}, "joint rbf surfaces (rbf_form=error, rbf_diagonal=mean): held = the bias polynomials stay at the sequential fit's, so the joint fit moves M and the weights and leaves the static response (which M does not act on) as the sequential fit found it; free = the bias polynomials move too, and take misfit from the turning rows into the static response between the temperature plateaus")
      .choice("rbf_form", &rbf_form, {"error", "scale_factor"}, "rbf surfaces: error = the network is the rate error e(T, g); scale_factor = the network is a relative scale-factor error r(T, g) and e = g r (the classical surface's form; fitted where |g| >= rbf_min_rate_dps; the static bias is then b(T)'s alone; with turns only at temperature plateaus far apart give the network a width that bridges them, e.g. surface.width=0.6)")
      .real("rbf_min_rate_dps", &rbf_min_rate_dps, 1e-6, 1e3, "rbf_form=scale_factor: the relative error is fitted on the samples where the gyro turns at least this fast, deg/s")
      .choice("order_criterion", &order_criterion, {"bic_lr", "bic", "aic"}, "how surface.sf_rate_order=auto / sf_cross_order=auto choose: bic_lr (the default: BIC's order, raised to the lowest order a likelihood-ratio test against the top order does not reject at order_test_level - BIC where the family holds the sensor, the order that removes the lack of fit where it does not, e.g. a FOG's rate ripple), bic (Schwarz: for the parameters, consistent when the family holds the sensor) or aic (Akaike: for prediction at the flights - higher orders, larger sigmas of M_ii)")
      .real("order_test_level", &order_test_level, 1e-9, 0.5, "order_criterion=bic_lr: the likelihood-ratio test's level, the chance of raising an order that holds the sensor")
      .passthrough("nls.", &solver_options, "an option of the least-squares back-end (listed by --options-of triad)")
      .passthrough("surface.", &surface_options, "an option of the surface kind or of its RBF solver; classical: sf_temperature_order, sf_rate_order (0..10 or auto; default here auto = 0..6 by order_criterion), sf_cross_order (0..4 or auto; default here auto = 0..3 by order_criterion, 0 = the thesis's separable form)");
  return t;
}

namespace {

ClassicalOptions classical_surface_options(const OptionMap& map) {
  ClassicalOptions o;  // the thesis's orders; the bias polynomial is the triad's own
  OptionTable t("triad classical surface");
  t.integer("sf_temperature_order", &o.sf_temperature_order, 0, 6, "scale-factor polynomial order in temperature")
      .integer("sf_rate_order", &o.sf_rate_order, 0, 10, "scale-factor polynomial order in rate (auto: 0..6 by order_criterion, fit_triad)")
      .integer("sf_cross_order", &o.sf_cross_order, 0, 4, "temperature order of the rate shape's coefficients (0: separable; auto: 0..3 by order_criterion, fit_triad)");
  t.apply(map);
  return o;
}

// surface.sf_rate_order=auto, surface.sf_cross_order=auto (classical surfaces): the orders chosen by
// order_criterion (fit_triad below).
constexpr int kMaxAutoRateOrder = 6;   // the thesis's order (fig 3.4), ClassicalOptions' default
constexpr int kMaxAutoCrossOrder = 3;
constexpr const char* kOrderKeys[] = {"sf_rate_order", "sf_cross_order"};
bool order_auto(const OptionMap& surface_options, const std::string& key) {
  const auto it = surface_options.find(key);
  return it != surface_options.end() && it->second == "auto";
}
// The triad's classical surfaces choose their rate order and cross order (order_criterion) unless told. The rate order:
// a triad programme visits few rate magnitudes per gyro (four, on the independent generator's six positions
// plus diagonal turns), and the thesis's order 6 then leaves M_ii's column nearly in the span of the odd rate
// powers - sigma(M_ii) 0.35 % there against 42 ppm at the order BIC chooses (experiments/triad_misalignment
// README, "Independent generator"). The cross order: the separable form (the thesis's, the single-gyro
// classical model's default) cannot hold a rate shape that moves with temperature, and a joint fit then leaks
// that misfit into M's off-diagonals (joint 1.108x sequential on the one-diagonal training's short flight with
// it, 0.27x with the order BIC chooses). Other surface kinds: the options as given.
OptionMap effective_surface_options(const std::string& surfaces, OptionMap map) {
  if (surfaces != "classical") return map;
  for (const char* key : kOrderKeys) map.emplace(key, "auto");
  return map;
}
OptionMap with_order(OptionMap map, const std::string& key, int order) {
  map[key] = std::to_string(order);
  return map;
}
}  // namespace

std::string TriadFitOptions::validate() const {
  if (order_criterion != "bic_lr" && order_criterion != "bic" && order_criterion != "aic")
    return str_cat("order_criterion must be bic_lr, bic or aic, not '", order_criterion, "'");
  if (!(order_test_level > 0.0 && order_test_level <= 0.5)) return str_cat("order_test_level must lie in (0, 0.5], not ", order_test_level);
  if (estimation != "joint" && estimation != "sequential" && estimation != "auto")
    return str_cat("estimation must be joint, sequential or auto, not '", estimation, "'");
  if (!(coupling_test_level > 0.0 && coupling_test_level <= 0.5)) return str_cat("coupling_test_level must lie in (0, 0.5], not ", coupling_test_level);
  for (const char* key : kOrderKeys) {
    if (!order_auto(effective_surface_options(surfaces, surface_options), key)) continue;
    if (surfaces != "classical") return str_cat("surface.", key, "=auto needs surfaces=classical");
    TriadFitOptions fixed = *this;
    fixed.surface_options = with_order(effective_surface_options(surfaces, surface_options), key, 0);
    return fixed.validate();
  }
  try {
    make_nls_solver(solver, solver_options);
    if (surfaces == "greybox" && estimation != "sequential") {
      return "surfaces=greybox is fitted by its own solver (thermal-lag search, ridge): use estimation=sequential, or classical/rbf surfaces for a joint solve";
    }
    if (rbf_form == "scale_factor" && surfaces != "rbf") return "rbf_form=scale_factor needs surfaces=rbf";
    if (rbf_form == "scale_factor" && rbf_diagonal == "zero_rate") {
      return "rbf_diagonal=zero_rate holds an additive surface's slope at zero rate; with rbf_form=scale_factor the network's value there is the zero-rate scale factor's share (use rbf_diagonal=mean)";
    }
    if (surfaces == "rbf") {
      make_solver(surface_solver, surface_options);
    } else if (surfaces == "classical" && estimation != "sequential") {
      classical_surface_options(surface_options);
    } else if (surfaces == "none" && !surface_options.empty()) {
      return "surface.* options given but surfaces=none";
    }
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

namespace {

// One solve of the triad problem: entries the data do not determine held at nominal, the back-end run, the
// covariance at the solution.
struct Stage {
  NlsProblem problem;
  TriadLayout layout;
  SolveSummary summary;
  NlsCovariance covariance;
  std::vector<std::string> undetermined;  // entry names held at nominal
};

// rbf_joint=weights: every node's centre and log-width entries held (the packed block [c, rho, w] of
// model/gaussian_node.h), so only its weight moves.
void hold_node_shapes(NlsProblem& p, const TriadLayout& layout) {
  for (const auto& nodes : layout.nodes) {
    for (int b : nodes) {
      for (int e = 0; e + 1 < p.block(b).size(); ++e) p.fix(b, e);
    }
  }
}

// rbf_bias=held (triad_fit.h): in a problem with additive RBF nodes in the mean gauge, every bias coefficient held
// at its start value - the sequential fit's.
bool holds_rbf_bias(const TriadFitOptions& o) {
  return o.surfaces == "rbf" && o.rbf_bias == "held" && o.rbf_form == "error" && o.rbf_diagonal == "mean";
}
void hold_bias(NlsProblem& p, const TriadLayout& layout) {
  for (int b : layout.bias) {
    for (int e = 0; e < p.block(b).size(); ++e) p.fix(b, e);
  }
}

// hold_cross_axis: M's off-diagonal entries and G held at the spec's start values (the sequential fit's second
// stage, classical surfaces).
// `start`: a solved stage of the same spec whose values the problem starts from (its free entries and the held).
Stage run_stage(const TriadData& d, const TriadRows& rows, const TriadProblemSpec& spec, const TriadFitOptions& o,
                const std::vector<GravityTurn>* turns = nullptr, bool hold_cross_axis = false, bool whiten_turns = true,
                const Stage* start = nullptr) {
  Stage s;
  s.problem = build_triad_problem(d, rows, spec, s.layout);
  if (start) {
    for (int b = 0; b < s.problem.block_count(); ++b) s.problem.block(b).values = start->problem.block(b).values;
  }
  if (hold_cross_axis) {
    for (int i = 0; i < 3; ++i) {
      const auto ai = static_cast<std::size_t>(i);
      for (int j = 0; j < 3; ++j) {
        if (j != i) s.problem.fix(s.layout.misalignment[ai], j);
        if (s.layout.g_sensitivity[ai] >= 0) s.problem.fix(s.layout.g_sensitivity[ai], j);
      }
    }
  }
  if (turns) add_gravity_turns(s.problem, d, *turns, spec, s.layout, 3, whiten_turns);  // group 3: the turns' own noise level
  if (o.rbf_joint == "weights") hold_node_shapes(s.problem, s.layout);
  if (holds_rbf_bias(o) && !s.layout.nodes[0].empty()) hold_bias(s.problem, s.layout);
  const auto free = s.problem.free_entries();  // copy: fixing changes the free set
  // M, b and G are the anchors: a linear surface coefficient within `collinearity` of their span (a rate shape
  // seen at one rate only looks like M_ii) is held; node parameters only when exactly undetermined.
  auto is_node = [&](const NlsProblem::FreeEntry& e) { return s.problem.block(e.block).name.find("_node") != std::string::npos; };
  auto is_surface = [&](const NlsProblem::FreeEntry& e) { return s.problem.block(e.block).name.rfind("surface_", 0) == 0; };
  std::vector<double> tolerance;
  std::vector<bool> anchor;
  for (const auto& e : free) {
    tolerance.push_back(is_node(e) ? 1e-7 : o.collinearity);
    anchor.push_back(!is_surface(e));
  }
  const NlsObservability obs = analyse_observability(s.problem, tolerance, anchor);
  for (std::size_t j = 0; j < free.size(); ++j) {
    if (obs.observable[j]) continue;
    NlsProblem::ParameterBlock& b = s.problem.block(free[j].block);
    const bool node = is_node(free[j]);
    if (!node) b.values[static_cast<std::size_t>(free[j].entry)] = 0.0;  // nominal; a node keeps its start
    s.problem.fix(free[j].block, free[j].entry);
    s.undetermined.push_back(s.problem.entry_name(free[j].block, free[j].entry));
  }
  OptionMap solver_options = o.solver_options;
  const bool nodes = spec.surfaces[0] && spec.surfaces[0]->nodes() > 0;
  if (o.solver == "ceres" && nodes && !solver_options.count("linear_solver")) {
    solver_options["linear_solver"] = "sparse_normal_cholesky";  // RBF nodes: the three gyros' blocks stay apart
  }
  const auto solver = make_nls_solver(o.solver, solver_options);
  s.summary = solve(*solver, s.problem);
  if (!s.summary.usable()) fail("triad: the ", o.solver, " solve failed: ", s.summary.message);
  s.covariance = estimate_covariance(s.problem);
  return s;
}

// sigma and inflation of every entry of a block (NaN for fixed entries).
std::vector<std::pair<double, double>> block_sigma(const Stage& s, int block) {
  std::vector<std::pair<double, double>> out(static_cast<std::size_t>(s.problem.block(block).size()), {NAN, NAN});
  if (!s.covariance.ok) return out;
  const auto& free = s.problem.free_entries();
  for (std::size_t j = 0; j < free.size(); ++j) {
    if (free[j].block == block) out[static_cast<std::size_t>(free[j].entry)] = {s.covariance.sigma(static_cast<Eigen::Index>(j)), s.covariance.inflation(static_cast<Eigen::Index>(j))};
  }
  return out;
}

bool is_fixed(const NlsProblem& p, int block, int entry) { return p.block(block).fixed[static_cast<std::size_t>(entry)]; }

// TriadUncertainty::misalignment_covariance from a stage: the covariance of the M entries it estimated.
Eigen::Matrix<double, 9, 9> misalignment_covariance_of(const Stage& s) {
  Eigen::Matrix<double, 9, 9> c = Eigen::Matrix<double, 9, 9>::Constant(NAN);
  if (!s.covariance.ok) return c;
  std::vector<std::pair<int, Eigen::Index>> at;  // (3 i + j, index among the free entries)
  const auto& free = s.problem.free_entries();
  for (std::size_t k = 0; k < free.size(); ++k)
    for (int i = 0; i < 3; ++i)
      if (free[k].block == s.layout.misalignment[static_cast<std::size_t>(i)]) at.emplace_back(3 * i + free[k].entry, static_cast<Eigen::Index>(k));
  for (const auto& [a, ka] : at)
    for (const auto& [b, kb] : at) c(a, b) = s.covariance.covariance(ka, kb);
  return c;
}

// Sigmas and determined entries of M, b and G from a stage; M and G entries above max_sigma are set to
// nominal in `model` and reported.
TriadUncertainty uncertainty_of(const Stage& s, bool g_sensitivity, double max_sigma, TriadModel& model, std::vector<std::string>& notes) {
  TriadUncertainty u;
  u.misalignment_covariance = misalignment_covariance_of(s);
  if (g_sensitivity) u.g_sensitivity_sigma = Eigen::Matrix3d::Constant(NAN);
  for (int i = 0; i < 3; ++i) {
    const auto ai = static_cast<std::size_t>(i);
    u.noise_radps[ai] = s.covariance.group_sigma.empty() ? NAN : s.covariance.group_sigma[ai];
    const auto m = block_sigma(s, s.layout.misalignment[ai]);
    for (int j = 0; j < 3; ++j) {
      const auto [sigma, inflation] = m[static_cast<std::size_t>(j)];
      u.misalignment_sigma(i, j) = sigma;
      u.misalignment_inflation(i, j) = inflation;
      bool known = !is_fixed(s.problem, s.layout.misalignment[ai], j);
      if (known && !(sigma <= max_sigma)) {  // NaN: no covariance - not a measurement either
        notes.push_back(str_cat("M_", kTriadAxes[i], kTriadAxes[j], ": sigma ", sigma, " exceeds max_sigma ", max_sigma, " (or could not be computed) - reported as not determined, compensated with 0"));
        known = false;
        model.misalignment(i, j) = 0.0;
      }
      u.misalignment_known[ai][static_cast<std::size_t>(j)] = known;
    }
    const auto b = block_sigma(s, s.layout.bias[ai]);
    u.bias_sigma[ai].resize(static_cast<Eigen::Index>(b.size()));
    for (std::size_t k = 0; k < b.size(); ++k) {
      u.bias_sigma[ai](static_cast<Eigen::Index>(k)) = b[k].first;
      u.bias_known[ai].push_back(!is_fixed(s.problem, s.layout.bias[ai], static_cast<int>(k)));
    }
    if (!g_sensitivity) continue;
    const auto g = block_sigma(s, s.layout.g_sensitivity[ai]);
    for (int j = 0; j < 3; ++j) {
      const double sigma = g[static_cast<std::size_t>(j)].first;
      (*u.g_sensitivity_sigma)(i, j) = sigma;
      bool known = !is_fixed(s.problem, s.layout.g_sensitivity[ai], j);
      if (known && !(sigma <= max_sigma)) {
        notes.push_back(str_cat("G_", kTriadAxes[i], kTriadAxes[j], ": sigma ", sigma, " rad/s per m/s^2 exceeds max_sigma - reported as not determined"));
        known = false;
        (*model.g_sensitivity)(i, j) = 0.0;
      }
      u.g_sensitivity_known[ai][static_cast<std::size_t>(j)] = known;
    }
  }
  return u;
}

std::string undetermined_note(const std::string& name) { return name + ": not determined by the data - held at its nominal value"; }

// Whether an entry's name (M_xy, G_xy, ...) is one the sequential classical fit holds in its second stage: M's
// off-diagonals and G.
bool held_in_second_stage(const std::string& name) {
  return name.rfind("G_", 0) == 0 || (name.rfind("M_", 0) == 0 && name.size() > 3 && name[2] != name[3]);
}

// The sequential classical fit's uncertainty: M_ii, b and the surfaces from its second stage, M's off-diagonals
// and G (held there) from the first, where they were estimated; an entry the first stage left undetermined is
// compensated with 0 and noted, as uncertainty_of does.
TriadUncertainty sequential_uncertainty(const Stage& first, const Stage& second, bool g_sensitivity, double max_sigma, TriadModel& model,
                                        std::vector<std::string>& notes) {
  TriadModel scratch = model;
  std::vector<std::string> first_notes;
  const TriadUncertainty u1 = uncertainty_of(first, g_sensitivity, max_sigma, scratch, first_notes);
  TriadUncertainty u = uncertainty_of(second, g_sensitivity, max_sigma, model, notes);
  for (int i = 0; i < 3; ++i) {
    const auto ai = static_cast<std::size_t>(i);
    for (int j = 0; j < 3; ++j) {
      const auto aj = static_cast<std::size_t>(j);
      if (j != i) {
        u.misalignment_sigma(i, j) = u1.misalignment_sigma(i, j);
        u.misalignment_inflation(i, j) = u1.misalignment_inflation(i, j);
        u.misalignment_known[ai][aj] = u1.misalignment_known[ai][aj];
        if (!u1.misalignment_known[ai][aj]) model.misalignment(i, j) = 0.0;
        for (int k = 0; k < 3; ++k)
          for (int l = 0; l < 3; ++l)
            if (l != k) u.misalignment_covariance(3 * i + j, 3 * k + l) = u1.misalignment_covariance(3 * i + j, 3 * k + l);
      }
      if (g_sensitivity) {
        (*u.g_sensitivity_sigma)(i, j) = (*u1.g_sensitivity_sigma)(i, j);
        u.g_sensitivity_known[ai][aj] = u1.g_sensitivity_known[ai][aj];
        if (!u1.g_sensitivity_known[ai][aj]) (*model.g_sensitivity)(i, j) = 0.0;
      }
    }
  }
  for (const auto& n : first_notes) {
    if (held_in_second_stage(n)) notes.push_back(n);
  }
  for (const auto& name : first.undetermined) {
    if (held_in_second_stage(name)) notes.push_back(undetermined_note(name));
  }
  return u;
}

// The samples where gyro a turns at `min_rate_dps` or more (|surface rate|): the rows a relative error e / g
// is measured on.
std::vector<Eigen::Index> turning_rows(const Eigen::MatrixX3d& surface_rate, int a, double min_rate_dps) {
  std::vector<Eigen::Index> out;
  for (Eigen::Index k = 0; k < surface_rate.rows(); ++k)
    if (std::abs(surface_rate(k, a)) >= units::dps_to_radps(min_rate_dps)) out.push_back(k);
  return out;
}

// rbf_form=scale_factor (triad_fit.h): gyro a's relative error r = e / g fitted by the RBF solver on the rows where
// it turns (turning_rows; there r's noise is the output's divided by |g|), its output then multiplied by the
// measured rate - e = g r(T, g).
std::shared_ptr<const CalibrationModel> fit_scale_factor_network(const TriadData& at, int a, const Eigen::VectorXd& error, const CalibrationRequest& request,
                                                                 double min_rate_dps, nlohmann::json& stages) {
  const std::vector<Eigen::Index> rows = turning_rows(at.gyro, a, min_rate_dps);
  constexpr std::size_t kMinRows = 20;
  if (rows.size() < kMinRows) {
    fail("triad: rbf_form=scale_factor: gyro ", kTriadAxes[a], " turns at ", min_rate_dps, " deg/s or more on ", rows.size(),
         " samples - too few to fit its scale factor (rbf_min_rate_dps, or rbf_form=error)");
  }
  TriadData turning;
  turning.gyro = at.gyro(rows, Eigen::all);
  turning.temp_c = at.temp_c(rows, Eigen::all);
  turning.reference = at.reference(rows, Eigen::all);
  for (const Eigen::Index k : rows) turning.t_s.push_back(at.t_s[static_cast<std::size_t>(k)]);
  Eigen::VectorXd relative(turning.size());
  for (Eigen::Index r = 0; r < turning.size(); ++r) relative(r) = error(rows[static_cast<std::size_t>(r)]) / turning.gyro(r, a);
  CalibrationResult fitted = calibrate(axis_recording(turning, a, &relative), request);
  stages.push_back({{"stage", str_cat("surface ", kTriadAxes[a], " (relative error on ", rows.size(), " turning samples)")}, {"summary", fitted.summary}});
  const auto* net = dynamic_cast<const RbfNetwork*>(fitted.model.get());
  if (!net) fail("triad: rbf_form=scale_factor needs an RBF network from surface_solver '", request.solver, "'");
  auto scaled = std::make_shared<RbfNetwork>(*net);
  scaled->output_factor = 0;  // the measured rate (axis_recording's features: measured_rate, temperature)
  return scaled;
}

// Each gyro's surface fitted to what the triad's linear part leaves (sequential stage 2, joint RBF start).
// A classical surface gets the triad's bias order unless told otherwise, so that sequential and joint fits
// span the same family of functions.
std::array<std::shared_ptr<const CalibrationModel>, 3> fit_surfaces(const TriadData& d, const TriadModel& linear, const TriadFitOptions& o,
                                                                    int bias_order, const Eigen::MatrixX3d& surface_rate, nlohmann::json& stages) {
  CalibrationRequest request;
  request.model = o.surfaces;
  request.solver = o.surface_solver;
  request.options = o.surface_options;
  if (o.surfaces == "classical" && !request.options.count("bias_order")) request.options["bias_order"] = std::to_string(bias_order);
  const Eigen::MatrixX3d left = d.gyro - linear.predict_outputs(d);
  TriadData at = d;  // the surfaces' rate input: what axis_recording calls the measured rate
  at.gyro = surface_rate;
  std::array<std::shared_ptr<const CalibrationModel>, 3> out;
  for (int a = 0; a < 3; ++a) {
    const Eigen::VectorXd error = left.col(a);
    if (o.rbf_form == "scale_factor") {
      out[static_cast<std::size_t>(a)] = fit_scale_factor_network(at, a, error, request, o.rbf_min_rate_dps, stages);
      continue;
    }
    CalibrationResult r = calibrate(axis_recording(at, a, &error), request);
    stages.push_back({{"stage", str_cat("surface ", kTriadAxes[a])}, {"summary", r.summary}});
    out[static_cast<std::size_t>(a)] = std::move(r.model);
  }
  return out;
}

// rbf_diagonal=zero_rate (triad_fit.h): one row w' s, s_j the slope d phi_j / d x_rate of node j at zero rate
// averaged over kSlopeTemperatures temperatures spread over [t_lo, t_hi] (normalised), times kSlopeWeight -
// the surface's mean slope in its own rate at zero rate, held near 0 so that M_aa carries the zero-rate scale
// factor. One row, one degree of freedom: the gauge along which M_aa and the surface trade. A slope that
// varies with temperature (a scale factor s_T(T)) stays the surface's.
Eigen::MatrixXd zero_rate_slope_row(const RbfNetwork& net, double t_lo, double t_hi) {
  constexpr int kSlopeTemperatures = 21;
  constexpr double kSlopeWeight = 1e3;  // a hard gauge on one degree of freedom (triad_fit.h)
  const double raw[2] = {0.0, 0.0};
  double x[2];
  net.normalizer.apply(raw, x);
  const Eigen::Index d = net.dimension();
  std::vector<double> block(static_cast<std::size_t>(NodeBlock<double>::size(d))), gradient(block.size());
  Eigen::MatrixXd row = Eigen::MatrixXd::Zero(1, net.nodes());
  for (Eigen::Index j = 0; j < net.nodes(); ++j) {
    net.pack_node(j, block.data());
    block.back() = 1.0;  // phi itself: d phi / d x_0 = -d phi / d c_0 (phi depends on x - c; model/gaussian_node.h)
    for (int m = 0; m < kSlopeTemperatures; ++m) {
      x[1] = t_lo + (t_hi - t_lo) * m / (kSlopeTemperatures - 1);
      node_output(x, {block.data(), d}, gradient.data());
      row(0, j) -= kSlopeWeight / kSlopeTemperatures * gradient[0];
    }
  }
  return row;
}

// Gyro a's weight rows in the joint problem (SurfaceTerm::weight_penalty), P w - t: the ridge its sequential fit
// applied (`summary`: that fit's; the ols fitter's global ridge, t = 0; other fitters' regularisation is not
// carried over, noted) stacked on the rows of the surface's share of M_aa's and b_a's columns (surface_terms.h),
// held at the sequential fit's share with weight kOwnedWeight on a unit-norm residual vector; with
// rbf_diagonal=zero_rate M_aa's column is not among them, and the zero-rate slope row (target 0) is added
// instead (zero_rate_slope_row). The sequential solution meets every row, so the joint cost starts at the
// sequential cost and can only fall.
std::pair<Eigen::MatrixXd, Eigen::VectorXd> joint_weight_rows(const TriadData& d, const Eigen::MatrixX3d& surface_rate, int a, const RbfNetwork& net,
                                                              const TriadBias& bias, int bias_order, const nlohmann::json& summary, const TriadFitOptions& o, std::vector<std::string>& notes) {
  constexpr double kOwnedWeight = 1e3;
  Eigen::MatrixXd x(d.size(), 2);  // the inputs measured_rate, temperature (RbfTerm's), normalised
  Eigen::MatrixXd owned(d.size(), bias_order + 2);  // omega_a | v^0..v^nb
  for (Eigen::Index k = 0; k < d.size(); ++k) {
    const double raw[2] = {surface_rate(k, a), d.temp_c(k, a)};
    double out[2];
    net.normalizer.apply(raw, out);
    x.row(k) << out[0], out[1];
    owned(k, 0) = d.reference(k, a);
    const double v = bias.normalised(d.temp_c(k, a));
    double vp = 1.0;
    for (int p = 0; p <= bias_order; ++p, vp *= v) owned(k, 1 + p) = vp;
  }
  // never turned: M_aa is not in the problem's span; zero_rate: M_aa's split is fixed by the slope row instead
  if (owned.col(0).isZero(0.0) || o.rbf_diagonal == "zero_rate") owned = owned.rightCols(bias_order + 1).eval();
  // The node columns as the joint rows see them: phi_j, or g phi_j for a relative error (rbf_form=scale_factor).
  const bool relative = net.output_factor >= 0;
  const Eigen::MatrixXd h = relative ? Eigen::MatrixXd(surface_rate.col(a).asDiagonal() * net.basis(x)) : net.basis(x);
  const Eigen::MatrixXd constraint = owned_column_rows(h, owned, kOwnedWeight);
  const Eigen::MatrixXd slope = o.rbf_diagonal == "zero_rate" ? zero_rate_slope_row(net, x.col(1).minCoeff(), x.col(1).maxCoeff()) : Eigen::MatrixXd();
  const FitNotes fit = fit_notes_of(summary.value("details", nlohmann::json::object()));
  Eigen::MatrixXd ridge;
  if (relative) {
    // No ridge: the fitter chose its lambda by GCV on r = e / g, whose noise is the output's over |g| (the
    // slowest turns' noise sets it); on the joint rows it has no exact counterpart. Carried over scaled by the
    // mean g^2 of the turns it moved the planted-law test by 2 % (between the training rates 4.44 against
    // 4.53 deg/h, TriadFit.ARelativeRbf...).
  } else if (o.surface_solver == "ols" && fit.ridge_lambda) {
    ridge = ols_ridge_penalty(h, *fit.ridge_lambda);
  } else if (a == 0) {
    notes.push_back(str_cat("joint rbf: the ", o.surface_solver, " fitter's regularisation is not carried into the joint problem"));
  }
  Eigen::MatrixXd rows(ridge.rows() + slope.rows() + constraint.rows(), net.nodes());
  if (ridge.size() > 0) rows.topRows(ridge.rows()) = ridge;
  if (slope.size() > 0) rows.middleRows(ridge.rows(), slope.rows()) = slope;  // target 0
  rows.bottomRows(constraint.rows()) = constraint;
  Eigen::VectorXd target = Eigen::VectorXd::Zero(rows.rows());
  target.tail(constraint.rows()) = constraint * net.weights;
  return {rows, target};
}

// Each gyro's output with its white noise averaged down (surface_input=smoothed): the linear part's prediction
// P from the reference plus the residual g - P averaged over a window of 2 w + 1 samples inside a run, the
// sample itself left out (so its column carries none of the noise its row fits: with it, a rate polynomial's
// near-degenerate powers fitted 1/(2 w + 1) of the noise variance each, and BIC took them) -
// consecutive samples whose reference rates differ by less than kRunStep (a rate-table step, a static hold) and
// share a position_id. Within a run what the residual holds besides noise (the surface, the linear part's
// misfit) moves only with the temperature, slowly: the window is centred (a linear drift kept exactly) but near
// a run's edges, where it keeps its length and slides inside the run (a run shorter than it is averaged whole),
// so every sample's noise is averaged over min(2 w + 1, run length) - 1 samples (a run of one sample keeps its
// recorded output). P follows the Earth rate turning
// through the other axes during a turn, which a mean of the raw outputs would smear.
constexpr double kRunStep = 1e-3;  // rad/s (0.057 deg/s)
bool same_run(const TriadData& d, Eigen::Index a, Eigen::Index b) {
  if (!d.position_id.empty() && d.position_id[static_cast<std::size_t>(a)] != d.position_id[static_cast<std::size_t>(b)]) return false;
  return (d.reference.row(a) - d.reference.row(b)).cwiseAbs().maxCoeff() < kRunStep;
}

Eigen::MatrixX3d smoothed_outputs(const TriadData& d, const TriadModel& linear, int half_width) {
  const Eigen::MatrixX3d p = linear.predict_outputs(d);
  const Eigen::Index n = d.size();
  Eigen::MatrixX3d sum(n + 1, 3);  // prefix sums of the residual g - P
  sum.row(0).setZero();
  for (Eigen::Index k = 0; k < n; ++k) sum.row(k + 1) = sum.row(k) + (d.gyro.row(k) - p.row(k));
  Eigen::MatrixX3d out(n, 3);
  for (Eigen::Index begin = 0; begin < n;) {
    Eigen::Index end = begin + 1;
    while (end < n && same_run(d, end - 1, end)) ++end;
    const Eigen::Index width = std::min<Eigen::Index>(2 * half_width + 1, end - begin);
    for (Eigen::Index k = begin; k < end; ++k) {
      const Eigen::Index first = std::clamp<Eigen::Index>(k - half_width, begin, end - width);
      if (width < 2) {
        out.row(k) = d.gyro.row(k);
        continue;
      }
      const auto own = d.gyro.row(k) - p.row(k);  // left out: the column must not carry the noise its row fits
      out.row(k) = p.row(k) + (sum.row(first + width) - sum.row(first) - own) / static_cast<double>(width - 1);
    }
    begin = end;
  }
  return out;
}

// Each gyro's surface term of the joint problem at the surface rates: classical columns, or the sequential
// network (its constant folded into the bias) with its weight rows; spec.surfaces points at them.
void joint_terms(const TriadData& d, const TriadFitOptions& o, int bias_order, const Eigen::MatrixX3d& surface_rate,
                 const std::array<std::shared_ptr<const CalibrationModel>, 3>& sequential, const nlohmann::json& stages,
                 TriadProblemSpec& spec, std::array<std::unique_ptr<SurfaceTerm>, 3>& terms, std::vector<std::string>& notes) {
  const std::size_t surface_stage0 = stages.size() >= 3 ? stages.size() - 3 : 0;  // rbf: the three surface fits' summaries
  for (int a = 0; a < 3; ++a) {
    const auto ai = static_cast<std::size_t>(a);
    if (o.surfaces == "classical") {
      terms[ai] = classical_term(classical_surface_options(o.surface_options), surface_rate.col(a), d.temp_c.col(a));
    } else {
      RbfNetwork net = dynamic_cast<const RbfNetwork&>(*sequential[ai]);
      // The network's constant into the triad's own column: the bias, or for a relative error the constant scale
      // factor g b_r = b_r (1 + M_aa) omega_a + O(b_r e) - M_aa's.
      if (net.output_factor >= 0) {
        spec.start.misalignment(a, a) += net.bias * (1.0 + spec.start.misalignment(a, a));
      } else {
        spec.start.bias.coefficients[ai](0) += net.bias;
      }
      net.bias = 0.0;
      auto [penalty, target] = joint_weight_rows(d, surface_rate, a, net, spec.start.bias, bias_order, stages[surface_stage0 + ai]["summary"], o, notes);
      terms[ai] = rbf_term(net, std::move(penalty), std::move(target));
    }
    spec.surfaces[ai] = terms[ai].get();
  }
}

TriadModel start_model(const TriadData& d, int bias_order) {
  TriadModel m;
  const double lo = d.temp_c.minCoeff(), hi = d.temp_c.maxCoeff();
  m.bias.reference_c = 0.5 * (lo + hi);
  m.bias.scale_c = std::max(0.5 * (hi - lo), 1.0);
  for (auto& c : m.bias.coefficients) c = Eigen::VectorXd::Zero(bias_order + 1);
  return m;
}

void finish(TriadFit& fit, const Stage& s, const TriadData& d, const TriadRows& rows, const Eigen::MatrixX3d& surface_rate) {
  // Every row carries one sample's noise sigma_s = N / sqrt(dt).
  const double dt = median_sample_interval(d.t_s);
  fit.sample_rate_hz = 1.0 / dt;
  for (std::size_t a = 0; a < 3; ++a) fit.noise_density[a] = fit.uncertainty.noise_radps[a] * std::sqrt(dt);
  for (const auto& name : s.undetermined) fit.notes.push_back(undetermined_note(name));
  fit.angles = analyse_angles(fit.uncertainty.misalignment_known);
  // Residual rms per gyro over the problem's rows, the surfaces at the input they were fitted at: the residuals
  // least squares minimised. Evaluated at the recorded outputs instead, every row's noise e becomes
  // (1 - e_i'(g)) e: a surface's slope of 1e-3 moves rss by 0.2 %, which on 10^5 rows outweighs BIC's penalty
  // for a dozen parameters, and the order BIC chose followed the fitted polynomial's slope, not its fit.
  TriadData at = d;
  at.gyro = surface_rate;
  const Eigen::MatrixX3d left = fit.model.predict_outputs(at) - d.gyro;
  for (int a = 0; a < 3; ++a) {
    double sum = 0.0;
    for (int r = 0; r < rows.rows(); ++r) {
      double row = 0.0;
      for (int e = rows.start[static_cast<std::size_t>(r)]; e < rows.start[static_cast<std::size_t>(r) + 1]; ++e) {
        row += rows.weight[static_cast<std::size_t>(e)] * left(rows.sample[static_cast<std::size_t>(e)], a);
      }
      sum += row * row;
    }
    fit.criterion.rss_radps2[static_cast<std::size_t>(a)] = sum;
    fit.residual_rms_dph[static_cast<std::size_t>(a)] = units::radps_to_dph(std::sqrt(sum / std::max(1, rows.rows())));
  }
  fit.criterion.rows_per_gyro = rows.rows();
  fit.reference = rows.description;
}

// The entries the sequential classical fit's first stage estimated and its second held (M's off-diagonals, G).
int held_estimates(const Stage& first) {
  int n = 0;
  for (const auto& e : first.problem.free_entries()) n += held_in_second_stage(first.problem.entry_name(e.block, e.entry)) ? 1 : 0;
  return n;
}

// A classical surface's coefficients (sf_temperature's index 0 is unused); -1 for another kind.
int classical_coefficients(const std::shared_ptr<const CalibrationModel>& surface) {
  const auto* c = dynamic_cast<const ClassicalModel*>(surface.get());
  if (!c) return -1;
  return static_cast<int>(c->bias.size() + std::max<Eigen::Index>(c->sf_temperature.size() - 1, 0) + c->sf_rate.size() + c->sf_cross.size());
}

// TriadInformationCriterion (triad_fit.h): k from the final stage's free entries plus what earlier stages or the
// surfaces' own fitters estimated; fit.criterion's rows and rss come from finish().
void information_criterion(TriadFit& fit, const Stage& final_stage, const Stage* first_of_triad_scale,
                           const std::array<std::shared_ptr<const CalibrationModel>, 3>& own_surfaces, bool all_rows) {
  TriadInformationCriterion& c = fit.criterion;
  bool counted = all_rows;
  c.parameters = static_cast<int>(final_stage.problem.free_entries().size());
  if (first_of_triad_scale) c.parameters += held_estimates(*first_of_triad_scale);
  for (const auto& s : own_surfaces) {
    if (!s) continue;
    const int n = classical_coefficients(s);
    counted = counted && n >= 0;
    c.parameters += std::max(n, 0);
  }
  const double r = c.rows_per_gyro;
  if (counted && r > 0) {
    double minus_2_ln_l = 0.0;  // up to a constant that depends on R only
    for (double rss : c.rss_radps2) minus_2_ln_l += r * std::log(std::max(rss / r, 1e-300));
    c.minus_2_ln_l = minus_2_ln_l;
    c.bic = minus_2_ln_l + c.parameters * std::log(3.0 * r);
    c.aic = minus_2_ln_l + 2.0 * c.parameters;
  }
  fit.summary.details["information_criterion"] = {
      {"bic", number_or_null(c.bic)},
      {"aic", number_or_null(c.aic)},
      {"rows_per_gyro", c.rows_per_gyro},
      {"parameters", c.parameters},
      {"rss_radps2", c.rss_radps2},
      {"definition", "BIC = sum_i R ln(rss_i / R) + k ln(3 R), AIC = sum_i R ln(rss_i / R) + 2 k: R rows_per_gyro, k parameters, rss_i per gyro in (rad/s)^2 (solvers/triad/triad_fit.h)"}};
}

// What the reference gives the fit: its mode (rate, angle or gravity), the rows against it, and a gravity
// reference's hand turns (their stillness checked into `fit`).
struct ReferenceRows {
  std::string mode;
  TriadRows rows;
  std::vector<GravityTurn> turns;
};

ReferenceRows reference_rows(const TriadData& d, const TriadFitOptions& o, const std::string& reference_metadata, TriadFit& fit) {
  ReferenceRows r;
  r.mode = triad_reference_mode(o, reference_metadata);
  if (r.mode == "gravity") {
    if (o.surfaces != "none" || o.g_sensitivity) fail("triad: reference=gravity estimates M and the biases only (surfaces=none, no g_sensitivity)");
    r.turns = gravity_turns(d);
    fit.hold_stillness = check_hold_stillness(d);
    for (const auto& h : fit.hold_stillness.not_still()) fit.notes.push_back(fit.hold_stillness.describe(h));
  }
  r.rows = r.mode == "angle" ? angle_rows(d) : r.mode == "gravity" ? hold_rows(d) : rate_rows(d);
  if (r.mode == "gravity") {
    r.rows.description = str_cat(r.rows.rows(), " static-hold samples against reference 0 and ", r.turns.size(),
                                 " hand turns known by the gravity directions of the holds around them");
  }
  if (r.mode == "angle" && o.surfaces != "none" && o.estimation == "sequential") {
    fail("triad: with an angle reference only segment integrals are known; sequential surfaces need per-sample reference rates (use estimation=joint or surfaces=none)");
  }
  return r;
}

// The bias polynomial's order: the option's, or a constant where the temperature spans less than 0.5 C.
int bias_order_of(const TriadData& d, const TriadFitOptions& o, TriadFit& fit) {
  if (d.temp_c.maxCoeff() - d.temp_c.minCoeff() >= 0.5 || o.bias_order <= 0) return o.bias_order;
  fit.notes.push_back(str_cat("temperature spans less than 0.5 C: the bias polynomial is reduced to a constant (bias_order 0)"));
  return 0;
}

// The summary's details beside the final stage's: every stage, the estimation and surfaces, a gravity
// reference's hold stillness, and the classical surfaces' orders.
void record_details(TriadFit& fit, const TriadFitOptions& o, const std::string& mode, nlohmann::json stages) {
  fit.summary.details["stages"] = std::move(stages);
  fit.summary.details["estimation"] = o.estimation;
  fit.summary.details["surfaces"] = o.surfaces;
  if (mode == "gravity") fit.summary.details["hold_stillness"] = fit.hold_stillness.json();
  if (o.surfaces == "classical") {
    const ClassicalOptions defaults;
    for (const auto& [key, value] : {std::pair{"sf_rate_order", defaults.sf_rate_order}, std::pair{"sf_cross_order", defaults.sf_cross_order}}) {
      const auto it = o.surface_options.find(key);
      fit.summary.details[str_cat("surface_", key)] = it == o.surface_options.end() ? std::to_string(value) : it->second;
    }
  }
}

TriadFit fit_triad_once(const TriadData& d, const TriadFitOptions& o, const std::string& reference_metadata) {
  if (d.size() < 4) fail("triad: ", d.size(), " samples are too few");
  TriadFit fit;
  fit.options = o;
  auto [mode, rows, turns] = reference_rows(d, o, reference_metadata, fit);
  const int bias_order = bias_order_of(d, o, fit);
  TriadProblemSpec spec;
  spec.bias_order = bias_order;
  spec.g_sensitivity = o.g_sensitivity;
  spec.start = start_model(d, bias_order);
  nlohmann::json stages = nlohmann::json::array();

  // Stage 1 (sequential; the whole fit without surfaces; the start of a joint solve with surfaces): M, b, G.
  const bool smoothed = o.surfaces != "none" && o.surface_input == "smoothed";
  const bool linear_stage = o.surfaces == "none" || o.estimation == "sequential" || o.surfaces == "rbf" || smoothed;
  Stage stage;
  if (mode == "gravity") {  // unweighted first, for the turns' misfit beyond the noise; then whitened (gravity_turns.h)
    const Stage first = run_stage(d, rows, spec, o, &turns, false, false);
    const TriadModel unweighted = triad_model_of(first.problem, first.layout, spec);
    const double misfit = turn_misfit_variance(d, turns, unweighted, bias_order);
    for (auto& t : turns) t.misfit_var = misfit;
    stages.push_back({{"stage", "hand turns, unweighted"}, {"summary", first.summary}, {"turn_misfit_rad", std::sqrt(misfit)}});
    spec.start = unweighted;
  }
  if (linear_stage) {
    stage = run_stage(d, rows, spec, o, mode == "gravity" ? &turns : nullptr);
    stages.push_back({{"stage", "misalignment and bias"}, {"summary", stage.summary}});
    spec.start = triad_model_of(stage.problem, stage.layout, spec);
  }
  const Eigen::MatrixX3d surface_rate = smoothed ? smoothed_outputs(d, spec.start, o.surface_window) : d.gyro;
  spec.surface_rate = &surface_rate;
  // Sequential classical surfaces with sequential_scale=triad, and RBF surfaces with rbf_diagonal=zero_rate or
  // rbf_form=scale_factor: the second stage is the triad problem with M's off-diagonals and G held at the first
  // stage's - M_ii, b and the surfaces in the joint fit's parametrisation. A joint zero_rate fit starts from it.
  const bool classical_scale = o.surfaces == "classical" && o.estimation == "sequential" && o.sequential_scale == "triad";
  const bool rbf_zero_rate = o.surfaces == "rbf" && o.rbf_diagonal == "zero_rate";
  const bool rbf_relative = o.surfaces == "rbf" && o.rbf_form == "scale_factor";
  const bool triad_scale = classical_scale || ((rbf_zero_rate || rbf_relative) && o.estimation == "sequential");
  std::array<std::shared_ptr<const CalibrationModel>, 3> sequential_surfaces;
  if (o.surfaces != "none" && (o.estimation == "sequential" || o.surfaces == "rbf") && !classical_scale) {
    sequential_surfaces = fit_surfaces(d, spec.start, o, bias_order, surface_rate, stages);
  }
  std::array<std::unique_ptr<SurfaceTerm>, 3> terms;
  Stage first;
  std::optional<TriadUncertainty> bias_stage;  // rbf_bias=held: the stage that determined the bias polynomials
  if (o.estimation == "joint" && holds_rbf_bias(o)) {
    TriadModel scratch = spec.start;
    std::vector<std::string> ignored;
    bias_stage = uncertainty_of(stage, o.g_sensitivity, o.max_sigma, scratch, ignored);
  }
  if ((o.estimation == "joint" || triad_scale) && o.surfaces != "none") {
    joint_terms(d, o, bias_order, surface_rate, sequential_surfaces, stages, spec, terms, fit.notes);
    const bool held_stage = triad_scale || rbf_zero_rate;
    if (held_stage) first = std::move(stage);
    TriadFitOptions weights_only = o;  // the held stage moves the nodes' weights only (rbf_joint=nodes: the joint stage the rest)
    weights_only.rbf_joint = "weights";
    stage = run_stage(d, rows, spec, held_stage ? weights_only : o, nullptr, held_stage);
    stages.push_back({{"stage", held_stage ? "surfaces with M_ii and b (off-diagonals and G held)" : "joint"}, {"summary", stage.summary}});
    if (held_stage && !triad_scale) {  // joint RBF, zero_rate: everything free, from the held stage's solution
      const Stage held = std::move(stage);
      stage = run_stage(d, rows, spec, o, nullptr, false, true, &held);
      stages.push_back({{"stage", "joint"}, {"summary", stage.summary}});
    }
  }
  fit.model = triad_model_of(stage.problem, stage.layout, spec);
  if (o.estimation == "sequential" && !triad_scale) fit.model.surfaces = sequential_surfaces;
  if (!stage.covariance.ok) fit.notes.push_back("covariance: " + stage.covariance.message);
  fit.uncertainty = triad_scale ? sequential_uncertainty(first, stage, o.g_sensitivity, o.max_sigma, fit.model, fit.notes)
                                : uncertainty_of(stage, o.g_sensitivity, o.max_sigma, fit.model, fit.notes);
  if (bias_stage) {  // held in the joint solve: their sigmas are the first stage's
    fit.uncertainty.bias_sigma = bias_stage->bias_sigma;
    fit.uncertainty.bias_known = bias_stage->bias_known;
  }
  finish(fit, stage, d, rows, surface_rate);
  fit.summary = stage.summary;
  information_criterion(fit, stage, triad_scale ? &first : nullptr, o.estimation == "sequential" && !triad_scale ? sequential_surfaces : decltype(sequential_surfaces){},
                        mode != "gravity");
  record_details(fit, o, mode, std::move(stages));
  return fit;
}

}  // namespace

namespace {

// One comparison of nested orders (TriadFitOptions::order_criterion): every candidate fit kept by its order,
// every candidate's criterion (or why it was no candidate) recorded by its order, then one chosen.
struct OrderChoice {
  explicit OrderChoice(const TriadFitOptions& o) : options(o) {}
  const TriadFitOptions& options;
  std::map<int, TriadFit> fits;
  nlohmann::json criteria = nlohmann::json::object();  // bic_lr: BIC's
  nlohmann::json tests = nlohmann::json::object();     // bic_lr: each order's test against the top order

  bool aic() const { return options.order_criterion == "aic"; }
  double value(const TriadFit& f) const { return aic() ? f.criterion.aic : f.criterion.bic; }
  void offer(int order, TriadFit f) {
    criteria[std::to_string(order)] = number_or_null(value(f));
    if (std::isfinite(value(f))) fits.emplace(order, std::move(f));
  }
  void fit(int order, const TriadData& d, const TriadFitOptions& o, const std::string& reference_metadata, bool must_fit) {
    try {
      offer(order, fit_triad_once(d, o, reference_metadata));
    } catch (const Error& e) {  // an order the recording cannot determine (the classical fitter's rank check) is no candidate
      if (must_fit) throw;
      criteria[std::to_string(order)] = str_cat("not fitted: ", e.what());
    }
  }
  // The order the criterion chooses; none when no candidate has a finite criterion.
  std::optional<int> choose() {
    if (fits.empty()) return std::nullopt;
    int best = fits.begin()->first;
    for (const auto& [order, f] : fits)
      if (value(f) < value(fits.at(best))) best = order;
    if (options.order_criterion != "bic_lr") return best;
    // Wilks: Lambda_o = (-2 ln L_o) - (-2 ln L_top) ~ chi^2(k_top - k_o) where order o holds the sensor.
    const TriadInformationCriterion& top = fits.rbegin()->second.criterion;
    for (const auto& [order, f] : fits) {
      if (order < best) continue;
      const int dof = top.parameters - f.criterion.parameters;
      if (dof <= 0) return order;  // the top order itself
      const double statistic = f.criterion.minus_2_ln_l - top.minus_2_ln_l;
      const double critical = stats::chi2_quantile(1.0 - options.order_test_level, dof);
      tests[std::to_string(order)] = {{"statistic", statistic}, {"dof", dof}, {"critical", critical}};
      if (statistic <= critical) return order;
    }
    return fits.rbegin()->first;
  }
};

}  // namespace

// surface.sf_rate_order=auto, surface.sf_cross_order=auto (the default for classical triad surfaces,
// effective_surface_options): the orders chosen by order_criterion (triad_fit.h; bic_lr by default) from the
// fits in the mode asked for (joint or sequential, each by its own final problem), so that neither mode is
// handed a family the data reject or denied one they call for. First the rate order 0..kMaxAutoRateOrder in
// the separable form (or at the given cross order), then the cross order 1..kMaxAutoCrossOrder at the chosen
// rate order. The likelihood can judge the rate order because the surfaces' input carries none of the noise
// its rows fit (smoothed_outputs leaves each sample out of its own average); at the recorded outputs the spare
// rate powers fit the noise and any criterion takes them. The criteria (and bic_lr's tests) are kept in the
// summary's details and a note.
TriadFit fit_triad(const TriadData& d, const TriadFitOptions& o, const std::string& reference_metadata) {
  if (auto p = o.validate(); !p.empty()) fail("triad: ", p);
  if (o.estimation == "auto") return fit_triad_auto(d, o, reference_metadata);
  OptionMap surface_options = effective_surface_options(o.surfaces, o.surface_options);
  const bool rate_auto = order_auto(surface_options, "sf_rate_order"), cross_auto = order_auto(surface_options, "sf_cross_order");
  if (!rate_auto && !cross_auto) return fit_triad_once(d, o, reference_metadata);
  TriadFitOptions oc = o;
  std::vector<std::string> notes;
  nlohmann::json details = nlohmann::json::object();
  std::optional<TriadFit> best;
  bool rate_shape = true;  // a rate order 0 has no rate shape for the temperature to move
  // Chooses among `choice`'s candidates for `key`: the chosen fit, its order in the surface options, the note.
  auto conclude = [&](OrderChoice& choice, const char* key) {
    const std::string name = choice.aic() ? "AIC" : "BIC";  // the criterion the candidates were compared by
    const std::optional<int> chosen = choice.choose();
    if (!chosen) fail("triad: surface.", key, "=auto found no order with a finite ", name, " (", choice.criteria.dump(), "); give the order");
    const std::string by = o.order_criterion == "bic_lr" ? str_cat(name, " and a likelihood-ratio test at level ", o.order_test_level) : name;
    notes.push_back(str_cat("surface.", key, "=auto: order ", *chosen, " chosen by ", by, " (", choice.criteria.dump(),
                            choice.tests.empty() ? "" : str_cat("; tests against the top order ", choice.tests.dump()), ")"));
    details[str_cat(key, choice.aic() ? "_aic" : "_bic")] = choice.criteria;
    if (!choice.tests.empty()) details[str_cat(key, "_lr")] = choice.tests;
    surface_options = with_order(surface_options, key, *chosen);
    best = std::move(choice.fits.at(*chosen));
    return *chosen;
  };
  if (rate_auto) {
    OrderChoice rate{o};
    const OptionMap base = cross_auto ? with_order(surface_options, "sf_cross_order", 0) : surface_options;
    for (int order = 0; order <= kMaxAutoRateOrder; ++order) {
      oc.surface_options = with_order(base, "sf_rate_order", order);
      rate.fit(order, d, oc, reference_metadata, order == 0);
    }
    rate_shape = conclude(rate, "sf_rate_order") > 0;
  }
  if (cross_auto && rate_shape) {
    OrderChoice cross{o};
    if (best) cross.offer(0, std::move(*best));  // the separable form at the chosen rate order, fitted above
    for (int order = best ? 1 : 0; order <= kMaxAutoCrossOrder; ++order) {
      oc.surface_options = with_order(surface_options, "sf_cross_order", order);
      cross.fit(order, d, oc, reference_metadata, order == 0);
    }
    conclude(cross, "sf_cross_order");
  }
  best->options = o;
  for (auto& n : notes) best->notes.push_back(std::move(n));
  for (auto& [key, value] : details.items()) best->summary.details[key] = value;
  return *best;
}

std::string triad_reference_mode(const TriadFitOptions& o, const std::string& metadata) {
  if (o.reference != "auto") return o.reference;
  return metadata == "angle" || metadata == "gravity" ? metadata : "rate";
}

}  // namespace gyrosid
