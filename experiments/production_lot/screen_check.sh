#!/bin/bash
# Screening as a production line would run it (issue 33), on lot 100 of run.py's screening part (N units per
# family, default 200, 2 % planted defects, cached under the work dir): the lot learned from the 50 training units' dual
# scans with the same units' 15-min recordings as the null's (`lot learn --screen-recordings`), then every
# other unit's 15-min recording screened at the default alpha. Prints false alarms and each defect's verdict.
# Every clean unit's z of the conditional Shupe test (lot_model.h) is printed too (mean and sd over the clean units),
# with the test's threshold at alpha / (2 x its physics tests) (screen.cpp's Bonferroni) under the lot's null and under the clean units' own
# |z| (the null known exactly): how many doubled-Shupe units each would flag, so that a miss can be told the null's
# or the statistic's.
#   experiments/production_lot/screen_check.sh GYROSID [WORK [OUT [N]]]   (after run.py --parts screen [--screen-units N])
set -euo pipefail
g=$(realpath "$1"); work=${2:-/tmp/gyrosid-production-lot}
out=${3:-$work/screen_check}; n=${4:-200}; mkdir -p "$out"
for fam in A B; do
  lot="$work/$fam/lot100_n$n"; train=(); short=()
  for u in $(seq 0 49); do f=$(printf %05d "$u"); train+=("$lot/u$f/dual.csv"); short+=("$lot/u$f/short.csv"); done
  "$g" --quiet lot learn --recordings "${train[@]}" --screen-recordings "${short[@]}" --set shupe=true --out "$out/lot_$fam.json"
  screened=()
  for u in $(seq 50 $((n - 1))); do f=$(printf %05d "$u"); screened+=("$lot/u$f/short.csv"); done
  [ -f "$out/$fam/screens.csv" ] || "$g" --quiet lot screen --prior "$out/lot_$fam.json" --recording "${screened[@]}" --out "$out/$fam" > /dev/null
done
/usr/bin/python3 - "$work" "$out" "$n" <<'PY'
import json, os, sys
import numpy as np
from scipy import stats
work, out, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
for fam in "AB":
    defects = {int(k): v for k, v in json.load(open(os.path.join(work, fam, "lot100_n%d" % n, "defects.json"))).items()}
    alarms = clean = 0
    z, planted = [], []
    for u in range(50, n):
        j = json.load(open(os.path.join(out, fam, "u%05d" % u, "short", "screen.json")))
        cond = j["tests"].get("shupe given the rest", {})
        if u in defects and defects[u] == "shupe_doubled" and "z" in cond:
            planted.append(cond["z"])
        if u in defects:
            print(fam, u, defects[u], "flagged" if j["out_of_family"] else "missed", "p = %.3g" % j["p_value"],
                  "shupe|rest z = %.3g" % cond.get("z", float("nan")), (j["reasons"] or ["-"])[0])
        else:
            clean += 1
            alarms += j["out_of_family"]
            if "z" in cond:
                z.append(cond["z"])
    print(fam, "false alarms: %d / %d = %.1f %%" % (alarms, clean, 100.0 * alarms / clean))
    if z:
        m = sum(z) / len(z)
        print(fam, "clean units' shupe|rest z: mean %.2f, sd %.2f" % (m, (sum((x - m) ** 2 for x in z) / (len(z) - 1)) ** 0.5))
        screening = json.load(open(os.path.join(out, "lot_%s.json" % fam)))["population"]["screening"]
        null = [t for t in screening["tests"] if "term" in t][0]
        level = 0.01 / (2 * (len(screening["tests"]) + ("misfit" in screening)))
        by_null = float(np.sqrt(null["scale"] * stats.chi2.ppf(1 - level, null["dof"])))
        exact = float(np.quantile(np.abs(z), 1 - level))
        beyond = lambda t: sum(abs(x) > t for x in planted)
        print(fam, "shupe|rest at %.3g: the lot's null |z| > %.2f (clean units beyond it %.2f %%) flags %d / %d doubled; "
              "the clean units' own |z| > %.2f flags %d / %d" % (level, by_null, 100.0 * np.mean(np.abs(z) > by_null), beyond(by_null),
                                                                 len(planted), exact, beyond(exact), len(planted)))
PY
