//! The axes of a unit refitted together: what T alone makes is made once for the unit.
//!
//! Each axis of a unit has a pipeline of its own (its Ω, its choices), but the axes share
//! their time and temperature: the plateau ranges, the sets' samples and dead-bands, the T
//! part of each set's moments and each sample's place on the curves are the same for every
//! axis whose T settings and designs are the same. [`run_unit`] makes the first axis's plateau
//! ranges, hands them to the others ([`Pipeline::share_t_stages`]), then runs the Ω stages of
//! every axis together ([`StageMemory::run_unit`]): a plateau edge released on a unit of three
//! axes makes the sets and the T moments once, not three times, and reads each set's samples
//! once for the three axes' moments and once for their statistics and points. Each axis's
//! results are those of its pipeline run alone, bit for bit (the T stages are the same values,
//! and every sum is made in the same order whether one axis or three are summed).

use super::correction::CorrectionSlot;
use super::*;

/// Two pipelines' prepared signals found to hold the same T: (ours, theirs).
pub(super) type TwinKey = (Same<Prepared>, Same<Prepared>);

impl Pipeline {
    /// Takes `other`'s plateau ranges when this pipeline's signals for `req` hold the same
    /// time, temperature and T derivatives as `other`'s last (the axes of one unit, with the
    /// same T settings), and says whether they do: then the Ω stages run with `other`'s
    /// ([`StageMemory::run_unit`]) take the sets' samples and the T part of the sets' moments
    /// its T stages made. Compared by value once per pair of signals, then by identity.
    pub fn share_t_stages(&mut self, other: &Pipeline, req: &Request) -> bool {
        let (Some((_, theirs)), Some((their_log, _))) = (&other.prepared, &other.source) else {
            return false;
        };
        let (ours, _) = self.prepared(&req.log, &req.recipe);
        let key = (Same::of(&ours), Same::of(theirs));
        if self.t_twin.as_ref() != Some(&key) {
            if !same_t(&ours, &req.log, theirs, their_log.value()) {
                return false;
            }
            self.t_twin = Some(key);
        }
        if let Some((p, choice, ranges)) = &other.ranges
            && *p == Same::of(theirs)
        {
            self.ranges = Some((Same::of(&ours), choice.clone(), ranges.clone()));
        }
        true
    }
}

/// Whether two prepared signals hold the same T: the same time stamps, temperatures, step,
/// segments and derivatives (NaN-free values compared exactly; any NaN makes them differ).
fn same_t(a: &Prepared, la: &Log, b: &Prepared, lb: &Log) -> bool {
    a.dt_s == b.dt_s
        && a.steps == b.steps
        && a.segments == b.segments
        && a.deriv.ready == b.deriv.ready
        && a.deriv.ready_from == b.deriv.ready_from
        && la.time_s == lb.time_s
        && la.temp_c == lb.temp_c
        && a.deriv.tdot == b.deriv.tdot
        && a.deriv.tddot == b.deriv.tddot
}

/// Runs the pipelines of a unit's axes, `pipes[k]` on `reqs[k]`: the first axis's signals and
/// plateau ranges, then the others' with the first's ranges ([`Pipeline::share_t_stages`]);
/// the Ω stages of every axis together ([`StageMemory::run_unit`]: the sets' samples and the T
/// part of their moments made once, each set's fits of the axes of one T in one pass); the
/// corrections the axes must make whole in one pass for the axes of the same T
/// ([`Calibration::correct_unit_into`]), then each axis judged. The outcomes in the axes'
/// order; each is what its pipeline's run alone gives, bit for bit.
pub fn run_unit(pipes: &mut [Pipeline], reqs: &[Request]) -> Vec<Result<Outcome, Error>> {
    let mut pipes: Vec<&mut Pipeline> = pipes.iter_mut().collect();
    run_unit_each(&mut pipes, reqs, |_, outcome| outcome)
}

/// [`run_unit`], with each axis's outcome handed to `each` (with the axis's place in `reqs`)
/// as soon as it is judged, side by side with the other axes' judging: the workbench draws an
/// axis while the next is judged. Returns what `each` returned, in the axes' order.
pub fn run_unit_each<T: Send>(
    pipes: &mut [&mut Pipeline],
    reqs: &[Request],
    each: impl Fn(usize, Result<Outcome, Error>) -> T + Sync,
) -> Vec<T> {
    let Some((first, rest)) = pipes.split_first_mut() else {
        return Vec::new();
    };
    let Some((req0, others)) = reqs.split_first() else {
        return Vec::new();
    };
    let first_inputs = first.fit_inputs(req0);
    let first: &Pipeline = first;
    // Each axis's inputs, and whether it holds the first axis's T (none does when the first
    // has no inputs: the Ω stages would take another's as the first).
    let first_ok = first_inputs.is_ok();
    let rest_inputs: Vec<(Result<FitInputs, Error>, bool)> = rest
        .par_iter_mut()
        .zip(others)
        .map(|(p, r)| {
            let twin = first_ok && p.share_t_stages(first, r);
            (p.fit_inputs(r), twin)
        })
        .collect();
    let inputs: Vec<(Result<FitInputs, Error>, bool)> = std::iter::once((first_inputs, true))
        .chain(rest_inputs)
        .collect();
    // The Ω stages of the axes with their inputs, together.
    let staged = {
        let mut memories = Vec::new();
        let mut stage_inputs = Vec::new();
        let mut twins = Vec::new();
        for ((p, r), (fit_inputs, twin)) in pipes.iter_mut().zip(reqs).zip(&inputs) {
            let Ok(f) = fit_inputs else {
                continue;
            };
            let Pipeline { stages, source, .. } = &mut **p;
            memories.push(stages);
            stage_inputs.push(StageInputs {
                log: &r.log,
                signals: Same::of(&f.prepared),
                prepared: &f.prepared,
                omega_filtered_dph: Cow::Borrowed(&f.prepared.omega_filtered_dph),
                ranges: &f.ranges,
                recipe: &r.recipe,
                points: true,
                source: source.as_ref().map(|(_, s)| s),
            });
            twins.push(*twin);
        }
        StageMemory::run_unit(&mut memories, stage_inputs, &twins)
    };
    let mut staged = staged.into_iter();
    let fits: Vec<(Result<Fitted, Error>, bool)> = inputs
        .into_iter()
        .map(|(fit_inputs, twin)| {
            let fitted = fit_inputs.and_then(|f| {
                let s = staged
                    .next()
                    .ok_or(Error::Internal("an axis's Ω stages are missing"))??;
                Ok(f.fitted(s))
            });
            (fitted, twin)
        })
        .collect();
    let corrections = correct_unit(pipes, reqs, &fits);
    pipes
        .par_iter_mut()
        .zip(reqs)
        .zip(fits.into_par_iter().zip(corrections))
        .enumerate()
        .map(|(k, ((p, r), ((fit, _), corrected)))| {
            let outcome = fit.map(|mut fitted| {
                let corrected = match corrected {
                    Some((c, ms)) => {
                        fitted.timings.correct_ms = ms;
                        c
                    }
                    // Every fitted axis has its correction (`correct_unit`); were one missing,
                    // the axis is corrected here, alone.
                    None => p.correct_kept(&fitted.calibration, &r.log, &fitted.prepared),
                };
                p.judge_part(r, fitted, corrected)
            });
            each(k, outcome)
        })
        .collect()
}

/// The corrections of a unit's fitted axes (with the milliseconds each took, a pass shared
/// counted whole for each axis in it); `None` for an axis whose fit failed. Kept and patched
/// corrections come from each pipeline; the whole ones of the axes that hold the first axis's
/// T are made in one pass, when their curves share their spots, else each alone.
fn correct_unit(
    pipes: &mut [&mut Pipeline],
    reqs: &[Request],
    fits: &[(Result<Fitted, Error>, bool)],
) -> Vec<Option<(Arc<Correction>, f64)>> {
    let t = Instant::now();
    let mut slots: Vec<Option<CorrectionSlot>> = pipes
        .iter_mut()
        .zip(reqs)
        .zip(fits)
        .map(|((p, r), (fit, _))| {
            let f = fit.as_ref().ok()?;
            Some(p.correction_slot(&f.calibration, &r.log, &f.prepared))
        })
        .collect();
    let slot_ms = ms(t);
    // The whole corrections of the axes of the first axis's T, made in one pass.
    let together: Vec<usize> = (0..slots.len())
        .filter(|&k| fits[k].1 && matches!(slots[k], Some(CorrectionSlot::Full(_))))
        .collect();
    let mut pass_ms = None;
    if together.len() > 1 {
        let t = Instant::now();
        let lead = together[0];
        let fitted = |k: usize| fits[k].0.as_ref().ok();
        let cals: Vec<&Calibration> = together
            .iter()
            .filter_map(|&k| fitted(k).map(|f| &f.calibration))
            .collect();
        let omegas: Vec<&[f64]> = together
            .iter()
            .map(|&k| reqs[k].log.omega_dph.as_slice())
            .collect();
        let mut bufs: Vec<&mut Correction> = slots
            .iter_mut()
            .enumerate()
            .filter(|(k, _)| together.contains(k))
            .filter_map(|(_, s)| match s {
                Some(CorrectionSlot::Full(full)) => Some(full.buffer()),
                _ => None,
            })
            .collect();
        let deriv = fitted(lead).map(|f| &f.prepared.deriv);
        if let Some(deriv) = deriv
            && cals.len() == together.len()
            && Calibration::correct_unit_into(
                &cals,
                &reqs[lead].log.temp_c,
                &omegas,
                deriv,
                &mut bufs,
            )
        {
            pass_ms = Some(ms(t));
        }
    }
    pipes
        .par_iter_mut()
        .zip(reqs)
        .zip(fits.par_iter().zip(slots))
        .enumerate()
        .map(|(k, ((p, r), ((fit, _), slot)))| {
            let f = fit.as_ref().ok()?;
            let t = Instant::now();
            let corrected = match slot? {
                CorrectionSlot::Done(c) => c,
                CorrectionSlot::Full(full) if pass_ms.is_some() && together.contains(&k) => {
                    p.keep_correction(full)
                }
                CorrectionSlot::Full(mut full) => {
                    f.calibration
                        .correct_into(&r.log, &f.prepared.deriv, full.buffer());
                    p.keep_correction(full)
                }
            };
            let shared = if together.contains(&k) { pass_ms } else { None };
            Some((corrected, slot_ms + shared.unwrap_or(0.0) + ms(t)))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::recipe::PlateauChoice;

    /// The sample unit's axes, each a log of its own as the workbench holds them.
    fn unit_views() -> Vec<Arc<Log>> {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("sample_logs/imu3-calibration.csv");
        let log = crate::log::ingest::read_path(&path, &Default::default()).expect("sample unit");
        log.axis_names()
            .iter()
            .map(|n| {
                let mut v = log.clone();
                assert!(v.select_axis(n));
                v.other_axes.clear();
                Arc::new(v)
            })
            .collect()
    }

    fn request(log: &Arc<Log>, recipe: &Recipe) -> Request {
        Request {
            log: log.clone(),
            recipe: recipe.clone(),
            merit: MeritOptions::default(),
            validation: None,
        }
    }

    /// Each axis of a unit run together is the axis run alone in a pipeline of its own, bit
    /// for bit, after the first run and after a plateau edge moved; and the T stages were
    /// taken from the first axis, not made again.
    #[test]
    fn a_unit_run_together_is_each_axis_run_alone() {
        let views = unit_views();
        assert_eq!(views.len(), 3);
        let base = Recipe::default();
        let mut pipes: Vec<Pipeline> = (0..3).map(|_| Pipeline::new()).collect();
        let reqs: Vec<Request> = views.iter().map(|v| request(v, &base)).collect();
        let first = run_unit(&mut pipes, &reqs);
        let ranges = first[0]
            .as_ref()
            .expect("the first axis fits")
            .ranges
            .clone();
        let mut moved = ranges.clone();
        moved.last_mut().expect("plateaus").start_s += 60.0;
        let edited = Recipe {
            plateaus: PlateauChoice::Manual { ranges: moved },
            ..base.clone()
        };
        let reqs2: Vec<Request> = views.iter().map(|v| request(v, &edited)).collect();
        let second = run_unit(&mut pipes, &reqs2);
        for (outs, reqs) in [(&first, &reqs), (&second, &reqs2)] {
            for (k, (out, req)) in outs.iter().zip(reqs).enumerate() {
                let out = out.as_ref().expect("fits");
                let alone = Pipeline::new().run(req).expect("fits alone");
                let strip = |c: &Calibration| Calibration {
                    created: String::new(),
                    ..c.clone()
                };
                assert_eq!(
                    strip(&out.calibration),
                    strip(&alone.calibration),
                    "axis {k}"
                );
                assert_eq!(out.k1_plus_points, alone.k1_plus_points, "axis {k}");
                assert_eq!(out.k2_minus_points, alone.k2_minus_points, "axis {k}");
                assert_eq!(
                    out.in_sample.corrected.cor_dph, alone.in_sample.corrected.cor_dph,
                    "axis {k}"
                );
                assert_eq!(out.warnings, alone.warnings, "axis {k}");
            }
        }
        // The second and third axes hold the first's sets (one allocation, not three).
        let (head, tail) = pipes.split_at_mut(1);
        assert!(tail[0].share_t_stages(&head[0], &reqs2[1]));
        let (a, b) = (head[0].stages.sets_kept(), tail[1].stages.sets_kept());
        assert!(
            a.zip(b).is_some_and(|(a, b)| Arc::ptr_eq(a, b)),
            "the third axis holds the first's sets"
        );
    }

    /// A log of another temperature is not taken for the unit's: nothing is shared.
    #[test]
    fn another_temperature_shares_nothing() {
        let views = unit_views();
        let base = Recipe::default();
        let mut a = Pipeline::new();
        a.run(&request(&views[0], &base)).expect("fits");
        let mut other = (*views[1]).clone();
        other.temp_c[100] += 0.001;
        let other = Arc::new(other);
        let mut b = Pipeline::new();
        assert!(!b.share_t_stages(&a, &request(&other, &base)));
        assert!(b.share_t_stages(&a, &request(&views[1], &base)));
    }
}
