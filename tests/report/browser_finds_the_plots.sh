#!/usr/bin/env bash
# The main job's index.html in a headless browser (Chromium): the page loads and every plot it shows is an
# image the browser could decode (the page counts them on load: data-images, data-images-loaded).
#   tests/report/browser_finds_the_plots.sh <gyrosid> <chromium>
set -euo pipefail
gyrosid=$1 chromium=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$gyrosid" --quiet run --flights short --rbf-config builtin:calibration/rbf_noisy.yaml --out "$dir/report" > /dev/null
dom=$("$chromium" --headless --no-sandbox --disable-gpu --disable-dev-shm-usage --user-data-dir="$dir/profile" \
      --virtual-time-budget=20000 --dump-dom "file://$dir/report/index.html" 2> "$dir/chromium.log")
images=$(grep -o 'data-images="[0-9]*"' <<< "$dom" | grep -o '[0-9]*' || true)
loaded=$(grep -o 'data-images-loaded="[0-9]*"' <<< "$dom" | grep -o '[0-9]*' || true)
expected=$(grep -c '<img ' "$dir/report/index.html" || true)
echo "images in the page: $expected; the browser counted $images, loaded $loaded"
[ -n "$images" ] || { echo "the page's load handler did not run"; tail -20 "$dir/chromium.log"; exit 1; }
[ "$images" -ge 6 ] && [ "$images" -eq "$expected" ] && [ "$loaded" -eq "$images" ]
grep -q "<h2>Provenance</h2>" <<< "$dom"
