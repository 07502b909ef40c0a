//! Least squares over the design rows of every usable sample, the searches for the
//! non-linear parameters, and the ranges and statistics of the result.

use super::signals::Signals;
use super::{
    CostCurve, Delay, DelaySpec, FitSamples, InputRanges, LagSpec, LambdaSpec, Range,
    RegressionModel, RegressionSpec, RegressionStats, Term, guess_temp2, search, terms,
};
use crate::error::{Error, Result};
use crate::log::Log;
use crate::models::recipe::PlateauChoice;
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// The normal equations of a least-squares fit, accumulated sample by sample.
struct Normal {
    p: usize,
    ata: Vec<f64>,
    aty: Vec<f64>,
    yty: f64,
    n: usize,
}

/// The fixed parts of a fit: terms, λ, knots, delay.
struct Design<'a> {
    terms: &'a [Term],
    lambda: f64,
    t_knots: &'a [f64],
    delay: &'a Delay,
}

/// The normal equations of `d` over `samples`, fitted to the rate less the prediction of
/// each earlier stage in `less` (its design and coefficients).
fn accumulate(
    s: &Signals,
    d: &Design,
    less: &[(&Design, &[f64])],
    samples: impl Iterator<Item = usize>,
) -> Normal {
    let p = terms::column_names(d.terms).len();
    let mut nm = Normal {
        p,
        ata: vec![0.0; p * p],
        aty: vec![0.0; p],
        yty: 0.0,
        n: 0,
    };
    let mut row = Vec::with_capacity(p);
    let mut earlier = Vec::new();
    let mut ch = vec![0.0; s.channels.len()];
    for i in samples {
        let x = s.inputs(i, d.delay, &mut ch);
        let mut y = s.omega[i];
        for (e, beta) in less {
            terms::row(e.terms, &x, &ch, e.lambda, e.t_knots, &mut earlier);
            y -= earlier.iter().zip(*beta).map(|(a, b)| a * b).sum::<f64>();
        }
        terms::row(d.terms, &x, &ch, d.lambda, d.t_knots, &mut row);
        if !y.is_finite() || row.iter().any(|v| !v.is_finite()) {
            continue;
        }
        for a in 0..p {
            let ra = row[a];
            nm.aty[a] += ra * y;
            let base = a * p;
            for (b, rb) in row.iter().enumerate().skip(a) {
                nm.ata[base + b] += ra * rb;
            }
        }
        nm.yty += y * y;
        nm.n += 1;
    }
    for a in 0..p {
        for b in 0..a {
            nm.ata[a * p + b] = nm.ata[b * p + a];
        }
    }
    nm
}

/// The solution of the normal equations: coefficients, residual sum of squares and the
/// diagonal of (AᵀA)⁻¹. Columns are scaled to unit RMS first (T³ and T̈ differ by twelve
/// orders of magnitude), and the SVD leaves out directions the data cannot tell apart.
struct Solution {
    beta: Vec<f64>,
    rss: f64,
    inv_diag: Vec<f64>,
}

fn solve(nm: &Normal) -> Option<Solution> {
    let p = nm.p;
    if nm.n < p || p == 0 {
        return None;
    }
    let scale: Vec<f64> = (0..p)
        .map(|a| {
            let v = (nm.ata[a * p + a] / nm.n as f64).sqrt();
            if v > 0.0 && v.is_finite() { v } else { 1.0 }
        })
        .collect();
    let a = DMatrix::from_fn(p, p, |i, j| nm.ata[i * p + j] / (scale[i] * scale[j]));
    let b = DVector::from_fn(p, |i, _| nm.aty[i] / scale[i]);
    let svd = a.svd(true, true);
    let tol = svd.singular_values.max() * 1e-12;
    let q = svd.solve(&b, tol).ok()?;
    let inv = svd.pseudo_inverse(tol).ok()?;
    let beta: Vec<f64> = (0..p).map(|i| q[i] / scale[i]).collect();
    // RSS = yᵀy − 2βᵀAᵀy + βᵀAᵀAβ, which equals yᵀy − βᵀAᵀy at the solution.
    let bty: f64 = beta.iter().zip(&nm.aty).map(|(b, y)| b * y).sum();
    let rss = (nm.yty - bty).max(0.0);
    let inv_diag = (0..p)
        .map(|i| inv[(i, i)] / (scale[i] * scale[i]))
        .collect();
    Some(Solution {
        beta,
        rss,
        inv_diag,
    })
}

/// The terms one least-squares solve finds, the columns they fill, and whether it runs on
/// the plateaus only.
struct Stage {
    terms: Vec<Term>,
    cols: Vec<usize>,
    on_plateaus: bool,
}

/// The solves of a fit in order: one for [`FitSamples::All`] and [`FitSamples::Plateaus`];
/// the static terms, then the rate terms, for [`FitSamples::Staged`] (a stage without
/// terms is left out).
fn stages(spec: &RegressionSpec) -> Vec<Stage> {
    let mut cols = Vec::new();
    let mut start = 0;
    for t in &spec.terms {
        cols.push((start..start + t.width()).collect::<Vec<usize>>());
        start += t.width();
    }
    let stage = |keep: &dyn Fn(&Term) -> bool, on_plateaus: bool| Stage {
        terms: spec.terms.iter().filter(|t| keep(t)).cloned().collect(),
        cols: spec
            .terms
            .iter()
            .zip(&cols)
            .filter(|(t, _)| keep(t))
            .flat_map(|(_, c)| c.iter().copied())
            .collect(),
        on_plateaus,
    };
    let v = match spec.samples {
        FitSamples::All => vec![stage(&|_| true, false)],
        FitSamples::Plateaus => vec![stage(&|_| true, true)],
        FitSamples::Staged => vec![
            stage(&|t| !t.is_rate(), true),
            stage(&|t| t.is_rate(), false),
        ],
    };
    v.into_iter().filter(|s| !s.terms.is_empty()).collect()
}

/// Coefficients of every column with their standard errors (each from its own stage's
/// residual), and the last stage's residual sum of squares over its `n` samples.
struct Solved {
    beta: Vec<f64>,
    std_errors: Vec<f64>,
    last_rss: f64,
    last_n: usize,
}

/// Solves the stages in turn, each on what the earlier ones leave. `samples(on_plateaus)`
/// gives the samples of a stage; a plateau stage keeps only those in `plateau`.
fn solve_stages<I: Iterator<Item = usize>>(
    s: &Signals,
    d: &Design,
    stages: &[Stage],
    plateau: &[bool],
    samples: impl Fn(bool) -> I,
) -> std::result::Result<Solved, (usize, usize)> {
    let p = terms::column_names(d.terms).len();
    let mut out = Solved {
        beta: vec![0.0; p],
        std_errors: vec![0.0; p],
        last_rss: 0.0,
        last_n: 0,
    };
    let designs: Vec<Design> = stages
        .iter()
        .map(|st| Design {
            terms: &st.terms,
            ..*d
        })
        .collect();
    let mut fitted: Vec<Vec<f64>> = Vec::new();
    for (k, st) in stages.iter().enumerate() {
        let less: Vec<(&Design, &[f64])> = designs[..k]
            .iter()
            .zip(&fitted)
            .map(|(d, b)| (d, b.as_slice()))
            .collect();
        let nm = if st.on_plateaus {
            accumulate(s, &designs[k], &less, samples(true).filter(|&i| plateau[i]))
        } else {
            accumulate(s, &designs[k], &less, samples(false))
        };
        let sol = solve(&nm).ok_or((nm.n, nm.p))?;
        let dof = nm.n.saturating_sub(nm.p).max(1) as f64;
        let sigma2 = sol.rss / dof;
        for (j, &c) in st.cols.iter().enumerate() {
            out.beta[c] = sol.beta[j];
            out.std_errors[c] = (sigma2 * sol.inv_diag[j].max(0.0)).sqrt();
        }
        out.last_rss = sol.rss;
        out.last_n = nm.n;
        fitted.push(sol.beta);
    }
    Ok(out)
}

/// RMS residual of coefficients `beta` over `samples`.
fn rms_residual(
    s: &Signals,
    d: &Design,
    beta: &[f64],
    samples: impl Iterator<Item = usize>,
) -> f64 {
    let mut row = Vec::with_capacity(beta.len());
    let mut ch = vec![0.0; s.channels.len()];
    let (mut ss, mut n) = (0.0, 0usize);
    for i in samples {
        let x = s.inputs(i, d.delay, &mut ch);
        terms::row(d.terms, &x, &ch, d.lambda, d.t_knots, &mut row);
        let r = s.omega[i] - row.iter().zip(beta).map(|(a, b)| a * b).sum::<f64>();
        if r.is_finite() {
            ss += r * r;
            n += 1;
        }
    }
    if n == 0 {
        f64::INFINITY
    } else {
        (ss / n as f64).sqrt()
    }
}

/// RMS residual of the fit over `samples(false)` (every sample of the search, the ramps
/// included, even where coefficients come from the plateaus), or +∞ when it cannot be
/// fitted.
fn cost<I: Iterator<Item = usize>>(
    s: &Signals,
    d: &Design,
    stages: &[Stage],
    plateau: &[bool],
    samples: impl Fn(bool) -> I,
) -> f64 {
    let Ok(sol) = solve_stages(s, d, stages, plateau, &samples) else {
        return f64::INFINITY;
    };
    match stages {
        [one] if !one.on_plateaus => {
            if sol.last_n > 0 {
                (sol.last_rss / sol.last_n as f64).sqrt()
            } else {
                f64::INFINITY
            }
        }
        _ => rms_residual(s, d, &sol.beta, samples(false)),
    }
}

/// The most samples a search's cost is computed on: evenly spread, the cost curve's shape
/// does not need every sample, and a 10⁷-sample log would otherwise take minutes.
const SEARCH_SAMPLES: usize = 100_000;

/// How far a fit's searches have gone, told to `progress` (the share of the cost evaluations
/// planned that are done, 0 to 1) after each one; when `progress` returns false the searches
/// stop and the fit returns [`Error::Cancelled`].
struct Budget<'p> {
    planned: usize,
    done: AtomicUsize,
    stop: AtomicBool,
    progress: &'p (dyn Fn(f64) -> bool + Sync),
}

impl Budget<'_> {
    /// Counts one evaluation; false once the fit is to stop.
    fn tick(&self) -> bool {
        if self.stop.load(Ordering::Relaxed) {
            return false;
        }
        let d = self.done.fetch_add(1, Ordering::Relaxed) + 1;
        let go = (self.progress)((d as f64 / self.planned.max(1) as f64).min(1.0));
        if !go {
            self.stop.store(true, Ordering::Relaxed);
        }
        go
    }

    fn check(&self) -> Result<()> {
        if self.stop.load(Ordering::Relaxed) {
            Err(Error::Cancelled)
        } else {
            Ok(())
        }
    }
}

/// Cost evaluations of a search over a grid of `points`: the grid, then the golden section's
/// two starting points and its twenty steps.
fn evaluations(points: usize) -> usize {
    points + 22
}

/// The cost evaluations `spec`'s searches make, for [`Budget`].
fn planned_evaluations(spec: &RegressionSpec) -> usize {
    let lag = match spec.lag {
        LagSpec::Search {
            with_temperature: true,
            ..
        } => 11 * evaluations(25),
        LagSpec::Search { .. } => evaluations(25),
        _ => 0,
    };
    let delay = match spec.delay {
        DelaySpec::Search { .. } => evaluations(31),
        DelaySpec::Bands { bands, .. } => bands * evaluations(31),
        _ => 0,
    };
    let lambda = match spec.lambda {
        LambdaSpec::Search { .. } if spec.terms.contains(&Term::SelfHeating) => {
            evaluations(25) * if delay > 0 { 2 } else { 1 }
        }
        _ => 0,
    };
    lag + delay + lambda + 1
}

/// Fits a regression model to `log`.
///
/// # Errors
/// An invalid spec, a channel the log lacks, or too few usable samples for the terms.
pub fn fit(log: &Log, spec: &RegressionSpec) -> Result<RegressionModel> {
    fit_with_progress(log, spec, &|_| true)
}

/// [`fit`], telling `progress` the share of its searches done (0 to 1) as it goes; when
/// `progress` returns false the fit stops as soon as it can.
///
/// # Errors
/// As [`fit`], and [`Error::Cancelled`] when stopped.
pub fn fit_with_progress(
    log: &Log,
    spec: &RegressionSpec,
    progress: &(dyn Fn(f64) -> bool + Sync),
) -> Result<RegressionModel> {
    spec.validate()?;
    let budget = Budget {
        planned: planned_evaluations(spec),
        done: AtomicUsize::new(0),
        stop: AtomicBool::new(false),
        progress,
    };
    if !(budget.progress)(0.0) {
        return Err(Error::Cancelled);
    }
    let needs_temp2 = spec.terms.iter().any(Term::needs_temp2);
    let temp2 = if needs_temp2 {
        let name = spec
            .temp2
            .clone()
            .or_else(|| guess_temp2(log))
            .ok_or_else(|| {
                Error::Fit(format!(
                    "{}: model {} needs a second temperature channel (dT) and the log has none",
                    log.source, spec.name
                ))
            })?;
        Some(name)
    } else {
        None
    };
    let s = Signals::of(log, spec, temp2.as_deref(), None)?;
    let p = terms::column_names(&spec.terms).len();
    let n = s.len();
    if s.ready_count() < 2 * p + 2 {
        return Err(Error::Fit(format!(
            "{}: {n} samples are too few for model {} ({p} coefficients)",
            log.source, spec.name
        )));
    }
    let stride = s.ready_count().div_ceil(SEARCH_SAMPLES).max(1);
    let stages = stages(spec);
    // The plateaus, when a stage needs them: the engineer's ranges, or found by the detector
    // (with the recipe's options) on T as measured, where the chamber held.
    let plateau: Vec<bool> = if stages.iter().any(|st| st.on_plateaus) {
        let ranges = match &spec.plateaus {
            // Within each segment's samples with full history: no plateau spans a gap.
            PlateauChoice::Auto(opts) => s
                .ready
                .iter()
                .flat_map(|r| {
                    crate::signal::plateau::detect(
                        &log.time_s[r.clone()],
                        &s.tdot[r.clone()],
                        0,
                        opts,
                    )
                })
                .collect(),
            PlateauChoice::Manual { ranges } => ranges.clone(),
        };
        if ranges.is_empty() {
            return Err(Error::Fit(format!(
                "{}: model {} is fitted on plateaus and the log has none",
                log.source, spec.name
            )));
        }
        crate::models::vakhrameev::plateau_mask(&log.time_s, &ranges)
    } else {
        vec![true; n]
    };
    // The samples the fit's statistics and input ranges cover.
    let use_sample: Vec<bool> = match spec.samples {
        FitSamples::Plateaus => plateau.clone(),
        FitSamples::All | FitSamples::Staged => vec![true; n],
    };
    let mut searches = Vec::new();
    let lambda0 = match spec.lambda {
        LambdaSpec::Fixed { seconds } => seconds,
        LambdaSpec::Search { min_s, max_s } => (min_s * max_s).sqrt(),
    };
    let lag: Option<(f64, f64)> = match spec.lag {
        LagSpec::None => None,
        LagSpec::Fixed { seconds, per_c } => Some((seconds, per_c)),
        LagSpec::Search {
            max_s,
            with_temperature,
        } => {
            let g = search::grid(0.0, max_s, 25, false);
            // Each curve refills one set of signals in place for every lag it tries.
            let tau_curve = |per_c: f64| {
                let mut held = Signals::of(log, spec, temp2.as_deref(), None).ok();
                search::minimize("lag_s", &g, false, |tau| {
                    let Some(s) = held.as_mut().filter(|_| budget.tick()) else {
                        return f64::INFINITY;
                    };
                    s.relag(log, spec, (tau, per_c));
                    let s = &*s;
                    let knots = t_knots_of(spec, s).unwrap_or_default();
                    let d = Design {
                        terms: &spec.terms,
                        lambda: lambda0,
                        t_knots: &knots,
                        delay: &Delay::default(),
                    };
                    cost(s, &d, &stages, &plateau, |_| {
                        s.ready_samples().step_by(stride)
                    })
                })
            };
            if with_temperature {
                // One τ search per slope, the slopes side by side on the cores: the slope's
                // own curve is the best cost of each.
                let slopes = search::grid(0.0, 0.025, 11, false);
                let curves: Vec<CostCurve> = slopes.par_iter().map(|&b| tau_curve(b)).collect();
                let best_cost =
                    |c: &CostCurve| c.rmse.iter().copied().fold(f64::INFINITY, f64::min);
                let k = (0..curves.len())
                    .min_by(|&a, &b| best_cost(&curves[a]).total_cmp(&best_cost(&curves[b])))
                    .unwrap_or(0);
                let per_c = slopes[k];
                searches.push(CostCurve {
                    parameter: "lag_per_c".into(),
                    x: slopes.clone(),
                    rmse: curves.iter().map(best_cost).collect(),
                    best: per_c,
                    at_edge: k == 0 || k + 1 == slopes.len(),
                });
                let mut c = curves[k].clone();
                c.parameter = format!("lag_s at {per_c} per degC");
                let tau = c.best;
                searches.push(c);
                Some((tau, per_c))
            } else {
                let c = tau_curve(0.0);
                let tau = c.best;
                searches.push(c);
                Some((tau, 0.0))
            }
        }
    };
    budget.check()?;
    let s = match lag {
        Some(_) => Signals::of(log, spec, temp2.as_deref(), lag)?,
        None => s,
    };
    let t_knots = t_knots_of(spec, &s).map_err(|e| Error::Fit(format!("{}: {e}", log.source)))?;
    // Searches run on at most SEARCH_SAMPLES evenly spread samples.
    let sub = || s.ready_samples().step_by(stride);
    let has_selfheat = spec.terms.contains(&Term::SelfHeating);
    let mut lambda = lambda0;
    let mut delay = match spec.delay {
        DelaySpec::Fixed { seconds } => Delay::constant(seconds),
        _ => Delay::default(),
    };
    let search_lambda = |delay: &Delay| -> Option<CostCurve> {
        let LambdaSpec::Search { min_s, max_s } = spec.lambda else {
            return None;
        };
        if !has_selfheat {
            return None;
        }
        let g = search::grid(min_s, max_s, 25, true);
        Some(search::minimize("lambda_s", &g, true, |l| {
            if !budget.tick() {
                return f64::INFINITY;
            }
            let d = Design {
                terms: &spec.terms,
                lambda: l,
                t_knots: &t_knots,
                delay,
            };
            cost(&s, &d, &stages, &plateau, |_| sub())
        }))
    };
    if let Some(c) = search_lambda(&delay) {
        lambda = c.best;
        searches.push(c);
    }
    match spec.delay {
        DelaySpec::Search { max_s } => {
            let g = search::grid(0.0, max_s, 31, false);
            let c = search::minimize("delay_s", &g, false, |tau| {
                if !budget.tick() {
                    return f64::INFINITY;
                }
                let d = Delay::constant(tau);
                let design = Design {
                    terms: &spec.terms,
                    lambda,
                    t_knots: &t_knots,
                    delay: &d,
                };
                cost(&s, &design, &stages, &plateau, |_| sub())
            });
            delay = Delay::constant(c.best);
            searches.push(c);
        }
        DelaySpec::Bands { bands, max_s } => {
            let (lo, hi) = s
                .ready_samples()
                .map(|i| s.temp[i])
                .filter(|v| v.is_finite())
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                    (a.min(v), b.max(v))
                });
            let width = (hi - lo) / bands as f64;
            let g = search::grid(0.0, max_s, 31, false);
            let mut points = Vec::new();
            for b in 0..bands {
                let (blo, bhi) = (lo + b as f64 * width, lo + (b + 1) as f64 * width);
                let in_band = |i: &usize| {
                    let t = s.temp[*i];
                    t >= blo && (t < bhi || b + 1 == bands)
                };
                let count = sub().filter(in_band).count();
                if count < 20 * p.max(1) {
                    continue;
                }
                let centre = sub().filter(in_band).map(|i| s.temp[i]).sum::<f64>() / count as f64;
                let c =
                    search::minimize(&format!("delay_s at {centre:.1} degC"), &g, false, |tau| {
                        if !budget.tick() {
                            return f64::INFINITY;
                        }
                        let d = Delay::constant(tau);
                        let design = Design {
                            terms: &spec.terms,
                            lambda,
                            t_knots: &t_knots,
                            delay: &d,
                        };
                        // Plateau stages keep every plateau: a band may hold only one.
                        cost(&s, &design, &stages, &plateau, |on_plateaus| {
                            sub().filter(move |i| on_plateaus || in_band(i))
                        })
                    });
                points.push([centre, c.best]);
                searches.push(c);
            }
            points.sort_by(|a, b| a[0].total_cmp(&b[0]));
            delay = Delay { points };
        }
        DelaySpec::None | DelaySpec::Fixed { .. } => {}
    }
    if !delay.points.is_empty()
        && let Some(c) = search_lambda(&delay)
    {
        lambda = c.best;
        searches.retain(|c| c.parameter != "lambda_s");
        searches.push(c);
    }

    budget.check()?;
    let design = Design {
        terms: &spec.terms,
        lambda,
        t_knots: &t_knots,
        delay: &delay,
    };
    let sol = solve_stages(&s, &design, &stages, &plateau, |_| s.ready_samples()).map_err(
        |(used, p)| {
            Error::Fit(format!(
                "{}: model {} could not be fitted ({used} usable samples for {p} coefficients)",
                log.source, spec.name
            ))
        },
    )?;
    let mut model = RegressionModel {
        spec: spec.clone(),
        temp2,
        names: terms::column_names(&spec.terms),
        coefficients: sol.beta,
        std_errors: sol.std_errors,
        lambda_s: has_selfheat.then_some(lambda),
        delay,
        lag_s: lag.map(|l| l.0),
        lag_per_c: lag.map_or(0.0, |l| l.1),
        t_knots,
        ranges: InputRanges::default(),
        dt_s: s.dt_s,
        stats: RegressionStats::default(),
        searches,
    };
    let (ranges, stats) = ranges_and_stats(&model, &s, &use_sample);
    model.ranges = ranges;
    model.stats = stats;
    Ok(model)
}

/// Knots of a `pwlT` term over the range of T (none when the model has no such term).
fn t_knots_of(spec: &RegressionSpec, s: &Signals) -> std::result::Result<Vec<f64>, String> {
    let Some(k) = spec.terms.iter().find_map(|t| match t {
        Term::PwlT { knots } => Some(*knots),
        _ => None,
    }) else {
        return Ok(Vec::new());
    };
    let (lo, hi) = s
        .ready_samples()
        .map(|i| s.temp[i])
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if hi <= lo || hi.is_nan() {
        return Err(format!(
            "T does not vary, so model {} cannot be fitted over it",
            spec.name
        ));
    }
    Ok(search::grid(lo, hi, k, false))
}

/// The input ranges over the fitted samples and the fit's statistics (from the residuals, not
/// the normal equations, for accuracy).
fn ranges_and_stats(
    m: &RegressionModel,
    s: &Signals,
    used: &[bool],
) -> (InputRanges, RegressionStats) {
    let t = &m.spec.terms;
    let uses = |f: fn(&Term) -> bool| t.iter().any(f);
    let mut r = [[f64::INFINITY, f64::NEG_INFINITY]; 4];
    let mut rc = vec![[f64::INFINITY, f64::NEG_INFINITY]; s.channels.len()];
    let mut ch = vec![0.0; s.channels.len()];
    let mut row = Vec::new();
    let (mut n, mut sum, mut sum2, mut ss_res) = (0usize, 0.0, 0.0, 0.0);
    let grow = |r: &mut Range, v: f64| {
        if v.is_finite() {
            r[0] = r[0].min(v);
            r[1] = r[1].max(v);
        }
    };
    for i in s.ready_samples().filter(|&i| used[i]) {
        let x = s.inputs(i, &m.delay, &mut ch);
        let y = s.omega[i];
        let pred = m.predict(&x, &ch, &mut row);
        if !y.is_finite() || !pred.is_finite() {
            continue;
        }
        for (k, v) in [x.temp, x.tdot, x.tddot, x.dt].into_iter().enumerate() {
            grow(&mut r[k], v);
        }
        for (rk, &v) in rc.iter_mut().zip(&ch) {
            grow(rk, v);
        }
        n += 1;
        sum += y;
        sum2 += y * y;
        ss_res += (y - pred) * (y - pred);
    }
    let some = |used: bool, r: Range| (used && r[0] <= r[1]).then_some(r);
    let ranges = InputRanges {
        temp: some(
            uses(|t| {
                matches!(
                    t,
                    Term::T | Term::T2 | Term::T3 | Term::TTdot | Term::TTddot | Term::PwlT { .. }
                )
            }),
            r[0],
        ),
        tdot: some(
            uses(|t| {
                matches!(
                    t,
                    Term::Tdot | Term::TTdot | Term::AbsTdot | Term::SgnTdotTddot
                )
            }),
            r[1],
        ),
        tddot: some(
            uses(|t| matches!(t, Term::Tddot | Term::TTddot | Term::SgnTdotTddot)),
            r[2],
        ),
        dt: some(uses(Term::needs_temp2), r[3]),
        channels: rc
            .into_iter()
            .map(|r| if r[0] <= r[1] { r } else { [0.0, 0.0] })
            .collect(),
    };
    let ss_tot = sum2 - sum * sum / n.max(1) as f64;
    let stats = RegressionStats {
        n,
        rmse: (ss_res / n.max(1) as f64).sqrt(),
        r2: if ss_tot > 0.0 {
            1.0 - ss_res / ss_tot
        } else {
            0.0
        },
    };
    (ranges, stats)
}
