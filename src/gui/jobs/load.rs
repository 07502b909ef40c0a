//! Reading a log off the UI thread, with progress and cancel, and the first views of it:
//! the read, then the averaging into bins the import view asks for (or one sample per burst
//! for a log written in bursts), then the pyramids the plots draw from.

use super::*;
use crate::gui::plot_items::Segments;
use crate::log::accel_axes::{AccelAsk, AccelError};
use crate::log::read::{DroneLog, InstanceChoice};
use crate::log::resample::{self, Resampling};
use std::path::Path;

/// How the workbench reads a log: the reader's options, then the averaging applied after the
/// read. Sessions keep it whole.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LoadOptions {
    /// How the reader parses the file (columns, units, dialect).
    pub read: ReadOptions,
    /// Average into bins of this many seconds after the read; `None`: a log written in bursts
    /// is reduced to one sample per burst, any other log is used as recorded.
    pub bin_s: Option<f64>,
    /// The gyro and temperature of a drone or robot log (nothing for a CSV).
    pub instance: InstanceChoice,
    /// A campaign's runs after the first (several files on the command line or dropped,
    /// File › Add run): each read and averaged as the first is, then joined after it by the
    /// engine ([`crate::log::campaign::join`], which refuses runs of another gyro); empty for
    /// one log.
    pub more_runs: Vec<PathBuf>,
    /// The columns read as accelerometer axes and their unit, as the import view chose them
    /// (the engine's [`AccelAsk`], the command line's `--accel-col` and `--accel-unit`); the
    /// default: every column named as one.
    pub accel: AccelAsk,
}

impl LoadOptions {
    /// Reading with `read`, nothing averaged unless the log is written in bursts.
    pub fn read(read: ReadOptions) -> LoadOptions {
        LoadOptions {
            read,
            ..LoadOptions::default()
        }
    }
}

/// The log as it was recorded, kept beside the log the workbench calibrates when that one is
/// its bursts' means: the plots draw the bursts behind the means.
#[derive(Debug)]
pub struct Recorded {
    /// The columns as read.
    pub log: Log,
    /// Pyramids of its Ω and T.
    pub lods: LogLods,
    /// Its segments (the bursts).
    pub segments: Segments,
}

/// Pyramids of a log's raw columns, built once after reading.
#[derive(Debug, Default)]
pub struct LogLods {
    /// Raw Ω.
    pub omega: MinMaxPyramid,
    /// Raw T (shared by the views of every axis of a log).
    pub temp: Arc<MinMaxPyramid>,
}

/// A log read from a file.
#[derive(Debug, Clone)]
pub struct Loaded {
    /// The file.
    pub path: PathBuf,
    /// How it was read.
    pub options: LoadOptions,
    /// The columns (averaged as [`LoadOptions::bin_s`] says).
    pub log: Arc<Log>,
    /// Pyramids of the raw columns.
    pub lods: Arc<LogLods>,
    /// The log's segments between gaps, for drawing.
    pub segments: Arc<Segments>,
    /// What the averaging after the read did, when it did anything.
    pub resampled: Option<String>,
    /// The log as recorded, when the workbench calibrates its bursts' means.
    pub recorded: Option<Arc<Recorded>>,
    /// SHA-256 of the file, for the calibration's source.
    pub sha256: Option<String>,
    /// What the reader said of a drone or robot log: its gyros, the one read and why.
    pub drone: Option<Arc<DroneLog>>,
    /// Seconds the read took.
    pub seconds: f64,
    /// For a log of several gyro axes, each axis as a log of its own (the same time and
    /// temperature, the axis's rate in `omega_dph`), in the log's order; empty for a log of
    /// one axis. The first is this log itself; the others hold no other axis (one copy of
    /// each rate in memory, not one per view).
    pub axis_views: Vec<Loaded>,
    /// The log with its accelerometer columns made axes after its gyro axes, in m/s², by the
    /// engine's one rule ([`crate::log::accel_axes::take`], the columns
    /// [`LoadOptions::accel`] asks for, by default every column named as one, as `calibrate
    /// --accel` takes them), or why they cannot be; `None` for a log with no accelerometer
    /// column that asks for none. Read once with the log, so that turning the accelerometer
    /// axes on and off reads nothing again.
    pub accel: Option<Result<Arc<Log>, AccelError>>,
}

impl Loaded {
    /// The log as `driftlab report` and `evaluate` are given it: its file and samples, or for
    /// a campaign each run's file with that run's samples on its own time (`full`: the log
    /// with every axis, for a unit).
    pub fn as_files(&self, full: &Log) -> Vec<(PathBuf, Log)> {
        if full.runs().len() < 2 {
            return vec![(self.path.clone(), full.clone())];
        }
        std::iter::once(&self.path)
            .chain(&self.options.more_runs)
            .enumerate()
            .filter_map(|(k, p)| Some((p.clone(), full.run_log(k)?)))
            .collect()
    }

    /// The log's name for the window: its file's, or for a campaign the first run's and how
    /// many runs follow (`heating.csv + 2 runs`).
    pub fn name(&self) -> String {
        let first = crate::gui::widgets::file_name(&self.path);
        match self.log.runs().len() {
            n if n > 1 => format!("{first} + {} run{}", n - 1, if n == 2 { "" } else { "s" }),
            _ => first,
        }
    }

    /// The view of the axis named `name` (see [`Loaded::axis_views`]).
    pub fn axis_view(&self, name: &str) -> Option<&Loaded> {
        self.axis_views.iter().find(|v| v.log.axis == name)
    }
}

/// A read in progress.
#[derive(Debug, Clone)]
pub struct LoadHandle {
    /// Which slot.
    pub target: Target,
    /// The file.
    pub path: PathBuf,
    /// Fraction done (f64 bits).
    pub(super) progress: Arc<AtomicU64>,
    /// Set to stop the read.
    pub(super) cancel: Arc<AtomicBool>,
    /// When it started.
    pub started: Instant,
}

impl LoadHandle {
    /// Fraction done, 0 to 1.
    pub fn progress(&self) -> f64 {
        f64::from_bits(self.progress.load(Ordering::Relaxed)).clamp(0.0, 1.0)
    }
}

pub(super) fn load_log(h: &LoadHandle, options: LoadOptions) -> JobResult {
    let t = Instant::now();
    let failed = |e: String| JobResult::LoadFailed(h.target, h.path.clone(), e);
    let read = match options.more_runs.is_empty() {
        true => read_one(h, &h.path, &options, (0.0, 1.0)),
        false => read_runs(h, &options),
    };
    match read {
        Ok((log, resampled, recorded, drone)) => {
            if log.len() < crate::models::MIN_SAMPLES {
                return failed(format!(
                    "{}: only {} samples, too few to work with",
                    h.path.display(),
                    log.len()
                ));
            }
            let path = h.path.clone();
            let views = other_axis_views(&log, recorded.as_deref());
            let accel = accel_log(&log, &options.accel);
            let (((omega, temp), segments), sha256) = rayon::join(
                || {
                    rayon::join(
                        || {
                            rayon::join(
                                || MinMaxPyramid::new(&log.omega_dph),
                                || MinMaxPyramid::new(&log.temp_c),
                            )
                        },
                        || Segments::of(&log),
                    )
                },
                // A campaign's runs keep their own hashes, in the log's runs.
                || match log.runs().is_empty() {
                    true => crate::files::calibration::sha256_file(&path).ok(),
                    false => None,
                },
            );
            let mut loaded = Loaded {
                path: h.path.clone(),
                options,
                log: Arc::new(log),
                lods: Arc::new(LogLods {
                    omega,
                    temp: Arc::new(temp),
                }),
                segments: Arc::new(segments),
                resampled,
                recorded,
                sha256,
                drone,
                seconds: 0.0,
                axis_views: Vec::new(),
                accel,
            };
            if !views.is_empty() {
                let first = loaded.clone();
                loaded.axis_views = std::iter::once(first)
                    .chain(views.into_iter().map(|(log, omega, recorded)| Loaded {
                        log: Arc::new(log),
                        lods: Arc::new(LogLods {
                            omega,
                            temp: loaded.lods.temp.clone(),
                        }),
                        recorded,
                        ..loaded.clone()
                    }))
                    .collect();
            }
            let seconds = t.elapsed().as_secs_f64();
            loaded.seconds = seconds;
            for v in &mut loaded.axis_views {
                v.seconds = seconds;
            }
            JobResult::Loaded(h.target, Box::new(loaded))
        }
        Err(_) if h.cancel.load(Ordering::Relaxed) => {
            JobResult::LoadCancelled(h.target, h.path.clone())
        }
        Err(e) => failed(e),
    }
}

/// One file read as the workbench reads a log: the reader, then the averaging; with the
/// averaging's words, the log as recorded when it is its bursts' means, and what a drone or
/// robot log's reader said. Progress goes from `span.0` to `span.1`.
fn read_one(
    h: &LoadHandle,
    path: &Path,
    options: &LoadOptions,
    span: (f64, f64),
) -> Result<Read, String> {
    let progress = h.progress.clone();
    let cancel = h.cancel.clone();
    // Any log driftlab reads: a CSV, or a drone or robot log told by its first bytes (the
    // gyro and temperature chosen, else its first gyro with a temperature, as every command).
    let any = crate::log::read::read_any_with_progress(
        path,
        &options.read,
        &options.instance.format_choice(),
        &|f| {
            let at = span.0 + (span.1 - span.0) * f;
            progress.store(at.to_bits(), Ordering::Relaxed);
            !cancel.load(Ordering::Relaxed)
        },
    )
    .map_err(|e| e.to_string())?;
    let log = any.log;
    let drone = any.drone.map(Arc::new);
    // Averaged before anything else, as every command does (bins, or bursts).
    let how = resample::choose(&log, options.bin_s);
    let recorded = (how == Resampling::BurstMeans).then(|| {
        let (omega, temp) = rayon::join(
            || MinMaxPyramid::new(&log.omega_dph),
            || MinMaxPyramid::new(&log.temp_c),
        );
        Arc::new(Recorded {
            segments: Segments::of(&log),
            lods: LogLods {
                omega,
                temp: Arc::new(temp),
            },
            log: log.clone(),
        })
    });
    let (log, resampled) = resample::resample(log, how).map_err(|e| e.to_string())?;
    Ok((log, resampled, recorded, drone))
}

/// A log read, its averaging's words, the log as recorded, and a drone log's reader's words.
type Read = (
    Log,
    Option<String>,
    Option<Arc<Recorded>>,
    Option<Arc<DroneLog>>,
);

/// A campaign: every run read and averaged as the first (`h.path`, then
/// [`LoadOptions::more_runs`]), each named by its file and hashed, then joined by the engine.
/// The runs are drawn as their means (a run written in bursts is not drawn behind them).
fn read_runs(h: &LoadHandle, options: &LoadOptions) -> Result<Read, String> {
    let paths: Vec<&PathBuf> = std::iter::once(&h.path).chain(&options.more_runs).collect();
    let n = paths.len() as f64;
    let mut runs = Vec::with_capacity(paths.len());
    let mut said = Vec::new();
    let mut first_drone = None;
    // Each run is named as the command line names it (by the folders that tell runs of one
    // file name apart).
    let names = crate::log::campaign::run_names(&paths);
    for (k, (path, name)) in paths.iter().zip(names).enumerate() {
        let (mut log, resampled, _, drone) =
            read_one(h, path, options, (k as f64 / n, (k + 1) as f64 / n))?;
        let sha256 = crate::files::calibration::sha256_file(path).map_err(|e| e.to_string())?;
        log.source = name;
        if let Some(r) = resampled {
            said.push(format!("{}: {r}", log.source));
        }
        first_drone = first_drone.or(drone);
        runs.push(crate::log::campaign::RunInput { log, sha256 });
    }
    let log = crate::log::campaign::join(runs).map_err(|e| e.to_string())?;
    let resampled = (!said.is_empty()).then(|| said.join("; "));
    Ok((log, resampled, None, first_drone))
}

/// Each gyro axis but the first of a log of several, as a log of its own with its rate in
/// `omega_dph` and no other axis, with the pyramid of its rate (and its bursts as recorded,
/// when the log is its bursts' means); empty for a log of one axis.
#[allow(clippy::type_complexity)]
fn other_axis_views(
    log: &Log,
    recorded: Option<&Recorded>,
) -> Vec<(Log, MinMaxPyramid, Option<Arc<Recorded>>)> {
    log.other_axes
        .par_iter()
        .map(|a| {
            let view = Log {
                omega_dph: a.omega_dph.clone(),
                axis: a.name.clone(),
                other_axes: Vec::new(),
                ..log_without_axes(log)
            };
            let omega = MinMaxPyramid::new(&view.omega_dph);
            let recorded = recorded.and_then(|r| {
                let rate = r.log.axis_rate(&a.name)?;
                let rlog = Log {
                    omega_dph: rate.to_vec(),
                    axis: a.name.clone(),
                    other_axes: Vec::new(),
                    ..log_without_axes(&r.log)
                };
                Some(Arc::new(Recorded {
                    lods: LogLods {
                        omega: MinMaxPyramid::new(&rlog.omega_dph),
                        temp: r.lods.temp.clone(),
                    },
                    segments: r.segments.clone(),
                    log: rlog,
                }))
            });
            (view, omega, recorded)
        })
        .collect()
}

/// `log` with the accelerometer columns `ask` names made axes ([`Loaded::accel`]); `None`
/// when it asks for none by name or unit and the log keeps no column named as an
/// accelerometer (a gyro's log without them).
fn accel_log(log: &Log, ask: &AccelAsk) -> Option<Result<Arc<Log>, AccelError>> {
    if ask.is_default() && !log.extra.iter().any(|c| c.is_accelerometer()) {
        return None;
    }
    let mut with = log.clone();
    Some(crate::log::accel_axes::take(&mut with, ask).map(|_| Arc::new(with)))
}

/// A copy of `log` without its rates (the fields a view of one axis shares with it).
fn log_without_axes(log: &Log) -> Log {
    Log {
        source: log.source.clone(),
        time_s: log.time_s.clone(),
        omega_dph: Vec::new(),
        temp_c: log.temp_c.clone(),
        extra: log.extra.clone(),
        axis: String::new(),
        axis_kind: crate::log::AxisKind::Gyro,
        other_axes: Vec::new(),
        info: log.info.clone(),
    }
}
