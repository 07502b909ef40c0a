//! The + and − sets of the Vakhrameev model: which samples each holds, their pointwise K1 and
//! K2 (gathered for display, or streamed to the fits without being held), and the fits of
//! K1± and K2± over them, with the paper's refinement passes.

use super::set_moments::{SetAxis, SetTMoments, fit_sets_moments};
use super::*;
use crate::models::approx::Evaluator;
use crate::signal::plateau;
use std::sync::Arc;

/// Pointwise K1 of one sample: `(Ω_f − K0(T) − K2(T̈)·T̈) / Ṫ`, with `rest` = `Ω_f − K0(T)`.
/// The paper's first pass has no K2 yet (`k2 = None`); refinement passes subtract the K2 term
/// fitted in the pass before. Every path to the pointwise K1 (the fits, the points shown by the
/// workbench and the report) computes it here.
#[inline(always)]
pub(super) fn k1_ratio(td: f64, tdd: f64, rest: f64, k2: Option<&Evaluator<'_>>) -> f64 {
    let k2_term = k2.map_or(0.0, |k2| k2.eval(tdd) * tdd);
    (rest - k2_term) / td
}

/// Pointwise K2 of one sample: `(Ω_f − K0(T) − K1(Ṫ)·Ṫ) / T̈` with the fitted K1. Every path to
/// the pointwise K2 computes it here.
#[inline(always)]
pub(super) fn k2_ratio(td: f64, tdd: f64, rest: f64, k1: &Evaluator<'_>) -> f64 {
    (rest - k1.eval(td) * td) / tdd
}

/// K1 and K2 of one set with the points they were fitted to.
#[derive(Debug, Clone)]
pub struct SetFit {
    /// K1 of the set.
    pub k1: Approx,
    /// K2 of the set.
    pub k2: Approx,
    /// The pointwise K1 of the last pass (empty unless asked for).
    pub k1_points: PointSet,
    /// The pointwise K2 of the last pass (empty unless asked for).
    pub k2_points: PointSet,
    /// What the fits had to work around.
    pub warnings: Vec<String>,
    /// The refinement passes run when they diverged and stopped before the recipe's; `None`
    /// when all ran.
    pub refinements_run: Option<usize>,
    /// The T part of the set's moments, for the next fit over the same sets' samples and
    /// designs (another axis's, or this one's after an edit of K0); `None` when the set was
    /// fitted pass by pass.
    pub t_moments: Option<Arc<SetTMoments>>,
}

/// The samples of the pointwise K1 and K2 of one set (+ or −), as indices into the log, in log
/// order: outside plateaus, in the set's regime, beyond the Ṫ (T̈) dead-band. Indices are `u32`, so a log to be
/// fitted may have at most `u32::MAX` (about 4.3 billion) samples; [`fit`] refuses longer ones.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SetSamples {
    /// Samples outside the Ṫ dead-band (K1's points).
    pub k1: Vec<u32>,
    /// Samples outside the T̈ dead-band (K2's points).
    pub k2: Vec<u32>,
    /// Count and range of the finite Ṫ of `k1` (the x of K1's points).
    pub k1_range: Option<XRange>,
    /// Count and range of the finite T̈ of `k2` (the x of K2's points).
    pub k2_range: Option<XRange>,
}

/// Whole-log columns the pointwise K1 and K2 are computed from.
#[derive(Debug, Clone, Copy)]
pub struct SetInputs<'a> {
    /// Ṫ, °C/s.
    pub tdot: &'a [f64],
    /// T̈, °C/s².
    pub tddot: &'a [f64],
    /// Ω_f − K0(T), °/h ([`rest_dph`]).
    pub rest: &'a [f64],
}

/// The samples of both sets (+, −) whose pointwise K1 and K2 the fits use; they depend
/// on the derivatives, the plateaus and the dead-bands only.
#[allow(clippy::needless_range_loop)] // one index walks three parallel columns
pub fn set_samples(deriv: &Derivatives, mask: &[bool], (db1, db2): (f64, f64)) -> [SetSamples; 2] {
    let n = deriv.tdot.len().min(deriv.tddot.len()).min(mask.len());
    const SPAN: usize = 1 << 16;
    // Spans of the samples with full history, each segment's cut into pieces of SPAN.
    let spans: Vec<(usize, usize)> = deriv
        .ready
        .iter()
        .flat_map(|r| {
            let end = r.end.min(n);
            (r.start.min(end)..end)
                .step_by(SPAN)
                .map(move |a| (a, (a + SPAN).min(end)))
        })
        .collect();
    // [set][k1, k2] index lists of one span of the log, with the count and range of their
    // finite x. A sample of a set has Ṫ·T̈ ≠ 0, so no x is a zero (whose sign `min` and `max`
    // could take from either side), and the spans' ranges combine to the whole's exactly.
    let no_range = XRange {
        n: 0,
        lo: f64::INFINITY,
        hi: f64::NEG_INFINITY,
    };
    let widen = |r: &mut XRange, x: f64| {
        if x.is_finite() {
            r.n += 1;
            r.lo = r.lo.min(x);
            r.hi = r.hi.max(x);
        }
    };
    type Part = ([[Vec<u32>; 2]; 2], [[XRange; 2]; 2]);
    let parts: Vec<Part> = spans
        .into_par_iter()
        .map(|(a, b)| {
            let mut out: [[Vec<u32>; 2]; 2] = Default::default();
            let mut ranges = [[no_range; 2]; 2];
            for i in a..b {
                let (td, tdd) = (deriv.tdot[i], deriv.tddot[i]);
                if mask[i] {
                    continue;
                }
                let s = match Regime::of(td, tdd) {
                    Regime::Plus => 0,
                    Regime::Minus => 1,
                    Regime::Static => continue,
                };
                // The engine's tests, negated as written there (a NaN rate passes them).
                let (skip1, skip2) = (td.abs() <= db1, tdd.abs() <= db2);
                if !skip1 {
                    out[s][0].push(i as u32);
                    widen(&mut ranges[s][0], td);
                }
                if !skip2 {
                    out[s][1].push(i as u32);
                    widen(&mut ranges[s][1], tdd);
                }
            }
            (out, ranges)
        })
        .collect();
    let gather = |s: usize, k: usize| {
        let mut v = Vec::with_capacity(parts.iter().map(|p| p.0[s][k].len()).sum());
        for p in &parts {
            v.extend_from_slice(&p.0[s][k]);
        }
        let r = parts.iter().fold(no_range, |r, p| {
            let q = p.1[s][k];
            XRange {
                n: r.n + q.n,
                lo: r.lo.min(q.lo),
                hi: r.hi.max(q.hi),
            }
        });
        (v, r)
    };
    let (plus, minus) = rayon::join(
        || rayon::join(|| gather(0, 0), || gather(0, 1)),
        || rayon::join(|| gather(1, 0), || gather(1, 1)),
    );
    [plus, minus].map(|((k1, k1_range), (k2, k2_range))| SetSamples {
        k1_range: Some(k1_range),
        k2_range: Some(k2_range),
        k1,
        k2,
    })
}

/// `Ω_f − K0(T)` over the whole log: what K1 and K2 explain.
pub fn rest_dph(omega_filtered_dph: &[f64], temp_c: &[f64], k0: &Approx) -> Vec<f64> {
    let mut rest = omega_filtered_dph.to_vec();
    into_rest(&mut rest, temp_c, k0);
    rest
}

/// Turns filtered Ω into `Ω_f − K0(T)` in place.
pub(super) fn into_rest(omega_filtered_dph: &mut [f64], temp_c: &[f64], k0: &Approx) {
    omega_filtered_dph
        .par_chunks_mut(1 << 15)
        .zip(temp_c.par_chunks(1 << 15))
        .for_each(|(o, t)| {
            let k0 = k0.evaluator();
            for (o, &t) in o.iter_mut().zip(t) {
                *o -= k0.eval(t);
            }
        });
}

/// [`into_rest`] written into `out` from `omega_filtered_dph`: the same bits, without a copy
/// of the column first.
pub(super) fn rest_into(out: &mut [f64], omega_filtered_dph: &[f64], temp_c: &[f64], k0: &Approx) {
    out.par_chunks_mut(1 << 15)
        .zip(omega_filtered_dph.par_chunks(1 << 15))
        .zip(temp_c.par_chunks(1 << 15))
        .for_each(|((o, w), t)| {
            let k0 = k0.evaluator();
            for ((o, &w), &t) in o.iter_mut().zip(w).zip(t) {
                *o = w - k0.eval(t);
            }
        });
}

/// The pointwise K1 of a set as fit points: `(Ṫ, (Ω_f − K0(T) − K2(T̈)·T̈) / Ṫ)`.
struct K1Source<'a> {
    idx: &'a [u32],
    inputs: SetInputs<'a>,
    k2: Option<&'a Approx>,
    drift: bool,
}

impl PointSource for K1Source<'_> {
    fn candidates(&self) -> usize {
        self.idx.len()
    }
    #[inline]
    fn visit<F: FnMut(f64, f64, f64)>(&self, from: usize, to: usize, mut f: F) {
        let SetInputs { tdot, tddot, rest } = self.inputs;
        let drift = self.drift;
        match self.k2 {
            None => {
                for &i in &self.idx[from..to] {
                    let i = i as usize;
                    let td = tdot[i];
                    let y = k1_ratio(td, tddot[i], rest[i], None);
                    f(td, y, if drift { td * td } else { 1.0 });
                }
            }
            Some(k2) => {
                let k2 = k2.evaluator();
                for &i in &self.idx[from..to] {
                    let i = i as usize;
                    let td = tdot[i];
                    let y = k1_ratio(td, tddot[i], rest[i], Some(&k2));
                    f(td, y, if drift { td * td } else { 1.0 });
                }
            }
        }
    }
}

/// The pointwise K2 of a set as fit points: `(T̈, (Ω_f − K0(T) − K1(Ṫ)·Ṫ) / T̈)`.
struct K2Source<'a> {
    idx: &'a [u32],
    inputs: SetInputs<'a>,
    k1: &'a Approx,
    drift: bool,
}

impl PointSource for K2Source<'_> {
    fn candidates(&self) -> usize {
        self.idx.len()
    }
    #[inline]
    fn visit<F: FnMut(f64, f64, f64)>(&self, from: usize, to: usize, mut f: F) {
        let SetInputs { tdot, tddot, rest } = self.inputs;
        let k1 = self.k1.evaluator();
        for &i in &self.idx[from..to] {
            let i = i as usize;
            let tdd = tddot[i];
            let y = k2_ratio(tdot[i], tdd, rest[i], &k1);
            f(tdd, y, if self.drift { tdd * tdd } else { 1.0 });
        }
    }
}

/// Points already gathered by [`k1_points_of`] or [`k2_points_of`], as a fit's source: the same
/// `(x, y, w)` in the same order as the [`K1Source`] or [`K2Source`] they were gathered from
/// (the weight is made from x as those make it from Ṫ or T̈), so a fit over them equals the
/// streaming fit to the bit. When the points are wanted anyway (for display), the fit and its
/// statistics then read them instead of evaluating the other coefficient twice more.
struct Gathered<'a> {
    p: &'a PointSet,
    drift: bool,
}

impl PointSource for Gathered<'_> {
    fn candidates(&self) -> usize {
        self.p.x.len().min(self.p.y.len())
    }
    #[inline]
    fn visit<F: FnMut(f64, f64, f64)>(&self, from: usize, to: usize, mut f: F) {
        let (x, y) = (&self.p.x[from..to], &self.p.y[from..to]);
        if self.drift {
            for (&x, &y) in x.iter().zip(y) {
                f(x, y, x * x);
            }
        } else {
            for (&x, &y) in x.iter().zip(y) {
                f(x, y, 1.0);
            }
        }
    }
}

/// The points of a source, materialised (for display, or for a fit that falls back).
fn collect_points<S: PointSource>(src: &S) -> (PointSet, Vec<f64>) {
    let n = src.candidates();
    let parts: Vec<(Vec<f64>, Vec<f64>, Vec<f64>)> = (0..n)
        .step_by(approx::CHUNK)
        .collect::<Vec<_>>()
        .into_par_iter()
        .map(|a| {
            let b = (a + approx::CHUNK).min(n);
            let mut p = (
                Vec::with_capacity(b - a),
                Vec::with_capacity(b - a),
                Vec::with_capacity(b - a),
            );
            src.visit(a, b, |x, y, w| {
                p.0.push(x);
                p.1.push(y);
                p.2.push(w);
            });
            p
        })
        .collect();
    let mut out = (
        PointSet {
            x: Vec::with_capacity(n),
            y: Vec::with_capacity(n),
        },
        Vec::with_capacity(n),
    );
    for (x, y, w) in parts {
        out.0.x.extend(x);
        out.0.y.extend(y);
        out.1.extend(w);
    }
    out
}

/// The pointwise K1 of a set ([`k1_ratio`]) at each of its K1 samples, in log order.
pub fn k1_points_of(samples: &SetSamples, inputs: SetInputs, k2: Option<&Approx>) -> PointSet {
    let SetInputs { tdot, tddot, rest } = inputs;
    let idx = &samples.k1;
    let k2 = k2.map(Approx::evaluator);
    let (x, y) = rayon::join(
        || idx.par_iter().map(|&i| tdot[i as usize]).collect(),
        || {
            idx.par_iter()
                .map(|&i| {
                    let i = i as usize;
                    k1_ratio(tdot[i], tddot[i], rest[i], k2.as_ref())
                })
                .collect()
        },
    );
    PointSet { x, y }
}

/// The pointwise K2 of a set ([`k2_ratio`]) at each of its K2 samples, in log order.
pub fn k2_points_of(samples: &SetSamples, inputs: SetInputs, k1: &Approx) -> PointSet {
    let SetInputs { tdot, tddot, rest } = inputs;
    let idx = &samples.k2;
    let k1 = k1.evaluator();
    let (x, y) = rayon::join(
        || idx.par_iter().map(|&i| tddot[i as usize]).collect(),
        || {
            idx.par_iter()
                .map(|&i| {
                    let i = i as usize;
                    k2_ratio(tdot[i], tddot[i], rest[i], &k1)
                })
                .collect()
        },
    );
    PointSet { x, y }
}

/// [`fit_or_fallback_weighted`] over a point source: the fit streams over the points, which are
/// gathered only when they cannot support `spec` and a simpler curve is sought.
fn fit_or_fallback_source<S: PointSource>(
    name: &str,
    spec: &ApproxSpec,
    src: &S,
    opts: FitOptions,
    warnings: &mut Vec<String>,
) -> Approx {
    if let Ok(a) = approx::fit_with(spec, src, opts) {
        return a;
    }
    let (p, w) = collect_points(src);
    fit_or_fallback_weighted(name, spec, &p.x, &p.y, Some(&w), warnings)
}

/// The approximation specs of a set (K1, K2) and its sign as names carry it.
pub(super) fn set_specs(
    regime: Regime,
    recipe: &Recipe,
) -> (&ApproxSpec, &ApproxSpec, &'static str) {
    match regime {
        Regime::Minus => (&recipe.k1_minus, &recipe.k2_minus, "-"),
        _ => (&recipe.k1_plus, &recipe.k2_plus, "+"),
    }
}

/// K2 of a set fitted on what `k1` leaves, from the points [`k2_points_of`] gave for the same
/// samples and K1: the same
/// approximation, bit for bit, from one evaluation of K1 per point instead of three (the
/// workbench gathers the points for display when a K1 knot is dragged, and fits on them).
pub fn fit_k2_gathered(
    samples: &SetSamples,
    points: &PointSet,
    regime: Regime,
    recipe: &Recipe,
    warnings: &mut Vec<String>,
) -> Approx {
    let src = Gathered {
        p: points,
        drift: recipe.weighting == Weighting::Drift,
    };
    fit_k2_from(samples, &src, regime, recipe, warnings)
}

/// K1 of a set refitted on the points of its last pass ([`k1_points_of`] with the K2 that pass
/// took out), with statistics: how a K1 whose knots were placed by hand is fitted, after the
/// set's passes (see `staged.rs`).
pub fn fit_k1_gathered(
    samples: &SetSamples,
    points: &PointSet,
    regime: Regime,
    recipe: &Recipe,
    warnings: &mut Vec<String>,
) -> Approx {
    let (spec1, _, sign) = set_specs(regime, recipe);
    let src = Gathered {
        p: points,
        drift: recipe.weighting == Weighting::Drift,
    };
    let opts = FitOptions {
        known: samples.k1_range,
        stats: true,
    };
    fit_or_fallback_source(&format!("K1{sign}"), spec1, &src, opts, warnings)
}

/// The statistics of `curve` on a set's gathered points ([`k1_points_of`] or [`k2_points_of`]),
/// weighted as the recipe weighs the fit: those of a curve whose knot values were set by hand,
/// judged on the points its fit saw rather than keeping the fitted curve's.
pub fn stats_on_points(curve: &Approx, points: &PointSet, recipe: &Recipe) -> approx::FitStats {
    let src = Gathered {
        p: points,
        drift: recipe.weighting == Weighting::Drift,
    };
    approx::stats_with(curve, &src)
}

/// The K2 fit of both: over the set's K2 samples, with statistics.
fn fit_k2_from<S: PointSource>(
    samples: &SetSamples,
    src: &S,
    regime: Regime,
    recipe: &Recipe,
    warnings: &mut Vec<String>,
) -> Approx {
    let (_, spec2, sign) = set_specs(regime, recipe);
    let opts = FitOptions {
        known: samples.k2_range,
        stats: true,
    };
    fit_or_fallback_source(&format!("K2{sign}"), spec2, src, opts, warnings)
}

/// K1 and K2 of one set (+ or −), as the paper does (K1 from the ratios, then K2 from what the
/// fitted K1 leaves), followed by the recipe's refinement passes, each refitting K1 with the K2
/// term removed and then K2 with the new K1; with the last pass's statistics, and its points
/// when `points` is true (for display).
///
/// The passes are solved from moments gathered once (`set_moments.rs`), their T part taken
/// from `known` when given (made over the same sets' samples with the same designs and
/// weighting: the caller keys it); a set those cannot take is fitted by
/// [`fit_set_streaming`]. [`fit_sets_from`] of one axis, for the tests.
#[cfg(test)]
pub fn fit_set_from(
    samples: &SetSamples,
    inputs: SetInputs,
    regime: Regime,
    recipe: &Recipe,
    points: bool,
    known: Option<&Arc<SetTMoments>>,
) -> SetFit {
    let axis = SetAxis {
        rest: inputs.rest,
        recipe,
        points,
    };
    let (tdot, tddot) = (inputs.tdot, inputs.tddot);
    let mut fits = fit_sets_from(samples, tdot, tddot, &[axis], regime, known);
    fits.pop()
        .unwrap_or_else(|| fit_set_streaming(samples, inputs, regime, recipe, points))
}

/// [`fit_set_from`] for the axes of a unit over the same set's samples, T, K1 and K2 specs
/// and weighting: fitted together from moments ([`fit_sets_moments`]: the T part and each
/// sample's lookups made once for all of them), an axis they cannot take by the streaming
/// passes alone. Each axis's fit is the one [`fit_set_from`] makes of it alone, bit for bit.
pub(super) fn fit_sets_from(
    samples: &SetSamples,
    tdot: &[f64],
    tddot: &[f64],
    axes: &[SetAxis<'_>],
    regime: Regime,
    known: Option<&Arc<SetTMoments>>,
) -> Vec<SetFit> {
    fit_sets_moments(samples, tdot, tddot, axes, regime, known)
        .into_iter()
        .zip(axes)
        .map(|(fit, a)| {
            fit.unwrap_or_else(|| {
                let inputs = SetInputs {
                    tdot,
                    tddot,
                    rest: a.rest,
                };
                fit_set_streaming(samples, inputs, regime, a.recipe, a.points)
            })
        })
        .collect()
}

/// [`fit_set_from`] pass by pass, each fit streaming over the set's samples: the fits fall
/// back to a simpler curve when the points cannot support the spec, and say so. The
/// statistics are computed for the last pass only (the earlier ones serve only their curves).
/// When the points are asked for, the last pass gathers them first and fits on them: the same
/// curves, with K2 (K1) evaluated once per point instead of three times.
pub(super) fn fit_set_streaming(
    samples: &SetSamples,
    inputs: SetInputs,
    regime: Regime,
    recipe: &Recipe,
    points: bool,
) -> SetFit {
    let (spec1, spec2, sign) = set_specs(regime, recipe);
    let drift = recipe.weighting == Weighting::Drift;
    let (name1, name2) = (format!("K1{sign}"), format!("K2{sign}"));
    let mut k2: Option<Approx> = None;
    let mut out = SetFit {
        k1: Approx::zero(spec1.kind),
        k2: Approx::zero(spec2.kind),
        k1_points: PointSet::default(),
        k2_points: PointSet::default(),
        warnings: Vec::new(),
        refinements_run: None,
        t_moments: None,
    };
    for pass in 0..=recipe.refinements {
        let last = pass == recipe.refinements;
        // Warnings from the last pass only: earlier passes fit the same point sets.
        let mut warnings = Vec::new();
        let src1 = K1Source {
            idx: &samples.k1,
            inputs,
            k2: k2.as_ref(),
            drift,
        };
        let opts1 = FitOptions {
            known: samples.k1_range,
            stats: last,
        };
        let opts2 = FitOptions {
            known: samples.k2_range,
            stats: last,
        };
        let k2_fit;
        let k1;
        if last && points {
            let p1 = k1_points_of(samples, inputs, k2.as_ref());
            let src1 = Gathered { p: &p1, drift };
            // K2 needs K1's curve only, so it is fitted while K1's statistics are computed.
            let k2_step = |k1: &Approx| {
                let p2 = k2_points_of(samples, inputs, k1);
                let src2 = Gathered { p: &p2, drift };
                let mut w = Vec::new();
                let k2 = fit_or_fallback_source(&name2, spec2, &src2, opts2, &mut w);
                (p2, k2, w)
            };
            let (p2, k2_warnings);
            (k1, (p2, k2_fit, k2_warnings)) =
                match approx::fit_with_then(spec1, &src1, opts1, k2_step) {
                    Ok(fitted) => fitted,
                    Err(_) => {
                        // As `fit_or_fallback_source` falls back.
                        let (p, w) = collect_points(&src1);
                        let k1 = fit_or_fallback_weighted(
                            &name1,
                            spec1,
                            &p.x,
                            &p.y,
                            Some(&w),
                            &mut warnings,
                        );
                        let k2 = k2_step(&k1);
                        (k1, k2)
                    }
                };
            warnings.extend(k2_warnings);
            out.k1_points = p1;
            out.k2_points = p2;
        } else {
            k1 = fit_or_fallback_source(&name1, spec1, &src1, opts1, &mut warnings);
            let src2 = K2Source {
                idx: &samples.k2,
                inputs,
                k1: &k1,
                drift,
            };
            k2_fit = fit_or_fallback_source(&name2, spec2, &src2, opts2, &mut warnings);
        }
        out.k1 = k1;
        out.k2 = k2_fit.clone();
        out.warnings = warnings;
        k2 = Some(k2_fit);
    }
    out
}

impl Calibration {
    /// The pointwise K1± and K2± of `log` as this calibration's fit saw them (its plateaus and
    /// dead-bands; K1 with the fitted K2 term removed, K2 with the fitted K1), for the report's
    /// and the workbench's scatter plots. Order: K1+, K1−, K2+, K2−.
    pub fn pointwise(&self, log: &Log) -> [PointSet; 4] {
        if log.len() < crate::models::MIN_SAMPLES {
            return Default::default();
        }
        let prepared = Prepared::new(log, &self.recipe);
        let ranges: Vec<PlateauRange> = self.plateaus.iter().map(|p| p.range).collect();
        let mask = plateau::mask(&log.time_s, &ranges);
        let db = (self.resolved.deadband_tdot, self.resolved.deadband_tddot);
        let [plus, minus] = set_samples(&prepared.deriv, &mask, db);
        let rest = rest_dph(&prepared.omega_filtered_dph, &log.temp_c, &self.k0);
        let inputs = SetInputs {
            tdot: &prepared.deriv.tdot,
            tddot: &prepared.deriv.tddot,
            rest: &rest,
        };
        [
            k1_points_of(&plus, inputs, Some(&self.k2_plus)),
            k1_points_of(&minus, inputs, Some(&self.k2_minus)),
            k2_points_of(&plus, inputs, &self.k1_plus),
            k2_points_of(&minus, inputs, &self.k1_minus),
        ]
    }
}

#[cfg(test)]
mod tests;
