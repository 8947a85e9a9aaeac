#!/usr/bin/env bash
# gyrosid's own set-up script: installs the Debian 12 packages that are missing (and only those),
# configures and builds gyrosid (Release), then runs one job:
#
#   scripts/setup.sh main   # the main job on the built-in default configuration, report in ./report/
#   scripts/setup.sh test   # every test, through ctest
#   scripts/setup.sh build  # install and build only
#
# Idempotent: a second run installs nothing and rebuilds only what changed. Nothing is downloaded from
# outside Debian's package archive.
set -euo pipefail

job="${1:-}"
case "$job" in
  main|test|build) ;;
  *) echo "usage: scripts/setup.sh main|test|build" >&2; exit 2 ;;
esac

cd "$(dirname "$0")/.."

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libsuitesparse-dev libceres-dev libnlopt-cxx-dev coinor-libipopt-dev
  libyaml-cpp-dev nlohmann-json3-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  gnuplot-nox
  python3 python3-numpy python3-scipy python3-sklearn python3-yaml
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]})); then
  echo "setup: installing missing Debian packages: ${missing[*]}" >&2
  sudo_cmd=()
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "setup: not root and no sudo; install: ${missing[*]}" >&2; exit 1; }
    sudo_cmd=(sudo)
  fi
  "${sudo_cmd[@]}" apt-get update
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y --no-install-recommends "${missing[@]}"
fi

build_dir="${GYROSID_BUILD_DIR:-build}"
jobs="$(nproc 2>/dev/null || echo 2)"
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build "$build_dir" --parallel "$jobs"

case "$job" in
  main)
    "$build_dir/gyrosid" run --out report
    echo "setup: main job done; report in $(pwd)/report/report.md" >&2
    ;;
  test)
    ctest --test-dir "$build_dir" --output-on-failure --parallel "$jobs"
    ;;
  build) ;;
esac
