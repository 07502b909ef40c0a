//! The opened calibration's work off the frame: its file read, and its judging on the open
//! logs (one at a time, the newest request waiting), axis by axis, as `driftlab evaluate` judges it ([`crate::judge::verify`]), each axis
//! with the drawing data of its corrected drift. The newest request wins: the window drops an
//! answer to logs or options it no longer shows.

use super::*;
use crate::gui::action::OpenLog;
use crate::gui::plot_items::Segments;
use crate::judge::metrics::Evaluation;
use crate::judge::verify::{self, LogFile};
use crate::models::UnitCalibration;
use std::collections::BTreeMap;

/// One open log, as the opened calibration is judged on it.
#[derive(Debug, Clone)]
pub struct LogInput {
    /// Which of the open logs it is.
    pub which: OpenLog,
    /// Its file (a campaign's first run).
    pub path: PathBuf,
    /// Its name for the window ([`super::Loaded::name`]).
    pub name: String,
    /// SHA-256 of the file (empty when not known): the in-sample rule reads it.
    pub sha256: String,
    /// The log with every axis: the calibration's axes are found among them.
    pub full: Arc<Log>,
    /// Each axis the workbench holds, as a log of its own (its rate in `omega_dph`): the
    /// views the drift plot draws, judged as they are.
    pub views: Vec<Arc<Log>>,
}

/// What the opened calibration is judged for: the calibration, the open logs, the figures'
/// options and the axes the engineer placed by hand.
#[derive(Debug, Clone)]
pub struct VerifyRequest {
    /// The calibration file, for messages.
    pub path: PathBuf,
    /// The calibration.
    pub unit: Arc<UnitCalibration>,
    /// The open logs: the calibration log, then the validation log when one is open.
    pub logs: Vec<LogInput>,
    /// The options of the figures: the workbench's, so that both calibrations are judged
    /// alike.
    pub merit: MeritOptions,
    /// Per open log and axis of the calibration (its index), the log's axis the engineer chose.
    pub chosen: BTreeMap<(OpenLog, usize), String>,
}

/// A request's inputs by identity (the logs and the calibration) and value (the rest): the
/// same again needs no judging, and an answer to another is stale.
#[derive(Debug, Clone, PartialEq)]
pub struct VerifyKey {
    unit: Same<UnitCalibration>,
    logs: Vec<(OpenLog, Same<Log>, Vec<Same<Log>>)>,
    merit: MeritOptions,
    chosen: BTreeMap<(OpenLog, usize), String>,
}

impl VerifyKey {
    /// The key of `r`.
    pub fn of(r: &VerifyRequest) -> VerifyKey {
        VerifyKey {
            unit: Same::of(&r.unit),
            logs: r
                .logs
                .iter()
                .map(|l| {
                    (
                        l.which,
                        Same::of(&l.full),
                        l.views.iter().map(Same::of).collect(),
                    )
                })
                .collect(),
            merit: r.merit,
            chosen: r.chosen.clone(),
        }
    }

    /// Whether this key is of the calibration `unit`.
    pub fn of_unit(&self, unit: &Arc<UnitCalibration>) -> bool {
        self.unit.is(unit)
    }
}

/// The opened calibration judged on the open logs.
pub struct Verified {
    /// The request number it answers.
    pub generation: u64,
    /// What it was judged for.
    pub key: VerifyKey,
    /// One per open log, in the request's order.
    pub logs: Vec<VerifiedLog>,
    /// Why nothing was judged, when the judging itself failed.
    pub failed: Option<String>,
}

/// The opened calibration judged on one open log.
pub struct VerifiedLog {
    /// Which log.
    pub which: OpenLog,
    /// Its file's name.
    pub name: String,
    /// Its gyro axes.
    pub log_axes: Vec<String>,
    /// One per axis of the calibration, in its order.
    pub axes: Vec<AxisVerdict>,
}

/// What became of one axis of the calibration on one log.
pub enum AxisVerdict {
    /// Judged on an axis of the log.
    Judged(Box<JudgedAxis>),
    /// The files do not say which axis of the log it corrects: the engineer chooses.
    Unplaced(String),
    /// It could not be judged on the log's axis `log_axis`: `why`, in the engine's words.
    Failed {
        /// The log's axis.
        log_axis: String,
        /// The engine's message.
        why: String,
    },
}

/// One axis of the opened calibration judged on one axis of a log.
pub struct JudgedAxis {
    /// The log's axis.
    pub log_axis: String,
    /// Chosen by the engineer (not found by name or rate column).
    pub by_hand: bool,
    /// The view of that axis it was judged on (the drift plot draws it when it shows this
    /// view).
    pub log: Arc<Log>,
    /// The options of the figures.
    pub options: MeritOptions,
    /// Whether the log is the calibration's own run.
    pub in_sample: bool,
    /// That, in `driftlab evaluate`'s words.
    pub label: String,
    /// What the check of the options told without refusing them.
    pub told: Option<String>,
    /// The figures.
    pub evaluation: Evaluation,
    /// The corrected drift filtered as the drift plot draws drifts (within the stretches
    /// whose rates have their history), °/h.
    pub cor_filtered_dph: Vec<f64>,
    /// Its pyramid.
    pub cor_filtered: MinMaxPyramid,
    /// The stretches whose rates have their history.
    pub ready: Segments,
    /// The filter's length, s (its warm-up is drawn faded).
    pub filter_lead_s: f64,
}

impl Jobs {
    /// Reads the calibration file at `path` on a thread, for [`JobResult::CalibrationRead`].
    pub fn read_calibration(&mut self, path: PathBuf) {
        let (tx, ctx) = (self.tx.clone(), self.ctx.clone());
        self.reading_calibration += 1;
        let spawned = std::thread::Builder::new()
            .name("driftlab-calibration".into())
            .spawn({
                let path = path.clone();
                move || {
                    let read = read_calibration(&path);
                    let _ = tx.send(JobResult::CalibrationRead(path, read));
                    repaint(&ctx);
                }
            });
        if let Err(e) = spawned {
            let _ = self.tx.send(JobResult::CalibrationRead(
                path,
                Err(format!("cannot start a thread: {e}")),
            ));
        }
    }

    /// Asks for the opened calibration to be judged as `request` says, unless the newest
    /// judging asked for was for the same inputs; true when it was asked for. One judging runs
    /// at a time: asked while one runs, the request waits, replacing any older one waiting
    /// (a filter dragged asks for one per frame), and the answer of the running one is
    /// dropped as stale.
    pub fn verify(&mut self, request: VerifyRequest) -> bool {
        let key = VerifyKey::of(&request);
        if self.verify_sent.as_ref() == Some(&key) {
            return false;
        }
        self.verify_requested += 1;
        let generation = self.verify_requested;
        self.verify_sent = Some(key);
        if self.verifying.is_some() {
            self.verify_waiting = Some((generation, Box::new(request)));
        } else {
            self.start_verify(generation, request);
        }
        true
    }

    pub(super) fn start_verify(&mut self, generation: u64, request: VerifyRequest) {
        let key = VerifyKey::of(&request);
        let (tx, ctx) = (self.tx.clone(), self.ctx.clone());
        let spawned = std::thread::Builder::new()
            .name("driftlab-verify".into())
            .spawn(move || {
                let run =
                    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| run_verify(&request)));
                // A defect in one judging leaves the opened calibration unjudged, and says so,
                // rather than the window gone.
                let failed = run.is_err().then(|| {
                    "the judging stopped on an internal error (the terminal shows where)"
                        .to_string()
                });
                let _ = tx.send(JobResult::Verified(Arc::new(Verified {
                    generation,
                    key,
                    logs: run.unwrap_or_default(),
                    failed,
                })));
                repaint(&ctx);
            });
        match spawned {
            Ok(_) => self.verifying = Some(generation),
            Err(_) => self.verify_sent = None,
        }
    }

    /// Forgets what the opened calibration was last judged for, and drops a judging waiting
    /// (it was closed): the same inputs again are judged again.
    pub fn forget_verify(&mut self) {
        self.verify_sent = None;
        self.verify_waiting = None;
    }
}

/// Reads the calibration file at `path` (either version) as a unit.
fn read_calibration(path: &std::path::Path) -> Result<Arc<UnitCalibration>, String> {
    crate::files::calibration::load_unit(path)
        .map(Arc::new)
        .map_err(|e| e.to_string())
}

/// Judges the request's calibration on each of its logs.
fn run_verify(r: &VerifyRequest) -> Vec<VerifiedLog> {
    r.logs.iter().map(|l| verify_log(r, l)).collect()
}

fn verify_log(r: &VerifyRequest, l: &LogInput) -> VerifiedLog {
    let found = verify::find_axes(&r.unit, &l.full);
    // (A campaign's name: its first run's and how many follow.)
    let file_name = l.name.clone();
    let log_axes = l.full.axis_names();
    let mut axes = r
        .unit
        .axes
        .par_iter()
        .enumerate()
        .map(|(k, ax)| {
            let chosen = r
                .chosen
                .get(&(l.which, k))
                .filter(|name| log_axes.contains(name));
            let (log_axis, by_hand) = match (chosen, found.get(k).cloned().flatten()) {
                (Some(c), _) => (c.clone(), true),
                (None, Some(f)) => (f, false),
                (None, None) => return Err(AxisVerdict::Unplaced(unplaced(r, k, l, &file_name))),
            };
            let Some(view) = l.views.iter().find(|v| v.axis == log_axis) else {
                return Err(AxisVerdict::Failed {
                    why: format!("{file_name}: axis {log_axis} is not open in the workbench"),
                    log_axis,
                });
            };
            let file = LogFile {
                name: &file_name,
                sha256: &l.sha256,
            };
            // (an accelerometer axis judged about the mean it keeps, as `evaluate` judges it)
            match verify::judge(&ax.model, &ax.as_fitted(view), file, r.merit, false) {
                Ok(j) => Ok((j, view.clone(), log_axis, by_hand)),
                Err(e) => Err(AxisVerdict::Failed {
                    log_axis,
                    why: e.to_string(),
                }),
            }
        })
        .collect::<Vec<_>>();
    // The axes share the log's rows: one that saw too few of them takes what all tell, as
    // `driftlab evaluate` settles them.
    let mut judged: Vec<&mut verify::Judged> = axes
        .iter_mut()
        .filter_map(|a| a.as_mut().ok().map(|(j, ..)| j))
        .collect();
    if r.unit.is_unit() {
        let mut in_sample: Vec<bool> = judged.iter().map(|j| j.in_sample).collect();
        let mut shares: Vec<_> = judged.iter().map(|j| j.share).collect();
        verify::settle_axes(&mut in_sample, &mut shares);
        for ((j, i), s) in judged.iter_mut().zip(in_sample).zip(shares) {
            (j.in_sample, j.share) = (i, s);
        }
    }
    let axes = axes
        .into_iter()
        .map(|a| match a {
            Ok((j, view, log_axis, by_hand)) => {
                AxisVerdict::Judged(Box::new(judged_axis(j, &view, log_axis, by_hand)))
            }
            Err(v) => v,
        })
        .collect();
    VerifiedLog {
        which: l.which,
        name: l.name.clone(),
        log_axes,
        axes,
    }
}

/// Why axis `k` of the request's calibration has no axis of the log `l`, and what to do.
fn unplaced(r: &VerifyRequest, k: usize, l: &LogInput, file_name: &str) -> String {
    let cal = crate::gui::widgets::file_name(&r.path);
    let axes = l.full.axis_names();
    let listed = format!("{} gyro axes ({})", axes.len(), axes.join(", "));
    if !r.unit.is_unit() {
        return format!(
            "{cal} is a calibration of one axis, which does not record the column it was \
             fitted on, and {file_name} has {listed}: choose the axis it corrects"
        );
    }
    let ax = &r.unit.axes[k];
    let column = if ax.rate_column.is_empty() || ax.rate_column == ax.name {
        String::new()
    } else {
        format!(" (column {})", ax.rate_column)
    };
    format!(
        "{file_name} has no axis {}{column} (its axes: {}): choose the one axis {} of {cal} \
         corrects, if any",
        ax.name,
        axes.join(", "),
        ax.name
    )
}

/// The judged axis with its drawing data: the corrected drift filtered with the figures'
/// filter within the stretches whose rates have their history, as the drift plot draws the
/// current fit's.
fn judged_axis(j: verify::Judged, view: &Arc<Log>, log_axis: String, by_hand: bool) -> JudgedAxis {
    let dt = view.nominal_dt_s();
    let window = crate::signal::seconds_to_samples(j.options.filter_s, dt).max(1);
    let cor_filtered_dph =
        super::fit::filtered_within(&j.correction.cor_dph, window, &j.correction.ready);
    let cor_filtered = MinMaxPyramid::new(&cor_filtered_dph);
    JudgedAxis {
        log_axis,
        by_hand,
        log: view.clone(),
        options: j.options,
        in_sample: j.in_sample,
        label: j.sample_label(),
        told: j.told.as_ref().map(ToString::to_string),
        evaluation: j.evaluation,
        ready: Segments::from_ranges(&view.time_s, &j.correction.ready),
        cor_filtered_dph,
        cor_filtered,
        filter_lead_s: window as f64 * dt,
    }
}
