#!/usr/bin/env bash
# The workbench in a real X server with no desktop portal, no D-Bus session and no zenity,
# driven by real key presses: `driftlab gui LOG`, then Ctrl+E and Enter must write the
# calibration beside the log, and Ctrl+S and Enter the session beside it (the workbench's own
# file dialog, since no system dialog can appear there).
#
#   bash .ci/gui-check.sh [path/to/driftlab]
#
# Needs Xvfb and xdotool (and imagemagick's `import` for the screenshot left on failure).
# Without them it says so and exits 0, except under CI (CI set), where it fails.
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=$(realpath "${1:-target/release/driftlab}")

skip_or_fail() {
  if [ -n "${CI:-}" ]; then
    echo "gui-check: FAILED: $*" >&2
    exit 1
  fi
  echo "gui-check: skipped: $*" >&2
  exit 0
}

for tool in Xvfb xdotool; do
  command -v "$tool" >/dev/null || skip_or_fail "$tool is not installed (apt-get install xvfb xdotool)"
done
[ -x "$BIN" ] || skip_or_fail "$BIN is not built (cargo build --release)"

WORK=$(mktemp -d)
APP_PID=""
X_PID=""
cleanup() {
  [ -n "$APP_PID" ] && kill "$APP_PID" 2>/dev/null || true
  [ -n "$X_PID" ] && kill "$X_PID" 2>/dev/null || true
  wait 2>/dev/null || true
}
trap cleanup EXIT

fail() {
  echo "gui-check: FAILED: $*" >&2
  if command -v import >/dev/null && [ -n "${DISPLAY_NUM:-}" ]; then
    DISPLAY=":$DISPLAY_NUM" import -window root "$WORK/failure.png" 2>/dev/null &&
      echo "gui-check: the screen is in $WORK/failure.png" >&2
  fi
  echo "gui-check: the workbench said:" >&2
  sed 's/^/  /' "$WORK/app.log" >&2 || true
  trap - EXIT
  cleanup
  exit 1
}

# A free display number.
DISPLAY_NUM=91
while [ -e "/tmp/.X11-unix/X$DISPLAY_NUM" ] || [ -e "/tmp/.X$DISPLAY_NUM-lock" ]; do
  DISPLAY_NUM=$((DISPLAY_NUM + 1))
done
Xvfb ":$DISPLAY_NUM" -screen 0 1600x1000x24 -nolisten tcp >"$WORK/xvfb.log" 2>&1 &
X_PID=$!
for _ in $(seq 100); do
  [ -e "/tmp/.X11-unix/X$DISPLAY_NUM" ] && break
  sleep 0.1
done
[ -e "/tmp/.X11-unix/X$DISPLAY_NUM" ] || fail "Xvfb did not start"

# The log in a folder of its own; a fresh home; no session bus; no zenity on PATH.
mkdir -p "$WORK/home" "$WORK/logs"
cp sample_logs/calibration.csv "$WORK/logs/run7.csv"
CLEAN_PATH=""
IFS=: read -ra DIRS <<<"$PATH"
for d in "${DIRS[@]}"; do
  [ -x "$d/zenity" ] && continue
  CLEAN_PATH="${CLEAN_PATH:+$CLEAN_PATH:}$d"
done

env -u DBUS_SESSION_BUS_ADDRESS -u XDG_RUNTIME_DIR -u XDG_CONFIG_HOME -u WAYLAND_DISPLAY \
  -u DRIFTLAB_FILE_DIALOG \
  HOME="$WORK/home" PATH="$CLEAN_PATH" DISPLAY=":$DISPLAY_NUM" \
  "$BIN" gui "$WORK/logs/run7.csv" >"$WORK/app.log" 2>&1 &
APP_PID=$!

# The window, once the log is read and calibrated (its title says so).
export DISPLAY=":$DISPLAY_NUM"
WIN=""
for _ in $(seq 600); do
  kill -0 "$APP_PID" 2>/dev/null || fail "the workbench exited"
  for w in $(xdotool search --pid "$APP_PID" 2>/dev/null || true); do
    name=$(xdotool getwindowname "$w" 2>/dev/null || true)
    case "$name" in
      "run7.csv — driftlab workbench"*) case "$name" in *"(calibrat"*) ;; *) WIN=$w ;; esac ;;
    esac
  done
  [ -n "$WIN" ] && break
  sleep 0.1
done
[ -n "$WIN" ] || fail "no calibrated workbench window within 60 s"
xdotool windowfocus --sync "$WIN"
sleep 0.5

press() {
  xdotool windowfocus --sync "$WIN"
  xdotool key --clearmodifiers "$1"
}

wait_for_file() {
  for _ in $(seq 200); do
    [ -s "$1" ] && return 0
    sleep 0.1
  done
  return 1
}

press ctrl+e
sleep 1
press Return
wait_for_file "$WORK/logs/run7-calibration.json" || fail "Ctrl+E, Enter wrote no run7-calibration.json beside the log"
grep -q '"format": "driftlab-calibration"' "$WORK/logs/run7-calibration.json" ||
  fail "run7-calibration.json is not a calibration file"
"$BIN" evaluate "$WORK/logs/run7-calibration.json" "$WORK/logs/run7.csv" >"$WORK/evaluate.txt" ||
  fail "driftlab evaluate does not read the calibration written"

press ctrl+s
sleep 1
press Return
wait_for_file "$WORK/logs/run7-session.json" || fail "Ctrl+S, Enter wrote no run7-session.json beside the log"
grep -q '"format": "driftlab-session"' "$WORK/logs/run7-session.json" ||
  fail "run7-session.json is not a session file"

# Screenshot mode on what the window cannot show: status 1 and the cause on standard error
# within seconds, no picture (it used to wait on an error dialog for ever).
printf '{ "format": "driftlab-session", "version": 99, "session": {} }\n' >"$WORK/newer.session.json"
{
  echo "time_s,omega_dph,temp_c"
  for i in $(seq 0 1999); do echo "$i,0.01,25.0"; done
} >"$WORK/flat.csv"
for what in "newer.session.json:version 99 is not supported" \
  "flat.csv:the calibration failed:"; do
  file=${what%%:*}
  want=${what#*:}
  rc=0
  env HOME="$WORK/home" DISPLAY=":$DISPLAY_NUM" timeout 60 "$BIN" gui "$WORK/$file" \
    --screenshot "$WORK/shot.png" >"$WORK/shot.log" 2>&1 || rc=$?
  [ "$rc" -eq 1 ] || fail "gui $file --screenshot: status $rc (wanted 1): $(cat "$WORK/shot.log")"
  grep -q "^error: .*$want" "$WORK/shot.log" ||
    fail "gui $file --screenshot did not say \"$want\": $(cat "$WORK/shot.log")"
  [ ! -e "$WORK/shot.png" ] || fail "gui $file --screenshot wrote a picture"
done

# A window larger than the 1600x1000 screen is said, not passed over (the picture is of the
# window the screen allowed).
rc=0
env HOME="$WORK/home" DISPLAY=":$DISPLAY_NUM" timeout 60 "$BIN" gui "$WORK/logs/run7.csv" \
  --window-size 2400x1500 --screenshot "$WORK/big.png" >"$WORK/big.log" 2>&1 || rc=$?
[ "$rc" -eq 0 ] || fail "gui --window-size 2400x1500 --screenshot: status $rc: $(cat "$WORK/big.log")"
grep -q "^warning: The window is .*smaller than the 2400×1500 asked for" "$WORK/big.log" ||
  fail "a window larger than the screen was not said: $(cat "$WORK/big.log")"

echo "gui-check: ok: with no portal, no D-Bus session and no zenity, Ctrl+E/Enter and Ctrl+S/Enter wrote run7-calibration.json and run7-session.json beside the log; --screenshot of a session or log that cannot be shown ended with status 1 and its message; a window larger than the screen was said"
