//! `driftlab lot`: every unit in the folders given calibrated, judged against a spec and
//! compared with the lot ([`driftlab::lot`]); a line per unit, the outliers, and a status a
//! test station can gate on.

use super::common::{self, CliError};
use driftlab::lot::{self, Lot, LotOutcome, Shard, Spec, Status};
use std::path::PathBuf;

/// The status of a lot in which a unit failed the spec (and none was an error).
pub const EXIT_FAIL: u8 = 2;

/// The status of a lot in which a unit could not be calibrated.
pub const EXIT_ERROR: u8 = 3;

/// Arguments of `lot`.
#[derive(clap::Args, Debug)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct Args {
    /// `lot merge OUT`: join the shards' tables.
    #[command(subcommand)]
    pub merge: Option<Merge>,
    /// Folders of units: each log file in one is a unit, each folder of logs a unit of several
    /// runs; a log file given here is a unit of its own.
    #[arg(required = true, value_name = "DIR")]
    pub dirs: Vec<PathBuf>,
    /// The acceptance spec (JSON): the limits every unit is held to (docs/lots.md).
    #[arg(long, value_name = "FILE", required = true)]
    pub spec: Option<PathBuf>,
    /// The output folder: each unit's calibration in OUT/UNIT/calibration.json, and
    /// OUT/lot.csv and OUT/lot.json.
    #[arg(long, short, value_name = "OUT", required = true)]
    pub out: Option<PathBuf>,
    /// The recipe of every unit without its own (UNIT.recipe.json beside it, or recipe.json
    /// in its folder); a recipe file or a calibration file whose recipe is reused.
    #[arg(long, value_name = "FILE")]
    pub recipe: Option<PathBuf>,
    /// Units calibrated at once (default: the processors the machine has).
    #[arg(long, value_name = "N")]
    pub jobs: Option<usize>,
    /// Calibrate shard I of N of the lot only (a job array's task I of N), writing
    /// OUT/lot-shard-I-of-N.json; `driftlab lot merge OUT` joins the shards.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<Shard>,
}

/// `lot`'s subcommand.
#[derive(clap::Subcommand, Debug)]
pub enum Merge {
    /// Join the tables of a sharded lot's shards (OUT/lot-shard-I-of-N.json, every shard of
    /// one lot) into OUT/lot.csv and OUT/lot.json, with the outliers of the whole lot.
    Merge {
        /// The output folder the shards wrote into.
        #[arg(value_name = "OUT")]
        out: PathBuf,
    },
}

/// Runs the lot (or merges its shards), prints a line per unit and its outliers, and ends with
/// the lot's status: 0 when every unit passes, [`EXIT_FAIL`] when one fails and none is an
/// error, [`EXIT_ERROR`] when one could not be calibrated.
pub fn run(a: Args) -> Result<(), CliError> {
    if let Some(Merge::Merge { out }) = &a.merge {
        let outcome = lot::merge(out).map_err(|e| e.to_string())?;
        print(&outcome, out, None)?;
        return status(&outcome);
    }
    let (Some(spec), Some(out)) = (&a.spec, &a.out) else {
        return Err("give --spec FILE and --out OUT".into());
    };
    if out == std::path::Path::new("-") {
        return Err(
            "--out -: `-` stands for standard input or output, and a lot writes a \
                    folder: give its name (./- for one named -)"
                .into(),
        );
    }
    let jobs = match a.jobs {
        Some(0) => return Err("--jobs 0: give 1 or more units to calibrate at once".into()),
        Some(n) => n,
        None => std::thread::available_parallelism().map_or(1, |n| n.get()),
    };
    let spec = Spec::load(spec).map_err(|e| e.to_string())?;
    let request = Lot {
        inputs: a.dirs.clone(),
        spec,
        out: out.clone(),
        recipe: a.recipe.clone(),
        jobs,
        shard: a.shard,
    };
    let bar = common::progress_bar("lot");
    let outcome = lot::run(&request, &mut |p| {
        if let Some(b) = &bar {
            b.set_position((p.done * 1000 / p.total.max(1)) as u64);
            b.set_message(format!("lot: {}/{} units", p.done, p.total));
        }
    });
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let outcome = outcome.map_err(|e| e.to_string())?;
    print(&outcome, out, a.shard)?;
    status(&outcome)
}

/// The lot's status as the command's.
fn status(outcome: &LotOutcome) -> Result<(), CliError> {
    common::flush_out()?;
    match outcome.status() {
        Status::Pass => Ok(()),
        Status::Fail => Err(CliError::Status(EXIT_FAIL)),
        Status::Error => Err(CliError::Status(EXIT_ERROR)),
    }
}

/// A line per unit (its status, and for a failure or an error why), a line per outlier, the
/// counts and the files written.
fn print(
    outcome: &LotOutcome,
    out: &std::path::Path,
    shard: Option<Shard>,
) -> Result<(), CliError> {
    let r = driftlab::number::readable;
    for u in &outcome.units {
        let unchanged = if u.cached {
            " (unchanged: not calibrated again)"
        } else {
            ""
        };
        match u.status {
            Status::Pass => out!("pass   {}{unchanged}", u.unit)?,
            Status::Fail => out!("FAIL   {}{unchanged}: {}", u.unit, u.reasons.join("; "))?,
            Status::Error => out!("ERROR  {}: {}", u.unit, u.reasons.join("; "))?,
        }
    }
    for o in &outcome.outliers {
        let axis = if o.axis.is_empty() {
            String::new()
        } else {
            format!(" axis {}", o.axis)
        };
        out!(
            "outlier {}{axis}: {} {} is {:+.1} robust sd from the lot's median {} ({} units)",
            o.unit,
            o.figure,
            r(o.value),
            o.sigmas,
            r(o.median),
            o.units
        )?;
    }
    let [pass, fail, error] = outcome.counts();
    let cached = outcome.units.iter().filter(|u| u.cached).count();
    let counts = format!(
        "{} units: {pass} pass, {fail} fail, {error} error",
        outcome.units.len()
    );
    let unchanged = format!("{cached} unchanged since the last lot in {}", out.display());
    if shard.is_some() {
        out!("{counts}; {unchanged}")?;
    } else {
        let mut flagged: Vec<&str> = outcome.outliers.iter().map(|o| o.unit.as_str()).collect();
        flagged.dedup();
        out!(
            "{counts}; {} outlier{}; {unchanged}",
            flagged.len(),
            if flagged.len() == 1 { "" } else { "s" },
        )?;
    }
    match shard {
        None => out!(
            "Lot written to {} (lot.csv, lot.json, {} calibrations)",
            out.display(),
            pass + fail
        ),
        Some(s) => out!(
            "Shard {} of {} written to {} ({}, {} calibrations); once every shard is done, \
             `driftlab lot merge {}` writes the lot's table and finds its outliers",
            s.index,
            s.count,
            out.display(),
            s.file_name(),
            pass + fail,
            out.display()
        ),
    }
}
