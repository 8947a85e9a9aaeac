"""The Python bindings against the command and against known truths: same seed, same numbers as `gyrosid`;
a planted bias recovered; models saved by Python loaded by the command's reader and back."""
import json
import os
import subprocess
import tempfile
import unittest

import numpy as np

import gyrosid

BUILD_PYTHON = next(p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p)
GYROSID = os.path.join(os.path.dirname(os.path.abspath(BUILD_PYTHON)), "gyrosid")


def run_gyrosid(*args):
    """The command beside the bindings. Without the interpreter's LD_PRELOAD: in the sanitizer job that preloads
    the sanitizer's runtime for the extension, and the command, which carries its own, must not be given a second."""
    env = {k: v for k, v in os.environ.items() if k != "LD_PRELOAD"}
    subprocess.run([GYROSID, "--quiet", *args], check=True, capture_output=True, env=env)


class Bindings(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.dir.cleanup()

    def path(self, name):
        return os.path.join(self.dir.name, name)

    def test_simulate_equals_the_command(self):
        rec = gyrosid.simulate(trajectory="builtin:trajectories/dual_scan.yaml", seed=3, samples=500)
        run_gyrosid("simulate", "--trajectory", "builtin:trajectories/dual_scan.yaml", "--seed", "3",
                    "--samples", "500", "--out", self.path("cli.csv"))
        cli = gyrosid.Recording.load(self.path("cli.csv"))
        self.assertEqual(len(rec), 500)
        for name in ("t_s", "ref_rate_dps", "temp_c", "gyro_dps"):
            np.testing.assert_array_equal(rec[name], cli[name])

    def test_recording_from_numpy_checks_the_format(self):
        t = np.arange(5.0)
        rec = gyrosid.Recording({"t_s": t, "ref_rate_dps": t, "temp_c": 20 + t, "gyro_dps": t + 1e-3})
        self.assertEqual(rec.names, ["t_s", "ref_rate_dps", "temp_c", "gyro_dps"])
        with self.assertRaisesRegex(gyrosid.Error, "t_s"):
            gyrosid.Recording({"t_s": t[::-1].copy(), "ref_rate_dps": t, "temp_c": t, "gyro_dps": t})
        with self.assertRaisesRegex(gyrosid.Error, "missing required column 'gyro_dps'"):
            gyrosid.Recording({"t_s": t, "ref_rate_dps": t, "temp_c": t})

    def test_classical_recovers_a_planted_bias_and_compensates(self):
        # A gyro whose only error is a bias of 36 deg/h (0.01 deg/s): the classical model finds it.
        t = np.arange(2000.0)
        rate = 50 * np.sin(t / 40.0)
        temp = -20 + 80 * t / t[-1]
        rec = gyrosid.Recording({"t_s": t, "ref_rate_dps": rate, "temp_c": temp, "gyro_dps": rate + 0.01})
        model = gyrosid.calibrate(rec, model="classical", options={"bias_order": 1, "sf_temperature_order": 1, "sf_rate_order": 1})
        self.assertEqual(model.kind, "classical")
        self.assertEqual(model.summary["termination"], "converged")
        x = np.column_stack([np.radians(rate[:10]), temp[:10]])
        np.testing.assert_allclose(np.degrees(model.predict(x)), 0.01, atol=1e-9)
        compensated = gyrosid.compensate(model, rec)
        np.testing.assert_allclose(compensated["compensated_dps"], rate, atol=1e-9)

    def test_models_round_trip_through_the_commands_files(self):
        rec = gyrosid.simulate(seed=2, samples=800)
        model = gyrosid.calibrate(rec, model="rbf", solver="ols", options={"width": 0.3, "max_nodes": 30})
        model.save(self.path("m.json"))
        rec.save(self.path("r.csv"))
        # The command reads the Python model; its compensation equals the in-process one.
        run_gyrosid("compensate", "--model", self.path("m.json"), "--recording", self.path("r.csv"),
                    "--out", self.path("c.csv"))
        cli = gyrosid.Recording.load(self.path("c.csv"))["compensated_dps"]
        np.testing.assert_array_equal(cli, gyrosid.compensate(model, rec)["compensated_dps"])
        back = gyrosid.load_model(self.path("m.json"))
        self.assertEqual(json.loads(back.to_json())["parameters"], json.loads(model.to_json())["parameters"])

    @staticmethod
    def untimed(path):
        """A model file's JSON without its recording path and the solves' times and memory."""
        def strip(x):
            if isinstance(x, dict):
                return {k: strip(v) for k, v in x.items() if k not in ("time_s", "peak_rss_mb", "recording")}
            return [strip(v) for v in x] if isinstance(x, list) else x
        with open(path) as f:
            return strip(json.load(f))

    def test_a_triad_model_is_a_model_like_any_other(self):
        # The triad's fit, saved as its file, loads as a Model that compensates, scores and exports as the
        # commands do with the same file.
        run_gyrosid("simulate", "--sensor", "builtin:sensors/fog_triad.yaml", "--trajectory",
                    "builtin:trajectories/triad_six_position.yaml", "--seed", "2", "--out", self.path("six.csv"))
        rec = gyrosid.Recording.load(self.path("six.csv"))
        with open(self.path("triad.json"), "w") as f:
            json.dump(gyrosid.calibrate_triad(rec, {"surfaces": "classical"}), f)
        model = gyrosid.load_model(self.path("triad.json"))
        self.assertEqual((model.kind, model.gyros), ("triad", 3))
        with self.assertRaisesRegex(gyrosid.Error, "triad model of 3 gyros"):
            model.features
        # calibrate(model="triad") is the same fit as the command's and calibrate_triad's; its Model saves the
        # file the command writes (the fit's sigmas beside the values), and a loaded Model saves it again.
        fitted = gyrosid.calibrate(rec, model="triad", options={"surfaces": "classical"})
        self.assertEqual((fitted.kind, fitted.gyros), ("triad", 3))
        run_gyrosid("calibrate", "--model", "triad", "--recording", self.path("six.csv"), "--set", "surfaces=classical",
                    "--out", self.path("cli_triad.json"))
        fitted.save(self.path("py_triad.json"))
        untimed = [self.untimed(self.path(p)) for p in ("py_triad.json", "cli_triad.json", "triad.json")]
        self.assertEqual(untimed[0], untimed[1])
        self.assertEqual(untimed[0], untimed[2])
        self.assertIn("sigma", untimed[0]["misalignment"])
        model.save(self.path("resaved.json"))
        with open(self.path("triad.json")) as a, open(self.path("resaved.json")) as b:
            self.assertEqual(json.load(a), json.load(b))
        run_gyrosid("compensate", "--model", self.path("triad.json"), "--recording", self.path("six.csv"),
                    "--out", self.path("c.csv"))
        cli = gyrosid.Recording.load(self.path("c.csv"))
        mine = gyrosid.compensate(model, rec)
        for axis in "xyz":
            np.testing.assert_array_equal(mine["compensated_%s_dps" % axis], cli["compensated_%s_dps" % axis])
        raw = np.concatenate([rec["gyro_%s_dps" % a] - rec["ref_rate_%s_dps" % a] for a in "xyz"])
        left = np.concatenate([mine["compensated_%s_dps" % a] - rec["ref_rate_%s_dps" % a] for a in "xyz"])
        self.assertLess(np.sqrt(np.mean(left ** 2)), 0.5 * np.sqrt(np.mean(raw ** 2)))  # misalignment and biases removed
        run_gyrosid("cof", "--model", self.path("triad.json"), "--sensor", "builtin:sensors/fog_triad.yaml",
                    "--trajectory", "short", "--out", self.path("cof"))
        with open(os.path.join(self.path("cof"), "cof.json")) as f:
            cli_cof = json.load(f)
        self.assertEqual(gyrosid.cof(model, trajectory="short", sensor="builtin:sensors/fog_triad.yaml")["end_error_m"],
                         cli_cof["end_error_m"])
        model.export_c(self.dir.name, "imu")
        with open(self.path("imu.h")) as f:
            self.assertIn("imu_compensate(", f.read())

    def test_allan_finds_the_white_noise(self):
        # White noise of 10 deg/h at 1 Hz: N = 10/60 deg/sqrt(h).
        rng = np.random.default_rng(4)
        fit = gyrosid.allan(10.0 * rng.standard_normal(36000), 1.0)
        self.assertAlmostEqual(fit["arw_deg_rt_h"], 10.0 / 60.0, delta=0.01)
        self.assertEqual(len(fit["tau_s"]), len(fit["adev_dph"]))

    def test_criterion_of_fit_truth_and_raw(self):
        truth = gyrosid.cof("truth", trajectory="short")
        raw = gyrosid.cof(None, trajectory="short")
        self.assertLess(truth["end_error_m"], 1e-9)
        self.assertGreater(raw["end_error_m"], 1.0)

    def test_design_fits_the_budget_improves_and_simulates(self):
        opts = {"space.segments": 2, "global_evaluations": 60, "local_evaluations": 40}
        yaml_text, d = gyrosid.design(8, model="classical", envelope=["short"], seed=4, options=opts)
        self.assertAlmostEqual(d["duration_min"], 8.0, places=9)
        self.assertLessEqual(d["objective"], d["solver_summary"]["initial_cost"])
        self.assertGreater(d["predicted"]["flights"]["short"]["cof_m"], 0.0)
        again, _ = gyrosid.design(8, model="classical", envelope=["short"], seed=4, options=opts)
        self.assertEqual(yaml_text, again)  # same seed, same design
        with open(self.path("trajectory.yaml"), "w") as f:
            f.write(yaml_text)
        rec = gyrosid.simulate(trajectory=self.path("trajectory.yaml"), seed=1)
        self.assertEqual(len(rec["t_s"]), 8 * 60 * 3)  # 8 min at the design's 3 Hz
        with self.assertRaises(ValueError):
            gyrosid.design(8, options={"no_such_option": 1})

    def test_design_is_the_commands_job_cof_minimax_included(self):
        # One job behind both: the same inputs give the same programme and the same design.json, the equipment's
        # limits and cof_minimax's reference included (the bindings once had a design of their own without them).
        ref = "builtin:trajectories/single_scan.yaml"
        opts = {"space.segments": 2, "global_evaluations": 60, "local_evaluations": 40}
        yaml_text, d = gyrosid.design(8, model="classical", envelope=["short"], seed=4, criterion="cof_minimax", reference=ref, options=opts)
        run_gyrosid("design", "--envelope", "short", "--model", "classical", "--budget-min", "8", "--seed", "4", "--criterion", "cof_minimax",
                    "--reference", ref, "--set", "space.segments=2", "--set", "global_evaluations=60", "--set", "local_evaluations=40",
                    "--out", self.path("d"))
        with open(self.path("d/trajectory.yaml")) as f:
            self.assertEqual(yaml_text, f.read())
        with open(self.path("d/design.json")) as f:
            cli = json.load(f)
        self.assertEqual(d["provenance"]["reference"], cli["provenance"]["reference"])
        self.assertEqual(d["predicted"], cli["predicted"])
        self.assertEqual(d["objective"], cli["objective"])

    def test_surface_is_the_commands_job(self):
        # The same job as `gyrosid surface`: the same surface.json; the arrays are its grid, and their difference
        # gives its statistics.
        model = gyrosid.calibrate(gyrosid.simulate(samples=1500, seed=2), model="classical")
        model.save(self.path("m.json"))
        s = gyrosid.surface(self.path("m.json"), temp_range_c=(0, 40), points=(11, 21))
        run_gyrosid("surface", "--model", self.path("m.json"), "--temp-range", "0,40", "--points", "11,21", "--out", self.path("s"))
        with open(self.path("s/surface.json")) as f:
            self.assertEqual(s["summary"], json.load(f))
        self.assertEqual(s["estimated_dph"].shape, (11, 21))
        self.assertAlmostEqual(s["temps_c"][-1], 40.0)
        diff = s["estimated_dph"] - s["true_dph"]
        self.assertAlmostEqual(np.sqrt(np.mean(diff ** 2)), s["summary"]["difference"]["rms_dph"], places=9)
        self.assertIsNone(s["sigma_dph"])
        with self.assertRaises(ValueError):
            gyrosid.surface(self.path("m.json"), points=(1, 21))

    def test_session_is_the_commands_job_and_resumes_across_them(self):
        # One job behind both, one fingerprint of the inputs: a lab session started in Python is resumed by the
        # command and finished in Python, and ends as the simulated session of the command does.
        with open(self.path("two.yaml"), "w") as f:
            f.write("format: gyrosid-prior/1\nname: two\nmembers:\n  - {sensor: builtin:sensors/open_loop_fog.yaml}\n"
                    "  - {sensor: builtin:priors/open_loop_fog_drift.yaml}\n")
        truth = "builtin:priors/open_loop_fog_drift.yaml"
        opts = {"space.segments": 2, "global_evaluations": 30, "local_evaluations": 20}
        cli = ["session", "--prior", self.path("two.yaml"), "--budget-min", "12", "--pilot-min", "4", "--envelope", "short",
               "--model", "classical", "--seed", "4"] + [a for k, v in opts.items() for a in ("--set", "%s=%s" % (k, v))]
        run_gyrosid(*cli, "--truth", truth, "--out", self.path("sim"))
        lab = dict(prior=self.path("two.yaml"), out=self.path("lab"), budget_min=12, pilot_min=4, envelope=["short"], model="classical",
                   options=opts, seed=4)
        first = gyrosid.session(**lab)
        self.assertEqual((first["segments_done"], first["segments"]), (0, 2))
        self.assertEqual(first["waiting_for"], self.path("lab/segment_1/recording.csv"))
        self.assertIsNone(first["model"])
        for k in ("1", "2"):
            with open(self.path("sim/segment_%s/trajectory.yaml" % k)) as a, open(self.path("lab/segment_%s/trajectory.yaml" % k)) as b:
                self.assertEqual(a.read(), b.read())
            with open(self.path("sim/segment_%s/recording.csv" % k)) as a, open(self.path("lab/segment_%s/recording.csv" % k), "w") as b:
                b.write(a.read())
            if k == "1":
                run_gyrosid(*cli, "--out", self.path("lab"), "--resume")  # the command takes the session on
        done = gyrosid.session(**lab, resume=True)
        self.assertEqual(done["session"]["status"], "complete")
        self.assertEqual(done["model"], self.path("lab/model.json"))
        with open(self.path("sim/recording.csv")) as a, open(self.path("lab/recording.csv")) as b:
            self.assertEqual(a.read(), b.read())
        with self.assertRaises(ValueError):  # other inputs: refused, naming the fingerprint
            gyrosid.session(**dict(lab, pilot_min=5), resume=True)

    def test_auto_calibrate_is_the_commands_preset_choice(self):
        # model="auto" is `gyrosid calibrate` without --model: the same job, the same preset and model, on a noisy
        # recording and on a noise-free one (which takes the interpolating network).
        for name, rec in (("noisy", gyrosid.simulate(samples=1500, seed=2)), ("clean", gyrosid.simulate(samples=800, seed=2, noise_free=True))):
            rec.save(self.path(name + ".csv"))
            model = gyrosid.calibrate(rec, model="auto")
            run_gyrosid("calibrate", "--recording", self.path(name + ".csv"), "--out", self.path(name + ".json"))
            with open(self.path(name + ".json")) as f:
                cli = json.load(f)
            model.save(self.path(name + "_py.json"))
            with open(self.path(name + "_py.json")) as f:
                mine = json.load(f)
            self.assertEqual(mine["parameters"], cli["parameters"])
            self.assertEqual(mine["training"]["preset"], cli["training"]["preset"])
            self.assertEqual(mine["training"]["preset"]["chosen"].endswith("noise_free.yaml"), name == "clean")
        with self.assertRaises(ValueError):
            gyrosid.calibrate(rec, model="auto", options={"width": 0.3})

    def test_lot_learn_screen_and_calibrate_are_the_commands_jobs(self):
        # The same jobs as `gyrosid lot learn`, `lot screen` and `calibrate --prior`: the same lot file, screen.json
        # and model; the lot's white noise is the simulated sensor's, 10 dph at 1 Hz.
        units = []
        for u in range(1, 8):
            gyrosid.simulate(samples=2000, seed=u).save(self.path("u%d.csv" % u))
            units.append(self.path("u%d.csv" % u))
        learned = gyrosid.lot_learn(self.path("lot.json"), recordings=units[:6], options={"lot.max_modes": 2}, name="six")
        run_gyrosid("lot", "learn", "--recordings", *units[:6], "--set", "lot.max_modes=2", "--name", "six", "--out", self.path("cli.json"))
        with open(self.path("cli.json")) as f:
            self.assertEqual(learned["file"], json.load(f))
        self.assertEqual(learned["units"], 6)
        self.assertLessEqual(learned["modes"], 2)
        self.assertAlmostEqual(np.exp(learned["file"]["population"]["noise"]["white_dph_at_1hz"]["log_mean"]), 10.0, delta=1.0)
        screens = gyrosid.lot_screen(self.path("lot.json"), [units[6], units[0]], self.path("s"))
        run_gyrosid("lot", "screen", "--prior", self.path("lot.json"), "--recording", units[6], units[0], "--out", self.path("cs"))
        for screen, name in zip(screens, ("u7", "u1")):
            with open(self.path("cs/%s/screen.json" % name)) as f:
                self.assertEqual(screen, json.load(f))
            self.assertEqual(set(screen), set(screen) | {"out_of_family", "p_value", "reasons"})
        unit = gyrosid.calibrate(gyrosid.Recording.load(units[6]), model="greybox", prior=self.path("lot.json"))
        unit.save(self.path("unit.json"))
        run_gyrosid("calibrate", "--recording", units[6], "--prior", self.path("lot.json"), "--out", self.path("cli_unit.json"))
        with open(self.path("unit.json")) as a, open(self.path("cli_unit.json")) as b:
            self.assertEqual(json.load(a)["parameters"], json.load(b)["parameters"])
        with self.assertRaises(ValueError):  # a lot option that is none, named
            gyrosid.lot_learn(self.path("x.json"), recordings=units[:6], options={"lot.bogus": 1})
        with self.assertRaises(ValueError):
            gyrosid.calibrate(gyrosid.Recording.load(units[6]), model="rbf", prior=self.path("lot.json"))


if __name__ == "__main__":
    unittest.main()
