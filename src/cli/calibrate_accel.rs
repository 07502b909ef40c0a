//! `calibrate --accel`: a log's accelerometer axes calibrated beside its gyro axes. Which
//! axes (`--accel`, `--accel-col`), the model each takes when none is named (the engine's
//! [`accel::DEFAULT_MODEL`]), and the options of the gyro axes' model that do not reach them.
//! Apart from `calibrate.rs` because it is the one place the command meets accelerometers.

use super::calibrate::{Args, Given};
use super::common::CliError;
use driftlab::Log;
use driftlab::log::AxisKind;
use driftlab::log::accel_axes::AccelAsk;
use driftlab::models::{AxisPlan, ModelChoice, accel};

impl Args {
    /// The accelerometer axes asked for: `--accel` (every column named as one), or the
    /// columns `--accel-col` gives; `None` when neither was given. Refused with several runs,
    /// before any is read: an accelerometer keeps the mean of one run.
    pub(super) fn accel_asked(&self) -> Result<Option<AccelAsk>, CliError> {
        if !self.accel && !self.log_args.accel_given() {
            return Ok(None);
        }
        if self.log.len() > 1 {
            return Err(format!(
                "{}: a campaign of {} runs calibrates its gyro axes; an accelerometer axis \
                 keeps the mean of the one run it is fitted on: calibrate the accelerometers \
                 on one run",
                if self.accel {
                    "--accel"
                } else {
                    "--accel-col, --accel-unit"
                },
                self.log.len()
            )
            .into());
        }
        Ok(Some(self.log_args.accel_ask()?))
    }

    /// The axes to fit with the accelerometer axes after the gyro axes `chosen` (`None`: the
    /// log's one axis, unnamed): every accelerometer axis is added unless `--axes` chose the
    /// axes; the one gyro axis a single `--rate-col` names is fitted by its name beside them:
    /// the engine's rule ([`accel::with_accelerometers`]), its refusal in flags.
    pub(super) fn with_accelerometers(
        &self,
        chosen: Option<Vec<String>>,
        log: &Log,
    ) -> Result<Option<Vec<String>>, CliError> {
        accel::with_accelerometers(chosen, !self.axes.is_empty(), log).map_err(|e| {
            format!(
                "{}: its gyro axis has no name, and a unit's axes are found by theirs: name its \
                 rate column (--rate-col) or calibrate the accelerometers alone (--axes {})",
                e.log,
                e.accels.join(",")
            )
            .into()
        })
    }

    /// The model of axis `name` of `log`: `choice` for a gyro axis, and for an accelerometer
    /// axis too when --model named it; else [`accel::DEFAULT_MODEL`] (an accelerometer takes
    /// a static model, and the default, Vakhrameev's, is none).
    pub(super) fn choice_for(&self, log: &Log, name: &str, choice: &ModelChoice) -> ModelChoice {
        if log.kind_of(name) == Some(AxisKind::Accel) && self.model.is_none() {
            ModelChoice::Preset(accel::DEFAULT_MODEL)
        } else {
            choice.clone()
        }
    }

    /// Whether `plan` is an accelerometer axis whose model no option named: the settings of
    /// the gyro axes' model (`--k0`, `--plateau` of Vakhrameev's) reach the gyro axes only,
    /// and are neither refused nor told of for it.
    pub(super) fn accel_by_default(&self, log: &Log, plan: &AxisPlan, given: &Given<'_>) -> bool {
        log.kind_of(&plan.name) == Some(AxisKind::Accel)
            && self.model.is_none()
            && !given.gave("--axis-model", &plan.name)
    }
}
