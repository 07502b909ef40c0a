#!/usr/bin/env bash
# Screenshots of the workbench at the sizes it must hold, for docs/workbench.md: the bundled
# calibration log with its validation run held out, at 1600x1000, 1280x720 and 1024x640, and
# at 1600x1000 with a calibration opened beside the fit (one made on the validation run, "last
# week's"), in a real X server (Xvfb, started here when no DISPLAY is set) through the
# workbench's own `--screenshot`.
#
#   bash scripts/workbench-shots.sh [path/to/driftlab] [out-folder]
#
# Needs Xvfb when DISPLAY is not set.
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=$(realpath "${1:-target/release/driftlab}")
OUT=${2:-docs/screenshots}
mkdir -p "$OUT"
[ -x "$BIN" ] || { echo "workbench-shots: $BIN is not built (cargo build --release)" >&2; exit 1; }

X_PID=""
trap '[ -n "$X_PID" ] && kill "$X_PID" 2>/dev/null || true' EXIT
if [ -z "${DISPLAY:-}" ]; then
  command -v Xvfb >/dev/null || { echo "workbench-shots: no DISPLAY and no Xvfb (apt-get install xvfb)" >&2; exit 1; }
  n=93
  while [ -e "/tmp/.X11-unix/X$n" ] || [ -e "/tmp/.X$n-lock" ]; do n=$((n + 1)); done
  Xvfb ":$n" -screen 0 1920x1200x24 -nolisten tcp >/dev/null 2>&1 &
  X_PID=$!
  for _ in $(seq 100); do [ -e "/tmp/.X11-unix/X$n" ] && break; sleep 0.1; done
  export DISPLAY=":$n"
fi

for size in 1600x1000 1280x720 1024x640; do
  for page in calibration models; do
    DRIFTLAB_GUI_PAGE=$page "$BIN" gui sample_logs/calibration.csv \
      --validation sample_logs/validation.csv --window-size "$size" \
      --screenshot "$OUT/$page-$size.png"
    echo "$OUT/$page-$size.png"
  done
done

# A calibration opened to compare: one fitted on the validation run with K0 a spline of three
# knots, as a calibration from another day would differ from the current fit.
CAL_DIR=$(mktemp -d)
trap '[ -n "$X_PID" ] && kill "$X_PID" 2>/dev/null || true; rm -rf "$CAL_DIR"' EXIT
"$BIN" calibrate sample_logs/validation.csv --k0 spline --knots 3 \
  --out "$CAL_DIR/last-week.json" >/dev/null
"$BIN" gui sample_logs/calibration.csv "$CAL_DIR/last-week.json" \
  --validation sample_logs/validation.csv --window-size 1600x1000 \
  --screenshot "$OUT/opened-calibration-1600x1000.png"
echo "$OUT/opened-calibration-1600x1000.png"
