//! `driftlab inspect`: what driftlab reads in a log.

use super::common::{self, CliError, LogArgs};
use super::log_source;
use driftlab::log::ColumnRole;
use driftlab::log::accel_axes::{self, AccelAsk};
use driftlab::log::formats::{self, InstanceSummary};
use driftlab::log::ingest::Input;
use driftlab::log::read::{self, TempFrom};
use driftlab::models::recipe::{PlateauChoice, Recipe};
use driftlab::signal::plateau::DetectOptions;
use driftlab::signal::summary::{SummaryOptions, describe_step, summarise};
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

/// What a drone or robot log holds besides the gyro inspected.
struct Drone {
    format: formats::Format,
    instances: Vec<InstanceSummary>,
    chosen: usize,
}

fn print_instances(
    source: &str,
    format: formats::Format,
    instances: &[InstanceSummary],
) -> Result<(), CliError> {
    out!(
        "{}: {format} log, {} gyro instance(s):",
        source,
        instances.len()
    )?;
    for s in instances {
        out!("  {}", log_source::in_flags(&s.line()))?;
        let accel = if s.has_accel {
            ", accel x y z (m/s^2)"
        } else {
            ""
        };
        out!("      axes: gyro x y z (rad/s){accel}")?;
    }
    Ok(())
}

/// A drone or robot log: its instances listed, then the chosen gyro as a log (`None` for a
/// CSV). When no gyro can be chosen as asked, the instances are still listed (what an engineer needs to choose
/// one) before the error says why.
fn drone(a: &Args) -> Result<Option<(driftlab::Log, Drone)>, CliError> {
    let opts = a.log_args.options()?;
    let Some(format) = log_source::check(&a.log_args, &a.log, &opts)? else {
        return Ok(None);
    };
    if a.log_args.format.temp_from == Some(TempFrom::None) {
        return Err(format!(
            "{}: --temp-from none leaves the log without a temperature: inspect lists every \
             instance's temperatures without it",
            a.log.display()
        )
        .into());
    }
    let rec = formats::read_path(&a.log).map_err(|e| log_source::in_flags(&e.to_string()))?;
    let instances = rec.summaries();
    let mut any = match read::from_recording(&rec, false, &a.log_args.format.choice()) {
        Ok(any) => any,
        Err(e) => {
            if a.json {
                common::print_json(&serde_json::json!({
                    "source": rec.source,
                    "format": format,
                    "instances": instances,
                    "problems": rec.problems,
                    "chosen": null,
                    "why_none": log_source::in_flags(&e.to_string()),
                }))?;
            } else {
                print_instances(&rec.source, format, &instances)?;
                for p in &rec.problems {
                    out!("  problem: {}", log_source::in_flags(&p.to_string()))?;
                }
            }
            return Err(log_source::in_flags(&e.to_string()).into());
        }
    };
    drop(rec);
    let d = any
        .drone
        .ok_or(CliError::from("a drone log read as a CSV"))?;
    if !a.json {
        print_instances(&any.log.source, format, &d.instances)?;
    }
    log_source::problems_in_flags(&mut any.log);
    log_source::print_notes(&d, &any.log);
    // As recorded, unless --bin asks for bins (as `LogArgs::read_recorded`).
    let log = match a.log_args.bin {
        Some(_) => a.log_args.resampled(any.log)?,
        None => any.log,
    };
    Ok(Some((
        log,
        Drone {
            format,
            instances: d.instances,
            chosen: d.chosen,
        },
    )))
}

pub fn run(a: Args) -> Result<(), CliError> {
    a.log_args.refuse_accel("inspect")?;
    // The sampling as recorded; the plateaus and rates as the other commands see the log
    // (a burst log reduced to its bursts' means). A drone or robot log is read from its file.
    let input = a.log_args.open(&a.log)?;
    let found = match &input {
        Input::Path(_) => drone(&a)?,
        Input::Bytes { .. } => None,
    };
    let (recorded, drone) = match found {
        Some((log, d)) => (log, Some(d)),
        None => (a.log_args.read_recorded(&input)?, None),
    };
    let timing = recorded.timing();
    let sampling = timing.describe(&recorded.time_s);
    let reduced = timing.bursts.is_some() && a.log_args.bin.is_none();
    let recorded_dt = timing.nominal_dt_s;
    let recorded_len = recorded.len();
    let log = if reduced {
        driftlab::log::resample::prepare(recorded, None)?.0
    } else {
        recorded
    };
    // What a calibration with the accelerometers would meet in their columns, by its rule.
    let accel_problems = accelerometer_problems(&log);
    let summary = summarise(&log, &summary_options(&Recipe::default()));
    let (tmin, tmax) = (summary.temp_min_c, summary.temp_max_c);
    let rate_max = summary.max_abs_rate_c_per_min;
    let plateaus = summary.plateaus;
    let dt = summary.step_s;
    let axes = gyro_axes(&log);
    if a.json {
        return common::print_json(&serde_json::json!({
            "source": log.source,
            "info": log.info,
            "samples": log.len(),
            "sampling": sampling,
            "step_s": dt,
            "sample_rate_hz": dt.map(|d| 1.0 / d),
            "duration_s": log.duration_s(),
            "temp_min_c": tmin,
            "temp_max_c": tmax,
            "max_abs_rate_c_per_min": rate_max,
            // What the summary could not find, and why (the reason beside each null above);
            // the reading's own problems are `info.problems`.
            "problems": summary.problems,
            "accelerometer_problems": accel_problems,
            "extra_channels": log.extra.iter().map(|c| &c.name).collect::<Vec<_>>(),
            "accelerometers": log
                .extra
                .iter()
                .filter(|c| c.is_accelerometer())
                .map(|c| serde_json::json!({ "name": c.name, "unit": c.unit }))
                .collect::<Vec<_>>(),
            "axis": log.axis,
            "other_axes": log.other_axes.iter().map(|x| &x.name).collect::<Vec<_>>(),
            "gyro_axes": axes,
            "plateaus": plateaus,
            "format": drone.as_ref().map(|d| d.format),
            "instances": drone.as_ref().map(|d| &d.instances),
            "chosen": drone.as_ref().map(|d| d.chosen),
        }));
    }
    let i = &log.info;
    match &drone {
        Some(d) => out!(
            "{}: gyro {} of the {} log, as read:",
            log.source,
            d.chosen,
            d.format
        )?,
        None => {
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
        }
    }
    out!("  columns:")?;
    for c in &i.columns {
        let unit = if c.unit.is_empty() {
            String::new()
        } else {
            format!(" [{}]", c.unit)
        };
        let accel = if c.role == ColumnRole::Extra && c.is_accelerometer() {
            " (accelerometer, kept)"
        } else {
            ""
        };
        out!(
            "    {:>2}  {:<24} {:?}{unit}{accel}",
            c.index,
            c.name,
            c.role
        )?;
    }
    if !log.other_axes.is_empty() {
        let listed: Vec<String> = axes.iter().map(GyroAxis::describe).collect();
        out!("  gyro axes: {}", listed.join(", "))?;
        let some = axes
            .iter()
            .take(2)
            .map(|x| x.name.as_str())
            .collect::<Vec<_>>()
            .join(",");
        // A flight log's columns are the format's own: one axis alone is one of `--axes`.
        let alone = if drone.is_some() {
            "--axes NAME"
        } else {
            "--rate-col NAME"
        };
        let most = driftlab::models::unit::MAX_UNIT_AXES;
        if axes.len() > most {
            out!(
                "    calibrate fits at most {most} axes into one unit calibration, and this log \
                 has {}: choose them (--axes {some}), or one alone ({alone});",
                axes.len()
            )?;
        } else {
            out!(
                "    calibrate fits every axis into one unit calibration (--axes {some} chooses \
                 some, {alone} one alone);"
            )?;
        }
        out!(
            "    evaluate, apply and report take every axis of a unit calibration; allan and \
             compare analyse every axis (--axes chooses)"
        )?;
    }
    out!(
        "  {recorded_len} samples ({} rows read), {}, duration {} h",
        i.rows_read,
        describe_step(recorded_len, recorded_dt),
        common::fixed(log.duration_s() / 3600.0, 2)
    )?;
    for line in &sampling {
        out!("  {line}")?;
    }
    if reduced {
        out!(
            "  the other commands reduce each burst to its mean time, rate and temperature: \
             {} samples, step {} s (--bin S chooses bins instead); the plateaus below are theirs",
            log.len(),
            common::num(log.nominal_dt_s())
        )?;
    }
    out!(
        "  temperature {} .. {} degC, fastest |Tdot| {}",
        common::fixed(tmin, 3),
        common::fixed(tmax, 3),
        rate_max.map_or("not computed (see problems)".to_string(), |r| format!(
            "{} degC/min",
            common::fixed(r, 3)
        ))
    )?;
    out!("  plateaus found ({}):", plateaus.len())?;
    // A week-long log can hold thousands: the first and last ones say enough on a terminal
    // (`--json` lists every one).
    const SHOWN: usize = 10;
    let line = |p: &driftlab::signal::plateau::PlateauStats| {
        out!(
            "    {:>9} .. {:>9} s   T {:>8} degC   Omega {:>9} deg/h   std {}   {} samples",
            driftlab::number::fixed_stamp(p.range.start_s),
            driftlab::number::fixed_stamp(p.range.end_s),
            common::fixed(p.temp_c, 3),
            common::fixed(p.omega_dph, 4),
            p.omega_std_dph
                .map_or("n/a".to_string(), |s| common::fixed(s, 4)),
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
    if i.problems.is_empty() && summary.problems.is_empty() && accel_problems.is_empty() {
        out!("  problems: none")?;
    } else {
        out!("  problems:")?;
        for p in &summary.problems {
            out!("    {p}")?;
        }
        for p in &i.problems {
            let at = if drone.is_some() { "sample" } else { "line" };
            if p.line == 0 {
                out!("    {}", p.message)?;
            } else {
                out!("    {at} {}: {}", p.line, p.message)?;
            }
        }
        for p in &accel_problems {
            out!("    {p}")?;
        }
    }
    Ok(())
}

/// What making the accelerometer columns of `log` axes would tell (`calibrate --accel`'s rule,
/// [`accel_axes::check`]): readings no accelerometer gives, or why the columns cannot be
/// axes; each a sentence naming the columns.
fn accelerometer_problems(log: &driftlab::Log) -> Vec<String> {
    match accel_axes::check(log, &AccelAsk::default()) {
        Ok(problems) => problems
            .into_iter()
            .map(|p| format!("accelerometers: {}", p.message))
            .collect(),
        Err(e) => vec![format!(
            "accelerometers: calibrate --accel would refuse them: {}",
            super::accel::in_words(&e)
        )],
    }
}

/// The summary's settings from a recipe: its derivative settings, and its detector (the
/// default detector when the recipe gives its plateaus by hand).
fn summary_options(recipe: &Recipe) -> SummaryOptions {
    SummaryOptions {
        temp_smoothing_s: recipe.temp_smoothing_s,
        step_h_s: recipe.step_h_s,
        plateaus: match &recipe.plateaus {
            PlateauChoice::Auto(o) => *o,
            PlateauChoice::Manual { .. } => DetectOptions::default(),
        },
    }
}

/// One gyro axis of a log as `inspect` lists it.
#[derive(serde::Serialize)]
struct GyroAxis {
    /// The axis's name (`gx`): what `--axes` and a unit calibration call it.
    name: String,
    /// The column it is read from (`gx_dps`), empty when the reader recorded none.
    column: String,
    /// The unit the column was read in (`deg/s`), converted to deg/h; empty when not known.
    unit: String,
}

impl GyroAxis {
    fn describe(&self) -> String {
        let unit = if self.unit.is_empty() {
            String::new()
        } else {
            format!(" [{}]", self.unit)
        };
        if self.column.is_empty() || self.column == self.name {
            format!("{}{unit}", self.name)
        } else {
            format!("{}{unit} (column {})", self.name, self.column)
        }
    }
}

/// Every gyro axis of `log` (the one in `omega_dph` first) with the column and unit it was
/// read from: the axes paired with their columns once (a log of 400 rate columns took minutes
/// when each axis named every column again).
fn gyro_axes(log: &driftlab::Log) -> Vec<GyroAxis> {
    let pairs = log.axis_columns();
    let rates: std::collections::HashMap<&str, &driftlab::log::ColumnInfo> = log
        .info
        .columns
        .iter()
        .filter(|c| matches!(c.role, ColumnRole::Rate | ColumnRole::OtherAxis))
        .map(|c| (c.name.as_str(), c))
        .collect();
    let by_axis: std::collections::HashMap<&str, &str> = pairs
        .iter()
        .map(|(axis, column)| (axis.as_str(), column.as_str()))
        .collect();
    log.axis_names()
        .into_iter()
        .map(|name| {
            let column = by_axis
                .get(name.as_str())
                .and_then(|c| rates.get(c))
                .or_else(|| rates.get(name.as_str()));
            GyroAxis {
                column: column.map(|c| c.name.clone()).unwrap_or_default(),
                unit: column.map(|c| c.unit.clone()).unwrap_or_default(),
                name,
            }
        })
        .collect()
}
