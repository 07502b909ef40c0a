//! A unit's accelerometer axes in the application data: what the load job made of the log's
//! columns, their newest calibration, the one shown, and what the exports take of them. Apart
//! from `state.rs` because they are held apart from the gyro axes: they have no choices of
//! their own.

use super::AppState;
use crate::gui::jobs::Loaded;
use std::sync::Arc;

/// A unit's accelerometer axes: calibrated together, beside the gyro axes, through the
/// engine's one unit path (`calibrate --accel`'s), each with the static model the engine
/// gives an accelerometer when none is named. They have no choices of their own: the unit's
/// T, its smoothing and its plateaus are theirs (the first gyro axis's recipe).
#[derive(Default)]
pub struct AccelAxes {
    /// The calibration log with them after the gyro axes, or why the engine could not make
    /// them of its columns.
    pub log: Option<Arc<crate::log::Log>>,
    /// Why they could not be made (the engine's words).
    pub read_error: Option<String>,
    /// Their names, in the log's order.
    pub names: Vec<String>,
    /// Each as a log of its own (its samples in `omega_dph`, no other axis), in the same
    /// order: what a calibration opened beside the fit is judged on for its accelerometer
    /// axes, as each gyro axis's view is for its gyro axes.
    pub views: Vec<Arc<crate::log::Log>>,
    /// The newest calibration of them answered.
    pub fit: Option<Arc<crate::gui::jobs::AccelView>>,
    /// The one shown on the Calibration page in place of the gyro axis, when one is.
    pub shown: Option<usize>,
}

impl AccelAxes {
    /// The accelerometer axes of the log `loaded`, as the load job made them
    /// ([`Loaded::accel`]); `None` for a log without accelerometer columns.
    pub fn of(loaded: &Loaded) -> Option<AccelAxes> {
        Some(match loaded.accel.as_ref()? {
            Ok(log) => {
                let names = log.axes_of(crate::log::AxisKind::Accel);
                let views = names
                    .iter()
                    .map(|n| {
                        let mut view = (**log).clone();
                        view.select_axis(n);
                        view.other_axes.clear();
                        Arc::new(view)
                    })
                    .collect();
                AccelAxes {
                    names,
                    views,
                    log: Some(log.clone()),
                    ..AccelAxes::default()
                }
            }
            Err(e) => AccelAxes {
                read_error: Some(crate::gui::view_import::accel_in_labels(e)),
                ..AccelAxes::default()
            },
        })
    }
}

impl AppState {
    /// Whether the unit calibrates its accelerometer axes: it has some, and they are not
    /// turned off. A log of one gyro axis with accelerometer axes is a unit of them.
    pub fn accel_on(&self) -> bool {
        self.accel.is_some() && !self.accel_off
    }

    /// Whether the Calibration page has an axis strip: a unit of several gyro axes, or a log
    /// with accelerometer axes (its one gyro axis beside them).
    pub fn has_axis_strip(&self) -> bool {
        self.unit.is_some() || self.accel.is_some()
    }

    /// The gyro axes of the unit, by name: a unit's, or for a log of one gyro axis with its
    /// accelerometer axes on, that axis as the engine names it in a unit
    /// ([`crate::models::accel::with_accelerometers`], the rule `calibrate --accel` takes it
    /// by); `None` for a log of one axis alone.
    ///
    /// # Errors
    /// Its gyro axis has no name to find it by (the engine's words).
    pub fn unit_gyro_names(&self) -> Option<Result<Vec<String>, String>> {
        if let Some(u) = &self.unit {
            return Some(Ok(u.names.clone()));
        }
        if !self.accel_on() {
            return None;
        }
        let log = self.unit_full_log()?;
        Some(
            crate::models::accel::with_accelerometers(None, false, &log)
                .map(|axes| {
                    axes.unwrap_or_default()
                        .into_iter()
                        .filter(|n| log.kind_of(n) == Some(crate::log::AxisKind::Gyro))
                        .collect()
                })
                .map_err(|e| {
                    format!(
                        "{e} (turn Accelerometers off in the axis strip to calibrate the gyro \
                         axis alone)"
                    )
                }),
        )
    }

    /// What the accelerometer axes are calibrated with now: the calibration log with them and
    /// the unit's recipe (the first gyro axis's); `None` when they are off or could not be
    /// made.
    pub fn accel_request(&self) -> Option<crate::gui::jobs::AccelRequest> {
        if !self.accel_on() {
            return None;
        }
        let log = self.accel.as_ref()?.log.clone()?;
        let first = self.axis(0)?;
        let loaded = first.log?;
        Some(crate::gui::jobs::AccelRequest {
            log,
            name: loaded
                .path
                .file_name()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| loaded.path.display().to_string()),
            sha256: loaded.sha256.clone().unwrap_or_default(),
            recipe: first.choices.recipe.clone(),
            validation: self.accel_validation(),
        })
    }

    /// The validation log open, with its accelerometer axes made of its columns as the
    /// calibration log's were (its import view's mapping), for the held-out figures.
    fn accel_validation(&self) -> Option<crate::gui::jobs::AccelValidation> {
        let file = self.validation_file.as_ref()?;
        let log = match &file.accel {
            Some(Ok(log)) => Ok(log.clone()),
            Some(Err(e)) => Err(crate::gui::view_import::accel_in_labels(e)),
            None => Err(format!(
                "{}: no accelerometer column (none of its columns is named as one, and none is \
                 mapped as one in its import view)",
                crate::gui::widgets::file_name(&file.path)
            )),
        };
        Some(crate::gui::jobs::AccelValidation {
            log,
            // (the file's name as `evaluate` gives it to the in-sample rule)
            name: file
                .path
                .file_name()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| file.path.display().to_string()),
            sha256: file.sha256.clone().unwrap_or_default(),
        })
    }

    /// The calibration of the accelerometer axes of the current choices (the engine's, stamped
    /// as `calibrate` stamps it); `None` when they are off.
    ///
    /// # Errors
    /// Why they could not be made of the log's columns or calibrated (the engine's words,
    /// naming the switch that leaves them out), or that their calibration is still on its way.
    pub fn accel_calibration(&self) -> Option<Result<crate::models::UnitCalibration, String>> {
        if !self.accel_on() {
            return None;
        }
        let a = self.accel.as_ref()?;
        let off = "turn Accelerometers off in the axis strip to leave them out";
        if let Some(e) = &a.read_error {
            return Some(Err(format!("accelerometer axes: {e} ({off})")));
        }
        let key = crate::gui::jobs::AccelKey::of(&self.accel_request()?);
        Some(match &a.fit {
            Some(f) if f.key == key => match &f.result {
                Ok(fit) => Ok(fit.unit.clone()),
                Err(e) => Err(format!("accelerometer axes: {e} ({off})")),
            },
            _ => Err("the accelerometer axes have no calibration of the current choices".into()),
        })
    }

    /// The calibration log with every axis of the unit: its accelerometer axes too when the
    /// unit calibrates them.
    pub fn unit_full_log(&self) -> Option<Arc<crate::log::Log>> {
        if self.accel_on()
            && let Some(log) = self.accel.as_ref().and_then(|a| a.log.clone())
        {
            return Some(log);
        }
        self.unit.as_ref()?.full_log.clone()
    }

    /// Whether the accelerometer axes' newest calibration answers the current choices (true
    /// when they are off or could not be made: nothing is on its way).
    pub fn accel_current(&self) -> bool {
        let (Some(req), Some(a)) = (self.accel_request(), self.accel.as_ref()) else {
            return true;
        };
        let key = crate::gui::jobs::AccelKey::of(&req);
        a.fit.as_ref().is_some_and(|f| f.key == key)
    }

    /// The accelerometer axis shown on the Calibration page in place of the gyro axis, when
    /// one is (and the unit calibrates them).
    pub fn accel_shown(&self) -> Option<usize> {
        self.accel
            .as_ref()
            .filter(|_| self.accel_on())
            .and_then(|a| a.shown)
    }
}
