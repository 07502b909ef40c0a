//! Campaigns (several chamber runs of one gyro fitted together) against independent truth:
//! the simulator's runs with known turn-on offsets and known drift, a campaign of one run
//! against the single-run calibration, and leave-one-run-out against the same folds joined
//! and fitted by hand.

use driftlab::judge::campaign::{hysteresis, repeatability};
use driftlab::judge::compare;
use driftlab::judge::metrics::{Evaluation, MeritOptions};
use driftlab::judge::recommend::{self, JudgedOn};
use driftlab::log::Log;
use driftlab::log::campaign::{CampaignError, RunInput, join};
use driftlab::models::campaign::{CampaignOptions, RunRecord, calibrate_campaign};
use driftlab::models::{self, AxisPlan, CheckedRecipe, DriftModel, ModelChoice, Preset};
use driftlab::sim::SimRun;
use driftlab::sim::campaign::{campaign, simulate_campaign};
use std::sync::OnceLock;

/// The simulated runs of a built-in campaign, with the logs read from them.
fn runs_of(name: &str) -> Vec<(SimRun, Log)> {
    let c = campaign(name).expect("a built-in campaign");
    simulate_campaign(&c)
        .into_iter()
        .zip(&c.runs)
        .map(|(sim, run)| {
            let log = sim.to_log(&format!("{name}-{}.csv", run.name));
            (sim, log)
        })
        .collect()
}

fn fog() -> &'static [(SimRun, Log)] {
    static RUNS: OnceLock<Vec<(SimRun, Log)>> = OnceLock::new();
    RUNS.get_or_init(|| runs_of("fog-three-runs"))
}

fn tiny() -> &'static [(SimRun, Log)] {
    static RUNS: OnceLock<Vec<(SimRun, Log)>> = OnceLock::new();
    RUNS.get_or_init(|| runs_of("tiny-three-runs"))
}

fn joined(runs: &[&Log]) -> Log {
    join(
        runs.iter()
            .map(|l| RunInput {
                log: (*l).clone(),
                sha256: String::new(),
            })
            .collect(),
    )
    .expect("one gyro")
}

fn vakhrameev() -> Vec<AxisPlan> {
    vec![AxisPlan::unnamed(
        ModelChoice::Preset(Preset::Vakhrameev),
        CheckedRecipe::default(),
    )]
}

/// The model with its date set, so that two fits compare as fits.
fn dated(model: &DriftModel) -> DriftModel {
    let mut m = model.clone();
    match &mut m {
        DriftModel::Vakhrameev(c) => c.created = "2026-12-05T00:00:00Z".into(),
        DriftModel::Regression(r) => r.created = "2026-12-05T00:00:00Z".into(),
    }
    m
}

fn fitted_runs(log: &mut Log, per_run_offset: bool) -> Vec<RunRecord> {
    let options = CampaignOptions {
        per_run_offset,
        ..CampaignOptions::default()
    };
    let fit = calibrate_campaign(log, &vakhrameev(), &MeritOptions::default(), &options)
        .expect("the campaign fits");
    fit.runs[0].clone()
}

#[test]
fn a_campaign_of_one_run_is_the_single_run_calibration_bit_for_bit() {
    let one = fog()[0].1.clone();
    let mut as_campaign = joined(&[&one]);
    assert!(as_campaign.runs().is_empty());
    let fit = calibrate_campaign(
        &mut as_campaign,
        &vakhrameev(),
        &MeritOptions::default(),
        &CampaignOptions::default(),
    )
    .unwrap();
    let mut alone = one.clone();
    let single = models::calibrate(&mut alone, &vakhrameev(), &MeritOptions::default()).unwrap();
    assert_eq!(
        dated(&fit.axes[0].calibrated.model),
        dated(&single[0].calibrated.model)
    );
    assert!(fit.runs[0].is_empty());
    let err = calibrate_campaign(
        &mut as_campaign,
        &vakhrameev(),
        &MeritOptions::default(),
        &CampaignOptions {
            per_run_offset: true,
            ..CampaignOptions::default()
        },
    )
    .unwrap_err();
    assert!(err.to_string().contains("one run"), "{err}");
}

#[test]
fn each_run_is_timed_and_differentiated_on_its_own() {
    let logs: Vec<&Log> = fog().iter().map(|(_, l)| l).collect();
    let campaign = joined(&logs);
    let timing = campaign.timing();
    let ends: Vec<usize> = campaign.runs().iter().map(|r| r.samples.end).collect();
    for end in &ends {
        assert!(
            timing.segments.iter().any(|s| s.end == *end),
            "a segment ends at every run's end: {:?} {ends:?}",
            timing.segments
        );
    }
    assert!(timing.gaps.is_empty(), "no outage between runs");
    // Each run set apart is the run as read, on its own time.
    for (k, log) in logs.iter().enumerate() {
        let back = campaign.run_log(k).unwrap();
        assert_eq!(back.time_s, log.time_s);
        assert_eq!(back.omega_dph, log.omega_dph);
        assert_eq!(back.temp_c, log.temp_c);
    }
    // The T stages of the campaign are each run's own: the plateaus found are the union of
    // those each run gives alone, moved to the joined time.
    let recipe = CheckedRecipe::default();
    let together = models::vakhrameev::Pipeline::new(&campaign, &recipe).unwrap();
    let mut apart = Vec::new();
    for (k, log) in logs.iter().enumerate() {
        let shift = campaign.runs()[k].time_shift_s;
        let p = models::vakhrameev::Pipeline::new(log, &recipe).unwrap();
        apart.extend(
            p.ranges()
                .iter()
                .map(|r| (r.start_s + shift, r.end_s + shift)),
        );
    }
    let got: Vec<(f64, f64)> = together
        .ranges()
        .iter()
        .map(|r| (r.start_s, r.end_s))
        .collect();
    assert_eq!(got.len(), apart.len());
    for (a, b) in got.iter().zip(&apart) {
        assert!(
            (a.0 - b.0).abs() < 1e-6 && (a.1 - b.1).abs() < 1e-6,
            "{a:?} {b:?}"
        );
    }
}

#[test]
fn turn_on_offsets_built_in_are_recovered() {
    let logs: Vec<&Log> = fog().iter().map(|(_, l)| l).collect();
    // fog-three-runs: the repeat turned on 0.05 °/h above the heating run, the cooling run
    // with none; a further +0.3 °/h given to the cooling run here.
    let mut cooling = logs[2].clone();
    for w in &mut cooling.omega_dph {
        *w += 0.3;
    }
    let built = [0.0, 0.05, 0.3];
    let mut log = joined(&[logs[0], logs[1], &cooling]);
    let read = log.omega_dph.clone();
    let runs = fitted_runs(&mut log, true);
    assert_eq!(log.omega_dph, read, "the log's rates end as read");
    let c: Vec<f64> = runs.iter().map(|r| r.turn_on_offset_dph.unwrap()).collect();
    assert!(
        c.iter().sum::<f64>().abs() < 1e-9,
        "offsets sum to zero: {c:?}"
    );
    for k in 1..3 {
        let (got, want) = (c[k] - c[0], built[k] - built[0]);
        assert!(
            (got - want).abs() < 0.01,
            "run {k}: offset {got} against run 0, built {want} ({c:?})"
        );
    }
    // Without the offsets taken out, the cooling run's +0.3 °/h is in K0 and in its figures.
    let mut plain = joined(&[logs[0], logs[1], &cooling]);
    let without = fitted_runs(&mut plain, false);
    assert!(without.iter().all(|r| r.turn_on_offset_dph.is_none()));
}

#[test]
fn offsets_of_runs_that_share_no_temperature_are_refused() {
    let logs: Vec<&Log> = tiny().iter().map(|(_, l)| l).collect();
    let hot = driftlab::sim::simulate(&driftlab::sim::profile("yan-steps-high").unwrap(), 9);
    let hot = hot.to_log("hot.csv");
    let mut log = joined(&[logs[0], &hot]);
    let err = calibrate_campaign(
        &mut log,
        &vakhrameev(),
        &MeritOptions::default(),
        &CampaignOptions {
            per_run_offset: true,
            ..CampaignOptions::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("hot.csv") && err.contains("shares no plateau temperature"),
        "{err}"
    );
}

/// The mean of `values` (one per logged sample of `sim`) over a plateau on the run's own
/// time.
fn mean_over(sim: &SimRun, values: &[f64], start_s: f64, end_s: f64) -> f64 {
    let picked: Vec<f64> = sim
        .logged_time_s()
        .iter()
        .zip(values)
        .filter(|(t, _)| **t >= start_s && **t <= end_s)
        .map(|(_, w)| *w)
        .collect();
    picked.iter().sum::<f64>() / picked.len() as f64
}

#[test]
fn repeatability_spread_is_the_one_built_in() {
    let sims: Vec<&SimRun> = fog().iter().map(|(s, _)| s).collect();
    let logs: Vec<&Log> = fog().iter().map(|(_, l)| l).collect();
    let mut log = joined(&logs);
    let runs = fitted_runs(&mut log, false);
    // The same plateaus with the simulator's noise-free drift (its offset included) for bias:
    // the spread built in. Each recorded bias is that truth plus the plateau's mean noise,
    // which bounds how far the spread may stand from the one built in.
    let mut truth = runs.clone();
    let mut noise_bound: f64 = 0.0;
    for ((r, t), sim) in runs.iter().zip(truth.iter_mut()).zip(&sims) {
        for (p, q) in r.plateaus.iter().zip(t.plateaus.iter_mut()) {
            let thermal = mean_over(sim, &sim.thermal_dph, p.start_s, p.end_s);
            let noise = mean_over(sim, &sim.noise_dph, p.start_s, p.end_s);
            assert!(
                (p.bias_dph - (thermal + noise)).abs() < 1e-9,
                "{}: bias {} is not the plateau's drift {thermal} and noise {noise}",
                r.name,
                p.bias_dph
            );
            q.bias_dph = thermal;
            noise_bound = noise_bound.max(noise.abs());
        }
    }
    let got = repeatability(&runs, 1.0);
    let want = repeatability(&truth, 1.0);
    assert_eq!(got.len(), want.len());
    assert!(got.len() >= 2, "20 and 60 °C at least: {got:?}");
    for (g, w) in got.iter().zip(&want) {
        assert_eq!(g.runs, w.runs);
        assert!(
            (g.spread_dph - w.spread_dph).abs() <= 2.0 * noise_bound + 1e-12,
            "{} °C: spread {} against {} built in (plateau noise up to {noise_bound})",
            g.temp_c,
            g.spread_dph,
            w.spread_dph
        );
    }
    // The independent truth: the repeat ran the heating run's program with a turn-on 0.05 °/h
    // higher, so plateau for plateau their biases differ by it, to their noise (and the
    // second or two by which the detector places the two runs' plateaus apart).
    assert_eq!(runs[0].plateaus.len(), runs[1].plateaus.len());
    for (h, r) in runs[0].plateaus.iter().zip(&runs[1].plateaus) {
        let diff = r.bias_dph - h.bias_dph;
        assert!(
            (diff - 0.05).abs() <= 2.0 * noise_bound + 0.002,
            "at {} °C the repeat stands {diff} °/h from the heating run, built 0.05",
            h.temp_c
        );
    }
    // The repeat's +0.05 °/h turn-on is in the spread at 60 °C, held by the two heating runs
    // and the cooling run's start.
    let at60 = want.iter().find(|g| (g.temp_c - 60.0).abs() < 1.0).unwrap();
    assert!(at60.spread_dph > 0.045, "{at60:?}");
    // The simulated gyro has no static hysteresis: net of the turn-on offsets, heating and
    // cooling agree at 20 °C to the noise and the settling left.
    let mut log = joined(&logs);
    let net = fitted_runs(&mut log, true);
    let h = hysteresis(&net, 1.0);
    let at20 = h.iter().find(|g| (g.temp_c - 20.0).abs() < 1.0).unwrap();
    assert!(at20.net_of_turn_on_offsets);
    assert!(at20.difference_dph.abs() < 0.01, "{at20:?}");
}

#[test]
fn runs_not_of_one_gyro_are_refused_saying_what_differs() {
    let logs: Vec<&Log> = tiny().iter().map(|(_, l)| l).collect();
    let run = |log: &Log, sha: &str| RunInput {
        log: log.clone(),
        sha256: sha.into(),
    };
    // The same file twice.
    let e = join(vec![run(logs[0], "ab"), run(logs[1], "AB")]).unwrap_err();
    assert!(matches!(e, CampaignError::SameFile { .. }), "{e}");
    // One run's samples under other bytes.
    let e = join(vec![run(logs[0], "a"), run(logs[0], "b")]).unwrap_err();
    assert!(matches!(e, CampaignError::SameRun { .. }), "{e}");
    // Another sampling step.
    let fast_profile = {
        let mut p = driftlab::sim::profile("calibration").unwrap();
        p.sample_rate_hz = 2.0;
        p.program.truncate(2);
        p
    };
    let fast = driftlab::sim::simulate(&fast_profile, 4).to_log("fast.csv");
    let e = join(vec![run(logs[0], "a"), run(&fast, "f")]).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("sampling step") && msg.contains("fast.csv") && msg.contains("0.5 s"),
        "{msg}"
    );
    // Other axes.
    let mut renamed = logs[1].clone();
    renamed.axis = "gz".into();
    let msg = join(vec![run(logs[0], "a"), run(&renamed, "r")])
        .unwrap_err()
        .to_string();
    assert!(msg.contains("gyro axes") && msg.contains("gz"), "{msg}");
    // A run with no plateau.
    let ramps = driftlab::sim::simulate(&driftlab::sim::profile("no-plateaus").unwrap(), 5)
        .to_log("ramps.csv");
    let mut log = join(vec![run(logs[0], "a"), run(&ramps, "r")]).unwrap();
    let err = calibrate_campaign(
        &mut log,
        &vakhrameev(),
        &MeritOptions::default(),
        &CampaignOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("ramps.csv") && err.contains("has no plateau"),
        "{err}"
    );
}

#[test]
fn leave_one_run_out_is_each_fold_fitted_and_judged_by_hand() {
    let logs: Vec<&Log> = tiny().iter().map(|(_, l)| l).collect();
    let campaign = joined(&logs);
    let choices = [
        ModelChoice::Preset(Preset::Vakhrameev),
        ModelChoice::Preset(Preset::PolyT),
    ];
    let recipe = CheckedRecipe::default();
    let merit = MeritOptions::default();
    let reports = compare::compare(&campaign, &[], &choices, &recipe, &merit);
    for (report, choice) in reports.iter().zip(&choices) {
        let loro = report.leave_one_run_out.as_ref().expect("a campaign");
        assert_eq!(loro.runs.len(), 3);
        let (mut ratios, mut raws, mut cors) = (Vec::new(), Vec::new(), Vec::new());
        for k in 0..3 {
            let rest: Vec<&Log> = (0..3).filter(|&j| j != k).map(|j| logs[j]).collect();
            let model = models::fit(&joined(&rest), choice, &recipe).unwrap();
            let c = model.correct(logs[k]).unwrap();
            let e = Evaluation::of_correction(logs[k], &c, &merit).comparison;
            let got = &loro.runs[k];
            assert_eq!(got.run, logs[k].source);
            assert_eq!(got.p2p_ratio, Some(e.p2p_ratio), "{} run {k}", report.model);
            assert_eq!(got.corrected_p2p_dph, Some(e.corrected.p2p_dph));
            ratios.push(e.p2p_ratio);
            raws.push(e.raw.p2p_dph);
            cors.push(e.corrected.p2p_dph);
        }
        // The mean is the ratio of the mean figures: one run's large ratio cannot hide a run
        // made worse.
        let mean = (raws.iter().sum::<f64>() / 3.0) / (cors.iter().sum::<f64>() / 3.0);
        let worst = ratios.iter().copied().fold(f64::INFINITY, f64::min);
        assert_eq!(loro.mean_p2p_ratio, Some(mean));
        assert_eq!(loro.worst_p2p_ratio, Some(worst));
    }
    // With no held-out log, the recommendation is judged on the runs left out.
    let rec = recommend::recommend(&campaign, &reports, &choices, &recipe, &merit, &|| true)
        .expect("judged");
    assert!(matches!(rec.judged_on, JudgedOn::RunsLeftOut { ref runs } if runs.len() == 3));
    assert!(rec.caution.is_none() || !rec.caution.as_deref().unwrap().contains("blocks"));
    let best = reports
        .iter()
        .max_by(|a, b| {
            let w =
                |r: &compare::ModelReport| r.leave_one_run_out.as_ref().unwrap().worst_p2p_ratio;
            w(a).partial_cmp(&w(b)).unwrap()
        })
        .unwrap();
    assert_eq!(rec.model, best.model);
    // A log of one run has nothing to leave out.
    let single = compare::compare(logs[0], &[], &choices[..1], &recipe, &merit);
    assert!(single[0].leave_one_run_out.is_none());
}

#[test]
fn a_unit_fitted_on_a_campaign_keeps_each_axis_record_through_its_file() {
    use driftlab::files::calibration::{unit_from_json, unit_to_json};
    use driftlab::models::{AxisModel, UnitCalibration};
    let read = |name: &str| {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("sample_logs")
            .join(name);
        driftlab::log::ingest::read_path(&path, &driftlab::log::ingest::ReadOptions::default())
            .unwrap()
    };
    let (a, b) = (read("imu3-calibration.csv"), read("imu3-validation.csv"));
    assert_eq!(a.axis_names().len(), 3);
    let mut log = joined(&[&a, &b]);
    let plans: Vec<AxisPlan> = log
        .axis_names()
        .into_iter()
        .map(|name| AxisPlan {
            name,
            choice: ModelChoice::Preset(Preset::Vakhrameev),
            recipe: CheckedRecipe::default(),
        })
        .collect();
    let options = CampaignOptions {
        per_run_offset: true,
        ..CampaignOptions::default()
    };
    let fit = calibrate_campaign(&mut log, &plans, &MeritOptions::default(), &options).unwrap();
    let unit = UnitCalibration {
        axes: fit
            .axes
            .iter()
            .zip(&fit.runs)
            .map(|(f, runs)| {
                let mut model = dated(&f.calibrated.model);
                model.source_mut().runs = runs.clone();
                AxisModel::gyro(f.name.clone(), f.rate_column.clone(), model)
            })
            .collect(),
    };
    // The axes' records differ (their own biases and offsets): each is kept beside its axis.
    assert_ne!(fit.runs[0], fit.runs[1]);
    let text = unit_to_json(&unit).unwrap();
    let back = unit_from_json(std::path::Path::new("unit.json"), &text).unwrap();
    for (x, y) in unit.axes.iter().zip(&back.axes) {
        assert_eq!(
            x.model.source().runs,
            y.model.source().runs,
            "axis {}",
            x.name
        );
    }
    assert_eq!(back, unit);
}

#[test]
fn self_heating_counts_from_each_run_s_power_on() {
    // Two laser-gyro runs, each powered on at its start: a model with the self-heating term
    // fits the same whichever run comes first.
    let p = driftlab::sim::profile("laser-gyro").unwrap();
    let a = driftlab::sim::simulate(&p, 1).to_log("lg-1.csv");
    let b = driftlab::sim::simulate(&p, 2).to_log("lg-2.csv");
    let sukhanov = ModelChoice::Preset(Preset::Sukhanov);
    let recipe = CheckedRecipe::default();
    let ab = models::fit(&joined(&[&a, &b]), &sukhanov, &recipe).unwrap();
    let ba = models::fit(&joined(&[&b, &a]), &sukhanov, &recipe).unwrap();
    let coefficients = |m: &DriftModel| match m {
        DriftModel::Regression(r) => (r.model.coefficients.clone(), r.model.lambda_s),
        DriftModel::Vakhrameev(_) => unreachable!("sukhanov is a regression"),
    };
    let ((ca, la), (cb, lb)) = (coefficients(&ab), coefficients(&ba));
    // Alike to the λ search's own tolerance (the order of the sums differs); a clock that
    // ran from the first run's start moved λ by a fifth and the coefficients by a tenth.
    for (x, y) in ca.iter().zip(&cb) {
        assert!((x - y).abs() <= 1e-3 * x.abs(), "{ca:?} against {cb:?}");
    }
    let (la, lb) = (la.unwrap(), lb.unwrap());
    assert!((la - lb).abs() <= 0.01 * la, "λ {la} s against {lb} s");
}

/// Why `runs` are not joined (a joined log is not printed: it is millions of numbers).
fn refused(runs: Vec<RunInput>) -> CampaignError {
    match join(runs) {
        Ok(log) => panic!("joined {}", log.source),
        Err(e) => e,
    }
}

/// `log` with its temperature read from another column: its values in `temp_c`, the
/// column the reader recorded renamed `name` (the chamber's air, where the gyro's sensor is
/// not in the file).
fn temperature_from(log: &Log, name: &str, values: Vec<f64>) -> Log {
    let mut out = log.clone();
    out.temp_c = values;
    for c in &mut out.info.columns {
        if c.role == driftlab::log::ColumnRole::Temperature {
            c.name = name.to_string();
        }
    }
    out
}

#[test]
fn runs_whose_temperatures_are_other_sensors_are_refused_naming_both_columns() {
    let (heating, repeat) = (&fog()[0].1, &fog()[1].1);
    let run = |log: &Log| RunInput {
        log: log.clone(),
        sha256: String::new(),
    };
    // The repeat logged with only the chamber's air: same unit, another sensor.
    let air = repeat.channel("temp_chamber_c").unwrap().values.clone();
    let chamber = temperature_from(repeat, "temp_chamber_c", air);
    let e = refused(vec![run(heating), run(&chamber)]);
    assert!(matches!(e, CampaignError::Differs { .. }), "{e}");
    let msg = e.to_string();
    assert!(
        msg.contains("temp_chamber_c")
            && msg.contains("temp_c")
            && msg.contains("temp_col")
            && msg.contains(&heating.source),
        "{msg}"
    );
    // Two numbered sensors, whatever they are, are not one.
    let t1 = temperature_from(heating, "T1 [°C]", heating.temp_c.clone());
    let t2 = temperature_from(repeat, "T2 [°C]", repeat.temp_c.clone());
    refused(vec![run(&t1), run(&t2)]);
    // The gyro's own sensor under another spelling is the same sensor.
    for name in ["Temperature [°C]", "gyro_temp_c", "TEMP_C"] {
        let renamed = temperature_from(repeat, name, repeat.temp_c.clone());
        let log = join(vec![run(heating), run(&renamed)]).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(log.runs().len(), 2);
    }
}

/// A run whose first `head` samples are `first`'s and the rest `second`'s (a logger's file
/// continued from a copy of the run before), named `name`.
fn spliced(first: &Log, second: &Log, head: usize, name: &str) -> Log {
    let mut out = second.clone();
    out.source = name.to_string();
    out.time_s[..head].copy_from_slice(&first.time_s[..head]);
    out.omega_dph[..head].copy_from_slice(&first.omega_dph[..head]);
    out.temp_c[..head].copy_from_slice(&first.temp_c[..head]);
    out
}

#[test]
fn a_run_holding_part_of_another_run_is_refused_with_the_share() {
    let (heating, repeat, cooling) = (&fog()[0].1, &fog()[1].1, &fog()[2].1);
    let run = |log: &Log| RunInput {
        log: log.clone(),
        sha256: String::new(),
    };
    // The honest campaign joins.
    assert!(join(vec![run(heating), run(repeat), run(cooling)]).is_ok());
    // Half of the second run is the first's: its plateaus would count twice, and the
    // repeatability be read from a plateau and its own copy.
    let half = spliced(heating, repeat, 20_000, "spliced.csv");
    let e = refused(vec![run(heating), run(&half), run(cooling)]);
    let CampaignError::SharesSamples {
        ref first,
        ref second,
        share,
        ..
    } = e
    else {
        panic!("{e}");
    };
    assert_eq!(
        (first.as_str(), second.as_str()),
        (heating.source.as_str(), "spliced.csv")
    );
    let truth = 20_000.0 / repeat.len() as f64;
    assert!((share - truth).abs() < 0.1, "{share} against {truth}");
    let msg = e.to_string();
    assert!(
        msg.contains("spliced.csv") && msg.contains(&heating.source),
        "{msg}"
    );
    assert!(
        msg.contains(&format!("{} %", (share * 100.0).round())),
        "{msg}"
    );
    // Given the other way round, the first run is the one that holds part of the other.
    let e = refused(vec![run(&half), run(heating)]);
    assert!(matches!(e, CampaignError::SharesSamples { .. }), "{e}");
    // A tenth of it is still a plateau or two counted twice.
    let tenth = spliced(heating, repeat, 4_000, "tenth.csv");
    let e = refused(vec![run(heating), run(&tenth)]);
    assert!(matches!(e, CampaignError::SharesSamples { .. }), "{e}");
}

#[test]
fn runs_of_one_file_name_are_named_by_the_folders_that_tell_them_apart() {
    use driftlab::log::campaign::run_names;
    use std::path::PathBuf;
    let p = |s: &str| PathBuf::from(s);
    assert_eq!(
        run_names(&[
            p("data/day1/run.csv"),
            p("data/day2/run.csv"),
            p("data/cold.csv")
        ]),
        ["day1/run.csv", "day2/run.csv", "cold.csv"]
    );
    // Only as far up as they differ, each on its own.
    assert_eq!(
        run_names(&[p("/a/x/run.csv"), p("/b/x/run.csv"), p("/a/y/run.csv")]),
        ["a/x/run.csv", "b/x/run.csv", "y/run.csv"]
    );
    assert_eq!(
        run_names(&[p("run.csv"), p("old/run.csv")]),
        ["run.csv", "old/run.csv"]
    );
    // Names that already differ are the files' names, as before.
    assert_eq!(
        run_names(&[p("/x/heating.csv"), p("/y/cooling.csv")]),
        ["heating.csv", "cooling.csv"]
    );
    assert_eq!(run_names(&[p("./day1/./run.csv")]), ["run.csv"]);
}

#[test]
fn a_run_that_records_no_drone_gyro_joins_with_a_warning_that_it_is_unchecked() {
    use driftlab::log::{DroneGyro, ProblemKind};
    let logs: Vec<&Log> = tiny().iter().map(|(_, l)| l).collect();
    let of_gyro = |log: &Log, device: u32| {
        let mut out = log.clone();
        out.info.instance = Some(DroneGyro {
            px4_device_id: Some(device),
            ..DroneGyro::numbered(0)
        });
        out
    };
    let run = |log: Log| RunInput {
        log,
        sha256: String::new(),
    };
    // A drone log's gyro beside a CSV (one `convert` wrote of it, or of another flight):
    // which gyro the CSV is cannot be checked, and is said.
    let ulog = of_gyro(logs[0], 2_424_842);
    let joined = join(vec![run(ulog.clone()), run(logs[1].clone())]).expect("joined");
    let said: Vec<&str> = joined
        .info
        .problems
        .iter()
        .filter(|p| p.kind == ProblemKind::Unchecked)
        .map(|p| p.message.as_str())
        .collect();
    assert_eq!(said.len(), 1, "{:?}", joined.info.problems);
    assert!(
        said[0].contains(&logs[1].source) && said[0].contains("device_id 2424842"),
        "{}",
        said[0]
    );
    // The campaign is of the one gyro a run records, whichever run it is.
    let csv_first = join(vec![run(logs[1].clone()), run(ulog.clone())]).expect("joined");
    assert_eq!(csv_first.info.instance, ulog.info.instance);
    // Two runs that record other gyros are refused, though a CSV stands between them.
    let other = of_gyro(logs[2], 3_670_050);
    let e = refused(vec![run(ulog), run(logs[1].clone()), run(other)]);
    let msg = e.to_string();
    assert!(
        matches!(
            e,
            CampaignError::Differs {
                what: "drone-log gyro",
                ..
            }
        ) && msg.contains("2424842")
            && msg.contains("3670050")
            && !msg.contains("no drone log"),
        "{msg}"
    );
}

/// The campaign's point, against the simulator's truth: its 13 plateaus at 7 temperatures hold
/// a K0 spline that no single run's 4 or 5 plateaus at 3 to 5 temperatures can, and the one
/// calibration on all three runs corrects two held-out programs of the same gyro better than
/// any run's own calibration does, with K0 parabolic (the default), piecewise-linear or spline
/// (docs/campaigns.md gives the figures).
#[test]
fn a_campaign_with_a_spline_k0_beats_every_run_alone_held_out() {
    use driftlab::models::approx::{ApproxKind, ApproxSpec};
    let held: Vec<Log> = [("validation", 11), ("yan-full-range", 12)]
        .iter()
        .map(|(name, seed)| {
            driftlab::sim::simulate(&driftlab::sim::profile(name).unwrap(), *seed)
                .to_log(&format!("{name}.csv"))
        })
        .collect();
    let merit = MeritOptions::default();
    let plan = |k0: ApproxSpec| {
        let recipe = driftlab::models::recipe::Recipe {
            k0,
            ..Default::default()
        };
        vec![AxisPlan::unnamed(
            ModelChoice::Preset(Preset::Vakhrameev),
            recipe.checked().unwrap(),
        )]
    };
    let spline = ApproxSpec {
        knots: 6,
        ..ApproxSpec::of(ApproxKind::Spline)
    };
    // Corrected peak-to-peak on each held-out log of a calibration fitted on `runs`.
    let held_out = |runs: &[&Log], k0: ApproxSpec| -> Vec<f64> {
        let mut log = joined(runs);
        let fit = calibrate_campaign(&mut log, &plan(k0), &merit, &CampaignOptions::default())
            .expect("fits");
        let model = &fit.axes[0].calibrated.model;
        held.iter()
            .map(|h| {
                let c = model.correct(h).unwrap();
                Evaluation::of_correction(h, &c, &merit)
                    .comparison
                    .corrected
                    .p2p_dph
            })
            .collect()
    };
    let logs: Vec<&Log> = fog().iter().map(|(_, l)| l).collect();
    let campaign = held_out(&logs, spline.clone());
    for one in &logs {
        for k0 in [
            ApproxSpec::of(ApproxKind::Parabolic),
            ApproxSpec {
                knots: 5,
                ..ApproxSpec::of(ApproxKind::Pwl)
            },
            spline.clone(),
        ] {
            let alone = held_out(&[one], k0.clone());
            for (h, (c, a)) in held.iter().zip(campaign.iter().zip(&alone)) {
                assert!(
                    c < a,
                    "on {}: the campaign {c} °/h, {} alone with K0 {:?} {a} °/h",
                    h.source,
                    one.source,
                    k0.kind
                );
            }
        }
    }
}
