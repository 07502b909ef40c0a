//! `driftlab simulate`: write a simulated chamber log.

use super::common::CliError;
use clap::builder::{PossibleValue, PossibleValuesParser};
use driftlab::log::ingest::{RateUnit, TimeUnit};
use driftlab::sim::{
    self, AccelUnit, CsvDialect, DialectPreset, HostJitter, Logging, RateNames, SimOptions,
};
use std::path::{Path, PathBuf};

/// Arguments of `simulate`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Test profile (`--help` describes each, `--list` too).
    #[arg(long, default_value = "calibration", value_parser = profile_parser())]
    pub profile: String,
    /// Random seed: the same seed gives the same log on every machine.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Write the noise alone: the same run (same seed, same noise samples, same temperatures
    /// and channels) with every deterministic drift term zero, the simulator's noise floor.
    #[arg(long)]
    pub noise_only: bool,
    /// Where to write the log (CSV).
    #[arg(long, short, required_unless_present_any = ["list", "campaign"])]
    pub out: Option<PathBuf>,
    /// List the profiles and the campaigns and exit.
    #[arg(long)]
    pub list: bool,
    /// Simulate a campaign instead of one profile: several runs of one gyro, each with its
    /// own program, seed and turn-on offset, written to --out-dir as CAMPAIGN-RUN.csv.
    #[arg(
        long,
        value_name = "NAME",
        requires = "out_dir",
        value_parser = campaign_parser(),
        conflicts_with_all = [
            "profile", "seed", "noise_only", "out", "axes", "accel", "rate_hz", "gaps",
            "bursts", "jitter", "accel_unit",
        ],
    )]
    pub campaign: Option<String>,
    /// Folder the runs of --campaign are written to (made if missing).
    #[arg(long, value_name = "DIR", requires = "campaign")]
    pub out_dir: Option<PathBuf>,
    /// Gyro axes of the unit, 1 to 3 (x, y, z): one thermal field, each axis with its own drift
    /// constants (other signs and sizes) and its own noise; x is the single gyro. Not for
    /// laser-gyro.
    #[arg(long, value_name = "N")]
    pub axes: Option<usize>,
    /// Three accelerometers on the housing (acc_x_g.. or ax_g..), reading gravity (0, 0, 1 g)
    /// with a small thermal sensitivity. Not for laser-gyro.
    #[arg(long)]
    pub accel: bool,
    /// Sampling rate of the log, Hz (default: the profile's, 1 Hz). A whole multiple is the
    /// same run sampled faster: the same thermal state and drift at the profile's instants,
    /// and the noise averaged over each second equal to the 1 Hz run's.
    #[arg(long, value_name = "HZ")]
    pub rate_hz: Option<f64>,
    /// A logger outage: no sample from START_S for DURATION_S seconds (repeatable).
    #[arg(long = "gap", value_name = "START_S:DURATION_S")]
    pub gaps: Vec<sim::Gap>,
    /// Log in bursts: ON_S seconds at the start of every EVERY_S seconds (e.g. 10:120).
    #[arg(long, value_name = "ON_S:EVERY_S")]
    pub bursts: Option<sim::Bursts>,
    /// Time stamps of a host reading the samples in batches (2 ms a sample, waits of 1-25 ms,
    /// now and then a stall up to 0.5 s); the true sampling stays regular.
    #[arg(long)]
    pub jitter: bool,
    /// Write the temperature as a raw int16 register, temp_raw_int16 (T = counts/340 + 36.53
    /// °C), followed by the real one as temp_C_est.
    #[arg(long)]
    pub raw_temp_col: bool,
    /// Column names, units and separators: driftlab (time_s,omega_dph,temp_c,...; default) or
    /// stand (time_ms;gx_dps;gy_dps;gz_dps;... in deg/s, decimal comma, a # line naming the
    /// stand). The options below change one thing of it.
    #[arg(long, value_name = "driftlab|stand")]
    pub dialect: Option<DialectPreset>,
    /// Rate column names: omega (omega_dph), g (gx_dps), w (wx_dps) or gyro (gyro_x_dps).
    #[arg(long, value_name = "omega|g|w|gyro")]
    pub rate_names: Option<RateNames>,
    /// Unit of the rate columns: dph (deg/h), dps (deg/s) or rad/s.
    #[arg(long, value_name = "UNIT")]
    pub rate_unit: Option<RateUnit>,
    /// Unit of the time column: s or ms.
    #[arg(long, value_name = "s|ms")]
    pub time_unit: Option<TimeUnit>,
    /// Field separator: comma, semicolon or tab.
    #[arg(long, value_name = "comma|semicolon|tab", value_parser = sim::parse_separator)]
    pub separator: Option<char>,
    /// Decimal mark: point or comma.
    #[arg(long, value_name = "point|comma", value_parser = sim::parse_decimal_mark)]
    pub decimal_mark: Option<bool>,
    /// Unit of the accelerometer columns: g (acc_x_g, the default), mg (acc_x_mg) or m/s2
    /// (acc_x_m_s2, as a flight controller logs them).
    #[arg(long, value_name = "g|mg|m/s2")]
    pub accel_unit: Option<AccelUnit>,
}

/// The built-in profiles as the values `--profile` accepts, each with its description.
fn profile_parser() -> PossibleValuesParser {
    PossibleValuesParser::new(sim::profile_names().iter().map(|&name| {
        let help = sim::profile(name)
            .map(|p| p.description)
            .unwrap_or_default();
        PossibleValue::new(name).help(help)
    }))
}

/// The built-in campaigns as the values `--campaign` accepts, each with its description.
fn campaign_parser() -> PossibleValuesParser {
    PossibleValuesParser::new(sim::campaign_names().iter().map(|&name| {
        let help = sim::campaign(name)
            .map(|c| c.description)
            .unwrap_or_default();
        PossibleValue::new(name).help(help)
    }))
}

pub fn run(a: Args) -> Result<(), CliError> {
    if a.list {
        for name in sim::profile_names() {
            if let Some(p) = sim::profile(name) {
                out!("{name:<14} {}", p.description)?;
            }
        }
        for name in sim::campaign_names() {
            if let Some(c) = sim::campaign(name) {
                out!("{name:<14} (campaign) {}", c.description)?;
            }
        }
        return Ok(());
    }
    let mut profile = sim::profile(&a.profile).ok_or_else(|| {
        format!(
            "unknown profile \"{}\"; profiles: {}",
            a.profile,
            sim::profile_names().join(", ")
        )
    })?;
    let mut dialect = a.dialect.unwrap_or(DialectPreset::Driftlab).dialect();
    if let Some(names) = a.rate_names {
        dialect.rate_names = names;
    }
    if let Some(unit) = a.rate_unit {
        dialect.rate_unit = unit;
    }
    if let Some(unit) = a.time_unit {
        dialect.time_unit = unit;
    }
    if let Some(sep) = a.separator {
        dialect.separator = sep;
    }
    if let Some(comma) = a.decimal_mark {
        dialect.decimal_comma = comma;
    }
    dialect.raw_temp_register = a.raw_temp_col;
    if let Some(unit) = a.accel_unit {
        dialect.accel_unit = unit;
    }
    if let (Some(name), Some(dir)) = (&a.campaign, &a.out_dir) {
        return write_campaign(name, dir, &dialect);
    }
    let Some(out) = a.out else {
        return Err("--out is required".into());
    };
    super::common::refuse_outputs(&[("--out", &out)], &super::common::Reads::default())?;
    if let Some(n) = a.axes {
        profile = profile.with_axes(n)?;
    }
    if a.accel {
        profile = profile.with_accelerometers()?;
    }
    if let Some(unit) = a.accel_unit
        && profile.accelerometers.is_empty()
    {
        return Err(format!(
            "--accel-unit {unit}: profile {} has no accelerometers to write (give --accel, or \
             the profile mems-imu)",
            a.profile
        )
        .into());
    }
    let options = SimOptions {
        noise_only: a.noise_only,
        logging: Logging {
            rate_hz: a.rate_hz,
            gaps: a.gaps,
            bursts: a.bursts,
            jitter: a.jitter.then(HostJitter::default),
        },
        dialect,
    };

    let bar = super::common::progress_bar(&format!("simulating {}", a.profile));
    let rows = sim::write_simulated_csv(&profile, a.seed, &options, &out, &|f| {
        if let Some(b) = &bar {
            b.set_position((f * 1000.0) as u64);
        }
    });
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let rows = rows.map_err(|e| e.to_string())?;
    note!(
        // The program's length: gaps may cut the log's own start or end.
        "{rows} samples of the {:.2}-h program{} written to {}",
        profile.duration_s() / 3600.0,
        if a.noise_only { ", noise only," } else { "" },
        out.display()
    );
    Ok(())
}

/// `simulate --campaign NAME --out-dir DIR`: every run of the campaign, written by the one CSV
/// writer as `DIR/NAME-RUN.csv`.
fn write_campaign(name: &str, dir: &Path, dialect: &CsvDialect) -> Result<(), CliError> {
    let campaign = sim::campaign(name).ok_or_else(|| {
        format!(
            "unknown campaign \"{name}\"; campaigns: {}",
            sim::campaign_names().join(", ")
        )
    })?;
    let paths: Vec<PathBuf> = campaign
        .runs
        .iter()
        .map(|r| dir.join(campaign.file_name(r)))
        .collect();
    if dir.exists() && !dir.is_dir() {
        return Err(CliError::Message(format!(
            "--out-dir {}: is a file, not a folder (the runs are written into a folder, made \
             when missing)",
            super::common::shown(&dir.display().to_string())
        )));
    }
    let outputs: Vec<(&str, &Path)> = paths.iter().map(|p| ("--out-dir", p.as_path())).collect();
    super::common::refuse_outputs(&outputs, &super::common::Reads::default())?;
    std::fs::create_dir_all(dir).map_err(|e| format!("--out-dir {}: {e}", dir.display()))?;
    let bar = super::common::progress_bar(&format!("simulating {name}"));
    let runs = sim::simulate_campaign(&campaign);
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    for (run, path) in runs.iter().zip(&paths) {
        run.write_csv_as(path, dialect)
            .map_err(|e| format!("{}: {e}", path.display()))?;
        note!(
            "{} samples of run {} ({:.2} h, turn-on offset {} °/h) written to {}",
            run.len(),
            run.campaign.as_ref().map_or("", |c| c.run.as_str()),
            (run.len().saturating_sub(1)) as f64 / run.sample_rate_hz / 3600.0,
            run.turn_on_offset_dph(),
            path.display()
        );
    }
    Ok(())
}
