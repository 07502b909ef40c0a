//! `driftlab inspect`: what driftlab reads in a log.

use super::common::{self, CliError, LogArgs};
use driftlab::models::recipe::Recipe;
use driftlab::models::vakhrameev::{self, Prepared};
use std::path::PathBuf;

/// Arguments of `inspect`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The log to look at.
    pub log: PathBuf,
    /// Print as JSON.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub log_args: LogArgs,
}

pub fn run(a: Args) -> Result<(), CliError> {
    // The sampling as recorded; the plateaus and rates as the other commands see the log
    // (a burst log reduced to its bursts' means).
    let input = a.log_args.open(&a.log)?;
    let recorded = a.log_args.read_recorded(&input)?;
    let timing = recorded.timing();
    let sampling = timing.describe(&recorded.time_s);
    let reduced = timing.bursts.is_some() && a.log_args.bin.is_none();
    let log = if reduced {
        driftlab::log::resample::prepare(recorded, None)?.0
    } else {
        recorded
    };
    let recipe = Recipe::default();
    let prepared = Prepared::new(&log, &recipe);
    let ranges = vakhrameev::plateau_ranges(&log, &prepared, &recipe);
    let plateaus = vakhrameev::plateau_stats(&log, &ranges);
    let (tmin, tmax) = log
        .temp_c
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let rate_max = prepared
        .deriv
        .tdot
        .iter()
        .fold(0.0f64, |a, v| a.max(v.abs()))
        * 60.0;
    let dt = log.nominal_dt_s();
    if a.json {
        return common::print_json(&serde_json::json!({
            "source": log.source,
            "info": log.info,
            "samples": log.len(),
            "sampling": sampling,
            "step_s": dt,
            "sample_rate_hz": 1.0 / dt,
            "duration_s": log.duration_s(),
            "temp_min_c": tmin,
            "temp_max_c": tmax,
            "max_abs_rate_c_per_min": rate_max,
            "extra_channels": log.extra.iter().map(|c| &c.name).collect::<Vec<_>>(),
            "plateaus": plateaus,
        }));
    }
    let i = &log.info;
    out!("{}", log.source)?;
    out!(
        "  format: separator {:?}, decimal {}, {}",
        i.delimiter,
        if i.decimal_comma { "comma" } else { "point" },
        if i.has_header {
            "header row"
        } else {
            "no header"
        }
    )?;
    out!("  columns:")?;
    for c in &i.columns {
        let unit = if c.unit.is_empty() {
            String::new()
        } else {
            format!(" [{}]", c.unit)
        };
        out!("    {:>2}  {:<24} {:?}{unit}", c.index, c.name, c.role)?;
    }
    out!(
        "  {} samples ({} rows read), step {} s ({} Hz), duration {} h",
        log.len(),
        i.rows_read,
        common::num(dt),
        common::num(1.0 / dt),
        common::fixed(log.duration_s() / 3600.0, 2)
    )?;
    for line in &sampling {
        out!("  {line}")?;
    }
    if reduced {
        out!(
            "  the other commands reduce each burst to its mean time, rate and temperature \
             (--bin S chooses bins instead)"
        )?;
    }
    out!(
        "  temperature {} .. {} degC, fastest |Tdot| {} degC/min",
        common::fixed(tmin, 3),
        common::fixed(tmax, 3),
        common::fixed(rate_max, 3)
    )?;
    out!("  plateaus found ({}):", plateaus.len())?;
    // A week-long log can hold thousands: the first and last ones say enough on a terminal
    // (`--json` lists every one).
    const SHOWN: usize = 10;
    let line = |p: &driftlab::signal::plateau::PlateauStats| {
        out!(
            "    {:>9} .. {:>9} s   T {:>8} degC   Omega {:>9} deg/h   std {}   {} samples",
            common::fixed(p.range.start_s, 0),
            common::fixed(p.range.end_s, 0),
            common::fixed(p.temp_c, 3),
            common::fixed(p.omega_dph, 4),
            common::fixed(p.omega_std_dph, 4),
            p.samples
        )
    };
    if plateaus.len() <= 2 * SHOWN {
        plateaus.iter().try_for_each(line)?;
    } else {
        plateaus[..SHOWN].iter().try_for_each(line)?;
        out!(
            "    ... {} more (--json lists them all) ...",
            plateaus.len() - 2 * SHOWN
        )?;
        plateaus[plateaus.len() - SHOWN..]
            .iter()
            .try_for_each(line)?;
    }
    if i.problems.is_empty() {
        out!("  problems: none")?;
    } else {
        out!("  problems:")?;
        for p in &i.problems {
            if p.line == 0 {
                out!("    {}", p.message)?;
            } else {
                out!("    line {}: {}", p.line, p.message)?;
            }
        }
    }
    Ok(())
}
