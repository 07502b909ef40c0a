//! `driftlab simulate`: write a simulated chamber log.

use clap::builder::{PossibleValue, PossibleValuesParser};
use driftlab::sim;
use std::path::PathBuf;

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
    #[arg(long, short, required_unless_present = "list")]
    pub out: Option<PathBuf>,
    /// List the profiles and exit.
    #[arg(long)]
    pub list: bool,
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

pub fn run(a: Args) -> Result<(), String> {
    if a.list {
        for name in sim::profile_names() {
            if let Some(p) = sim::profile(name) {
                println!("{name:<14} {}", p.description);
            }
        }
        return Ok(());
    }
    let profile = sim::profile(&a.profile).ok_or_else(|| {
        format!(
            "unknown profile \"{}\"; profiles: {}",
            a.profile,
            sim::profile_names().join(", ")
        )
    })?;
    let Some(out) = a.out else {
        return Err("--out is required".into());
    };
    let bar = super::common::progress_bar(&format!("simulating {}", a.profile));
    let mut run = sim::simulate_with_progress(&profile, a.seed, &|f| {
        if let Some(b) = &bar {
            b.set_position((f * 1000.0) as u64);
        }
    });
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    if a.noise_only {
        run = run.noise_only();
    }
    run.write_csv(&out)
        .map_err(|e| format!("{}: {e}", out.display()))?;
    eprintln!(
        "{} samples ({:.2} h){} written to {}",
        run.time_s.len(),
        run.time_s.last().copied().unwrap_or(0.0) / 3600.0,
        if a.noise_only { ", noise only," } else { "" },
        out.display()
    );
    Ok(())
}
