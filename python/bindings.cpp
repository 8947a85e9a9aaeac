// Python bindings of gyrosid (pybind11): numpy arrays in and out, the library's functions called in-process,
// results as the same JSON documents the command writes (parsed into Python dicts). The package is
// python/gyrosid; see python/README.md.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <nlohmann/json.hpp>

#include <fstream>
#include <memory>
#include <sstream>

#include "core/error.h"
#include "core/format.h"
#include "core/recording.h"
#include "core/builtin_configs.h"
#include "core/enum_names.h"
#include "core/units.h"
#include "design/design.h"
#include "explain/explain.h"
#include "model/calibration_model.h"
#include "model/compensate_recording.h"
#include "nav/cof_report.h"
#include "pipeline/calibrate_job.h"
#include "pipeline/design_job.h"
#include "pipeline/lot_jobs.h"
#include "pipeline/main_job.h"
#include "pipeline/session.h"
#include "pipeline/surface_job.h"
#include "report/allan_report.h"
#include "report/cof_json.h"
#include "report/design_report.h"
#include "report/explain_json.h"
#include "report/surface_report.h"
#include "noise/allan.h"
#include "noise/identify.h"
#include "sensor/sensor_config.h"
#include "sim/simulate.h"
#include "solvers/calibrate.h"
#include "solvers/triad/triad_fit.h"
#include "trajectory/programme.h"

namespace py = pybind11;

namespace gyrosid::python {
namespace {

// A JSON document as Python objects (through Python's json module: exact for every number).
py::object to_python(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }
nlohmann::json from_python(const py::object& o) {
  return nlohmann::json::parse(py::module_::import("json").attr("dumps")(o).cast<std::string>());
}

py::array_t<double> to_numpy(const double* data, std::size_t n) { return py::array_t<double>(static_cast<py::ssize_t>(n), data); }
std::vector<double> from_numpy(const py::array_t<double, py::array::c_style | py::array::forcecast>& a) {
  if (a.ndim() != 1) throw Error("expected a one-dimensional array");
  return {a.data(), a.data() + a.size()};
}

// Option values as the command's key=value text (Python True/False as true/false).
OptionMap option_map(const py::dict& options) {
  OptionMap out;
  for (const auto& [k, v] : options) {
    const std::string key = py::str(k);
    out[key] = py::isinstance<py::bool_>(v) ? (v.cast<bool>() ? "true" : "false") : std::string(py::str(v));
  }
  return out;
}

// A model of any kind (model/sensor_model.h: one gyro's calibration model or a triad's) with what its file holds
// beside it (training provenance, solver summary).
struct Model {
  std::shared_ptr<SensorModel> model;
  nlohmann::json extra = nlohmann::json::object();

  // features and predict are a single gyro's.
  const CalibrationModel& gyro() const {
    if (const auto* m = dynamic_cast<const CalibrationModel*>(model.get())) return *m;
    throw Error(str_cat("a ", model->kind(), " model of ", model->gyros(), " gyros has no single-gyro features or predict; compensate a recording with it"));
  }
};

Recording recording_of_columns(const py::dict& columns, const py::dict& metadata, const std::string& source) {
  Recording rec(source);
  for (const auto& [k, v] : metadata) rec.set_meta(py::str(k), py::str(v));
  for (const auto& [k, v] : columns) rec.set_column(py::str(k), from_numpy(v.cast<py::array_t<double, py::array::c_style | py::array::forcecast>>()));
  // The file round trip applies every rule of the format (required columns, increasing t_s, ...).
  return parse_recording(format_recording(rec), source);
}

// `gyrosid calibrate`'s job (pipeline/calibrate_job.h); model "auto": the preset chosen from the recording's
// noise, as the command with no model.
Model calibrate_py(const Recording& rec, const std::string& model, const std::string& solver, const py::dict& options,
                   const std::vector<std::string>& features, const std::string& target, const std::string& normalization, const std::string& prior,
                   const std::string& decimate) {
  CalibrateJobInput in;
  in.decimate = decimate;
  if (model == "auto") {
    if (solver != CalibrationRequest{}.solver || !options.empty() || !features.empty() || target != "error" || normalization != "range" || !prior.empty()) {
      throw Error("model='auto' chooses the preset from the recording's noise: solver, options, features, target, normalization and prior do not apply");
    }
  } else {
    CalibrationRequest r;
    r.model = model, r.solver = solver, r.options = option_map(options), r.features = features;
    r.target = parse_enum<ModelTarget>(target, "target");
    r.normalization = parse_enum<NormalizationKind>(normalization, "normalization");
    if (!prior.empty()) {  // calibrate --prior
      if (model != "greybox") throw Error("prior (a lot file) calibrates the greybox model, not model='" + model + "'");
      if (!r.options.empty()) throw Error("prior fixes the model's structure to the lot's: options do not apply");
      take_lot_prior(r, load_lot(prior));
    }
    in.request = r;
  }
  ModelFit fit = run_calibrate_job(rec, in).fit;
  return {std::shared_ptr<SensorModel>(std::move(fit.model)), std::move(fit.extra)};
}

py::array_t<double> predict_py(const Model& m, const py::array_t<double, py::array::c_style | py::array::forcecast>& x) {
  const CalibrationModel& gyro = m.gyro();
  const auto d = static_cast<py::ssize_t>(gyro.features().size());
  if (x.ndim() != 2 || x.shape(1) != d) throw Error("predict: x must be an N x " + std::to_string(d) + " array (the model's features)");
  py::array_t<double> out(x.shape(0));
  for (py::ssize_t i = 0; i < x.shape(0); ++i) out.mutable_at(i) = gyro.predict(x.data(i, 0));
  return out;
}

py::dict allan_py(const py::array_t<double, py::array::c_style | py::array::forcecast>& rate_dph, double dt_s) {
  const AllanPhase phase(from_numpy(rate_dph), dt_s);
  const std::vector<AllanPoint> curve = overlapping_allan_deviation(phase, AllanOptions{});
  const NoiseIdentification noise = identify_noise(phase);
  const CompositeNoise& fit = noise.model;
  std::vector<double> tau, adev, lo, hi;
  for (const auto& p : curve) tau.push_back(p.tau_s), adev.push_back(p.adev), lo.push_back(p.ci_low), hi.push_back(p.ci_high);
  py::dict out;
  out["tau_s"] = to_numpy(tau.data(), tau.size());
  out["adev_dph"] = to_numpy(adev.data(), adev.size());
  out["ci_low_dph"] = to_numpy(lo.data(), lo.size());
  out["ci_high_dph"] = to_numpy(hi.data(), hi.size());
  out["arw_deg_rt_h"] = fit.white / 60.0;
  out["bias_instability_dph"] = fit.flicker;
  out["rrw_dph_rt_h"] = fit.random_walk * 60.0;
  out["quantization_arcsec"] = fit.quantization;
  out["rate_ramp_dph_per_h"] = fit.ramp * 3600.0;
  py::list markov;
  for (const auto& gm : fit.gauss_markov) {
    py::dict g;
    g["sigma_dph"] = gm.sigma, g["tau_s"] = gm.tau_s;
    markov.append(g);
  }
  out["gauss_markov"] = markov;
  out["model"] = noise.structure.name();
  out["fit_band_s"] = py::make_tuple(noise.fit_tau_low_s, noise.fit_tau_high_s);
  return out;
}

py::object cof_py(const py::object& model, const std::string& trajectory, const std::string& sensor, int monte_carlo,
                  std::uint64_t seed, double start_temp_c) {
  nav::CofRequest r;
  r.trajectory = trajectory, r.sensor = sensor, r.seed = seed, r.options.start_temp_c = start_temp_c;
  r.monte_carlo = monte_carlo != 0;
  r.mc.runs = monte_carlo > 0 ? monte_carlo : 0;  // -1: automatic stop
  const SensorModel* m = nullptr;
  nav::CompensationMode mode = nav::CompensationMode::model;
  if (model.is_none()) {
    r.model = "none", mode = nav::CompensationMode::none;
  } else if (py::isinstance<py::str>(model) && model.cast<std::string>() == "truth") {
    r.model = "truth", mode = nav::CompensationMode::truth;
  } else {
    m = model.cast<const Model&>().model.get();
    r.model = std::string(m->kind());
  }
  const nav::CofReport report = nav::score_flight(nav::load_flight(trajectory, r.rate_hz), as_triad(load_sensor_file(sensor)), m, mode, r);
  return to_python(cof_json(report));
}

py::tuple explain_py(const Recording& rec, const std::string& model_path, const std::string& baseline_path, const std::string& effects) {
  explain::ExplainOptions o;
  o.model_path = model_path, o.baseline_path = baseline_path, o.effects = effects;
  explain::ExplainResult r = explain::explain_recording(rec, o);
  return py::make_tuple(to_python(to_json(r.summary)), Model{std::shared_ptr<CalibrationModel>(std::move(r.model)), nlohmann::json::object()});
}

// calibrate(model="triad") as the model file's JSON (the form this function has always returned).
py::object calibrate_triad_py(const Recording& rec, const py::dict& options) {
  CalibrationRequest r;
  r.model = "triad", r.options = option_map(options);
  const ModelFit fit = fit_model(rec, r);
  return to_python(model_file_json(*fit.model, fit.extra));
}

py::object run_main_job_py(const std::filesystem::path& out, const std::vector<std::string>& flights, bool noisy,
                           const std::string& rbf_config, std::uint64_t seed) {
  MainJobOptions o;
  o.out = out, o.flights = flights, o.noisy = noisy, o.rbf_config = rbf_config, o.seed = seed;
  o.on_step = [](int, int, const std::string&) {};
  run_main_job(o);
  std::ifstream in(out / "summary.json");
  return to_python(nlohmann::json::parse(in));
}

// `gyrosid design` in-process: the command's job (pipeline/design_job.h), so the same inputs give the same
// design: the designed programme as trajectory YAML (what trajectory.yaml holds) and design.json as a dict.
// Options as --set: space.*, model.*, envelope.*, quadrature.*, select.*, prior.* for the design, anything else
// for the solver. cof_minimax compares against `reference` (default: the dual scan); `prior` is a prior over
// sensors (or a lot) in place of `sensor`.
py::tuple design_py(double budget_min, const std::string& model, const std::vector<std::string>& envelope, const std::string& sensor_path,
                    const std::string& solver, const std::string& criterion, std::uint64_t seed, const py::dict& options,
                    const std::string& reference, const std::string& prior) {
  DesignJobInput in;
  in.budget_min = budget_min, in.model = model, in.sensor = sensor_path, in.solver = solver, in.criterion = criterion, in.seed = seed;
  in.reference = reference, in.prior = prior;
  in.envelope.clear();
  for (const auto& name : envelope) in.envelope += (in.envelope.empty() ? "" : ",") + name;
  for (const auto& [key, value] : option_map(options)) in.set.push_back(key + "=" + value);
  in.invocation = "gyrosid.design (Python)";
  std::ostringstream log;  // what the command prints; the provenance in design.json holds the same
  const PreparedDesign prepared = prepare_design(in, log);
  const DesignJobResult r = run_design_job(prepared, in, nullptr);
  return py::make_tuple(programme_yaml(r.result.trajectory), to_python(r.design_file));
}

// `gyrosid session` in-process: the same job (pipeline/session.h), so a session started here can be resumed by
// the command and the other way round. Options as --set: session.* for the session, the rest for the designs.
py::dict session_py(const std::string& prior, const std::filesystem::path& out, const std::string& truth, double budget_min, double pilot_min,
                    const std::vector<double>& updates_at_min, const std::string& model, const std::string& calibration,
                    const std::vector<std::string>& envelope, const std::string& equipment, const py::dict& options, std::uint64_t seed, bool resume) {
  SessionOptions o;
  o.prior = prior, o.out = out, o.truth = truth, o.budget_min = budget_min, o.pilot_min = pilot_min, o.updates_at_min = updates_at_min;
  o.model = model, o.calibration = calibration, o.envelope = join(envelope, ","), o.equipment = equipment, o.seed = seed, o.resume = resume;
  o.set(option_map(options));
  const SessionResult r = run_session(o);
  py::dict d;
  d["segments_done"] = r.segments_done, d["segments"] = r.segments;
  d["waiting_for"] = r.waiting_for ? py::object(py::str(r.waiting_for->string())) : py::none();
  d["model"] = r.model.empty() ? py::none() : py::object(py::str(r.model.string()));
  d["session"] = to_python(r.session);
  return d;
}

// `gyrosid lot learn`'s job (pipeline/lot_jobs.h): writes the lot file `out`; options as --set (lot.* for the
// lot, the rest for the units' grey-box structure). Returns {file (the lot file's JSON), units, modes,
// mode_share, left_out}.
py::dict lot_learn_py(const std::filesystem::path& out, const std::vector<std::string>& recordings, const std::vector<std::string>& models,
                      const std::vector<std::string>& screen_recordings, const py::dict& options, const std::string& name, double package_tau_s,
                      bool resume) {
  LotLearnOptions o;
  o.out = out, o.recordings = recordings, o.models = models, o.screen_recordings = screen_recordings, o.name = name;
  o.members.package_tau_s = package_tau_s, o.resume = resume;
  o.set(option_map(options));
  const LotLearnResult r = run_lot_learn(o);
  py::dict d;
  d["file"] = to_python(r.file);
  d["units"] = r.lot.unit_names.size(), d["modes"] = r.lot.modes.cols(), d["mode_share"] = r.mode_share, d["left_out"] = r.lot.left_out;
  return d;
}

// `gyrosid lot screen`'s job: each recording's screen.json as a dict, in order (written under `out` as the
// command writes them).
py::list lot_screen_py(const std::string& prior, const std::vector<std::string>& recordings, const std::filesystem::path& out, double alpha,
                       bool resume) {
  LotScreenOptions o;
  o.prior = prior, o.recordings = recordings, o.out = out, o.screen.alpha = alpha, o.resume = resume;
  py::list screens;
  for (const ScreenedUnit& u : run_lot_screen(o).units) screens.append(to_python(u.file));
  return screens;
}

// A temps x rates matrix as a 2-D numpy array (a copy, row-major).
py::array_t<double> grid_to_numpy(const Eigen::MatrixXd& m) {
  py::array_t<double> out({static_cast<py::ssize_t>(m.rows()), static_cast<py::ssize_t>(m.cols())});
  auto v = out.mutable_unchecked<2>();
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) v(i, j) = m(i, j);
  return out;
}

// `gyrosid surface`'s job (pipeline/surface_job.h): surface.json as a dict under "summary", and the grid's axes
// and surfaces (deg/h, temperatures x rates) as numpy arrays.
py::dict surface_py(const std::string& model, const std::string& sensor, std::optional<std::array<double, 2>> temp_range_c,
                    std::optional<std::array<double, 2>> rate_range_dps, std::optional<std::array<int, 2>> points) {
  SurfaceJobInput in;
  in.model = model, in.sensor = sensor, in.temp_range_c = temp_range_c, in.rate_range_dps = rate_range_dps, in.points = points;
  const SurfaceJobResult r = run_surface_job(in);
  const SurfaceComparison& c = r.comparison;
  py::dict d;
  d["summary"] = to_python(surface_json(in.model, in.sensor, *r.model, r.grid, c));
  d["temps_c"] = to_numpy(c.temps_c.data(), c.temps_c.size());
  d["rates_dps"] = to_numpy(c.rates_dps.data(), c.rates_dps.size());
  d["true_dph"] = grid_to_numpy(c.true_dph);
  d["estimated_dph"] = grid_to_numpy(c.estimated_dph);
  d["sigma_dph"] = c.sigma_dph.size() > 0 ? py::object(grid_to_numpy(c.sigma_dph)) : py::none();
  return d;
}

void bind_recording(py::module_& m) {
  py::class_<Recording>(m, "Recording", "A recording (docs/recording_format.md): named columns with their unit in the name.")
      .def(py::init(&recording_of_columns), py::arg("columns"), py::arg("metadata") = py::dict(), py::arg("source") = "<python>",
           "From a dict of 1-D arrays; the format's rules are checked (required columns, increasing t_s, ...).")
      .def_static("load", [](const std::filesystem::path& p) { return read_recording(p); }, py::arg("path"),
                  "Read a recording file (the reader of every command).")
      .def("save", [](const Recording& r, const std::filesystem::path& p) { write_recording(r, p); }, py::arg("path"),
           "Write the recording, atomically, with the digits that read back the same doubles.")
      .def_property_readonly("names", &Recording::names, "Column names, in file order.")
      .def_property_readonly("source", &Recording::source, "The file it was read from (or <python>).")
      .def_property_readonly("metadata", [](const Recording& r) {
        py::dict d;
        for (const auto& [k, v] : r.metadata()) d[py::str(k)] = v;
        return d;
      }, "The `# key: value` metadata.")
      .def("__len__", &Recording::rows)
      .def("__getitem__", [](const Recording& r, const std::string& name) {
        const auto& c = r.column(name);
        return to_numpy(c.data(), c.size());
      }, py::arg("name"), "A column as a numpy array (a copy), by name.")
      .def("columns", [](const Recording& r) {
        py::dict d;
        for (const auto& n : r.names()) d[py::str(n)] = to_numpy(r.column(n).data(), r.rows());
        return d;
      }, "Every column as {name: numpy array}.");
}

void bind_model(py::module_& m) {
  py::class_<Model>(m, "Model", "A calibration model of one gyro or of a triad; saves to and loads from the same JSON as `gyrosid calibrate`.")
      .def_property_readonly("kind", [](const Model& x) { return std::string(x.model->kind()); }, "The model kind (classical, rbf, ..., triad).")
      .def_property_readonly("gyros", [](const Model& x) { return x.model->gyros(); }, "How many gyros it calibrates: 1, or 3 for a triad.")
      .def_property_readonly("features", [](const Model& x) { return x.gyro().features(); }, "Its inputs, in the order predict() takes them (one gyro's model).")
      .def_property_readonly("summary", [](const Model& x) { return to_python(x.extra.value("summary", nlohmann::json::object())); },
                             "The solve summary (solver, termination, iterations, time_s, details).")
      .def_property_readonly("training", [](const Model& x) { return to_python(x.extra.value("training", nlohmann::json::object())); },
                             "Where it was trained: recording, options, samples.")
      .def("predict", &predict_py, py::arg("x"), "Model output (rate error, rad/s) for N x d inputs in SI units, the order of features.")
      .def("to_json", [](const Model& x) { return model_file_json(*x.model, x.extra).dump(1); }, "The model file's JSON text.")
      .def("save", [](const Model& x, const std::filesystem::path& p) { save_model(p, *x.model, x.extra); }, py::arg("path"),
           "Write the model file `gyrosid` reads (compensate, cof, export).")
      .def("export_c", [](const Model& x, const std::filesystem::path& dir, const std::string& prefix) { x.model->export_c(dir, prefix); },
           py::arg("dir"), py::arg("prefix") = "gyro", "Write <prefix>.h and <prefix>.c, dependency-free C99, into dir.");
  m.def("load_model", [](const std::filesystem::path& p) {
    const nlohmann::json j = load_model_json(p);
    std::shared_ptr<SensorModel> model = sensor_model_from_json(j, p.string());
    nlohmann::json extra = fields_beside(j, *model);  // saved again, the same file
    return Model{std::move(model), std::move(extra)};
  }, py::arg("path"), "Read a model file of any kind written by `gyrosid calibrate` or Model.save.");
}

}  // namespace
}  // namespace gyrosid::python

PYBIND11_MODULE(_gyrosid, m) {
  using namespace gyrosid;
  using namespace gyrosid::python;
  m.doc() = "gyrosid: gyroscope calibration as system identification (in-process bindings)";
  py::register_exception<Error>(m, "Error", PyExc_ValueError).attr("__doc__") =
      "A bad input, named by file, line, column, key or option (the command's errors).";
  bind_recording(m);
  bind_model(m);
  m.def("simulate", [](const std::string& sensor, const std::string& trajectory, std::uint64_t seed, bool noise_free, std::optional<std::size_t> samples) {
    return simulate_files(sensor, trajectory, seed, samples, noise_free).recording;
  }, py::arg("sensor") = kDefaultSensor, py::arg("trajectory") = kDefaultTrajectory,
        py::arg("seed") = 1, py::arg("noise_free") = false, py::arg("samples") = std::nullopt,
        "A sensor along a calibration trajectory, as `gyrosid simulate` (same seed, same numbers).");
  m.def("calibrate", &calibrate_py, py::arg("recording"), py::arg("model") = "rbf", py::arg("solver") = "ols",
        py::arg("options") = py::dict(), py::arg("features") = std::vector<std::string>{}, py::arg("target") = "error",
        py::arg("normalization") = "range", py::arg("prior") = "", py::arg("decimate") = "",
        "Fit a model kind (rbf with a named solver, classical, greybox, hybrid, triad, ...) to a recording, `gyrosid calibrate`'s job; model 'auto': the "
        "preset chosen from the recording's noise (the command without --model); prior: a lot file (greybox only), the unit fitted under the "
        "lot's population as `calibrate --prior`; decimate: none, auto or N samples per block (default: auto for 'auto', else none).");
  m.def("calibrate_triad", &calibrate_triad_py, py::arg("recording"), py::arg("options") = py::dict(),
        "calibrate(recording, model='triad', options=...) as the model file's JSON, a dict: a triad's misalignment, biases and surfaces.");
  m.def("compensate", [](const Model& model, const Recording& rec) { return model.model->compensate_recording(rec).recording; },
        py::arg("model"), py::arg("recording"), "The recording with compensated_dps added (a triad model: compensated_{x,y,z}_dps).");
  m.def("allan", &allan_py, py::arg("rate_dph"), py::arg("dt_s"), "Overlapping Allan deviation and the IEEE Std 952 noise fit.");
  m.def("cof", &cof_py, py::arg("model"), py::arg("trajectory") = "short", py::arg("sensor") = kDefaultSensor,
        py::arg("monte_carlo") = 0, py::arg("seed") = 1, py::arg("start_temp_c") = 10.0,
        "Criterion of fit (cof.json as a dict); model None (raw gyros), 'truth' or a Model; monte_carlo runs (-1: until normal).");
  m.def("explain", &explain_py, py::arg("recording"), py::arg("model_path") = "", py::arg("baseline_path") = "", py::arg("effects") = "",
        "Missing-physics finder: (explain.json as a dict, the explained Model).");
  m.def("run_main_job", &run_main_job_py, py::arg("out"), py::arg("flights") = std::vector<std::string>{"short", "medium", "long"},
        py::arg("noisy") = false, py::arg("rbf_config") = "", py::arg("seed") = 1, "The main job in-process; returns summary.json.");
  m.def("design", &design_py, py::arg("budget_min"), py::arg("model") = "auto", py::arg("envelope") = std::vector<std::string>{"short", "medium", "long"},
        py::arg("sensor") = kDefaultSensor, py::arg("solver") = "nlopt", py::arg("criterion") = "cof", py::arg("seed") = 1,
        py::arg("options") = py::dict(), py::arg("reference") = "", py::arg("prior") = "",
        "A calibration trajectory designed for a time budget by `gyrosid design`'s job: (trajectory YAML text, design.json as a dict).");
  m.def("surface", &surface_py, py::arg("model"), py::arg("sensor") = kDefaultSensor, py::arg("temp_range_c") = std::nullopt,
        py::arg("rate_range_dps") = std::nullopt, py::arg("points") = std::nullopt,
        "A model's estimated error surface against the sensor's true one, `gyrosid surface`'s job: {summary (surface.json), temps_c, "
        "rates_dps, true_dph, estimated_dph, sigma_dph (None without a posterior)}; the grid defaults to the model's training temperatures.");
  const SessionOptions session_defaults;
  m.def("session", &session_py, py::arg("prior"), py::arg("out"), py::arg("truth") = "", py::arg("budget_min") = session_defaults.budget_min,
        py::arg("pilot_min") = session_defaults.pilot_min, py::arg("updates_at_min") = std::vector<double>{}, py::arg("model") = session_defaults.model,
        py::arg("calibration") = "", py::arg("envelope") = std::vector<std::string>{"short", "medium", "long"},
        py::arg("equipment") = session_defaults.equipment, py::arg("options") = py::dict(), py::arg("seed") = session_defaults.seed,
        py::arg("resume") = false,
        "An adaptive calibration session, `gyrosid session`'s job: a pilot, the prior over sensors updated by the recording, a redesign of "
        "the rest. Without truth it stops after each designed segment for the lab's recording (waiting_for); call again with resume=True. "
        "Returns {segments_done, segments, waiting_for, model, session (session.json)}.");
  const LotLearnOptions lot_defaults;
  m.def("lot_learn", &lot_learn_py, py::arg("out"), py::arg("recordings") = std::vector<std::string>{}, py::arg("models") = std::vector<std::string>{},
        py::arg("screen_recordings") = std::vector<std::string>{}, py::arg("options") = py::dict(), py::arg("name") = "",
        py::arg("package_tau_s") = lot_defaults.members.package_tau_s, py::arg("resume") = false,
        "Learn a production lot's population from its units' recordings (or grey-box model files), `gyrosid lot learn`'s job; writes the lot "
        "file `out`. options: lot.* (variance_kept, max_modes, trim_alpha, max_loo_units) and the units' grey-box structure. Returns {file, "
        "units, modes, mode_share, left_out}.");
  m.def("lot_screen", &lot_screen_py, py::arg("prior"), py::arg("recordings"), py::arg("out"), py::arg("alpha") = ScreenOptions{}.alpha,
        py::arg("resume") = false,
        "Screen units against a lot, `gyrosid lot screen`'s job: each recording's screen.json as a dict (out_of_family, p_value, "
        "reasons, ...), written under `out` as the command writes them.");
}
