#!/usr/bin/env bash
# Fuzzes every reader of outside input (tests/fuzz/fuzz_targets.cpp) with libFuzzer, under AddressSanitizer
# and UndefinedBehaviorSanitizer:
#
#   scripts/fuzz.sh [seconds-per-target] [target ...]     # default 600 s each, every target
#
# Builds with `scripts/setup.sh fuzz` (installs clang if missing). The corpus of each target starts from its
# seeds (configs/, tests/fuzz/seeds/) and its recorded regressions, grows in build-fuzz/corpus/<target>/ and is
# kept between runs. A crash is written to build-fuzz/crashes/<target>/; fix it, then copy the input into
# tests/fuzz/regressions/<target>/ so the ordinary test suite replays it for ever. Exit status 1 when any
# target crashed. Prints the seconds fuzzed and the executions per target.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-600}"
shift || true
all=(recording sensor_config trajectory_config calibration_config flight_config model_json flight_csv kalibr_csv ros_csv imu_tk ulog rosbag)
targets=("${@:-${all[@]}}")
[ ${#targets[@]} -eq 0 ] && targets=("${all[@]}")

build="${GYROSID_BUILD_DIR:-build-fuzz}"
[ "${GYROSID_FUZZ_NO_BUILD:-0}" = 1 ] || scripts/setup.sh fuzz   # GYROSID_FUZZ_NO_BUILD=1: use the build as it is

seeds_of() {
  case "$1" in
    recording) echo tests/fuzz/seeds/recording/* ;;
    sensor_config) echo configs/sensors/*.yaml ;;
    trajectory_config) echo configs/trajectories/*.yaml ;;
    calibration_config) echo configs/calibration/*.yaml ;;
    flight_config) echo tests/fuzz/seeds/flight_config/* ;;
    model_json) echo tests/fuzz/seeds/model_json/* ;;
    flight_csv) echo tests/fuzz/seeds/flight_csv/* ;;
    kalibr_csv|ros_csv|imu_tk|ulog|rosbag) echo tests/fuzz/seeds/"$1"/* ;;
  esac
}

status=0
for t in "${targets[@]}"; do
  if [ ! -x "$build/tests/fuzz/fuzz_$t" ]; then  # rosbag: only with the ROS 1 bag library
    echo "fuzz: $t is not built here, skipped" >&2
    continue
  fi
  corpus="$build/corpus/$t"
  crashes="$build/crashes/$t"
  mkdir -p "$corpus" "$crashes"
  # shellcheck disable=SC2046
  cp -n $(seeds_of "$t") "$corpus"/ 2>/dev/null || true
  [ -d "tests/fuzz/regressions/$t" ] && cp -n tests/fuzz/regressions/"$t"/* "$corpus"/ 2>/dev/null || true
  log="$build/fuzz_$t.log"
  echo "fuzz: $t for $seconds s (log $log)" >&2
  if ! "$build/tests/fuzz/fuzz_$t" "$corpus" -max_total_time="$seconds" -max_len=65536 -rss_limit_mb=4096 -timeout=30 \
        -artifact_prefix="$crashes/" -print_final_stats=1 > "$log" 2>&1; then
    echo "fuzz: $t CRASHED - see $log and $crashes/" >&2
    status=1
  fi
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  echo "fuzz: $t done: $execs executions, corpus $(ls "$corpus" | wc -l) inputs" >&2
done
exit $status
