//! driftlab: calibration of the thermal drift of gyroscopes.
//!
//! The engine behind the workbench and the command line. It reads chamber test logs, finds the
//! temperature plateaus, differentiates the temperature, fits the Vakhrameev model
//! `Ω = K0(T) + K1±(Ṫ)·Ṫ + K2±(T̈)·T̈` or a regression model of the other papers, corrects logs in
//! batch or one sample at a time, compares models on held-out logs, and reports: Allan
//! deviation, figures and HTML, C for the gyro's processor. Nothing here depends on a user
//! interface. The method is described in `docs/method.md`.
//!
//! The folders follow the flow, top to bottom:
//!
//! | module | stage |
//! |---|---|
//! | [`log`] | a test log and its readers ([`read_path`] for any format, [`log::ingest`] the CSV reader, [`log::formats`] the drone and robot logs) |
//! | [`signal`] | moving averages, derivatives, plateaus, the plot pyramid |
//! | [`models`] | every model: the shared face, presets, recipe, Vakhrameev's, the regressions, the curve approximations |
//! | [`judge`] | figures of merit, Allan deviation, models compared on held-out logs |
//! | [`files`] | calibration and session files, the corrected log, atomic writes |
//! | [`export`] | the C header and tables for firmware, the test report |
//! | [`refit`] | the workbench's refit after an edit: the one pipeline with its stages kept |
//! | [`sim`] | the thermal-chamber simulator behind the sample logs and the tests |
//!
//! From a log to corrected figures:
//!
//! ```
//! use driftlab::{MeritOptions, ModelChoice, Preset, ReadOptions, Recipe};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let path = concat!(env!("CARGO_MANIFEST_DIR"), "/sample_logs/calibration.csv");
//! let log = driftlab::read_path(path.as_ref(), &ReadOptions::default())?;
//!
//! // Every choice of the calibration, checked once and carried checked; then any model
//! // fitted the same way.
//! let recipe = Recipe::default().checked()?;
//! let choice = ModelChoice::Preset(Preset::Vakhrameev);
//! let model = driftlab::fit(&log, &choice, &recipe)?;
//!
//! // Corrected in batch, and judged raw against corrected.
//! let correction = model.correct(&log)?;
//! let eval = driftlab::Evaluation::of_correction(&log, &correction, &MeritOptions::default());
//! let c = &eval.comparison;
//! println!(
//!     "peak-to-peak {:.3} -> {:.3} deg/h ({:.1}x)",
//!     c.raw.p2p_dph, c.corrected.p2p_dph, c.p2p_ratio
//! );
//! assert!(c.p2p_ratio > 3.0);
//!
//! // The same correction one sample at a time, as the gyro's processor runs it.
//! let mut stream = model.corrector_for(1.0)?;
//! let first = stream.push(log.time_s[0], log.omega_dph[0], log.temp_c[0], f64::NAN, &[]);
//! assert!(first.omega_cor_dph.is_finite());
//! # Ok(())
//! # }
//! ```

pub mod error;
pub mod export;
pub mod files;
pub mod judge;
pub mod log;
pub mod lot;
pub mod models;
pub mod number;
pub mod refit;
pub mod signal;
pub mod sim;
pub mod text;

/// The desktop workbench (feature `gui`): a face over the engine, holding no calculation.
/// Public for the `driftlab` binary and the workbench's tests only: not the library's API.
#[cfg(feature = "gui")]
#[doc(hidden)]
pub mod gui;

pub use error::{Error, Result};
pub use judge::metrics::{Comparison, Evaluation, MeritOptions};
pub use log::Log;
pub use log::ingest::ReadOptions;
pub use log::read::read_path;
pub use models::{
    AxisPlan, Calibrated, CheckedRecipe, DriftModel, ModelChoice, Preset, Recipe, UnitCalibration,
    calibrate, fit,
};
