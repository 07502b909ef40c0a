//! Applying a calibration: `Ω_cor = Ω_raw − Ω_pred` (docs/method.md §1), for a whole
//! log at once or one sample at a time.
//!
//! Both paths use only past samples for Ṫ and T̈ (causal smoothing, backward differences), so a
//! correction computed here is the correction a gyro's processor would have made in real time.
//! [`StreamCorrector`] is the piece a firmware engineer ports; it keeps a few short ring buffers
//! and does a fixed amount of work per sample.

use crate::error::Result;
use crate::log::Log;
use crate::models::vakhrameev::{Calibration, Predictor, Regime, Spots};
use crate::signal::timing::GAP_FACTOR;
use crate::signal::{self, DerivativeSteps, Derivatives, Rates};
use rayon::prelude::*;

/// A corrected log.
#[derive(Debug, Clone, Default)]
pub struct Correction {
    /// Predicted thermal drift, °/h.
    pub pred_dph: Vec<f64>,
    /// Corrected rate, °/h.
    pub cor_dph: Vec<f64>,
    /// Regime of each sample.
    pub regime: Vec<Regime>,
    /// Share of samples whose T, Ṫ or T̈ lay outside the calibrated ranges (edge values held).
    pub outside_fraction: f64,
    /// Samples outside the calibrated ranges, by regime (static, +, −), so that a partial
    /// re-correction of one regime can keep the others' counts.
    pub outside_by_regime: [usize; 3],
    /// First sample with full derivative history (figures of merit start there).
    pub ready_from: usize,
    /// The samples with full derivative history, one range per segment of the log: the
    /// figures of merit read these.
    pub ready: Vec<std::ops::Range<usize>>,
}

/// A log's predicted drift alone ([`Calibration::predict_log`]).
#[derive(Debug, Clone, Default)]
pub struct Prediction {
    /// Predicted thermal drift, °/h.
    pub pred_dph: Vec<f64>,
    /// Share of samples whose T, Ṫ or T̈ lay outside the calibrated ranges (edge values held).
    pub outside_fraction: f64,
}

/// A log's predicted drift produced in order, one batch at a time
/// ([`Calibration::log_predictor`]): the rates are one causal pass, so each batch continues
/// where the one before stopped.
#[derive(Debug, Clone)]
pub struct LogPredictor<'a> {
    predictor: Predictor<'a>,
    rates: Rates,
    temps: &'a [f64],
    next: usize,
    outside: usize,
    /// The log's segments (the rates start afresh at each), and the next one to start.
    segments: Vec<std::ops::Range<usize>>,
    segment: usize,
    steps: DerivativeSteps,
    dt_s: f64,
}

impl LogPredictor<'_> {
    /// Samples in the log.
    pub fn len(&self) -> usize {
        self.temps.len()
    }

    /// Whether the log has no samples.
    pub fn is_empty(&self) -> bool {
        self.temps.is_empty()
    }

    /// Predicts the next `out.len()` samples (fewer at the end of the log; the rest of `out`
    /// is left as it was) and returns how many it predicted.
    pub fn fill(&mut self, out: &mut [f64]) -> usize {
        let end = (self.next + out.len()).min(self.temps.len());
        let n = end - self.next;
        let mut at = self.next;
        while at < end {
            // A segment starting here restarts the rates, as a corrector does after a gap.
            if let Some(r) = self.segments.get(self.segment)
                && r.start == at
            {
                if self.segment > 0 {
                    self.rates = Rates::new(self.steps.within(r.len()), self.dt_s);
                }
                self.segment += 1;
            }
            let stop = self
                .segments
                .get(self.segment)
                .map_or(end, |r| r.start.min(end));
            let o = &mut out[at - self.next..stop - self.next];
            for (o, &t) in o.iter_mut().zip(&self.temps[at..stop]) {
                let (td, tdd) = self.rates.push(t);
                let (p, _, outside) = self.predictor.sample(t, td, tdd);
                self.outside += usize::from(outside);
                *o = p;
            }
            at = stop;
        }
        self.next = end;
        n
    }

    /// Share of the samples predicted so far whose T, Ṫ or T̈ lay outside the calibrated
    /// ranges (edge values held).
    pub fn outside_fraction(&self) -> f64 {
        if self.next > 0 {
            self.outside as f64 / self.next as f64
        } else {
            0.0
        }
    }
}

/// A log's corrected rate alone ([`Calibration::corrected_rate_with`]).
#[derive(Debug, Clone, Default)]
pub struct CorrectedRate {
    /// Corrected rate, °/h.
    pub cor_dph: Vec<f64>,
    /// Share of samples whose T, Ṫ or T̈ lay outside the calibrated ranges (edge values held).
    pub outside_fraction: f64,
    /// First sample with full derivative history (figures of merit start there).
    pub ready_from: usize,
    /// The samples with full derivative history, one range per segment of the log.
    pub ready: Vec<std::ops::Range<usize>>,
}

impl Correction {
    /// Its columns made `n` samples long, kept as they are when they already are (a
    /// correction made into them writes every sample).
    fn sized(&mut self, n: usize) {
        for v in [&mut self.pred_dph, &mut self.cor_dph] {
            if v.len() != n {
                v.clear();
                v.resize(n, 0.0);
            }
        }
        if self.regime.len() != n {
            self.regime.clear();
            self.regime.resize(n, Regime::Static);
        }
    }

    /// Recomputes `outside_fraction` from the per-regime counts.
    pub fn update_outside_fraction(&mut self) {
        let n = self.pred_dph.len();
        let total: usize = self.outside_by_regime.iter().sum();
        self.outside_fraction = if n > 0 { total as f64 / n as f64 } else { 0.0 };
    }
}

impl Calibration {
    /// Derivative settings for a log sampled every `dt_s` seconds.
    pub fn steps_for(&self, dt_s: f64) -> DerivativeSteps {
        self.resolved.steps_for(dt_s)
    }

    /// The smoothed temperature and its rates on `log`, as this calibration computes them.
    pub fn derivatives(&self, log: &Log) -> Derivatives {
        let timing = log.timing();
        let dt = timing.nominal_dt_s;
        signal::derivatives_in(&log.temp_c, self.steps_for(dt), dt, &timing.segments)
    }

    /// Corrects a whole log.
    pub fn correct(&self, log: &Log) -> Correction {
        self.correct_with(log, &self.derivatives(log))
    }

    /// Corrects a log whose derivatives are already known (the workbench keeps them while only
    /// approximations change). Runs in parallel over chunks of the log.
    pub fn correct_with(&self, log: &Log, deriv: &Derivatives) -> Correction {
        let n = log.len().min(deriv.tdot.len()).min(deriv.tddot.len());
        // Zeroed allocations are cheap (the pages are mapped on first write), and with the
        // lengths right `correct_into` writes every sample once.
        let mut c = Correction {
            pred_dph: vec![0.0; n],
            cor_dph: vec![0.0; n],
            regime: vec![Regime::Static; n],
            ..Correction::default()
        };
        self.correct_into(log, deriv, &mut c);
        c
    }

    /// The corrected rate of every sample alone, as [`Calibration::correct_with`] computes it
    /// (the same bits; a test holds them equal): what `driftlab calibrate` judges its own log
    /// by. The predicted drift and regimes a whole [`Correction`] also holds would be 90 MB on
    /// a 10⁷-sample log, allocated and written for nothing.
    pub fn corrected_rate_with(&self, log: &Log, deriv: &Derivatives) -> CorrectedRate {
        let n = log.len().min(deriv.tdot.len()).min(deriv.tddot.len());
        const CHUNK: usize = 1 << 15;
        let mut cor_dph = vec![0.0; n];
        let predictor = self.predictor();
        let outside: usize = cor_dph
            .par_chunks_mut(CHUNK)
            .enumerate()
            .map(|(c, q)| {
                let base = c * CHUNK;
                let mut outside = 0;
                for (k, q) in q.iter_mut().enumerate() {
                    let i = base + k;
                    let (t, td, tdd) = (log.temp_c[i], deriv.tdot[i], deriv.tddot[i]);
                    let (p, _, beyond) = predictor.sample(t, td, tdd);
                    *q = log.omega_dph[i] - p;
                    outside += usize::from(beyond);
                }
                outside
            })
            .sum();
        CorrectedRate {
            cor_dph,
            outside_fraction: if n > 0 {
                outside as f64 / n as f64
            } else {
                0.0
            },
            ready_from: deriv.ready_from,
            ready: deriv.ready.clone(),
        }
    }

    /// Corrects a log into `out`, reusing its buffers (the workbench's live loop corrects a
    /// long log on every edit; new buffers would cost more than the correction). The result
    /// equals [`Calibration::correct_with`]'s sample for sample.
    pub fn correct_into(&self, log: &Log, deriv: &Derivatives, out: &mut Correction) {
        let n = log.len().min(deriv.tdot.len()).min(deriv.tddot.len());
        out.sized(n);
        const CHUNK: usize = 1 << 15;
        let omega = &log.omega_dph[..n];
        let predictor = self.predictor();
        out.outside_by_regime = out
            .pred_dph
            .par_chunks_mut(CHUNK)
            .zip(out.cor_dph.par_chunks_mut(CHUNK))
            .zip(out.regime.par_chunks_mut(CHUNK))
            .enumerate()
            .map(|(c, ((p, q), r))| {
                let base = c * CHUNK;
                let mut outside = [0usize; 3];
                for k in 0..p.len() {
                    let i = base + k;
                    let (t, td, tdd) = (log.temp_c[i], deriv.tdot[i], deriv.tddot[i]);
                    let beyond;
                    (p[k], r[k], beyond) = predictor.sample(t, td, tdd);
                    q[k] = omega[i] - p[k];
                    outside[r[k] as usize] += usize::from(beyond);
                }
                outside
            })
            .reduce(|| [0; 3], |a, b| [a[0] + b[0], a[1] + b[1], a[2] + b[2]]);
        out.ready_from = deriv.ready_from;
        out.ready.clone_from(&deriv.ready);
        out.update_outside_fraction();
    }

    /// Corrects the axes of a unit in one pass: axis `a`, of rate `omegas[a]`, with `cals[a]`
    /// into `outs[a]`, the axes sharing their temperature `temp_c` and its rates `deriv`. Each
    /// sample's T and rates are read, its regime found and its spots on the curves
    /// ([`super::Spots`]) looked up once for all the axes, then each axis's values read at
    /// them: each result equals [`Calibration::correct_into`]'s on a log of that T and rate,
    /// bit for bit (a test holds them equal). Returns `false`, and corrects nothing, unless the
    /// calibrations' curves share their spots ([`super::Predictor::shares_spots`]), as those
    /// of a unit's axes refitted together on the same plateaus and sets do.
    pub fn correct_unit_into(
        cals: &[&Calibration],
        temp_c: &[f64],
        omegas: &[&[f64]],
        deriv: &Derivatives,
        outs: &mut [&mut Correction],
    ) -> bool {
        let predictors: Vec<Predictor<'_>> = cals.iter().map(|c| c.predictor()).collect();
        let n = temp_c.len().min(deriv.tdot.len()).min(deriv.tddot.len());
        let shared = !cals.is_empty()
            && cals.len() == omegas.len()
            && cals.len() == outs.len()
            && omegas.iter().all(|o| o.len() >= n)
            && predictors.iter().all(|p| p.shares_spots(&predictors[0]));
        if !shared {
            return false;
        }
        const CHUNK: usize = 1 << 15;
        for out in outs.iter_mut() {
            out.sized(n);
        }
        // Each chunk of the log with every axis's slices of it.
        type Slices<'s> = (&'s mut [f64], &'s mut [f64], &'s mut [Regime]);
        let mut chunks: Vec<Vec<Slices<'_>>> = (0..n.div_ceil(CHUNK)).map(|_| Vec::new()).collect();
        for out in outs.iter_mut() {
            let parts = out
                .pred_dph
                .chunks_mut(CHUNK)
                .zip(out.cor_dph.chunks_mut(CHUNK))
                .zip(out.regime.chunks_mut(CHUNK));
            for (c, ((p, q), r)) in parts.enumerate() {
                chunks[c].push((p, q, r));
            }
        }
        let temp = &temp_c[..n];
        let (tdot, tddot) = (&deriv.tdot[..n], &deriv.tddot[..n]);
        // Each chunk a block at a time: the block's spots found once, then each axis's values
        // read at them in a loop of its own (the axis's curves held through the loop). A
        // sample's regime and whether it lies outside are the same for every axis whose curves
        // share their spots, so they are counted once.
        let counts: Vec<[usize; 3]> = chunks
            .into_par_iter()
            .enumerate()
            .map(|(c, mut axes)| {
                const BLOCK: usize = 512;
                let base = c * CHUNK;
                let mut outside = [0usize; 3];
                let len = axes.first().map_or(0, |a| a.0.len());
                let mut spots: Vec<Spots> = Vec::with_capacity(BLOCK);
                for from in (0..len).step_by(BLOCK) {
                    let to = (from + BLOCK).min(len);
                    let (i0, i1) = (base + from, base + to);
                    spots.clear();
                    for ((&t, &td), &tdd) in
                        temp[i0..i1].iter().zip(&tdot[i0..i1]).zip(&tddot[i0..i1])
                    {
                        let s = predictors[0].spots(t, td, tdd);
                        let beyond = predictors[0].is_outside(t, td, tdd, s.regime);
                        outside[s.regime as usize] += usize::from(beyond);
                        spots.push(s);
                    }
                    for ((p, q, rg), (predictor, omega)) in
                        axes.iter_mut().zip(predictors.iter().zip(omegas))
                    {
                        let omega = &omega[i0..i1];
                        let p = &mut p[from..to];
                        let q = &mut q[from..to];
                        let rg = &mut rg[from..to];
                        for (k, s) in spots.iter().enumerate() {
                            let pred = predictor.predict_at(s);
                            p[k] = pred;
                            q[k] = omega[k] - pred;
                            rg[k] = s.regime;
                        }
                    }
                }
                outside
            })
            .collect();
        let outside = counts
            .iter()
            .fold([0; 3], |s, c| [s[0] + c[0], s[1] + c[1], s[2] + c[2]]);
        for out in outs.iter_mut() {
            out.outside_by_regime = outside;
            out.ready_from = deriv.ready_from;
            out.ready.clone_from(&deriv.ready);
            out.update_outside_fraction();
        }
        true
    }

    /// The predicted drift of every sample, and the share outside the calibrated ranges: what
    /// `driftlab apply` writes (the corrected rate is `Ω − pred`), without the columns a whole
    /// [`Correction`] holds. On a 10⁷-sample log the rates, regimes and corrected rate it skips
    /// are 330 MB. The same bits as [`Calibration::correct`]'s `pred_dph` (a test holds them
    /// equal): one pass of the same [`Rates`] and the same [`Calibration::predict`].
    pub fn predict_log(&self, log: &Log) -> Prediction {
        let mut p = self.log_predictor(log);
        let mut pred_dph = vec![0.0; p.len()];
        p.fill(&mut pred_dph);
        Prediction {
            pred_dph,
            outside_fraction: p.outside_fraction(),
        }
    }

    /// [`Calibration::predict_log`] a batch at a time, in order: a writer can format one batch
    /// while the next is predicted, and hold no column of the prediction.
    pub fn log_predictor<'a>(&'a self, log: &'a Log) -> LogPredictor<'a> {
        let n = log.len();
        let timing = log.timing();
        let dt = timing.nominal_dt_s;
        let steps = self.steps_for(dt);
        let first = timing.segments.first().map_or(n, |r| r.len());
        LogPredictor {
            predictor: self.predictor(),
            rates: Rates::new(steps.within(first), dt),
            temps: &log.temp_c[..n],
            next: 0,
            outside: 0,
            segments: timing.segments,
            segment: 0,
            steps,
            dt_s: dt,
        }
    }

    /// Whether a sample lies beyond what the calibration saw (its T outside K0's range, or its
    /// rate outside the range of the approximation its regime uses; a term left out has no
    /// range, [`Approx::judged_range`](crate::models::approx::Approx::judged_range)).
    #[inline]
    pub fn is_outside(&self, temp_c: f64, tdot: f64, tddot: f64, regime: Regime) -> bool {
        self.k0.is_beyond(temp_c)
            || match regime {
                Regime::Static => false,
                Regime::Plus => self.k1_plus.is_beyond(tdot) || self.k2_plus.is_beyond(tddot),
                Regime::Minus => self.k1_minus.is_beyond(tdot) || self.k2_minus.is_beyond(tddot),
            }
    }

    /// A streaming corrector for samples every `dt_s` seconds.
    ///
    /// # Errors
    /// A step that is not a positive number of seconds, or one so small that the corrector's
    /// windows would span more than [`signal::MAX_HISTORY_SAMPLES`] samples.
    pub fn corrector_for(&self, dt_s: f64) -> Result<StreamCorrector> {
        let steps = self.steps_for(dt_s);
        signal::check_history(steps, 0.0, dt_s)?;
        Ok(StreamCorrector::new(self.clone(), steps, dt_s))
    }

    /// A streaming corrector at the calibration log's sampling step.
    ///
    /// # Errors
    /// As [`Calibration::corrector_for`].
    pub fn corrector(&self) -> Result<StreamCorrector> {
        self.corrector_for(self.resolved.dt_s)
    }
}

/// One corrected sample.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Corrected {
    /// Time of the sample, s (as given).
    pub time_s: f64,
    /// Corrected rate, °/h.
    pub omega_cor_dph: f64,
    /// Predicted thermal drift, °/h.
    pub omega_pred_dph: f64,
    /// Ṫ used, °C/s.
    pub tdot: f64,
    /// T̈ used, °C/s².
    pub tddot: f64,
    /// Regime of the sample.
    pub regime: Regime,
}

impl Corrected {
    /// The sample at `time_s` with raw rate `omega_dph`, corrected by the drift `pred_dph`
    /// predicted from its rates `tdot` and `tddot`.
    pub fn of(time_s: f64, omega_dph: f64, pred_dph: f64, tdot: f64, tddot: f64) -> Corrected {
        Corrected {
            time_s,
            omega_cor_dph: omega_dph - pred_dph,
            omega_pred_dph: pred_dph,
            tdot,
            tddot,
            regime: Regime::of(tdot, tddot),
        }
    }
}

/// Real-time correction, one sample at a time, using only past samples.
///
/// State: the causal T filter, the last `2s+1` smoothed temperatures and the last `2s+1` values
/// of Ṫ ([`signal::Rates`]). Per sample: one filter update, two backward differences, one model
/// evaluation. Samples are assumed to arrive at the fixed step the corrector was made for; a
/// step of more than [`GAP_FACTOR`] of them is a dropout, after which the history starts
/// afresh (the batch correction restarts each segment of a log alike).
#[derive(Debug, Clone)]
pub struct StreamCorrector {
    cal: Calibration,
    steps: DerivativeSteps,
    dt_s: f64,
    rates: Rates,
    last_time_s: f64,
}

impl StreamCorrector {
    /// A corrector for `cal` with the given derivative settings and sampling step.
    pub fn new(cal: Calibration, steps: DerivativeSteps, dt_s: f64) -> StreamCorrector {
        StreamCorrector {
            cal,
            steps,
            dt_s,
            rates: Rates::new(steps, dt_s),
            last_time_s: f64::NAN,
        }
    }

    /// Forgets all history (after a power cycle or a gap in the data).
    pub fn reset(&mut self) {
        self.rates = Rates::new(self.steps, self.dt_s);
        self.last_time_s = f64::NAN;
    }

    /// Feeds one sample and returns its correction. A time more than [`GAP_FACTOR`] steps
    /// after the last sample's is a gap: the history starts afresh from this sample.
    pub fn push(&mut self, time_s: f64, omega_dph: f64, temp_c: f64) -> Corrected {
        if time_s - self.last_time_s > GAP_FACTOR * self.dt_s {
            self.rates = Rates::new(self.steps, self.dt_s);
        }
        self.last_time_s = time_s;
        let (tdot, tddot) = self.rates.push(temp_c);
        let (pred, _) = self.cal.predict(temp_c, tdot, tddot);
        Corrected::of(time_s, omega_dph, pred, tdot, tddot)
    }
}
