//! The model to use, named from a comparison: the one whose correction holds up best on data
//! it was not fitted on.
//!
//! The figure is the raw ÷ corrected peak-to-peak of the filtered drift (the comparison's
//! `p2p_ratio`, above 1 better), taken at its worst over what the models are judged on: a
//! calibration ships to every run of the gyro, so the run it does least well on is the one
//! that counts. What it is judged on, strongest first:
//!
//! 1. the held-out logs of the comparison, when any was given and told apart from the
//!    training run (a log that is the training run, or that the sketch cannot tell, is no
//!    held-out evidence);
//! 2. otherwise, when the training is a campaign of several runs, its runs, each left out in
//!    turn (every model fitted on the other runs and judged on the one left out:
//!    [`crate::judge::runs_left_out`]);
//! 3. otherwise, [`BLOCKS`] blocks of the training log, each held out in turn: every model
//!    fitted on the rest of the run and judged on the block. A weaker judge, said with the
//!    recommendation: the blocks share the run's gyro, chamber program and day, and a block
//!    without a plateau leaves a model that needs one without it.
//!
//! Reference rows (the firmware scripts' own fits) are never recommended: they are shown beside
//! so that an engineer sees what the script would have given. Among the models a flight
//! controller can take (a polynomial in T of order 3 at most, [`flight_form`]), the best is
//! named too, for an engineer whose export target takes nothing else.

use crate::judge::compare::{ModelReport, Outcome};
use crate::judge::metrics::{Evaluation, MeritOptions};
use crate::log::Log;
use crate::models::presets::{ModelChoice, Preset};
use crate::models::recipe::CheckedRecipe;
use rayon::prelude::*;
use serde::Serialize;

/// Blocks of the training log held out in turn when no other log judges the models.
pub const BLOCKS: usize = 4;

/// What the recommendation was judged on.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum JudgedOn {
    /// The comparison's held-out logs, by name.
    HeldOutLogs {
        /// The logs.
        logs: Vec<String>,
    },
    /// The runs of the training campaign, each left out in turn.
    RunsLeftOut {
        /// The runs, by name.
        runs: Vec<String>,
    },
    /// Blocks of the training log, each held out in turn.
    TrainingBlocks {
        /// How many.
        blocks: usize,
        /// The test logs that were given and set aside, being the training run (or not told
        /// from it): why no held-out log judges although some were given.
        #[serde(skip_serializing_if = "Vec::is_empty")]
        set_aside: Vec<String>,
    },
}

impl JudgedOn {
    /// In words, for a person.
    pub fn describe(&self) -> String {
        match self {
            JudgedOn::HeldOutLogs { logs } => format!("held out on {}", logs.join(", ")),
            JudgedOn::RunsLeftOut { runs } => format!(
                "on the {} runs of the campaign, each left out in turn (fitted on the others): {}",
                runs.len(),
                runs.join(", ")
            ),
            JudgedOn::TrainingBlocks { blocks, set_aside } if set_aside.is_empty() => format!(
                "on {blocks} blocks of the training log, each held out in turn (no held-out log \
                 was given)"
            ),
            JudgedOn::TrainingBlocks { blocks, set_aside } => format!(
                "on {blocks} blocks of the training log, each held out in turn ({} {} the \
                 training run or cannot be told from it, so no held-out log judges)",
                set_aside.join(", "),
                if set_aside.len() == 1 { "is" } else { "are" }
            ),
        }
    }

    /// Why a person should weigh it less, when they should.
    pub fn caution(&self) -> Option<&'static str> {
        match self {
            JudgedOn::HeldOutLogs { .. } | JudgedOn::RunsLeftOut { .. } => None,
            JudgedOn::TrainingBlocks { .. } => Some(
                "a weaker judge than another run: the blocks share the training run's gyro, \
                 chamber program and day; judge on a held-out log (--test) before shipping",
            ),
        }
    }
}

/// One candidate's standing.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Standing {
    /// The model's name.
    pub model: String,
    /// Its worst raw ÷ corrected peak-to-peak of the filtered drift over what it was judged
    /// on; `None` when it could not be judged on every part (`why` says which).
    pub worst_p2p_ratio: Option<f64>,
    /// Whether a flight controller can take it ([`flight_form`]).
    pub flight_form: bool,
    /// Why it was not judged on every part.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub why: Option<String>,
}

/// The recommendation of a comparison.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Recommendation {
    /// The model to use.
    pub model: String,
    /// Its worst raw ÷ corrected peak-to-peak ratio over what it was judged on.
    pub worst_p2p_ratio: f64,
    /// What it was judged on.
    pub judged_on: JudgedOn,
    /// Why to weigh it less, when the judge is weak.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub caution: Option<String>,
    /// The best of the models a flight controller can take, when one was compared and judged
    /// (the same as `model` when that is one).
    pub flight_form: Option<String>,
    /// Every candidate (reference rows left out), best first; those not judged on every part
    /// last, with why.
    pub standings: Vec<Standing>,
    /// The reference rows compared (the firmware scripts' own fits), judged alike on the same
    /// parts, in the order compared: what the recommendation is set beside, never a candidate.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub references: Vec<Standing>,
    /// How the recommended model stands against the reference rows judged; `None` when none
    /// was.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub against_references: Option<AgainstReferences>,
}

impl AgainstReferences {
    /// How a recommendation whose worst ratio is `worst_p2p_ratio` stands against the
    /// `references` judged (the firmware scripts' own fits); `None` when none was judged.
    fn of(worst_p2p_ratio: f64, references: &[Standing]) -> Option<AgainstReferences> {
        // The reference whose worst ratio is highest: the one to be at least as good as.
        let best = references
            .iter()
            .filter_map(|r| r.worst_p2p_ratio.map(|x| (r.model.clone(), x)))
            .max_by(|a, b| a.1.total_cmp(&b.1))?;
        if ratio_key(worst_p2p_ratio) >= ratio_key(best.1) {
            return Some(AgainstReferences::AtLeastAsGood);
        }
        // Corrected peak-to-peak over the same raw drift: the ratio of ratios.
        let shortfall = 1.0 - worst_p2p_ratio / best.1;
        Some(if shortfall <= SAME_WITHIN {
            AgainstReferences::WithinNoise {
                model: best.0,
                shortfall,
            }
        } else {
            AgainstReferences::Worse {
                model: best.0,
                shortfall,
            }
        })
    }
}

/// How far below the best reference row's worst ratio the recommendation may fall and still
/// be called as good: two fits of one form on one log differ by up to about this much on its
/// noise alone, which no single log can rank. Measured on simulated three-axis MEMS logs whose
/// biases are cubics in T (24 seeds at each of two noise levels, 0.3 and 0.03 °/h, held out on
/// another chamber program, every corrected drift at the noise floor): driftlab's `px4` fit
/// against the better of `px4-script` and `ardupilot-script` ranged from 0.3 % above to 3.1 %
/// below, 0.4 % below on average (the better of two noisy rows is itself favoured by the
/// noise).
pub const SAME_WITHIN: f64 = 0.05;

/// The recommendation set beside the firmware scripts' own fits.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "verdict", rename_all = "snake_case")]
pub enum AgainstReferences {
    /// Its worst ratio is not below any reference row's.
    AtLeastAsGood,
    /// Below the best reference row's by no more than [`SAME_WITHIN`]: as good, to the noise.
    WithinNoise {
        /// The reference row it falls short of.
        model: String,
        /// By how much, as a fraction of that row's worst ratio.
        shortfall: f64,
    },
    /// Below the best reference row's by more than [`SAME_WITHIN`].
    Worse {
        /// The reference row it falls short of.
        model: String,
        /// By how much, as a fraction of that row's worst ratio.
        shortfall: f64,
    },
}

impl AgainstReferences {
    /// In words, after the recommended model's name.
    pub fn describe(&self) -> String {
        let pct = |f: f64| crate::number::fixed(100.0 * f, 1);
        match self {
            AgainstReferences::AtLeastAsGood => "is at least as good as each".into(),
            AgainstReferences::WithinNoise { model, shortfall } => format!(
                "is as good as each to the noise ({}% below {model}; two fits of one form \
                 differ by up to {}% on a log's noise)",
                pct(*shortfall),
                pct(SAME_WITHIN)
            ),
            AgainstReferences::Worse { model, shortfall } => {
                format!("is worse than {model} by {}%", pct(*shortfall))
            }
        }
    }

    /// Whether it is worse than a reference row beyond the noise.
    pub fn is_worse(&self) -> bool {
        matches!(self, AgainstReferences::Worse { .. })
    }
}

/// Whether a flight controller's temperature calibration can take the model as it is: a
/// polynomial in T alone of order 3 at most (PX4's `SENS_GYRO*_X0..X3`, ArduPilot's
/// `INS_TCAL*_GYR1..3` with its constant measured at boot), fitted by driftlab: the presets
/// of that form, and a custom model of those terms alone (what `export` writes for either).
pub fn flight_form(choice: &ModelChoice) -> bool {
    match choice {
        ModelChoice::Preset(p) => match p {
            Preset::PolyOrder(n) => *n <= 3,
            Preset::PolyT | Preset::Px4 | Preset::ArduPilot => true,
            _ => false,
        },
        // A custom model the export writes as it is: terms of a polynomial in T of order 3
        // at most (about 0 °C or about Tref), on T as measured.
        ModelChoice::Custom(spec) => {
            use crate::models::regression::{DelaySpec, LagSpec, Term};
            matches!(spec.delay, DelaySpec::None)
                && matches!(spec.lag, LagSpec::None)
                && spec.temp2.is_none()
                && spec.terms.iter().all(|t| match t {
                    Term::One | Term::T | Term::T2 | Term::T3 => true,
                    Term::Tc { power } => *power <= 3,
                    _ => false,
                })
        }
    }
}

/// The recommendation from `reports` (one per `choices`, in order, as [`super::compare`]
/// makes them): on their held-out logs when any, else on [`BLOCKS`] blocks of `train` held
/// out in turn (models fitted again here, each fit started only while `keep_going` says so:
/// a face's Cancel). `None` when no candidate was judged on every part.
pub fn recommend(
    train: &Log,
    reports: &[ModelReport],
    choices: &[ModelChoice],
    recipe: &CheckedRecipe,
    merit: &MeritOptions,
    keep_going: &(dyn Fn() -> bool + Sync),
) -> Option<Recommendation> {
    let held_out = held_out_logs(reports);
    // Every row judged alike, candidates and reference rows, then parted.
    let (judged_on, all) = if held_out.is_empty() && train.runs().len() >= 2 {
        let all = on_runs_left_out(reports, choices);
        let runs = train.runs().iter().map(|r| r.name.clone()).collect();
        (JudgedOn::RunsLeftOut { runs }, all)
    } else if held_out.is_empty() {
        let all = on_blocks(train, reports, choices, recipe, merit, keep_going);
        let set_aside = set_aside_logs(reports);
        (
            JudgedOn::TrainingBlocks {
                blocks: BLOCKS,
                set_aside,
            },
            all,
        )
    } else {
        let all = on_held_out(reports, choices);
        (JudgedOn::HeldOutLogs { logs: held_out }, all)
    };
    let mut references = Vec::new();
    let mut candidates = Vec::new();
    for (r, s) in reports.iter().zip(all) {
        if r.reference {
            references.push(s);
        } else {
            candidates.push(s);
        }
    }
    let standings = ranked(candidates);
    let best = standings.first()?;
    let worst_p2p_ratio = best.worst_p2p_ratio?;
    let flight = standings
        .iter()
        .find(|s| s.flight_form && s.worst_p2p_ratio.is_some())
        .map(|s| s.model.clone());
    // A best that leaves the drift as it was or worse is no model to adopt: said first.
    let none_helps = (ratio_key(worst_p2p_ratio) <= 0).then(|| {
        format!(
            "no model makes the peak-to-peak of the drift smaller on what it was judged on \
             (the best, {}, gives raw ÷ corrected {}): none is worth adopting from this \
             comparison",
            best.model,
            crate::number::fixed(worst_p2p_ratio, 3)
        )
    });
    let caution = match (none_helps, judged_on.caution()) {
        (Some(a), Some(b)) => Some(format!("{a}; {b}")),
        (Some(a), None) => Some(a),
        (None, b) => b.map(str::to_string),
    };
    Some(Recommendation {
        model: best.model.clone(),
        worst_p2p_ratio,
        caution,
        judged_on,
        flight_form: flight,
        standings,
        against_references: AgainstReferences::of(worst_p2p_ratio, &references),
        references,
    })
}

/// The names of the logs every fitted model was judged on held out (the same for all: the
/// training run's sketch tells each test log once); none means the blocks of the training log
/// judge instead.
pub fn held_out_logs(reports: &[ModelReport]) -> Vec<String> {
    reports
        .iter()
        .find(|r| r.error.is_none() && !r.reference)
        .map(|r| {
            r.logs
                .iter()
                .filter(|j| j.held_out && j.cannot_tell.is_none())
                .map(|j| j.log.clone())
                .collect()
        })
        .unwrap_or_default()
}

/// The test logs every fitted model set aside as no held-out evidence: the training run
/// given again, or a log its sketch cannot tell from it.
fn set_aside_logs(reports: &[ModelReport]) -> Vec<String> {
    reports
        .iter()
        .find(|r| r.error.is_none() && !r.reference)
        .map(|r| {
            r.logs
                .iter()
                .skip(1)
                .filter(|j| !j.held_out || j.cannot_tell.is_some())
                .map(|j| j.log.clone())
                .collect()
        })
        .unwrap_or_default()
}

/// The worst of `ratios`, or why there is none: a part not judged, or a ratio n/a.
fn worst(ratios: Vec<Result<f64, String>>) -> (Option<f64>, Option<String>) {
    let mut w = f64::INFINITY;
    for r in ratios {
        match r {
            Ok(x) if x.is_finite() => w = w.min(x),
            Ok(_) => return (None, Some("its peak-to-peak ratio is n/a on a part".into())),
            Err(e) => return (None, Some(e)),
        }
    }
    if w.is_finite() {
        (Some(w), None)
    } else {
        (None, Some("judged on nothing".into()))
    }
}

/// The standings on the held-out logs of `reports` (reference rows too), in their order.
fn on_held_out(reports: &[ModelReport], choices: &[ModelChoice]) -> Vec<Standing> {
    reports
        .iter()
        .zip(choices)
        .map(|(r, choice)| {
            standing(r, choice, || {
                r.logs
                    .iter()
                    .filter(|j| j.held_out && j.cannot_tell.is_none())
                    .map(|j| match &j.result {
                        Outcome::Evaluation(e) => Ok(e.comparison.p2p_ratio),
                        Outcome::Error(e) => Err(format!("{}: {e}", j.log)),
                    })
                    .collect()
            })
        })
        .collect()
}

/// The standings on the runs of the training campaign left out in turn, as each report holds
/// them (reference rows too), in their order.
fn on_runs_left_out(reports: &[ModelReport], choices: &[ModelChoice]) -> Vec<Standing> {
    reports
        .iter()
        .zip(choices)
        .map(|(r, choice)| {
            standing(r, choice, || match &r.leave_one_run_out {
                Some(l) => l
                    .runs
                    .iter()
                    .map(|run| match (&run.error, run.p2p_ratio) {
                        (Some(e), _) => Err(format!("{} left out: {e}", run.run)),
                        (None, Some(x)) => Ok(x),
                        (None, None) => Err(format!("{} left out: not judged", run.run)),
                    })
                    .collect(),
                None => vec![Err("not judged on the runs left out".into())],
            })
        })
        .collect()
}

/// A candidate's standing from its ratios on the parts it was judged on (`ratios`, read
/// only when it was fitted).
fn standing(
    r: &ModelReport,
    choice: &ModelChoice,
    ratios: impl FnOnce() -> Vec<Result<f64, String>>,
) -> Standing {
    let (worst_p2p_ratio, why) = match &r.error {
        Some(e) => (None, Some(format!("not fitted: {e}"))),
        None => worst(ratios()),
    };
    Standing {
        model: r.model.clone(),
        worst_p2p_ratio,
        flight_form: flight_form(choice),
        why,
    }
}

/// The rows of block `b` of [`BLOCKS`] over `n` samples.
fn block(n: usize, b: usize) -> std::ops::Range<usize> {
    (b * n / BLOCKS)..((b + 1) * n / BLOCKS)
}

/// The standings on [`BLOCKS`] blocks of `train`, each held out in turn: each row (reference
/// rows too, in their order) fitted on the rest of the run and judged on the block.
fn on_blocks(
    train: &Log,
    reports: &[ModelReport],
    choices: &[ModelChoice],
    recipe: &CheckedRecipe,
    merit: &MeritOptions,
    keep_going: &(dyn Fn() -> bool + Sync),
) -> Vec<Standing> {
    let n = train.len();
    let parts: Vec<(Log, Log)> = (0..BLOCKS)
        .map(|b| {
            let rows = block(n, b);
            let name = format!("{} block {} of {BLOCKS}", train.source, b + 1);
            (
                train.rows_without(
                    &format!("{} without block {}", train.source, b + 1),
                    rows.clone(),
                ),
                train.rows_in(&name, rows),
            )
        })
        .collect();
    let candidates: Vec<(&ModelReport, &ModelChoice)> = reports.iter().zip(choices).collect();
    let jobs: Vec<(usize, usize)> = (0..candidates.len())
        .flat_map(|c| (0..BLOCKS).map(move |b| (c, b)))
        .collect();
    let ratios: Vec<Result<f64, String>> = jobs
        .par_iter()
        .map(|&(c, b)| {
            if !keep_going() {
                return Err("cancelled".to_string());
            }
            let (rest, held) = &parts[b];
            let m = crate::models::fit(rest, candidates[c].1, recipe)
                .map_err(|e| format!("not fitted without block {}: {e}", b + 1))?;
            let corrected = m
                .correct(held)
                .map_err(|e| format!("not applied to block {}: {e}", b + 1))?;
            Ok(Evaluation::of_correction(held, &corrected, merit)
                .comparison
                .p2p_ratio)
        })
        .collect();
    candidates
        .iter()
        .enumerate()
        .map(|(c, (r, choice))| {
            standing(r, choice, || ratios[c * BLOCKS..(c + 1) * BLOCKS].to_vec())
        })
        .collect()
}

/// A ratio as a whole number of parts per 10⁹ of its logarithm: ratios that differ by the
/// rounding of one fit against another (1.0000000000000002 and 1.0, the same cubic fitted
/// as two models) rank alike, the one compared first first; 0 is a ratio of 1.
fn ratio_key(r: f64) -> i64 {
    (r.ln() * 1e9).round() as i64
}

/// Best first (the highest worst ratio, ratios equal to rounding in the order compared),
/// those without a figure last in their order.
fn ranked(mut s: Vec<Standing>) -> Vec<Standing> {
    s.sort_by(|a, b| match (a.worst_p2p_ratio, b.worst_p2p_ratio) {
        (Some(x), Some(y)) => ratio_key(y).cmp(&ratio_key(x)),
        (Some(_), None) => std::cmp::Ordering::Less,
        (None, Some(_)) => std::cmp::Ordering::Greater,
        (None, None) => std::cmp::Ordering::Equal,
    });
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_verdict_beside_the_scripts_is_taken_against_the_better_one() {
        let st = |m: &str, r: Option<f64>| Standing {
            model: m.into(),
            worst_p2p_ratio: r,
            flight_form: false,
            why: None,
        };
        let refs = [
            st("px4-script", Some(100.0)),
            st("ardupilot-script", Some(98.0)),
        ];
        assert_eq!(
            AgainstReferences::of(100.0, &refs),
            Some(AgainstReferences::AtLeastAsGood)
        );
        // 4.5 % below the better script: as good to the noise.
        let Some(AgainstReferences::WithinNoise { model, shortfall }) =
            AgainstReferences::of(95.5, &refs)
        else {
            panic!("within the noise")
        };
        assert_eq!(model, "px4-script");
        assert!((shortfall - 0.045).abs() < 1e-12);
        // 6 % below it: worse, though less so against the other script.
        assert!(AgainstReferences::of(94.0, &refs).unwrap().is_worse());
        // A script not judged is no bar; none judged, no verdict.
        assert_eq!(
            AgainstReferences::of(
                99.0,
                &[st("px4-script", None), st("ardupilot-script", Some(98.0))]
            ),
            Some(AgainstReferences::AtLeastAsGood)
        );
        assert_eq!(AgainstReferences::of(99.0, &[st("px4-script", None)]), None);
    }

    #[test]
    fn ratios_equal_to_rounding_rank_in_the_order_compared() {
        let st = |m: &str, r: f64| Standing {
            model: m.into(),
            worst_p2p_ratio: Some(r),
            flight_form: true,
            why: None,
        };
        let got = ranked(vec![
            st("px4", 1.0),
            st("ardupilot", 1.000_000_000_000_000_2),
            st("poly-t", 0.5),
            st("vakhrameev", 4.2),
        ]);
        let names: Vec<&str> = got.iter().map(|s| s.model.as_str()).collect();
        assert_eq!(names, ["vakhrameev", "px4", "ardupilot", "poly-t"]);
        assert_eq!(ratio_key(1.0), 0);
        assert!(ratio_key(0.999) < 0 && ratio_key(1.001) > 0);
    }

    #[test]
    fn a_custom_polynomial_in_t_of_order_three_is_a_flight_form() {
        use crate::models::presets::CustomOptions;
        use crate::models::regression::DelaySpec;
        let form = |terms: &str, how: &CustomOptions| {
            let choices = ModelChoice::list(&["poly-t".into()], &[terms.into()], how).unwrap();
            flight_form(choices.last().unwrap())
        };
        let plain = CustomOptions::default();
        assert!(form("1,T,T^2,T^3", &plain));
        assert!(form("1,(T-Tref)^2,T-Tref,(T-Tref)^3", &plain));
        assert!(
            !form("1,T,Tdot", &plain),
            "a rate term is left out by the export"
        );
        assert!(!form("1,(T-Tref)^4", &plain), "order 4");
        let delayed = CustomOptions {
            delay: DelaySpec::Fixed { seconds: 60.0 },
            ..CustomOptions::default()
        };
        assert!(!form("1,T", &delayed), "T delayed is not T as measured");
    }

    #[test]
    fn blocks_cover_every_row_once() {
        for n in [0, 1, 3, 4, 5, 17, 1000] {
            let mut next = 0;
            for b in 0..BLOCKS {
                let r = block(n, b);
                assert_eq!(r.start, next, "{n}");
                next = r.end;
            }
            assert_eq!(next, n);
        }
    }

    #[test]
    fn the_worst_part_counts_and_a_missing_one_is_said() {
        assert_eq!(worst(vec![Ok(3.0), Ok(1.5), Ok(2.0)]), (Some(1.5), None));
        assert_eq!(
            worst(vec![Ok(3.0), Err("x".into())]),
            (None, Some("x".into()))
        );
        assert!(worst(vec![Ok(f64::NAN)]).0.is_none());
        assert!(worst(vec![]).0.is_none());
    }
}
