#!/bin/bash
# The predictive sigma of `calibrate --prior` (issue 33, item 2) on held-out units: for each family and lot seed
# of run.py's prior part (cached under the work dir), the lot learned from its 50 training units' dual scans
# (greybox, shupe=true), then each held-out unit (50..59) calibrated from its 15-min recording under that prior
# and compared with its own truth by `gyrosid surface` over the model's grid, -20..60 C x -100..100 deg/s.
# The 15-min probe reaches -30..11.4 C: above 11 C the prior fills in. Prints, per family and temperature band,
# the rms of z = (estimated - true) / sigma and the 95 % band's coverage, and where calibrate put sigma's maximum.
#   experiments/production_lot/sigma_check.sh GYROSID [WORK] [SEEDS]   (after run.py --parts prior; about 12 min on 2 shared cores)
set -euo pipefail
g=$(realpath "$1"); work=${2:-/tmp/gyrosid-production-lot}; seeds=${3:-"1 2 3 4 5"}
out="$work/sigma_check"; mkdir -p "$out"
for fam in A B; do
  for s in $seeds; do
    lot="$work/$fam/lot$s"; train=()
    for u in $(seq 0 49); do train+=("$lot/u$(printf %05d "$u")/dual.csv"); done
    [ -f "$out/lot_${fam}$s.json" ] || "$g" --quiet lot learn --recordings "${train[@]}" --set shupe=true --out "$out/lot_${fam}$s.json" > /dev/null
    for u in $(seq 50 59); do
      f=$(printf %05d "$u"); d="$out/$fam/$s/$f"; mkdir -p "$d"
      "$g" --quiet calibrate --recording "$lot/u$f/short.csv" --prior "$out/lot_${fam}$s.json" --out "$d/model.json" > "$d/calibrate.txt"
      "$g" --quiet surface --model "$d/model.json" --sensor "$lot/u$f/sensor.yaml" --temp-range -20,60 --out "$d/surface" > /dev/null
    done
  done
done
/usr/bin/python3 - "$out" "$seeds" <<'PY'
import collections, csv, json, os, sys
import numpy as np
out, seeds = sys.argv[1], sys.argv[2].split()
bands = [(-20, 0), (0, 11.5), (11.5, 30), (30, 60)]
for fam in "AB":
    z = collections.defaultdict(list)
    where = collections.Counter()
    units = 0
    for s in seeds:
        for u in range(50, 60):
            d = os.path.join(out, fam, s, "%05d" % u)
            units += 1
            for row in csv.DictReader(open(os.path.join(d, "surface", "surface.csv"))):
                t = float(row["temp_c"])
                band = next(b for b in bands if b[0] <= t <= b[1])
                z[band].append((float(row["difference_dph"]) / float(row["sigma_dph"]), float(row["sigma_dph"])))
            ps = json.load(open(os.path.join(d, "model.json")))["summary"]["details"]["predictive_sigma"]
            where["%g C, %g deg/s" % (ps["max_at_temp_c"], ps["max_at_rate_dps"])] += 1
    print("family %s, %d held-out units; sigma's maximum over the grid's nodes at: %s" % (fam, units, dict(where.most_common(4))))
    for b in bands:
        a = np.array(z[b])
        print("  T in [%g, %g] C: rms z %.2f, 95 %% band covers %.1f %%, median sigma %.3g deg/h" % (
            b[0], b[1], np.sqrt(np.mean(a[:, 0] ** 2)), 100 * np.mean(np.abs(a[:, 0]) <= 1.96), np.median(a[:, 1])))
PY
