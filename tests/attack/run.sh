#!/usr/bin/env bash
# An attack on the driftlab command line, as a careless or unlucky test engineer makes it:
# logs with wild cells and broken structure, hand-edited calibrations, options outside sense,
# outputs that are inputs, links, FIFOs and devices, standard output full or closed, signals
# in the middle of a write. Every run must end within its time limit, with status 0 or with
# status 1 and a line `error: ...` (141, quietly, for a closed pipe), never a panic or an
# abort; no input may change, no `.driftlab-*.tmp` may stay, a calibration it writes must load,
# no successful run may print NaN, and no run may print a number of 25 digits.
#
#     tests/attack/run.sh [DRIFTLAB]         # default: target/release/driftlab
#     ATTACK_QUICK=1 tests/attack/run.sh     # about a seventh of the runs (what `cargo test` runs)
#
# It needs bash, coreutils (timeout, mkfifo, sha256sum), sed and awk, and prints one line per
# finding, then `N runs, N findings`. Its exit status is the number of findings (capped at 100).
# `inf` and `0.0000` printed for figures that cannot be computed are counted apart, as notes:
# replacing them by `n/a` with the reason is the work of the figures of merit.

set -u
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
bin=$(realpath "${1:-$root/target/release/driftlab}")
samples="$root/sample_logs"
quick=${ATTACK_QUICK:-0}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 100

runs=0
findings=0
notes=0
finding() {
    findings=$((findings + 1))
    echo "FINDING: $*"
}

# The files a run names that are there before it are hashed before and after it: nothing a
# command reads may change. (A run's outputs are named in o/ and are not there before it.)
inputs_sum() {
    local a
    for a in "$@"; do
        sha256sum "$a" 2>/dev/null
    done
    return 0
}

# run EXPECT ARGS...: runs driftlab with a time limit and judges what it did. EXPECT is `ok`
# (must succeed), `fail` (must fail with a message) or `any`.
run() {
    local expect=$1
    shift
    runs=$((runs + 1))
    local before a
    local existing=()
    for a in "$@"; do
        [ -f "$a" ] && existing+=("$a")
    done
    before=$(inputs_sum "${existing[@]}")
    timeout 120 "$bin" "$@" >out.txt 2>err.txt </dev/null
    local rc=$?
    local what="driftlab $*"
    # 2 is a usage error of the argument parser (`--knots 1e9` is no whole number).
    [ $rc -eq 2 ] && grep -q "^error: " err.txt && rc=1
    case $rc in
        124) finding "hang (over 120 s): $what" ;;
        0 | 1) ;;
        *) finding "status $rc: $what: $(tail -1 err.txt)" ;;
    esac
    if grep -q "panicked\|RUST_BACKTRACE" err.txt; then
        finding "panic: $what: $(grep -m1 panicked err.txt)"
    fi
    if [ $rc -eq 1 ] && ! grep -q "^error: " err.txt; then
        finding "failed without a message: $what"
    fi
    if [ $rc -eq 1 ] && [ "$(grep -c "^error: " err.txt)" -ne 1 ]; then
        finding "more than one error line: $what"
    fi
    if [ "$expect" = ok ] && [ $rc -ne 0 ]; then
        finding "should succeed: $what: $(tail -1 err.txt)"
    fi
    if [ "$expect" = fail ] && [ $rc -eq 0 ]; then
        finding "accepted silently: $what"
    fi
    # A figure of merit that cannot be computed (NaN, inf, 0.0000 in the raw/corrected table)
    # is a note: `n/a` with its reason is the figures of merit's to print. NaN anywhere else
    # is a finding.
    # ("blank or NaN in column" is a warning about a dropped row, not a NaN printed.)
    local figures='(filtered drift|mean\||RMS) |blank or NaN'
    if [ $rc -eq 0 ] && grep -vE "$figures" out.txt | grep -qw "NaN"; then
        finding "NaN printed: $what: $(grep -vE "$figures" out.txt | grep -m1 -w NaN)"
    fi
    local table='(filtered drift|mean\||RMS) '
    if [ $rc -eq 0 ] && grep -E "$table" out.txt | grep -qwE "NaN|inf|0\.0000"; then
        notes=$((notes + 1))
        echo "note: $what: $(grep -E "$table" out.txt | grep -m1 -wE "NaN|inf|0\.0000")"
    fi
    # Numbers for people have at most a few significant digits (1e-300, not three hundred
    # digits); `export` prints a file's text, which keeps round-trip precision.
    local long
    if [ "$1" != export ]; then
        long=$(grep -hoE '[0-9]{25,}' out.txt err.txt | head -1 | cut -c1-40)
        [ -n "$long" ] && finding "a number of 25 digits or more printed ($long...): $what"
    fi
    if [ "$(inputs_sum "${existing[@]}")" != "$before" ]; then
        finding "an input changed: $what"
    fi
    local left
    left=$(find . -name '.driftlab-*.tmp' | head -1)
    if [ -n "$left" ]; then
        finding "temporary file left: $left: $what"
        find . -name '.driftlab-*.tmp' -delete
    fi
    return 0
}

# A calibration a successful command wrote must load.
loads() {
    if [ -e "$1" ] && ! "$bin" export "$1" --format csv-table >/dev/null 2>err.txt; then
        finding "written but does not load: $1: $(tail -1 err.txt)"
    fi
}

cp "$samples/calibration.csv" base.csv
cp "$samples/validation.csv" held.csv
cp "$samples/laser-gyro.csv" laser.csv
"$bin" calibrate base.csv --out cal.json >/dev/null 2>&1 || finding "no base calibration"
"$bin" calibrate base.csv --k1 pwl --knots 4 --out pwl.json >/dev/null 2>&1
"$bin" calibrate base.csv --model coil-lag --out coil.json >/dev/null 2>&1
"$bin" calibrate base.csv --model yan-delayed --out yan.json >/dev/null 2>&1
"$bin" calibrate laser.csv --model sukhanov --out suk.json >/dev/null 2>&1
mkdir -p gen o

# ---- Logs: wild cells in each column, and broken structure ----------------------------------
tokens=(1e160 -1e308 1e308 1e-320 NaN inf -inf "" "#NUM!" 0x10 "1.2.3" "--1" "1e" " " "+-0")
lines=(100 5001 20000)
columns=(1 2 3)
if [ "$quick" = 1 ]; then
    tokens=(1e160 -1e308 "#NUM!")
    lines=(5001)
    columns=(2 3)
fi
k=0
for line in "${lines[@]}"; do
    for col in "${columns[@]}"; do
        for tok in "${tokens[@]}"; do
            k=$((k + 1))
            awk -v l="$line" -v c="$col" -v t="$tok" 'BEGIN { FS = OFS = "," }
                NR == l { $c = t } { print }' base.csv >"gen/cell$k.csv"
        done
    done
done
printf '' >gen/empty.csv
printf '\xef\xbb\xbf' >gen/bom.csv
head -2 base.csv >gen/header.csv
cut -d, -f2 base.csv >gen/one-column.csv
tr '\n' '\r' <base.csv >gen/cr.csv
head -c 4096 /dev/urandom >gen/random.csv
head -3000 base.csv >gen/short.csv
head -20 base.csv >gen/tiny.csv
sed 's/time_s,omega_dph,temp_c,temp_chamber_c/time_s,omega_dph,omega_dph,temp_c/' base.csv >gen/dup.csv
awk 'NR == 50 { printf "%s", $0; for (i = 0; i < 600000; i++) printf ",1.0"; print ""; next } { print }' \
    base.csv >gen/long-line.csv
head -c 500000 base.csv >gen/truncated.csv
awk 'NR < 3 { print; next } { print $0 }' base.csv | sed '1000,1010d' >gen/gap.csv
if command -v iconv >/dev/null; then iconv -f UTF-8 -t UTF-16 base.csv >gen/utf16.csv; fi
awk 'BEGIN { FS = OFS = "," } NR > 2 { $1 = $1 * 1e-9 } { print }' base.csv >gen/nanosecond.csv
awk 'BEGIN { FS = OFS = "," } NR > 2 { $1 = $1 * 1e300 } { print }' base.csv >gen/huge-time.csv
for f in gen/*.csv; do
    mv "$f" "./log-$(basename "$f")"
done
for log in log-*.csv; do
    run any inspect "$log"
    run any calibrate "$log" --out o/cal.json
    [ -e o/cal.json ] && loads o/cal.json
    rm -f o/cal.json
    run any evaluate cal.json "$log"
    run any apply cal.json "$log" --out o/out.csv
    rm -f o/out.csv
    run any allan "$log"
    if [ "$quick" != 1 ]; then
        run any calibrate "$log" --model ieee952 --out o/cal.json
        [ -e o/cal.json ] && loads o/cal.json
        rm -f o/cal.json
        run any report cal.json "$log" --out o/rep
        rm -rf o/rep
    fi
done

# ---- Calibrations edited by hand ---------------------------------------------------------------
edit() { # SOURCE NAME SED-SCRIPT
    sed -E "$3" "$1" >"$2"
}
vals=(1e308 -1e308 1e-300 0 -1 9.9e6 null '"x"' 1e400)
[ "$quick" = 1 ] && vals=(1e308 null)
n=0
for v in "${vals[@]}"; do
    n=$((n + 1))
    edit cal.json "e-k0c$n.json" "0,/\"coeffs\": \[/{n}; /\"coeffs\": \[/{n;s/-?[0-9.e+-]+/$v/}"
    edit cal.json "e-xmin$n.json" "0,/\"x_min\"/s/(\"x_min\": )[^,]*/\1$v/"
    edit cal.json "e-xmax$n.json" "0,/\"x_max\"/s/(\"x_max\": )[^,]*/\1$v/"
    edit cal.json "e-dt$n.json" "s/(\"dt_s\": )[^,]*/\1$v/"
    edit cal.json "e-smooth$n.json" "s/(\"smooth_samples\": )[^,]*/\1$v/"
    edit cal.json "e-plateau$n.json" "0,/\"omega_dph\"/s/(\"omega_dph\": )[^,]*/\1$v/"
    edit pwl.json "e-knot$n.json" "0,/\"knots_x\": \[/{n}; /\"knots_x\": \[/{n;n;s/-?[0-9.e+-]+/$v/}"
    edit coil.json "e-lag$n.json" "s/(\"lag_s\": )[^,]*/\1$v/"
    edit coil.json "e-coef$n.json" "/\"coefficients\": \[/{n;s/-?[0-9.e+-]+/$v/}"
    edit yan.json "e-delay$n.json" "/\"points\": \[/{n;n;n;s/-?[0-9.e+-]+/$v/}"
    edit suk.json "e-lambda$n.json" "s/(\"lambda_s\": )[^,]*/\1$v/"
done
edit coil.json e-names.json 's/"T\^2",/"T^3",/'
edit cal.json e-version.json 's/"version": 1/"version": 0/'
edit cal.json e-kind.json '0,/"kind": "parabolic"/s/"kind": "parabolic"/"kind": "spline"/'
awk '/"coeffs": \[/ && !done { print; for (i = 0; i < 1000000; i++) print "1e-9,"; done = 1; next } { print }' \
    cal.json >e-million.json
head -c 2000 cal.json >e-truncated.json
for cal in e-*.json; do
    run any apply "$cal" base.csv --out o/out.csv
    rm -f o/out.csv
    run any evaluate "$cal" base.csv
    run any export "$cal" --format c-header
    if [ "$quick" != 1 ]; then
        run any export "$cal" --format csv-table
        run any report "$cal" base.csv --out o/rep
        rm -rf o/rep
    fi
done
rm -f e-*.json

# ---- Options outside sense --------------------------------------------------------------------
bad=(0 -1 1e-300 1e300 inf nan 1e12 1e9)
[ "$quick" = 1 ] && bad=(1e-300 inf 1e12)
for v in "${bad[@]}"; do
    run fail allan base.csv --tau0 "$v"
    # A window of less than a sample is one sample: no figure of nothing, so not refused.
    if [ "$v" = 1e-300 ]; then
        run any evaluate cal.json base.csv --filter "$v"
        run any evaluate cal.json base.csv --window "$v"
        run any calibrate base.csv --smooth "$v" --out o/cal.json
        rm -f o/cal.json
        continue
    fi
    run fail evaluate cal.json base.csv --filter "$v"
    run fail evaluate cal.json base.csv --window "$v"
    run fail calibrate base.csv --filter "$v" --out o/cal.json
    run fail calibrate base.csv --smooth "$v" --out o/cal.json
    run fail calibrate base.csv --step-h "$v" --out o/cal.json
    if [ "$quick" != 1 ]; then
        run fail report cal.json base.csv --window "$v" --out o/rep
        run fail compare --train base.csv --filter "$v" --models ieee952
        run any export cal.json --format csv-table --points "$v"
        run any calibrate base.csv --knots "$v" --k0 spline --out o/cal.json
    fi
    rm -rf o/rep o/cal.json
done
printf '{ "filter_s": 1e9 }\n' >recipe.json
run fail calibrate base.csv --recipe recipe.json --out o/cal.json
rm -f recipe.json

# ---- Outputs that are inputs, links, FIFOs, devices --------------------------------------------
run fail apply cal.json base.csv --out base.csv
run fail apply cal.json base.csv --out cal.json
run fail apply cal.json base.csv --out ./././base.csv
run fail calibrate base.csv --out base.csv
run fail calibrate base.csv --out o/new.json --save-recipe o/new.json
run fail export cal.json --format c-header --out cal.json
ln -s base.csv link.lnk
run fail apply cal.json base.csv --out link.lnk
ln -sf cal-target.json o/out-link.lnk
run ok calibrate base.csv --out o/out-link.lnk
[ -L o/out-link.lnk ] || finding "a link was replaced by a file"
loads o/cal-target.json
rm -f link.lnk o/out-link.lnk o/cal-target.json o/new.json
mkfifo o/out.fifo
(cat o/out.fifo >o/fifo.txt &)
run ok export cal.json --format c-header --out o/out.fifo
sleep 0.2
[ -p o/out.fifo ] || finding "a FIFO was replaced by a file"
grep -q '#define' o/fifo.txt 2>/dev/null || finding "nothing came through the FIFO"
rm -f o/out.fifo o/fifo.txt
if [ -w /dev/full ]; then
    run fail export cal.json --format c-header --out /dev/full
    [ -c /dev/full ] || finding "/dev/full was replaced"
fi
mkdir o/adir
run fail apply cal.json base.csv --out o/adir
run fail apply cal.json base.csv --out no/such/dir/out.csv
rmdir o/adir

# ---- Standard output full or closed -------------------------------------------------------------
printing=("inspect base.csv" "evaluate cal.json base.csv" "allan base.csv" "simulate --list"
    "compare --train base.csv --models ieee952" "export cal.json --format c-header"
    "calibrate base.csv --out o/cal.json" "inspect --json base.csv")
for c in "${printing[@]}"; do
    runs=$((runs + 1))
    # shellcheck disable=SC2086
    timeout 60 "$bin" $c >/dev/full 2>err.txt
    rc=$?
    [ $rc -eq 1 ] && grep -q "^error: standard output: No space left" err.txt ||
        finding "full standard output: driftlab $c: status $rc: $(tail -1 err.txt)"
    runs=$((runs + 1))
    # shellcheck disable=SC2086
    (timeout 60 "$bin" $c 2>err.txt; echo $? >rc.txt) | true
    rc=$(cat rc.txt)
    { [ "$rc" -eq 141 ] || [ "$rc" -eq 0 ]; } && ! grep -q "panicked\|error" err.txt ||
        finding "closed pipe: driftlab $c: status $rc: $(tail -1 err.txt)"
done
rm -f o/cal.json rc.txt

# ---- Logs read once: FIFO and standard input ---------------------------------------------------
for c in "inspect" "allan" "calibrate @ --out o/cal.json" "evaluate cal.json @" \
    "apply cal.json @ --out o/out.csv" "report cal.json @ --out o/rep"; do
    runs=$((runs + 1))
    rm -f in.fifo
    mkfifo in.fifo
    (cat base.csv >in.fifo; echo $? >writer.txt) &
    args=${c//@/in.fifo}
    [ "$args" = "$c" ] && args="$c in.fifo"
    # shellcheck disable=SC2086
    timeout 60 "$bin" $args >/dev/null 2>err.txt
    rc=$?
    wait
    [ $rc -eq 0 ] && [ "$(cat writer.txt)" = 0 ] ||
        finding "FIFO log: driftlab $args: status $rc: $(tail -1 err.txt)"
    runs=$((runs + 1))
    args=${c//@/-}
    [ "$args" = "$c" ] && args="$c -"
    # shellcheck disable=SC2086
    timeout 60 "$bin" $args <base.csv >/dev/null 2>err.txt ||
        finding "standard input log: driftlab $args: $(tail -1 err.txt)"
    rm -rf in.fifo writer.txt o/cal.json o/out.csv rep
done

# ---- Signals during a write ---------------------------------------------------------------------
echo "the old log" >o/sig.csv
odir=$(cd o && pwd -P)
for sig in TERM INT HUP KILL; do
    runs=$((runs + 1))
    "$bin" simulate --rate-hz 50 --out o/sig.csv >/dev/null 2>&1 &
    pid=$!
    for _ in $(seq 1 3000); do
        compgen -G 'o/.driftlab-sig.csv.*.tmp' >/dev/null && break
        # On Linux the temporary has no name while it is written (O_TMPFILE): /proc shows it.
        ls -l "/proc/$pid/fd" 2>/dev/null | grep -qF "$odir/#" && break
        sleep 0.01
    done
    kill -"$sig" "$pid" 2>/dev/null
    wait "$pid" 2>/dev/null
    [ "$(cat o/sig.csv)" = "the old log" ] || finding "SIG$sig: the old output was lost"
    if [ "$sig" = KILL ]; then
        "$bin" simulate --profile calibration --out o/sig.csv >/dev/null 2>&1
        compgen -G 'o/.driftlab-sig.csv.*.tmp' >/dev/null &&
            finding "the temporary file of a killed run was not cleaned up by the next write"
    elif compgen -G 'o/.driftlab-*.tmp' >/dev/null; then
        finding "SIG$sig: a temporary file was left"
    fi
    rm -f o/.driftlab-*.tmp
done

echo "$runs runs, $findings findings ($notes notes: a figure of merit that cannot be computed printed as NaN, inf or 0.0000)"
[ $findings -gt 100 ] && findings=100
exit $findings
