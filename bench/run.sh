#!/usr/bin/env bash
# Whole-process benchmarks of driftlab against polars and numpy (BENCHMARKS.md).
#
#   bench/run.sh [ROWS]          # default 10 000 000 rows (about 300 MB of CSV)
#
# Environment: RUNS (clean measured runs wanted per command, default 5; one more warm-up run is
# discarded; a run during which other processes used over 10 % of a core is not clean, and at
# most 2*RUNS runs are made), QUIET_WAIT (seconds to wait for an idle machine before each run,
# default 180),
# WORK (folder for the big log and the results, default /tmp/driftlab-bench),
# SKIP_CRITERION=1 (skip `cargo bench`), SKIP_NUMPY=1 (skip the numpy pipeline, ~30 s a run).
#
# Every measured run goes through `/usr/bin/time -f` (wall time, peak RSS, user, sys) and is
# appended to $WORK/runs.tsv with the load average at its start and the CPU time other processes
# took while it ran (from /proc/stat); bench/summarize.py then prints
# the medians, the ratios and the verdict on each requirement ($WORK/summary.md). The file is
# read from the page cache in every run (it is written just before and the machine has 24 GB).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
ROWS=${1:-10000000}
RUNS=${RUNS:-5}
WORK=${WORK:-/tmp/driftlab-bench}
mkdir -p "$WORK"
BIG=$WORK/big.csv

# ---- tools ---------------------------------------------------------------------------------
if [ ! -x /usr/bin/time ]; then
  apt-get update -qq && apt-get install -y -qq time >/dev/null
fi
if ! python3 -c "import polars, numpy" 2>/dev/null; then
  pip install -q polars numpy
fi

echo "== building (release, no default features)" >&2
cargo build --release --no-default-features --bin driftlab --example make_big_log >&2
BIN=$ROOT/target/release/driftlab
# The bench binary doubles as an ingest-only process (DRIFTLAB_STAGES_INGEST_ONLY).
ENGINE=$(cargo bench --no-default-features --bench engine --no-run --message-format=json 2>/dev/null \
  | python3 -c 'import json,sys
for l in sys.stdin:
    try: m = json.loads(l)
    except ValueError: continue
    if m.get("reason") == "compiler-artifact" and m.get("target", {}).get("name") == "engine" and m.get("executable"):
        print(m["executable"])' | tail -1)
[ -x "$ENGINE" ] || { echo "could not build the bench binary" >&2; exit 1; }

echo "== generating $BIG ($ROWS rows)" >&2
"$ROOT/target/release/examples/make_big_log" "$BIG" "$ROWS"

# ---- machine -------------------------------------------------------------------------------
{
  echo "date	$(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "nproc	$(nproc)"
  echo "cpu	$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //')"
  echo "mem	$(free -g | awk '/Mem:/ {print $2 " GiB"}')"
  echo "kernel	$(uname -r)"
  echo "rustc	$(rustc --version)"
  echo "python	$(python3 --version 2>&1)"
  echo "polars	$(python3 -c 'import polars; print(polars.__version__)')"
  echo "numpy	$(python3 -c 'import numpy; print(numpy.__version__)')"
  echo "git	$(git rev-parse --short HEAD 2>/dev/null)$(git diff --quiet HEAD -- src 2>/dev/null || echo ' (src/ modified in the work tree)')"
  echo "rows	$ROWS"
  echo "bytes	$(stat -c %s "$BIG")"
  echo "runs	$RUNS"
} > "$WORK/machine.tsv"
cat "$WORK/machine.tsv" >&2

# ---- whole-process runs --------------------------------------------------------------------
RUNS_TSV=$WORK/runs.tsv
: > "$RUNS_TSV"
LOGDIR=$WORK/logs
mkdir -p "$LOGDIR"

# CPU time used by the whole machine so far, in clock ticks (USER_HZ, 100 a second).
busy_ticks() {
  local _cpu u n sy idle iow irq sirq steal
  read -r _cpu u n sy idle iow irq sirq steal _ < /proc/stat
  echo $((u + n + sy + irq + sirq + steal))
}

# Waits (at most QUIET_WAIT seconds, default 180) until the machine is idle: less than 10 % of
# its CPU busy over 2 s. Other sessions build on this machine too; a run that shares the two
# cores with a compiler measures the compiler as much as the program.
wait_quiet() {
  local waited=0 b0 b1 pct
  while :; do
    b0=$(busy_ticks); sleep 2; b1=$(busy_ticks)
    pct=$(( (b1 - b0) * 100 / (200 * $(nproc)) ))
    if [ "$pct" -lt 10 ] || [ "$waited" -ge "${QUIET_WAIT:-180}" ]; then
      [ "$waited" -gt 0 ] && echo "   (waited ${waited} s for a quiet machine; now ${pct}% busy)" >&2
      return 0
    fi
    sleep 5; waited=$((waited + 7))
  done
}

# measure NAME CMD... : one warm-up run, then measured runs until RUNS of them were clean
# (other processes used under 10 % of one core during the run, or under 0.05 CPU s) or 2*RUNS
# were made. Each
# measured run is a line of runs.tsv: name, run, load average, wall s, peak RSS kB, user s,
# sys s, CPU seconds used by other processes during the run.
measure() {
  local name=$1
  shift
  echo "== $name: $*" >&2
  wait_quiet
  "$@" >"$LOGDIR/$name.0.out" 2>"$LOGDIR/$name.0.err"
  local k=0 clean=0
  while [ "$clean" -lt "$RUNS" ] && [ "$k" -lt $((2 * RUNS)) ]; do
    k=$((k + 1))
    wait_quiet
    local load b0 b1 t others
    load=$(cut -d' ' -f1 /proc/loadavg)
    b0=$(busy_ticks)
    /usr/bin/time -f "%e	%M	%U	%S" -o "$WORK/time.out" "$@" \
      >"$LOGDIR/$name.$k.out" 2>"$LOGDIR/$name.$k.err"
    b1=$(busy_ticks)
    t=$(tail -1 "$WORK/time.out")
    others=$(awk -v b=$((b1 - b0)) -v u="$(echo "$t" | cut -f3)" -v s="$(echo "$t" | cut -f4)" \
      'BEGIN { o = b / 100 - u - s; if (o < 0) o = 0; printf "%.2f", o }')
    if awk -v o="$others" -v w="$(echo "$t" | cut -f1)" 'BEGIN { exit !(o <= 0.1 * w || o <= 0.05) }'; then
      clean=$((clean + 1))
    fi
    printf '%s\t%s\t%s\t%s\t%s\n' "$name" "$k" "$load" "$t" "$others" >> "$RUNS_TSV"
    echo "   run $k: $(echo "$t" | awk '{print $1 " s, " $2 * 1.024 / 1000 " MB"}'), others used ${others} CPU s" >&2
  done
}

measure ingest_only env DRIFTLAB_STAGES="$BIG" DRIFTLAB_STAGES_INGEST_REPEAT=1 \
  DRIFTLAB_STAGES_INGEST_ONLY=1 "$ENGINE"
measure polars_read python3 bench/polars_read.py "$BIG"
measure inspect "$BIN" inspect "$BIG"
measure calibrate "$BIN" calibrate "$BIG" --out "$WORK/cal.json"
measure apply "$BIN" apply "$WORK/cal.json" "$BIG" --out "$WORK/out.csv"
if [ -z "${SKIP_NUMPY:-}" ]; then
  mkdir -p "$WORK/np"
  measure numpy_pipeline python3 bench/numpy_pipeline.py "$BIG" --out-dir "$WORK/np"
  python3 bench/numpy_pipeline.py "$BIG" --out-dir "$WORK/np" --no-write --check "$WORK/cal.json" \
    2> "$WORK/numpy_check.txt" || true
fi
rm -f "$WORK/out.csv" "$WORK/np/numpy_out.csv"

# ---- requirement 1, paired: one read in a fresh process each, driftlab and polars alternately
# (the machine drifts between minutes; alternating cancels it), read time as each measures it.
echo "== paired ingest: driftlab and polars alternately, $((2 * RUNS + 1)) pairs" >&2
: > "$WORK/paired.tsv"
for k in $(seq 1 $((2 * RUNS + 1))); do
  wait_quiet
  d=$(DRIFTLAB_STAGES="$BIG" DRIFTLAB_STAGES_INGEST_REPEAT=1 DRIFTLAB_STAGES_INGEST_ONLY=1 "$ENGINE" \
    | sed -n 's/.*ingest median of 1: \([0-9.]*\) ms.*/\1/p')
  p=$(python3 bench/polars_read.py "$BIG" 2>&1 | sed -n 's/.* in \([0-9.]*\) s .*/\1/p')
  printf '%s\t%s\t%s\n' "$k" "$(awk -v d="$d" 'BEGIN { print d / 1000 }')" "$p" >> "$WORK/paired.tsv"
  echo "   pair $k: driftlab ${d} ms, polars ${p} s" >&2
done

# ---- in-process figures --------------------------------------------------------------------
echo "== in-process: polars.read_csv x $RUNS" >&2
wait_quiet
python3 bench/polars_read.py "$BIG" --repeat "$RUNS" 2> "$WORK/polars_inproc.txt"
echo "== in-process: driftlab stages (ingest x $RUNS, then calibrate and apply stage by stage)" >&2
wait_quiet
DRIFTLAB_STAGES="$BIG" DRIFTLAB_STAGES_INGEST_REPEAT="$RUNS" "$ENGINE" > "$WORK/stages.txt"
cat "$WORK/stages.txt" >&2

if [ -z "${SKIP_CRITERION:-}" ]; then
  echo "== criterion (1M samples)" >&2
  cargo bench --no-default-features --bench engine --no-run >/dev/null 2>&1
  wait_quiet
  cargo bench --no-default-features --bench engine 2>&1 \
    | grep -v '^Benchmarking' > "$WORK/criterion.txt" || true
fi

python3 bench/summarize.py "$WORK" | tee "$WORK/summary.md"
