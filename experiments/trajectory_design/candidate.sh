#!/bin/bash
# A 62-min cof_minimax design against the dual scan, then its 10-seed predictor check (README, 2026-11-25 third
# session). Run under the experiment lock:
#   STAT=mse flock /tmp/gyrosid-exp.lock experiments/trajectory_design/candidate.sh NAME GYROSID [--set key=value ...]
# Writes results/selection/NAME/{trajectory.yaml,design.json,time.txt,check.txt}, results/predictor_check_NAME.json.
set -e
NAME=$1; BIN=$2; shift 2
STAT=${STAT:-mse}
EXP=$(cd "$(dirname "$0")" && pwd)
OUT=$EXP/results/selection/$NAME
mkdir -p "$OUT"
if [ ! -f "$OUT/trajectory.yaml" ]; then
  /usr/bin/time -f "%e s wall %U s user" -o "$OUT/time.txt" "$BIN" --quiet design --budget-min 62 --model hybrid \
    --envelope short,medium,long --solver ipopt --seed 1 --criterion cof_minimax --reference builtin:trajectories/dual_scan.yaml \
    --reference-statistic "$STAT" --set model.network_prior=evidence "$@" --out "$OUT" > "$OUT/stdout.txt"
fi
python3 "$EXP/predictor_check.py" "$BIN" dual_scan=builtin:trajectories/dual_scan.yaml "$NAME=$OUT/trajectory.yaml" \
  --seeds 1,2,3,4,5,6,7,8,9,10 --evaluation "evaluate_$NAME" --out "$EXP/results/predictor_check_$NAME.json" > "$OUT/check.txt" 2>&1
