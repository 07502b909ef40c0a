//! The figures of merit and display series of a correction, and the validation log judged.

use super::average::moving_average_within_into;
use super::*;

impl Pipeline {
    /// The figures of merit and the display series of the correction made last, kept while
    /// that correction stays; the display series reuses a buffer the UI no longer holds.
    pub(super) fn evaluate_kept(
        &mut self,
        corrected: &Correction,
        dt_s: f64,
        merit: &MeritOptions,
        filter: usize,
    ) -> (Figures, Arc<Vec<f64>>) {
        let generation = self.correction_generation;
        if let Some(e) = &self.evaluated
            && e.generation == generation
            && e.merit == *merit
            && e.filter == filter
        {
            return (e.figures, e.filtered.clone());
        }
        let mut pool: Vec<Arc<Vec<f64>>> = self
            .evaluated
            .take()
            .map(|e| e.filtered)
            .into_iter()
            .chain(self.spare_filtered.take())
            .collect();
        let mut target = match pool.iter_mut().position(|a| Arc::get_mut(a).is_some()) {
            Some(j) => pool.swap_remove(j),
            None => Arc::new(Vec::new()),
        };
        self.spare_filtered = pool.pop();
        let Some(out) = Arc::get_mut(&mut target) else {
            unreachable!("the buffer was just found unshared")
        };
        let prefix = &mut self.prefix;
        let kept = &mut self.merit_filtered;
        let (figures, ()) = rayon::join(
            || match corrected.ready.as_slice() {
                [r] if r.end >= corrected.cor_dph.len() => {
                    let x = &corrected.cor_dph;
                    crate::judge::metrics::figures_buffered(x, dt_s, r.start, merit, kept)
                }
                ready => {
                    crate::judge::metrics::figures_over(&corrected.cor_dph, dt_s, ready, merit)
                }
            },
            || {
                moving_average_within_into(
                    &corrected.cor_dph,
                    filter,
                    &corrected.ready,
                    prefix,
                    out,
                )
            },
        );
        self.evaluated = Some(EvalCache {
            generation,
            merit: *merit,
            filter,
            figures,
            filtered: target.clone(),
        });
        (figures, target)
    }

    /// Corrects and judges the validation log, keeping its derivatives and raw figures.
    pub(super) fn judge_validation(
        &mut self,
        cal: &Calibration,
        log: &Arc<Log>,
        merit: &MeritOptions,
    ) -> Judged {
        let timing = log.timing();
        let dt = timing.nominal_dt_s;
        let steps = cal.steps_for(dt);
        let filter = signal::seconds_to_samples(merit.filter_s, dt).max(1);
        let fresh = match &self.validation {
            Some(v) => v.log != Same::of(log) || v.steps != steps || v.filter != filter,
            None => true,
        };
        if fresh {
            let (deriv, raw_filtered) = rayon::join(
                || signal::derivatives_in(&log.temp_c, steps, dt, &timing.segments),
                || signal::moving_average_centered_in(&log.omega_dph, filter, &timing.segments),
            );
            self.validation = Some(ValidationCache {
                log: Same::of(log),
                steps,
                deriv: Arc::new(deriv),
                filter,
                raw_filtered: Arc::new(raw_filtered),
                raw_key: (usize::MAX, *merit),
                raw_figures: Figures::default(),
            });
        }
        let Some(v) = self.validation.as_mut() else {
            unreachable!("validation cache was just filled")
        };
        let mut corrected = self
            .validation_corrected
            .take()
            .and_then(|mut c| Arc::get_mut(&mut c).is_some().then_some(c))
            .unwrap_or_default();
        let Some(c) = Arc::get_mut(&mut corrected) else {
            unreachable!("the buffer was just found unshared")
        };
        cal.correct_into(log, &v.deriv, c);
        self.validation_corrected = Some(corrected.clone());
        if v.raw_key != (corrected.ready_from, *merit) {
            v.raw_figures =
                crate::judge::metrics::figures_over(&log.omega_dph, dt, &corrected.ready, merit);
            v.raw_key = (corrected.ready_from, *merit);
        }
        let (cor_figures, cor_filtered) = rayon::join(
            || crate::judge::metrics::figures_over(&corrected.cor_dph, dt, &corrected.ready, merit),
            || {
                let mut out = Vec::new();
                let ready = &corrected.ready;
                moving_average_within_into(
                    &corrected.cor_dph,
                    filter,
                    ready,
                    &mut Vec::new(),
                    &mut out,
                );
                out
            },
        );
        let evaluation = evaluation(v.raw_figures, cor_figures, &corrected, cal);
        Judged {
            log: log.clone(),
            per_run: Comparison::of_runs(log, &corrected.cor_dph, &corrected.ready, merit),
            corrected,
            evaluation,
            raw_filtered_dph: v.raw_filtered.clone(),
            cor_filtered_dph: Arc::new(cor_filtered),
        }
    }
}

/// Raw against corrected figures, with the ratios as [`Comparison::of`] makes them, of the
/// calibration `cal` (whose terms left out are named beside the share outside its ranges).
pub(super) fn evaluation(
    raw: Figures,
    corrected: Figures,
    c: &Correction,
    cal: &Calibration,
) -> Evaluation {
    Evaluation {
        comparison: Comparison::from_figures(raw, corrected),
        outside_fraction: c.outside_fraction,
        warmup_samples: c.ready_from,
        left_out: cal.left_out(),
    }
}
