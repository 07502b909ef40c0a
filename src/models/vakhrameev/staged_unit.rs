//! The Ω stages of a unit's axes run together: each axis's stages up to its sets' fits
//! ([`StageMemory::begin`]), then the sets' fits of every axis over the same sets' samples and
//! designs made together ([`fit_sets`]: the T part of the moments and each sample's lookups
//! once for all of them), then each axis's calibration ([`StageMemory::finish`]).
//!
//! One axis run alone ([`StageMemory::run`]) is the same three steps for a unit of one, so an
//! axis run with others gets the calibration, statistics and points it gets alone, bit for bit
//! (each sum is made in the same order: `set_moments.rs`, `set_judged.rs`).

use super::set_moments::{SetAxis, SetTMoments};
use super::sets::fit_sets_from;
use super::staged::{Begun, FittedNow, FittedSet, StageInputs, StageMemory, Staged, regime_of};
use crate::error::Result;
use rayon::prelude::*;
use std::sync::Arc;

impl<S: Clone + PartialEq + Send + Sync> StageMemory<S> {
    /// Runs the Ω stages of a unit's axes, `memories[k]` on `inputs[k]`, each as
    /// [`StageMemory::run`] would alone: the first axis's plateau stage first, whose sets'
    /// samples and T moments the axes of the same T (`same_t[k]`, which the caller vouches
    /// for, as [`StageMemory::adopt_t_stages`] asks) then take; then the sets of every axis
    /// over the same samples and designs fitted together. The results in the axes' order.
    pub fn run_unit(
        memories: &mut [&mut StageMemory<S>],
        inputs: Vec<StageInputs<'_, S>>,
        same_t: &[bool],
    ) -> Vec<Result<Staged>> {
        let mut inputs = inputs.into_iter();
        let (Some((first, rest)), Some(i0)) = (memories.split_first_mut(), inputs.next()) else {
            return Vec::new();
        };
        let theirs = i0.signals.clone();
        let b0 = first.begin(i0);
        let first: &StageMemory<S> = first;
        let others: Vec<StageInputs<'_, S>> = inputs.collect();
        let rest_begun: Vec<Result<Begun<'_, S>>> = rest
            .par_iter_mut()
            .zip(others)
            .enumerate()
            .map(|(k, (m, i))| {
                if same_t.get(k + 1).copied().unwrap_or(false) {
                    m.adopt_t_stages(first, &theirs, &i.signals);
                }
                m.begin(i)
            })
            .collect();
        let begun: Vec<Result<Begun<'_, S>>> = std::iter::once(b0).chain(rest_begun).collect();
        let ok: Vec<&Begun<'_, S>> = begun.iter().filter_map(|b| b.as_ref().ok()).collect();
        let mut fitted = fit_sets(&ok).into_iter();
        let fitted: Vec<Option<FittedNow>> = begun
            .iter()
            .map(|b| b.as_ref().ok().and_then(|_| fitted.next()))
            .collect();
        memories
            .par_iter_mut()
            .zip(begun)
            .zip(fitted)
            .map(|((m, b), f)| m.finish(b?, f.unwrap_or_default()))
            .collect()
    }
}

/// One axis's set fitted in a group: (axis, set, its fit, the T part of its moments).
type GroupFit = (usize, usize, FittedSet, Option<Arc<SetTMoments>>);

/// The sets each axis of `begun` must fit again, fitted: the axes over the same sets' samples
/// (one allocation: the axes of one T), with the same K1 and K2 specs, weighting and T
/// moments kept, together ([`fit_sets_from`]); each group and set side by side. In the axes'
/// order, each set with the T part of its moments.
pub(super) fn fit_sets<S: Sync>(begun: &[&Begun<'_, S>]) -> Vec<FittedNow> {
    // (set, the axes fitted together), the groups in order of their first axis.
    let mut groups: Vec<(usize, Vec<usize>)> = Vec::new();
    for s in 0..2 {
        for (k, b) in begun.iter().enumerate() {
            if b.rest.is_none() || !b.todo.contains(&s) {
                continue;
            }
            let together = |j: usize| {
                let a = begun[j];
                let spec = |b: &Begun<'_, S>| {
                    let r: &crate::models::recipe::Recipe = &b.even;
                    let (s1, s2, _) = super::sets::set_specs(regime_of(s), r);
                    (s1.clone(), s2.clone(), r.weighting)
                };
                Arc::ptr_eq(&a.sets, &b.sets)
                    && spec(a) == spec(b)
                    && match (&a.known[s], &b.known[s]) {
                        (Some(x), Some(y)) => Arc::ptr_eq(x, y),
                        (None, None) => true,
                        _ => false,
                    }
            };
            match groups
                .iter_mut()
                .find(|(gs, axes)| *gs == s && together(axes[0]))
            {
                Some((_, axes)) => axes.push(k),
                None => groups.push((s, vec![k])),
            }
        }
    }
    let done: Vec<Vec<GroupFit>> = groups
        .par_iter()
        .map(|(s, axes)| {
            let s = *s;
            let lead = begun[axes[0]];
            let set_axes: Vec<SetAxis<'_>> = axes
                .iter()
                .filter_map(|&k| {
                    let b = begun[k];
                    Some(SetAxis {
                        rest: b.rest.as_deref()?,
                        recipe: &b.even,
                        points: b.points || b.hand[s],
                    })
                })
                .collect();
            let deriv = &lead.prepared.deriv;
            let fits = fit_sets_from(
                &lead.sets.samples[s],
                &deriv.tdot,
                &deriv.tddot,
                &set_axes,
                regime_of(s),
                lead.known[s].as_ref(),
            );
            axes.iter()
                .zip(fits)
                .map(|(&k, f)| {
                    let fit = FittedSet {
                        k1: f.k1,
                        k2: f.k2,
                        p1: Arc::new(f.k1_points),
                        p2: Arc::new(f.k2_points),
                        warnings: f.warnings,
                        refinements_run: f.refinements_run,
                    };
                    (k, s, fit, f.t_moments)
                })
                .collect()
        })
        .collect();
    let mut out: Vec<FittedNow> = begun.iter().map(|_| Default::default()).collect();
    for (k, s, fit, t) in done.into_iter().flatten() {
        out[k][s] = Some((fit, t));
    }
    out
}
