"""summary.md of the noisy-calibration experiment from its rows: medians over seeds, ratios to the Cramer-Rao
floor, the criterion of fit against the classical soak, coverage, time and memory, and the issue's targets."""
import os
import statistics

from gyrosid_experiments import fmt, write_text

PEERS = ["gp_sklearn", "krr_sklearn"]
NOT_CANDIDATES = {"crb_floor", "crb_oracle", "classical_scan", "classical_soak"}


def num(v):
    try:
        return float(v)
    except (TypeError, ValueError):
        return None


def cell(rows, metric, **key):
    """Median of `metric` over the rows matching key (over seeds), and how many there were."""
    vals = [num(r.get(metric)) for r in rows if all(r.get(k) == v for k, v in key.items())]
    vals = [v for v in vals if v is not None]
    return (statistics.median(vals), len(vals)) if vals else (None, 0)


def recording(r):
    return tuple(r[k] for k in ("sensor", "trajectory", "noise", "seed"))


def best_method(rows):
    """gyrosid's best configuration, chosen from the data: among the methods run on every recording that has
    a floor, the lowest median over recordings of held-out rms / floor. Returns (method, {method: median})."""
    floors = {recording(r): num(r["heldout_rms_dph"]) for r in rows if r["method"] == "crb_floor" and num(r.get("heldout_rms_dph"))}
    ratios = {}
    for r in rows:
        if r["method"] in NOT_CANDIDATES or r["method"].endswith("_sklearn") or recording(r) not in floors:
            continue
        if num(r.get("heldout_rms_dph")) is not None:
            ratios.setdefault(r["method"], {})[recording(r)] = num(r["heldout_rms_dph"]) / floors[recording(r)]
    medians = {m: statistics.median(v.values()) for m, v in ratios.items() if set(v) == set(floors)}
    return (min(medians, key=medians.get) if medians else "hybrid"), medians


def order(values, preferred):
    return [v for v in dict.fromkeys(preferred) if v in values] + sorted(v for v in values if v not in preferred)


def grid_table(rows, metric, sensor, trajectory, noises, methods):
    head = "| method | " + " | ".join(noises) + " |\n|---|" + "---|" * len(noises) + "\n"
    body = ""
    for m in methods:
        cells = []
        for n in noises:
            v, k = cell(rows, metric, sensor=sensor, trajectory=trajectory, noise=n, method=m)
            cells.append("" if v is None else fmt(v) + ("" if k >= 5 else " (%d)" % k))
        body += "| %s | %s |\n" % (m, " | ".join(cells))
    return head + body


def ratio_table(rows, sensor, trajectory, noises, methods):
    """Held-out rms of each method over the floor's, median over seeds."""
    head = "| method / floor | " + " | ".join(noises) + " |\n|---|" + "---|" * len(noises) + "\n"
    body = ""
    for m in methods:
        cells = []
        for n in noises:
            f, _ = cell(rows, "heldout_rms_dph", sensor=sensor, trajectory=trajectory, noise=n, method="crb_floor")
            v, _ = cell(rows, "heldout_rms_dph", sensor=sensor, trajectory=trajectory, noise=n, method=m)
            cells.append("" if v is None or not f else fmt(v / f))
        body += "| %s | %s |\n" % (m, " | ".join(cells))
    return head + body


def section_sensor(rows, sensor, cfg_noises, title, best):
    md = []
    trajectories = order({r["trajectory"] for r in rows if r["sensor"] == sensor and r["trajectory"] not in ("soak", "scaling")}, ["dual", "test_4x16"])
    for t in trajectories:
        noises = [n for n in cfg_noises if any(r["noise"] == n and r["trajectory"] == t and r["sensor"] == sensor for r in rows)]
        methods = order({r["method"] for r in rows if r["sensor"] == sensor and r["trajectory"] == t},
                        ["crb_floor", "crb_oracle", best, "hybrid", "hybrid_white", "default", "bayes", "ols", "lrols_loo", "ofs_loo", "nlopt", "ceres", "ipopt",
                         "classical_scan"] + PEERS)
        md.append("\n### %s, %s: surface rms (deg/h)\n\n" % (title, t) + grid_table(rows, "surface_rms_dph", sensor, t, noises, methods))
        md.append("\n### %s, %s: held-out rms (deg/h)\n\n" % (title, t) + grid_table(rows, "heldout_rms_dph", sensor, t, noises, methods))
        md.append("\n### %s, %s: held-out rms / Cramer-Rao floor\n\n" % (title, t) +
                  ratio_table(rows, sensor, t, noises, [m for m in methods if m != "crb_floor"]))
        cov = [m for m in methods if any(num(r.get("heldout_coverage_95")) is not None for r in rows if r["method"] == m and r["sensor"] == sensor)]
        md.append("\n### %s, %s: coverage of the 95 %% band on held-out data\n\n" % (title, t) +
                  grid_table(rows, "heldout_coverage_95", sensor, t, noises, cov))
    return md


def cof_section(rows, noises, best):
    md = ["\n## Criterion of fit (reference sensor, noise-free flights; m, long: after 1 h; medians over seeds)\n\n"]
    for n in noises:
        if not any(r["noise"] == n and r["method"] == "classical_soak" for r in rows):
            continue
        md.append("\n### %s\n\n| trained on | method | short | medium | long (1 h) |\n|---|---|---|---|---|\n" % n)
        for t in ["soak", "dual", "test_4x16"]:
            for m in order({r["method"] for r in rows if r["trajectory"] == t and r["sensor"] == "reference"},
                           ["classical_soak", "crb_oracle", best, "hybrid", "default", "bayes", "ols", "nlopt", "ceres", "classical_scan"]):
                vals = [cell(rows, k, sensor="reference", trajectory=t, noise=n, method=m)[0] for k in ("cof_short_m", "cof_medium_m", "cof_long_1h_m")]
                if any(v is not None for v in vals):
                    md.append("| %s | %s | %s |\n" % (t, m, " | ".join(fmt(v) if v is not None else "" for v in vals)))
    return md


def time_section(rows, best):
    md = ["\n## Time and memory (medians; reference sensor, white 10 deg/h)\n\n| trajectory | method | samples | time (s) | peak RSS (MB) | nodes |\n|---|---|---|---|---|---|\n"]
    for t in ["dual", "test_4x16"]:
        for m in order({r["method"] for r in rows if r["trajectory"] == t}, [best, "hybrid", "hybrid_white", "default", "bayes", "ols", "nlopt", "ceres"] + PEERS):
            key = dict(sensor="reference", trajectory=t, noise="white_10", method=m)
            tv = cell(rows, "time_s", **key)[0]
            if tv is None:
                continue
            md.append("| %s | %s | %s | %s | %s | %s |\n" % (t, m, fmt(cell(rows, "samples", **key)[0]), fmt(tv),
                                                            fmt(cell(rows, "peak_rss_mb", **key)[0]), fmt(cell(rows, "nodes", **key)[0])))
    scaling = [r for r in rows if r["trajectory"] == "scaling"]
    if scaling:
        md.append("\nAgainst N (test trajectory resampled, white 10 deg/h, one run each; the machine is shared):\n\n"
                  "| method | samples | time (s) | peak RSS (MB) | nodes |\n|---|---|---|---|---|\n")
        for r in sorted(scaling, key=lambda r: (r["method"], num(r["samples"]))):
            md.append("| %s | %s | %s | %s | %s |\n" % (r["method"], r["samples"], fmt(num(r["time_s"])), fmt(num(r["peak_rss_mb"])), r["nodes"]))
    return md


def per_seed(rows, metric, method, **key):
    return {r["seed"]: num(r.get(metric)) for r in rows if r["method"] == method and all(r.get(k) == v for k, v in key.items())}


def targets_section(rows, cfg, best):
    md = ["\n### `%s`\n\n" % best]
    # 1. Held-out rms at most 1.3 x the floor, and below both peers on every recording.
    worst, beaten, total, time_ratio = 0.0, 0, 0, []
    for r in rows:
        if r["method"] != best or num(r.get("heldout_rms_dph")) is None:
            continue
        key = {k: r[k] for k in ("sensor", "trajectory", "noise", "seed")}
        floor = per_seed(rows, "heldout_rms_dph", "crb_floor", **{k: v for k, v in key.items() if k != "seed"}).get(r["seed"])
        if floor:
            worst = max(worst, num(r["heldout_rms_dph"]) / floor)
        peers = [x for x in rows if x["method"] in PEERS and all(x.get(k) == v for k, v in key.items())]
        if peers:
            total += 1
            beaten += all(num(r["heldout_rms_dph"]) < num(p["heldout_rms_dph"]) and num(r["surface_rms_dph"]) < num(p["surface_rms_dph"]) for p in peers)
            time_ratio += [num(r["time_s"]) / num(p["time_s"]) for p in peers if num(p["time_s"])]
    md.append("- Held-out rms of `%s` over the Cramer-Rao floor: worst recording %s (target <= 1.3).\n" % (best, fmt(worst)))
    if total:
        md.append("- Beats GP and KernelRidge on surface and held-out rms on %d of %d recordings with peers; median time %s of theirs.\n" % (
            beaten, total, fmt(statistics.median(time_ratio)) if time_ratio else "?"))
    # 2. CoF on the dual scan at 10 deg/h against the classical soak.
    for flight, key in (("short", "cof_short_m"), ("medium", "cof_medium_m"), ("long", "cof_long_1h_m")):
        soak = per_seed(rows, key, "classical_soak", sensor="reference", trajectory="soak", noise="white_10")
        ours = per_seed(rows, key, best, sensor="reference", trajectory="dual", noise="white_10")
        seeds = sorted(s for s in set(soak) & set(ours) if soak[s] is not None and ours[s] is not None)
        if seeds:
            ratios = [soak[s] / ours[s] for s in seeds]
            md.append("- CoF %s, dual scan 10 deg/h: classical soak / %s = %s per seed (median %s; target %s).\n" % (
                flight, best, ", ".join(fmt(x) for x in ratios), fmt(statistics.median(ratios)), ">= 2" if flight != "long" else ">= 1"))
    # 3. Gauss-Markov against white at the same power.
    for t in ["dual", "test_4x16"]:
        w, _ = cell(rows, "surface_rms_dph", sensor="reference", trajectory=t, noise="white_10", method=best)
        wf, _ = cell(rows, "surface_rms_dph", sensor="reference", trajectory=t, noise="white_10", method="crb_floor")
        for n in [x["name"] for x in cfg["noises"] if x.get("gm_sigma_dph")]:
            g, _ = cell(rows, "surface_rms_dph", sensor="reference", trajectory=t, noise=n, method=best)
            gf, _ = cell(rows, "surface_rms_dph", sensor="reference", trajectory=t, noise=n, method="crb_floor")
            if w and g:
                md.append("- %s, %s: surface rms %s vs white 10 deg/h %s: ratio %s (target <= 2); the floors' ratio is %s.\n" % (
                    t, n, fmt(g), fmt(w), fmt(g / w), fmt(gf / wf) if gf and wf else "?"))
    # 4. Coverage.
    # Per recording the share inside the band is a fraction of a few effective samples (one smooth error draw
    # along the held-out trajectory): even the exact posterior (crb_oracle) scatters, so it is shown beside.
    recording = lambda r: tuple(str(r[k]) for k in ("sensor", "trajectory", "noise", "seed"))
    coverage = lambda m: {recording(r): num(r["heldout_coverage_95"]) for r in rows if r["method"] == m and num(r.get("heldout_coverage_95")) is not None}
    cov, oracle = coverage(best), coverage("crb_oracle")
    if cov:
        md.append("- 95 %% band coverage on held-out data, `%s`: mean %s, median %s, range %s-%s over %d recordings (target 0.93-0.97).\n" % (
            best, fmt(statistics.mean(cov.values())), fmt(statistics.median(cov.values())), fmt(min(cov.values())), fmt(max(cov.values())), len(cov)))
    common = [k for k in oracle if k in cov]
    if common:
        md.append("- The exact posterior of the true structure (crb_oracle) on the %d recordings it ran: coverage %s-%s, %d inside "
                  "0.93-0.97, mean %s; `%s` on the same recordings: mean %s.\n" % (
                      len(common), fmt(min(oracle[k] for k in common)), fmt(max(oracle[k] for k in common)),
                      sum(0.93 <= oracle[k] <= 0.97 for k in common), fmt(statistics.mean(oracle[k] for k in common)), best,
                      fmt(statistics.mean(cov[k] for k in common))))
    return md


def write_summary(out, rows, cfg, command, done):
    noises = [n["name"] for n in cfg["noises"]]
    md = ["# Noisy calibration at the statistical floor\n\n",
          "Generated by `%s`%s. Medians over seeds (a count in brackets where fewer than 5 seeds ran). Surface: estimated "
          "- true error over the grid (reference: -20..60 C x +-100 deg/s; sensor C: its (T, omega) grid); held-out: "
          "compensated - reference on a noise-free held-out trajectory. crb_floor: the expected rms of the efficient "
          "(Cramer-Rao) estimate of the true model along the same recording; crb_oracle: that estimate itself.\n" % (
              command, "" if done else " (partial: the sweep has not finished)")]
    runs = {}
    for r in rows:
        runs[str(r.get("run") or "earlier")] = runs.get(str(r.get("run") or "earlier"), 0) + 1
    if len(runs) > 1 or "earlier" in runs:
        md.append("\nRows by the run that produced them (the `run` column of rows.csv): %s.\n" % (
            "; ".join("%s: %d" % (k, v) for k, v in sorted(runs.items()))))
    best, medians = best_method(rows)
    md.append("\n## Targets (issue 11)\n\ngyrosid's best configuration, chosen by the median over recordings of held-out rms / floor "
              "among the methods run on every recording: `%s` (%s). The targets for it and for `hybrid` "
              "(builtin:calibration/rbf_noisy.yaml):\n" % (best, ", ".join("%s %s" % (m, fmt(v)) for m, v in sorted(medians.items(), key=lambda x: x[1]))))
    for method in dict.fromkeys([best, "hybrid"]):
        md += targets_section(rows, cfg, method)
    md.append("\n## Reference sensor\n")
    md += section_sensor(rows, "reference", noises, "reference", best)
    md += cof_section(rows, noises, best)
    md += time_section(rows, best)
    md.append("\n## Sensor C (independent generator)\n")
    md += section_sensor(rows, "C", [n["name"] for n in cfg["sensor_c"]["noises"]], "sensor C", best)
    write_text(os.path.join(out, "summary.md"), "".join(md))
