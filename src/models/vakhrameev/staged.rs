//! The Ω stages of the one Vakhrameev pipeline, after the T stages: plateau statistics, K0
//! (fitted at its hand-placed knots, with its hand-set values), the dead-bands and the sets'
//! samples, `Ω_f − K0(T)`, then K1 and K2 of the + and − sets side by side (their knots placed
//! and set by hand applied after each set's passes), and the calibration.
//!
//! Each stage's result can be kept in a [`StageMemory`] under the key of what it was made from,
//! and is reused while that stays. A batch fit ([`super::Pipeline`]) runs the stages with a
//! memory that keeps nothing Ω made ([`StageMemory::batch`]): each axis of a unit brings its
//! own Ω, and only the sets' samples, which depend on T alone, are shared between the axes. The
//! workbench holds a memory that keeps everything ([`StageMemory::kept`]) between edits, so an
//! edit of K1+ refits only the + set. Both call [`StageMemory::run`]: a refit is the batch fit
//! with a warm memory, and there is no second pipeline to drift from this one.

use super::knots::{Coefficient, check_hand_kept, with_knots};
use super::set_moments::SetTMoments;
use super::sets::{
    fit_k1_gathered, fit_k2_gathered, into_rest, k2_points_of, rest_into, stats_on_points,
};
use super::staged_unit::fit_sets;
use super::stages::fit_k0;
use super::{
    Calibration, PointSet, Prepared, Regime, SetInputs, SetSamples, SetsOfSamples, SourceInfo,
};
use crate::error::{Error, Result};
use crate::log::Log;
use crate::models::approx::{Approx, ApproxSpec};
use crate::models::recipe::{Recipe, Weighting};
use crate::signal::plateau::{self, PlateauRange, PlateauStats};
use std::borrow::Cow;
use std::sync::Arc;
use std::time::Instant;

/// What the sets' samples were made from: the T signals (named by the caller's `S`), the
/// plateau ranges and the dead-band settings.
#[derive(Debug, Clone, PartialEq)]
struct PlateauKey<S> {
    signals: S,
    ranges: Vec<PlateauRange>,
    deadband_tdot: Option<f64>,
    deadband_tddot: Option<f64>,
}

/// What the plateau statistics were made from: the signals (Ω among them) and the ranges.
type StatsKey<S> = (S, Vec<PlateauRange>);

/// What one set's fit depends on.
#[derive(Debug, Clone, PartialEq)]
struct SetKey<S> {
    plateaus: PlateauKey<S>,
    k0: Approx,
    spec1: ApproxSpec,
    spec2: ApproxSpec,
    weighting: Weighting,
    refinements: usize,
}

/// What the T part of one set's moments depends on: the sets' samples and the designs the
/// set's passes are fitted with (knots equally spaced: hand-placed knots are put in after).
#[derive(Debug, Clone, PartialEq)]
struct TMomentsKey<S> {
    plateaus: PlateauKey<S>,
    spec1: ApproxSpec,
    spec2: ApproxSpec,
    weighting: Weighting,
}

/// K1 and K2 of one set, with the points of its last pass (shared with the display).
#[derive(Debug, Clone)]
pub(super) struct FittedSet {
    pub(super) k1: Approx,
    pub(super) k2: Approx,
    pub(super) p1: Arc<PointSet>,
    pub(super) p2: Arc<PointSet>,
    pub(super) warnings: Vec<String>,
    /// The refinement passes run, when they stopped before the recipe's.
    pub(super) refinements_run: Option<usize>,
}

/// What the Ω stages keep between runs, each result under the key of what made it. `S` names
/// the T signals the stages were made from, as the caller tells them apart: `()` for a batch
/// pipeline, which has one set of T signals, an identity of the kept signals for the
/// workbench.
#[derive(Debug, Clone)]
pub struct StageMemory<S> {
    /// Whether the stages that read Ω (plateau statistics, `Ω_f − K0(T)`, the sets' fits) are
    /// kept: not in a batch fit, whose axes share `S` but not Ω.
    keep_omega: bool,
    sets: Option<(PlateauKey<S>, Arc<SetsOfSamples>)>,
    stats: Option<(StatsKey<S>, Vec<PlateauStats>)>,
    rest: Option<(S, Approx, Arc<Vec<f64>>)>,
    fits: [Option<(SetKey<S>, FittedSet)>; 2],
    /// The T part of each set's moments (T's alone, so kept in a batch fit too: the axes of a
    /// unit with the same designs gather only their Ω part).
    t_moments: [Option<(TMomentsKey<S>, Arc<SetTMoments>)>; 2],
}

/// One axis's Ω stages up to its sets' fits ([`StageMemory::begin`]): what the sets' fits
/// read ([`super::staged_unit::fit_sets`], the axes of a unit together) and what the
/// calibration is assembled from after ([`StageMemory::finish`]).
pub(super) struct Begun<'a, S> {
    log: &'a Log,
    pub(super) prepared: &'a Prepared,
    recipe: &'a Recipe,
    /// Whether the points are gathered for display.
    pub(super) points: bool,
    source: Option<&'a SourceInfo>,
    stats: Vec<PlateauStats>,
    /// The sets' samples (shared between the axes of one T).
    pub(super) sets: Arc<SetsOfSamples>,
    k0: Approx,
    warnings: Vec<String>,
    /// Whether each set has knots placed or set by hand (its points are then gathered).
    pub(super) hand: [bool; 2],
    /// The recipe the sets are fitted with: the knots placed and set by hand left out.
    pub(super) even: Cow<'a, Recipe>,
    t_keys: [TMomentsKey<S>; 2],
    keys: [SetKey<S>; 2],
    /// The sets to fit again (0: +, 1: −).
    pub(super) todo: Vec<usize>,
    /// `Ω_f − K0(T)`, when a set is fitted or has knots set by hand.
    pub(super) rest: Option<Arc<Vec<f64>>>,
    /// The T part of each set's moments, kept for these sets and designs.
    pub(super) known: [Option<Arc<SetTMoments>>; 2],
    plateaus_ms: f64,
    /// When the sets' fits began.
    t: Instant,
}

/// Each set (+, −) fitted now, with the T part of its moments when made from them.
pub(super) type FittedNow = [Option<(FittedSet, Option<Arc<SetTMoments>>)>; 2];

/// What one run of the Ω stages reads.
pub struct StageInputs<'a, S> {
    /// Time, T and the axis's raw Ω (`omega_dph`).
    pub log: &'a Log,
    /// The identity of the T signals in `prepared` (see [`StageMemory`]).
    pub signals: S,
    /// T's derivatives, segments and the filter length the calibration records.
    pub prepared: &'a Prepared,
    /// The axis's Ω filtered as the recipe says: owned, it becomes `Ω_f − K0(T)` in place
    /// when nothing is kept.
    pub omega_filtered_dph: Cow<'a, [f64]>,
    /// The plateau ranges K0's points are taken over.
    pub ranges: &'a [PlateauRange],
    /// Every choice, the knots placed and set by hand among them.
    pub recipe: &'a Recipe,
    /// Whether the pointwise K1± and K2± points are gathered (for display).
    pub points: bool,
    /// The log as the calibration records it, when the caller keeps it: its sketch reads every
    /// sample (17 ms of a 1M-sample log), which a refit after a knot drag cannot afford
    /// each time. `None`: made from `log`.
    pub source: Option<&'a SourceInfo>,
}

/// What one run of the Ω stages made.
#[derive(Debug, Clone)]
pub struct Staged {
    /// The calibration, hand-set knots applied.
    pub calibration: Calibration,
    /// What the fits had to work around.
    pub warnings: Vec<String>,
    /// The pointwise K1+, K1−, K2+, K2− of the last pass (empty unless asked for).
    pub points: [Arc<PointSet>; 4],
    /// Milliseconds spent on the plateau statistics and the sets' samples (0 when kept).
    pub plateaus_ms: f64,
    /// Milliseconds spent on K1 and K2 (0 when every set was kept and no knot was set).
    pub fit_ms: f64,
}

impl<S> StageMemory<S> {
    /// A memory for a batch fit: only the sets' samples (T's alone) are kept, so the axes of a
    /// unit share them while their dead-band settings agree.
    pub fn batch() -> StageMemory<S> {
        StageMemory {
            keep_omega: false,
            ..StageMemory::kept()
        }
    }

    /// A memory that keeps every stage, for a refit after each edit.
    pub fn kept() -> StageMemory<S> {
        StageMemory {
            keep_omega: true,
            sets: None,
            stats: None,
            rest: None,
            fits: [None, None],
            t_moments: [None, None],
        }
    }
}

impl<S: Clone + PartialEq> StageMemory<S> {
    /// The sets' samples kept, if any (for tests of what is shared).
    #[cfg(test)]
    pub(crate) fn sets_kept(&self) -> Option<&Arc<SetsOfSamples>> {
        self.sets.as_ref().map(|(_, s)| s)
    }

    /// Takes the stages `from` made from T alone (the sets' samples, the T part of the sets'
    /// moments), made from its signals `theirs`, as made from this memory's signals `ours`.
    /// For the axes of a unit, whose T signals are the same values held apart: the caller
    /// vouches that `ours` and `theirs` are equal, and the next run then gathers only its Ω
    /// part. What `from` made from other signals is left.
    pub fn adopt_t_stages(&mut self, from: &StageMemory<S>, theirs: &S, ours: &S) {
        let ours_of = |k: &PlateauKey<S>| PlateauKey {
            signals: ours.clone(),
            ..k.clone()
        };
        if let Some((k, sets)) = &from.sets
            && k.signals == *theirs
        {
            self.sets = Some((ours_of(k), sets.clone()));
        }
        for (mine, (k, t)) in self
            .t_moments
            .iter_mut()
            .zip(
                from.t_moments
                    .iter()
                    .map(|e| e.as_ref().filter(|(k, _)| k.plateaus.signals == *theirs)),
            )
            .filter_map(|(m, e)| e.map(|e| (m, e)))
        {
            *mine = Some((
                TMomentsKey {
                    plateaus: ours_of(&k.plateaus),
                    ..k.clone()
                },
                t.clone(),
            ));
        }
    }
}

impl<S> Default for StageMemory<S> {
    /// [`StageMemory::kept`].
    fn default() -> Self {
        StageMemory::kept()
    }
}

impl<S: Clone + PartialEq + Send + Sync> StageMemory<S> {
    /// Runs every Ω stage whose inputs changed since what this memory keeps.
    ///
    /// # Errors
    /// What K0's fit refuses (no plateaus).
    pub fn run(&mut self, i: StageInputs<'_, S>) -> Result<Staged> {
        let begun = self.begin(i)?;
        let fitted = fit_sets(&[&begun]).pop().unwrap_or_default();
        self.finish(begun, fitted)
    }

    /// The Ω stages of one axis up to its sets' fits: the plateau statistics, the sets'
    /// samples, K0, which sets must be fitted again and `Ω_f − K0(T)` for them.
    ///
    /// # Errors
    /// What K0's fit refuses (no plateaus).
    pub(super) fn begin<'a>(&mut self, i: StageInputs<'a, S>) -> Result<Begun<'a, S>> {
        let StageInputs {
            log,
            signals,
            prepared,
            omega_filtered_dph,
            ranges,
            recipe,
            points,
            source,
        } = i;
        let keep = self.keep_omega;
        if prepared.deriv.ready.iter().all(|r| r.is_empty()) {
            return Err(no_rate_history(log, prepared));
        }

        let t = Instant::now();
        let mut plateaus_ms = 0.0;
        let stats_key = (signals.clone(), ranges.to_vec());
        let stats = match &self.stats {
            Some((k, stats)) if keep && *k == stats_key => stats.clone(),
            _ => {
                let stats = plateau::stats_of(&log.time_s, &log.temp_c, &log.omega_dph, ranges);
                if keep {
                    self.stats = Some((stats_key, stats.clone()));
                }
                plateaus_ms = ms(t);
                stats
            }
        };
        let pkey = PlateauKey {
            signals: signals.clone(),
            ranges: ranges.to_vec(),
            deadband_tdot: recipe.deadband_tdot,
            deadband_tddot: recipe.deadband_tddot,
        };
        let sets = match &self.sets {
            Some((k, sets)) if *k == pkey => sets.clone(),
            _ => {
                let sets = Arc::new(super::sets_of_samples(
                    &log.time_s,
                    prepared,
                    ranges,
                    recipe,
                ));
                self.sets = Some((pkey.clone(), sets.clone()));
                plateaus_ms = ms(t);
                sets
            }
        };

        let mut warnings = Vec::new();
        let k0 = k0_of(&stats, recipe, &mut warnings)?;

        let t = Instant::now();
        // The sets are fitted with their knots equally spaced and fitted; the knots placed and
        // set by hand are put in after (`apply_hand_knots`), so that a knot dragged, sideways
        // or up and down, refits no set's passes.
        let hand = [Regime::Plus, Regime::Minus].map(|regime| {
            let (c1, c2, _) = set_names(regime);
            c1.spec(recipe).hand_knots() || c2.spec(recipe).hand_knots()
        });
        let even = if hand.contains(&true) {
            Cow::Owned(Recipe {
                k1_plus: recipe.k1_plus.without_hand_knots(),
                k1_minus: recipe.k1_minus.without_hand_knots(),
                k2_plus: recipe.k2_plus.without_hand_knots(),
                k2_minus: recipe.k2_minus.without_hand_knots(),
                ..recipe.clone()
            })
        } else {
            Cow::Borrowed(recipe)
        };
        let t_keys = [Regime::Plus, Regime::Minus].map(|regime| {
            let (c1, c2, _) = set_names(regime);
            TMomentsKey {
                plateaus: pkey.clone(),
                spec1: c1.spec(&even).clone(),
                spec2: c2.spec(&even).clone(),
                weighting: recipe.weighting,
            }
        });
        let keys = [Regime::Plus, Regime::Minus].map(|regime| {
            let (c1, c2, _) = set_names(regime);
            SetKey {
                plateaus: pkey.clone(),
                k0: k0.clone(),
                spec1: c1.spec(&even).clone(),
                spec2: c2.spec(&even).clone(),
                weighting: recipe.weighting,
                refinements: recipe.refinements,
            }
        });
        let todo: Vec<usize> = (0..2)
            .filter(|&s| !keep || self.fits[s].as_ref().is_none_or(|(k, _)| *k != keys[s]))
            .collect();
        let rest = (!todo.is_empty() || hand.contains(&true))
            .then(|| self.rest(&signals, &k0, omega_filtered_dph, &log.temp_c));
        let known: [Option<Arc<SetTMoments>>; 2] = [0, 1].map(|s| {
            self.t_moments[s]
                .as_ref()
                .filter(|(k, _)| *k == t_keys[s])
                .map(|(_, t)| t.clone())
        });
        Ok(Begun {
            log,
            prepared,
            recipe,
            points,
            source,
            stats,
            sets,
            k0,
            warnings,
            hand,
            even,
            t_keys,
            keys,
            todo,
            rest,
            known,
            plateaus_ms,
            t,
        })
    }

    /// The Ω stages of one axis after its sets' fits: the sets fitted now kept, the knots
    /// placed and set by hand put in, and the calibration.
    ///
    /// # Errors
    /// A set's fit missing; what the knots placed or set by hand refuse.
    pub(super) fn finish(&mut self, b: Begun<'_, S>, fitted: FittedNow) -> Result<Staged> {
        let Begun {
            log,
            prepared,
            recipe,
            source,
            stats,
            sets,
            k0,
            mut warnings,
            hand,
            t_keys,
            keys,
            todo,
            rest,
            plateaus_ms,
            t,
            ..
        } = b;
        let mut now: [Option<FittedSet>; 2] = [None, None];
        for (s, f) in fitted.into_iter().enumerate() {
            let Some((fit, t_moments)) = f else {
                continue;
            };
            if let Some(tm) = t_moments {
                self.t_moments[s] = Some((t_keys[s].clone(), tm));
            }
            if self.keep_omega {
                self.fits[s] = Some((keys[s].clone(), fit.clone()));
            }
            now[s] = Some(fit);
        }
        let samples = &sets.samples;
        let mut set = |s: usize| -> Result<FittedSet> {
            let fit = match now[s].take() {
                Some(fit) => fit,
                None => self.fits[s]
                    .as_ref()
                    .map(|(_, fit)| fit.clone())
                    .ok_or(Error::Internal("a set's fit is missing"))?,
            };
            Ok(match &rest {
                Some(rest) if hand[s] => {
                    let inputs = SetInputs {
                        tdot: &prepared.deriv.tdot,
                        tddot: &prepared.deriv.tddot,
                        rest,
                    };
                    apply_hand_knots(&fit, &samples[s], inputs, regime_of(s), recipe)?
                }
                _ => fit,
            })
        };
        let (plus, minus) = (set(0)?, set(1)?);
        drop(rest);
        let fit_ms = if todo.is_empty() && !hand.contains(&true) {
            0.0
        } else {
            ms(t)
        };
        warnings.extend(plus.warnings);
        warnings.extend(minus.warnings);
        let mut calibration = Calibration::assemble(
            source.cloned().unwrap_or_else(|| SourceInfo::of(log)),
            prepared,
            recipe,
            sets.deadbands,
            stats,
            [k0, plus.k1, minus.k1, plus.k2, minus.k2],
        );
        if plus.refinements_run.is_some() || minus.refinements_run.is_some() {
            let run = |r: Option<usize>| r.unwrap_or(recipe.refinements);
            calibration.resolved.refinements_run =
                Some([run(plus.refinements_run), run(minus.refinements_run)]);
        }
        Ok(Staged {
            calibration,
            warnings,
            points: [plus.p1, minus.p1, plus.p2, minus.p2],
            plateaus_ms,
            fit_ms,
        })
    }

    /// `Ω_f − K0(T)`: the kept one while the signals and K0 stay, or made afresh (in place of
    /// an owned filtered Ω).
    fn rest(
        &mut self,
        signals: &S,
        k0: &Approx,
        omega_filtered_dph: Cow<'_, [f64]>,
        temp_c: &[f64],
    ) -> Arc<Vec<f64>> {
        if let Some((s, k, rest)) = &self.rest
            && self.keep_omega
            && s == signals
            && k == k0
        {
            return rest.clone();
        }
        // The last column's buffer when nothing else holds it: written over in one pass,
        // without a fresh allocation's zeroed pages (8 MB at a million samples).
        let reused = self
            .rest
            .take()
            .and_then(|(_, _, mut r)| Arc::get_mut(&mut r).is_some().then_some(r))
            .filter(|r| r.len() == omega_filtered_dph.len() && r.len() == temp_c.len());
        let rest = match reused {
            Some(mut r) => {
                if let Some(buf) = Arc::get_mut(&mut r) {
                    rest_into(buf, &omega_filtered_dph, temp_c, k0);
                }
                r
            }
            None => {
                let mut rest = omega_filtered_dph.into_owned();
                into_rest(&mut rest, temp_c, k0);
                Arc::new(rest)
            }
        };
        if self.keep_omega {
            self.rest = Some((signals.clone(), k0.clone(), rest.clone()));
        }
        rest
    }
}

/// K0 through the plateaus' points as the recipe asks, its knot values set by hand put in:
/// the K0 of a fit, and of the workbench's preview while a plateau edge is dragged
/// ([`crate::refit::preview_plateaus`]), which must not differ from it.
///
/// # Errors
/// No plateaus.
pub fn k0_of(
    stats: &[PlateauStats],
    recipe: &Recipe,
    warnings: &mut Vec<String>,
) -> Result<Approx> {
    let k0 = fit_k0(stats, &recipe.k0, warnings)?;
    check_hand_kept(Coefficient::K0, &recipe.k0, &k0, warnings)?;
    let values = recipe
        .k0
        .values
        .as_ref()
        .filter(|v| v.len() == k0.knots().1.len());
    if values.is_none() {
        return Ok(k0);
    }
    // Judged on the plateau points, as the fit is: the fitted curve's R² is not this one's.
    let k0 = with_knots(&k0, values);
    let t: Vec<f64> = stats.iter().map(|p| p.temp_c).collect();
    let w: Vec<f64> = stats.iter().map(|p| p.omega_dph).collect();
    let judged = crate::models::approx::stats_on(&k0, &t, &w, None);
    Ok(k0.with_stats(judged))
}

fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

/// The regime of set `s` (`0`: +, `1`: −).
pub(super) fn regime_of(s: usize) -> Regime {
    if s == 0 { Regime::Plus } else { Regime::Minus }
}

/// The coefficients of a set's K1 and K2, and the set's sign as warnings write it.
fn set_names(regime: Regime) -> (Coefficient, Coefficient, &'static str) {
    match regime {
        Regime::Minus => (Coefficient::K1Minus, Coefficient::K2Minus, "-"),
        _ => (Coefficient::K1Plus, Coefficient::K2Plus, "+"),
    }
}

/// The knots placed and set by hand applied to a set fitted with equally spaced, fitted knots
/// (its passes, refinements and all):
///
/// - a K1 whose knots are placed by hand is refitted at them on the points its last pass was
///   fitted on (the ratios with that pass's K2 taken out);
/// - a K1 whose values are set by hand takes them;
/// - a K1 changed either way is followed by a K2 fitted on what it leaves (unless K2's values
///   are set by hand), as the paper's K2 step asks; a K2 whose knots are placed by hand is
///   refitted at them on the points of the set's last pass (or on what the new K1 leaves);
/// - a K2 whose values are set by hand takes them.
///
/// So a knot dragged sideways costs one or two fits over the gathered points of one set, not
/// the set's passes again; the batch fit does the same, so the two stay equal bit for bit.
fn apply_hand_knots(
    fit: &FittedSet,
    samples: &SetSamples,
    inputs: SetInputs,
    regime: Regime,
    recipe: &Recipe,
) -> Result<FittedSet> {
    let (c1, c2, sign) = set_names(regime);
    let (spec1, spec2) = (c1.spec(recipe), c2.spec(recipe));
    let mut out = fit.clone();
    let mut k1_changed = false;
    if spec1.at.is_some() {
        let mut w = Vec::new();
        out.k1 = fit_k1_gathered(samples, &fit.p1, regime, recipe, &mut w);
        out.warnings
            .retain(|m| !m.starts_with(&format!("K1{sign}")));
        out.warnings.extend(w);
        k1_changed = true;
    }
    check_hand_kept(c1, spec1, &out.k1, &out.warnings)?;
    let values1 = spec1
        .values
        .as_ref()
        .filter(|v| v.len() == out.k1.knots().1.len());
    if values1.is_some() {
        let k1 = with_knots(&out.k1, values1);
        // Judged on the points its fit saw: the fitted curve's R² is not this curve's.
        out.k1 = k1.clone().with_stats(stats_on_points(&k1, &fit.p1, recipe));
        k1_changed = true;
    }
    if k1_changed {
        // K2's points are what the K1 now in place leaves.
        out.p2 = Arc::new(k2_points_of(samples, inputs, &out.k1));
    }
    if spec2.at.is_some() || (k1_changed && spec2.values.is_none()) {
        // The points are gathered for display anyway; the fit reads them rather than
        // evaluating K1 again in each of its passes.
        let mut w = Vec::new();
        out.k2 = fit_k2_gathered(samples, &out.p2, regime, recipe, &mut w);
        out.warnings
            .retain(|m| !m.starts_with(&format!("K2{sign}")));
        out.warnings.extend(w);
    }
    check_hand_kept(c2, spec2, &out.k2, &out.warnings)?;
    let values2 = spec2
        .values
        .as_ref()
        .filter(|v| v.len() == out.k2.knots().1.len());
    if values2.is_some() {
        let k2 = with_knots(&out.k2, values2);
        out.k2 = k2.clone().with_stats(stats_on_points(&k2, &out.p2, recipe));
    }
    Ok(out)
}

/// Why no sample has its rates of T: every segment is shorter than the history Ṫ and T̈ need.
/// Without it the fit would store K1 and K2 of no points and dead-bands of 0, numbers that
/// stand for nothing computed.
fn no_rate_history(log: &Log, prepared: &Prepared) -> Error {
    let dt = prepared.dt_s;
    let needed = prepared.steps.map_or(0, |s| s.ready_from());
    let longest = prepared
        .segments
        .iter()
        .filter(|r| !r.is_empty())
        .map(|r| log.time_s[r.end - 1] - log.time_s[r.start] + dt)
        .fold(0.0, f64::max);
    crate::models::FitError::NoRateHistory {
        log: log.source.clone(),
        needed_s: needed as f64 * dt,
        longest_s: longest,
    }
    .into()
}
