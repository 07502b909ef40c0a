#!/usr/bin/env python3
"""Summarises a bench/run.sh run: medians, ratios and the verdict on each requirement.

    python3 bench/summarize.py WORK_DIR      (WORK_DIR as in bench/run.sh, /tmp/driftlab-bench)

Prints Markdown (bench/run.sh also saves it as WORK_DIR/summary.md).
"""
import glob
import json
import os
import re
import statistics
import sys

# Requirement 4: a frame is 16 ms; "well under" is read as at most half a frame, leaving the
# other half to drawing.
FRAME_MS = 16.0
WELL_UNDER_MS = 8.0


def med(v):
    return statistics.median(v) if v else float("nan")


def main():
    work = sys.argv[1] if len(sys.argv) > 1 else "/tmp/driftlab-bench"
    machine = {}
    for line in open(os.path.join(work, "machine.tsv")):
        k, _, v = line.rstrip("\n").partition("\t")
        machine[k] = v
    runs = {}
    all_runs = {}
    for line in open(os.path.join(work, "runs.tsv")):
        name, k, load, wall, rss_kb, user, sys_, others = line.rstrip("\n").split("\t")
        all_runs.setdefault(name, []).append(
            {"k": int(k), "wall": float(wall), "rss_mb": int(rss_kb) * 1024 / 1e6,
             "load": float(load), "user": float(user), "sys": float(sys_),
             "others": float(others),
             "clean": float(others) <= max(0.1 * float(wall), 0.05)}
        )
    # The medians use the clean runs (other processes took under 10 % of a core meanwhile)
    # when there are at least 3 of them, else every run.
    runs = {}
    for name, v in all_runs.items():
        clean = [r for r in v if r["clean"]]
        runs[name] = clean if len(clean) >= 3 else v

    def wall(name):
        return med([r["wall"] for r in runs.get(name, [])])

    def rss(name, how=med):
        v = [r["rss_mb"] for r in all_runs.get(name, [])]
        return how(v) if v else float("nan")

    out = []
    p = out.append
    rows = int(machine.get("rows", "0"))
    p(f"# driftlab benchmarks, {machine.get('date', '?')}")
    p("")
    p(f"Machine: {machine.get('nproc')} cores, {machine.get('cpu')}, {machine.get('mem')}, "
      f"Linux {machine.get('kernel')}; {machine.get('rustc')}; {machine.get('python')}, "
      f"polars {machine.get('polars')}, numpy {machine.get('numpy')}; driftlab at "
      f"{machine.get('git')}.")
    p(f"Log: {rows:,} rows, {int(machine.get('bytes', 0)) / 1e6:.1f} MB; "
      f"{machine.get('runs')} measured runs per command after one warm-up run.")
    n_all = sum(len(v) for v in all_runs.values())
    n_clean = sum(r["clean"] for v in all_runs.values() for r in v)
    p(f"{n_clean} of {n_all} measured runs were clean (other processes used under 10 % of a "
      "core while they ran); medians are over the clean runs of a command when it has at "
      "least 3, peak RSS over all runs.")
    p("")
    p("## Whole-process runs (`/usr/bin/time`)")
    p("")
    p("MB are 10^6 bytes throughout (the budgets of requirement 3 are counted in them too).")
    p("")
    p("| command | median wall s | min..max s | clean runs / runs | median peak RSS MB | max peak RSS MB |")
    p("|---|---|---|---|---|---|")
    for name, v in runs.items():
        w = [r["wall"] for r in v]
        nc = sum(r["clean"] for r in all_runs[name])
        p(f"| {name} | {med(w):.2f} | {min(w):.2f}..{max(w):.2f} | {nc}/{len(all_runs[name])} | "
          f"{rss(name):.0f} | {rss(name, max):.0f} |")
    p("")

    # In-process figures.
    polars_in = []
    pf = os.path.join(work, "polars_inproc.txt")
    if os.path.exists(pf):
        for line in open(pf):
            m = re.search(r" in ([0-9.]+) s", line)
            if m:
                polars_in.append(float(m.group(1)))
    stages = {}
    repeated = {}
    ingest_in = []
    sf = os.path.join(work, "stages.txt")
    if os.path.exists(sf):
        for line in open(sf):
            m = re.match(r"(.+?)\s+([0-9.]+) ms\s+rss before\s+([0-9]+) MB, peak\s+([0-9]+) MB", line)
            if m:
                name = m.group(1).strip()
                stages[name] = (float(m.group(2)), int(m.group(4)))
                if name.startswith("ingest::read_path (run"):
                    ingest_in.append(float(m.group(2)) / 1e3)
                r = re.match(r"(.+) \(run \d+\)$", name)
                if r:
                    repeated.setdefault(r.group(1), []).append(
                        (float(m.group(2)), int(m.group(4))))
    # A stage run several times counts with its median time (and its largest peak).
    for name, v in repeated.items():
        stages[name + " (median)"] = (med([t for t, _ in v]), max(pk for _, pk in v))
        stages[name] = stages[name + " (median)"]
    np_stages = {}
    np_used = {r["k"] for r in runs.get("numpy_pipeline", [])}
    for f in sorted(glob.glob(os.path.join(work, "logs", "numpy_pipeline.*.err"))):
        if int(f.rsplit(".", 2)[-2]) not in np_used:
            continue  # the warm-up, or a run left out of the medians
        for line in open(f):
            if line.startswith("{"):
                for k, v in json.loads(line)["seconds"].items():
                    np_stages.setdefault(k, []).append(v)
    np_med = {k: med(v) for k, v in np_stages.items()}

    pairs = []
    pf2 = os.path.join(work, "paired.tsv")
    if os.path.exists(pf2):
        for line in open(pf2):
            f = line.split()
            if len(f) == 3:
                pairs.append((float(f[1]), float(f[2])))

    p("## Requirements")
    p("")
    # 1. Ingest.
    d_in, pl_in = med(ingest_in), med(polars_in)
    r1_one = d_in / pl_in if pl_in else float("nan")
    d_wp, pl_wp = wall("ingest_only"), wall("polars_read")
    if pairs:
        ratios = sorted(d / q for d, q in pairs)
        r1 = med(ratios)
        p(f"1. **Ingest at most half of polars.read_csv**: {len(pairs)} pairs of reads, each in a "
          f"fresh process, driftlab and polars alternately: driftlab `ingest::read_path` median "
          f"{med([d for d, _ in pairs]):.3f} s, `polars.read_csv` median "
          f"{med([q for _, q in pairs]):.3f} s; ratio per pair {ratios[0]:.2f}..{ratios[-1]:.2f}, "
          f"median {r1:.2f} (needs <= 0.50): **{'met' if r1 <= 0.5 else 'NOT met'}**"
          f"{' (by a margin under 10 %)' if abs(r1 - 0.5) < 0.05 else ''}. "
          f"Repeated reads in one process: {d_in:.3f} s vs {pl_in:.3f} s, ratio "
          f"{r1_one:.2f}. Whole process (ingest-only process vs `python3 bench/polars_read.py`, "
          f"interpreter start and imports included): {d_wp:.2f} s vs {pl_wp:.2f} s, ratio "
          f"{d_wp / pl_wp:.2f}.")
    else:
        p(f"1. **Ingest at most half of polars.read_csv**: repeated reads in one process: "
          f"driftlab {d_in:.3f} s, polars {pl_in:.3f} s, ratio {r1_one:.2f}: "
          f"**{'met' if r1_one <= 0.5 else 'NOT met'}**. Whole process: {d_wp:.2f} s vs "
          f"{pl_wp:.2f} s, ratio {d_wp / pl_wp:.2f}.")
    # 2. calibrate + apply.
    d_cal, d_app, np_wall = wall("calibrate"), wall("apply"), wall("numpy_pipeline")
    if np_wall == np_wall:
        r2 = np_wall / (d_cal + d_app)
        line = (f"2. **calibrate + apply at least 20x faster than numpy**: whole process, "
                f"driftlab {d_cal:.2f} + {d_app:.2f} = {d_cal + d_app:.2f} s, numpy pipeline "
                f"{np_wall:.2f} s: speed-up {r2:.1f}x: **{'met' if r2 >= 20 else 'NOT met'}**.")
        dfit = stages.get("model::fit (whole, as calibrate calls it)", (float("nan"),))[0]
        dev = stages.get("Evaluation::of (in-sample figures)", (float("nan"),))[0]
        dcor = stages.get("Calibration::correct (apply)", (float("nan"),))[0]
        d_compute = (dfit + dev + dcor) / 1e3
        n_compute = np_med.get("compute_only", float("nan"))
        line += (f" Compute only (no reading, hashing or writing; fit + in-sample evaluation + "
                 f"correction): driftlab {d_compute:.2f} s, numpy {n_compute:.2f} s: "
                 f"{n_compute / d_compute:.1f}x.")
        nfit = np_med.get("fit_only", float("nan"))
        line += f" Fit alone: driftlab {dfit / 1e3:.2f} s, numpy {nfit:.2f} s: {nfit / (dfit / 1e3):.1f}x."
        p(line)
    else:
        p("2. numpy pipeline not run (SKIP_NUMPY).")
    # 3. Memory.
    col_mb = rows * 8 / 1e6
    ingest_budget, cmd_budget = 3 * 4 * col_mb, 3 * 3 * col_mb
    p(f"3. **Peak memory at most 3x the f64 columns**: one column of {rows:,} f64 is "
      f"{col_mb:.0f} MB. Ingest (4 columns, budget {ingest_budget:.0f} MB): ingest-only process "
      f"{rss('ingest_only', max):.0f} MB, `inspect` {rss('inspect', max):.0f} MB: "
      f"**{'met' if rss('ingest_only', max) <= ingest_budget else 'NOT met'}** for ingest. "
      f"calibrate and apply use 3 of the columns (time, rate, temperature; budget "
      f"{cmd_budget:.0f} MB; {ingest_budget:.0f} MB if the 4 columns ingest keeps are counted): "
      f"calibrate {rss('calibrate', max):.0f} MB "
      f"(**{'met' if rss('calibrate', max) <= cmd_budget else 'NOT met'}**"
      f"{'' if rss('calibrate', max) <= cmd_budget else (', ' + ('met' if rss('calibrate', max) <= ingest_budget else 'not met') + ' with 4 columns')}), "
      f"apply {rss('apply', max):.0f} MB "
      f"(**{'met' if rss('apply', max) <= cmd_budget else 'NOT met'}**"
      f"{'' if rss('apply', max) <= cmd_budget else (', ' + ('met' if rss('apply', max) <= ingest_budget else 'not met') + ' with 4 columns')}).")
    # 4. Live loop.
    crit = {}
    cf = os.path.join(work, "criterion.txt")
    if os.path.exists(cf):
        name = None
        for line in open(cf):
            m = re.match(r"^(\S+/\S+)", line)
            if m:
                name = m.group(1)
            t = re.search(r"time:\s+\[([0-9.]+) (\w+) ([0-9.]+) (\w+) ([0-9.]+) (\w+)\]", line)
            if t and name:
                scale = {"ns": 1e-6, "µs": 1e-3, "us": 1e-3, "ms": 1.0, "s": 1e3}[t.group(4)]
                crit[name] = float(t.group(3)) * scale
    frames = {k: v for k, v in crit.items() if k.startswith(("live/frame", "live/pipeline"))}
    if frames:
        worst = max(frames.values())
        verdict = ("met" if worst <= WELL_UNDER_MS else
                   ("under a frame but not well under" if worst < FRAME_MS else "NOT met"))
        p(f"4. **Live loop well under a frame (16 ms) on 1M samples**: "
          + ", ".join(f"`{k}` {v:.1f} ms" for k, v in frames.items())
          + f": **{verdict}** (read as <= {WELL_UNDER_MS:.0f} ms, half a frame).")
    else:
        p("4. criterion not run (SKIP_CRITERION).")
    p("")
    if crit:
        p("## Criterion (1M samples, median estimate)")
        p("")
        p("| benchmark | ms |")
        p("|---|---|")
        for k, v in crit.items():
            p(f"| {k} | {v:.2f} |")
        p("")
    if stages:
        p("## driftlab stages in one process (`DRIFTLAB_STAGES`)")
        p("")
        p("| stage | ms | peak RSS MB |")
        p("|---|---|---|")
        for k, (ms, peak) in stages.items():
            if k + " (median)" in stages:
                continue  # printed once, as "(median)"
            p(f"| {k} | {ms:.1f} | {peak} |")
        p("")
    if np_med:
        p("## numpy pipeline stages (median over runs)")
        p("")
        p("| stage | s |")
        p("|---|---|")
        for k, v in np_med.items():
            p(f"| {k} | {v:.3f} |")
        p("")
    chk = os.path.join(work, "numpy_check.txt")
    if os.path.exists(chk):
        p("## numpy against driftlab (same file)")
        p("")
        p("```")
        p("".join(l for l in open(chk) if not l.startswith("{")).rstrip())
        p("```")
    print("\n".join(out))


if __name__ == "__main__":
    main()
