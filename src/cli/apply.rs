//! `driftlab apply`: correct a log with a calibration and write the result as CSV.

use super::common::{self, LogArgs};
use driftlab::calfile;
use std::path::PathBuf;

/// Arguments of `apply`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The calibration (JSON) made by `driftlab calibrate`.
    pub calibration: PathBuf,
    /// The log to correct.
    pub log: PathBuf,
    /// Where to write `time_s,omega_raw_dph,omega_pred_dph,omega_cor_dph,temp_c`.
    #[arg(long, short)]
    pub out: PathBuf,
    #[command(flatten)]
    pub log_args: LogArgs,
}

pub fn run(a: Args) -> Result<(), String> {
    let cal = calfile::load(&a.calibration).map_err(|e| e.to_string())?;
    let log = a.log_args.read(&a.log)?;
    let c = cal.correct(&log);
    let bar = common::progress_bar(&format!("writing {}", a.out.display()));
    let n = log.len();
    driftlab::atomic::write_with(&a.out, |w| {
        w.write_all(b"time_s,omega_raw_dph,omega_pred_dph,omega_cor_dph,temp_c\n")?;
        let mut line = String::with_capacity(128);
        for i in 0..n {
            line.clear();
            use std::fmt::Write as _;
            let _ = writeln!(
                line,
                "{},{},{},{},{}",
                log.time_s[i], log.omega_dph[i], c.pred_dph[i], c.cor_dph[i], log.temp_c[i]
            );
            w.write_all(line.as_bytes())?;
            if i % 100_000 == 0
                && let Some(b) = &bar
            {
                b.set_position((i as f64 / n as f64 * 1000.0) as u64);
            }
        }
        Ok(())
    })
    .map_err(|e| format!("{}: {e}", a.out.display()))?;
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    if c.outside_fraction > 0.0 {
        eprintln!(
            "note: {:.1}% of the samples lie outside the calibrated ranges of T, Tdot or Tddot; \
             the coefficients were held at their edge values there",
            c.outside_fraction * 100.0
        );
    }
    eprintln!("{n} samples corrected, written to {}", a.out.display());
    Ok(())
}
