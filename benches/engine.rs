//! Engine benchmarks (BENCHMARKS.md).
//!
//! ```text
//! cargo bench --no-default-features --bench engine              # criterion, 1M samples
//! cargo bench --no-default-features --bench engine -- live      # only the live loop
//! cargo bench --no-default-features --bench engine -- live_unit # the live loop of a unit
//! DRIFTLAB_STAGES=/tmp/big.csv cargo bench --no-default-features --bench engine
//! ```
//!
//! The criterion benchmarks run on a 1-million-sample log: the simulator's `calibration`
//! profile (40 201 samples at 1 Hz) tiled with time continuing, as `examples/make_big_log.rs`
//! writes it. They cover ingest (CSV written into a temporary folder), `vakhrameev::fit`,
//! `Calibration::correct`, and the workbench's live loop (requirement 4: well under 16 ms), in
//! two forms: at engine level (refit one approximation with `approx::fit_weighted`, correct the
//! log again with `correct_with` and the derivatives already known), and as the GUI runs it,
//! `refit::Pipeline::run` after one change (an approximation's kind, a knot dragged by hand),
//! with everything the change leaves alone kept from the run before.
//!
//! With `DRIFTLAB_STAGES=FILE` the benchmark instead times, once each, the stages that
//! `driftlab calibrate` and `driftlab apply` go through on that file, with the peak resident
//! memory of each stage (from `/proc/self/status`, reset between stages through
//! `/proc/self/clear_refs`), so that the whole-process numbers of `bench/run.sh` can be taken
//! apart (`DRIFTLAB_STAGES_INGEST_REPEAT=N` reads the file N times first, default 3, and
//! `DRIFTLAB_STAGES_INGEST_ONLY=1` stops there; `DRIFTLAB_STAGES_REPEAT=N` repeats the fit,
//! the evaluation and the correction, default 3). No timing here is an assertion: these are
//! measurements.

#[path = "common/live_scenarios.rs"]
mod live_scenarios;
#[path = "common/tiled_log.rs"]
mod tiled_log;
use tiled_log::tiled_log;

use criterion::{Criterion, Throughput};
use driftlab::Log;
use driftlab::files::session::{Coefficient, KnotEdits};
use driftlab::judge::metrics::{Evaluation, MeritOptions};
use driftlab::log::ingest::{self, ReadOptions};
use driftlab::models::approx::{self, Approx, ApproxKind, ApproxSpec};
use driftlab::models::recipe::Recipe;
use driftlab::models::vakhrameev::correct::Correction;
use driftlab::models::vakhrameev::{self, Calibration, Fit, PointSet, Regime};
use driftlab::refit::{Pipeline, Request};
use driftlab::signal::plateau::PlateauRange;
use std::fmt::Write as _;
use std::hint::black_box;
use std::io::Write;
use std::path::Path;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Samples of the benchmark log.
const ROWS: usize = 1_000_000;

/// Writes a log as `SimRun::write_csv` does (rate to 0.0001, temperatures to 0.001).
fn write_csv(log: &Log, path: &Path) {
    let f = std::fs::File::create(path).expect("create bench CSV");
    let mut w = std::io::BufWriter::with_capacity(1 << 20, f);
    let chamber = &log.extra[0].values;
    let mut line = String::with_capacity(64);
    w.write_all(b"# driftlab bench\ntime_s,omega_dph,temp_c,temp_chamber_c\n")
        .expect("write");
    for (i, chamber) in chamber.iter().enumerate() {
        line.clear();
        let _ = writeln!(
            line,
            "{},{:.4},{:.3},{:.3}",
            log.time_s[i], log.omega_dph[i], log.temp_c[i], chamber
        );
        w.write_all(line.as_bytes()).expect("write");
    }
    w.flush().expect("flush");
}

/// Drift weighting (the default recipe's): each pointwise coefficient weighted by its
/// denominator squared, as `model` does before `fit_or_fallback_weighted`.
fn drift_weights(p: &PointSet) -> Vec<f64> {
    p.x.iter().map(|x| x * x).collect()
}

fn refit(spec: &ApproxSpec, p: &PointSet) -> Approx {
    let w = drift_weights(p);
    approx::fit_weighted(spec, &p.x, &p.y, Some(&w)).expect("refit")
}

/// What the workbench keeps between frames of the live loop.
struct Live {
    log: Log,
    fit: Fit,
    mask: Vec<bool>,
}

impl Live {
    fn new(log: Log) -> Live {
        let fit = vakhrameev::fit(&log, &driftlab::models::CheckedRecipe::default()).expect("fit");
        let ranges: Vec<PlateauRange> = fit.calibration.plateaus.iter().map(|p| p.range).collect();
        let mask = driftlab::signal::plateau::mask(&log.time_s, &ranges);
        Live { log, fit, mask }
    }

    /// The derivatives a correction of the log uses (the calibration's own settings).
    fn correction_derivatives(&self) -> driftlab::signal::Derivatives {
        let cal = &self.fit.calibration;
        let dt = self.log.nominal_dt_s();
        driftlab::signal::derivatives(&self.log.temp_c, cal.steps_for(dt), dt)
    }

    /// Frame type A: the engineer changes K2+; refit it, then correct again.
    fn frame_k2_plus(&self, deriv: &driftlab::signal::Derivatives) -> Correction {
        let mut cal = self.fit.calibration.clone();
        cal.k2_plus = refit(&cal.recipe.k2_plus, &self.fit.k2_plus_points);
        cal.correct_with(&self.log, deriv)
    }

    /// Frame type B: the engineer changes K1+; refit it, recompute the K2 points from the new
    /// K1 and refit both K2 (K2− does not depend on K1+, but a workbench that refits "the K2s
    /// after a K1" does this), then correct again.
    fn frame_k1_plus(&self, deriv: &driftlab::signal::Derivatives) -> Correction {
        let mut cal = self.fit.calibration.clone();
        let prepared = &self.fit.prepared;
        let db2 = cal.resolved.deadband_tddot;
        cal.k1_plus = refit(&cal.recipe.k1_plus, &self.fit.k1_plus_points);
        let (p2p, p2m) = rayon::join(
            || {
                k2_points(
                    &self.log,
                    prepared,
                    &self.mask,
                    &cal.k0,
                    &cal.k1_plus,
                    db2,
                    Regime::Plus,
                )
            },
            || {
                k2_points(
                    &self.log,
                    prepared,
                    &self.mask,
                    &cal.k0,
                    &cal.k1_minus,
                    db2,
                    Regime::Minus,
                )
            },
        );
        cal.k2_plus = refit(&cal.recipe.k2_plus, &p2p);
        cal.k2_minus = refit(&cal.recipe.k2_minus, &p2m);
        cal.correct_with(&self.log, deriv)
    }
}

/// `Ω_cor = Ω − pred` for every sample into buffers that already exist.
fn predict_into(
    cal: &Calibration,
    log: &Log,
    deriv: &driftlab::signal::Derivatives,
    pred: &mut [f64],
    cor: &mut [f64],
) {
    for (i, (p, q)) in pred.iter_mut().zip(cor.iter_mut()).enumerate() {
        *p = cal.predict(log.temp_c[i], deriv.tdot[i], deriv.tddot[i]).0;
        *q = log.omega_dph[i] - *p;
    }
}

/// A polynomial approximation flattened for a tight loop: three coefficients (zero-padded),
/// clamped to the fitted range unless it extrapolates.
#[derive(Clone, Copy)]
struct Flat {
    c: [f64; 3],
    lo: f64,
    hi: f64,
}

impl Flat {
    fn of(a: &Approx) -> Option<Flat> {
        let approx::Curve::Polynomial { coeffs } = a.curve() else {
            return None;
        };
        if coeffs.len() > 3 {
            return None;
        }
        let mut c = [0.0; 3];
        c[..coeffs.len()].copy_from_slice(coeffs);
        let (lo, hi) = if a.extrapolates() {
            (f64::NEG_INFINITY, f64::INFINITY)
        } else {
            (a.x_min(), a.x_max())
        };
        Some(Flat { c, lo, hi })
    }

    #[inline(always)]
    fn eval(&self, x: f64) -> f64 {
        let u = x.clamp(self.lo, self.hi);
        let v = (self.c[2] * u + self.c[1]) * u + self.c[0];
        if x.is_finite() { v } else { 0.0 }
    }
}

/// What the per-sample evaluation costs without `Approx::eval`'s generality: the default
/// recipe's curves are all polynomials, flattened; the result equals `Calibration::predict`.
fn predict_flat(
    f: &[Flat; 5],
    log: &Log,
    deriv: &driftlab::signal::Derivatives,
    pred: &mut [f64],
    cor: &mut [f64],
) {
    let [k0, k1p, k1m, k2p, k2m] = f;
    for (i, (p, q)) in pred.iter_mut().zip(cor.iter_mut()).enumerate() {
        let (t, td, tdd) = (log.temp_c[i], deriv.tdot[i], deriv.tddot[i]);
        let r = td * tdd;
        let (k1, k2) = if r > 0.0 { (k1p, k2p) } else { (k1m, k2m) };
        let dyn_part = k1.eval(td) * td + k2.eval(tdd) * tdd;
        *p = k0.eval(t) + if r != 0.0 { dyn_part } else { 0.0 };
        *q = log.omega_dph[i] - *p;
    }
}

fn benches(c: &mut Criterion) {
    let log = tiled_log(ROWS);

    // Ingest of a 1M-row CSV written into a temporary folder.
    let dir = tempfile::tempdir().expect("tempdir");
    let csv = dir.path().join("bench_1m.csv");
    write_csv(&log, &csv);
    let bytes = std::fs::metadata(&csv).expect("csv").len();
    {
        let mut g = c.benchmark_group("ingest");
        g.sample_size(10).measurement_time(Duration::from_secs(5));
        g.throughput(Throughput::Bytes(bytes));
        g.bench_function("read_path_1M_rows", |b| {
            b.iter(|| ingest::read_path(black_box(&csv), &ReadOptions::default()).expect("read"))
        });
        g.finish();
    }

    let recipe = Recipe::default();
    {
        let mut g = c.benchmark_group("model");
        g.sample_size(10).measurement_time(Duration::from_secs(5));
        g.throughput(Throughput::Elements(ROWS as u64));
        g.bench_function("fit_1M", |b| {
            b.iter(|| {
                vakhrameev::fit(black_box(&log), &recipe.clone().checked().unwrap()).expect("fit")
            })
        });
        g.bench_function("prepared_new_1M", |b| {
            b.iter(|| vakhrameev::Prepared::new(black_box(&log), &recipe))
        });
        g.finish();
    }

    let live = Live::new(log);
    let cal: &Calibration = &live.fit.calibration;
    {
        let mut g = c.benchmark_group("correct");
        g.sample_size(20).measurement_time(Duration::from_secs(4));
        g.throughput(Throughput::Elements(ROWS as u64));
        g.bench_function("correct_1M", |b| {
            b.iter(|| cal.correct(black_box(&live.log)))
        });
        g.finish();
    }

    // The live loop (requirement 4). Criterion times the whole frame; the parts are timed too
    // so that BENCHMARKS.md can say where a frame goes.
    let deriv = live.correction_derivatives();
    {
        let mut g = c.benchmark_group("live");
        g.sample_size(20).measurement_time(Duration::from_secs(4));
        g.bench_function("frame_refit_k2p_correct_1M", |b| {
            b.iter(|| live.frame_k2_plus(&deriv))
        });
        g.bench_function("frame_refit_k1p_then_k2_correct_1M", |b| {
            b.iter(|| live.frame_k1_plus(&deriv))
        });
        // Parts of a frame.
        g.bench_function("part_refit_k2p", |b| {
            b.iter(|| refit(&cal.recipe.k2_plus, black_box(&live.fit.k2_plus_points)))
        });
        g.bench_function("part_refit_k1p", |b| {
            b.iter(|| refit(&cal.recipe.k1_plus, black_box(&live.fit.k1_plus_points)))
        });
        g.bench_function("part_k2_points_plus_1M", |b| {
            b.iter(|| {
                k2_points(
                    &live.log,
                    &live.fit.prepared,
                    &live.mask,
                    &cal.k0,
                    &cal.k1_plus,
                    cal.resolved.deadband_tddot,
                    Regime::Plus,
                )
            })
        });
        // A lower bound for the correction: the same per-sample model evaluation
        // (`Calibration::predict`) into buffers kept from frame to frame, no clone, no
        // allocation; sequential and over rayon's threads.
        let n = live.log.len();
        let (mut pred, mut cor) = (vec![0.0; n], vec![0.0; n]);
        g.bench_function("part_predict_into_kept_buffers_1M_seq", |b| {
            b.iter(|| {
                predict_into(cal, &live.log, &deriv, &mut pred, &mut cor);
            })
        });
        g.bench_function("part_predict_into_kept_buffers_1M_par", |b| {
            b.iter(|| {
                use rayon::prelude::*;
                const CHUNK: usize = 1 << 15;
                pred.par_chunks_mut(CHUNK)
                    .zip(cor.par_chunks_mut(CHUNK))
                    .enumerate()
                    .for_each(|(c, (p, q))| {
                        let base = c * CHUNK;
                        for k in 0..p.len() {
                            let i = base + k;
                            p[k] = cal
                                .predict(live.log.temp_c[i], deriv.tdot[i], deriv.tddot[i])
                                .0;
                            q[k] = live.log.omega_dph[i] - p[k];
                        }
                    });
            })
        });
        let flat = [
            &cal.k0,
            &cal.k1_plus,
            &cal.k1_minus,
            &cal.k2_plus,
            &cal.k2_minus,
        ]
        .map(Flat::of);
        if let [Some(a), Some(b), Some(c2), Some(d), Some(e)] = flat {
            let flat = [a, b, c2, d, e];
            // The flattened loop must give what `predict` gives, or it measures something else.
            let (mut p2, mut q2) = (vec![0.0; n], vec![0.0; n]);
            predict_flat(&flat, &live.log, &deriv, &mut p2, &mut q2);
            predict_into(cal, &live.log, &deriv, &mut pred, &mut cor);
            let worst = p2
                .iter()
                .zip(&pred)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(worst < 1e-9, "flattened prediction differs by {worst}");
            g.bench_function("part_predict_flat_polynomials_1M_seq", |b| {
                b.iter(|| predict_flat(&flat, &live.log, &deriv, &mut p2, &mut q2))
            });
        }
        g.bench_function("part_correct_with_1M", |b| {
            b.iter(|| cal.correct_with(&live.log, black_box(&deriv)))
        });
        g.finish();
    }
    pipeline_benches(c, Arc::new(live.log.clone()));
    drop(dir);
}

/// The workbench's own live loop, `refit::Pipeline::run`, after one change the engineer makes:
/// every stage whose inputs did not change is kept from the run before, as in the GUI. Each
/// iteration toggles between two states so that every run has something to redo.
fn pipeline_benches(c: &mut Criterion, log: Arc<Log>) {
    let scenarios = live_scenarios::scenarios(&log);
    let mut g = c.benchmark_group("live");
    g.sample_size(20).measurement_time(Duration::from_secs(4));
    for (name, reqs) in &scenarios {
        let mut p = Pipeline::new();
        let mut flip = 0;
        // One run of each state first, so that the timed runs find what the GUI would keep.
        for r in reqs {
            p.run(r).expect("pipeline");
        }
        // Back to the first state: a run with one change, as every timed run below is.
        let t = p.run(&reqs[0]).expect("pipeline").timings;
        println!(
            "{name}: one run: prepare {:.2} ms, plateaus {:.2}, fit {:.2}, correct {:.2}, \
             evaluate {:.2}, total {:.2}",
            t.prepare_ms, t.plateaus_ms, t.fit_ms, t.correct_ms, t.evaluate_ms, t.total_ms
        );
        g.bench_function(format!("pipeline_{name}_1M"), |b| {
            b.iter(|| {
                flip ^= 1;
                p.run(&reqs[flip]).expect("pipeline")
            })
        });
    }
    // What a plateau edge drag computes each frame until its release: the plateaus'
    // statistics and K0 (`refit::preview_plateaus`), the last plateau's start moved by a minute
    // and back.
    let recipe = Recipe::default();
    let ranges = Pipeline::new()
        .run(&Request {
            log: log.clone(),
            recipe: recipe.clone(),
            merit: MeritOptions::default(),
            validation: None,
        })
        .expect("pipeline")
        .ranges;
    let moved: [Vec<PlateauRange>; 2] = [0.0, 60.0].map(|shift_s| {
        let mut r = ranges.clone();
        if let Some(last) = r.last_mut() {
            last.start_s += shift_s;
        }
        r
    });
    let mut flip = 0;
    g.bench_function("plateau_edge_dragged_1M", |b| {
        b.iter(|| {
            flip ^= 1;
            driftlab::refit::preview_plateaus(&log, &moved[flip], &recipe).expect("preview")
        })
    });
    g.finish();
}

/// The live loop of a unit as the workbench runs it: a three-axis log of 1M samples per axis
/// (the simulator's calibration run at 25 Hz, written as CSV and read back as the workbench
/// reads it), one view per axis (its rate in `omega_dph`, no other axis) and one warm
/// `refit::Pipeline` per axis. An edit of one axis runs that axis's pipeline alone; the other
/// two stay resident beside it, as in the workbench. `live/plateau_edge_released_unit3_1M`
/// is what follows the release of a plateau edge: the three axes refitted on the shared
/// plateaus as the worker runs them (`refit::run_unit`: the sets and the T part of their
/// moments made once) (`live_unit/plateau_moved_all_axes_1M`:
/// one after the other).
fn unit_pipeline_benches(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("imu3-25hz.csv");
    let profile = driftlab::sim::profile("calibration")
        .expect("the calibration profile")
        .with_axes(3)
        .expect("three axes");
    let logging = driftlab::sim::Logging {
        rate_hz: Some(25.0),
        ..Default::default()
    };
    let run = driftlab::sim::simulate_logged(&profile, 1, &logging, &|_| {}).expect("simulate");
    run.write_csv(&path).expect("write the unit's log");
    drop(run);
    let log = ingest::read_path(&path, &ReadOptions::default()).expect("read the unit's log");
    let names = log.axis_names();
    assert_eq!(names.len(), 3, "three gyro axes read: {names:?}");
    println!(
        "unit log: {} samples per axis, axes {}",
        log.len(),
        names.join(", ")
    );
    let views: Vec<Arc<Log>> = names
        .iter()
        .map(|n| {
            let mut v = log.clone();
            v.select_axis(n);
            v.other_axes.clear();
            Arc::new(v)
        })
        .collect();
    drop(log);
    let request = |k: usize, recipe: &Recipe, knots: KnotEdits| {
        let mut recipe = recipe.clone();
        knots
            .fold_into(&mut recipe)
            .expect("the recipe sets no values of its own");
        Request {
            log: views[k].clone(),
            recipe,
            merit: MeritOptions::default(),
            validation: None,
        }
    };
    let pwl = Recipe {
        k1_plus: ApproxSpec::of(ApproxKind::Pwl),
        k2_plus: ApproxSpec::of(ApproxKind::Pwl),
        ..Recipe::default()
    };
    let mut pipes: Vec<Pipeline> = (0..3).map(|_| Pipeline::new()).collect();
    let mut fitted = Vec::new();
    for (k, p) in pipes.iter_mut().enumerate() {
        fitted.push(
            p.run(&request(k, &pwl, KnotEdits::default()))
                .expect("pipeline"),
        );
    }
    let edited = 1;
    let dragged = |c: Coefficient, a: &Approx| {
        let mut v = a.knots().1.to_vec();
        let j = v.len() / 2;
        v[j] += 0.05 * (v[j].abs() + 1.0);
        let mut k = KnotEdits::default();
        k.set(c, Some(v));
        k
    };
    // As `live/pipeline_k2p_kind_changed_1M`: from the default recipe, K2+ made parabolic.
    let base = Recipe::default();
    let mut other_k2p = base.clone();
    other_k2p.k2_plus.kind = ApproxKind::Parabolic;
    // A plateau edge moved by a minute (the plateaus as the detector found them, by hand).
    let ranges = fitted[edited].ranges.clone();
    let manual = |shift_s: f64| {
        let mut r = pwl.clone();
        let mut ranges = ranges.clone();
        if let Some(last) = ranges.last_mut() {
            last.start_s += shift_s;
        }
        r.plateaus = driftlab::models::recipe::PlateauChoice::Manual { ranges };
        r
    };
    let (a, b) = (manual(0.0), manual(60.0));
    let cal = &fitted[edited].calibration;
    let scenarios: Vec<(&str, [Request; 2])> = vec![
        (
            "nothing_changed_1M",
            [
                request(edited, &pwl, KnotEdits::default()),
                request(edited, &pwl, KnotEdits::default()),
            ],
        ),
        (
            "k2p_knot_dragged_1M",
            [
                request(edited, &pwl, KnotEdits::default()),
                request(edited, &pwl, dragged(Coefficient::K2Plus, &cal.k2_plus)),
            ],
        ),
        (
            "k1p_knot_dragged_1M",
            [
                request(edited, &pwl, KnotEdits::default()),
                request(edited, &pwl, dragged(Coefficient::K1Plus, &cal.k1_plus)),
            ],
        ),
        (
            "k2p_kind_changed_1M",
            [
                request(edited, &base, KnotEdits::default()),
                request(edited, &other_k2p, KnotEdits::default()),
            ],
        ),
        (
            "plateau_moved_1M",
            [
                request(edited, &a, KnotEdits::default()),
                request(edited, &b, KnotEdits::default()),
            ],
        ),
    ];
    // The outcomes held here would keep buffers the pipelines reuse once they are dropped.
    drop(fitted);
    let mut g = c.benchmark_group("live_unit");
    g.sample_size(20).measurement_time(Duration::from_secs(4));
    for (name, reqs) in &scenarios {
        let p = &mut pipes[edited];
        for r in reqs {
            p.run(r).expect("pipeline");
        }
        let t = p.run(&reqs[0]).expect("pipeline").timings;
        println!(
            "live_unit/{name} (axis {}): one run: prepare {:.2} ms, plateaus {:.2}, fit {:.2}, \
             correct {:.2}, evaluate {:.2}, total {:.2}",
            names[edited],
            t.prepare_ms,
            t.plateaus_ms,
            t.fit_ms,
            t.correct_ms,
            t.evaluate_ms,
            t.total_ms
        );
        let mut flip = 0;
        g.bench_function(*name, |bench| {
            bench.iter(|| {
                flip ^= 1;
                p.run(&reqs[flip]).expect("pipeline")
            })
        });
    }
    // The release of a plateau edge: every axis refitted on the shared plateaus.
    let all: [Vec<Request>; 2] = [
        (0..3)
            .map(|k| request(k, &a, KnotEdits::default()))
            .collect(),
        (0..3)
            .map(|k| request(k, &b, KnotEdits::default()))
            .collect(),
    ];
    for state in &all {
        for (p, r) in pipes.iter_mut().zip(state) {
            p.run(r).expect("pipeline");
        }
    }
    let mut flip = 0;
    g.bench_function("plateau_moved_all_axes_1M", |bench| {
        bench.iter(|| {
            flip ^= 1;
            for (p, r) in pipes.iter_mut().zip(&all[flip]) {
                black_box(p.run(r).expect("pipeline"));
            }
        })
    });
    g.finish();
    // The release as the workbench's worker runs it (`refit::run_unit`): the first axis's
    // plateau stage, then every axis's sets fitted together on the sets' samples it made.
    let mut g = c.benchmark_group("live");
    g.sample_size(20).measurement_time(Duration::from_secs(4));
    let mut flip = 0;
    g.bench_function("plateau_edge_released_unit3_1M", |bench| {
        bench.iter(|| {
            flip ^= 1;
            for out in driftlab::refit::run_unit(&mut pipes, &all[flip]) {
                black_box(out.expect("pipeline"));
            }
        })
    });
    g.finish();
    println!(
        "resident after the unit benchmarks: {:.0} MB",
        current_rss_mb()
    );
}

// ---- stages of the two commands on a big file ---------------------------------------------

/// Peak resident memory since the last reset, MB (10^6 bytes, as BENCHMARKS.md counts).
fn peak_rss_mb() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok())
        .map_or(f64::NAN, |kb| kb * 1024.0 / 1e6)
}

fn current_rss_mb() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmRSS:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<f64>().ok())
        .map_or(f64::NAN, |kb| kb * 1024.0 / 1e6)
}

/// Resets the peak to the current resident size (Linux: "5" to clear_refs).
fn reset_peak() {
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

fn stage<T>(name: &str, f: impl FnOnce() -> T) -> T {
    reset_peak();
    let before = current_rss_mb();
    let t0 = Instant::now();
    let v = f();
    let s = t0.elapsed().as_secs_f64();
    println!(
        "{name:<44} {:>9.1} ms   rss before {:>7.0} MB, peak {:>7.0} MB, after {:>7.0} MB",
        s * 1e3,
        before,
        peak_rss_mb(),
        current_rss_mb()
    );
    v
}

fn stages(path: &Path) {
    println!(
        "stages of `driftlab calibrate` and `driftlab apply` on {} ({} rayon threads)",
        path.display(),
        rayon::current_num_threads()
    );
    let recipe = Recipe::default();
    // Ingest several times (the first may pay for pages the process never touched yet); the
    // median is the figure BENCHMARKS.md compares with polars.
    let repeat: usize = std::env::var("DRIFTLAB_STAGES_INGEST_REPEAT")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3)
        .max(1);
    let mut times = Vec::new();
    let mut log = Log::default();
    for k in 0..repeat {
        drop(std::mem::take(&mut log));
        let t0 = Instant::now();
        log = stage(&format!("ingest::read_path (run {})", k + 1), || {
            ingest::read_path(path, &ReadOptions::default()).expect("read")
        });
        times.push(t0.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    println!(
        "  {} samples; ingest median of {repeat}: {:.1} ms",
        log.len(),
        times[times.len() / 2] * 1e3
    );
    if std::env::var_os("DRIFTLAB_STAGES_INGEST_ONLY").is_some() {
        return;
    }

    // vakhrameev::fit, stage by stage (the same calls `vakhrameev::fit` makes).
    let t_fit = Instant::now();
    let prepared = stage("fit: Prepared::new (filter, derivatives)", || {
        vakhrameev::Prepared::new(&log, &recipe)
    });
    let ranges = stage("fit: plateau_ranges", || {
        let d = &prepared.deriv;
        driftlab::signal::plateau::ranges(&recipe.plateaus, &log.time_s, &d.tdot, &d.ready)
    });
    let mut warnings = Vec::new();
    let k0 = stage("fit: plateau_stats + fit_k0", || {
        let stats =
            driftlab::signal::plateau::stats_of(&log.time_s, &log.temp_c, &log.omega_dph, &ranges);
        vakhrameev::fit_k0(&stats, &recipe.k0, &mut warnings).expect("k0")
    });
    let mask = stage("fit: plateau_mask", || {
        driftlab::signal::plateau::mask(&log.time_s, &ranges)
    });
    let (db1, db2) = stage("fit: deadbands", || {
        vakhrameev::deadbands(&prepared, &mask, &recipe)
    });
    for (regime, s1, s2) in [
        (Regime::Plus, &recipe.k1_plus, &recipe.k2_plus),
        (Regime::Minus, &recipe.k1_minus, &recipe.k2_minus),
    ] {
        let mut k2: Option<Approx> = None;
        for pass in 0..=recipe.refinements {
            let p1 = stage(&format!("fit: k1_points {regime:?} pass {pass}"), || {
                k1_points(&log, &prepared, &mask, &k0, k2.as_ref(), db1, regime)
            });
            let k1 = stage(
                &format!("fit: fit K1 {regime:?} pass {pass} ({} pts)", p1.len()),
                || refit(s1, &p1),
            );
            let p2 = stage(&format!("fit: k2_points {regime:?} pass {pass}"), || {
                k2_points(&log, &prepared, &mask, &k0, &k1, db2, regime)
            });
            k2 = Some(stage(
                &format!("fit: fit K2 {regime:?} pass {pass} ({} pts)", p2.len()),
                || refit(s2, &p2),
            ));
        }
    }
    println!(
        "  (stages of the fit above: {:.1} ms in all)",
        t_fit.elapsed().as_secs_f64() * 1e3
    );
    drop(prepared);
    drop(mask);

    // The three compute stages of the two commands, several times (the median is what
    // BENCHMARKS.md compares with numpy): `DRIFTLAB_STAGES_REPEAT`, default 3.
    let repeat_compute: usize = std::env::var("DRIFTLAB_STAGES_REPEAT")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3)
        .max(1);
    let mut fit = None;
    for k in 0..repeat_compute {
        drop(fit.take());
        fit = Some(stage(
            &format!(
                "vakhrameev::fit (whole, with the point sets) (run {})",
                k + 1
            ),
            || vakhrameev::fit(&log, &recipe.clone().checked().unwrap()).expect("fit"),
        ));
    }
    let fit = fit.expect("at least one fit");
    let cal = fit.calibration.clone();
    drop(fit);
    for k in 0..repeat_compute {
        stage(
            &format!(
                "vakhrameev::calibrate (lean, as calibrate calls it) (run {})",
                k + 1
            ),
            || vakhrameev::fit_lean(&log, &recipe.clone().checked().unwrap()).expect("calibrate"),
        );
    }
    stage("calfile::sha256_file", || {
        driftlab::files::calibration::sha256_file(path).expect("sha")
    });
    let dir = tempfile::tempdir_in(std::env::temp_dir()).expect("tempdir");
    stage("calfile::save", || {
        driftlab::files::calibration::save(&dir.path().join("cal.json"), &cal).expect("save")
    });
    let opts = MeritOptions {
        filter_s: recipe.filter_s,
        ..MeritOptions::default()
    };
    for k in 0..repeat_compute {
        stage(
            &format!("Evaluation::of (in-sample figures) (run {})", k + 1),
            || Evaluation::of(&cal, &log, &opts),
        );
    }
    let mut c = None;
    for k in 0..repeat_compute {
        drop(c.take());
        c = Some(stage(
            &format!("Calibration::correct (apply) (run {})", k + 1),
            || cal.correct(&log),
        ));
    }
    let c = c.expect("at least one correction");
    stage("Evaluation::of_correction (figures only)", || {
        Evaluation::of_correction(&log, &c, &opts)
    });

    // `driftlab apply` writes its CSV with `corrected_csv::write`: rows formatted in parallel
    // blocks, written in order into a temporary file, fsync, rename.
    let out = dir.path().join("out.csv");
    stage("apply: corrected_csv::write (with fsync)", || {
        driftlab::files::corrected_csv::write(&out, &log, &c.pred_dph, &c.cor_dph, &|_| {})
            .expect("write")
    });
    let size = std::fs::metadata(&out).map(|m| m.len()).unwrap_or(0);
    println!("  corrected CSV: {:.1} MB", size as f64 / 1e6);
}

fn main() {
    if let Some(path) = std::env::var_os("DRIFTLAB_STAGES") {
        stages(Path::new(&path));
        return;
    }
    // No plots: criterion draws them with plotters, whose text needs a system font that
    // driftlab's own plotters build (a bundled font, no font lookup) does not provide.
    let mut c = Criterion::default()
        .without_plots()
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(4))
        .configure_from_args();
    benches(&mut c);
    unit_pipeline_benches(&mut c);
    c.final_summary();
}

/// The plain walk of the method: pointwise K1 on the set `regime`: `(Ω_f − K0(T) − K2(T̈)·T̈) / Ṫ` where |Ṫ| exceeds the
/// dead-band, outside plateaus. The paper's first pass has no K2 yet (`k2 = None`); refinement
/// passes subtract the K2 term fitted in the pass before.
#[allow(clippy::needless_range_loop)] // one index walks six parallel columns
fn k1_points(
    log: &Log,
    prepared: &vakhrameev::Prepared,
    mask: &[bool],
    k0: &Approx,
    k2: Option<&Approx>,
    deadband: f64,
    regime: Regime,
) -> PointSet {
    let d = &prepared.deriv;
    let mut out = PointSet::default();
    for i in d.ready_from..log.len() {
        let (td, tdd) = (d.tdot[i], d.tddot[i]);
        if mask[i] || td.abs() <= deadband || Regime::of(td, tdd) != regime {
            continue;
        }
        let k2_term = k2.map_or(0.0, |k2| k2.eval(tdd) * tdd);
        out.x.push(td);
        out.y
            .push((prepared.omega_filtered_dph[i] - k0.eval(log.temp_c[i]) - k2_term) / td);
    }
    out
}

/// Pointwise K2 on the set `regime`: `(Ω_f − K0(T) − K1(Ṫ)·Ṫ) / T̈` with the fitted K1, where
/// |T̈| exceeds the dead-band, outside plateaus.
#[allow(clippy::needless_range_loop)] // one index walks six parallel columns
fn k2_points(
    log: &Log,
    prepared: &vakhrameev::Prepared,
    mask: &[bool],
    k0: &Approx,
    k1: &Approx,
    deadband: f64,
    regime: Regime,
) -> PointSet {
    let d = &prepared.deriv;
    let mut out = PointSet::default();
    for i in d.ready_from..log.len() {
        let (td, tdd) = (d.tdot[i], d.tddot[i]);
        if mask[i] || tdd.abs() <= deadband || Regime::of(td, tdd) != regime {
            continue;
        }
        let rest = prepared.omega_filtered_dph[i] - k0.eval(log.temp_c[i]) - k1.eval(td) * td;
        out.x.push(tdd);
        out.y.push(rest / tdd);
    }
    out
}
