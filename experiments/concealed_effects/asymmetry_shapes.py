#!/usr/bin/env python3
"""Scale-factor asymmetry beside a flexible baseline on the independent generator (issue 34, class 5): an
asymmetry the baseline's scale-factor surface (or, at small rates, its polynomial) absorbs most of, run by one
or more gyrosid binaries on the same recordings.

The asymmetry is a step of the scale factor at zero rate, or a smooth transition over +-4 or +-20 deg/s (tanh).
Its size is the RMS of the effect less its mean ("raw"), in white-noise sigmas, so the part the baseline
cannot absorb (the `unabsorbed_sigma` of truth.json) is what is left, often a small fraction. It is planted
alone, beside an ageing trend, and at rates within +-15 deg/s (the baseline then a polynomial in T and omega).

Right: scale_factor_asymmetry named. Detected: named, or listed as an alternative the baseline absorbs (the
class's minimum: "reported as at least an ambiguity with the experiment that would separate it").

    asymmetry_shapes.py --gyrosid build/gyrosid --tag main --out /tmp/asym [--seeds 1]
"""
import argparse
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "lib"))
import independent_cases as ic  # noqa: E402

FORMS = {"step": 0.0, "tanh4": 4.0, "tanh20": 20.0}
MAGNITUDES = (0.5, 1.0)
# name: what else the recording has (rate_scale 0.15: rates within +-15 deg/s)
SETTINGS = {"alone": {}, "with_ageing": {"effects": [{"id": "aging_trend", "magnitude": 1.0}]}, "small_rates": {"rate_scale": 0.15}}


def jobs(out, seeds):
    for setting, extra in SETTINGS.items():
        for form, transition in FORMS.items():
            for m in MAGNITUDES:
                for seed in seeds:
                    sd = 7800 + seed + int(100 * m) + 10 * list(FORMS).index(form) + 1000 * list(SETTINGS).index(setting)
                    case = "%s@%s@%s" % (form, m, setting)
                    spec = {"effects": [{"id": "scale_factor_asymmetry", "magnitude": m, "size": "raw", "transition_dps": transition}]
                            + extra.get("effects", [])}
                    spec.update({k: v for k, v in extra.items() if k != "effects"})
                    yield {"generator": "independent", "group": "effect", "case": case, "seed": sd, "spec": spec,
                           "dir": os.path.join(out, "cases", case.replace("@", "_") + "_%d" % sd)}
    for seed in seeds:  # controls: the small-rate setting without an asymmetry (the others are the suite's controls)
        sd = 7790 + seed
        yield {"generator": "independent", "group": "control", "case": "control@small_rates", "seed": sd, "spec": {"rate_scale": 0.15},
               "dir": os.path.join(out, "cases", "control_small_rates_%d" % sd)}


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ic.add_binary_arguments(p)
    p.add_argument("--seeds", default="1", help="seeds per form, magnitude and setting (comma-separated)")
    a = p.parse_args()
    rows = []
    for job, truth, ex, row in ic.explained_rows(a.gyrosid, a.tag, jobs(a.out, [int(s) for s in a.seeds.split(",")])):
        asym = next((e for e in truth["effects"] if e["id"] == "scale_factor_asymmetry"), None)
        row["unabsorbed_sigma"] = asym["unabsorbed_sigma"] if asym else None
        row["absorbed"] = " ".join(sorted("%s/%s" % (x["id"], x["absorbed_by"]) for x in ex.get("absorbed_alternatives", [])))
        rows.append(row)
        print("%-24s %5d %-22s named %-40s absorbed %-40s unabsorbed %s %.1f s" % (
            job["case"], job["seed"], ex["verdict"], row["named"], row["absorbed"],
            "%.3f" % row["unabsorbed_sigma"] if asym else "-", ex["run_time_s"]), flush=True)
    keys = ["case", "seed", "verdict", "named", "absorbed", "correct", "detected", "wrong_extra", "unabsorbed_sigma",
            "heldout_excess_removed", "run_time_s"]
    ic.write_rows(os.path.join(a.out, a.tag + ".csv"), rows, keys)
    for setting in SETTINGS:
        g = [r for r in rows if r["case"].endswith("@" + setting)]
        print("%-12s named %d/%d, named or absorbed %d/%d, false discoveries %d" % (
            setting, sum(bool(r.get("correct")) for r in g), len(g), sum(bool(r.get("detected")) for r in g), len(g),
            sum(r.get("wrong_extra", 0) for r in g)))
    c = [r for r in rows if r["case"].startswith("control")]
    print("controls: %d named something, %d list an absorbed alternative" % (sum(bool(r["named"]) for r in c), sum(bool(r["absorbed"]) for r in c)))


if __name__ == "__main__":
    main()
