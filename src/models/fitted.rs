//! Any fitted drift model — the Vakhrameev calibration or a regression model — behind one
//! face, so that files, `apply`, `compare` and the workbench treat them alike.

use crate::error::{Invalid, Result};
use crate::log::Log;
use crate::models::FitError;
use crate::models::presets::Preset;
use crate::models::regression::{RegressionCalibration, RegressionCorrector};
use crate::models::vakhrameev::correct::{
    Corrected, Correction, LogPredictor, Prediction, StreamCorrector,
};
use crate::models::vakhrameev::{Calibration, SourceInfo};

/// A fitted model of a gyro's thermal drift.
#[derive(Debug, Clone, PartialEq)]
pub enum DriftModel {
    /// K0/K1±/K2± (docs/method.md §1).
    Vakhrameev(Box<Calibration>),
    /// A model linear in its coefficients over the log's channels.
    Regression(Box<RegressionCalibration>),
}

impl DriftModel {
    /// The rate terms left out for want of points (Vakhrameev's K1±, K2±); none for a model
    /// fitted over every sample.
    pub fn left_out(&self) -> crate::models::vakhrameev::LeftOut {
        match self {
            DriftModel::Vakhrameev(c) => c.left_out(),
            DriftModel::Regression(_) => Default::default(),
        }
    }

    /// How many samples of `log` are corrected before the rates of T the model reads have
    /// their full history: the first [`DerivativeSteps::ready_from`] samples of each segment
    /// (the rates restart after every gap), or every sample of a segment shorter than that.
    /// Their Ṫ and T̈ are no reading (a segment too short carries none), so their correction
    /// is the static part alone. 0 for a model that reads no rate.
    ///
    /// [`DerivativeSteps::ready_from`]: crate::signal::DerivativeSteps::ready_from
    pub fn warm_up_samples(&self, log: &Log) -> usize {
        let timing = log.timing();
        let steps = match self {
            DriftModel::Vakhrameev(c) => c.steps_for(timing.nominal_dt_s),
            DriftModel::Regression(r) => {
                if !r.model.spec.terms.iter().any(|t| t.is_rate()) {
                    return 0;
                }
                r.model.steps_for(timing.nominal_dt_s)
            }
        };
        let need = steps.ready_from();
        timing.segments.iter().map(|s| s.len().min(need)).sum()
    }

    /// The model's name (`vakhrameev`, a preset's name, or the custom model's).
    pub fn name(&self) -> &str {
        match self {
            DriftModel::Vakhrameev(_) => Preset::Vakhrameev.name(),
            DriftModel::Regression(r) => &r.model.spec.name,
        }
    }

    /// The tag of the model section in a calibration file.
    pub fn tag(&self) -> &'static str {
        match self {
            DriftModel::Vakhrameev(_) => "vakhrameev",
            DriftModel::Regression(_) => "regression",
        }
    }

    /// Gyro identifier.
    pub fn gyro_id(&self) -> &str {
        match self {
            DriftModel::Vakhrameev(c) => &c.gyro_id,
            DriftModel::Regression(r) => &r.gyro_id,
        }
    }

    /// The log the model was fitted on.
    pub fn source(&self) -> &SourceInfo {
        match self {
            DriftModel::Vakhrameev(c) => &c.source,
            DriftModel::Regression(r) => &r.source,
        }
    }

    /// The log the model was fitted on, to fill in its name and hash.
    pub fn source_mut(&mut self) -> &mut SourceInfo {
        match self {
            DriftModel::Vakhrameev(c) => &mut c.source,
            DriftModel::Regression(r) => &mut r.source,
        }
    }

    /// Corrects a whole log.
    ///
    /// # Errors
    /// The log lacks a channel a regression model reads.
    pub fn correct(&self, log: &Log) -> Result<Correction> {
        match self {
            DriftModel::Vakhrameev(c) => Ok(c.correct(log)),
            DriftModel::Regression(r) => r.model.correct(log),
        }
    }

    /// The predicted drift of every sample of `log` (the corrected rate is `Ω − pred`), as
    /// `driftlab apply` writes it: for the Vakhrameev model without the other columns of a
    /// correction ([`Calibration::predict_log`]).
    ///
    /// # Errors
    /// The log lacks a channel the model reads.
    pub fn predict_log(&self, log: &Log) -> Result<Prediction> {
        match self {
            DriftModel::Vakhrameev(c) => Ok(c.predict_log(log)),
            DriftModel::Regression(r) => {
                let c = r.model.correct(log)?;
                Ok(Prediction {
                    pred_dph: c.pred_dph,
                    outside_fraction: c.outside_fraction,
                })
            }
        }
    }

    /// The predicted drift of `log` a batch at a time ([`Predictor`]), as `driftlab apply`
    /// writes it: the Vakhrameev model predicts each batch as it is asked for; a regression
    /// model, whose channels may be filtered over the whole log, predicts all at once.
    ///
    /// # Errors
    /// The log lacks a channel the model reads.
    pub fn predictor<'a>(&'a self, log: &'a Log) -> Result<Predictor<'a>> {
        Ok(match self {
            DriftModel::Vakhrameev(c) => Predictor::Batches(Box::new(c.log_predictor(log))),
            DriftModel::Regression(_) => Predictor::Whole {
                prediction: self.predict_log(log)?,
                next: 0,
            },
        })
    }

    /// A streaming corrector for samples `dt_s` seconds apart.
    ///
    /// # Errors
    /// A step the corrector cannot keep histories for (see
    /// [`Calibration::corrector_for`]).
    pub fn corrector_for(&self, dt_s: f64) -> Result<ModelCorrector> {
        Ok(match self {
            DriftModel::Vakhrameev(c) => {
                ModelCorrector::Vakhrameev(Box::new(c.corrector_for(dt_s)?))
            }
            DriftModel::Regression(r) => {
                ModelCorrector::Regression(Box::new(r.model.corrector_for(dt_s)?))
            }
        })
    }

    /// The second temperature channel and the extra channels a streaming corrector wants.
    pub fn inputs(&self) -> (Option<String>, Vec<String>) {
        match self {
            DriftModel::Vakhrameev(_) => (None, Vec::new()),
            DriftModel::Regression(r) => (r.model.temp2.clone(), r.model.channel_names()),
        }
    }

    /// Checks a model read from a file.
    ///
    /// # Errors
    /// A message naming what is inconsistent.
    pub fn validate(&self) -> std::result::Result<(), Invalid> {
        let created = match self {
            DriftModel::Vakhrameev(c) => &c.created,
            DriftModel::Regression(r) => &r.created,
        };
        check_identity(self.gyro_id(), created)?;
        match self {
            DriftModel::Vakhrameev(c) => c.validate(),
            DriftModel::Regression(r) => r.validate(),
        }
    }
}

/// Checks the gyro's serial number and the date a calibration holds, which every output
/// copies and the terminal shows: printable text (the rule of
/// [`is_unprintable`](crate::text::is_unprintable)), the serial number with no space around
/// it either ([`id_fault`](crate::text::id_fault), as for a recipe's `gyro_id`) and at most
/// [`MAX_GYRO_ID_CHARS`](crate::models::recipe::MAX_GYRO_ID_CHARS) long.
///
/// # Errors
/// An [`Invalid`] naming `gyro_id` or `created`.
pub fn check_identity(gyro_id: &str, created: &str) -> std::result::Result<(), Invalid> {
    use crate::models::recipe::MAX_GYRO_ID_CHARS;
    if let Some(why) = crate::text::id_fault(gyro_id) {
        return Err(Invalid::new(
            "gyro_id",
            format!("{why}: a serial number is printable text, with no space around it"),
        ));
    }
    if let Some(c) = created.chars().find(|&c| crate::text::is_unprintable(c)) {
        return Err(Invalid::new(
            "created",
            format!(
                "holds {}: a date is printable text",
                crate::text::unprintable_named(c)
            ),
        ));
    }
    if !is_date_time(created) {
        return Err(Invalid::new(
            "created",
            format!(
                "{} is not a date and time; a calibration records when it was made as RFC 3339 \
                 (2026-12-04T11:07:31Z, or with an offset: 2026-12-04T12:07:31+01:00)",
                match created.char_indices().nth(40) {
                    Some((end, _)) => format!("\"{}…\"", &created[..end]),
                    None => format!("\"{created}\""),
                }
            ),
        ));
    }
    let chars = gyro_id.chars().count();
    if chars > MAX_GYRO_ID_CHARS {
        return Err(Invalid::new(
            "gyro_id",
            format!("is {chars} characters long: a serial number has at most {MAX_GYRO_ID_CHARS}"),
        ));
    }
    Ok(())
}

/// Whether `text` is an RFC 3339 date and time (`2026-12-04T11:07:31Z`, fractional seconds,
/// a space for the `T`, no zone or a `±HH:MM` offset), as `created` is written.
fn is_date_time(text: &str) -> bool {
    let local = match text.len().checked_sub(6).map(|i| text.split_at(i)) {
        Some((head, zone))
            if text.is_char_boundary(text.len() - 6)
                && zone.len() == 6
                && matches!(zone.as_bytes()[0], b'+' | b'-')
                && zone.as_bytes()[3] == b':'
                && zone[1..3]
                    .bytes()
                    .chain(zone[4..].bytes())
                    .all(|b| b.is_ascii_digit()) =>
        {
            head
        }
        _ => text,
    };
    humantime::parse_rfc3339_weak(local).is_ok()
}

/// Checks the statistics of a fit stored under `field` (`k0.stats`, `model.stats`), beyond
/// being numbers: R² is one less a ratio of sums of squares, so at most 1; an RMS residual
/// is a root, never negative; and they are over at least one point, unless `none_fitted`
/// (a term with no point to fit is left out as zero, over none).
///
/// # Errors
/// An [`Invalid`] naming the statistic (`k0.stats.r2`).
pub fn check_stats(
    field: &str,
    n: usize,
    rmse: f64,
    r2: f64,
    none_fitted: bool,
) -> std::result::Result<(), Invalid> {
    let readable = crate::number::readable;
    if !(r2.is_finite() && r2 <= 1.0) {
        return Err(Invalid::new(
            format!("{field}.r2"),
            format!(
                "is {}: R² is 1 less a ratio of sums of squares, never above 1",
                readable(r2)
            ),
        ));
    }
    if !(rmse.is_finite() && rmse >= 0.0) {
        return Err(Invalid::new(
            format!("{field}.rmse"),
            format!(
                "is {}: an RMS residual is the root of a mean square, never negative",
                readable(rmse)
            ),
        ));
    }
    if n == 0 && !none_fitted {
        return Err(Invalid::new(
            format!("{field}.n"),
            "is 0: a fitted curve was fitted to at least one point",
        ));
    }
    Ok(())
}

/// A log's predicted drift handed out in order, a batch at a time ([`DriftModel::predictor`]).
#[derive(Debug, Clone)]
pub enum Predictor<'a> {
    /// Predicted batch by batch.
    Batches(Box<LogPredictor<'a>>),
    /// Predicted whole, handed out in batches.
    Whole {
        /// The whole prediction.
        prediction: Prediction,
        /// The next sample to hand out.
        next: usize,
    },
}

impl Predictor<'_> {
    /// Fills `out` with the next samples' predicted drift (fewer at the end of the log) and
    /// returns how many it filled.
    pub fn fill(&mut self, out: &mut [f64]) -> usize {
        match self {
            Predictor::Batches(p) => p.fill(out),
            Predictor::Whole { prediction, next } => {
                let rest = &prediction.pred_dph[(*next).min(prediction.pred_dph.len())..];
                let n = rest.len().min(out.len());
                out[..n].copy_from_slice(&rest[..n]);
                *next += n;
                n
            }
        }
    }

    /// Share of the samples outside the calibrated ranges, of those predicted so far.
    pub fn outside_fraction(&self) -> f64 {
        match self {
            Predictor::Batches(p) => p.outside_fraction(),
            Predictor::Whole { prediction, .. } => prediction.outside_fraction,
        }
    }
}

/// A streaming corrector for any model.
#[derive(Debug, Clone)]
pub enum ModelCorrector {
    /// The Vakhrameev corrector.
    Vakhrameev(Box<StreamCorrector>),
    /// A regression model's corrector.
    Regression(Box<RegressionCorrector>),
}

impl ModelCorrector {
    /// Feeds one sample (see [`DriftModel::inputs`] for what `temp2_c` and `channels` are;
    /// the Vakhrameev model reads neither).
    pub fn push(
        &mut self,
        time_s: f64,
        omega_dph: f64,
        temp_c: f64,
        temp2_c: f64,
        channels: &[f64],
    ) -> Corrected {
        match self {
            ModelCorrector::Vakhrameev(c) => c.push(time_s, omega_dph, temp_c),
            ModelCorrector::Regression(c) => c.push(time_s, omega_dph, temp_c, temp2_c, channels),
        }
    }
}

/// The values a streaming corrector is fed for sample `i` of `log`: the second temperature
/// and the extra channels the model reads.
///
/// # Errors
/// A channel the log lacks.
pub fn stream_inputs(model: &DriftModel, log: &Log) -> Result<(Vec<f64>, Vec<Vec<f64>>)> {
    let (temp2, names) = model.inputs();
    let find = |name: &str| {
        log.extra
            .iter()
            .find(|c| c.name == name)
            .map(|c| c.values.clone())
            .ok_or_else(|| FitError::missing_channel(log, name).into())
    };
    let t2 = match temp2 {
        Some(n) => find(&n)?,
        None => vec![f64::NAN; log.len()],
    };
    let ch = names.iter().map(|n| find(n)).collect::<Result<Vec<_>>>()?;
    Ok((t2, ch))
}
