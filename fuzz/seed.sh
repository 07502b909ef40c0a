#!/usr/bin/env bash
# Seeds the fuzz corpora: slices of the sample logs in several dialects (read_log; the first
# byte of each input picks the reader options), the calibration files the command line writes
# for every model (calibration_file), and two session files (session_file).
set -euo pipefail
cd "$(dirname "$0")"
root=..
mkdir -p corpus/read_log corpus/calibration_file corpus/session_file
# The binary-log targets: from the sample logs of ../../shared/data/formats, read by path.
python3 seed_formats.py
python3 - <<'PY'
import glob
d = 'corpus/read_log'
i = 0
def put(sel, b):
    global i
    open(f'{d}/seed{i:03}', 'wb').write(bytes([sel]) + b)
    i += 1
for f in sorted(glob.glob('../sample_logs/*.csv')):
    lines = open(f, 'rb').read().split(b'\n')
    put(0, b'\n'.join(lines[:25]) + b'\n')
    put(5, b'\n'.join(lines[:3] + lines[3000:3010]) + b'\n')
put(1, "time_s;omega_dph;temp_c\n0;0,5;20,0\n1;0,6;20,5\n2;0,7;21,0\n".encode())
put(0, "\ufefftime_s,omega_dph,temp_c\r\n0,1,20\r\n1,2,21\r\n".encode())
put(6, b"t\tomega\ttemp\n0\t1.5\t20\n1\t1.6\t20.1\n")
put(2, b"  time    omega   temp\n  0.0     1.00    20.0\n  1.0     1.10    20.1\n")
put(0, b'# comment\n"time","omega","temp"\n"0","1,5","20"\n1,2,21\n# mid\n2,,22\n3,4,23\n')
put(4, "Time [ms];Rate [deg/s];Temp [\u00b0C]\n0;0,001;20\n100;0,002;20,1\n".encode())
put(3, b"1.0,20.0\n1.1,20.1\n1.2,20.2\n")
put(7, b"omega,temp,other\n1,20,x\n2,21,y\n")
put(0, b'time,omega,temp\n0,1,"2\n0"\n1,2,21\n')
PY
bin=$root/target/release/driftlab
[ -x "$bin" ] || (cd $root && cargo build --release --no-default-features)
log=$root/sample_logs/calibration.csv
$bin calibrate "$log" --out corpus/calibration_file/vakhrameev.json >/dev/null
for m in ieee952 yan-cross yan-delayed sukhanov poly-t pwl-t; do
    $bin calibrate "$log" --model $m --out corpus/calibration_file/$m.json >/dev/null
done
$bin calibrate $root/sample_logs/laser-gyro.csv --model custom \
    --terms "1,T,Tdot,T*Tdot,selfheat,ch:laser_power_mw,ch^2:piezo_v,dT,T*Tddot,|Tdot|" \
    --lag auto --delay auto --out corpus/calibration_file/custom.json >/dev/null
recipe=$(python3 -c "import json;print(json.dumps(json.load(open('corpus/calibration_file/vakhrameev.json'))['calibration']['recipe']))")
cat > corpus/session_file/full.json <<JSON
{"format": "driftlab-session", "version": 1, "session": {
  "log": {"path": "run7.csv", "read": {"delimiter": ";", "decimal_comma": true,
          "rate_col": "omega_dph", "temp_col": 3, "time_unit": "ms", "sample_rate_hz": 10.0}},
  "validation": {"path": "/data/val.csv"},
  "recipe": $recipe,
  "knots": {"k1_plus": [30.0, 35.0, 40.0, 45.0, 50.0], "k0": [1, 2, 3]},
  "view": {"time_range_s": [1000.0, 20000.0], "show_validation": true}}}
JSON
echo '{"format":"driftlab-session","version":1,"session":{}}' > corpus/session_file/empty.json
echo "seeded: $(ls corpus/read_log | wc -l) logs, $(ls corpus/calibration_file | wc -l) calibrations, $(ls corpus/session_file | wc -l) sessions"
