// The gyrosid command end to end: run the executable, read what it wrote, check its errors.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <thread>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/random.h"
#include "core/recording.h"
#include "core/units.h"
#include "sensor/sensor_prior.h"
#include "trajectory/trajectory_config.h"
#include "solvers/hand_turn_session.h"
#include "read_file.h"

namespace gyrosid {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;
namespace fs = std::filesystem;

struct Result {
  int status;
  std::string output;  // stdout and stderr
};

Result run(const std::string& args) {
  const std::string command = std::string(GYROSID_EXE) + " " + args + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  std::string out;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) out += buffer;
  const int status = pclose(pipe);
  return {WEXITSTATUS(status), out};
}

using testing_support::read_json;
using testing_support::read_text;

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    // The process id in the name: two suites (say the Release and the sanitizer build) may run side by side.
    dir_ = fs::temp_directory_path() / ("gyrosid_cli_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  // Units 1..count of a lot: the reference sensor on the dual scan, `samples` samples, seed u, as unit<u>.csv;
  // their paths appended to `recordings`, each after a space.
  void simulate_units(int count, int samples, std::string& recordings) const {
    for (int u = 1; u <= count; ++u) {
      const std::string rec = path("unit" + std::to_string(u) + ".csv");
      ASSERT_EQ(run("simulate --samples " + std::to_string(samples) + " --seed " + std::to_string(u) + " --out " + rec).status, 0);
      recordings += " " + rec;
    }
  }
  fs::path dir_;
};

TEST_F(Cli, SimulateWritesTheDefaultRecordingDeterministically) {
  const std::string src = GYROSID_SOURCE_DIR;
  const Result r = run("simulate --sensor " + src + "/configs/sensors/open_loop_fog.yaml --trajectory " + src +
                       "/configs/trajectories/dual_scan.yaml --seed 1 --out " + path("a.csv"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("11110 samples over 62 min"));
  const Recording rec = read_recording(path("a.csv"));
  EXPECT_EQ(rec.rows(), 11110u);
  EXPECT_EQ(rec.kind(), RecordingKind::single);
  EXPECT_EQ(rec.meta("seed").value(), "1");
  for (const char* c : {"t_s", "ref_rate_dps", "temp_c", "gyro_dps", "chamber_temp_c", "accel_z_mps2"}) EXPECT_TRUE(rec.has(c)) << c;
  ASSERT_EQ(run("simulate --seed 1 --out " + path("b.csv")).status, 0);  // built-in defaults, same configs
  EXPECT_EQ(read_text(path("a.csv")), read_text(path("b.csv")));
  ASSERT_EQ(run("simulate --seed 2 --out " + path("c.csv")).status, 0);
  EXPECT_NE(read_text(path("a.csv")), read_text(path("c.csv")));
}

TEST_F(Cli, SamplesOverrideAndTriadColumns) {
  ASSERT_EQ(run("simulate --samples 1111 --out " + path("s.csv")).status, 0);
  EXPECT_EQ(read_recording(path("s.csv")).rows(), 1111u);
  const Result r = run("simulate --sensor builtin:sensors/fog_triad.yaml --trajectory builtin:trajectories/classical_soak.yaml --samples 5000 --out " + path("t.csv"));
  ASSERT_EQ(r.status, 0) << r.output;
  const Recording t = read_recording(path("t.csv"));
  EXPECT_EQ(t.kind(), RecordingKind::triad);
  EXPECT_TRUE(t.has("position_id"));
  EXPECT_TRUE(t.has("gyro_y_dps"));
}

TEST_F(Cli, AllanRecoversTheReferenceSensorsWhiteNoise) {
  ASSERT_EQ(run("simulate --trajectory builtin:trajectories/static_2h.yaml --seed 3 --out " + path("static.csv")).status, 0);
  const Result r = run("allan --recording " + path("static.csv") + " --column gyro_dps --subtract ref_rate_dps --out " + path("allan"));
  ASSERT_EQ(r.status, 0) << r.output;
  const auto j = nlohmann::json::parse(read_text(dir_ / "allan" / "allan.json"));
  // Reference sensor: white noise sigma 10 deg/h at 1 Hz, i.e. N = 10/60 deg/sqrt(h).
  EXPECT_NEAR(j["coefficients"]["arw_deg_rt_h"].get<double>(), 10.0 / 60.0, 0.1 * 10.0 / 60.0);
  EXPECT_TRUE(fs::exists(dir_ / "allan" / "allan.png"));
  EXPECT_THAT(read_text(dir_ / "allan" / "allan.csv"), HasSubstr("tau_s,adev_dph,ci_low_dph,ci_high_dph"));
  EXPECT_THAT(r.output, Not(HasSubstr("warning")));
  // Without --subtract on a rate-table recording the curve is the table's motion: the command says so.
  ASSERT_EQ(run("simulate --trajectory builtin:trajectories/dual_scan.yaml --samples 1111 --out " + path("scan.csv")).status, 0);
  const Result w = run("allan --recording " + path("scan.csv") + " --out " + path("allan_scan"));
  EXPECT_EQ(w.status, 0);
  EXPECT_THAT(w.output, HasSubstr("pass --subtract ref_rate_dps"));
}

// design --noise: the noise a recording showed replaces the sensor config's. The reference sensor's own static
// run identifies its 10 deg/h white noise, and the design predicts the same surface noise as from the config;
// a gyro three times noisier (30 deg/h) predicts three times the noise part of the surface error.
TEST_F(Cli, DesignTakesTheNoiseARecordingShowed) {
  const std::string src = GYROSID_SOURCE_DIR;
  std::string sensor = read_text(src + "/configs/sensors/open_loop_fog.yaml");
  sensor.replace(sensor.find("white_dph_at_1hz: 10"), 20, "white_dph_at_1hz: 30");
  std::ofstream(path("noisy.yaml")) << sensor;
  for (const std::string name : {"ref", "noisy"}) {
    const std::string sensor_arg = name == "ref" ? "" : " --sensor " + path("noisy.yaml");
    ASSERT_EQ(run("simulate --trajectory builtin:trajectories/static_2h.yaml --seed 5" + sensor_arg + " --out " + path(name + ".csv")).status, 0);
    const Result a = run("allan --recording " + path(name + ".csv") + " --subtract ref_rate_dps --out " + path(name + "_allan"));
    ASSERT_EQ(a.status, 0) << a.output;
  }
  const std::string evaluate = "design --evaluate builtin:trajectories/dual_scan.yaml --model classical --envelope short --out ";
  auto surface_noise = [&](const std::string& out) {
    const auto j = nlohmann::json::parse(read_text(dir_ / out / "evaluation.json"));
    return j["trajectories"]["builtin:trajectories/dual_scan.yaml"]["flights"]["short"]["surface_noise_dph"].get<double>();
  };
  ASSERT_EQ(run(evaluate + path("config")).status, 0);
  const Result r = run(evaluate + path("measured") + " --noise " + path("ref_allan/allan.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("in place of"));
  ASSERT_EQ(run(evaluate + path("noisy") + " --noise " + path("noisy_allan/allan.json")).status, 0);
  EXPECT_NEAR(surface_noise("measured") / surface_noise("config"), 1.0, 0.1);
  EXPECT_NEAR(surface_noise("noisy") / surface_noise("config"), 3.0, 0.3);
  // Not an allan.json: an error naming the file and what is missing.
  std::ofstream(path("other.json")) << "{\"noise\": {}}";
  const Result bad = run(evaluate + path("bad") + " --noise " + path("other.json"));
  EXPECT_EQ(bad.status, 2);
  EXPECT_THAT(bad.output, HasSubstr("other.json: no noise.composite"));
}

TEST_F(Cli, BadInputsAreClearErrorsAndLeaveNothingBehind) {
  std::ofstream(path("bad.csv")) << "t_s,ref_rate_dps,temp_c,gyro_dps\n0,1,25,1\n1,x,25,1\n";
  Result r = run("allan --recording " + path("bad.csv") + " --out " + path("o"));
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("bad.csv:3: column 'ref_rate_dps'"));
  EXPECT_FALSE(fs::exists(path("o")));

  std::ofstream(path("gappy.csv")) << "t_s,ref_rate_dps,temp_c,gyro_dps\n0,1,25,1\n1,1,25,1\n2,1,25,1\n4,1,25,1\n5,1,25,1\n";
  r = run("allan --recording " + path("gappy.csv") + " --out " + path("o"));
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("gappy.csv:5: the Allan deviation needs uniform sampling"));

  std::ofstream(path("sensor.yaml")) << "kind: gyro\nbias:\n  constnt_dph: 3\n";
  r = run("simulate --sensor " + path("sensor.yaml") + " --out " + path("x.csv"));
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("sensor.yaml:3"));
  EXPECT_THAT(r.output, HasSubstr("unknown key 'constnt_dph'"));
  EXPECT_FALSE(fs::exists(path("x.csv")));

  r = run("simulate --trajectory " + path("missing.yaml") + " --out " + path("x.csv"));
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("missing.yaml: cannot open config file"));

  r = run("allan --recording " + path("bad.csv") + " --column temp_c --out " + path("o"));
  EXPECT_EQ(r.status, 2);

  // A solver, a target and a normalization are the RBF network's; named for another model kind they are refused,
  // not dropped (a classical fit with --target corrected_rate modelled the error, and its file said corrected_rate).
  std::ofstream(path("ok.csv")) << "t_s,ref_rate_dps,temp_c,gyro_dps\n0,1,25,1\n1,2,26,2\n2,3,27,3\n";
  r = run("calibrate --recording " + path("ok.csv") + " --model hybrid --solver bayes --out " + path("m.json"));
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("solver 'bayes' applies to --model rbf and triad; --model hybrid has its own fit"));
  EXPECT_FALSE(fs::exists(path("m.json")));
  r = run("calibrate --recording " + path("ok.csv") + " --model classical --target corrected_rate --out " + path("m.json"));
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("--target corrected_rate applies to --model rbf; --model classical models the rate error"));
  r = run("calibrate --recording " + path("ok.csv") + " --model greybox --normalization units --out " + path("m.json"));
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("--normalization units applies to --model rbf; --model greybox scales its own inputs"));
  EXPECT_FALSE(fs::exists(path("m.json")));

  r = run("simulate");
  EXPECT_NE(r.status, 0);
  EXPECT_THAT(r.output, HasSubstr("--out is required"));
}

// simulate -> calibrate -> compensate -> surface -> export: each step reads what the previous one wrote.
TEST_F(Cli, CalibrationChainOnNoiseFreeDataBeatsTheRawGyroByOrdersOfMagnitude) {
  ASSERT_EQ(run("simulate --noise-free --samples 1111 --out " + path("dual.csv")).status, 0);
  Result r = run("calibrate --recording " + path("dual.csv") + " --config builtin:calibration/rbf_noisy.yaml --out " + path("rbf.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("hybrid model"));
  r = run("compensate --model " + path("rbf.json") + " --recording " + path("dual.csv") + " --out " + path("comp.csv"));
  ASSERT_EQ(r.status, 0) << r.output;
  const Recording c = read_recording(path("comp.csv"));
  double raw = 0.0, left = 0.0;
  for (std::size_t i = 0; i < c.rows(); ++i) {
    raw += std::pow(c.column("gyro_dps")[i] - c.column("ref_rate_dps")[i], 2);
    left += std::pow(c.column("compensated_dps")[i] - c.column("ref_rate_dps")[i], 2);
  }
  EXPECT_LT(std::sqrt(left / raw), 1e-3);  // the raw error is ~100 deg/h at the rate extremes
  r = run("surface --model " + path("rbf.json") + " --out " + path("surface"));
  ASSERT_EQ(r.status, 0) << r.output;
  const auto s = read_json(dir_ / "surface" / "surface.json");
  EXPECT_LT(s["difference"]["rms_dph"].get<double>(), 1.0);  // against the sensor's true surface
  EXPECT_TRUE(fs::exists(dir_ / "surface" / "difference.png"));
  r = run("calibrate --recording " + path("dual.csv") + " --config builtin:calibration/rbf_noisy.yaml --set width=-1 --out " + path("x.json"));
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("width"));
  EXPECT_FALSE(fs::exists(path("x.json")));
  std::ofstream(path("cal.yaml")) << "model: rbf\nsolver: ols\noptoins:\n  width: 0.2\n";
  r = run("calibrate --recording " + path("dual.csv") + " --config " + path("cal.yaml") + " --out " + path("x.json"));
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("cal.yaml:3"));
  EXPECT_THAT(r.output, HasSubstr("unknown key 'optoins'"));
}

// gyrosid cof's contract: the keys outside tools read, a perfect compensation scoring zero, the raw gyro
// scoring its uncompensated error, and the error components adding up to the end error.
TEST_F(Cli, CofContractTruthNoneAndMonteCarlo) {
  Result r = run("cof --model truth --trajectory short --out " + path("truth"));
  ASSERT_EQ(r.status, 0) << r.output;
  const auto t = read_json(dir_ / "truth" / "cof.json");
  EXPECT_EQ(t["trajectory"], "short");
  EXPECT_NEAR(t["duration_s"].get<double>(), 10.0, 1e-9);
  EXPECT_LT(t["end_error_m"].get<double>(), 1e-9);
  EXPECT_GT(t["uncompensated_end_error_m"].get<double>(), 0.1);
  for (const char* key : {"along_track_m", "drift_m_per_h"}) EXPECT_TRUE(t.contains(key)) << key;
  ASSERT_EQ(t["cross_track_m"].size(), 2u);

  r = run("cof --model none --trajectory short --monte-carlo 30 --seed 4 --out " + path("none"));
  ASSERT_EQ(r.status, 0) << r.output;
  const auto n = read_json(dir_ / "none" / "cof.json");
  EXPECT_DOUBLE_EQ(n["end_error_m"].get<double>(), t["uncompensated_end_error_m"].get<double>());
  const double along = n["along_track_m"], c0 = n["cross_track_m"][0], c1 = n["cross_track_m"][1];
  EXPECT_NEAR(std::sqrt(along * along + c0 * c0 + c1 * c1), n["end_error_m"].get<double>(), 1e-9 * n["end_error_m"].get<double>());
  EXPECT_EQ(n["monte_carlo"]["runs"], 30);
  EXPECT_GT(n["monte_carlo"]["sigma_m"].get<double>(), 0.0);
  EXPECT_TRUE(n["monte_carlo"]["anderson_darling_accepted"].is_boolean());
  for (const char* png : {"ground_track.png", "error_growth.png", "monte_carlo.png"}) EXPECT_TRUE(fs::exists(dir_ / "none" / png)) << png;

  r = run("cof --model none --trajectory medum --out " + path("bad"));
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("medum"));
  EXPECT_FALSE(fs::exists(path("bad")));
}

// The main job on a reduced set-up (one flight, the fast RBF preset): it writes its report, and the RBF
// compensation beats the classical one by the criterion of fit on the short flight.
TEST_F(Cli, MainJobWritesItsReport) {
  const Result r = run("run --flights short --rbf-config builtin:calibration/rbf_noisy.yaml --out " + path("report"));
  ASSERT_EQ(r.status, 0) << r.output;
  const auto s = read_json(dir_ / "report" / "summary.json");
  EXPECT_GT(s["criterion_of_fit"]["short"]["ratio"].get<double>(), 30.0);
  EXPECT_LT(s["models"]["rbf"]["surface"]["rms_dph"].get<double>(), s["models"]["classical"]["surface"]["rms_dph"].get<double>());
  const std::string md = read_text(dir_ / "report" / "report.md");
  EXPECT_THAT(md, HasSubstr("Criterion of fit"));
  for (const char* f : {"models/rbf.json", "models/classical.json", "data/dual_scan.csv", "cof/short_error_growth.png", "allan/allan.png"})
    EXPECT_TRUE(fs::exists(dir_ / "report" / f)) << f;
}

// gyrosid explain's contract: explain.json keys, residuals.csv columns, a model.json every command loads.
TEST_F(Cli, ExplainWritesItsContract) {
  std::ofstream(path("shupe.yaml")) << read_text(fs::path(GYROSID_SOURCE_DIR) / "configs/sensors/open_loop_fog.yaml")
                                    << "\nshupe_dph_per_c_per_min: 4\n";
  ASSERT_EQ(run("simulate --sensor " + path("shupe.yaml") + " --trajectory builtin:trajectories/test_4x16.yaml --seed 2 --out " + path("rec.csv")).status, 0);
  Result r = run("explain --recording " + path("rec.csv") + " --baseline-form polynomial --bootstrap 199 --out " + path("why"));
  ASSERT_EQ(r.status, 0) << r.output;
  const auto j = read_json(dir_ / "why" / "explain.json");
  EXPECT_EQ(j["verdict"], "missing_physics");
  ASSERT_FALSE(j["effects"].empty());
  EXPECT_EQ(j["effects"][0]["id"], "shupe");
  for (const char* key : {"id", "description", "parameters", "confidence", "delta_bic", "p_value", "alternatives"}) {
    EXPECT_TRUE(j["effects"][0].contains(key)) << key;
  }
  EXPECT_NEAR(j["effects"][0]["parameters"]["k_dph_per_cpm"].get<double>(), 4.0, 0.4);
  EXPECT_TRUE(j["noise"]["terms"].is_array());
  EXPECT_TRUE(j["unexplained"].is_array());
  for (const char* key : {"rms_before_dph", "rms_after_dph", "heldout_rms_before_dph", "heldout_rms_after_dph"}) EXPECT_TRUE(j["fit"].contains(key)) << key;
  EXPECT_LT(j["fit"]["heldout_rms_after_dph"].get<double>(), j["fit"]["heldout_rms_before_dph"].get<double>());
  const std::string residuals = read_text(dir_ / "why" / "residuals.csv");
  EXPECT_EQ(residuals.substr(0, residuals.find('\n')), "t_s,residual_before_dph,residual_after_dph,heldout,heldout_scored");
  EXPECT_EQ(static_cast<std::size_t>(std::count(residuals.begin(), residuals.end(), '\n')), read_recording(path("rec.csv")).rows() + 1);
  // heldout_scored marks the rows the held-out proof scores: their rms is explain.json's held-out rms, and
  // every one of them is held out.
  std::istringstream rows(residuals.substr(residuals.find('\n') + 1));
  double ss = 0.0, t = 0.0, before = 0.0, after = 0.0;
  int n = 0, held = 0, scored = 0;
  char comma = 0;
  while (rows >> t >> comma >> before >> comma >> after >> comma >> held >> comma >> scored) {
    ASSERT_TRUE(scored == 0 || (scored == 1 && held > 0)) << "t_s " << t;
    if (scored == 1) ss += after * after, ++n;
  }
  EXPECT_TRUE(rows.eof());
  ASSERT_GT(n, 0);
  EXPECT_NEAR(std::sqrt(ss / n), j["fit"]["heldout_rms_after_dph"].get<double>(), 1e-6 * j["fit"]["heldout_rms_after_dph"].get<double>());
  for (const char* png : {"residual_time.png", "residual_grid.png", "correlations.png", "allan.png", "report.md"}) {
    EXPECT_TRUE(fs::exists(dir_ / "why" / png)) << png;
  }
  // The refitted model compensates the recording: the error left is the noise.
  r = run("compensate --model " + path("why/model.json") + " --recording " + path("rec.csv") + " --out " + path("comp.csv"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("rms error against ref_rate_dps"));

  r = run("explain --recording " + path("rec.csv") + " --model m.json --baseline b.csv --out " + path("x"));
  EXPECT_NE(r.status, 0);
  r = run("explain --recording " + path("rec.csv") + " --effects shupe,warp_drive --out " + path("x"));
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("warp_drive"));
  EXPECT_FALSE(fs::exists(path("x")));
}

// Starts `gyrosid args` and kills it with SIGKILL after `seconds` (if it is still running). True if killed.
bool run_and_kill(const std::string& args, double seconds) {
  const pid_t pid = fork();
  if (pid == 0) {
    const std::string command = std::string(GYROSID_EXE) + " " + args + " > /dev/null 2>&1";
    execl("/bin/sh", "sh", "-c", ("exec " + command).c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  int status = 0;
  while (std::chrono::steady_clock::now() < deadline) {
    if (waitpid(pid, &status, WNOHANG) == pid) return false;  // finished first
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  return true;
}

// Runs `args --out whole` uninterrupted, then the same command into `killed`, killed with SIGKILL at random
// points (resuming from the second attempt on) and finished with --resume. After every kill no JSON result is
// half-written; at the end no checkpoint or temporary is left. Returns how many runs were actually killed.
// `out_file` (optional): the command writes that file in the directories rather than the directories themselves.
int kill_and_resume(const std::string& args, const fs::path& whole, const fs::path& killed, const std::string& checkpoint,
                    std::uint64_t seed, const std::string& out_file = "") {
  const auto start = std::chrono::steady_clock::now();
  const std::string out_whole = (out_file.empty() ? whole : whole / out_file).string(), out = (out_file.empty() ? killed : killed / out_file).string();
  const Result first = run(args + " --out " + out_whole);
  EXPECT_EQ(first.status, 0) << first.output;
  const double duration = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  RandomStream random(seed, "kill-points");
  int kills = 0;
  for (int attempt = 0; attempt < 2; ++attempt) {
    const double at = (0.15 + 0.6 * random.uniform()) * duration;
    kills += run_and_kill(args + " --out " + out + (attempt > 0 ? " --resume" : ""), at) ? 1 : 0;
    if (!fs::exists(killed)) continue;
    for (const auto& entry : fs::directory_iterator(killed)) {
      const std::string name = entry.path().filename().string();
      if (name.find(".tmp.") != std::string::npos) continue;  // a temporary of the killed write, never a result
      if (entry.path().extension() == ".json") {
        EXPECT_NO_THROW(read_json(entry.path())) << name << " is half-written after a kill at " << at << " s";
      }
    }
  }
  const Result resumed = run(args + " --out " + out + " --resume");
  EXPECT_EQ(resumed.status, 0) << resumed.output;
  EXPECT_FALSE(fs::exists(killed / checkpoint));
  for (const auto& entry : fs::directory_iterator(killed)) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp."), std::string::npos) << "stale temporary " << entry.path();
    EXPECT_NE(entry.path().extension(), ".rows") << "a checkpoint's spool left behind: " << entry.path();
  }
  return kills;
}

// A Monte Carlo killed (SIGKILL) at random points and resumed ends with the same cof.json, byte for byte, as an
// uninterrupted run; a kill never leaves a half-written result or checkpoint.
TEST_F(Cli, KilledMonteCarloResumesToTheSameResult) {
  const std::string args = "--quiet cof --model none --trajectory medium --monte-carlo 800 --seed 9";
  const int kills = kill_and_resume(args, dir_ / "whole", dir_ / "killed", ".cof_checkpoint.json", 2026);
  EXPECT_GE(kills, 1) << "the run finished before every kill point; the test did not test resumption";
  EXPECT_EQ(read_text(dir_ / "killed" / "cof.json"), read_text(dir_ / "whole" / "cof.json"));
  // A resume with another seed is refused, naming the checkpoint (when the kill left one behind).
  run_and_kill(args + " --out " + path("other"), 2.0);
  if (fs::exists(dir_ / "other" / ".cof_checkpoint.json")) {
    const Result other = run("--quiet cof --model none --trajectory medium --monte-carlo 800 --seed 10 --resume --out " + path("other"));
    EXPECT_EQ(other.status, 2);
    EXPECT_THAT(other.output, HasSubstr("belongs to another computation"));
  }
}

// The same for a design (its finished global search and Ipopt starts are the checkpoint): the trajectory is
// identical byte for byte, and so is design.json but for the solve's measured time and memory.
TEST_F(Cli, KilledDesignResumesToTheSameResult) {
  for (const std::string solver : {"nlopt --set global_evaluations=400 --set local_evaluations=300", "ipopt --set starts=4 --set max_iterations=15"}) {
    const std::string name = solver.substr(0, solver.find(' '));
    const std::string args = "--quiet design --budget-min 20 --envelope short --model rbf --seed 3 --solver " + solver;
    const int kills = kill_and_resume(args, dir_ / (name + "_whole"), dir_ / (name + "_killed"), ".design_checkpoint.json", 7);
    EXPECT_GE(kills, 1) << name << ": the run finished before every kill point";
    EXPECT_EQ(read_text(dir_ / (name + "_killed") / "trajectory.yaml"), read_text(dir_ / (name + "_whole") / "trajectory.yaml")) << name;
    auto whole = read_json(dir_ / (name + "_whole") / "design.json"), resumed = read_json(dir_ / (name + "_killed") / "design.json");
    for (auto* j : {&whole, &resumed}) (*j)["solver_summary"].erase("time_s"), (*j)["solver_summary"].erase("peak_rss_mb");
    EXPECT_EQ(resumed, whole) << name;
  }
}

// A file's text with the lines of measured time and memory left out and `dir` (a session's own directory,
// which its files name) written as `as`.
std::string comparable_text(const fs::path& file, const fs::path& dir, const fs::path& as) {
  std::string text = read_text(file), out, line;
  for (std::size_t at = text.find(dir.string()); at != std::string::npos; at = text.find(dir.string(), at + as.string().size())) {
    text.replace(at, dir.string().size(), as.string());
  }
  std::istringstream in(text);
  while (std::getline(in, line)) {
    if (line.find("\"time_s\"") == std::string::npos && line.find("\"peak_rss_mb\"") == std::string::npos) out += line + "\n";
  }
  return out;
}

// The same for an adaptive session (issue 32; each finished segment, and each segment's finished design
// stages, are the checkpoint): killed at random points through its pilot, calibrations and redesign, it
// ends with the same programmes, recordings, models and session.json as an uninterrupted session, and leaves
// no checkpoint in any segment.
TEST_F(Cli, KilledSessionResumesToTheSameResult) {
  std::ofstream(path("two.yaml")) << ("format: gyrosid-prior/1\nname: two\nmembers:\n  - {sensor: builtin:sensors/open_loop_fog.yaml}\n"
                                "  - {sensor: builtin:priors/open_loop_fog_drift.yaml}\n");
  const std::string args = "--quiet session --prior " + path("two.yaml") + " --truth builtin:priors/open_loop_fog_drift.yaml --budget-min 40 "
                           "--pilot-min 10 --envelope short --model classical --set space.segments=3 --set global_evaluations=3000 "
                           "--set local_evaluations=1500 --seed 4";
  const fs::path whole = dir_ / "whole", killed = dir_ / "killed";
  const int kills = kill_and_resume(args, whole, killed, ".session_checkpoint.json", 17);
  EXPECT_GE(kills, 1) << "the run finished before every kill point";
  std::vector<std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(whole)) {
    if (entry.is_regular_file()) files.push_back(fs::relative(entry.path(), whole).string());
  }
  EXPECT_GE(files.size(), 12u);  // session.json, model.json, recording, trajectory, and each segment's
  for (const std::string& f : files) EXPECT_EQ(comparable_text(killed / f, killed, whole), comparable_text(whole / f, whole, whole)) << f;
  for (const auto& entry : fs::recursive_directory_iterator(killed)) {
    EXPECT_EQ(entry.path().filename().string().find("checkpoint"), std::string::npos) << "left behind: " << entry.path();
    EXPECT_EQ(entry.path().filename().string().find(".tmp."), std::string::npos) << "stale temporary: " << entry.path();
  }
  // The checkpoint is read on resume: one a killed session left is refused for another seed, naming it.
  run_and_kill(args + " --out " + path("other"), 1.0);
  if (fs::exists(dir_ / "other" / ".session_checkpoint.json")) {
    std::string other_seed = args;
    other_seed.replace(other_seed.find("--seed 4"), 8, "--seed 5");
    const Result other = run(other_seed + " --resume --out " + path("other"));
    EXPECT_EQ(other.status, 2);
    EXPECT_THAT(other.output, HasSubstr("belongs to another computation"));
  }
}

// The same for explain (each finished selection step's bootstrap is the checkpoint): explain.json identical but
// for its run time, the refitted model and the residuals identical byte for byte.
TEST_F(Cli, KilledExplainResumesToTheSameResult) {
  std::ofstream(path("shupe.yaml")) << read_text(fs::path(GYROSID_SOURCE_DIR) / "configs/sensors/open_loop_fog.yaml")
                                    << "\nshupe_dph_per_c_per_min: 4\n";
  ASSERT_EQ(run("simulate --sensor " + path("shupe.yaml") + " --trajectory builtin:trajectories/test_4x16.yaml --seed 2 --out " + path("rec.csv")).status, 0);
  const std::string args = "--quiet explain --recording " + path("rec.csv") + " --baseline-form polynomial --bootstrap 1999 --seed 3";
  const int kills = kill_and_resume(args, dir_ / "whole", dir_ / "killed", ".explain_checkpoint.json", 11);
  EXPECT_GE(kills, 1) << "the run finished before every kill point";
  auto whole = read_json(dir_ / "whole" / "explain.json"), resumed = read_json(dir_ / "killed" / "explain.json");
  EXPECT_EQ(whole["verdict"], "missing_physics");
  for (const char* timing : {"run_time_s", "stage_times_s"}) whole.erase(timing), resumed.erase(timing);  // wall times
  EXPECT_EQ(resumed, whole);
  for (const char* f : {"model.json", "residuals.csv"}) EXPECT_EQ(read_text(dir_ / "killed" / f), read_text(dir_ / "whole" / f)) << f;
}

// --threads changes how work is split, never the result: the same model, bit for bit, on 1 and 2 threads.
TEST_F(Cli, ThreadCountDoesNotChangeTheModel) {
  ASSERT_EQ(run("simulate --trajectory builtin:trajectories/dual_scan.yaml --samples 1500 --seed 4 --out " + path("r.csv")).status, 0);
  for (const char* threads : {"1", "2"}) {
    const Result r = run(std::string("--quiet --threads ") + threads + " calibrate --recording " + path("r.csv") +
                         " --solver lrols_loo --set candidates=300 --out " + path(std::string("m") + threads + ".json"));
    ASSERT_EQ(r.status, 0) << r.output;
  }
  const auto a = read_json(dir_ / "m1.json"), b = read_json(dir_ / "m2.json");
  EXPECT_EQ(a["parameters"], b["parameters"]);
  EXPECT_THAT(run("--threads 0 calibrate --help").output, HasSubstr("--threads"));
}

// Same inputs, same bytes, wherever the allocator puts things: Ceres orders a covariance's columns by the
// parameter blocks' addresses, and a sequential triad's sigmas once moved in their last digits with glibc's
// malloc settings (3 different files from one binary). GLIBC_TUNABLES moves the heap's layout.
TEST_F(Cli, ATriadsSigmasDoNotFollowTheAllocatorsLayout) {
  ASSERT_EQ(run("simulate --sensor builtin:sensors/fog_triad.yaml --trajectory builtin:trajectories/triad_six_position.yaml --seed 2 --out " + path("six.csv")).status, 0);
  std::vector<nlohmann::json> misalignment;
  for (const char* tunables : {"", "glibc.malloc.mmap_threshold=4096", "glibc.malloc.top_pad=1048576"}) {
    const std::string out = path("t" + std::to_string(misalignment.size()) + ".json");
    const std::string command = std::string("GLIBC_TUNABLES=") + tunables + " " + GYROSID_EXE + " calibrate --model triad --recording " +
                                path("six.csv") + " --surfaces classical --sequential --out " + out + " > /dev/null 2>&1";
    ASSERT_EQ(std::system(command.c_str()), 0) << tunables;
    misalignment.push_back(read_json(out)["misalignment"]);
  }
  for (std::size_t k = 1; k < misalignment.size(); ++k) {
    EXPECT_EQ(misalignment[k]["sigma"], misalignment[0]["sigma"]) << k;
    EXPECT_EQ(misalignment[k]["inflation"], misalignment[0]["inflation"]) << k;
  }
  // The triad's options (--set surfaces=..., estimation=...) are what the older flags spell; the help teaches
  // the options only.
  ASSERT_EQ(run("calibrate --model triad --recording " + path("six.csv") + " --set surfaces=classical --set estimation=sequential --out " + path("s.json")).status, 0);
  EXPECT_EQ(read_json(path("s.json"))["misalignment"], misalignment[0]);
  const std::string help = run("calibrate --help").output;
  EXPECT_THAT(help, HasSubstr("--set surfaces=classical --set estimation=joint"));
  EXPECT_THAT(help, Not(HasSubstr("--sequential")));
}

// A triad: simulate -> calibrate --model triad -> compensate -> cof; the planted matrix of fog_triad.yaml
// (eq 3.72: M_xy = phi_y + mu_y = -0.1 mrad, M_xz = -(phi_x + mu_x) = -1.1 mrad, ...) within 4 sigma.
TEST_F(Cli, TriadCalibrationCompensationAndCriterionOfFit) {
  Result r = run("simulate --sensor builtin:sensors/fog_triad.yaml --trajectory builtin:trajectories/triad_six_position.yaml --seed 2 --out " + path("six.csv"));
  ASSERT_EQ(r.status, 0) << r.output;
  r = run("calibrate --model triad --recording " + path("six.csv") + " --set bias_order=2 --out " + path("triad.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  const nlohmann::json j = read_json(path("triad.json"));
  EXPECT_EQ(j["kind"], "triad");
  const double planted[3][3] = {{0, -0.1e-3, -1.1e-3}, {0.8e-3, 0, 1.4e-3}, {0.4e-3, -1.0e-3, 0}};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      if (i == k) continue;
      const double sigma = j["misalignment"]["sigma"][i][k].get<double>();
      EXPECT_LT(sigma, 25e-6);
      EXPECT_LT(std::abs(j["misalignment"]["matrix"][i][k].get<double>() - planted[i][k]), 4 * sigma) << i << k;
    }
  EXPECT_EQ(j["bias_dph"]["value"].size(), 3u);
  EXPECT_NEAR(j["bias_dph"]["value"][0].get<double>(), -15.0, 1.5);
  EXPECT_EQ(j["observable"]["independent_combinations"], 6);
  EXPECT_EQ(j["summary"]["solver"], "ceres");

  r = run("compensate --model " + path("triad.json") + " --recording " + path("six.csv") + " --out " + path("comp.csv"));
  ASSERT_EQ(r.status, 0) << r.output;
  const Recording comp = read_recording(path("comp.csv"));
  EXPECT_TRUE(comp.has("compensated_x_dps") && comp.has("compensated_y_dps") && comp.has("compensated_z_dps"));

  const std::string cof = "cof --sensor builtin:sensors/fog_triad.yaml --trajectory short --model ";
  ASSERT_EQ(run(cof + path("triad.json") + " --out " + path("cof_triad")).status, 0);
  ASSERT_EQ(run(cof + "none --out " + path("cof_none")).status, 0);
  const double with = read_json(path("cof_triad/cof.json"))["end_error_m"].get<double>();
  const double without = read_json(path("cof_none/cof.json"))["end_error_m"].get<double>();
  EXPECT_LT(with, 0.7 * without);

  ASSERT_EQ(run("export --model " + path("triad.json") + " --format kalibr --prefix fog --out " + dir_.string()).status, 0);
  EXPECT_THAT(read_text(dir_ / "fog_imu.yaml"), HasSubstr("model: scale-misalignment"));
  ASSERT_EQ(run("export --model " + path("triad.json") + " --prefix fog --out " + dir_.string()).status, 0);
  EXPECT_THAT(read_text(dir_ / "fog.h"), HasSubstr("void fog_compensate(const double gyro_radps[3]"));
  EXPECT_THAT(run("calibrate --options-of triad").output, HasSubstr("nls.<key>"));

  r = run("calibrate --model triad --recording " + path("six.csv") + " --set surfacez=rbf --out " + path("x.json"));
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("surfacez"));
  r = run("calibrate --model triad --recording " + path("six.csv") + " --solver lbfgs --out " + path("x.json"));
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("ceres"));
  for (const char* bad : {"order_criterion=aicc", "order_test_level=0.7", "rbf_form=scale_factor", "rbf_form=relative", "coupling_test_level=0.7"}) {
    r = run("calibrate --model triad --recording " + path("six.csv") + " --surfaces classical --set " + bad + " --out " + path("x.json"));
    EXPECT_EQ(r.status, 2) << bad;
    EXPECT_THAT(r.output, HasSubstr(std::string(bad).substr(0, std::string(bad).find('=')))) << bad;
  }
  r = run("calibrate --model triad --recording " + path("six.csv") + " --surfaces rbf --set rbf_form=scale_factor --set rbf_diagonal=zero_rate --out " + path("x.json"));
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("rbf_diagonal=zero_rate"));
  for (const char* mode : {"--joint", "--auto"}) {
    r = run("calibrate --model triad --recording " + path("comp.csv") + " --surfaces greybox " + mode + " --out " + path("x.json"));
    EXPECT_EQ(r.status, 2) << mode;
    EXPECT_THAT(r.output, HasSubstr("sequential")) << mode;
  }
  r = run("calibrate --model triad --recording " + path("six.csv") + " --surfaces classical --joint --auto --out " + path("x.json"));
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("exclude each other"));
  EXPECT_FALSE(fs::exists(path("x.json")));
  // --auto on the six-position programme (balanced: single-axis turns) keeps the sequential fit, and says why.
  r = run("calibrate --model triad --recording " + path("six.csv") + " --surfaces classical --set surface.sf_rate_order=2 --set surface.sf_cross_order=0 --auto --out " +
          path("auto.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("auto (sequential returned)"));
  const nlohmann::json test = read_json(path("auto.json"))["summary"]["details"]["coupling_test"];
  EXPECT_LT(test["statistic"].get<double>(), test["critical"].get<double>());
}

TEST_F(Cli, HelpTeaches) {
  for (const char* sub : {"simulate", "allan", "run", "calibrate", "compensate", "surface", "export", "cof", "explain", "design"}) {
    const Result r = run(std::string(sub) + " --help");
    EXPECT_EQ(r.status, 0) << sub;
    EXPECT_THAT(r.output, HasSubstr("--out")) << sub;
  }
  EXPECT_THAT(run("allan --help").output, HasSubstr("IEEE Std 952"));
  EXPECT_THAT(run("--help").output, HasSubstr("simulate"));
  EXPECT_THAT(run("--help").output, HasSubstr("GYROSID_THREADS"));
}

// import end to end: the summary line states the rate and the sampling; a ULog's dropout is a warning line.
TEST_F(Cli, ImportStatesTheSamplingAndWarnsOfDropouts) {
  std::ofstream(path("imu0.csv")) << "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1]\n"
                                     "1403636579758555392,0.1,0.2,0.3\n1403636579763555392,0.1,0.2,0.3\n1403636579768555392,0.1,0.2,0.3\n";
  Result r = run("import --format euroc --input " + path("imu0.csv") + " --stationary --temp-c 22 --out " + path("rec.csv"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("3 samples from euroc log " + path("imu0.csv") + ", 200 Hz (median); sampling uniform"));
  EXPECT_EQ(read_recording(path("rec.csv")).column("t_s")[2], 0.01);
  r = run("import --format ulog --input " + std::string(GYROSID_SOURCE_DIR) + "/tests/data/pyulog/sample_log_small.ulg --instance 2 --stationary --out " + path("u.csv"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("sample_log_small.ulg: dropouts: 1 in the log (30 ms in all)"));
  EXPECT_THAT(r.output, HasSubstr("6 samples from ulog log"));
  // No temperature in the log and none given: the recording has no temp_c, and says so; a command that needs one refuses it.
  r = run("import --format euroc --input " + path("imu0.csv") + " --stationary --out " + path("x.csv"));
  ASSERT_EQ(r.status, 0) << r.output;
  const Recording x = read_recording(path("x.csv"));
  EXPECT_FALSE(x.has("temp_c"));
  EXPECT_THAT(x.meta("temperature").value_or(""), HasSubstr("none: the log records none"));
  const std::string help = run("import --help").output;
  for (const char* format : {"euroc", "kalibr", "ros", "imu_tk", "ulog", "rosbag"}) EXPECT_THAT(help, HasSubstr("gyrosid import --format " + std::string(format))) << format;
}

// Holds checked for stillness on the command line (solvers/triad/hold_stillness.h): a hand-turned session with
// hand motion in hold 5 (a 1 deg/s wobble about x, 0.05 deg/s noise elsewhere): a warning names that hold, no
// other, and the model file's summary lists it.
TEST_F(Cli, HandTurnedSessionNamesTheHoldThatIsNotStill) {
  TriadData d = testing_support::hand_turn_session(testing_support::hand_turn_misalignment(), testing_support::hand_turn_bias(), 5,
                                                   units::dps_to_radps(0.05), 1e-3);
  Recording rec("hand");
  rec.set_meta("reference", "gravity");
  rec.set_column("t_s", d.t_s);
  const char* axes[] = {"x", "y", "z"};
  std::vector<double> id(d.position_id.begin(), d.position_id.end());
  for (Eigen::Index k = 0; k < d.size(); ++k) {
    if (d.position_id[static_cast<std::size_t>(k)] == 5) d.gyro(k, 0) += units::dps_to_radps(std::sin(4.0 * units::kPi * d.t_s[static_cast<std::size_t>(k)]));
  }
  for (int a = 0; a < 3; ++a) {
    std::vector<double> gyro(static_cast<std::size_t>(d.size())), accel(gyro.size());
    for (Eigen::Index k = 0; k < d.size(); ++k) gyro[static_cast<std::size_t>(k)] = units::radps_to_dps(d.gyro(k, a)), accel[static_cast<std::size_t>(k)] = d.accel(k, a);
    rec.set_column(std::string("ref_rate_") + axes[a] + "_dps", std::vector<double>(gyro.size(), 0.0));
    rec.set_column(std::string("gyro_") + axes[a] + "_dps", gyro);
    rec.set_column(std::string("accel_") + axes[a] + "_mps2", accel);
  }
  rec.set_column("temp_c", std::vector<double>(id.size(), 25.0));
  rec.set_column("position_id", id);
  write_recording(rec, path("hand.csv"));
  const Result r = run("calibrate --model triad --recording " + path("hand.csv") + " --set bias_order=0 --out " + path("triad.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("warning: " + path("hand.csv") + ": hold position_id 5 (10 s to 10.99 s) is not still: gyro std x/y/z 0.7"));
  EXPECT_THAT(r.output, Not(HasSubstr("hold position_id 4 ")));
  EXPECT_THAT(r.output, Not(HasSubstr("hold position_id 6 ")));
  const nlohmann::json j = read_json(path("triad.json"));
  ASSERT_EQ(j["summary"]["details"]["hold_stillness"]["not_still"].size(), 1u);
  EXPECT_EQ(j["summary"]["details"]["hold_stillness"]["not_still"][0]["position_id"], 5);
}

TEST_F(Cli, DesignWritesATrajectoryThatSimulateReadsDeterministically) {
  const std::string quick = " --envelope short --model classical --budget-min 8 --set space.segments=2 --set global_evaluations=60 "
                            "--set local_evaluations=40 --seed 4 --compare builtin:trajectories/single_scan.yaml --out ";
  const Result r = run("design" + quick + path("d1"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("predicted: short"));
  for (const char* f : {"trajectory.yaml", "design.json", "coverage.png", "report.md", "calibration.yaml"}) {
    EXPECT_TRUE(fs::exists(dir_ / "d1" / f)) << f;
  }
  const auto j = nlohmann::json::parse(read_text(dir_ / "d1" / "design.json"));
  EXPECT_NEAR(j["duration_min"].get<double>(), 8.0, 1e-9);
  EXPECT_GT(j["predicted"]["flights"]["short"]["cof_m"].get<double>(), 0.0);
  EXPECT_GT(j["predicted"]["flights"]["short"]["surface_rms_dph"].get<double>(), 0.0);
  EXPECT_EQ(j["solver_summary"]["solver"], "nlopt");
  EXPECT_LE(j["objective"].get<double>(), j["solver_summary"]["initial_cost"].get<double>());
  // Same seed, same design, byte for byte; the design is an ordinary trajectory for simulate.
  ASSERT_EQ(run("design" + quick + path("d2")).status, 0);
  EXPECT_EQ(read_text(dir_ / "d1" / "trajectory.yaml"), read_text(dir_ / "d2" / "trajectory.yaml"));
  const Result sim = run("simulate --trajectory " + path("d1/trajectory.yaml") + " --out " + path("rec.csv"));
  ASSERT_EQ(sim.status, 0) << sim.output;
  EXPECT_EQ(read_recording(path("rec.csv")).rows(), 8u * 60u * 3u);  // 8 min at the design's 3 Hz
  const Result cal = run("calibrate --config " + path("d1/calibration.yaml") + " --recording " + path("rec.csv") + " --out " + path("m.json"));
  EXPECT_EQ(cal.status, 0) << cal.output;
  // The predicted accuracy of any trajectory, the design's own among them.
  const Result ev = run("design --evaluate " + path("d1/trajectory.yaml") + " builtin:trajectories/dual_scan.yaml --envelope short --model classical");
  ASSERT_EQ(ev.status, 0) << ev.output;
  EXPECT_THAT(ev.output, HasSubstr("dual scan (62 min): predicted short"));
  // Bad inputs name the option.
  EXPECT_THAT(run("design --budget-min 10 --model spline --out " + path("x")).output, HasSubstr("known: rbf, greybox, classical"));
  EXPECT_THAT(run("design --budget-min 10 --set space.segmnts=3 --out " + path("x")).output, HasSubstr("unknown option 'space.segmnts'"));
  EXPECT_THAT(run("design --budget-min 10 --solver ipopt --set tolerance=0 --out " + path("x")).output, HasSubstr("tolerance"));
  EXPECT_THAT(run("design --out " + path("x")).output, HasSubstr("--budget-min is required"));
  EXPECT_FALSE(fs::exists(dir_ / "x"));
}

// --prior: a sensor config is the prior of that sensor (the same design as --sensor, byte for byte); a prior of
// two writes the design's prediction and gain on each member; what a prior cannot take is refused by name.
TEST_F(Cli, DesignForAPriorOverSensors) {
  const std::string quick = " --envelope short --model classical --budget-min 8 --set space.segments=2 --set global_evaluations=30 "
                            "--set local_evaluations=20 --seed 4 --compare builtin:trajectories/single_scan.yaml";
  ASSERT_EQ(run("design" + quick + " --out " + path("s")).status, 0);
  const Result one = run("design" + quick + " --prior builtin:sensors/open_loop_fog.yaml --out " + path("p1"));
  ASSERT_EQ(one.status, 0) << one.output;
  EXPECT_EQ(read_text(dir_ / "s" / "trajectory.yaml"), read_text(dir_ / "p1" / "trajectory.yaml"));
  EXPECT_FALSE(read_json(dir_ / "p1" / "design.json").contains("prior"));
  std::ofstream(path("two.yaml")) << ("format: gyrosid-prior/1\nname: two\nmembers:\n  - {sensor: builtin:sensors/open_loop_fog.yaml}\n"
                                "  - {sensor: builtin:priors/open_loop_fog_drift.yaml, weight: 2}\n");
  const Result two = run("design" + quick + " --prior " + path("two.yaml") + " --out " + path("p2"));
  ASSERT_EQ(two.status, 0) << two.output;
  const nlohmann::json j = read_json(dir_ / "p2" / "design.json");
  ASSERT_EQ(j["prior"]["members"].size(), 2u);
  EXPECT_EQ(j["prior"]["members"][1]["weight"], 2.0);
  // The spread is over the members' own predictions: its mean is their weighted mean.
  const double a = j["prior"]["members"][0]["predicted"]["flights"]["short"]["cof_m"], b = j["prior"]["members"][1]["predicted"]["flights"]["short"]["cof_m"];
  EXPECT_NEAR(j["prior"]["flights"]["short"]["design_cof_m"]["mean"].get<double>(), (a + 2.0 * b) / 3.0, 1e-12 * a);
  EXPECT_EQ(j["prior"]["members"][0]["predicted"], j["predicted"]);
  EXPECT_THAT(read_text(dir_ / "p2" / "report.md"), HasSubstr("## Over the prior (2 sensors)"));
  EXPECT_THAT(run("design" + quick + " --prior " + path("two.yaml") + " --criterion cof_minimax --out " + path("x")).output,
              HasSubstr("criterion cof_minimax takes one sensor (it compares against one reference; use --criterion cof), not a prior of 2"));
  EXPECT_THAT(run("design" + quick + " --prior " + path("two.yaml") + " --sensor builtin:sensors/open_loop_fog.yaml --out " + path("x")).output,
              HasSubstr("excludes"));
  EXPECT_FALSE(fs::exists(dir_ / "x"));
}

// session: a simulated session joins its segments into the recording of one uninterrupted run of the true
// sensor, learns which member of the prior recorded it, and ends with a model; the same session in the lab
// (no --truth) stops for each recording and, given the same recordings, designs the same segments byte for byte.
TEST_F(Cli, SessionAdaptsToTheUnitAndWaitsForTheLab) {
  std::ofstream(path("two.yaml")) << ("format: gyrosid-prior/1\nname: two\nmembers:\n  - {sensor: builtin:sensors/open_loop_fog.yaml}\n"
                                "  - {sensor: builtin:priors/open_loop_fog_drift.yaml}\n");
  const std::string truth = "builtin:priors/open_loop_fog_drift.yaml";
  const std::string options = " --prior " + path("two.yaml") + " --budget-min 12 --pilot-min 4 --envelope short --model classical "
                              "--set space.segments=2 --set global_evaluations=30 --set local_evaluations=20 --seed 4";
  // session.measured_white_noise: the white noise the pilot shows replaces the members': 8 deg/h at 1 Hz is 8 sqrt(3)
  // per sample at 3 Hz.
  ASSERT_EQ(run("session" + options + " --set session.measured_white_noise=true --out " + path("measured") + " --truth " + truth).status, 0);
  const nlohmann::json measured = read_json(dir_ / "measured" / "session.json")["segments"][0]["measured_noise"];
  EXPECT_NEAR(measured["white_dph_per_sample"].get<double>(), 8.0 * std::sqrt(3.0), 0.12 * 8.0 * std::sqrt(3.0));
  EXPECT_NEAR(measured["arw_dph_rt_h"].get<double>(), 8.0 / 60.0, 0.12 * 8.0 / 60.0);
  // With the members' own noise the pilot tells the drifting member from the reference.
  const std::string quick = options + " --out ";
  const Result r = run("session" + quick + path("sim") + " --truth " + truth);
  ASSERT_EQ(r.status, 0) << r.output;
  const nlohmann::json j = read_json(dir_ / "sim" / "session.json");
  EXPECT_EQ(j["status"], "complete");
  ASSERT_EQ(j["segments"].size(), 2u);
  EXPECT_EQ(j["segments"][1]["start_min"], 4.0);
  EXPECT_EQ(j["segments"][1]["duration_min"], 8.0);
  // The member that recorded (the drift unit) takes the posterior; the redesign is for it alone.
  EXPECT_GT(j["segments"][0]["posterior"]["members"][1]["weight"].get<double>(), 0.99);
  EXPECT_EQ(j["segments"][1]["designed_for"].size(), 1u);
  // The joined recording is the truth simulated on the joined programme in one run: the same numbers.
  ASSERT_EQ(run("simulate --sensor " + truth + " --trajectory " + path("sim/trajectory.yaml") + " --seed 4 --out " + path("one.csv")).status, 0);
  const Recording joined = read_recording(path("sim/recording.csv")), one = read_recording(path("one.csv"));
  ASSERT_EQ(joined.rows(), 12u * 60u * 3u);
  for (const char* c : {"t_s", "gyro_dps", "temp_c", "ref_rate_dps"}) EXPECT_EQ(joined.column(c), one.column(c)) << c;
  EXPECT_TRUE(fs::exists(dir_ / "sim" / "model.json"));
  EXPECT_TRUE(fs::exists(dir_ / "sim" / "segment_1" / "model.json"));  // the interim calibration
  // In the lab: it designs the pilot and waits; each recording given, --resume goes on.
  const Result w = run("session" + quick + path("lab"));
  ASSERT_EQ(w.status, 0) << w.output;
  EXPECT_THAT(w.output, HasSubstr("record it to " + path("lab/segment_1/recording.csv")));
  EXPECT_THAT(read_text(dir_ / "lab" / "session.json"), HasSubstr("waiting for"));
  EXPECT_THAT(run("session" + quick + path("lab")).output, HasSubstr("holds a session (session.json): continue it with --resume"));
  for (const char* k : {"1", "2"}) {
    const std::string seg = std::string("segment_") + k;
    EXPECT_EQ(read_text(dir_ / "lab" / seg / "trajectory.yaml"), read_text(dir_ / "sim" / seg / "trajectory.yaml")) << seg;
    fs::copy_file(dir_ / "sim" / seg / "recording.csv", dir_ / "lab" / seg / "recording.csv");
    const Result next = run("session" + quick + path("lab") + " --resume");
    ASSERT_EQ(next.status, 0) << next.output;
  }
  EXPECT_EQ(read_json(dir_ / "lab" / "session.json")["status"], "complete");
  EXPECT_EQ(read_text(dir_ / "lab" / "recording.csv"), read_text(dir_ / "sim" / "recording.csv"));
  // A resume with other inputs is refused; bad options are named.
  const auto replaced = [&](const std::string& from, const std::string& to) {  // `quick` with one option changed
    std::string q = quick;
    return q.replace(q.find(from), from.size(), to);
  };
  const auto with_pilot = [&](const std::string& minutes) { return replaced("--pilot-min 4", "--pilot-min " + minutes); };
  EXPECT_THAT(run("session" + with_pilot("5") + path("lab") + " --resume").output, HasSubstr("another fingerprint"));
  EXPECT_THAT(run("session" + with_pilot("12") + path("x")).output, HasSubstr("--pilot-min 12 must lie in (0, --budget-min 12)"));
  EXPECT_THAT(run("session" + quick + path("x") + " --set session.drop_share=0.7").output, HasSubstr("session.drop_share"));
  EXPECT_THAT(run("session" + quick + path("x") + " --truth builtin:sensors/fog_triad.yaml").output, HasSubstr("is a triad"));
  // --model auto designs for what gyrosid calibrate fits on a noisy recording, as design's auto does: the hybrid.
  ASSERT_EQ(run("session" + replaced("--model classical", "--model auto") + path("auto")).status, 0);
  EXPECT_EQ(read_json(dir_ / "auto" / "session.json")["model"], "hybrid");
  EXPECT_THAT(read_text(dir_ / "auto" / "calibration.yaml"), HasSubstr("\nmodel: hybrid\n"));
}

// --equipment: the design keeps the chamber's cooling limit and the table's rate and acceleration, writes them
// into trajectory.yaml (which simulate checks again) and writes the set-point table; --set space.* overrides.
TEST_F(Cli, DesignKeepsTheEquipmentFile) {
  std::ofstream(path("lab.yaml")) << "kind: equipment\nchamber: {min_c: -40, max_c: 85, heating_c_per_min: 3, cooling_c_per_min: 1}\n"
                                     "table: {max_rate_dps: 50, max_acceleration_dps2: 2}\n";
  const std::string quick = " --envelope short --model classical --budget-min 8 --set space.segments=2 --set global_evaluations=30 "
                            "--set local_evaluations=20 --seed 4 --equipment " + path("lab.yaml");
  const Result r = run("design" + quick + " --out " + path("e"));
  ASSERT_EQ(r.status, 0) << r.output;
  const TrajectorySpec t = load_trajectory_file(path("e/trajectory.yaml"));  // check_limits with the file's limits
  EXPECT_EQ(t.profile.limits.limit_c_per_min(false), 1.0);
  EXPECT_EQ(t.profile.limits.min_c, -40.0);
  EXPECT_NEAR(t.profile.table_limits.max_acceleration_radps2, units::dps_to_radps(2.0), 1e-15);
  for (const auto& s : t.profile.segments) {
    EXPECT_GE((s.chamber_end_c - s.chamber_start_c) / (s.duration_s / 60.0), -1.0 - 1e-9) << s.label;
    const double peak = s.rate.shape == RateProfile::Shape::triangle ? std::max(std::abs(s.rate.low_radps), std::abs(s.rate.high_radps))
                                                                     : std::abs(s.rate.value_radps);
    EXPECT_LE(peak, units::dps_to_radps(50.0) * (1 + 1e-12)) << s.label;
  }
  EXPECT_EQ(read_text(dir_ / "e" / "setpoints.csv").substr(0, 47), "t_s,chamber_setpoint_c,table_rate_dps,position\n");
  const Result over = run("design" + quick + " --set space.chamber_cooling_limit_c_per_min=0.5 --out " + path("o"));
  ASSERT_EQ(over.status, 0) << over.output;
  EXPECT_EQ(load_trajectory_file(path("o/trajectory.yaml")).profile.limits.limit_c_per_min(false), 0.5);
  EXPECT_THAT(run("design" + quick + "x --out " + path("x")).output, HasSubstr("lab.yamlx"));
  EXPECT_FALSE(fs::exists(dir_ / "x"));
}

// cof_minimax against a reference that is also a --compare predicts it once (one report row); --evaluate with a
// reference writes the evaluated trajectories only; --help names the exact selection's keys.
TEST_F(Cli, DesignAgainstAReferencePredictsItOnce) {
  const std::string ref = "builtin:trajectories/single_scan.yaml";
  const Result r = run("design --envelope short --model classical --budget-min 8 --set space.segments=2 --set global_evaluations=60 "
                       "--set local_evaluations=40 --seed 4 --criterion cof_minimax --reference " + ref + " --compare " + ref +
                       " --out " + path("m1"));
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string report = read_text(dir_ / "m1" / "report.md");
  std::size_t rows = 0;
  for (auto at = report.find("| single scan"); at != std::string::npos; at = report.find("| single scan", at + 1)) ++rows;
  EXPECT_EQ(rows, 1u) << report;
  const Result ev = run("design --evaluate builtin:trajectories/dual_scan.yaml --envelope short --model classical --criterion cof_minimax "
                        "--reference " + ref + " --out " + path("e1"));
  ASSERT_EQ(ev.status, 0) << ev.output;
  EXPECT_THAT(ev.output, HasSubstr("single scan (reference, classical)"));
  const auto j = nlohmann::json::parse(read_text(dir_ / "e1" / "evaluation.json"));
  EXPECT_EQ(j["trajectories"].size(), 1u);
  EXPECT_TRUE(j["trajectories"].contains("builtin:trajectories/dual_scan.yaml"));
  EXPECT_THAT(run("design --help").output, HasSubstr("select.rounds"));
}

// `--axis` reads one gyro of a triad under the single-gyro names: a network calibrated on the y gyro (the simulated
// sensor's error) compensates that gyro; the same on the x gyro (planted with half that error) removes half of it.
// Temperature is required by what uses it only: calibrate's default features name the file and temp_c; allan
// and explain run without one.
TEST_F(Cli, AxisPicksTheTriadGyroAndTemperatureIsRequiredWhereItIsUsed) {
  ASSERT_EQ(run("simulate --noise-free --samples 1111 --out " + path("dual.csv")).status, 0);
  const Recording one = read_recording(path("dual.csv"));
  Recording triad("triad");
  triad.set_column("t_s", one.column("t_s"));
  triad.set_column("temp_c", one.column("temp_c"));
  for (const char* a : {"x", "y", "z"}) {
    triad.set_column(std::string("ref_rate_") + a + "_dps", one.column("ref_rate_dps"));
    std::vector<double> gyro = one.column("gyro_dps");  // y: the simulated sensor; x and z: half its error
    for (std::size_t i = 0; i < gyro.size(); ++i) gyro[i] -= std::string(a) == "y" ? 0.0 : 0.5 * (gyro[i] - one.column("ref_rate_dps")[i]);
    triad.set_column(std::string("gyro_") + a + "_dps", gyro);
  }
  write_recording(triad, path("triad.csv"));
  Result r = run("calibrate --recording " + path("triad.csv") + " --config builtin:calibration/rbf_noisy.yaml --out " + path("none.json"));
  EXPECT_EQ(r.status, 2);
  EXPECT_THAT(r.output, HasSubstr("--axis"));
  const auto rms_ratio = [&](const std::string& model) {
    EXPECT_EQ(run("compensate --model " + model + " --recording " + path("dual.csv") + " --out " + path("comp.csv")).status, 0);
    const Recording c = read_recording(path("comp.csv"));
    double raw = 0.0, left = 0.0;
    for (std::size_t i = 0; i < c.rows(); ++i) {
      raw += std::pow(c.column("gyro_dps")[i] - c.column("ref_rate_dps")[i], 2);
      left += std::pow(c.column("compensated_dps")[i] - c.column("ref_rate_dps")[i], 2);
    }
    return std::sqrt(left / raw);
  };
  for (const char* axis : {"y", "x"}) {
    r = run("calibrate --recording " + path("triad.csv") + " --axis " + axis + " --config builtin:calibration/rbf_noisy.yaml --out " + path(std::string(axis) + ".json"));
    ASSERT_EQ(r.status, 0) << r.output;
  }
  EXPECT_LT(rms_ratio(path("y.json")), 1e-3);  // as from the single-gyro recording itself
  EXPECT_NEAR(rms_ratio(path("x.json")), 0.5, 0.01);  // the x gyro's model removes half the y gyro's error

  Recording no_temperature("no_temperature");
  for (const char* c : {"t_s", "ref_rate_dps", "gyro_dps"}) no_temperature.set_column(c, one.column(c));
  write_recording(no_temperature, path("no_temp.csv"));
  r = run("calibrate --recording " + path("no_temp.csv") + " --config builtin:calibration/rbf_noisy.yaml --out " + path("t.json"));
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("no_temp.csv"));
  EXPECT_THAT(r.output, HasSubstr("temp_c"));
  EXPECT_FALSE(fs::exists(path("t.json")));
  r = run("allan --recording " + path("no_temp.csv") + " --subtract ref_rate_dps --out " + path("allan"));
  EXPECT_EQ(r.status, 0) << r.output;
  r = run("explain --recording " + path("no_temp.csv") + " --bootstrap 199 --out " + path("explain"));
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir_ / "explain" / "explain.json"));
}

}  // namespace
}  // namespace gyrosid

namespace gyrosid {
namespace {

// calibrate with no options characterises the noise and says which preset it chose and why; the hybrid's
// posterior gives surface a sigma map whose 95 % band covers most of the actual error, and compensate a
// sigma column.
TEST_F(Cli, CalibrateWithoutOptionsChoosesAPresetFromTheNoise) {
  ASSERT_EQ(run("simulate --noise-free --samples 1111 --out " + path("clean.csv")).status, 0);
  ASSERT_EQ(run("simulate --seed 4 --samples 2222 --out " + path("noisy.csv")).status, 0);
  Result r = run("calibrate --recording " + path("clean.csv") + " --out " + path("clean.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("noise-free"));
  EXPECT_THAT(r.output, HasSubstr("rbf_noise_free.yaml"));
  r = run("calibrate --recording " + path("noisy.csv") + " --out " + path("noisy.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("rbf_noisy.yaml"));
  EXPECT_THAT(r.output, HasSubstr("noise model: "));
  const auto model = read_json(dir_ / "noisy.json");
  EXPECT_EQ(model["training"]["preset"]["chosen"], "builtin:calibration/rbf_noisy.yaml");
  EXPECT_THAT(r.output, HasSubstr("noise: white "));
  ASSERT_EQ(run("surface --model " + path("noisy.json") + " --out " + path("surface")).status, 0);
  const auto s = read_json(dir_ / "surface" / "surface.json");
  ASSERT_TRUE(s.contains("sigma"));
  EXPECT_GT(s["sigma"]["coverage_95"].get<double>(), 0.8);
  EXPECT_GT(s["sigma"]["rms_sigma_dph"].get<double>(), 0.2 * s["difference"]["rms_dph"].get<double>());
  EXPECT_LT(s["sigma"]["rms_sigma_dph"].get<double>(), 5.0 * s["difference"]["rms_dph"].get<double>());
  EXPECT_TRUE(fs::exists(dir_ / "surface" / "sigma.png"));
  ASSERT_EQ(run("compensate --model " + path("noisy.json") + " --recording " + path("clean.csv") + " --out " + path("comp.csv")).status, 0);
  EXPECT_EQ(read_recording(path("comp.csv")).column("compensated_sigma_dps").size(), 1111u);
}

// A rate table run at one chamber temperature, and a soak at rest: the default calibration fits what the
// recording determines and says what it left out (both used to stop on a rank-deficient physics design).
TEST_F(Cli, CalibrateWithoutOptionsLeavesOutWhatAHeldInputCannotDetermine) {
  ASSERT_EQ(run("simulate --seed 4 --samples 2222 --out " + path("noisy.csv")).status, 0);
  Recording one_temperature = read_recording(path("noisy.csv"));
  one_temperature.set_column("temp_c", std::vector<double>(one_temperature.rows(), 25.0));
  write_recording(one_temperature, path("one_temperature.csv"));
  Result r = run("calibrate --recording " + path("one_temperature.csv") + " --out " + path("t.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("physics: the temperature stays within 0 C of 25 C: the recording does not determine dT^1"));
  EXPECT_THAT(r.output, HasSubstr("the calibration holds at this temperature only"));
  r = run("calibrate --recording " + path("one_temperature.csv") + " --model greybox --out " + path("g.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("physics: the temperature stays within 0 C of 25 C: the ridge, not the recording, sets the terms in it"));
  Recording at_rest = read_recording(path("noisy.csv"));
  std::vector<double> gyro = at_rest.column("gyro_dps");
  const std::vector<double>& ref = at_rest.column("ref_rate_dps");
  for (std::size_t i = 0; i < gyro.size(); ++i) gyro[i] -= ref[i];  // the same errors, the table at rest
  at_rest.set_column("gyro_dps", gyro);
  at_rest.set_column("ref_rate_dps", std::vector<double>(gyro.size(), 0.0));
  write_recording(at_rest, path("at_rest.csv"));
  for (const char* model : {"", " --model classical"}) {
    r = run("calibrate --recording " + path("at_rest.csv") + model + " --out " + path("r.json"));
    ASSERT_EQ(r.status, 0) << model << r.output;
    EXPECT_THAT(r.output, HasSubstr("the rate within 0 deg/s of 0 deg/s")) << model;
    EXPECT_THAT(r.output, HasSubstr("the scale factor is not calibrated")) << model;
  }
  // A network of the measured rate would fit the error as a function of itself there: refused, saying why.
  r = run("calibrate --recording " + path("at_rest.csv") + " --model rbf --solver bayes --out " + path("b.json"));
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("holds the table rate (within 0 deg/s of 0 deg/s)"));
  EXPECT_FALSE(fs::exists(path("b.json")));
}

// A lot of eight units of the reference sensor: learned, a unit of it in family, one with 3x the white noise
// out of family for its noise; a short recording calibrated with the lot's prior lands nearer the truth's bias
// than the same recording alone, with a predictive sigma; misuse is named.
TEST_F(Cli, LotLearnsScreensAndCalibratesWithItsPrior) {
  std::string recordings;
  ASSERT_NO_FATAL_FAILURE(simulate_units(8, 3000, recordings));
  ASSERT_EQ(run("simulate --samples 3000 --seed 9 --out " + path("unit9.csv")).status, 0);
  const Result learned = run("lot learn --recordings" + recordings + " --out " + path("lot.json"));
  ASSERT_EQ(learned.status, 0) << learned.output;
  EXPECT_THAT(learned.output, HasSubstr("8 units, 76 coordinates"));
  const nlohmann::json lot = read_json(path("lot.json"));
  EXPECT_EQ(lot["format"], "gyrosid-prior/1");
  EXPECT_NEAR(std::exp(lot["population"]["noise"]["white_dph_at_1hz"]["log_mean"].get<double>()), 10.0, 1.0);
  // The lot file is a prior over sensors for `design --prior`: its members, the mean first.
  const SensorPrior as_prior = load_sensor_prior(path("lot.json"));
  EXPECT_EQ(as_prior.members.size(), 2 * lot["population"]["modes"].size() + 1);
  EXPECT_EQ(as_prior.members.front().name, "lot mean");
  EXPECT_NEAR(as_prior.total_weight(), 1.0, 1e-12);
  // With the greybox model a design takes the lot's structure and counts its population as the calibration's
  // prior: the dual scan of the lot's mean unit is then predicted better on both flights than by its own data
  // (measured 0.0795 against 0.0964 m short, 0.292 against 0.467 m medium).
  const std::string evaluate = "design --evaluate builtin:trajectories/dual_scan.yaml --envelope short,medium --model greybox --prior " + path("lot.json");
  const Result with_lot = run(evaluate + " --out " + path("ew"));
  ASSERT_EQ(with_lot.status, 0) << with_lot.output;
  EXPECT_THAT(with_lot.output, HasSubstr("its population as the calibration's prior"));
  ASSERT_EQ(run(evaluate + " --without-lot-prior --out " + path("eo")).status, 0);
  const nlohmann::json ew = read_json(dir_ / "ew" / "evaluation.json")["trajectories"]["builtin:trajectories/dual_scan.yaml"]["flights"];
  const nlohmann::json eo = read_json(dir_ / "eo" / "evaluation.json")["trajectories"]["builtin:trajectories/dual_scan.yaml"]["flights"];
  for (const char* flight : {"short", "medium"}) EXPECT_LT(ew[flight]["cof_m"].get<double>(), 0.9 * eo[flight]["cof_m"].get<double>()) << flight;
  // Without --model a design is for what `calibrate` fits on the recording: under the lot, its greybox MAP
  // (calibrate --prior); for a noisy sensor, the hybrid (its preset). The same prediction as asking for it.
  const std::string by_default = "design --evaluate builtin:trajectories/dual_scan.yaml --envelope short,medium --prior " + path("lot.json");
  const Result auto_lot = run(by_default + " --out " + path("ea"));
  ASSERT_EQ(auto_lot.status, 0) << auto_lot.output;
  EXPECT_THAT(auto_lot.output, HasSubstr("model: greybox, what gyrosid calibrate fits on the recording (calibrate --prior with the lot)"));
  EXPECT_EQ(read_json(dir_ / "ea" / "evaluation.json")["trajectories"]["builtin:trajectories/dual_scan.yaml"]["flights"], ew);
  const std::string on_sensor = "design --evaluate builtin:trajectories/dual_scan.yaml --envelope short --out ";
  const Result auto_sensor = run(on_sensor + path("es"));
  EXPECT_THAT(auto_sensor.output, HasSubstr("model: hybrid, what gyrosid calibrate fits on the recording (its preset for a noisy gyro)"));
  ASSERT_EQ(run(on_sensor + path("eh") + " --model hybrid").status, 0);
  const nlohmann::json es = read_json(dir_ / "es" / "evaluation.json"), eh = read_json(dir_ / "eh" / "evaluation.json");
  EXPECT_EQ(es["provenance"]["model"], "hybrid");
  EXPECT_EQ(es["trajectories"], eh["trajectories"]);
  EXPECT_THAT(run(evaluate + " --set model.bias_order=2").output, HasSubstr("--set model.bias_order: the lot " + path("lot.json") + " fixes the grey-box structure"));
  EXPECT_THAT(run("design --evaluate builtin:trajectories/dual_scan.yaml --without-lot-prior --prior builtin:priors/open_loop_fog_type.yaml").output,
              HasSubstr("--without-lot-prior is for a lot"));

  const Result in = run("lot screen --prior " + path("lot.json") + " --recording " + path("unit9.csv") + " --out " + path("s9"));
  ASSERT_EQ(in.status, 0) << in.output;
  EXPECT_FALSE(read_json(dir_ / "s9" / "screen.json")["out_of_family"].get<bool>()) << in.output;
  EXPECT_EQ(read_json(dir_ / "s9" / "screen.json")["warning"], "");
  std::string noisy = read_text(std::string(GYROSID_SOURCE_DIR) + "/configs/sensors/open_loop_fog.yaml");
  noisy.replace(noisy.find("white_dph_at_1hz: 10"), 20, "white_dph_at_1hz: 30");
  std::ofstream(path("noisy.yaml")) << noisy;
  ASSERT_EQ(run("simulate --samples 3000 --seed 10 --sensor " + path("noisy.yaml") + " --out " + path("noisy.csv")).status, 0);
  const Result out = run("lot screen --prior " + path("lot.json") + " --recording " + path("noisy.csv") + " --out " + path("sn"));
  ASSERT_EQ(out.status, 0) << out.output;
  const nlohmann::json sn = read_json(dir_ / "sn" / "screen.json");
  EXPECT_TRUE(sn["out_of_family"].get<bool>());
  EXPECT_LT(sn["p_noise"].get<double>(), 1e-6);
  ASSERT_FALSE(sn["reasons"].empty());
  EXPECT_THAT(sn["reasons"].back().get<std::string>(), HasSubstr("noise: white"));

  // 200 samples of a single scan: the bias from the recording alone and with the lot's prior, against the truth's
  // -15 deg/h + 0.12 dT - 0.0025 dT^2 + 0.00004 dT^3 (dT = T - 25 C), summed over five temperatures.
  ASSERT_EQ(run("simulate --trajectory builtin:trajectories/single_scan.yaml --samples 200 --seed 11 --out " + path("short.csv")).status, 0);
  const Result with = run("calibrate --recording " + path("short.csv") + " --prior " + path("lot.json") + " --out " + path("with.json"));
  ASSERT_EQ(with.status, 0) << with.output;
  EXPECT_THAT(with.output, HasSubstr("share of each term's information from the recording (1) or the lot's prior (0): bias"));
  ASSERT_EQ(run("calibrate --recording " + path("short.csv") + " --model greybox --out " + path("alone.json")).status, 0);
  auto bias_error_dph = [&](const std::string& file) {
    const nlohmann::json p = read_json(path(file))["parameters"];
    double error = 0.0;
    for (double t : {-20.0, 0.0, 25.0, 40.0, 60.0}) {
      double b = p["bias_radps"].get<double>(), x = 1.0;
      for (double c : p["bias_temperature_radps"]["coefficients"]) b += c * x, x *= t - p["bias_temperature_radps"]["reference"].get<double>();
      const double dt = t - 25.0;
      error += std::abs(units::radps_to_dph(b) - (-15.0 + 0.12 * dt - 0.0025 * dt * dt + 0.00004 * dt * dt * dt));
    }
    return error;
  };
  EXPECT_LT(bias_error_dph("with.json"), 0.5 * bias_error_dph("alone.json"));
  // The fit under the prior carries its posterior: calibrate states the predictive sigma over the surface grid,
  // and surface reports it; its 95 % band covers about 95 % of |estimated - true| over the grid the model
  // spans (measured 96.1 %; a sigma off by a factor of two either way covers 68 % or 99.99 % of a Gaussian
  // error). Without the prior the model has no posterior, as before.
  EXPECT_THAT(with.output, HasSubstr("predictive sigma of the estimated error over the surface grid's nodes: rms"));
  const Result surface_with = run("surface --model " + path("with.json") + " --temp-range -20,60 --out " + path("sw"));
  ASSERT_EQ(surface_with.status, 0) << surface_with.output;
  EXPECT_THAT(surface_with.output, HasSubstr("predictive sigma rms"));
  EXPECT_NEAR(read_json(dir_ / "sw" / "surface.json")["sigma"]["coverage_95"].get<double>(), 0.95, 0.04);
  ASSERT_EQ(run("surface --model " + path("alone.json") + " --temp-range -20,60 --out " + path("sa")).status, 0);
  EXPECT_FALSE(read_json(dir_ / "sa" / "surface.json").contains("sigma"));
  // A 32-min recording against a lot of 62-min ones: screened, with the warning that the null is not its own.
  const Result other = run("lot screen --prior " + path("lot.json") + " --recording " + path("short.csv") + " --out " + path("ss"));
  EXPECT_THAT(other.output, HasSubstr("warning: the lot's null was calibrated on 62-min recordings and this one is 31.8 min"));
  EXPECT_TRUE(read_json(dir_ / "ss" / "screen.json")["out_of_family"].get<bool>());
  // The same units recorded on that short programme calibrate the null: the unit is then in family, unwarned.
  std::string short_recordings;
  for (int u = 1; u <= 8; ++u) {
    const std::string rec = path("short" + std::to_string(u) + ".csv");
    ASSERT_EQ(run("simulate --trajectory builtin:trajectories/single_scan.yaml --samples 200 --seed " + std::to_string(20 + u) + " --out " + rec).status, 0);
    short_recordings += " " + rec;
  }
  ASSERT_EQ(run("lot learn --recordings" + recordings + " --screen-recordings" + short_recordings + " --out " + path("lot_short.json")).status, 0);
  const Result own = run("lot screen --prior " + path("lot_short.json") + " --recording " + path("short.csv") + " --out " + path("ss2"));
  EXPECT_THAT(own.output, Not(HasSubstr("warning")));
  EXPECT_FALSE(read_json(dir_ / "ss2" / "screen.json")["out_of_family"].get<bool>()) << own.output;
  EXPECT_THAT(run("lot learn --recordings" + recordings + " --screen-recordings " + path("short1.csv") + " --out " + path("x.json")).output,
              HasSubstr("1 screening recordings for 8 units"));
  EXPECT_EQ(read_json(path("with.json"))["training"]["prior"], path("lot.json"));

  EXPECT_THAT(run("calibrate --recording " + path("short.csv") + " --prior " + path("lot.json") + " --model rbf --out " + path("x.json")).output,
              HasSubstr("--prior (a lot file) calibrates the greybox model, not --model rbf"));
  EXPECT_THAT(run("lot screen --prior builtin:priors/open_loop_fog_type.yaml --recording " + path("short.csv") + " --out " + path("x")).output,
              HasSubstr("builtin:priors/open_loop_fog_type.yaml: not a JSON lot file"));
  std::ofstream(path("plain.json")) << R"({"format": "gyrosid-prior/1", "members": []})";
  EXPECT_THAT(run("lot screen --prior " + path("plain.json") + " --recording " + path("short.csv") + " --out " + path("x")).output,
              HasSubstr("no 'population'"));
  EXPECT_THAT(run("lot learn --recordings " + path("short.csv") + " --models " + path("with.json") + " --out " + path("x.json")).output,
              HasSubstr("give exactly one of --recordings"));
}

// A lot as a session's prior with the grey-box model (issue 33): the designs take the lot's structure and count
// its population, and every calibration of the session is `calibrate --prior` with the lot - the final model is
// the one calibrate gives on the session's recording.
TEST_F(Cli, ASessionUnderALotCalibratesWithItsPopulation) {
  std::string recordings;
  ASSERT_NO_FATAL_FAILURE(simulate_units(5, 2000, recordings));
  ASSERT_EQ(run("lot learn --recordings" + recordings + " --out " + path("lot.json")).status, 0);
  const std::string session = "session --prior " + path("lot.json") + " --model greybox --truth builtin:priors/open_loop_fog_drift.yaml --budget-min 12 "
                              "--pilot-min 4 --envelope short --set global_evaluations=30 --set local_evaluations=20";
  const Result r = run(session + " --out " + path("s"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("its population as the calibration's prior"));
  EXPECT_EQ(read_json(dir_ / "s" / "session.json")["prior"]["calibration_prior"], path("lot.json"));
  EXPECT_THAT(read_text(dir_ / "s" / "calibration.yaml"), HasSubstr("gyrosid calibrate --recording rec.csv --prior " + path("lot.json")));
  const nlohmann::json model = read_json(dir_ / "s" / "model.json");
  EXPECT_EQ(model["training"]["prior"], path("lot.json"));
  ASSERT_EQ(run("calibrate --recording " + path("s/recording.csv") + " --prior " + path("lot.json") + " --out " + path("unit.json")).status, 0);
  EXPECT_EQ(model["parameters"], read_json(path("unit.json"))["parameters"]);
  EXPECT_THAT(run(session + " --calibration " + path("s/calibration.yaml") + " --out " + path("x")).output,
              HasSubstr("--calibration: with the lot " + path("lot.json") + " as --prior and --model greybox the calibration is the lot's"));
}

// A lot run killed (SIGKILL) at random points and resumed writes the same lot file, byte for byte; a batch of
// units screened at once gives each the same screen.json as its own run, and a table of them.
TEST_F(Cli, LotRunsResumeToTheSameBytesAndScreenInBatches) {
  std::string recordings;
  ASSERT_NO_FATAL_FAILURE(simulate_units(16, 3000, recordings));
  const std::string learn = "--quiet --threads 1 lot learn --recordings" + recordings;
  const int kills = kill_and_resume(learn, dir_ / "whole", dir_ / "killed", ".lot.json_checkpoint.json", 33, "lot.json");
  EXPECT_GE(kills, 1);
  EXPECT_EQ(read_text(dir_ / "killed" / "lot.json"), read_text(dir_ / "whole" / "lot.json"));
  // The lot's file does not depend on the threads that calibrated its units.
  ASSERT_EQ(run("--threads 2 lot learn --recordings" + recordings + " --out " + path("two.json")).status, 0);
  EXPECT_EQ(read_text(path("two.json")), read_text(dir_ / "whole" / "lot.json"));

  const std::string lot = (dir_ / "whole" / "lot.json").string();
  const Result batch = run("lot screen --prior " + lot + " --recording " + path("unit3.csv") + " " + path("unit5.csv") + " --out " + path("batch"));
  ASSERT_EQ(batch.status, 0) << batch.output;
  EXPECT_THAT(batch.output, HasSubstr("of 2 units out of family at alpha 0.01"));
  for (const char* unit : {"unit3", "unit5"}) {
    ASSERT_EQ(run("lot screen --prior " + lot + " --recording " + path(std::string(unit) + ".csv") + " --out " + path(unit)).status, 0);
    EXPECT_EQ(read_text(dir_ / "batch" / unit / "screen.json"), read_text(dir_ / unit / "screen.json")) << unit;
  }
  const std::string table = read_text(dir_ / "batch" / "screens.csv");
  EXPECT_EQ(std::count(table.begin(), table.end(), '\n'), 3);
  EXPECT_THAT(table, HasSubstr("\"" + path("unit5.csv") + "\","));
  EXPECT_FALSE(fs::exists(dir_ / "batch" / ".lot_screen_checkpoint.json"));
  EXPECT_THAT(run("lot screen --prior " + lot + " --recording " + path("unit3.csv") + " " + path("unit3.csv") + " --out " + path("x")).output,
              HasSubstr("would both be screened into"));
}

}  // namespace
}  // namespace gyrosid
