//! driftlab: calibration of the thermal drift of gyroscopes.
//!
//! The engine behind the workbench and the command line. It reads chamber test logs, finds the
//! temperature plateaus, differentiates the temperature, fits the Vakhrameev model
//! `Ω = K0(T) + K1±(Ṫ)·Ṫ + K2±(T̈)·T̈` or a regression model over the log's channels
//! (`regression`, `presets`), corrects logs in batch or one sample at a time, compares models
//! on held-out logs (`compare`), and reports: Allan deviation (`allan`), figures and HTML
//! (`report`), C for the gyro's processor (`firmware`). Nothing here depends on a user
//! interface.
//!
//! The flow, each step a plain function of the one before:
//!
//! ```text
//! ingest::read_path -> Log
//!   Recipe (every choice, validated once)
//!     model::fit(&Log, &Recipe) -> Calibration
//!        Calibration::correct(&Log) -> Correction      (batch)
//!        Calibration::corrector()   -> StreamCorrector (one sample at a time)
//!   metrics::FiguresOfMerit::of(...)                   (before and after)
//!   calfile::save / calfile::load                      (versioned JSON)
//!   regression::fit(&Log, &RegressionSpec) -> RegressionModel   (other models)
//!     drift_model::DriftModel: any fitted model, correct / corrector_for
//!   compare::compare(train, tests, choices, ...)       (side by side, held out)
//! ```

pub mod allan;
pub mod approx;
pub mod atomic;
pub mod calfile;
pub mod compare;
pub mod correct;
pub mod corrected_csv;
pub mod drift_model;
pub mod error;
pub mod firmware;
pub mod ingest;
pub mod live;
pub mod lod;
pub mod log;
pub mod mapping_check;
pub mod metrics;
pub mod model;
pub mod plateau;
pub mod presets;
pub mod recipe;
pub mod regression;
pub mod report;
pub mod session;
pub mod signal;
pub mod sim;

/// The desktop workbench (feature `gui`): a face over the engine, holding no calculation.
#[cfg(feature = "gui")]
pub mod gui;

pub use log::Log;
