//! Knot curves: the `splines` evaluator with its phantom end keys, the same curve as weights on
//! the knot values (the basis the fits use), and as one cubic per segment (the fast evaluator).

use super::{ApproxKind, Curve};
use splines::{Interpolation, Key, Spline};

/// A knot curve as cubic polynomials in the local parameter `u ∈ [0, 1]` of each segment.
///
/// The `splines` crate defines the curve; evaluating it costs a binary search and a Hermite
/// blend per call (about 16 ns), which a correction of millions of samples per edit cannot
/// afford. Each segment of a piecewise-linear or Catmull-Rom curve is a polynomial of degree
/// at most 3 in `u`, so four samples of the crate's curve per segment determine it exactly; the
/// hot loop then finds the segment (arithmetically, for the equally spaced knots fits produce)
/// and takes one Horner step. A test holds the two evaluations equal.
#[derive(Debug, Clone)]
pub(super) struct Segments {
    knots_x: Vec<f64>,
    /// `1/h` when the knots are equally spaced, else 0 (binary search).
    inv_step: f64,
    /// Per segment, `c0 + c1·u + c2·u² + c3·u³`.
    coeffs: Vec<[f64; 4]>,
    /// Equally spaced knots only: each segment's start, width and cubic side by side, so that
    /// the hot loop reads one small record per sample ([`Uniform`]).
    flat: Vec<Flat>,
}

/// A segment as the uniform evaluator reads it: its left knot, its width (the same difference
/// [`Segments::eval`] takes, so the same bits) and its cubic.
#[derive(Debug, Clone, Copy)]
pub(super) struct Flat {
    x0: f64,
    width: f64,
    c: [f64; 4],
}

/// [`Segments::eval`] for equally spaced knots, with everything it recomputes per call (the
/// last segment's index as a float, the knot and coefficient lookups) taken out of the loop.
#[derive(Debug, Clone, Copy)]
pub(super) struct Uniform<'a> {
    first: f64,
    inv_step: f64,
    last_f: f64,
    last: usize,
    flat: &'a [Flat],
}

impl Uniform<'_> {
    /// The segment `x` falls in and its local parameter there: [`Segments::locate`], bit for
    /// bit, with what that recomputes per call taken out of the loop.
    #[inline(always)]
    pub(super) fn locate(&self, x: f64) -> (usize, f64) {
        let t = (x - self.first) * self.inv_step;
        let i = if t < self.last_f {
            t as u32 as usize
        } else {
            self.last
        };
        let s = &self.flat[i];
        (i, ((x - s.x0) / s.width).clamp(0.0, 1.0))
    }

    /// The cubic of segment `i` at its local parameter `u`.
    #[inline(always)]
    pub(super) fn at(&self, i: usize, u: f64) -> f64 {
        let c = &self.flat[i].c;
        ((c[3] * u + c[2]) * u + c[1]) * u + c[0]
    }

    /// Whether `other`'s segments start and span where these do, bit for bit.
    pub(super) fn same_knots(&self, other: &Uniform<'_>) -> bool {
        let bits = |a: f64, b: f64| a.to_bits() == b.to_bits();
        bits(self.first, other.first)
            && bits(self.inv_step, other.inv_step)
            && self.last == other.last
            && self.flat.len() == other.flat.len()
            && self
                .flat
                .iter()
                .zip(other.flat)
                .all(|(a, b)| bits(a.x0, b.x0) && bits(a.width, b.width))
    }
}

impl Segments {
    pub(super) fn of(curve: &Curve) -> Option<Segments> {
        let (Curve::Pwl { knots_x, knots_y } | Curve::CatmullRom { knots_x, knots_y }) = curve
        else {
            return None;
        };
        let spline = build_spline(curve);
        let n = knots_x.len();
        let coeffs: Vec<[f64; 4]> = (0..n - 1)
            .map(|i| {
                let (a, b) = (knots_x[i], knots_x[i + 1]);
                let at = |u: f64| {
                    if u >= 1.0 {
                        knots_y[i + 1]
                    } else {
                        spline.sample(a + (b - a) * u).unwrap_or(knots_y[i])
                    }
                };
                if matches!(curve, Curve::Pwl { .. }) {
                    // Linear segments: the two ends say it all, and exactly.
                    let (p0, p3) = (at(0.0), at(1.0));
                    return [p0, p3 - p0, 0.0, 0.0];
                }
                let (p0, p1, p2, p3) = (at(0.0), at(1.0 / 3.0), at(2.0 / 3.0), at(1.0));
                // The cubic through (0, p0), (1/3, p1), (2/3, p2), (1, p3) in powers of u.
                [
                    p0,
                    (-11.0 * p0 + 18.0 * p1 - 9.0 * p2 + 2.0 * p3) / 2.0,
                    (18.0 * p0 - 45.0 * p1 + 36.0 * p2 - 9.0 * p3) / 2.0,
                    (-9.0 * p0 + 27.0 * p1 - 27.0 * p2 + 9.0 * p3) / 2.0,
                ]
            })
            .collect();
        let h = (knots_x[n - 1] - knots_x[0]) / (n - 1) as f64;
        let uniform = knots_x
            .iter()
            .enumerate()
            .all(|(j, &x)| (x - (knots_x[0] + h * j as f64)).abs() <= 1e-12 * h.abs().max(1e-300));
        let flat = if uniform {
            coeffs
                .iter()
                .enumerate()
                .map(|(i, &c)| Flat {
                    x0: knots_x[i],
                    width: knots_x[i + 1] - knots_x[i],
                    c,
                })
                .collect()
        } else {
            Vec::new()
        };
        Some(Segments {
            knots_x: knots_x.clone(),
            inv_step: if uniform { 1.0 / h } else { 0.0 },
            coeffs,
            flat,
        })
    }

    /// The knot positions, `1/h` (0 when not equally spaced) and the per-segment cubics.
    pub(super) fn parts(&self) -> (&[f64], f64, &[[f64; 4]]) {
        (&self.knots_x, self.inv_step, &self.coeffs)
    }

    /// The uniform evaluator, when the knots are equally spaced.
    pub(super) fn uniform(&self) -> Option<Uniform<'_>> {
        (self.inv_step > 0.0 && !self.flat.is_empty()).then(|| Uniform {
            first: self.knots_x[0],
            inv_step: self.inv_step,
            last_f: (self.knots_x.len() - 2) as f64,
            last: self.knots_x.len() - 2,
            flat: &self.flat,
        })
    }

    /// Value at `x` inside the knots.
    #[inline]
    pub(super) fn eval(&self, x: f64) -> f64 {
        let (i, u) = self.locate(x);
        self.at(i, u)
    }

    /// The segment `x` (inside the knots) falls in, and its local parameter there.
    #[inline]
    pub(super) fn locate(&self, x: f64) -> (usize, f64) {
        let k = &self.knots_x;
        let last = k.len() - 2;
        let i = if self.inv_step > 0.0 {
            // ⌊t⌋ capped at the last segment, as `(t as usize).min(last)` gives it (t ≥ 0 here),
            // without the saturating float-to-usize conversion, which costs more than the rest
            // of a segment's evaluation.
            let t = (x - k[0]) * self.inv_step;
            if t < last as f64 {
                t as u32 as usize
            } else {
                last
            }
        } else {
            at_or_below(k, x).saturating_sub(1).min(last)
        };
        (i, ((x - k[i]) / (k[i + 1] - k[i])).clamp(0.0, 1.0))
    }

    /// The cubic of segment `i` at its local parameter `u`.
    #[inline]
    pub(super) fn at(&self, i: usize, u: f64) -> f64 {
        let c = &self.coeffs[i];
        ((c[3] * u + c[2]) * u + c[1]) * u + c[0]
    }

    /// Whether `other`'s knots are these, bit for bit.
    pub(super) fn same_knots(&self, other: &Segments) -> bool {
        self.knots_x.len() == other.knots_x.len()
            && self
                .knots_x
                .iter()
                .zip(&other.knots_x)
                .all(|(a, b)| a.to_bits() == b.to_bits())
    }
}

/// The `splines` evaluator of a knot curve. Catmull-Rom needs a key beyond each end: a phantom
/// knot continuing the end segment straight, so that the curve's end tangents follow the data.
pub(super) fn build_spline(curve: &Curve) -> Spline<f64, f64> {
    match curve {
        Curve::Polynomial { .. } => Spline::from_vec(Vec::new()),
        Curve::Pwl { knots_x, knots_y } => Spline::from_vec(
            knots_x
                .iter()
                .zip(knots_y)
                .map(|(&x, &y)| Key::new(x, y, Interpolation::Linear))
                .collect(),
        ),
        Curve::CatmullRom { knots_x, knots_y } => {
            let n = knots_x.len();
            let mut keys = Vec::with_capacity(n + 2);
            keys.push(Key::new(
                2.0 * knots_x[0] - knots_x[1],
                2.0 * knots_y[0] - knots_y[1],
                Interpolation::CatmullRom,
            ));
            keys.extend(
                knots_x
                    .iter()
                    .zip(knots_y)
                    .map(|(&x, &y)| Key::new(x, y, Interpolation::CatmullRom)),
            );
            keys.push(Key::new(
                2.0 * knots_x[n - 1] - knots_x[n - 2],
                2.0 * knots_y[n - 1] - knots_y[n - 2],
                Interpolation::CatmullRom,
            ));
            Spline::from_vec(keys)
        }
    }
}

/// How many of the (increasing) knots are at or below `x`: `knots.partition_point(|&k| k <=
/// x)`, counted without branches for the few knots a curve has. A binary search over knots
/// placed by hand mispredicts a branch or two per sample, which made a correction and each
/// pass of a fit over a million samples three times slower than the equally spaced knots'
/// arithmetic lookup.
#[inline]
fn at_or_below(knots: &[f64], x: f64) -> usize {
    if knots.len() <= 32 {
        knots.iter().map(|&k| usize::from(k <= x)).sum()
    } else {
        knots.partition_point(|&k| k <= x)
    }
}

/// Equally spaced knot positions over `[lo, hi]` (a degenerate range is widened a little so the
/// knots stay strictly increasing).
pub fn knot_positions(lo: f64, hi: f64, m: usize) -> Vec<f64> {
    let (lo, hi) = if hi > lo {
        (lo, hi)
    } else {
        let pad = lo.abs().max(1.0) * 1e-9;
        (lo - pad, hi + pad)
    };
    (0..m)
        .map(|j| lo + (hi - lo) * j as f64 / (m - 1) as f64)
        .collect()
}

/// Weights of the knot values at `x` for a knot curve, as (first knot index, up to 4 weights).
///
/// The value of a piecewise-linear or Catmull-Rom curve is linear in its knot values; these are
/// the coefficients, written out from the same formulas the `splines` crate evaluates
/// (`cubic_hermite` with finite-difference tangents), with the phantom end knots folded back onto
/// the real ones. `x` must lie within the knots.
pub fn knot_weights(kind: ApproxKind, knots_x: &[f64], x: f64) -> (usize, [f64; 4]) {
    let n = knots_x.len();
    // Segment i: knots_x[i] <= x < knots_x[i+1] (the last segment includes its right end).
    let i = match at_or_below(knots_x, x) {
        0 => 0,
        p => (p - 1).min(n - 2),
    };
    let (xa, xb) = (knots_x[i], knots_x[i + 1]);
    let t = ((x - xa) / (xb - xa)).clamp(0.0, 1.0);
    if kind != ApproxKind::Spline {
        return (i, [1.0 - t, t, 0.0, 0.0]);
    }
    // Neighbouring knot positions, phantom ones by straight continuation.
    let xp = if i == 0 {
        2.0 * xa - xb
    } else {
        knots_x[i - 1]
    };
    let xn = if i + 2 >= n {
        2.0 * xb - xa
    } else {
        knots_x[i + 2]
    };
    let (t2, t3) = (t * t, t * t * t);
    let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
    let h10 = t3 - 2.0 * t2 + t;
    let h01 = 3.0 * t2 - 2.0 * t3;
    let h11 = t3 - t2;
    let s0 = (xb - xa) / (xb - xp);
    let s1 = (xb - xa) / (xn - xa);
    // value = h00·ya + h10·s0·(yb − yp) + h01·yb + h11·s1·(yn − ya)
    let mut w = [0.0; 4]; // weights on knots i-1, i, i+1, i+2
    w[0] -= h10 * s0;
    w[1] += h00 - h11 * s1;
    w[2] += h01 + h10 * s0;
    w[3] += h11 * s1;
    // Fold phantoms: yp = 2ya − yb at the left end, yn = 2yb − ya at the right end.
    if i == 0 {
        let wp = w[0];
        w[0] = 0.0;
        w[1] += 2.0 * wp;
        w[2] -= wp;
    }
    if i + 2 >= n {
        let wn = w[3];
        w[3] = 0.0;
        w[2] += 2.0 * wn;
        w[1] -= wn;
    }
    if i == 0 {
        // Shift so the first weight belongs to knot 0.
        (0, [w[1], w[2], w[3], 0.0])
    } else {
        (i - 1, w)
    }
}
