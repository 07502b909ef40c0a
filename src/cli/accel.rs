//! The accelerometer options every command that reads a log takes (`--accel-col`,
//! `--accel-unit`): read into the engine's [`AccelAsk`], honoured by the commands that
//! calibrate, correct or analyse accelerometer axes, refused by name by the others.

use super::common::{CliError, LogArgs};
use driftlab::Log;
use driftlab::log::accel_axes::{self, AccelAsk, AccelUnit};
use driftlab::log::ingest::{ColumnRef, ExtraColumns, Input, Needs};
use driftlab::models::UnitCalibration;

impl LogArgs {
    /// Whether `--accel-col` or `--accel-unit` was given.
    pub fn accel_given(&self) -> bool {
        !self.accel_col.is_empty() || self.accel_unit.is_some()
    }

    /// The accelerometer axes asked for: the `--accel-col` columns (every column named as an
    /// accelerometer without it), in `--accel-unit` where their names state none.
    pub fn accel_ask(&self) -> Result<AccelAsk, String> {
        let columns = self
            .accel_col
            .iter()
            .map(|v| v.parse::<ColumnRef>())
            .collect::<Result<_, _>>()
            .map_err(|e| format!("--accel-col: {e}"))?;
        let unit = self
            .accel_unit
            .as_deref()
            .map(|u| u.parse::<AccelUnit>())
            .transpose()
            .map_err(|e| format!("--accel-unit: {e}"))?;
        Ok(AccelAsk { columns, unit })
    }

    /// The accelerometer options given, by name.
    fn accel_options_given(&self) -> Vec<&'static str> {
        [
            ("--accel-col", !self.accel_col.is_empty()),
            ("--accel-unit", self.accel_unit.is_some()),
        ]
        .into_iter()
        .filter_map(|(option, given)| given.then_some(option))
        .collect()
    }

    /// Refuses the accelerometer options given for a calibration that has no accelerometer
    /// axis, naming the options given and the axes it has.
    pub fn refuse_accel_without(&self, unit: &UnitCalibration) -> Result<(), String> {
        let given = self.accel_options_given();
        if given.is_empty() {
            return Ok(());
        }
        let axes = match unit.axis_names().as_slice() {
            [""] => "it holds one gyro axis".to_string(),
            names => format!("its axes: {}", names.join(", ")),
        };
        Err(format!(
            "{}: the calibration has no accelerometer axis ({axes})",
            given.join(", ")
        ))
    }

    /// Refuses the accelerometer options for a command that reads no accelerometer axis.
    pub fn refuse_accel(&self, command: &str) -> Result<(), CliError> {
        match self.accel_options_given().first() {
            Some(option) => Err(format!(
                "{option}: {command} reads no accelerometer axis (calibrate --accel, apply, \
                 evaluate, report and gui do)"
            )
            .into()),
            None => Ok(()),
        }
    }

    /// Makes the accelerometer axes `ask` names axes of `log`, after its gyro axes; their
    /// names.
    pub fn take_accelerometers(
        &self,
        log: &mut Log,
        ask: &AccelAsk,
    ) -> Result<Vec<String>, String> {
        let told = log.info.problems.len();
        let names = accel_axes::take(log, ask).map_err(|e| in_words(&e))?;
        // What making them axes found (readings no accelerometer gives), told as the log's
        // own problems were when it was read.
        super::common::print_problems(&log.source, &log.info.problems[told..]);
        Ok(names)
    }

    /// Reads a log for a calibration with accelerometer axes: the calibration columns, the
    /// columns of its accelerometer axes (those `--accel-col` gives, else the columns they
    /// were calibrated from) and, when `plain` is false, every other column; then makes them
    /// axes.
    pub(super) fn read_with_accelerometers(
        &self,
        input: &Input,
        unit: &UnitCalibration,
        plain: bool,
    ) -> Result<Log, String> {
        let ask = self.accel_ask_for(unit)?;
        let by_name = by_name(&ask);
        let every = !plain || by_name.len() < ask.columns.len();
        let mut log = if every {
            self.read(input)?
        } else {
            self.read_needing(
                input,
                &Needs {
                    temperature: true,
                    extras: Some(ExtraColumns {
                        names: by_name,
                        accelerometers: ask.columns.is_empty(),
                        temperatures: false,
                    }),
                },
            )?
        };
        self.take_accelerometers(&mut log, &ask)?;
        Ok(log)
    }

    /// The accelerometer axes a log is read with for `unit`'s accelerometer axes: the columns
    /// `--accel-col` gives, else those the axes were calibrated from (every column named as an
    /// accelerometer where the calibration does not say).
    pub(super) fn accel_ask_for(&self, unit: &UnitCalibration) -> Result<AccelAsk, String> {
        let mut ask = self.accel_ask()?;
        if ask.columns.is_empty() {
            ask.columns = unit
                .axes
                .iter()
                .filter(|a| a.kind == driftlab::log::AxisKind::Accel && !a.rate_column.is_empty())
                .map(|a| ColumnRef::Name(a.rate_column.clone()))
                .collect();
        }
        Ok(ask)
    }
}

/// The columns of `ask` named by their header names.
pub(super) fn by_name(ask: &AccelAsk) -> Vec<String> {
    ask.columns
        .iter()
        .filter_map(|c| match c {
            ColumnRef::Name(n) => Some(n.clone()),
            ColumnRef::Index(_) => None,
        })
        .collect()
}

/// An accelerometer axis that could not be made, in the command line's words.
pub(super) fn in_words(e: &accel_axes::AccelError) -> String {
    use accel_axes::AccelError;
    match e {
        AccelError::NoColumn { .. } => format!("{e} (--accel-col)"),
        AccelError::NoAccelerometers { .. } => e.to_string().replace(
            "name them with the accelerometer columns option",
            "name them with --accel-col",
        ),
        AccelError::UnitUntold { .. } => format!("{e} (--accel-unit g, mg or m/s2)"),
        AccelError::NotAnAcceleration { .. } | AccelError::TakenColumn { .. } => {
            format!("{e} (--accel-col)")
        }
        AccelError::UnitContradicted { .. } => format!("{e} (--accel-unit)"),
        AccelError::NotGravity { .. } => {
            format!("{e} (--accel-unit g, mg or m/s2 gives the unit of columns that state none)")
        }
    }
}
