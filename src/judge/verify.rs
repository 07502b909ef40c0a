//! A saved calibration judged on a log: which of the log's axes each axis of the calibration
//! corrects, the figures of merit there, and whether the log is the calibration's own run
//! (in-sample) or held out, in words. `driftlab evaluate` prints it and the workbench's opened
//! calibration draws it; both call these functions, so a figure the window shows is the figure
//! the command line prints for the same files and options.

use crate::error::{Error, Invalid};
use crate::judge::metrics::{Evaluation, MeritOptions};
use crate::log::run_sketch::Shared;
use crate::log::{DroneGyro, Log};
use crate::models::UnitCalibration;
use crate::models::fitted::DriftModel;
use crate::models::vakhrameev::correct::Correction;

/// The file a log was read from, as the in-sample rule knows it: its name (the calibration
/// records its log's name) and the SHA-256 of its bytes (empty when not known).
#[derive(Debug, Clone, Copy)]
pub struct LogFile<'a> {
    /// The file's name, without its folder.
    pub name: &'a str,
    /// SHA-256 of the file's bytes, hex; empty when not known.
    pub sha256: &'a str,
}

/// The options of the figures of `model`: the filter and window asked for, else the model's
/// own filter (a Vakhrameev calibration's recipe; the default for a regression model) and the
/// default window. A calibration is judged with the filter it was made with unless another is
/// asked, so that its figures are those it was made to reach.
pub fn merit_options(
    model: &DriftModel,
    filter_s: Option<f64>,
    window_s: Option<f64>,
) -> MeritOptions {
    let default = MeritOptions::default();
    let own_filter = match model {
        DriftModel::Vakhrameev(cal) => cal.recipe.filter_s,
        DriftModel::Regression(_) => default.filter_s,
    };
    MeritOptions {
        filter_s: filter_s.unwrap_or(own_filter),
        window_s: window_s.unwrap_or(default.window_s),
    }
}

/// One model judged on one axis of a log.
#[derive(Debug, Clone)]
pub struct Judged {
    /// The options the figures were computed with.
    pub options: MeritOptions,
    /// Whether the log holds the run the model was fitted on
    /// ([`crate::models::vakhrameev::SourceInfo::is_run_of`]).
    pub in_sample: bool,
    /// How much of the log is the calibration log's, when the calibration's sketch of its
    /// samples tells (files written before sketches were kept do not).
    pub share: Option<Shared>,
    /// What the check of the options tells without refusing them (a filter shorter than a
    /// sample, taken as one).
    pub told: Option<Invalid>,
    /// (the gyro the model was fitted on, the gyro of the drone log judged) when they are two
    /// gyros: another sensor's samples, held out whatever the file.
    pub other_gyro: Option<(DroneGyro, DroneGyro)>,
    /// The run of the calibration's campaign whose file this log is, in words
    /// ([`campaign_run_label`]); `None` for another file, or a calibration of one run.
    pub campaign_run: Option<String>,
    /// Raw against corrected.
    pub evaluation: Evaluation,
    /// The correction itself (the window draws it).
    pub correction: Correction,
}

impl Judged {
    /// Whether the log is the calibration's own, in words ([`sample_label`]), and when it is
    /// another gyro than the one calibrated, which two.
    pub fn sample_label(&self) -> String {
        let label = match &self.campaign_run {
            Some(run) if self.in_sample => run.clone(),
            _ => sample_label(self.in_sample, self.share),
        };
        match &self.other_gyro {
            Some((fitted, read)) => format!(
                "{label}; another gyro than the one calibrated: this log's {}, the \
                 calibration's {}",
                read.describe(),
                fitted.describe()
            ),
            None => label,
        }
    }
}

/// Why a model could not be judged on a log.
#[derive(Debug, thiserror::Error)]
pub enum JudgeError {
    /// The options of the figures do not fit the log (a filter longer than the log, a window
    /// asked for that is shorter than its step).
    #[error("{0}")]
    Options(Invalid),
    /// The log's rate never moves: a frozen or saturated gyro, nothing to judge.
    #[error("{0}")]
    FrozenRate(Error),
    /// The model cannot correct the log (a channel a regression model reads is missing).
    #[error("{0}")]
    Correct(Error),
}

/// Judges `model` on `log` (whose `omega_dph` holds the axis it corrects), read from `file`,
/// with the figures' `options`; `window_asked`: the window was asked for, so one shorter than
/// the log's step is refused rather than giving `n/a` figures.
///
/// # Errors
/// [`JudgeError`]: options that do not fit the log, a rate that never moves, a log the model
/// cannot correct.
pub fn judge(
    model: &DriftModel,
    log: &Log,
    file: LogFile<'_>,
    options: MeritOptions,
    window_asked: bool,
) -> Result<Judged, JudgeError> {
    let source = model.source();
    let (in_sample, share) = source.judge_run(log, file.name, file.sha256);
    let other_gyro = match (&source.instance, &log.info.instance) {
        (Some(fitted), Some(read)) if !fitted.same_gyro(read) => {
            Some((fitted.clone(), read.clone()))
        }
        _ => None,
    };
    let told = crate::judge::options::check_merit(&options, log).map_err(JudgeError::Options)?;
    if window_asked {
        crate::judge::options::check_window_whole(options.window_s, log)
            .map_err(JudgeError::Options)?;
    }
    crate::models::check_axis_readings(log).map_err(JudgeError::FrozenRate)?;
    let correction = model.correct(log).map_err(JudgeError::Correct)?;
    // A window asked for must fit in what is judged: the samples after the warm-up.
    if window_asked {
        crate::judge::options::check_window_fits(options.window_s, log, &correction.ready)
            .map_err(JudgeError::Options)?;
    }
    let evaluation = Evaluation::of_correction(log, &correction, &options).of_model(model);
    Ok(Judged {
        options,
        in_sample,
        share,
        told,
        other_gyro,
        campaign_run: campaign_run_label(source, file.sha256),
        evaluation,
        correction,
    })
}

/// "in-sample: run 2 of the calibration's campaign (B.csv)" for a log whose file's SHA-256
/// is a run's of the campaign the calibration was fitted on; `None` otherwise.
pub fn campaign_run_label(
    source: &crate::models::vakhrameev::SourceInfo,
    file_sha256: &str,
) -> Option<String> {
    if file_sha256.is_empty() {
        return None;
    }
    source
        .runs
        .iter()
        .position(|r| !r.sha256.is_empty() && r.sha256.eq_ignore_ascii_case(file_sha256))
        .map(|k| {
            format!(
                "in-sample: run {} of the {} runs of the calibration's campaign ({})",
                k + 1,
                source.runs.len(),
                crate::text::escaped(&source.runs[k].name, false)
            )
        })
}

/// Whether the log judged on is the calibration's own, in words: with how much of it is the
/// calibration log's, or how much of the calibration log it is, when its samples' sketch
/// (`share`) tells that it is not all of it; or that the sketch cannot tell, and why (too few
/// of its samples compared, a column written coarser than the calibration log's), rather than
/// "not the calibration log" said of a log it could not judge.
pub fn sample_label(in_sample: bool, share: Option<Shared>) -> String {
    let axes = |s: &Shared| {
        if s.told_with_other_axes() {
            " (told with the unit's other axes)"
        } else {
            ""
        }
    };
    match (in_sample, share) {
        (false, Some(s)) if s.cannot_tell().is_some() => format!(
            "cannot tell if it is the calibration log: {}",
            s.cannot_tell().unwrap_or_default()
        ),
        (false, Some(s)) if s.partly().is_some() => format!(
            "held out, though {} of its samples are the calibration log's{}",
            share_words(s.share_of_log),
            axes(&s)
        ),
        (false, Some(s)) => format!("held out: not the calibration log{}", axes(&s)),
        (false, None) => "held out: not the calibration log".into(),
        // In-sample by its file (its samples binned, say): the sketch has nothing to add.
        (true, Some(s)) if !s.in_sample() => "in-sample: the calibration log".into(),
        // The sketch estimates from 128 hashes: within a few % of all is all.
        (true, Some(s)) if s.share_of_log < 0.95 => format!(
            "in-sample: {} of its samples are the calibration log's{}",
            share_words(s.share_of_log),
            axes(&s)
        ),
        (true, Some(s)) if s.share_of_run() < 0.95 => format!(
            "in-sample: a part of the calibration log, {} of it{}",
            share_words(s.share_of_run()),
            axes(&s)
        ),
        (true, Some(s)) => format!("in-sample: the calibration log{}", axes(&s)),
        (true, None) => "in-sample: the calibration log".into(),
    }
}

/// A share (0 to 1) as the labels say it: "about 9 %", and "under 1 %" for a share that is
/// not 0 but rounds to it (a 0 that means "less than one percent" reads as none).
pub fn share_words(share: f64) -> String {
    let p = 100.0 * share;
    if p < 0.5 {
        "under 1 %".into()
    } else {
        // Rounded half up, so that no share that is said at all is said to be 0.
        format!("about {} %", crate::number::fixed(p.round(), 0))
    }
}

/// What a unit's axes judged on one log's rows (`in_sample` and `share` of each, in the same
/// order) tell together ([`Shared::settle_axes`]): an axis that saw too few of the rows to
/// tell alone takes what the axes' values pooled tell, so that the axes of one unit do not
/// contradict each other on the same rows; its `in_sample` follows. Every face judging a
/// unit calls it.
pub fn settle_axes(in_sample: &mut [bool], shares: &mut [Option<Shared>]) {
    Shared::settle_axes(shares);
    for (i, s) in in_sample.iter_mut().zip(shares.iter()) {
        *i |= s.is_some_and(|s| s.in_sample());
    }
}

/// The kind of a label: the sample label's first words ("in-sample", "held out",
/// "cannot tell"), which a unit's summary groups its axes by.
pub fn sample_kind(in_sample: bool, share: Option<Shared>) -> &'static str {
    if in_sample {
        "in-sample"
    } else if share.is_some_and(|s| s.cannot_tell().is_some()) {
        "cannot tell"
    } else {
        "held out"
    }
}

/// The label of a unit's axes (`labels`, each axis's name, kind and label) on one log: the
/// one label when every axis has it, else the axes grouped by kind ("in-sample on gx, gy;
/// held out on gz").
pub fn unit_label(axes: &[(&str, &'static str, String)]) -> String {
    if let Some((_, _, first)) = axes.first()
        && axes.iter().all(|(_, _, l)| l == first)
    {
        return first.clone();
    }
    ["in-sample", "held out", "cannot tell"]
        .iter()
        .filter_map(|kind| {
            let names: Vec<&str> = axes
                .iter()
                .filter(|(_, k, _)| k == kind)
                .map(|(n, _, _)| *n)
                .collect();
            (!names.is_empty()).then(|| format!("{kind} on {}", names.join(", ")))
        })
        .collect::<Vec<_>>()
        .join("; ")
}

/// The log's axis each axis of `unit` corrects, in the unit's order, where the files tell:
/// for a named axis, the log's axis of that name, or of the rate column it was read from on
/// its own log ([`Log::matching_axis`]); for the one unnamed axis of a single-axis
/// calibration, the log's axis when the log has only one. `None` where they do not: an axis
/// the log lacks, or a single-axis calibration (which records no column) on a log of several
/// axes. A face asks the engineer then, or refuses, and never guesses.
pub fn find_axes(unit: &UnitCalibration, log: &Log) -> Vec<Option<String>> {
    if !unit.is_unit() {
        let one = log.other_axes.is_empty();
        return vec![one.then(|| log.axis.clone())];
    }
    unit.axes
        .iter()
        .map(|ax| log.matching_axis(&ax.name, &ax.rate_column))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A drone log's gyro judged with a calibration fitted on another gyro of it: held out
    /// however alike the samples are, and the label names both gyros; on the gyro it was
    /// fitted on, in-sample and no word of gyros.
    #[test]
    fn another_gyro_is_held_out_and_named() {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs/calibration.csv");
        let mut log = crate::log::ingest::read_path(&path, &Default::default()).expect("log");
        let gyro = |index: usize, imu: u8| DroneGyro {
            dataflash_imu: Some(imu),
            ..DroneGyro::numbered(index)
        };
        log.info.instance = Some(gyro(0, 0));
        let recipe = crate::models::recipe::Recipe::default()
            .checked()
            .expect("recipe");
        let mut model = crate::models::fit(
            &log,
            &crate::models::ModelChoice::Preset(crate::models::Preset::Vakhrameev),
            &recipe,
        )
        .expect("fit");
        let file = LogFile {
            name: "calibration.csv",
            sha256: "",
        };
        model.source_mut().instance = Some(gyro(0, 0));
        let same = judge(&model, &log, file, MeritOptions::default(), false).expect("judged");
        assert!(same.in_sample);
        assert_eq!(same.other_gyro, None);
        assert!(
            !same.sample_label().contains("gyro"),
            "{}",
            same.sample_label()
        );
        model.source_mut().instance = Some(gyro(1, 1));
        let other = judge(&model, &log, file, MeritOptions::default(), false).expect("judged");
        assert!(!other.in_sample);
        assert_eq!(other.other_gyro, Some((gyro(1, 1), gyro(0, 0))));
        assert_eq!(
            other.sample_label(),
            "held out: not the calibration log; another gyro than the one calibrated: this \
             log's gyro 0 (DataFlash IMU I=0), the calibration's gyro 1 (DataFlash IMU I=1)"
        );
        // A PX4 chip is told by its device_id, not its number: the same chip at another
        // number (a chip before it re-enumerated in one log) is the calibration's gyro, and
        // another chip at the same number is not.
        let chip = |index: usize, device_id: u32| DroneGyro {
            px4_device_id: Some(device_id),
            ..DroneGyro::numbered(index)
        };
        log.info.instance = Some(chip(1, 0x380022));
        model.source_mut().instance = Some(chip(2, 0x380022));
        let same = judge(&model, &log, file, MeritOptions::default(), false).expect("judged");
        assert!(same.in_sample);
        assert_eq!(same.other_gyro, None);
        model.source_mut().instance = Some(chip(1, 0x280022));
        let other = judge(&model, &log, file, MeritOptions::default(), false).expect("judged");
        assert!(!other.in_sample);
        assert_eq!(
            other.other_gyro,
            Some((chip(1, 0x280022), chip(1, 0x380022)))
        );
        assert!(
            other.sample_label().ends_with(
                "this log's gyro 1 (device_id 3670050 (0x380022)), the calibration's \
                            gyro 1 (device_id 2621474 (0x280022))"
            ),
            "{}",
            other.sample_label()
        );
    }

    #[test]
    fn the_label_says_held_out_and_in_sample() {
        assert_eq!(
            sample_label(false, None),
            "held out: not the calibration log"
        );
        assert_eq!(sample_label(true, None), "in-sample: the calibration log");
    }

    /// A share under one percent is never written 0 %; from one half percent on it is the
    /// share rounded to a whole percent.
    #[test]
    fn a_share_under_one_percent_is_not_said_to_be_none() {
        for (share, words) in [
            (0.004_975, "under 1 %"),
            (1e-9, "under 1 %"),
            (0.005, "about 1 %"),
            (0.0924, "about 9 %"),
            (0.5, "about 50 %"),
        ] {
            assert_eq!(share_words(share), words, "{share}");
        }
    }

    #[test]
    fn a_units_label_groups_its_axes_by_kind() {
        let l = |s: &str| s.to_string();
        let same = [
            ("gx", "in-sample", l("in-sample: x")),
            ("gy", "in-sample", l("in-sample: x")),
        ];
        assert_eq!(unit_label(&same), "in-sample: x");
        let mixed = [
            ("gx", "in-sample", l("in-sample: about 96 %")),
            ("gy", "cannot tell", l("cannot tell if ...")),
            ("gz", "in-sample", l("in-sample: about 97 %")),
            ("gw", "held out", l("held out: ...")),
        ];
        assert_eq!(
            unit_label(&mixed),
            "in-sample on gx, gz; held out on gw; cannot tell on gy"
        );
    }
}
