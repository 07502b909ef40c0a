//! `driftlab export`: a calibration for a gyro's processor, as a C header or lookup tables.

use super::common::CliError;
use driftlab::export::firmware::{self, ExportOptions, Format};
use driftlab::files::calibration;
use std::io::Write;
use std::path::PathBuf;

/// Arguments of `export`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The calibration (JSON) made by `driftlab calibrate`.
    pub calibration: PathBuf,
    /// c-header: one self-contained C99 header with the coefficients and the streaming corrector
    /// (init/reset/push), correcting bit for bit as driftlab does; csv-table: K0(T), K1±(Ṫ) and
    /// K2±(T̈) tabulated over their fitted ranges, to interpolate linearly (a regression model:
    /// its coefficients with standard errors, ranges and settings as comments).
    #[arg(long, value_name = "c-header|csv-table")]
    pub format: Format,
    /// Where to write (atomically); standard output when not given.
    #[arg(long, short, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Rows of each table, end points included (csv-table of a Vakhrameev calibration only).
    #[arg(long, value_name = "N", default_value_t = ExportOptions::default().points)]
    pub points: usize,
}

pub fn run(a: Args) -> Result<(), CliError> {
    if let Some(out) = &a.out {
        super::common::refuse_overwriting("--out", out, &[("the calibration", &a.calibration)])?;
    }
    let model = calibration::load_model(&a.calibration).map_err(|e| e.to_string())?;
    let opts = ExportOptions { points: a.points };
    let text = firmware::export_model(&model, a.format, &opts)
        .map_err(|e| format!("{}: {e}", a.calibration.display()))?;
    match &a.out {
        Some(path) => {
            driftlab::files::atomic::write_bytes(path, text.as_bytes())
                .map_err(|e| format!("{}: {e}", path.display()))?;
            let what = if model.gyro_id().is_empty() {
                model.source().name.clone()
            } else {
                model.gyro_id().to_string()
            };
            note!("{} of {what} written to {}", a.format, path.display());
        }
        None => {
            let mut out = std::io::stdout().lock();
            out.write_all(text.as_bytes())
                .and_then(|()| out.flush())
                .map_err(super::common::stdout_error)?;
        }
    }
    Ok(())
}
