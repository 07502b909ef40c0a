//! A set's K1 and K2 through the paper's passes from moments gathered once.
//!
//! Each pass of the paper refits K1 on `(Ω_f − K0 − K2(T̈)·T̈) / Ṫ` with the K2 of the pass
//! before, then K2 on `(Ω_f − K0 − K1(Ṫ)·Ṫ) / T̈` with the new K1. Both curves are linear in
//! their parameters, so a K1 point is `yr − z·θ₂` with `yr = (Ω_f − K0)/Ṫ` and
//! `z = φ₂(T̈)·T̈/Ṫ` (`φ₂`: the weights of K2's parameters in its value), and K1's normal
//! equations are `A₁·θ₁ = h₁ − C₁·θ₂` with `A₁ = Σ w·B₁B₁ᵀ`, `h₁ = Σ w·B₁·yr` and
//! `C₁ = Σ w·B₁zᵀ`; K2's alike. One pass over each set's samples gathers `A`, `h` and `C`;
//! every pass after that is two small solves. A fit of three passes over a million samples read
//! the samples ten times; it now reads them four times (the moments, then the last pass's
//! points and statistics, `set_judged.rs`), whatever the number of refinements.
//!
//! `A` and `C` are T's alone, so the axes of a unit fitted over the same sets' samples and
//! designs share them: one pass gathers them once and each axis's `h` and `Σ w·yr` beside
//! them, each sample's basis found once ([`fit_sets_moments`]). Each axis's sums are added in
//! the order a pass over its points alone adds them, so its curves are the same bits.
//!
//! The designs (knots, scaling, penalty, solver) are the streaming fit's
//! ([`approx::Design`]), so the curves differ from a fit pass by pass only by rounding; the
//! statistics are computed on the points of the last pass, exactly as the streaming fit's. A
//! set the moments cannot take (too few points for a curve, a sample whose rate or K2 term is
//! not finite) is fitted by the streaming passes, which fall back to a simpler curve and say so.

use super::Regime;
use super::set_judged::{Judge, judged};
use super::sets::{SetFit, SetSamples, set_specs};
use crate::models::approx::{self, Approx, Design, Weights};
use crate::models::recipe::{Recipe, Weighting};
use std::sync::Arc;

/// The normal equations of one coefficient's fit over its set's samples, with the
/// cross-products that carry the other coefficient's term.
#[derive(Debug, Clone)]
struct Moments {
    /// Points used, and the sum of their weights.
    n: usize,
    sw: f64,
    /// `Σ w·B·Bᵀ`, upper triangle, row-major over `p × p`.
    ata: Vec<f64>,
    /// `Σ w·B·yr`.
    h: Vec<f64>,
    /// `Σ w·B·zᵀ`, row-major over `p × q`.
    cross: Vec<f64>,
    /// `Σ w·yr` and `Σ w·z`: the points' mean for a given other curve.
    s_yr: f64,
    s_z: Vec<f64>,
    /// Whether every point used had a finite `z`.
    finite: bool,
}

impl Moments {
    fn zero(p: usize, q: usize) -> Moments {
        Moments {
            n: 0,
            sw: 0.0,
            ata: vec![0.0; p * p],
            h: vec![0.0; p],
            cross: vec![0.0; p * q],
            s_yr: 0.0,
            s_z: vec![0.0; q],
            finite: true,
        }
    }

    /// The `p × q` sums of moments kept with strides `p + WB` and `q + WP` (the padding holds
    /// products with zero weights only).
    fn unpadded(self, p: usize, q: usize) -> Moments {
        let (sp, sq) = (self.h.len(), self.s_z.len());
        let mut out = Moments::zero(p, q);
        for a in 0..p {
            out.h[a] = self.h[a];
            out.ata[a * p..(a + 1) * p].copy_from_slice(&self.ata[a * sp..a * sp + p]);
            out.cross[a * q..(a + 1) * q].copy_from_slice(&self.cross[a * sq..a * sq + q]);
        }
        out.s_z.copy_from_slice(&self.s_z[..q]);
        Moments {
            n: self.n,
            sw: self.sw,
            s_yr: self.s_yr,
            finite: self.finite,
            ..out
        }
    }

    fn add(mut self, b: Moments) -> Moments {
        self.n += b.n;
        self.sw += b.sw;
        self.s_yr += b.s_yr;
        self.finite &= b.finite;
        for (x, y) in [
            (&mut self.ata, &b.ata),
            (&mut self.h, &b.h),
            (&mut self.cross, &b.cross),
            (&mut self.s_z, &b.s_z),
        ] {
            x.iter_mut().zip(y).for_each(|(p, q)| *p += q);
        }
        self
    }

    /// The right-hand side `h − C·θ_other` (`h` when there is no other curve yet).
    fn rhs(&self, other: Option<&[f64]>) -> Vec<f64> {
        let Some(t) = other else {
            return self.h.clone();
        };
        let q = t.len();
        self.h
            .iter()
            .enumerate()
            .map(|(j, h)| h - dot(&self.cross[j * q..(j + 1) * q], t))
            .collect()
    }

    /// The weighted mean of the points `yr − z·θ_other`.
    fn mean(&self, other: Option<&[f64]>) -> f64 {
        let s = self.s_yr - other.map_or(0.0, |t| dot(&self.s_z, t));
        s / self.sw
    }
}

/// The moments of a set that T alone makes (`A`, `C`, the weights and their sums: everything
/// but `h` and `Σ w·yr`, which carry Ω − K0): the same for every axis of a unit fitted over
/// the same sets' samples with the same K1 and K2 designs and weighting. Kept beside the sets'
/// samples ([`super::staged::StageMemory`]) and given back to [`fit_set_moments`], which
/// then reads each sample's Ω alone: a second axis's fit costs its `h` and its statistics.
#[derive(Debug, Clone)]
pub struct SetTMoments {
    /// K1's moments, `h` and `Σ w·yr` left at zero.
    k1: Moments,
    /// K2's alike.
    k2: Moments,
}

impl SetTMoments {
    /// The T part of `m1` and `m2`.
    fn of(m1: &Moments, m2: &Moments) -> SetTMoments {
        let t = |m: &Moments| Moments {
            h: vec![0.0; m.h.len()],
            s_yr: 0.0,
            ..m.clone()
        };
        SetTMoments {
            k1: t(m1),
            k2: t(m2),
        }
    }
}

/// The Ω part of a coefficient's moments: `Σ w·B·yr`, `Σ w·yr`, and the points they counted.
struct OmegaMoments {
    n: usize,
    h: Vec<f64>,
    s_yr: f64,
}

impl OmegaMoments {
    fn add(mut self, b: OmegaMoments) -> OmegaMoments {
        self.n += b.n;
        self.s_yr += b.s_yr;
        self.h.iter_mut().zip(&b.h).for_each(|(p, q)| *p += q);
        self
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The columns of one coefficient's points that T alone makes: its own argument (Ṫ for K1),
/// the other's (T̈).
#[derive(Clone, Copy)]
struct Columns<'a> {
    own: &'a [f64],
    other: &'a [f64],
}

/// Whether a point of argument `x` and weight `w` can be counted, its ratio aside: what
/// [`approx::usable`] asks of `x` and `w`.
#[inline(always)]
fn weighed(x: f64, w: f64) -> bool {
    x.is_finite() && w.is_finite() && w > 0.0
}

impl OmegaMoments {
    fn zero(p: usize) -> OmegaMoments {
        OmegaMoments {
            n: 0,
            h: vec![0.0; p],
            s_yr: 0.0,
        }
    }

    /// Adds one axis's point of argument `x`, weight `w` and basis weights `b` (from
    /// `first`), when its ratio `rest / x` is finite (else the point is not counted, as
    /// [`approx::usable`] leaves it out).
    #[inline(always)]
    fn push<const WB: usize>(&mut self, x: f64, w: f64, rest: f64, first: usize, b: &[f64; 4]) {
        let yr = rest / x;
        if !yr.is_finite() {
            return;
        }
        self.n += 1;
        self.s_yr += w * yr;
        for (h, &ba) in self.h[first..first + WB].iter_mut().zip(&b[..WB]) {
            let wa = w * ba;
            *h += wa * yr;
        }
    }

    /// The `p` sums of moments kept with padding.
    fn truncated(mut self, p: usize) -> OmegaMoments {
        self.h.truncate(p);
        self
    }
}

/// The chunks' sums of each axis added in order.
fn add_axes(a: Vec<OmegaMoments>, b: Vec<OmegaMoments>) -> Vec<OmegaMoments> {
    a.into_iter().zip(b).map(|(x, y)| x.add(y)).collect()
}

/// Each axis's moments: the T part `t` with the axis's Ω part, when the axis counted every
/// point `t` did (else `None`: a point whose `Ω − K0` is not finite sends the axis's set to
/// the streaming fit, which leaves such points out and says what it fitted).
fn with_omega(t: &Moments, omega: Vec<OmegaMoments>) -> Vec<Option<Moments>> {
    omega
        .into_iter()
        .map(|o| {
            (o.n == t.n).then(|| Moments {
                n: o.n,
                h: o.h,
                s_yr: o.s_yr,
                ..t.clone()
            })
        })
        .collect()
}

/// Gathers the moments of the points `idx` of one coefficient (basis `own`) against the other
/// coefficient's value weights (`other`), over fixed chunks summed in order, so the sums do
/// not depend on the number of threads: the T part once (`h` and `Σ w·yr` left at zero), and
/// the Ω part of each axis whose `Ω_f − K0` is in `rests`. Each axis's sums are those a pass
/// over its points alone makes (the same products, added in the same order).
fn moments(
    idx: &[u32],
    cols: Columns,
    rests: &[&[f64]],
    own: &Design,
    other: &Design,
    drift: bool,
) -> (Moments, Vec<OmegaMoments>) {
    // The kernel is made for each pair of basis widths (2: a line or a piecewise-linear
    // curve; 3: a parabola; 4: a spline), so its loops have fixed lengths and unroll.
    macro_rules! by_width {
        ($($b:literal, $p:literal);*) => {
            match (own.max_width(), other.max_width()) {
                $(($b, $p) => moments_of::<$b, $p>(idx, cols, rests, own, other, drift),)*
                _ => moments_of::<4, 4>(idx, cols, rests, own, other, drift),
            }
        };
    }
    by_width!(2, 2; 2, 3; 2, 4; 3, 2; 3, 3; 3, 4; 4, 2; 4, 3)
}

/// [`moments`] with bases of at most `WB` (own) and `WP` (other) weights a point. The sums are
/// kept in arrays padded by the widths, so that the weights a point lacks (zeros past a
/// basis's width) are added without a bound check and change nothing.
fn moments_of<const WB: usize, const WP: usize>(
    idx: &[u32],
    cols: Columns,
    rests: &[&[f64]],
    own: &Design,
    other: &Design,
    drift: bool,
) -> (Moments, Vec<OmegaMoments>) {
    let (p, q) = (own.params(), other.params());
    let (sp, sq) = (p + WB, q + WP);
    let zero = || {
        let omega = rests.iter().map(|_| OmegaMoments::zero(sp)).collect();
        (Moments::zero(sp, sq), omega)
    };
    let part = |from: usize, to: usize| {
        let (mut m, mut omega): (Moments, Vec<OmegaMoments>) = zero();
        for &i in &idx[from..to] {
            let i = i as usize;
            let (x, o) = (cols.own[i], cols.other[i]);
            let w = if drift { x * x } else { 1.0 };
            if !weighed(x, w) {
                continue;
            }
            let zf = o / x;
            if !zf.is_finite() {
                m.finite = false;
                continue;
            }
            let phi = other.value_weights(o);
            m.n += 1;
            m.sw += w;
            for k in 0..WP {
                m.s_z[phi.first + k] += w * phi.weights[k] * zf;
            }
            let Weights {
                first, weights: b, ..
            } = own.basis(x);
            for a in 0..WB {
                let wa = w * b[a];
                let row = (first + a) * sp + first;
                for (c, bc) in b.iter().enumerate().take(WB).skip(a) {
                    m.ata[row + c] += wa * bc;
                }
                let row = (first + a) * sq + phi.first;
                let waz = wa * zf;
                for k in 0..WP {
                    m.cross[row + k] += waz * phi.weights[k];
                }
            }
            for (om, rest) in omega.iter_mut().zip(rests) {
                om.push::<WB>(x, w, rest[i], first, &b);
            }
        }
        (m, omega)
    };
    let add = |(a, ao): (Moments, Vec<OmegaMoments>), (b, bo): (Moments, Vec<OmegaMoments>)| {
        (a.add(b), add_axes(ao, bo))
    };
    let (m, omega) = approx::over_chunks(idx.len(), part, add).unwrap_or_else(zero);
    let omega = omega.into_iter().map(|o| o.truncated(p)).collect();
    (m.unpadded(p, q), omega)
}

/// The moments of the points `idx` of one coefficient whose T part `t` is known, for each
/// axis of `rests`: only `h` and `Σ w·yr` are gathered, each sample's basis evaluated once
/// more (once for all the axes). Every sum is made as [`moments_of`] makes it (the same
/// products, added in the same order, over the same chunks), so the moments are those
/// [`moments`] gives, bit for bit; `None` for an axis that did not count every point `t` did.
fn moments_given_t(
    idx: &[u32],
    cols: Columns,
    rests: &[&[f64]],
    own: &Design,
    drift: bool,
    t: &Moments,
) -> Vec<Option<Moments>> {
    macro_rules! by_width {
        ($($b:literal),*) => {
            match own.max_width() {
                $($b => omega_moments_of::<$b>(idx, cols, rests, own, drift),)*
                _ => omega_moments_of::<4>(idx, cols, rests, own, drift),
            }
        };
    }
    with_omega(t, by_width!(2, 3))
}

/// [`moments_given_t`]'s pass, with a basis of at most `WB` weights a point.
fn omega_moments_of<const WB: usize>(
    idx: &[u32],
    cols: Columns,
    rests: &[&[f64]],
    own: &Design,
    drift: bool,
) -> Vec<OmegaMoments> {
    let p = own.params();
    let sp = p + WB;
    let zero = || rests.iter().map(|_| OmegaMoments::zero(sp)).collect();
    let part = |from: usize, to: usize| {
        let mut omega: Vec<OmegaMoments> = zero();
        for &i in &idx[from..to] {
            let i = i as usize;
            let (x, o) = (cols.own[i], cols.other[i]);
            let w = if drift { x * x } else { 1.0 };
            if !weighed(x, w) || !(o / x).is_finite() {
                continue;
            }
            let Weights {
                first, weights: b, ..
            } = own.basis(x);
            for (om, rest) in omega.iter_mut().zip(rests) {
                om.push::<WB>(x, w, rest[i], first, &b);
            }
        }
        omega
    };
    let omega = approx::over_chunks(idx.len(), part, add_axes).unwrap_or_else(zero);
    omega.into_iter().map(|o| o.truncated(p)).collect()
}

/// One axis of a set fitted from moments: what is its own of the set's fit.
pub(super) struct SetAxis<'a> {
    /// `Ω_f − K0(T)` of the axis, °/h.
    pub rest: &'a [f64],
    /// The axis's recipe (its K1 and K2 specs and weighting those of every axis fitted with
    /// it; its refinements its own).
    pub recipe: &'a Recipe,
    /// Whether the points of the last pass are kept.
    pub points: bool,
}

/// One axis's passes solved: its curves, the K2 its last K1 points carry, the points' means
/// and the pass the passes stopped at (when they diverged).
struct Solved {
    k1: Approx,
    k2: Approx,
    k2_before: Option<Approx>,
    means: (f64, f64),
    stopped: Option<usize>,
}

/// K1 and K2 of one set from its moments, through the recipe's passes, with the last pass's
/// statistics and (when `points`) its points; `None` when the moments cannot take the set
/// (see the module's text), which the streaming passes then fit. [`fit_sets_moments`] of
/// one axis, for the tests.
#[cfg(test)]
pub(super) fn fit_set_moments(
    samples: &SetSamples,
    inputs: super::sets::SetInputs,
    regime: Regime,
    recipe: &Recipe,
    points: bool,
    known: Option<&Arc<SetTMoments>>,
) -> Option<SetFit> {
    let axis = SetAxis {
        rest: inputs.rest,
        recipe,
        points,
    };
    let mut fits = fit_sets_moments(samples, inputs.tdot, inputs.tddot, &[axis], regime, known);
    fits.pop().flatten()
}

/// [`fit_set_moments`] for several axes over the same set's samples, T (`tdot`, `tddot`),
/// K1 and K2 specs and weighting (those of the first axis's recipe): the moments' T part
/// gathered once (or taken from `known`), each sample's basis found once for every axis's Ω
/// part, each axis's passes solved, then every axis judged in one pass. Each axis's fit is
/// the one [`fit_set_moments`] makes of it alone, bit for bit; `None` for an axis the moments
/// cannot take.
pub(super) fn fit_sets_moments(
    samples: &SetSamples,
    tdot: &[f64],
    tddot: &[f64],
    axes: &[SetAxis<'_>],
    regime: Regime,
    known: Option<&Arc<SetTMoments>>,
) -> Vec<Option<SetFit>> {
    let none = || axes.iter().map(|_| None).collect();
    let Some(first) = axes.first() else {
        return Vec::new();
    };
    let (spec1, spec2, _) = set_specs(regime, first.recipe);
    let designs = samples
        .k1_range
        .zip(samples.k2_range)
        .and_then(|(r1, r2)| Some((Design::new(spec1, r1).ok()?, Design::new(spec2, r2).ok()?)));
    let Some((d1, d2)) = designs else {
        return none();
    };
    let drift = first.recipe.weighting == Weighting::Drift;
    let rests: Vec<&[f64]> = axes.iter().map(|a| a.rest).collect();
    // K1's points are over Ṫ with K2's term of T̈, K2's the other way round.
    let cols = |own, other| Columns { own, other };
    // The T part given (another axis's, or this one's before an edit that left T's sets as
    // they were) when its sizes are these designs'; else all of it gathered here.
    let known = known.filter(|t| {
        (t.k1.h.len(), t.k1.s_z.len(), t.k2.h.len(), t.k2.s_z.len())
            == (d1.params(), d2.params(), d2.params(), d1.params())
    });
    let (m1, m2, t_moments) = match known {
        Some(t) => {
            let (m1, m2) = rayon::join(
                || moments_given_t(&samples.k1, cols(tdot, tddot), &rests, &d1, drift, &t.k1),
                || moments_given_t(&samples.k2, cols(tddot, tdot), &rests, &d2, drift, &t.k2),
            );
            (m1, m2, t.clone())
        }
        None => {
            let ((t1, o1), (t2, o2)) = rayon::join(
                || moments(&samples.k1, cols(tdot, tddot), &rests, &d1, &d2, drift),
                || moments(&samples.k2, cols(tddot, tdot), &rests, &d2, &d1, drift),
            );
            let t = Arc::new(SetTMoments::of(&t1, &t2));
            (with_omega(&t1, o1), with_omega(&t2, o2), t)
        }
    };
    let solved: Vec<Option<Solved>> = axes
        .iter()
        .zip(m1.iter().zip(&m2))
        .map(|(axis, (m1, m2))| {
            // Every point the range counted, each with its other term: else the streaming fit.
            let (m1, m2) = (m1.as_ref()?, m2.as_ref()?);
            if m1.n != d1.points() || m2.n != d2.points() || !m1.finite || !m2.finite {
                return None;
            }
            solve(&d1, &d2, m1, m2, axis.recipe.refinements)
        })
        .collect();
    // Every axis the moments took, judged on its points in one pass per coefficient.
    let took: Vec<(&SetAxis<'_>, &Solved)> = axes
        .iter()
        .zip(&solved)
        .filter_map(|(a, s)| Some((a, s.as_ref()?)))
        .collect();
    let judge1: Vec<Judge<'_>> = took
        .iter()
        .map(|(a, s)| Judge {
            rest: a.rest,
            curve: &s.k1,
            other: s.k2_before.as_ref(),
            mean: s.means.0,
            gather: a.points,
        })
        .collect();
    let judge2: Vec<Judge<'_>> = took
        .iter()
        .map(|(a, s)| Judge {
            rest: a.rest,
            curve: &s.k2,
            other: Some(&s.k1),
            mean: s.means.1,
            gather: a.points,
        })
        .collect();
    let (judged1, judged2) = rayon::join(
        || judged(&samples.k1, tdot, tddot, &judge1, drift),
        || judged(&samples.k2, tddot, tdot, &judge2, drift),
    );
    let mut judged = judged1.into_iter().zip(judged2);
    axes.iter()
        .zip(solved)
        .map(|(axis, s)| {
            let s = s?;
            let ((s1, p1), (s2, p2)) = judged.next()?;
            Some(SetFit {
                k1: s.k1.with_stats(s1),
                k2: s.k2.with_stats(s2),
                k1_points: p1,
                k2_points: p2,
                warnings: s
                    .stopped
                    .map(|pass| {
                        let (c1, c2, sign) = (spec1.kind, spec2.kind, regime_sign(regime));
                        vec![format!(
                            "K1{sign}: the refinement passes of K1{sign} ({c1}) and K2{sign} \
                             ({c2}) diverge (refinement {pass} moved K1{sign} more than \
                             refinement {}): stopped after {} of the {} refinements asked for; \
                             ask for fewer refinements or fewer knots",
                            pass - 1,
                            pass - 1,
                            axis.recipe.refinements
                        )]
                    })
                    .unwrap_or_default(),
                refinements_run: s.stopped.map(|pass| pass - 1),
                t_moments: Some(t_moments.clone()),
            })
        })
        .collect()
}

/// The passes of one axis solved from its moments: `refinements` refinements after the first
/// pass, stopped at the last one before the change grows.
fn solve(
    d1: &Design,
    d2: &Design,
    m1: &Moments,
    m2: &Moments,
    refinements: usize,
) -> Option<Solved> {
    let mut theta1 = Vec::new();
    let mut theta2: Option<Vec<f64>> = None;
    // The K2 the last pass's K1 points carry (the pass before's; none in a single pass).
    let mut k2_before = None;
    // The passes alternate between two fits over different samples and weights, which need
    // not converge: with many knots each pass can move the curves more than the one before
    // (64-knot splines refined 14 times reached an RMS residual of 6.6e4 °/h). The passes stop
    // at the last one before the change grows, and say so.
    let mut last_step = f64::INFINITY;
    let mut stopped = None;
    for pass in 0..=refinements {
        let next = d1.solve(&m1.ata, m1.rhs(theta2.as_deref()));
        if pass > 0 {
            let step = distance(&next, &theta1);
            let scale = 1e-9 * (1.0 + norm(&theta1));
            if pass >= 2 && step > last_step && step > scale {
                stopped = Some(pass);
                break;
            }
            last_step = step;
        }
        theta1 = next;
        k2_before = theta2.take();
        theta2 = Some(d2.solve(&m2.ata, m2.rhs(Some(&theta1))));
    }
    let k1 = d1.approx(&theta1).ok()?;
    let k2 = d2.approx(theta2.as_deref()?).ok()?;
    let k2_before_curve = match &k2_before {
        Some(t) => Some(d2.approx(t).ok()?),
        None => None,
    };
    Some(Solved {
        k1,
        k2,
        k2_before: k2_before_curve,
        means: (m1.mean(k2_before.as_deref()), m2.mean(Some(&theta1))),
        stopped,
    })
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

/// The sign of a regime's set as warnings write it.
fn regime_sign(regime: Regime) -> &'static str {
    if regime == Regime::Minus { "-" } else { "+" }
}

#[cfg(test)]
mod tests;
