#!/usr/bin/env python3
"""A plain numpy implementation of `driftlab calibrate` + `driftlab apply` with the default
recipe, the reference of requirement 2 (BENCHMARKS.md).

    python3 bench/numpy_pipeline.py BIG.csv [--io polars|numpy] [--out-dir DIR] [--no-write]
                                            [--check CAL.json]

It does the steps driftlab does (METHOD.md section 1 and src/model.rs, src/correct.rs,
src/metrics.rs), vectorised the way a numpy user would write them, not deliberately slow:

calibrate  read the log (polars.read_csv, then numpy arrays: numpy's own readers are 10-50x
           slower and would flatter driftlab); nominal step (median of a strided sample of
           differences); centred moving average of omega over 100 s (cumsum); causal moving
           average of T over 60 s (cumsum) and 3-point backward derivatives with H = 30 s;
           plateau detection (quiet runs of |Tdot| < 0.05 degC/min, bridged over 60 s, at
           least 1200 s, end trimmed to the last |Tdot| under a fifth of the limit, settled
           second half); plateau means; K0 parabola (np.polyfit);
           automatic dead-bands (95th percentile / 5 via np.partition); K1+-, K2+- fitted as
           lines by weighted least squares (weights Tdot^2, Tddot^2: the "drift" weighting)
           with 2 refinement passes; SHA-256 of the file; in-sample figures of merit (apply
           the calibration, filtered drift p2p and std, 10-minute window means and RMS, raw and
           corrected); the calibration saved as JSON.
apply      load the JSON, read the log again, derivatives, prediction and correction, and write
           time_s,omega_raw_dph,omega_pred_dph,omega_cor_dph,temp_c with polars.write_csv
           (np.savetxt would take minutes).

`--io` chooses the reading and writing: `polars` (the default above: a "strong numpy" baseline
whose I/O is compiled and multithreaded) or `numpy`, numpy's own I/O as a plain numpy script
uses it: `np.loadtxt` to read the three columns and `np.savetxt` (`%.17g`, lossless) to write.
The compute is the same numpy code in both modes.

Both commands run in this one process, one after the other, each reading the file as the two
driftlab commands do. Stage timings go to stderr as one JSON object (the compute-only
comparison of BENCHMARKS.md uses them); `--check CAL.json` compares the fitted coefficients
with a calibration made by driftlab on the same file.
"""
import argparse
import hashlib
import json
import os
import sys
import time

import numpy as np

# Set by --io: "polars" or "numpy".
IO = "polars"

# The default recipe (src/recipe.rs).
FILTER_S = 100.0
SMOOTH_S = 60.0
STEP_H_S = 30.0
PLATEAU_MAX_RATE_C_PER_MIN = 0.05
PLATEAU_MIN_DURATION_S = 1200.0
PLATEAU_SETTLED_FRACTION = 0.5
PLATEAU_BRIDGE_S = 60.0
REFINEMENTS = 2
MERIT_WINDOW_S = 600.0

TIMES: dict = {}


class Stage:
    """Adds the wall time of a `with` block to TIMES[name]."""

    def __init__(self, name):
        self.name = name

    def __enter__(self):
        self.t0 = time.perf_counter()

    def __exit__(self, *exc):
        TIMES[self.name] = TIMES.get(self.name, 0.0) + time.perf_counter() - self.t0


# ---- reading ---------------------------------------------------------------------------------


def header_line(path):
    """0-based index of the header line (the first line that is not a # comment)."""
    with open(path, "rb") as f:
        for k, line in enumerate(f):
            if not line.startswith(b"#"):
                return k, line.decode().strip().split(",")
    raise ValueError(f"{path}: no header")


def read_log(path):
    if IO == "numpy":
        k, names = header_line(path)
        cols = tuple(names.index(c) for c in ("time_s", "omega_dph", "temp_c"))
        t, omega, temp = np.loadtxt(
            path, delimiter=",", skiprows=k + 1, usecols=cols, unpack=True, dtype=np.float64
        )
        return t, omega, temp
    import polars as pl

    df = pl.read_csv(
        path,
        comment_prefix="#",
        columns=["time_s", "omega_dph", "temp_c"],
        schema_overrides={"time_s": pl.Float64, "omega_dph": pl.Float64, "temp_c": pl.Float64},
    )
    return (
        df["time_s"].to_numpy(),
        df["omega_dph"].to_numpy(),
        df["temp_c"].to_numpy(),
    )


# ---- signal processing -----------------------------------------------------------------------


def seconds_to_samples(seconds, dt):
    return max(int(round(seconds / dt)), 1)


def nominal_dt(t):
    n = len(t)
    if n < 2:
        return 1.0
    stride = max(n // 10_000, 1)
    k = np.arange(0, n - 1, stride)
    d = t[k + 1] - t[k]
    d = d[np.isfinite(d) & (d > 0)]
    if len(d) == 0:
        return 1.0
    mid = len(d) // 2
    return float(np.partition(d, mid)[mid])


def moving_average_centered(x, window):
    n = len(x)
    if window <= 1 or n == 0:
        return x.copy()
    back, ahead = (window - 1) // 2, window // 2
    origin = x[0]
    prefix = np.empty(n + 1)
    prefix[0] = 0.0
    np.cumsum(x - origin, out=prefix[1:])
    i = np.arange(n)
    lo = np.maximum(i - back, 0)
    hi = np.minimum(i + ahead, n - 1)
    return origin + (prefix[hi + 1] - prefix[lo]) / (hi + 1 - lo)


def moving_average_valid(x, window):
    n = len(x)
    if window <= 1:
        return x.copy()
    if n < window:
        return np.empty(0)
    c = np.empty(n + 1)
    c[0] = 0.0
    np.cumsum(x - x[0], out=c[1:])
    return x[0] + (c[window:] - c[:-window]) / window


def moving_average_causal(x, window):
    n = len(x)
    window = max(window, 1)
    c = np.empty(n + 1)
    c[0] = 0.0
    np.cumsum(x - x[0], out=c[1:])
    lo = np.maximum(np.arange(1, n + 1) - window, 0)
    count = np.minimum(np.arange(1, n + 1), window)
    return x[0] + (c[1:] - c[lo]) / count


def backward_derivative(x, s, dt):
    s = max(s, 1)
    out = np.zeros_like(x)
    out[2 * s :] = (3.0 * x[2 * s :] - 4.0 * x[s:-s] + x[: -2 * s]) / (2.0 * s * dt)
    return out


def derivatives(temp, smooth, step, dt):
    ts = moving_average_causal(temp, smooth)
    tdot = backward_derivative(ts, step, dt)
    tddot = backward_derivative(tdot, step, dt)
    ready = min(4 * max(step, 1), len(temp))
    tddot[:ready] = 0.0
    return tdot, tddot, ready


# ---- calibration -----------------------------------------------------------------------------


def detect_plateaus(t, tdot, ready):
    limit = PLATEAU_MAX_RATE_C_PER_MIN / 60.0
    quiet = np.abs(tdot) < limit
    quiet[:ready] = False
    edges = np.diff(quiet.astype(np.int8), prepend=0, append=0)
    a = np.flatnonzero(edges == 1)
    b = np.flatnonzero(edges == -1)
    if len(a) == 0:
        return []
    # Bridge short excursions: a run starts a new group when it begins more than bridge_s after
    # the end of the previous run.
    new = np.ones(len(a), dtype=bool)
    new[1:] = t[a[1:]] - t[b[:-1] - 1] > PLATEAU_BRIDGE_S
    starts = np.flatnonzero(new)
    ends = np.append(starts[1:], len(a)) - 1
    ga, gb = a[starts], b[ends]
    keep = (t[gb - 1] - t[ga] >= PLATEAU_MIN_DURATION_S) & (gb - ga >= 2)
    ga, gb = ga[keep], gb[keep]
    # Trim each stretch's end back to its last sample with |Tdot| below a fifth of the limit.
    calm = np.flatnonzero(np.abs(tdot) < limit / 5.0)
    j = np.searchsorted(calm, gb, "left") - 1
    ok = (j >= 0) & (calm[np.maximum(j, 0)] >= ga) if len(calm) else np.zeros(len(ga), bool)
    ga, gb = ga[ok], calm[j[ok]] + 1
    end = t[gb - 1]
    start = end - (end - t[ga]) * PLATEAU_SETTLED_FRACTION
    ok = end > start
    return list(zip(start[ok], end[ok]))


def plateau_points(t, temp, omega, ranges):
    st = np.array([r[0] for r in ranges])
    en = np.array([r[1] for r in ranges])
    lo = np.searchsorted(t, st, "left")
    hi = np.maximum(np.searchsorted(t, en, "right"), lo)
    ok = hi > lo
    lo, hi = lo[ok], hi[ok]
    ct = np.concatenate(([0.0], np.cumsum(temp)))
    cw = np.concatenate(([0.0], np.cumsum(omega)))
    cnt = hi - lo
    return (ct[hi] - ct[lo]) / cnt, (cw[hi] - cw[lo]) / cnt, lo, hi


class Poly:
    """A polynomial held at its edge values outside the fitted x-range (as driftlab's Approx)."""

    def __init__(self, coeffs, lo, hi):
        self.coeffs = np.asarray(coeffs, dtype=float)  # highest power first (np.polyval)
        self.lo, self.hi = float(lo), float(hi)

    @staticmethod
    def fit(x, y, deg, w=None):
        lo, hi = float(x.min()), float(x.max())
        if w is None:
            c = np.polyfit(x, y, deg)
        else:
            c = np.polyfit(x, y, deg, w=np.sqrt(w))
        return Poly(c, lo, hi)

    def __call__(self, x):
        v = np.polyval(self.coeffs, np.clip(x, self.lo, self.hi))
        return np.where(np.isfinite(x), v, 0.0)

    def to_json(self):
        return {"coeffs_low_first": self.coeffs[::-1].tolist(), "x_min": self.lo, "x_max": self.hi}

    @staticmethod
    def from_json(d):
        return Poly(np.asarray(d["coeffs_low_first"])[::-1], d["x_min"], d["x_max"])


def auto_deadband(v, usable):
    stride = max(len(v) // 200_000, 1)
    vs = v[::stride]
    a = np.abs(vs[usable[::stride] & np.isfinite(vs)])
    if len(a) == 0:
        return 0.0
    k = min(int(len(a) * 0.95), len(a) - 1)
    return float(np.partition(a, k)[k]) / 5.0


def fit_set(base, tdot, tddot, in_set, db1, db2):
    """K1 and K2 of one regime with the refinement passes; `base` = omega_f - K0(T)."""
    s1 = in_set & (np.abs(tdot) > db1)
    s2 = in_set & (np.abs(tddot) > db2)
    x1, b1, tdd1 = tdot[s1], base[s1], tddot[s1]
    x2, b2, td2 = tddot[s2], base[s2], tdot[s2]
    k2 = None
    for _ in range(1 + REFINEMENTS):
        y1 = (b1 - (k2(tdd1) * tdd1 if k2 is not None else 0.0)) / x1
        k1 = Poly.fit(x1, y1, 1, w=x1 * x1)
        y2 = (b2 - k1(td2) * td2) / x2
        k2 = Poly.fit(x2, y2, 1, w=x2 * x2)
    return k1, k2, len(x1), len(x2)


def predict(cal, temp, tdot, tddot):
    p = tdot * tddot
    plus, minus = p > 0, p < 0
    pred = cal["k0"](temp)
    pred += np.where(
        plus,
        cal["k1_plus"](tdot) * tdot + cal["k2_plus"](tddot) * tddot,
        np.where(minus, cal["k1_minus"](tdot) * tdot + cal["k2_minus"](tddot) * tddot, 0.0),
    )
    outside = (temp < cal["k0"].lo) | (temp > cal["k0"].hi)
    for name_set, k1, k2 in (
        (plus, cal["k1_plus"], cal["k2_plus"]),
        (minus, cal["k1_minus"], cal["k2_minus"]),
    ):
        outside |= name_set & (
            (tdot < k1.lo) | (tdot > k1.hi) | (tddot < k2.lo) | (tddot > k2.hi)
        )
    return pred, float(outside.mean())


def figures(x, dt, skip):
    x = x[skip:]
    f = moving_average_valid(x, seconds_to_samples(FILTER_S, dt))
    w = seconds_to_samples(MERIT_WINDOW_S, dt)
    m = len(x) // w
    blocks = x[: m * w].reshape(m, w)
    means = blocks.mean(axis=1)
    rms = np.sqrt((blocks * blocks).mean(axis=1))
    return {
        "p2p_dph": float(f.max() - f.min()),
        "std_dph": float(f.std()),
        "mean_dph": float(x.mean()),
        "win_mean_max_abs_dph": float(np.abs(means).max()),
        "win_rms_mean_dph": float(rms.mean()),
    }


def sha256_file(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        while True:
            b = f.read(1 << 20)
            if not b:
                break
            h.update(b)
    return h.hexdigest()


def calibrate(path, out_json):
    with Stage("calibrate.read"):
        t, omega, temp = read_log(path)
    n = len(t)
    with Stage("calibrate.prepare"):
        dt = nominal_dt(t)
        filt = seconds_to_samples(FILTER_S, dt)
        smooth, step = seconds_to_samples(SMOOTH_S, dt), seconds_to_samples(STEP_H_S, dt)
        omega_f = moving_average_centered(omega, filt)
        tdot, tddot, ready = derivatives(temp, smooth, step, dt)
    with Stage("calibrate.plateaus_k0"):
        ranges = detect_plateaus(t, tdot, ready)
        pt, pw, lo, hi = plateau_points(t, temp, omega, ranges)
        k0 = Poly.fit(pt, pw, 2 if len(pt) >= 3 else len(pt) - 1)
        mask = np.zeros(n + 1, dtype=np.int32)
        np.add.at(mask, lo, 1)
        np.add.at(mask, hi, -1)
        on_plateau = np.cumsum(mask[:n]) > 0
    with Stage("calibrate.points_fits"):
        usable = ~on_plateau
        usable[:ready] = False
        db1, db2 = auto_deadband(tdot, usable), auto_deadband(tddot, usable)
        base = omega_f - k0(temp)
        p = tdot * tddot
        k1p, k2p, n1p, n2p = fit_set(base, tdot, tddot, usable & (p > 0), db1, db2)
        k1m, k2m, n1m, n2m = fit_set(base, tdot, tddot, usable & (p < 0), db1, db2)
    cal = {"k0": k0, "k1_plus": k1p, "k1_minus": k1m, "k2_plus": k2p, "k2_minus": k2m}
    with Stage("calibrate.sha256"):
        digest = sha256_file(path)
    with Stage("calibrate.evaluate"):
        # In-sample figures, as `driftlab calibrate` prints them: correct the log (derivatives
        # again, from the calibration's settings) and compare raw and corrected.
        tdot_e, tddot_e, ready_e = derivatives(temp, smooth, step, dt)
        pred, outside = predict(cal, temp, tdot_e, tddot_e)
        cor = omega - pred
        raw_fig, cor_fig = figures(omega, dt, ready_e), figures(cor, dt, ready_e)
    with Stage("calibrate.save"):
        doc = {
            "format": "numpy-pipeline-calibration",
            "source": {"name": os.path.basename(path), "sha256": digest, "samples": n},
            "resolved": {
                "dt_s": dt,
                "filter_samples": filt,
                "smooth_samples": smooth,
                "step_samples": step,
                "deadband_tdot": db1,
                "deadband_tddot": db2,
            },
            "plateaus": len(pt),
            "points": {"k1_plus": n1p, "k2_plus": n2p, "k1_minus": n1m, "k2_minus": n2m},
            "in_sample": {"raw": raw_fig, "corrected": cor_fig, "outside_fraction": outside},
        }
        doc.update({k: v.to_json() for k, v in cal.items()})
        with open(out_json, "w") as f:
            json.dump(doc, f, indent=2)
    return doc


def apply(cal_json, path, out_csv):
    with Stage("apply.load_cal"):
        with open(cal_json) as f:
            doc = json.load(f)
        cal = {k: Poly.from_json(doc[k]) for k in ("k0", "k1_plus", "k1_minus", "k2_plus", "k2_minus")}
        r = doc["resolved"]
    with Stage("apply.read"):
        t, omega, temp = read_log(path)
    with Stage("apply.correct"):
        dt = nominal_dt(t)
        if abs(dt - r["dt_s"]) <= 1e-9 * r["dt_s"]:
            smooth, step = r["smooth_samples"], r["step_samples"]
        else:
            smooth = seconds_to_samples(r["smooth_samples"] * r["dt_s"], dt)
            step = seconds_to_samples(r["step_samples"] * r["dt_s"], dt)
        tdot, tddot, _ = derivatives(temp, smooth, step, dt)
        pred, outside = predict(cal, temp, tdot, tddot)
        cor = omega - pred
    if out_csv is not None:
        with Stage("apply.write"):
            if IO == "numpy":
                np.savetxt(
                    out_csv,
                    np.column_stack((t, omega, pred, cor, temp)),
                    fmt="%.17g",
                    delimiter=",",
                    header="time_s,omega_raw_dph,omega_pred_dph,omega_cor_dph,temp_c",
                    comments="",
                )
                return pred, cor, outside
            import polars as pl

            pl.DataFrame(
                {
                    "time_s": t,
                    "omega_raw_dph": omega,
                    "omega_pred_dph": pred,
                    "omega_cor_dph": cor,
                    "temp_c": temp,
                }
            ).write_csv(out_csv)
    return pred, cor, outside


def check_against(doc, driftlab_cal_path):
    """Prints how far this fit is from driftlab's on the same file (for BENCHMARKS.md)."""
    with open(driftlab_cal_path) as f:
        d = json.load(f)["calibration"]
    print("coefficients, numpy vs driftlab (lowest power first):", file=sys.stderr)
    for k in ("k0", "k1_plus", "k1_minus", "k2_plus", "k2_minus"):
        mine = doc[k]["coeffs_low_first"]
        theirs = d[k]["curve"].get("coeffs")
        print(f"  {k:9} numpy {np.array2string(np.array(mine), precision=6)}"
              f"  driftlab {np.array2string(np.array(theirs), precision=6)}", file=sys.stderr)
    print(f"  dead-bands numpy {doc['resolved']['deadband_tdot']:.6e} "
          f"{doc['resolved']['deadband_tddot']:.6e}  driftlab "
          f"{d['resolved']['deadband_tdot']:.6e} {d['resolved']['deadband_tddot']:.6e}; "
          f"plateaus numpy {doc['plateaus']} driftlab {len(d['plateaus'])}", file=sys.stderr)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("log")
    ap.add_argument("--out-dir", default=None, help="where cal.json and out.csv go (default: a temp dir)")
    ap.add_argument("--no-write", action="store_true", help="skip writing the corrected CSV")
    ap.add_argument("--check", metavar="CAL.json", help="compare with a driftlab calibration")
    ap.add_argument("--io", choices=("polars", "numpy"), default="polars",
                    help="read and write with polars (default) or with numpy's loadtxt/savetxt")
    a = ap.parse_args()
    global IO
    IO = a.io
    import tempfile

    out_dir = a.out_dir or tempfile.mkdtemp(prefix="numpy-pipeline-")
    cal_json = os.path.join(out_dir, "numpy_cal.json")
    out_csv = None if a.no_write else os.path.join(out_dir, "numpy_out.csv")
    t0 = time.perf_counter()
    doc = calibrate(a.log, cal_json)
    t1 = time.perf_counter()
    _, _, outside = apply(cal_json, a.log, out_csv)
    t2 = time.perf_counter()
    TIMES["calibrate.total"] = t1 - t0
    TIMES["apply.total"] = t2 - t1
    compute = sum(v for k, v in TIMES.items() if k in (
        "calibrate.prepare", "calibrate.plateaus_k0", "calibrate.points_fits",
        "calibrate.evaluate", "apply.correct"))
    TIMES["compute_only"] = compute
    TIMES["fit_only"] = sum(TIMES[k] for k in (
        "calibrate.prepare", "calibrate.plateaus_k0", "calibrate.points_fits"))
    info = {
        "numpy": np.__version__,
        "io": IO,
        "polars": __import__("polars").__version__ if IO == "polars" else None,
        "samples": doc["source"]["samples"],
        "plateaus": doc["plateaus"],
        "points": doc["points"],
        "in_sample_p2p_raw_cor": [doc["in_sample"]["raw"]["p2p_dph"], doc["in_sample"]["corrected"]["p2p_dph"]],
        "outside_fraction": outside,
        "seconds": {k: round(v, 4) for k, v in TIMES.items()},
    }
    print(json.dumps(info), file=sys.stderr)
    if a.check:
        check_against(doc, a.check)
    if a.out_dir is None:
        for p in (cal_json, out_csv):
            if p and os.path.exists(p):
                os.remove(p)
        os.rmdir(out_dir)


if __name__ == "__main__":
    main()
