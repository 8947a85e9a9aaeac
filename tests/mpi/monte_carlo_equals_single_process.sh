#!/usr/bin/env bash
# `mpirun -np 2 gyrosid-mpi cof --monte-carlo` writes the same cof.json, byte for byte, as `gyrosid cof` on one
# process - for a fixed number of runs and for the automatic (Anderson-Darling) stop.
#   tests/mpi/monte_carlo_equals_single_process.sh <gyrosid> <gyrosid-mpi> <mpirun>
set -euo pipefail
gyrosid=$1 gyrosid_mpi=$2 mpirun=$3
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
# Under the sanitizer (scripts/setup.sh sanitize): OpenMPI's plugins have no frame pointers, so LeakSanitizer's
# fast unwinder stops inside them and the suppressions of tests/sanitize/lsan.supp never see libmpi's frames
# (its start-up allocations were reported as leaks of an unknown module); unwind fully on malloc instead.
if [ -n "${ASAN_OPTIONS:-}" ]; then export ASAN_OPTIONS="$ASAN_OPTIONS:fast_unwind_on_malloc=0"; fi
for mc in 96 auto; do
  args="--quiet cof --model none --trajectory short --monte-carlo $mc --seed 5"
  "$gyrosid" --threads 1 $args --out "$dir/single_$mc" > /dev/null
  "$mpirun" -np 2 "$gyrosid_mpi" $args --out "$dir/mpi_$mc" > "$dir/mpi_$mc.log" 2>&1 || { cat "$dir/mpi_$mc.log"; exit 1; }
  if ! cmp "$dir/single_$mc/cof.json" "$dir/mpi_$mc/cof.json"; then
    diff "$dir/single_$mc/cof.json" "$dir/mpi_$mc/cof.json" | head -20
    exit 1
  fi
  echo "monte carlo $mc: identical"
done
