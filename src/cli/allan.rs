//! `driftlab allan`: the Allan deviation of a log's rate, with intervals and the gyro
//! read-outs (ARW, bias instability, RRW).

use super::common::{self, CliError, LogArgs};
use driftlab::judge::allan::{self, AllanDeviation, AllanOptions, Readout, TauSpacing};
use std::path::PathBuf;

/// Arguments of `allan`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The log: a chamber log (its rate column is used), or one column of rate samples.
    pub log: PathBuf,
    /// Sampling interval, s. Needed for a one-column log (its sample index times this is the
    /// time); for a log with time it overrides the median step.
    #[arg(long, value_name = "S")]
    pub tau0: Option<f64>,
    /// Every averaging factor up to N/4 instead of octaves (slow on long logs: O(N²)).
    #[arg(long)]
    pub all_tau: bool,
    /// Print one JSON object instead of the table.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub log_args: LogArgs,
}

pub fn run(a: Args) -> Result<(), CliError> {
    if let Some(t) = a.tau0 {
        allan::check_tau0(t).map_err(|e| format!("--tau0: {e}"))?;
    }
    let read_opts = a.log_args.options()?;
    let input = a.log_args.open(&a.log)?;
    let (source, rate, tau0_s) = match input.rate_series(&read_opts).map_err(|e| e.to_string())? {
        Some(series) => {
            let tau0 = a
                .tau0
                .or(a.log_args.sample_rate.map(|hz| 1.0 / hz))
                .ok_or_else(|| {
                    format!(
                        "{}: a log of one column has no time; give its sampling interval with \
                         --tau0 S (or --sample-rate HZ)",
                        series.source
                    )
                })?;
            (series.source, series.omega_dph, tau0)
        }
        None => {
            // The Allan deviation needs evenly spaced samples: a log with gaps gives its
            // longest stretch, and says so.
            let (log, note) = driftlab::log::resample::longest_segment(a.log_args.read(&input)?);
            if let Some(note) = note {
                note!("note: {}: {note}", log.source);
            }
            let step = log.nominal_dt_s();
            let tau0 = a.tau0.unwrap_or(step);
            (log.source, log.omega_dph, tau0)
        }
    };
    let opts = AllanOptions {
        tau0_s,
        spacing: if a.all_tau {
            TauSpacing::All
        } else {
            TauSpacing::Octave
        },
        ..AllanOptions::default()
    };
    if a.all_tau && rate.len() > 200_000 {
        note!(
            "warning: --all-tau on {} samples computes {} deviations of O(N) each; octave τ \
             (the default) takes a fraction of a second",
            rate.len(),
            rate.len() / 4
        );
    }
    common::status(&format!("computing the Allan deviation of {source}"));
    let dev = allan::allan(&rate, &opts).map_err(|e| format!("{source}: {e}"))?;
    if a.json {
        return common::print_json(&json(&source, &dev));
    }
    print_table(&source, &dev)
}

/// The one JSON object: columns of the curve, then the read-outs.
fn json(source: &str, d: &AllanDeviation) -> serde_json::Value {
    let col = |f: &dyn Fn(&allan::AllanPoint) -> serde_json::Value| {
        d.points.iter().map(f).collect::<Vec<_>>()
    };
    serde_json::json!({
        "source": source,
        "samples": d.samples,
        "tau0_s": d.options.tau0_s,
        "overlapping": d.options.overlapping,
        "confidence": d.options.confidence,
        "unit": "deg/h",
        "tau": col(&|p| p.tau_s.into()),
        "adev": col(&|p| p.adev.into()),
        "n": col(&|p| p.n_terms.into()),
        "adev_min": col(&|p| p.adev_min.into()),
        "adev_max": col(&|p| p.adev_max.into()),
        "alpha": col(&|p| p.alpha.into()),
        "edf": col(&|p| p.edf.into()),
        "readouts": d.readouts,
    })
}

fn print_table(source: &str, d: &AllanDeviation) -> Result<(), CliError> {
    out!(
        "{source}: overlapping Allan deviation of {} samples, tau0 = {} s, {:.1}% intervals",
        d.samples,
        common::num(d.options.tau0_s),
        d.options.confidence * 100.0
    )?;
    out!(
        "  {:>12} {:>13} {:>10} {:>13} {:>13} {:>5}",
        "tau (s)",
        "sigma (deg/h)",
        "n",
        "min",
        "max",
        "alpha"
    )?;
    let opt = |v: Option<f64>| v.map_or_else(|| "-".to_string(), |v| format!("{v:.6e}"));
    for p in &d.points {
        out!(
            "  {:>12} {:>13.6e} {:>10} {:>13} {:>13} {:>5}",
            // m·τ0 in binary can print as 0.30000000000000004; nine digits are plenty.
            driftlab::number::significant(p.tau_s, 9),
            p.adev,
            p.n_terms,
            opt(p.adev_min),
            opt(p.adev_max),
            p.alpha
        )?;
    }
    out!("  read-outs:")?;
    let r = &d.readouts;
    readout("angle random walk", &r.arw, "no -1/2 region in the curve")?;
    readout(
        "bias instability",
        &r.bias_instability,
        "the curve shows no minimum it rises from",
    )?;
    readout("rate random walk", &r.rrw, "no +1/2 region in the curve")
}

fn readout(name: &str, r: &Option<Readout>, none: &str) -> Result<(), CliError> {
    match r {
        Some(r) => out!(
            "    {name:<18} {:.6e} {:<14} {}{}",
            r.value,
            r.unit,
            r.method,
            if r.extrapolated {
                " (extrapolated)"
            } else {
                ""
            }
        ),
        None => out!("    {name:<18} none: {none}"),
    }
}
