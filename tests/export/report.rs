//! The test report: calibrated on the bundled calibration log, judged on it (in-sample) and on
//! the validation log (held out). The figures must be real PNG and SVG files with their axis
//! labels, and the page must carry the gyro, both logs with their labels, the figures of merit
//! `metrics::Evaluation::of` computes, and nothing from outside itself.

use driftlab::Log;
use driftlab::export::report::figures::{DrawError, FigureError};
use driftlab::export::report::{self, AllanCurve, ReportOptions, html};
use driftlab::files::calibration;
use driftlab::judge::metrics::{Evaluation, MeritOptions};
use driftlab::log::ingest::{self, ReadOptions};
use driftlab::models::fitted::DriftModel;
use driftlab::models::presets::ModelChoice;
use driftlab::models::recipe::Recipe;
use driftlab::models::regression::terms::parse_terms;
use driftlab::models::regression::{DelaySpec, LagSpec, RegressionSpec};
use driftlab::models::vakhrameev::{self, Calibration};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

const GYRO: &str = "FOG-REPORT-7";

fn sample(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("sample_logs")
        .join(name)
}

fn read(path: &Path) -> Log {
    ingest::read_path(path, &ReadOptions::default()).expect("sample log reads")
}

/// The calibration `driftlab calibrate --gyro-id FOG-REPORT-7` makes of the calibration log.
fn calibration() -> &'static Calibration {
    static CAL: OnceLock<Calibration> = OnceLock::new();
    CAL.get_or_init(|| {
        let path = sample("calibration.csv");
        let recipe = Recipe {
            gyro_id: GYRO.into(),
            ..Recipe::default()
        };
        let mut cal = vakhrameev::fit(&read(&path), &recipe.clone().checked().unwrap())
            .expect("fits")
            .calibration;
        cal.source.name = "calibration.csv".into();
        cal.source.sha256 = calibration::sha256_file(&path).unwrap();
        cal
    })
}

fn logs() -> Vec<(PathBuf, Log)> {
    ["calibration.csv", "validation.csv"]
        .into_iter()
        .map(|n| {
            let p = sample(n);
            let log = read(&p);
            (p, log)
        })
        .collect()
}

/// Width and height from a PNG's IHDR, after checking the signature, and every row decoded.
fn png_size(path: &Path) -> (u32, u32) {
    let file = std::io::BufReader::new(std::fs::File::open(path).unwrap());
    let mut reader = png::Decoder::new(file).read_info().expect("a PNG header");
    let mut buf = vec![0; reader.output_buffer_size().expect("a sane size")];
    let info = reader.next_frame(&mut buf).expect("PNG data decodes");
    // Not a blank canvas: a figure has dark text and lines on white.
    let dark = buf.chunks(3).filter(|p| p.iter().all(|&c| c < 100)).count();
    assert!(
        dark > 1000,
        "{} looks blank ({dark} dark pixels)",
        path.display()
    );
    (info.width, info.height)
}

/// The text of an SVG file after a light well-formedness check (one root, tags balanced).
fn svg_text(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    let t = text.trim();
    assert!(
        t.starts_with("<svg") && t.ends_with("</svg>"),
        "{}",
        path.display()
    );
    let opens = t.matches("<svg").count();
    let closes = t.matches("</svg>").count();
    assert_eq!((opens, closes), (1, 1));
    let texts = (t.matches("<text").count(), t.matches("</text>").count());
    assert_eq!(texts.0, texts.1, "unbalanced <text> in {}", path.display());
    assert!(texts.0 > 10, "too little text in {}", path.display());
    text
}

/// The figure-of-merit table of one log in the page.
fn merit_table<'a>(html: &'a str, log: &str) -> &'a str {
    let start = html
        .find(&format!("<table class=\"merit\" data-log=\"{log}\""))
        .unwrap_or_else(|| panic!("no figures of merit for {log}"));
    let end = start + html[start..].find("</table>").unwrap();
    &html[start..end]
}

fn cell(v: f64) -> String {
    format!("<td class=\"num\">{v:.4}</td>")
}

fn ratio_cell(r: f64) -> String {
    format!("<td class=\"num\">{r:.2}×</td>")
}

/// Everything a page could pull from elsewhere: links, sources, imports, scripts.
fn assert_self_contained(html: &str) {
    for needle in [
        "src=", "href=", "<link", "<script", "@import", "url(", "<iframe", "<object",
    ] {
        assert!(
            !html.contains(needle),
            "the page refers outside itself: {needle}"
        );
    }
}

#[test]
fn report_of_in_sample_and_held_out_logs() {
    let cal = calibration();
    let logs = logs();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("report");
    let summary = report::write(cal, &logs, &out, &ReportOptions::default()).unwrap();

    // Files: the calibration's figures and each log's, as PNG and SVG, and the page.
    for stem in [
        "k0",
        "k1",
        "k2",
        "temperature-calibration",
        "drift-calibration",
        "temperature-validation",
        "drift-validation",
    ] {
        for ext in ["png", "svg"] {
            let p = out.join(format!("{stem}.{ext}"));
            assert!(summary.files.contains(&p), "{} not listed", p.display());
            assert!(p.is_file(), "{} missing", p.display());
        }
        assert_eq!(png_size(&out.join(format!("{stem}.png"))), (1200, 700));
    }
    assert!(summary.files.iter().all(|f| f.is_file()));
    assert_eq!(summary.html, out.join("report.html"));

    // Axis labels with units, and legends.
    let want = [
        ("k0", vec!["temperature T, °C", "K0, °/h", "plateau means"]),
        (
            "k1",
            vec![
                "rate of temperature dT/dt, °C/s",
                "K1, (°/h)/(°C/s)",
                "K1+ fit",
                "K1− fit",
                "pointwise K1+",
            ],
        ),
        (
            "k2",
            vec![
                "second derivative of temperature d²T/dt², °C/s²",
                "K2, (°/h)/(°C/s²)",
                "K2+ fit",
                "K2− fit",
            ],
        ),
        (
            "temperature-calibration",
            vec!["time, h", "temperature, °C", "plateaus used for K0"],
        ),
        (
            "drift-validation",
            vec![
                "time, h",
                "gyro rate Ω, °/h",
                "raw, 100-s moving average",
                "corrected, 100-s moving average",
            ],
        ),
    ];
    for (stem, labels) in want {
        let svg = svg_text(&out.join(format!("{stem}.svg")));
        for l in labels {
            assert!(svg.contains(l), "{stem}.svg lacks \"{l}\"");
        }
    }

    // The page.
    let html = std::fs::read_to_string(&summary.html).unwrap();
    assert!(html.starts_with("<!DOCTYPE html>"));
    assert!(html.contains(&format!("<b class=\"gyro-id\">{GYRO}</b>")));
    assert!(html.contains(&cal.source.sha256));
    assert!(html.contains(&cal.created));
    assert_self_contained(&html);
    // Every figure inline: k0, k1, k2, and temperature, drift and Allan deviation per log.
    assert_eq!(html.matches("<figure>").count(), 9);
    assert_eq!(html.matches("<svg ").count(), 9);

    let merit = MeritOptions {
        filter_s: cal.recipe.filter_s,
        ..MeritOptions::default()
    };
    for ((path, log), (name, set)) in logs.iter().zip([
        ("calibration.csv", "in-sample"),
        ("validation.csv", "held-out"),
    ]) {
        let table = merit_table(&html, name);
        assert!(
            table.contains(&format!("data-set=\"{set}\"")),
            "{name} should be {set}"
        );
        let e = Evaluation::of(cal, log, &merit);
        let c = &e.comparison;
        for (raw, cor) in [
            (c.raw.p2p_dph, c.corrected.p2p_dph),
            (c.raw.std_dph, c.corrected.std_dph),
            (c.raw.win_mean_max_abs_dph, c.corrected.win_mean_max_abs_dph),
            (c.raw.win_rms_mean_dph, c.corrected.win_rms_mean_dph),
        ] {
            let row = format!("{}{}", cell(raw), cell(cor));
            assert!(table.contains(&row), "{name}: no row {row}");
        }
        for r in [c.p2p_ratio, c.std_ratio, c.win_mean_ratio, c.win_rms_ratio] {
            assert!(table.contains(&ratio_cell(r)), "{name}: no ratio {r:.2}");
        }
        let reported = summary
            .logs
            .iter()
            .find(|l| &l.path == path)
            .expect("log in summary");
        assert_eq!(reported.evaluation, e);
        assert_eq!(reported.in_sample, set == "in-sample");
    }
    // The tags a reader sees.
    assert!(html.contains("calibration.csv <span class=\"tag in-sample\">in-sample</span>"));
    assert!(html.contains("validation.csv <span class=\"tag held-out\">held out</span>"));
    // The Allan figures of both logs, with their log-log axes.
    assert!(!html.contains("Allan deviation: not computed"));
    assert_eq!(html.matches("averaging time τ, s").count(), 2);
}

#[test]
fn allan_curves_given_are_drawn_log_log() {
    let cal = calibration();
    let logs: Vec<_> = logs().into_iter().skip(1).collect();
    let tau: Vec<f64> = (0..30).map(|k| 10f64.powf(k as f64 / 7.0)).collect();
    let raw: Vec<f64> = tau
        .iter()
        .map(|t| 0.3 / t.sqrt() + 0.002 * t.sqrt())
        .collect();
    let cor: Vec<f64> = tau
        .iter()
        .map(|t| 0.3 / t.sqrt() + 0.0002 * t.sqrt())
        .collect();
    let curves = vec![
        AllanCurve {
            label: "raw".into(),
            tau_s: tau.clone(),
            adev_dph: raw,
        },
        AllanCurve {
            label: "corrected".into(),
            tau_s: tau,
            adev_dph: cor,
        },
    ];
    let dir = tempfile::tempdir().unwrap();
    let opts = ReportOptions {
        allan: Some(vec![Some(curves)]),
        ..ReportOptions::default()
    };
    let summary = report::write(cal, &logs, dir.path(), &opts).unwrap();
    let svg = svg_text(&dir.path().join("allan-validation.svg"));
    for l in [
        "averaging time τ, s",
        "Allan deviation σ(τ), °/h",
        "raw",
        "corrected",
    ] {
        assert!(svg.contains(l), "allan svg lacks \"{l}\"");
    }
    // Decades labelled as numbers a reader writes.
    for tick in ["0.01", "0.1", "1", "10", "100", "1000"] {
        assert!(
            svg.lines().any(|l| l.trim() == tick),
            "allan svg lacks the tick {tick}"
        );
    }
    assert_eq!(
        png_size(&dir.path().join("allan-validation.png")),
        (1200, 700)
    );
    let html = std::fs::read_to_string(&summary.html).unwrap();
    assert!(!html.contains("Allan deviation: not computed"));
    // Without the calibration log, every log is held out and the page says why.
    assert!(html.contains("validation.csv <span class=\"tag held-out\">held out</span>"));
    assert!(!html.contains("tag in-sample\">in-sample</span>"));
    assert!(html.contains("is not among the logs"));
}

#[test]
fn odd_logs_give_a_report_not_a_panic() {
    let cal = calibration();
    let dir = tempfile::tempdir().unwrap();
    let n = 400;
    let t: Vec<f64> = (0..n).map(f64::from).collect();
    let mut w: Vec<f64> = t.iter().map(|x| (x * 0.1).sin()).collect();
    w[17] = f64::NAN;
    // A rate no gyro reads, and one held at zero: left out with why, not drawn.
    let mut inf = w.clone();
    inf[18] = f64::INFINITY;
    let logs = vec![
        (
            dir.path().join("empty.csv"),
            Log::from_columns("empty", vec![], vec![], vec![]),
        ),
        (
            dir.path().join("one.csv"),
            Log::from_columns("one", vec![0.0], vec![1.0], vec![20.0]),
        ),
        (
            dir.path().join("flat.csv"),
            Log::from_columns(
                "flat",
                t.clone(),
                t.iter().map(|x| 1e-3 * x).collect(),
                vec![20.0; n as usize],
            ),
        ),
        (
            dir.path().join("stuck.csv"),
            Log::from_columns(
                "stuck",
                t.clone(),
                vec![0.0; n as usize],
                vec![20.0; n as usize],
            ),
        ),
        (
            dir.path().join("inf.csv"),
            Log::from_columns("inf", t.clone(), inf, vec![20.0; n as usize]),
        ),
        (
            dir.path().join("nan.csv"),
            Log::from_columns("nan", t, w, vec![f64::NAN; n as usize]),
        ),
        // Clock time: the axis counts from the first sample.
        (
            dir.path().join("clock.csv"),
            Log::from_columns(
                "clock",
                (0..n).map(|i| 1.7e9 + f64::from(i)).collect(),
                (0..n).map(|i| 0.1 + 1e-3 * f64::from(i)).collect(),
                (0..n).map(|i| 20.0 + 0.01 * f64::from(i)).collect(),
            ),
        ),
        // The same stem twice: the figures must not overwrite each other.
        (
            dir.path().join("a").join("flat.csv"),
            Log::from_columns(
                "flat",
                vec![0.0, 1.0, 2.0],
                vec![0.0, 0.1, 0.0],
                vec![1.0, 2.0, 3.0],
            ),
        ),
    ];
    let out = dir.path().join("odd");
    let summary = report::write(cal, &logs, &out, &ReportOptions::default()).unwrap();
    assert!(out.join("drift-flat.png").is_file());
    assert!(out.join("drift-flat-2.png").is_file());
    assert_eq!(summary.logs.len(), 6, "{:?}", summary.left_out);
    // Left out, each with the reason evaluate refuses it with, and not drawn.
    let left: Vec<(&str, usize, &str)> = summary
        .left_out
        .iter()
        .map(|l| (l.name.as_str(), l.index, l.reason.as_str()))
        .collect();
    assert_eq!(left.len(), 2, "{left:?}");
    assert_eq!((left[0].0, left[0].1), ("stuck.csv", 3));
    assert!(left[0].2.contains("never changes"), "{left:?}");
    assert_eq!((left[1].0, left[1].1), ("inf.csv", 4));
    assert!(left[1].2.contains("holds 1 reading beyond"), "{left:?}");
    assert!(!out.join("drift-stuck.png").exists());
    assert!(!out.join("drift-inf.png").exists());
    let clock = svg_text(&out.join("temperature-clock.svg"));
    assert!(clock.contains("time, s from the first sample"));
    assert!(summary.logs.iter().all(|l| !l.in_sample));
    let html = std::fs::read_to_string(&summary.html).unwrap();
    assert_self_contained(&html);

    // No logs at all: the calibration alone.
    let summary = report::write(
        cal,
        &[],
        &dir.path().join("none"),
        &ReportOptions::default(),
    )
    .unwrap();
    assert!(summary.html.is_file());

    // A folder that cannot be made is an error naming it.
    let blocker = dir.path().join("file");
    std::fs::write(&blocker, "x").unwrap();
    let err = report::write(cal, &[], &blocker.join("sub"), &ReportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(err.contains("file"), "{err}");
}

fn driftlab(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_driftlab"))
        .args(args)
        .output()
        .expect("driftlab runs")
}

#[test]
fn cli_report_writes_the_files_it_lists() {
    let dir = tempfile::tempdir().unwrap();
    let cal = dir.path().join("cal.json").display().to_string();
    let cal_log = sample("calibration.csv").display().to_string();
    let val_log = sample("validation.csv").display().to_string();
    let out = driftlab(&["calibrate", &cal_log, "--out", &cal, "--gyro-id", GYRO]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );

    let rep = dir.path().join("rep");
    let rep_s = rep.display().to_string();
    let out = driftlab(&["report", &cal, &cal_log, &val_log, "--out", &rep_s]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert!(stdout.contains("calibration.csv (in-sample)"), "{stdout}");
    assert!(stdout.contains("validation.csv (held out)"), "{stdout}");
    let listed: Vec<&str> = stdout
        .lines()
        .filter_map(|l| l.strip_prefix("  "))
        .collect();
    // k0, k1, k2 and temperature, drift, Allan per log, each as PNG and SVG, and the page.
    assert_eq!(listed.len(), 19, "{stdout}");
    for f in &listed {
        assert!(Path::new(f).is_file(), "listed but missing: {f}");
    }
    let html = std::fs::read_to_string(rep.join("report.html")).unwrap();
    assert!(html.contains(GYRO));

    // Errors are messages and a failure status, never a panic.
    let out = driftlab(&["report", &cal, "no-such-log.csv", "--out", &rep_s]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("no-such-log.csv") && !err.contains("panicked"),
        "{err}"
    );
    let out = driftlab(&["report", &cal, "--out", &rep_s]);
    assert!(!out.status.success(), "a report needs at least one log");
    let out = driftlab(&["report", &val_log, &cal_log, "--out", &rep_s]);
    assert!(!out.status.success(), "a log is not a calibration");
}

// ---- Regression models -----------------------------------------------------------------

/// A regression model fitted on the laser gyro's first run, with searches for λ, τd per
/// temperature band and the lag, and its source recorded as `driftlab calibrate` records it.
fn regression_model(terms: &str, searches: bool) -> DriftModel {
    let path = sample("laser-gyro.csv");
    let log = read(&path);
    let mut spec = RegressionSpec::new("custom-rlg", parse_terms(terms).unwrap());
    if searches {
        spec.delay = DelaySpec::Bands {
            bands: 2,
            max_s: 900.0,
        };
        spec.lag = LagSpec::Search {
            max_s: 1800.0,
            with_temperature: false,
        };
    }
    let recipe = Recipe {
        gyro_id: "RLG-REPORT-3".into(),
        ..Recipe::default()
    };
    let mut model = driftlab::models::fit(
        &log,
        &ModelChoice::Custom(spec),
        &recipe.clone().checked().unwrap(),
    )
    .unwrap();
    let src = model.source_mut();
    src.name = "laser-gyro.csv".into();
    src.sha256 = calibration::sha256_file(&path).unwrap();
    model
}

fn laser_logs() -> Vec<(PathBuf, Log)> {
    ["laser-gyro.csv", "laser-gyro-2.csv"]
        .into_iter()
        .map(|n| {
            let p = sample(n);
            let log = read(&p);
            (p, log)
        })
        .collect()
}

#[test]
fn regression_report_shows_coefficients_searches_and_every_log() {
    let model = regression_model("1,T,Tdot,T*Tdot,dT,selfheat,ch:laser_power_mw", true);
    let DriftModel::Regression(rc) = &model else {
        panic!("not a regression model");
    };
    let m = &rc.model;
    assert!(m.searches.len() >= 3, "{:?}", m.searches);
    let logs = laser_logs();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("report");
    let summary = report::write_model(&model, &logs, &out, &ReportOptions::default()).unwrap();

    for stem in [
        "costs",
        "temperature-laser-gyro",
        "drift-laser-gyro",
        "allan-laser-gyro",
        "temperature-laser-gyro-2",
        "drift-laser-gyro-2",
        "allan-laser-gyro-2",
    ] {
        for ext in ["png", "svg"] {
            let p = out.join(format!("{stem}.{ext}"));
            assert!(summary.files.contains(&p), "{} not listed", p.display());
            assert!(p.is_file(), "{} missing", p.display());
        }
        assert_eq!(png_size(&out.join(format!("{stem}.png"))), (1200, 700));
    }
    let costs = svg_text(&out.join("costs.svg"));
    for c in &m.searches {
        assert!(
            costs.contains(&c.parameter),
            "costs.svg lacks {}",
            c.parameter
        );
    }
    assert!(costs.contains("RMS residual, °/h") && costs.contains("chosen:"));
    assert!(summary.files.iter().all(|f| f.is_file()));

    // In-sample by the recorded hash, held out otherwise.
    assert_eq!(
        summary.logs.iter().map(|l| l.in_sample).collect::<Vec<_>>(),
        vec![true, false]
    );
    let html = std::fs::read_to_string(&summary.html).unwrap();
    assert!(html.starts_with("<!DOCTYPE html>"));
    assert_self_contained(&html);
    assert!(html.contains("<b class=\"gyro-id\">RLG-REPORT-3</b>"));
    assert!(html.contains("<b class=\"model-name\">custom-rlg</b>"));
    // Every coefficient ± its standard error, as the page prints them.
    for ((name, c), se) in m.names.iter().zip(&m.coefficients).zip(&m.std_errors) {
        let row = format!(
            "<td class=\"num\">{}</td><td class=\"num\">± {}</td>",
            html::fmt_coef(*c),
            html::fmt_se(*se)
        );
        assert!(
            html.contains(&row),
            "coefficient {name}: {row} not in the page"
        );
    }
    assert!(html.contains(&format!("{} s", html::fmt_num(m.lambda_s.unwrap()))));
    assert!(html.contains(&format!("τ = {} s", html::fmt_num(m.lag_s.unwrap()))));
    for p in &m.delay.points {
        assert!(html.contains(&format!(
            "{} s at {} °C",
            html::fmt_num(p[1]),
            html::fmt_num(p[0])
        )));
    }
    assert!(html.contains("laser_power_mw"));
    assert!(html.contains(&format!("{} samples, RMS residual", m.stats.n)));
    // The figures of merit of each log are those of its correction.
    for (path, log) in &logs {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let e =
            Evaluation::of_correction(log, &model.correct(log).unwrap(), &MeritOptions::default());
        let table = merit_table(&html, &name);
        assert!(table.contains(&cell(e.comparison.raw.p2p_dph)), "{name}");
        assert!(
            table.contains(&cell(e.comparison.corrected.p2p_dph)),
            "{name}"
        );
    }
    // The cost curves, then temperature, drift and Allan deviation per log, all inline.
    assert_eq!(html.matches("<figure>").count(), 7);
    assert_eq!(html.matches("<svg ").count(), 7);
}

#[test]
fn regression_report_without_searches_has_no_cost_figure() {
    let model = regression_model("1,T,Tdot", false);
    let logs = laser_logs();
    let dir = tempfile::tempdir().unwrap();
    let summary =
        report::write_model(&model, &logs[1..], dir.path(), &ReportOptions::default()).unwrap();
    assert!(summary.figures.is_empty());
    assert!(!dir.path().join("costs.svg").exists());
    let html = std::fs::read_to_string(&summary.html).unwrap();
    assert!(!html.contains("<h2>Searches</h2>"));
    assert!(html.contains("not among the logs"));
    assert_eq!(html.matches("<figure>").count(), 3);
}

#[test]
fn regression_report_names_a_missing_channel() {
    // A model reading the laser power, judged on the FOG log that has none: an error naming
    // the log and the channel, no panic.
    let model = regression_model("1,T,ch:laser_power_mw", false);
    let p = sample("validation.csv");
    let logs = vec![(p.clone(), read(&p))];
    let dir = tempfile::tempdir().unwrap();
    let err = report::write_model(&model, &logs, dir.path(), &ReportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("laser_power_mw") && err.contains("validation.csv"),
        "{err}"
    );
}

#[test]
fn cli_report_of_a_regression_calibration() {
    let dir = tempfile::tempdir().unwrap();
    let cal = dir.path().join("cal.json").display().to_string();
    let out = dir.path().join("rep");
    let (a, b) = (
        sample("laser-gyro.csv").display().to_string(),
        sample("laser-gyro-2.csv").display().to_string(),
    );
    let run = driftlab(&["calibrate", &a, "--model", "sukhanov", "--out", &cal]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let run = driftlab(&["report", &cal, &a, &b, "--out", &out.display().to_string()]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let stdout = String::from_utf8(run.stdout).unwrap();
    assert!(stdout.contains("laser-gyro.csv (in-sample)"), "{stdout}");
    assert!(stdout.contains("laser-gyro-2.csv (held out)"), "{stdout}");
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.contains("<b class=\"model-name\">sukhanov</b>"));
    assert!(html.contains("lambda_s"));
    assert!(out.join("costs.svg").is_file());
}

#[test]
fn an_absurd_coefficient_is_a_figure_error_naming_the_file_and_the_axis() {
    // K0 of 1e308 °/h: no axis can be drawn over it, and the plotting library's search for
    // tick spacings would not end. The report refuses it with the figure's file and axis.
    let mut v = serde_json::to_value(calibration()).unwrap();
    v["k0"]["curve"]["coeffs"] = serde_json::json!([1e308, 0.0, 0.0]);
    let cal: Calibration = serde_json::from_value(v).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let err = report::write(&cal, &logs()[..1], dir.path(), &ReportOptions::default()).unwrap_err();
    match &err {
        driftlab::Error::Figure(FigureError::Drawing {
            path,
            source: DrawError::AxisBeyond { axis, value, log },
        }) => {
            assert_eq!(path, &dir.path().join("k0.svg"));
            assert_eq!(axis, "K0");
            assert!(value.abs() > 1e100 && !log, "{value} {log}");
        }
        other => panic!("not a figure error: {other:?}"),
    }
    let text = err.to_string();
    assert!(
        text.contains("k0.svg") && text.contains("K0 axis"),
        "{text}"
    );
}

#[test]
fn figures_of_merit_without_a_window_name_the_setting() {
    let dir = tempfile::tempdir().unwrap();
    for (merit, setting) in [
        (
            MeritOptions {
                filter_s: 0.0,
                ..MeritOptions::default()
            },
            "filter_s",
        ),
        (
            MeritOptions {
                window_s: f64::NAN,
                ..MeritOptions::default()
            },
            "window_s",
        ),
    ] {
        let opts = ReportOptions {
            merit: Some(merit),
            ..ReportOptions::default()
        };
        match report::write(calibration(), &logs()[..1], dir.path(), &opts).unwrap_err() {
            driftlab::Error::Invalid(e) => {
                assert_eq!(e.field, setting);
                assert!(!e.reason.contains("--"), "{e}");
            }
            other => panic!("not an invalid setting: {other:?}"),
        }
    }
}

/// A calibration's source name and a log's file name holding a right-to-left override, a line
/// separator or an escape reach the page as their `\uXXXX` escapes, never as characters that
/// would reorder or forge the text around them.
#[test]
fn names_that_would_reorder_the_page_are_escaped() {
    let dir = tempfile::tempdir().unwrap();
    let mut cal = calibration().clone();
    cal.source.name = "run\u{202e}vsc.exe\u{2028}\u{1b}[2J.csv".into();
    let crafted = dir.path().join("held\u{202e}out.csv");
    std::fs::copy(sample("validation.csv"), &crafted).unwrap();
    let logs = vec![(crafted.clone(), read(&crafted))];
    let out = dir.path().join("report");
    report::write(&cal, &logs, &out, &ReportOptions::default()).unwrap();
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    for c in ['\u{202e}', '\u{2028}', '\u{1b}'] {
        assert!(!html.contains(c), "{:?} reached the page", c);
    }
    assert!(html.contains("run\\u202evsc.exe\\u2028\\u001b[2J.csv"));
    assert!(html.contains("held\\u202eout.csv"));

    // The calibration's own log under such a name: in-sample, its name in the captions of
    // the figures that draw its points.
    let own = dir.path().join("cal\u{1b}[2J\u{202e}.csv");
    std::fs::copy(sample("calibration.csv"), &own).unwrap();
    let logs = vec![(own.clone(), read(&own))];
    let out = dir.path().join("report-own");
    report::write(calibration(), &logs, &out, &ReportOptions::default()).unwrap();
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(
        html.contains("pointwise values on the calibration log cal\\u001b[2J\\u202e.csv"),
        "the caption names the log escaped"
    );
    for c in ['\u{202e}', '\u{1b}'] {
        assert!(!html.contains(c), "{:?} reached the page", c);
    }
}
