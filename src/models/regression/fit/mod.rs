//! Least squares over the design rows of every usable sample, the searches for the
//! non-linear parameters, and the ranges and statistics of the result.
//!
//! This module holds the fit itself, [`fit`], which runs the searches and the final solve; the
//! normal equations (`normal`), the staged solves and their cost (`stages`), the count of the
//! searches' work (`budget`) and the ranges and statistics of a fitted model (`ranges`) are in
//! modules of their own.

mod budget;
mod normal;
mod ranges;
mod stages;

use budget::{Budget, planned_evaluations};
use normal::Design;
use ranges::ranges_and_stats;
use stages::{cost, solve_stages, stages};

use super::signals::Signals;
use super::{
    CostCurve, Delay, DelaySpec, FitSamples, InputRanges, LagSpec, LambdaSpec, RegressionModel,
    RegressionSpec, RegressionStats, Term, guess_temp2, search, terms,
};
use crate::error::{Error, Result};
use crate::log::Log;
use crate::models::FitError;
use crate::signal::plateau;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicUsize};

/// The most samples a search's cost is computed on: evenly spread, the cost curve's shape
/// does not need every sample, and a 10⁷-sample log would otherwise take minutes.
const SEARCH_SAMPLES: usize = 100_000;

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
    // A delay over half the log reads the log's first temperature for most of it: the
    // delayed T is then nearly constant, its terms nearly collinear with the constant, and
    // coefficients with standard errors would be printed for what the log cannot show.
    if let super::DelaySpec::Fixed { seconds } = spec.delay
        && seconds > 0.5 * log.duration_s()
    {
        return Err(FitError::DelayBeyondLog {
            log: log.source.clone(),
            model: spec.name.clone(),
            delay_s: seconds,
            duration_s: log.duration_s(),
        }
        .into());
    }
    // Every model is fitted and judged on the samples past the rates' warm-up (the same
    // samples for every model, so that their figures compare).
    crate::models::recipe::check_history(spec.smoothing_s, spec.step_h_s, log)?;
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
            .ok_or_else(|| FitError::NoSecondTemperature {
                log: log.source.clone(),
                model: spec.name.clone(),
            })?;
        Some(name)
    } else {
        None
    };
    let s = Signals::of(log, spec, temp2.as_deref(), None)?;
    let p = terms::column_names(&spec.terms).len();
    let n = s.len();
    if s.ready_count() == 0 && n > 0 {
        // Every sample is in a stretch shorter than the history the rates of T need.
        let needed = super::signals::steps(spec, s.dt_s).ready_from();
        let starts = s.segment_starts.iter().copied().chain(std::iter::once(n));
        let longest = starts
            .clone()
            .zip(starts.skip(1))
            .filter(|(a, b)| b > a)
            .map(|(a, b)| s.time[b - 1] - s.time[a] + s.dt_s)
            .fold(0.0, f64::max);
        return Err(FitError::NoRateHistory {
            log: log.source.clone(),
            needed_s: needed as f64 * s.dt_s,
            longest_s: longest,
        }
        .into());
    }
    if s.ready_count() < 2 * p + 2 {
        return Err(FitError::TooFewForModel {
            log: log.source.clone(),
            count: s.ready_count(),
            model: spec.name.clone(),
            coefficients: p,
        }
        .into());
    }
    let stride = s.ready_count().div_ceil(SEARCH_SAMPLES).max(1);
    let stages = stages(spec);
    // The plateaus, when a stage needs them: the engineer's ranges, or found by the detector
    // (with the recipe's options) on T as measured, where the chamber held.
    let plateau: Vec<bool> = if stages.iter().any(|st| st.on_plateaus) {
        let ranges = plateau::ranges(&spec.plateaus, &log.time_s, &s.tdot, &s.ready);
        if ranges.is_empty() {
            return Err(FitError::NoPlateaus {
                log: log.source.clone(),
                model: spec.name.clone(),
            }
            .into());
        }
        plateau::mask(&log.time_s, &ranges)
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
            let possible = possible_lag(log);
            // Each curve refills one set of signals in place for every lag it tries.
            let tau_curve = |per_c: f64| {
                let mut held = Signals::of(log, spec, temp2.as_deref(), None).ok();
                search::minimize("lag_s", &g, false, |tau| {
                    if !possible(tau, per_c) {
                        return f64::INFINITY;
                    }
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
                        t_ref: t_ref_of(spec, s, &use_sample, &Delay::default())
                            .map_or(0.0, |t| t.celsius),
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
                let slopes = search::grid(0.0, super::LAG_SLOPE_SEARCH_MAX, 11, false);
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
    let t_knots = t_knots_of(spec, &s).ok_or_else(|| FitError::FlatTemperature {
        log: log.source.clone(),
        model: spec.name.clone(),
    })?;
    let t_ref = t_ref_of(spec, &s, &use_sample, &Delay::default()).map(|t| t.celsius);
    // Searches run on at most SEARCH_SAMPLES evenly spread samples.
    let sub = || s.ready_samples().step_by(stride);
    let has_selfheat = spec.terms.contains(&Term::SelfHeating);
    let mut lambda = lambda0;
    let mut delay = match spec.delay {
        DelaySpec::Fixed { seconds } => Delay::constant(seconds),
        _ => Delay::default(),
    };
    let search_lambda = |delay: &Delay, t_ref: Option<f64>| -> Option<CostCurve> {
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
                t_ref: t_ref.unwrap_or(0.0),
                delay,
            };
            cost(&s, &d, &stages, &plateau, |_| sub())
        }))
    };
    if let Some(c) = search_lambda(&delay, t_ref) {
        lambda = c.best;
        searches.push(c);
    }
    // Whether sample `i` lies in the band `[lo, hi)` of T (`[lo, hi]` for the last band).
    let in_band = |i: &usize, (lo, hi, last): (f64, f64, bool)| {
        let t = s.temp[*i];
        t >= lo && (t < hi || last)
    };
    // The cost of a constant delay τ with λ as found, over the searched samples (those of one
    // band of T, when one is given; a plateau stage keeps every plateau: a band may hold only
    // one).
    let delay_cost = |tau: f64, band: Option<(f64, f64, bool)>| {
        if !budget.tick() {
            return f64::INFINITY;
        }
        let d = Delay::constant(tau);
        let design = Design {
            terms: &spec.terms,
            lambda,
            t_knots: &t_knots,
            t_ref: t_ref.unwrap_or(0.0),
            delay: &d,
        };
        cost(&s, &design, &stages, &plateau, |on_plateaus| {
            sub().filter(move |i| on_plateaus || band.is_none_or(|b| in_band(i, b)))
        })
    };
    match spec.delay {
        DelaySpec::Search { max_s } => {
            let g = search::grid(0.0, max_s, 31, false);
            let c = search::minimize("delay_s", &g, false, |tau| delay_cost(tau, None));
            delay = Delay::constant(c.best);
            searches.push(c);
        }
        DelaySpec::Bands { bands, max_s } => {
            let (lo, hi) = temp_range(&s);
            let width = (hi - lo) / bands as f64;
            let g = search::grid(0.0, max_s, 31, false);
            let mut points = Vec::new();
            for b in 0..bands {
                let band = (
                    lo + b as f64 * width,
                    lo + (b + 1) as f64 * width,
                    b + 1 == bands,
                );
                let count = sub().filter(|i| in_band(i, band)).count();
                if count < 20 * p.max(1) {
                    continue;
                }
                let centre = sub()
                    .filter(|i| in_band(i, band))
                    .map(|i| s.temp[i])
                    .sum::<f64>()
                    / count as f64;
                let c =
                    search::minimize(&format!("delay_s at {centre:.1} degC"), &g, false, |tau| {
                        delay_cost(tau, Some(band))
                    });
                points.push([centre, c.best]);
                searches.push(c);
            }
            points.sort_by(|a, b| a[0].total_cmp(&b[0]));
            delay = Delay { points };
        }
        DelaySpec::None | DelaySpec::Fixed { .. } => {}
    }
    // Tref in the middle of T as the model reads it, through the delay found: the range the
    // model holds T to (`ranges.temp`), as PX4's TREF is the middle of [TMIN, TMAX]; a file's
    // Tref is checked against that middle.
    let centre = t_ref_of(spec, &s, &use_sample, &delay);
    if let Some(c) = centre
        .as_ref()
        .filter(|c| c.span_c < crate::models::MIN_TEMP_SPAN_C)
    {
        return Err(FitError::NarrowSpan {
            log: log.source.clone(),
            model: spec.name.clone(),
            span_c: Some(c.range),
            minimum_c: crate::models::MIN_TEMP_SPAN_C,
        }
        .into());
    }
    let t_ref = centre.map(|c| c.celsius);
    if !delay.points.is_empty()
        && let Some(c) = search_lambda(&delay, t_ref)
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
        t_ref: t_ref.unwrap_or(0.0),
        delay: &delay,
    };
    let sol = solve_stages(&s, &design, &stages, &plateau, |_| s.ready_samples()).map_err(
        |(used, coefficients)| FitError::Unsolvable {
            log: log.source.clone(),
            model: spec.name.clone(),
            used,
            coefficients,
        },
    )?;
    if !sol.dependent.is_empty() {
        // The net under the spec's check of polynomial terms: any other dependence of the
        // columns on this log (pwlT's hats with a constant, an extra channel that is a copy of
        // T, a T held constant by the plateaus chosen).
        let names = terms::column_names(&spec.terms);
        return Err(FitError::DependentColumns {
            log: log.source.clone(),
            model: spec.name.clone(),
            columns: sol.dependent.iter().map(|&j| names[j].clone()).collect(),
        }
        .into());
    }
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
        t_ref_c: t_ref,
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

/// Knots of a `pwlT` term over the range of T (none when the model has no such term); `None`
/// when T does not vary, so no knots can be spread over it.
fn t_knots_of(spec: &RegressionSpec, s: &Signals) -> Option<Vec<f64>> {
    let Some(k) = spec.terms.iter().find_map(|t| match t {
        Term::PwlT { knots } => Some(*knots),
        _ => None,
    }) else {
        return Some(Vec::new());
    };
    let (lo, hi) = temp_range(s);
    if hi <= lo || hi.is_nan() {
        return None;
    }
    Some(search::grid(lo, hi, k, false))
}

/// Tref of a model's `(T-Tref)^k` terms, and the range of T it is fitted over.
struct Centre {
    /// Tref, °C.
    celsius: f64,
    /// The lowest and highest T over the samples the fit covers, as the model reads it, °C.
    range: (f64, f64),
    /// Their difference, °C (0 when no T is finite).
    span_c: f64,
}

/// Tref of the `(T-Tref)^k` terms (`None` when the model has none): the spec's fixed
/// temperature, or the middle of T's range as the model reads it (through `delay`) over the
/// samples the fit covers (`used`, with a rate history and a reading), where PX4's script puts `TREF`; the
/// fitted range is also where the model holds T, as PX4 holds it to `[TMIN, TMAX]`, and is
/// what [`ranges_and_stats`] records as `ranges.temp`.
fn t_ref_of(spec: &RegressionSpec, s: &Signals, used: &[bool], delay: &Delay) -> Option<Centre> {
    if !spec.terms.iter().any(|t| matches!(t, Term::Tc { .. })) {
        return None;
    }
    let mut ch = vec![0.0; s.channels.len()];
    // Over the samples `ranges_and_stats` takes the range from: a sample with no reading (an
    // accelerometer's cell that could not be read, a channel's gap) is none, so that Tref is
    // the middle of the range the file records.
    let (lo, hi) = s
        .ready_samples()
        .filter(|&i| used[i] && s.omega[i].is_finite())
        .filter_map(|i| {
            let temp = s.inputs(i, delay, &mut ch).temp;
            ch.iter().all(|v| v.is_finite()).then_some(temp)
        })
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    let (range, span_c) = if lo <= hi {
        ((lo, hi), hi - lo)
    } else {
        ((0.0, 0.0), 0.0)
    };
    Some(Centre {
        celsius: match spec.t_ref {
            super::TRefSpec::Fixed { celsius } => celsius,
            super::TRefSpec::MidRange => 0.5 * (range.0 + range.1),
        },
        range,
        span_c,
    })
}

/// The lowest and highest finite T over the samples with full history (∞ and −∞ when there
/// is none).
fn temp_range(s: &Signals) -> (f64, f64) {
    s.ready_samples()
        .map(|i| s.temp[i])
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        })
}

/// Whether a lag of `tau` s at 20 °C changing by `per_c` per °C is one the log could show,
/// as a loaded model is checked ([`super::fitted`]'s lag over the fitted range): positive and
/// no longer than the log at every temperature it holds. The search tries no other, so that
/// every model it fits is one its own file reads back (a lag of 3600 s at 20 °C and 0.025
/// per °C is 18,000 s at −38 °C, over an 8000-s log). No lag at all is always possible.
fn possible_lag(log: &Log) -> impl Fn(f64, f64) -> bool {
    let (lo, hi) = log
        .temp_c
        .iter()
        .filter(|t| t.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &t| {
            (a.min(t), b.max(t))
        });
    let duration = log.duration_s();
    move |tau, per_c| {
        tau <= 0.0
            || [lo, hi].iter().filter(|t| t.is_finite()).all(|&t| {
                let at = super::lag_at(tau, per_c, t);
                at.is_finite() && at > 0.0 && at <= duration
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lag_the_log_cannot_show_is_not_tried() {
        // 8000 s from −40 to +60 °C.
        let n = 8000;
        let log = Log::from_columns(
            "run.csv",
            (0..n).map(|i| i as f64).collect(),
            vec![0.0; n],
            (0..n)
                .map(|i| -40.0 + 100.0 * i as f64 / n as f64)
                .collect(),
        );
        let possible = possible_lag(&log);
        assert!(possible(0.0, 0.0) && possible(0.0, 0.1));
        assert!(possible(3600.0, 0.0) && !possible(9000.0, 0.0));
        // 3600 s at 20 °C and 0.025 per °C is 3600 / (1 − 1.5) → held at 0.2: 18,000 s at
        // −40 °C, longer than the log; the file's check refuses it, so the search must not
        // find it.
        assert!(!possible(3600.0, 0.025));
        assert!(possible(1000.0, 0.0125));
    }
}
