//! Applying a regression model: to a whole log, and one sample at a time for firmware.
//!
//! Both use only past samples (causal smoothing, backward differences, a delay that reads
//! back in time), so the batch correction is what a gyro's processor would have computed in
//! real time; a test holds the two to 1e-9 °/h.

use super::signals::{Lag, Signals, delayed_index, split};
use super::{Inputs, RegressionModel};
use crate::error::Result;
use crate::log::Log;
use crate::models::vakhrameev::correct::{Corrected, Correction};
use crate::models::vakhrameev::{Regime, SourceInfo};
use crate::signal::Rates;
use crate::signal::timing::GAP_FACTOR;

impl RegressionModel {
    /// Corrects a whole log.
    ///
    /// # Errors
    /// The log lacks a channel the model reads.
    pub fn correct(&self, log: &Log) -> Result<Correction> {
        let s = Signals::of(
            log,
            &self.spec,
            self.temp2.as_deref(),
            self.lag_s.map(|l| (l, self.lag_per_c)),
        )?;
        let n = s.len();
        let mut out = Correction {
            pred_dph: Vec::with_capacity(n),
            cor_dph: Vec::with_capacity(n),
            regime: Vec::with_capacity(n),
            ready_from: s.ready_from.min(n),
            ready: s.ready.clone(),
            ..Correction::default()
        };
        let mut ch = vec![0.0; s.channels.len()];
        let mut row = Vec::new();
        for i in 0..n {
            let mut x = s.inputs(i, &self.delay, &mut ch);
            let outside = self.clamp(&mut x, &mut ch);
            let pred = self.predict(&x, &ch, &mut row);
            let regime = Regime::of(s.tdot[i], s.tddot[i]);
            if outside {
                out.outside_by_regime[regime as usize] += 1;
            }
            out.pred_dph.push(pred);
            out.cor_dph.push(s.omega[i] - pred);
            out.regime.push(regime);
        }
        out.update_outside_fraction();
        Ok(out)
    }

    /// A streaming corrector for a log sampled every `dt_s` seconds.
    ///
    /// # Errors
    /// A step that is not a positive number of seconds, or one so small that the corrector's
    /// windows or delay history would span more than [`crate::signal::MAX_HISTORY_SAMPLES`]
    /// samples.
    pub fn corrector_for(&self, dt_s: f64) -> Result<RegressionCorrector> {
        crate::signal::check_history(self.steps_for(dt_s), self.delay.max_s(), dt_s)?;
        Ok(RegressionCorrector::new(self.clone(), dt_s))
    }
}

/// A ring of the last values of one signal, read back by age.
#[derive(Debug, Clone)]
struct History {
    buf: Vec<f64>,
}

impl History {
    fn new(len: usize) -> History {
        History {
            buf: vec![0.0; len.max(1)],
        }
    }
    /// The value pushed as sample `i`, for an `i` still held.
    #[inline]
    fn get(&self, i: usize) -> f64 {
        self.buf[i % self.buf.len()]
    }
    #[inline]
    fn set(&mut self, i: usize, v: f64) {
        let n = self.buf.len();
        self.buf[i % n] = v;
    }
    /// The value at fractional sample index `f`, interpolated as the batch path does.
    #[inline]
    fn at(&self, f: f64) -> f64 {
        let (j, w) = split(f);
        if w == 0.0 {
            self.get(j)
        } else {
            let a = self.get(j);
            a + (self.get(j + 1) - a) * w
        }
    }
}

/// Real-time correction by a regression model, one sample at a time, with only past samples:
/// the piece a firmware engineer ports. Memory is fixed at construction (rings as long as the
/// derivative history and the longest delay).
#[derive(Debug, Clone)]
pub struct RegressionCorrector {
    model: RegressionModel,
    dt_s: f64,
    lag: Lag,
    rates: Rates,
    temp: History,
    tdot: History,
    tddot: History,
    temp2: History,
    channels: Vec<f64>,
    row: Vec<f64>,
    count: usize,
    t0: f64,
    /// Time of the last sample, to see a gap.
    last_time_s: f64,
    /// The sample at which the current segment started: no delayed read reaches before it.
    segment_start: usize,
}

impl RegressionCorrector {
    /// A corrector for `model` on samples `dt_s` seconds apart.
    pub fn new(model: RegressionModel, dt_s: f64) -> RegressionCorrector {
        let back = (model.delay.max_s() / dt_s).ceil() as usize + 2;
        let n_ch = model.channel_names().len();
        RegressionCorrector {
            dt_s,
            lag: Lag::new(model.lag_s.unwrap_or(0.0), model.lag_per_c, dt_s),
            rates: Rates::new(model.steps_for(dt_s), dt_s),
            temp: History::new(back),
            tdot: History::new(back),
            tddot: History::new(back),
            temp2: History::new(back),
            channels: vec![0.0; n_ch],
            row: Vec::new(),
            count: 0,
            t0: 0.0,
            last_time_s: f64::NAN,
            segment_start: 0,
            model,
        }
    }

    /// Forgets all history (after a power cycle: the self-heating clock restarts too).
    pub fn reset(&mut self) {
        *self = RegressionCorrector::new(self.model.clone(), self.dt_s);
    }

    /// The extra channels [`push`](Self::push) expects, in order.
    pub fn channel_names(&self) -> Vec<String> {
        self.model.channel_names()
    }

    /// Feeds one sample: time, raw rate, temperature, the second temperature sensor (ignored
    /// when the model has none) and the extra channels in the order of
    /// [`channel_names`](Self::channel_names).
    pub fn push(
        &mut self,
        time_s: f64,
        omega_dph: f64,
        temp_c: f64,
        temp2_c: f64,
        channels: &[f64],
    ) -> Corrected {
        let i = self.count;
        if i == 0 {
            self.t0 = time_s;
        }
        // A step of more than GAP_FACTOR samples is a dropout: T's rates and lag start afresh,
        // as the batch correction restarts each segment; the gyro stayed on, so the
        // self-heating clock runs on.
        if time_s - self.last_time_s > GAP_FACTOR * self.dt_s {
            self.rates = Rates::new(self.model.steps_for(self.dt_s), self.dt_s);
            self.lag = Lag::new(
                self.model.lag_s.unwrap_or(0.0),
                self.model.lag_per_c,
                self.dt_s,
            );
            self.segment_start = i;
        }
        self.last_time_s = time_s;
        // T as the model reads it: through the lag, when there is one.
        let temp_c = if self.model.lag_s.is_some_and(|l| l > 0.0) {
            self.lag.push(temp_c)
        } else {
            temp_c
        };
        let (tdot, tddot) = self.rates.push(temp_c);
        self.tdot.set(i, tdot);
        self.tddot.set(i, tddot);
        self.temp.set(i, temp_c);
        self.temp2.set(i, temp2_c);
        self.count += 1;

        let f =
            delayed_index(i, self.model.delay.at(temp_c), self.dt_s).max(self.segment_start as f64);
        let temp = self.temp.at(f);
        let mut x = Inputs {
            t_s: time_s - self.t0,
            temp,
            tdot: self.tdot.at(f),
            tddot: self.tddot.at(f),
            dt: if self.model.temp2.is_some() {
                temp - self.temp2.at(f)
            } else {
                0.0
            },
        };
        for (k, v) in self.channels.iter_mut().enumerate() {
            *v = channels.get(k).copied().unwrap_or(f64::NAN);
        }
        self.model.clamp(&mut x, &mut self.channels);
        let pred = self.model.predict(&x, &self.channels, &mut self.row);
        Corrected::of(time_s, omega_dph, pred, tdot, tddot)
    }
}

impl super::RegressionCalibration {
    /// A calibration of `model` fitted on `log`.
    pub fn new(gyro_id: &str, log: &Log, model: RegressionModel) -> super::RegressionCalibration {
        super::RegressionCalibration {
            gyro_id: gyro_id.to_string(),
            source: SourceInfo::of(log),
            created: crate::models::vakhrameev::now_rfc3339(),
            model,
        }
    }
}
