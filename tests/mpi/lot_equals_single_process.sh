#!/usr/bin/env bash
# `mpirun -np 2 gyrosid-mpi lot learn` and `lot screen` of several units write the same files, byte for byte,
# as `gyrosid` on one process: each unit is calibrated from its own recording alone, wherever it runs.
#   tests/mpi/lot_equals_single_process.sh <gyrosid> <gyrosid-mpi> <mpirun>
set -euo pipefail
gyrosid=$1 gyrosid_mpi=$2 mpirun=$3
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
if [ -n "${ASAN_OPTIONS:-}" ]; then export ASAN_OPTIONS="$ASAN_OPTIONS:fast_unwind_on_malloc=0"; fi  # as monte_carlo_equals_single_process.sh
recordings=()
for u in 1 2 3 4 5 6 7 8 9 10 11; do
  "$gyrosid" --quiet simulate --samples 2000 --seed "$u" --out "$dir/unit$u.csv" > /dev/null
  recordings+=("$dir/unit$u.csv")
done
learn=(--quiet lot learn --set shupe=true --recordings "${recordings[@]:0:9}")  # Shupe: its conditional test too
screen=(--quiet lot screen --recording "${recordings[@]:8}")
"$gyrosid" --threads 1 "${learn[@]}" --out "$dir/single/lot.json" > /dev/null
"$mpirun" -np 2 "$gyrosid_mpi" "${learn[@]}" --out "$dir/mpi/lot.json" > "$dir/mpi_learn.log" 2>&1 || { cat "$dir/mpi_learn.log"; exit 1; }
cmp "$dir/single/lot.json" "$dir/mpi/lot.json"
echo "lot learn: identical"
"$gyrosid" --threads 1 "${screen[@]}" --prior "$dir/single/lot.json" --out "$dir/single/screens" > /dev/null
"$mpirun" -np 2 "$gyrosid_mpi" "${screen[@]}" --prior "$dir/single/lot.json" --out "$dir/mpi/screens" > "$dir/mpi_screen.log" 2>&1 || { cat "$dir/mpi_screen.log"; exit 1; }
diff -r "$dir/single/screens" "$dir/mpi/screens"
echo "lot screen: identical"
