//! `driftlab compare`: several models fitted on one log, judged on it and on held-out logs.

use super::common::{self, CliError, LogArgs};
use driftlab::judge::compare::{self, ModelReport, Outcome};
use driftlab::judge::metrics::MeritOptions;
use driftlab::judge::recommend::{self, Recommendation};
use driftlab::log::ingest::{ExtraColumns, Needs};
use driftlab::models::presets::{CustomOptions, ModelChoice, Preset};
use driftlab::models::recipe::{CheckedRecipe, Recipe};
use driftlab::models::regression::{DelaySpec, FitSamples, LagSpec, Term, terms};
use std::path::{Path, PathBuf};

/// More runs than this in a campaign compared: the leave-one-run-out is announced as long, on
/// any stderr.
const LONG_CAMPAIGN_RUNS: usize = 8;

/// Arguments of `compare`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The log every model is fitted on; several logs are the runs of one campaign, fitted
    /// together, and each model is then also judged on each run left out in turn (fitted on
    /// the others).
    #[arg(long, value_name = "LOG", num_args = 1.., required = true)]
    pub train: Vec<PathBuf>,
    /// Logs of the same gyro to judge the models on (held out).
    #[arg(long, value_name = "LOG", num_args = 1..)]
    pub test: Vec<PathBuf>,
    /// Models to compare, comma-separated (default: every preset and the flight
    /// controllers' forms): vakhrameev, ieee952, yan-cross, yan-delayed, sukhanov, poly-t,
    /// pwl-t, coil-lag, px4, ardupilot; and, only when named, a polynomial in T of order N
    /// poly-tN (N 1 to 9), and the reference rows px4-script and ardupilot-script (the fits PX4's and
    /// ArduPilot's own scripts make, marked * in the tables and "reference": true in the
    /// JSON).
    #[arg(long, value_name = "LIST", value_delimiter = ',')]
    pub models: Vec<String>,
    /// A custom model as comma-separated terms: 1, T, T^2, T^3, Tdot, Tddot, T*Tdot, |Tdot|,
    /// T*Tddot, sgn(Tdot)*Tddot, dT, dT^2, selfheat, ch:NAME, ch^2:NAME, pwlT:N, T-Tref,
    /// (T-Tref)^K (K 1 to 9; Tref the middle of the fitted T range) (repeatable).
    #[arg(long, value_name = "TERMS")]
    pub custom: Vec<String>,
    /// Delay of the temperature channels in custom models: none, SECONDS, auto (one delay
    /// searched up to 1800 s) or bands:N (one per temperature band); default none. Only with
    /// --custom.
    #[arg(long, value_name = "DELAY")]
    pub delay: Option<DelaySpec>,
    /// First-order lag of T in custom models (an estimate of the temperature inside the
    /// gyro): none, SECONDS, auto (searched up to 3600 s) or auto-t (searched with a time
    /// constant that changes with temperature); default none. Only with --custom.
    #[arg(long, value_name = "LAG")]
    pub lag: Option<LagSpec>,
    /// Samples custom models are fitted on: all (every sample with a rate history), plateaus
    /// (the temperature plateaus only: static models) or staged (static terms on the
    /// plateaus, then rate terms on what they leave, as Vakhrameev calibrates); default all.
    /// Only with --custom.
    #[arg(long, value_name = "SAMPLES")]
    pub fit: Option<FitSamples>,
    /// Causal smoothing of T before differentiating, s (every model).
    #[arg(long, value_name = "S", default_value_t = 60.0)]
    pub smooth: f64,
    /// Derivative step H, s (every model).
    #[arg(long = "step-h", value_name = "S", default_value_t = 30.0)]
    pub step_h: f64,
    /// Moving-average window of the filtered drift, s.
    #[arg(long, value_name = "S", default_value_t = 100.0)]
    pub filter: f64,
    /// Length of the consecutive mean/RMS windows, s (default 600). One asked for that is
    /// shorter than a log's step is refused; the default's figures are then n/a, with why.
    #[arg(long, value_name = "S")]
    pub window: Option<f64>,
    /// The gyro axes to compare models on, comma-separated (`gx,gz`, or by rate column or
    /// ending letter): by default every axis of a training log of several (a single
    /// `--rate-col` compares on that one). Each is fitted on its own and judged on the same
    /// axis of the test logs.
    #[arg(long, value_name = "LIST", value_delimiter = ',')]
    pub axes: Vec<String>,
    /// Print the comparison as JSON.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub log_args: LogArgs,
}

pub fn run(a: Args) -> Result<(), CliError> {
    a.log_args.refuse_accel("compare")?;
    refuse_custom_options_without_custom(&a)?;
    let how = CustomOptions {
        delay: a.delay.clone().unwrap_or_default(),
        lag: a.lag.clone().unwrap_or_default(),
        samples: a.fit.unwrap_or_default(),
    };
    let choices = ModelChoice::list(&a.models, &a.custom, &how).map_err(|e| match e {
        driftlab::error::Error::Invalid(i) => common::with_option(i),
        other => other.into(),
    })?;
    let merit = MeritOptions {
        filter_s: a.filter,
        window_s: a.window.unwrap_or(MeritOptions::default().window_s),
    };
    let logs: Vec<&Path> = a
        .train
        .iter()
        .chain(&a.test)
        .map(PathBuf::as_path)
        .collect();
    common::refuse_stream_twice(&logs)?;
    // The columns the models read: a preset reads none but T (Sukhanov's every one), a custom
    // model the channels it names.
    let needs = Needs {
        extras: extras_read(&choices),
        ..Needs::default()
    };
    let read = |p: &PathBuf| {
        let input = a.log_args.open(p)?;
        a.log_args.read_needing(&input, &needs)
    };
    // Before any run is read: a mistyped glob of thousands of logs is refused at once.
    if a.train.len() > driftlab::log::campaign::MAX_RUNS {
        return Err(CliError::Message(format!(
            "--train: {}",
            driftlab::log::campaign::CampaignError::TooManyRuns(a.train.len())
        )));
    }
    let mut runs = Vec::with_capacity(a.train.len());
    for p in &a.train {
        let input = a.log_args.open(p)?;
        runs.push(driftlab::log::campaign::RunInput {
            log: a.log_args.read_needing(&input, &needs)?,
            sha256: driftlab::files::calibration::sha256_input(&input)
                .map_err(|e| e.to_string())?,
        });
    }
    if runs.len() > 1 {
        // A campaign's runs are named by their files, as `calibrate` names them.
        for (r, name) in runs
            .iter_mut()
            .zip(driftlab::log::campaign::run_names(&a.train))
        {
            r.log.source = name;
        }
    }
    let mut train = driftlab::log::campaign::join(runs)
        .map_err(|e| CliError::Message(super::log_source::in_flags(&e.to_string())))?;
    let runs = train.runs().len();
    if runs >= 2 {
        // Said whether or not stderr is a terminal when it is long: N runs make N more fits
        // of every model (64 runs: the better part of an hour).
        let said = format!(
            "{} models, each also fitted {runs} times with each run left out: {} fits in all",
            choices.len(),
            choices.len() * (runs + 1)
        );
        match runs > LONG_CAMPAIGN_RUNS {
            true => note!("{said}; this takes long (the runs left out are judged one by one)"),
            false => common::status(&format!("{said} ...")),
        }
    }
    let mut tests = a.test.iter().map(read).collect::<Result<Vec<_>, _>>()?;
    for log in std::iter::once(&train).chain(&tests) {
        common::check_merit(&merit, a.window.is_some(), log)?;
    }
    common::status(&format!("fitting {} models ...", choices.len()));
    let recipe = Recipe {
        filter_s: a.filter,
        temp_smoothing_s: a.smooth,
        step_h_s: a.step_h,
        ..Recipe::default()
    }
    .checked()
    .map_err(common::with_option)?;
    if train.runs().len() >= 2 {
        // Each run needs a plateau, as `calibrate` asks: the one check, on the T settings
        // every model is fitted with.
        driftlab::models::campaign::run_plateaus(&train, &recipe)
            .map_err(|e| CliError::Message(format!("{}: {e}", train.source)))?;
    }
    if let Some(axes) = axes_to_compare(&a, &train)? {
        return run_axes(
            &a,
            &mut train,
            &mut tests,
            &axes,
            (&choices, &recipe, &merit),
        );
    }
    let bar = common::progress_bar(&format!("comparing {} models", choices.len()));
    let done = std::sync::atomic::AtomicUsize::new(0);
    let reports = compare::compare_telling(&train, &tests, &choices, &recipe, &merit, &|| {
        let k = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        if let Some(b) = &bar {
            b.set_position((1000 * k / choices.len().max(1)) as u64);
        }
    });
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let recommended = recommended(&train, &reports, &choices, &recipe, &merit);
    if a.json {
        common::print_json(&serde_json::json!({
            "train": train_json(&a.train),
            "test": a.test,
            "options": merit,
            "models": reports,
            "recommended": recommended,
        }))?;
    } else {
        print_tables(&reports, &merit)?;
        print_recommendation(recommended.as_ref(), None)?;
    }
    refuse_none_fitted(&train.source, [&reports[..]])
}

/// `--delay`, `--lag` and `--fit` shape the custom models alone: given without `--custom`
/// they would be dropped (every preset has its own), so they are refused by name, as
/// `calibrate` refuses them with a preset.
fn refuse_custom_options_without_custom(a: &Args) -> Result<(), CliError> {
    let custom_only = [
        ("--delay", a.delay.is_some()),
        ("--lag", a.lag.is_some()),
        ("--fit", a.fit.is_some()),
    ];
    match custom_only.iter().find(|(_, given)| *given) {
        Some((option, _)) if a.custom.is_empty() => Err(format!(
            "{option} shapes the custom models (--custom TERMS), and none is compared: the \
             presets each have their own"
        )
        .into()),
        _ => Ok(()),
    }
}

/// A comparison in which no model could be fitted is a failure, not a table of reasons: the
/// reasons are printed (in the table or the JSON), then the command exits with an error, so
/// that a script does not take an empty comparison for a result.
fn refuse_none_fitted<'r>(
    train: &str,
    per_axis: impl IntoIterator<Item = &'r [ModelReport]>,
) -> Result<(), CliError> {
    let mut reports = per_axis.into_iter().flatten().peekable();
    if reports.peek().is_some() && reports.all(|r| r.error.is_some()) {
        return Err(
            format!("{train}: no model could be fitted (each one's reason is above)",).into(),
        );
    }
    Ok(())
}

/// The extra columns `choices` read: the channels each model's terms name, and the other
/// temperatures where a term reads a second sensor (a custom model's `dT`, guessed among them);
/// `None`, every one, for Sukhanov's model, which makes a term of each extra channel, and for
/// any model whose terms cannot be told before a log is read.
fn extras_read(choices: &[ModelChoice]) -> Option<ExtraColumns> {
    let mut kept = ExtraColumns::default();
    // A preset's terms on a log of no column: Sukhanov's, which reads the log's every channel,
    // has none to give.
    let no_log = driftlab::Log::default();
    for choice in choices {
        if choice.is_vakhrameev() {
            continue;
        }
        if *choice == ModelChoice::Preset(Preset::Sukhanov) {
            return None;
        }
        let Ok(Some(spec)) = choice.spec(&no_log) else {
            return None;
        };
        kept.names.extend(terms::channel_names(&spec.terms));
        kept.names.extend(spec.temp2.clone());
        kept.temperatures |= spec.terms.iter().any(Term::needs_temp2);
    }
    Some(kept)
}

/// The axes to compare on ([`common::chosen_axes`] of the training log).
fn axes_to_compare(a: &Args, train: &driftlab::Log) -> Result<Option<Vec<String>>, CliError> {
    common::chosen_axes(&a.axes, &a.log_args, train)
}

/// `compare` on several axes: for each, every model fitted on that axis of the training log
/// and judged on the same axis of every test log (by name, or by the rate column it was read
/// from), as the single-axis command does on that axis alone; then a summary of every axis.
fn run_axes(
    a: &Args,
    train: &mut driftlab::Log,
    tests: &mut [driftlab::Log],
    axes: &[String],
    (choices, recipe, merit): (&[ModelChoice], &CheckedRecipe, &MeritOptions),
) -> Result<(), CliError> {
    let mut per_axis: Vec<(String, Vec<ModelReport>)> = Vec::with_capacity(axes.len());
    let mut recommendations: Vec<Option<Recommendation>> = Vec::with_capacity(axes.len());
    for name in axes {
        if !train.select_axis(name) {
            return Err(format!("{}: axis {name} vanished from the log", train.source).into());
        }
        let column = train.rate_column().unwrap_or_default();
        for t in tests.iter_mut() {
            let found = t.matching_axis(name, &column);
            if !found.as_deref().is_some_and(|f| t.select_axis(f)) {
                return Err(format!(
                    "{}: no gyro axis {name} (column {}) to judge axis {name} of {} on (its \
                     axes: {})",
                    t.source,
                    if column.is_empty() { "?" } else { &column },
                    train.source,
                    t.axis_names().join(", ")
                )
                .into());
            }
        }
        common::status(&format!(
            "fitting {} models on axis {name} ...",
            choices.len()
        ));
        let reports = compare::compare(train, tests, choices, recipe, merit);
        recommendations.push(recommended(train, &reports, choices, recipe, merit));
        per_axis.push((name.clone(), reports));
    }
    if a.json {
        // The first axis's models at the top, as for a log of one axis; every axis under
        // "axes".
        let axes_json: Vec<serde_json::Value> = per_axis
            .iter()
            .zip(&recommendations)
            .map(|((name, reports), rec)| {
                serde_json::json!({ "name": name, "models": reports, "recommended": rec })
            })
            .collect();
        common::print_json(&serde_json::json!({
            "train": train_json(&a.train),
            "test": a.test,
            "options": merit,
            "models": per_axis.first().map(|(_, r)| r),
            "recommended": recommendations.first(),
            "axes": axes_json,
        }))?;
    } else {
        for ((name, reports), rec) in per_axis.iter().zip(&recommendations) {
            out!("=== Axis {name} ===")?;
            print_tables(reports, merit)?;
            print_recommendation(rec.as_ref(), None)?;
            out!()?;
        }
        print_axes_summary(&per_axis)?;
        out!()?;
        for ((name, _), rec) in per_axis.iter().zip(&recommendations) {
            print_recommendation(rec.as_ref(), Some(name))?;
        }
    }
    refuse_none_fitted(&train.source, per_axis.iter().map(|(_, r)| &r[..]))
}

/// For every log, one line per model: its corrected peak-to-peak on each axis with the ratio
/// (marked "worse" below 1). No raw column: each model's figures leave out its own warm-up.
/// The heading of one log's table: its name, and whether the models were fitted on it.
fn print_log_heading(j: &compare::Judgement) -> Result<(), CliError> {
    out!()?;
    match &j.cannot_tell {
        Some(why) => out!(
            "{} (cannot tell if it is the training log: {why}; its figures are no held-out \
             evidence)",
            j.log
        )?,
        None => out!("{} ({})", j.log, j.kind())?,
    }
    Ok(())
}

fn print_axes_summary(per_axis: &[(String, Vec<ModelReport>)]) -> Result<(), CliError> {
    let Some((_, first_axis)) = per_axis.first() else {
        return Ok(());
    };
    let Some(first) = first_axis.iter().find(|r| r.error.is_none()) else {
        return Ok(());
    };
    out!(
        "Summary of every axis: corrected peak-to-peak of the filtered drift, deg/h, and \
         raw/cor (raw over the same samples)"
    )?;
    for (k, j) in first.logs.iter().enumerate() {
        // Each axis judged the log by its own samples: one word when they agree, else which.
        let held: Vec<(&str, &str)> = per_axis
            .iter()
            .filter_map(|(name, reports)| {
                let r = reports.iter().find(|r| r.error.is_none())?;
                Some((name.as_str(), r.logs.get(k)?.kind()))
            })
            .collect();
        if held.iter().all(|&(_, h)| h == j.kind()) {
            print_log_heading(j)?;
        } else {
            let groups: Vec<String> = ["in-sample", "held out", "cannot tell"]
                .iter()
                .filter_map(|kind| {
                    let names: Vec<&str> = held
                        .iter()
                        .filter(|&&(_, h)| h == *kind)
                        .map(|&(n, _)| n)
                        .collect();
                    (!names.is_empty()).then(|| format!("{kind} on {}", names.join(", ")))
                })
                .collect();
            out!()?;
            out!("{} ({})", j.log, groups.join("; "))?;
        }
        let w = name_width(first_axis);
        let mut head = format!("  {:<w$}", "model");
        for (name, _) in per_axis {
            head.push_str(&format!(" {:>20}", name));
        }
        out!("{head}")?;
        for (m, r) in first_axis.iter().enumerate() {
            let mut line = format!("  {:<w$}", shown_name(r));
            for (_, reports) in per_axis {
                let cell = match reports.get(m).filter(|q| q.model == r.model) {
                    Some(r) if r.error.is_some() => "not fitted".to_string(),
                    Some(r) => match r.logs.get(k).map(|j| &j.result) {
                        Some(Outcome::Evaluation(e)) => format!(
                            "{} {}",
                            common::figure(e.comparison.corrected.p2p_dph),
                            common::ratio(e.comparison.p2p_ratio)
                        ),
                        Some(Outcome::Error(_)) => "not applied".to_string(),
                        None => "n/a".to_string(),
                    },
                    None => "n/a".to_string(),
                };
                line.push_str(&format!(" {cell:>20}"));
            }
            out!("{line}")?;
        }
        say_references(first_axis)?;
        // The figures not in the summary that a model made worse than raw.
        for r in first_axis.iter().filter(|r| r.error.is_none()) {
            for (name, reports) in per_axis {
                let worse = reports
                    .iter()
                    .find(|q| q.model == r.model)
                    .and_then(|q| match q.logs.get(k).map(|j| &j.result) {
                        Some(Outcome::Evaluation(e)) => Some(e.comparison.worse_than_raw),
                        _ => None,
                    })
                    .filter(|w| w.any());
                if let Some(w) = worse {
                    out!(
                        "  {}, axis {name}: worse than raw: {} (ratio below 1)",
                        r.model,
                        w.names().join(", ")
                    )?;
                }
            }
        }
    }
    Ok(())
}

/// A model's name in a table: a reference row's marked with `*`.
fn shown_name(r: &ModelReport) -> String {
    if r.reference {
        format!("{}*", r.model)
    } else {
        r.model.clone()
    }
}

/// The width of the tables' model column: 12, or the longest name shown.
fn name_width(reports: &[ModelReport]) -> usize {
    reports
        .iter()
        .map(|r| shown_name(r).chars().count())
        .fold(12, usize::max)
}

/// The line under a table that says what its `*` rows are, when it has any.
fn say_references(reports: &[ModelReport]) -> Result<(), CliError> {
    if reports.iter().any(|r| r.reference && r.error.is_none()) {
        out!(
            "  * reference: the fit the flight controller's own script makes (its filtering \
             and binning), shown beside driftlab's models"
        )?;
    }
    Ok(())
}

fn print_tables(reports: &[ModelReport], merit: &MeritOptions) -> Result<(), CliError> {
    out!(
        "Figures of the drift filtered over {} s, in deg/h; ratio = raw / corrected (above 1 is \
         better); windows of {} s.",
        common::num(merit.filter_s),
        common::num(merit.window_s)
    )?;
    for r in reports.iter().filter(|r| r.error.is_some()) {
        out!(
            "  {}: not fitted: {}",
            r.model,
            r.error.as_deref().unwrap_or("")
        )?;
    }
    let Some(first) = reports.iter().find(|r| r.error.is_none()) else {
        return Ok(());
    };
    let w = name_width(reports);
    for (k, j) in first.logs.iter().enumerate() {
        print_log_heading(j)?;
        out!(
            "  {:<w$} {:>9} {:>9} {:>8} {:>8} {:>10} {:>8} {:>8}",
            "model",
            "p2p raw",
            "p2p cor",
            "p2p",
            "std",
            driftlab::judge::options::window_label(merit.window_s),
            "RMS",
            "outside"
        )?;
        for r in reports.iter().filter(|r| r.error.is_none()) {
            match r.logs.get(k).map(|j| &j.result) {
                Some(Outcome::Evaluation(e)) => {
                    let c = &e.comparison;
                    out!(
                        "  {:<w$} {:>9} {:>9} {:>8} {:>8} {:>10} {:>8} {:>7}%",
                        shown_name(r),
                        common::figure(c.raw.p2p_dph),
                        common::figure(c.corrected.p2p_dph),
                        common::ratio(c.p2p_ratio),
                        common::ratio(c.std_ratio),
                        common::ratio(c.win_mean_ratio),
                        common::ratio(c.win_rms_ratio),
                        driftlab::number::percent(e.outside_fraction)
                    )?;
                }
                Some(Outcome::Error(msg)) => out!("  {:<w$} {msg}", shown_name(r))?,
                None => {}
            }
        }
        say_references(reports)?;
        // Why a figure is n/a, once per reason, as `evaluate` says it under its table.
        let mut said = Vec::new();
        for r in reports.iter().filter(|r| r.error.is_none()) {
            if let Some(Outcome::Evaluation(e)) = r.logs.get(k).map(|j| &j.result) {
                for told in e.comparison.unavailable() {
                    if !said.contains(&told) {
                        out!("  {} n/a: {}", told.0, told.1)?;
                        said.push(told);
                    }
                }
            }
        }
    }
    print_runs_left_out(reports)
}

/// The training runs, as `--json` gives them: the path of one log, or the list of a
/// campaign's.
fn train_json(train: &[PathBuf]) -> serde_json::Value {
    match train {
        [one] => serde_json::json!(one),
        many => serde_json::json!(many),
    }
}

/// On a campaign, each model's figures on every run left out in turn (fitted on the other
/// runs): one line a run, then the mean and the worst.
fn print_runs_left_out(reports: &[ModelReport]) -> Result<(), CliError> {
    let Some(first) = reports.iter().find_map(|r| r.leave_one_run_out.as_ref()) else {
        return Ok(());
    };
    let w = name_width(reports);
    out!()?;
    out!("Leave one run out (each model fitted on the other runs, judged on the run left out):")?;
    let runs: Vec<&str> = first.runs.iter().map(|r| r.run.as_str()).collect();
    let rw = runs
        .iter()
        .map(|r| r.chars().count())
        .max()
        .unwrap_or(3)
        .max(3);
    out!(
        "  {:<w$} {:<rw$} {:>9} {:>9} {:>8}",
        "model",
        "run",
        "p2p raw",
        "p2p cor",
        "p2p"
    )?;
    for r in reports.iter().filter(|r| r.error.is_none()) {
        let Some(l) = &r.leave_one_run_out else {
            continue;
        };
        for run in &l.runs {
            match &run.error {
                Some(e) => out!("  {:<w$} {:<rw$} {e}", shown_name(r), run.run)?,
                None => out!(
                    "  {:<w$} {:<rw$} {:>9} {:>9} {:>8}",
                    shown_name(r),
                    run.run,
                    run.raw_p2p_dph.map_or("n/a".into(), common::figure),
                    run.corrected_p2p_dph.map_or("n/a".into(), common::figure),
                    run.p2p_ratio.map_or("n/a".into(), common::ratio),
                )?,
            }
        }
        out!(
            "  {:<w$} {:<rw$} {:>9} {:>9} {:>8}   worst cor {} ratio {}",
            "",
            "mean",
            l.mean_raw_p2p_dph.map_or("n/a".into(), common::figure),
            l.mean_corrected_p2p_dph
                .map_or("n/a".into(), common::figure),
            l.mean_p2p_ratio.map_or("n/a".into(), common::ratio),
            l.worst_corrected_p2p_dph
                .map_or("n/a".into(), common::figure),
            l.worst_p2p_ratio.map_or("n/a".into(), common::ratio),
        )?;
    }
    Ok(())
}

/// The recommendation of a comparison ([`recommend::recommend`]), told on the status line
/// while the blocks of the training log are fitted when no held-out log judges it.
fn recommended(
    train: &driftlab::Log,
    reports: &[ModelReport],
    choices: &[ModelChoice],
    recipe: &CheckedRecipe,
    merit: &MeritOptions,
) -> Option<Recommendation> {
    if recommend::held_out_logs(reports).is_empty() {
        common::status(&format!(
            "judging the models on {} blocks of {} held out in turn (no held-out log) ...",
            recommend::BLOCKS,
            train.source
        ));
    }
    recommend::recommend(train, reports, choices, recipe, merit, &|| true)
}

/// The recommendation under a table (of `axis`, in the summary of several).
fn print_recommendation(rec: Option<&Recommendation>, axis: Option<&str>) -> Result<(), CliError> {
    let on = axis.map(|a| format!(" on axis {a}")).unwrap_or_default();
    let Some(r) = rec else {
        out!("Recommended{on}: none: no model was judged on every part (the reasons are above)")?;
        return Ok(());
    };
    out!(
        "Recommended{on}: {} (worst raw/cor peak-to-peak {}, judged {})",
        r.model,
        common::ratio(r.worst_p2p_ratio),
        r.judged_on.describe()
    )?;
    if let Some(c) = &r.caution {
        out!("  caution: {c}")?;
    }
    match &r.flight_form {
        Some(f) if *f == r.model => {}
        Some(f) => {
            let ratio = r
                .standings
                .iter()
                .find(|s| s.model == *f)
                .and_then(|s| s.worst_p2p_ratio);
            out!(
                "  for a flight controller that takes a polynomial in T only: {f} (worst {})",
                ratio.map_or_else(|| "n/a".to_string(), common::ratio)
            )?;
        }
        None => {}
    }
    if !r.references.is_empty() {
        let rows: Vec<String> = r
            .references
            .iter()
            .map(|s| match (s.worst_p2p_ratio, &s.why) {
                (Some(x), _) => format!("{} {}", s.model, common::ratio(x)),
                (None, Some(why)) => format!("{} not judged ({why})", s.model),
                (None, None) => format!("{} not judged", s.model),
            })
            .collect();
        let verdict = match &r.against_references {
            Some(v) => format!("{} {}", r.model, v.describe()),
            None => "none of them could be judged".to_string(),
        };
        out!(
            "  beside it, the firmware scripts' own fits judged alike (worst): {}; {verdict}",
            rows.join(", ")
        )?;
    }
    Ok(())
}
