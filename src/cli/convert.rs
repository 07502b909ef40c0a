//! `driftlab convert`: one gyro of a drone or robot log (PX4 ULog, ArduPilot DataFlash, ROS 1
//! bag, MCAP) as a CSV the other commands read with no options.

use super::common::{self, CliError};
use super::log_source::in_flags;
use driftlab::log::formats::{self, TempFrom};
use driftlab::log::kept_samples::kept_samples;
use std::path::PathBuf;

/// Arguments of `convert`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The log: PX4 ULog, ArduPilot DataFlash .bin, ROS 1 bag or MCAP (told by its bytes).
    pub log: PathBuf,
    /// Where to write the CSV (atomically): time_s, gyro_x/y/z_rad_s, temp_c, then
    /// accel_x/y/z_m_s2 when the gyro has an accelerometer.
    #[arg(long, short, value_name = "CSV")]
    pub out: PathBuf,
    /// The gyro instance (as `inspect` lists them; default: the first whose temperature has
    /// a finite value).
    #[arg(long, value_name = "N")]
    pub gyro: Option<usize>,
    /// The temperature to write when the gyro's own is missing: accel (its accelerometer's),
    /// imu-status (PX4 vehicle_imu_status) or none (temp_c NaN); own is the default.
    #[arg(long, value_name = "own|accel|imu-status|none")]
    pub temp_from: Option<TempFrom>,
}

pub fn run(a: Args) -> Result<(), CliError> {
    let mut reads = common::Reads::default();
    reads.add("the log", &a.log);
    common::refuse_outputs(&[("--out", &a.out)], &reads)?;
    let rec = formats::read_path(&a.log).map_err(|e| in_flags(&e.to_string()))?;
    for p in &rec.problems {
        note!("{}: {}", rec.source, in_flags(&p.to_string()));
    }
    let sel = formats::select(&rec, a.gyro, a.temp_from).map_err(|e| in_flags(&e.to_string()))?;
    note!("{}", in_flags(&sel.note));
    // The samples every other command reads of this gyro: the same drops and refusals (time
    // order, stray and repeated stamps, NaN rows, temperature glitches), told the same way.
    let kept = kept_samples(&sel).map_err(|e| in_flags(&e.to_string()))?;
    for p in &kept.problems {
        // A count only when there are several and the message does not give it.
        let times = p.times();
        note!("warning: {}: {}{times}", rec.source, in_flags(&p.message));
    }
    driftlab::files::atomic::write_with(&a.out, |w| formats::write_csv(&sel, &kept.rows, w))
        .map_err(|e| format!("{}: {e}", a.out.display()))?;
    note!(
        "{} of {} written to {}",
        if kept.rows.len() == 1 {
            "1 sample".to_string()
        } else {
            format!("{} samples", kept.rows.len())
        },
        sel.instance.label,
        a.out.display()
    );
    Ok(())
}
