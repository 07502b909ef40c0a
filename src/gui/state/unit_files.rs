//! What the exports take of a unit: its calibration from every axis's fit (its accelerometer
//! axes after the gyro axes) and its validation log put back together from each axis's view.
//! Apart from `state.rs` because it is one idea: the unit as the files written of it hold it.

use super::{AppState, Loaded};

impl AppState {
    /// The validation log with every axis of the unit, put back together from each axis's view
    /// of it (each holds its own rate beside the shared columns): what the unit's report
    /// judges. `None` for a log of one axis alone, no validation log, or one lacking an axis.
    pub fn unit_validation_log(&self) -> Option<(std::path::PathBuf, crate::log::Log)> {
        if self.unit.is_none() && !self.accel_on() {
            return None;
        }
        let views: Vec<&Loaded> = (0..self.axis_count())
            .map(|k| self.axis(k).and_then(|a| a.validation))
            .collect::<Option<_>>()?;
        let first = views.first()?;
        let mut log = (*first.log).clone();
        log.other_axes = views[1..]
            .iter()
            .map(|v| crate::log::Axis {
                name: v.log.axis.clone(),
                omega_dph: v.log.omega_dph.clone(),
                kind: v.log.axis_kind,
            })
            .collect();
        // The accelerometer axes of the unit, from the validation log's own columns.
        if self.accel_on() {
            let with = self
                .validation_file
                .as_ref()?
                .accel
                .as_ref()?
                .as_ref()
                .ok()?;
            let accel = self.accel.as_ref()?;
            for name in &accel.names {
                let rate = with.axis_rate(name)?;
                log.other_axes.push(crate::log::Axis {
                    name: name.clone(),
                    omega_dph: rate.to_vec(),
                    kind: crate::log::AxisKind::Accel,
                });
            }
        }
        views[1..]
            .iter()
            .all(|v| v.log.len() == log.len())
            .then(|| (first.path.clone(), log))
    }

    /// The unit's calibration from every axis's current fit, each stamped with the log's
    /// name and SHA-256 as files record it, its accelerometer axes after the gyro axes when it
    /// calibrates them ([`AppState::accel_calibration`]); `None` for a log of one axis alone
    /// (one gyro axis with its accelerometer axes on is a unit, [`AppState::unit_gyro_names`]).
    ///
    /// # Errors
    /// Naming the first axis with no calibration of its current choices, or why the
    /// accelerometer axes have none.
    pub fn unit_calibration(&self) -> Option<Result<crate::models::UnitCalibration, String>> {
        let names = match self.unit_gyro_names()? {
            Ok(n) => n,
            Err(e) => return Some(Err(e)),
        };
        let mut axes = Vec::with_capacity(names.len());
        for (k, name) in names.iter().enumerate() {
            let Some(a) = self.axis(k) else {
                return Some(Err(format!("axis {name} is missing")));
            };
            let (Some(log), Some(fit)) = (a.log, a.fit.filter(|_| a.fit_current())) else {
                return Some(Err(format!(
                    "axis {name} has no calibration of its current choices{}",
                    a.fit_error.map(|e| format!(" ({e})")).unwrap_or_default()
                )));
            };
            let cal = match crate::gui::export::stamped(&fit.outcome.calibration, log) {
                Ok(c) => c,
                Err(e) => return Some(Err(e)),
            };
            axes.push(crate::models::AxisModel::gyro(
                name.clone(),
                log.log.rate_column().unwrap_or_default(),
                crate::models::DriftModel::Vakhrameev(Box::new(cal)),
            ));
        }
        // The accelerometer axes after the gyro axes, as `calibrate --accel` lists them.
        match self.accel_calibration() {
            Some(Ok(unit)) => axes.extend(unit.axes),
            Some(Err(e)) => return Some(Err(e)),
            None => {}
        }
        Some(Ok(crate::models::UnitCalibration { axes }))
    }
}
