//! The statistics and points of a set's last pass, for every axis fitted over the set at once.
//!
//! A K1 point is `(Ṫ, (Ω_f − K0 − K2(T̈)·T̈) / Ṫ)` and a K2 point `(T̈, (Ω_f − K0 − K1(Ṫ)·Ṫ) / T̈)`
//! ([`super::sets::k1_ratio`], [`super::sets::k2_ratio`]); the statistics are those of the
//! fitted curve on them. Everything but `Ω_f − K0` is T's alone, and the axes of a unit fitted
//! over the same sets have curves of the same knots: each sample's rates are read and its spots
//! on the curves found once ([`Evaluator::same_spots`]), then each axis's point made and
//! judged. Each axis's statistics and points are those it gets judged alone, bit for bit: the
//! same values ([`Evaluator::at`] at [`Evaluator::spot`] is [`Evaluator::eval`]), summed over the
//! same chunks in the same order.

use super::PointSet;
use crate::models::approx::{self, Approx, Evaluator, FitStats, Spot};
use rayon::prelude::*;

/// One axis's curve to judge on a coefficient's points.
pub(super) struct Judge<'a> {
    /// `Ω_f − K0(T)` of the axis, °/h.
    pub rest: &'a [f64],
    /// The curve judged (K1 on K1's points).
    pub curve: &'a Approx,
    /// The other coefficient's curve the points carry (K2 of the pass before for K1's points,
    /// none in a single pass; K1 for K2's).
    pub other: Option<&'a Approx>,
    /// The points' weighted mean.
    pub mean: f64,
    /// Whether the points are kept (for display, or a fit at knots placed by hand).
    pub gather: bool,
}

/// A chunk's (points used, Σw, SSres, SStot) of one axis.
type Sums = (usize, f64, f64, f64);

/// The statistics and (when gathered) points of each axis's curve on the points `idx`: the
/// coefficient's own argument in `own` (Ṫ for K1), the other's in `other` (T̈ for K1).
pub(super) fn judged(
    idx: &[u32],
    own: &[f64],
    other: &[f64],
    axes: &[Judge<'_>],
    drift: bool,
) -> Vec<(FitStats, PointSet)> {
    if axes.is_empty() {
        return Vec::new();
    }
    let n = idx.len();
    let mut pts: Vec<PointSet> = axes
        .iter()
        .map(|a| PointSet {
            x: if a.gather { vec![0.0; n] } else { Vec::new() },
            y: if a.gather { vec![0.0; n] } else { Vec::new() },
        })
        .collect();
    let evals: Vec<(Evaluator<'_>, Option<Evaluator<'_>>)> = axes
        .iter()
        .map(|a| (a.curve.evaluator(), a.other.map(Approx::evaluator)))
        .collect();
    // Whether every axis's curves fall on the first's spots: then found once a sample.
    let shared = evals.iter().all(|(c, o)| {
        c.same_spots(&evals[0].0)
            && match (o, &evals[0].1) {
                (Some(o), Some(first)) => o.same_spots(first),
                (None, None) => true,
                _ => false,
            }
    });
    let chunks = n.div_ceil(approx::CHUNK);
    // Each chunk with every axis's lane: its curves and its slices of the points (empty when
    // not gathered).
    let mut parts: Vec<Vec<Lane<'_, '_>>> = (0..chunks).map(|_| Vec::new()).collect();
    for ((p, axis), (curve, other)) in pts.iter_mut().zip(axes).zip(&evals) {
        let lane = |xs, ys| Lane {
            rest: axis.rest,
            curve: *curve,
            other: *other,
            mean: axis.mean,
            xs,
            ys,
            sums: (0, 0.0, 0.0, 0.0),
        };
        if p.x.is_empty() {
            parts
                .iter_mut()
                .for_each(|c| c.push(lane(&mut [], &mut [])));
        } else {
            let xs = p.x.chunks_mut(approx::CHUNK);
            for (c, (xs, ys)) in xs.zip(p.y.chunks_mut(approx::CHUNK)).enumerate() {
                parts[c].push(lane(xs, ys));
            }
        }
    }
    let part = |c: usize, mut lanes: Vec<Lane<'_, '_>>| -> Vec<Sums> {
        let from = c * approx::CHUNK;
        let to = (from + approx::CHUNK).min(n);
        let idx = &idx[from..to];
        if shared {
            judge_chunk::<true>(idx, own, other, drift, &mut lanes);
        } else {
            judge_chunk::<false>(idx, own, other, drift, &mut lanes);
        }
        lanes.into_iter().map(|l| l.sums).collect()
    };
    let per_chunk: Vec<Vec<Sums>> = parts
        .into_par_iter()
        .enumerate()
        .map(|(c, lanes)| part(c, lanes))
        .collect();
    pts.into_iter()
        .enumerate()
        .map(|(a, p)| {
            let (used, sw, ss_res, ss_tot) = per_chunk.iter().fold((0, 0.0, 0.0, 0.0), |s, c| {
                (s.0 + c[a].0, s.1 + c[a].1, s.2 + c[a].2, s.3 + c[a].3)
            });
            let stats = FitStats {
                n: used,
                rmse: (ss_res / sw).sqrt(),
                r2: if ss_tot > 0.0 {
                    1.0 - ss_res / ss_tot
                } else {
                    0.0
                },
            };
            (stats, p)
        })
        .collect()
}

/// One axis in a chunk of points: its `Ω_f − K0`, its curves, its slices of the points
/// (empty when they are not kept) and its sums so far.
struct Lane<'a, 's> {
    rest: &'a [f64],
    curve: Evaluator<'a>,
    other: Option<Evaluator<'a>>,
    mean: f64,
    xs: &'s mut [f64],
    ys: &'s mut [f64],
    sums: Sums,
}

/// The points `idx` (a chunk's) made and judged for every lane; with `SHARED`, each point's
/// spots are found on the first lane's curves once for every lane (their curves have the same
/// spots), else on each lane's own.
#[inline(always)]
fn judge_chunk<const SHARED: bool>(
    idx: &[u32],
    own: &[f64],
    other: &[f64],
    drift: bool,
    lanes: &mut [Lane<'_, '_>],
) {
    let Some(first) = lanes.first() else {
        return;
    };
    let (lead, lead_other) = (first.curve, first.other);
    for (k, &i) in idx.iter().enumerate() {
        let i = i as usize;
        let (x, o) = (own[i], other[i]);
        let w = if drift { x * x } else { 1.0 };
        let (at_x, at_o) = if SHARED {
            (lead.spot(x), lead_other.map_or(Spot::Zero, |e| e.spot(o)))
        } else {
            (Spot::Zero, Spot::Zero)
        };
        for lane in lanes.iter_mut() {
            let term = match &lane.other {
                Some(e) => e.at(if SHARED { at_o } else { e.spot(o) }) * o,
                None => 0.0,
            };
            let y = (lane.rest[i] - term) / x;
            if let (Some(px), Some(py)) = (lane.xs.get_mut(k), lane.ys.get_mut(k)) {
                *px = x;
                *py = y;
            }
            if approx::usable(x, y, w) {
                let s = &mut lane.sums;
                s.0 += 1;
                s.1 += w;
                let r = y - lane
                    .curve
                    .at(if SHARED { at_x } else { lane.curve.spot(x) });
                s.2 += w * r * r;
                s.3 += w * (y - lane.mean) * (y - lane.mean);
            }
        }
    }
}
