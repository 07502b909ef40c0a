//! `driftlab simulate`: write a simulated chamber log.

use driftlab::sim;
use std::path::PathBuf;

/// Arguments of `simulate`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Test profile (see --list).
    #[arg(long, default_value = "calibration")]
    pub profile: String,
    /// Random seed: the same seed gives the same log on every machine.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Where to write the log (CSV).
    #[arg(long, short, required_unless_present = "list")]
    pub out: Option<PathBuf>,
    /// List the profiles and exit.
    #[arg(long)]
    pub list: bool,
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
    let run = sim::simulate_with_progress(&profile, a.seed, &|f| {
        if let Some(b) = &bar {
            b.set_position((f * 1000.0) as u64);
        }
    });
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    run.write_csv(&out)
        .map_err(|e| format!("{}: {e}", out.display()))?;
    eprintln!(
        "{} samples ({:.2} h) written to {}",
        run.time_s.len(),
        run.time_s.last().copied().unwrap_or(0.0) / 3600.0,
        out.display()
    );
    Ok(())
}
