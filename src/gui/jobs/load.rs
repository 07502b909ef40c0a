//! Reading a log off the UI thread, with progress and cancel, and the first views of it:
//! the read, then the averaging into bins the import view asks for (or one sample per burst
//! for a log written in bursts), then the pyramids the plots draw from.

use super::*;
use crate::gui::plot_items::Segments;
use crate::log::read::{DroneLog, InstanceChoice};
use crate::log::resample::{self, Resampling};

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
}

impl Loaded {
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
    let progress = h.progress.clone();
    let cancel = h.cancel.clone();
    // Any log driftlab reads: a CSV, or a drone or robot log told by its first bytes (the
    // gyro and temperature chosen, else its first gyro with a temperature, as every command).
    let result = crate::log::read::read_any_with_progress(
        &h.path,
        &options.read,
        &options.instance.format_choice(),
        &|f| {
            progress.store(f.to_bits(), Ordering::Relaxed);
            !cancel.load(Ordering::Relaxed)
        },
    );
    match result {
        Ok(any) => {
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
            let (log, resampled) = match resample::resample(log, how) {
                Ok(r) => r,
                Err(e) => return JobResult::LoadFailed(h.target, h.path.clone(), e.to_string()),
            };
            if log.len() < crate::models::MIN_SAMPLES {
                return JobResult::LoadFailed(
                    h.target,
                    h.path.clone(),
                    format!(
                        "{}: only {} samples, too few to work with",
                        h.path.display(),
                        log.len()
                    ),
                );
            }
            let path = h.path.clone();
            let views = other_axis_views(&log, recorded.as_deref());
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
                || crate::files::calibration::sha256_file(&path).ok(),
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
        Err(e) => JobResult::LoadFailed(h.target, h.path.clone(), e.to_string()),
    }
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

/// A copy of `log` without its rates (the fields a view of one axis shares with it).
fn log_without_axes(log: &Log) -> Log {
    Log {
        source: log.source.clone(),
        time_s: log.time_s.clone(),
        omega_dph: Vec::new(),
        temp_c: log.temp_c.clone(),
        extra: log.extra.clone(),
        axis: String::new(),
        other_axes: Vec::new(),
        info: log.info.clone(),
    }
}
