//! The workbench driven headless: unsaved work is not lost silently, a plot saved as PNG,
//! remembered settings and recent files, and the frame cost on a big log (run by hand).

use driftlab::gui::{Action, Workbench};
use eframe::egui::{self, Key, Pos2};
use egui_kittest::kittest::Queryable;
use std::path::Path;

use crate::common;
use common::gui::*;

#[test]
fn unsaved_work_is_not_lost_silently() {
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    h.get_by_label("Suggest plateaus").click();
    settle(&mut h);
    let choices = h.state().state.shown.choices.clone();
    let ctx = h.ctx.clone();
    h.state_mut()
        .act(&ctx, Action::OpenLogPath(sample("validation.csv")));
    h.run_ok();
    h.get_by_label("Unsaved work");
    h.get_by_label("Cancel").click();
    h.run_ok();
    assert!(h.query_by_label("Unsaved work").is_none());
    assert!(h.state_mut().import_view().is_none());
    assert_eq!(h.state().state.shown.choices, choices);
    assert!(h.state().state.dirty());
}

/// A validation log opened is not work that could be lost (it is a file on disk, as an
/// opened calibration is): `driftlab gui LOG --validation VAL` starts with nothing unsaved,
/// no "•" beside the log's name, and quits without asking; an edit still counts.
#[test]
fn a_validation_log_opened_is_not_unsaved_work() {
    use driftlab::gui::ScriptedDialogs;
    use driftlab::gui::settings::Settings;
    let mut wb = Workbench::new(Settings::default(), None, Box::new(ScriptedDialogs::new()));
    wb.open_log(sample("calibration.csv"), Default::default(), false);
    wb.open_validation_after(sample("validation.csv"), Default::default());
    let mut h = harness(wb);
    settle(&mut h);
    assert!(h.state().state.shown.validation.is_some());
    assert!(!h.state().state.dirty(), "nothing was edited");
    assert!(h.query_by_label("calibration.csv").is_some());
    assert!(h.query_by_label("calibration.csv •").is_none());
    let ctx = h.ctx.clone();
    h.state_mut().act(&ctx, Action::Quit);
    h.run_ok();
    assert!(
        h.query_by_label("Unsaved work").is_none(),
        "quitting asks nothing"
    );
    // Closed again: still nothing to save.
    h.state_mut().act(&ctx, Action::CloseValidation);
    h.run_ok();
    assert!(!h.state().state.dirty());
    // An edit is work.
    h.state_mut().state.recipe_mut().filter_s = 150.0;
    h.run_ok();
    assert!(h.state().state.dirty());
    assert!(h.query_by_label("calibration.csv •").is_some());
}

/// `driftlab gui X --screenshot OUT.png` when the window cannot show what was asked: the run
/// ends with the message (which `driftlab gui` prints on standard error, status 1) within a
/// few frames, and writes no picture. It used to show an error dialog and wait for ever (or,
/// for a calibration that failed, three minutes).
#[test]
fn screenshot_mode_ends_with_the_message_when_the_window_cannot_show_what_was_asked() {
    use driftlab::gui::settings::Settings;
    use driftlab::gui::{ScreenshotOutcome, ScriptedDialogs};
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let png = d.join("shot.png");
    let write = |name: &str, text: &str| {
        let path = d.join(name);
        std::fs::write(&path, text).unwrap();
        path
    };
    let newer = write(
        "newer.session.json",
        r#"{ "format": "driftlab-session", "version": 99, "session": {} }"#,
    );
    let no_log = write(
        "nolog.session.json",
        r#"{ "format": "driftlab-session", "version": 1, "session": {} }"#,
    );
    let mut bad_cell = std::fs::read_to_string(sample("calibration.csv")).unwrap();
    bad_cell = bad_cell.replacen("\n0,-0.2554,", "\n0,oops,", 1);
    let bad_cell = write("bad.csv", &bad_cell);
    // A log that reads but holds one temperature: no model can be fitted on it.
    let mut flat = String::from("time_s,omega_dph,temp_c\n");
    for i in 0..2000 {
        flat += &format!("{i},{:.3},25.0\n", 0.01 * (i % 7) as f64);
    }
    let flat = write("flat.csv", &flat);
    let missing_log = write(
        "missing.session.json",
        &format!(
            r#"{{ "format": "driftlab-session", "version": 1,
                 "session": {{ "log": {{ "path": "{}" }} }} }}"#,
            d.join("gone.csv").display()
        ),
    );
    let cases = [
        (
            "a session of an unknown version",
            newer,
            "version 99 is not supported",
        ),
        ("a session with no log", no_log, "the session names no log"),
        ("a session whose log is gone", missing_log, "gone.csv"),
        (
            "a log with a bad cell",
            bad_cell,
            "cannot read \"oops\" as a number",
        ),
        (
            "a log no model can be fitted on",
            flat,
            "too little for model vakhrameev",
        ),
    ];
    for (what, file, want) in cases {
        // As `driftlab gui FILE --screenshot shot.png` starts its window.
        let outcome = ScreenshotOutcome::default();
        let mut wb = Workbench::new(Settings::default(), None, Box::new(ScriptedDialogs::new()));
        let shot = Some((png.clone(), outcome.clone()));
        driftlab::gui::start(&mut wb, Some(file), Default::default(), shot);
        let mut h = harness(wb);
        for _ in 0..40 {
            if outcome.is_done() {
                break;
            }
            h.state_mut().wait_for_jobs();
            h.step();
        }
        match outcome.take() {
            Some(Err(e)) => {
                assert!(e.contains(want), "{what}: wanted {want:?} in {e:?}");
                assert!(
                    !e.contains('\n'),
                    "{what}: one line on standard error: {e:?}"
                );
            }
            other => panic!(
                "{what}: the screenshot run did not end with an error: {other:?} (fit {}, error {:?})",
                h.state().state.shown.fit.is_some(),
                h.state().state.shown.fit_error
            ),
        }
        assert!(!png.exists(), "{what}: a picture was written");
    }
}

#[test]
fn a_plot_is_saved_as_png_cropped_from_a_screenshot() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("plot.png");
    let mut img = egui::ColorImage::filled([200, 100], egui::Color32::WHITE);
    for y in 20..60 {
        for x in 50..150 {
            img.pixels[y * 200 + x] = egui::Color32::from_rgb(10, 20, 30);
        }
    }
    let crop = egui::Rect::from_min_max(Pos2::new(25.0, 10.0), Pos2::new(75.0, 30.0));
    driftlab::gui::export::save_png(&out, &img, Some(crop), 2.0).unwrap();
    let back = image::open(&out).unwrap().to_rgba8();
    assert_eq!(back.dimensions(), (100, 40));
    assert_eq!(back.get_pixel(0, 0).0, [10, 20, 30, 255]);
    // An empty crop is refused, nothing is written.
    let none = dir.path().join("none.png");
    assert!(driftlab::gui::export::save_png(&none, &img, Some(egui::Rect::NOTHING), 1.0).is_err());
    assert!(!none.exists());
}

/// Frame cost on a big log (`DRIFTLAB_BIG_LOG=/path/to/10M.csv cargo test --release --test
/// gui_window -- --ignored --nocapture big_log`): layout and shapes of the whole window, then
/// tessellation, while the time axis is zoomed and panned.
#[test]
#[ignore = "needs a big log: set DRIFTLAB_BIG_LOG"]
fn big_log_frames_stay_cheap() {
    let Ok(path) = std::env::var("DRIFTLAB_BIG_LOG") else {
        return;
    };
    let t = std::time::Instant::now();
    let wb = Workbench::new_for_test(Path::new(&path));
    eprintln!("read and calibrated in {:.2?}", t.elapsed());
    let mut h = harness(wb);
    settle(&mut h);
    let keys = [
        Key::Home,
        Key::Plus,
        Key::Plus,
        Key::ArrowRight,
        Key::Minus,
        Key::ArrowLeft,
        Key::Plus,
        Key::Plus,
        Key::Plus,
    ];
    let (mut ui_ms, mut tess_ms, mut worst) = (Vec::new(), Vec::new(), 0.0f64);
    for round in 0..4 {
        for &k in &keys {
            h.key_press(k);
            let t = std::time::Instant::now();
            h.step();
            let a = t.elapsed().as_secs_f64() * 1e3;
            let shapes = h.output().shapes.clone();
            let t = std::time::Instant::now();
            let prims = h.ctx.tessellate(shapes, 1.0);
            let b = t.elapsed().as_secs_f64() * 1e3;
            let vertices: usize = prims
                .iter()
                .map(|p| match &p.primitive {
                    egui::epaint::Primitive::Mesh(m) => m.vertices.len(),
                    _ => 0,
                })
                .sum();
            if round > 0 {
                ui_ms.push(a);
                tess_ms.push(b);
                worst = worst.max(a + b);
            }
            if round == 1 {
                eprintln!("{k:?}: ui {a:.1} ms, tessellation {b:.1} ms, {vertices} vertices");
            }
        }
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    eprintln!(
        "mean ui {:.1} ms, tessellation {:.1} ms, worst frame {:.1} ms",
        mean(&ui_ms),
        mean(&tess_ms),
        worst
    );
    assert!(mean(&ui_ms) + mean(&tess_ms) < 50.0);
}

#[test]
fn remembered_settings_round_trip_and_keep_ten_recent_files() {
    use driftlab::gui::settings::{Settings, ThemeChoice, WindowGeometry};
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("driftlab").join("workbench.json");
    let mut s = Settings {
        theme: ThemeChoice::Dark,
        window: Some(WindowGeometry {
            x: 10.0,
            y: 20.0,
            width: 1400.0,
            height: 900.0,
            maximized: false,
        }),
        ..Settings::default()
    };
    for i in 0..12 {
        s.add_recent(&dir.path().join(format!("run{i}.csv")));
    }
    s.add_recent(&dir.path().join("run5.csv"));
    assert_eq!(s.recent.len(), 10);
    assert!(
        s.recent[0].ends_with("run5.csv"),
        "most recent first, no duplicates"
    );
    s.save(&path).unwrap();
    assert_eq!(Settings::load(&path), s);
    // A damaged file gives the defaults, not an error.
    std::fs::write(&path, "{ not json").unwrap();
    assert_eq!(Settings::load(&path), Settings::default());
}

#[test]
fn the_gui_command_takes_the_mapping_options_and_refuses_them_for_a_session() {
    let bin = env!("CARGO_BIN_EXE_driftlab");
    // A unit it does not know is refused by name, before any window opens.
    let out = std::process::Command::new(bin)
        .args(["gui", "--rate-unit", "furlongs/fortnight"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--rate-unit"), "{err}");
    // A session keeps its own mapping: options given with one are refused, not dropped.
    let dir = tempfile::tempdir().unwrap();
    let session = dir.path().join("s.session.json");
    std::fs::write(&session, "{}").unwrap();
    let out = std::process::Command::new(bin)
        .args(["gui"])
        .arg(&session)
        .args(["--temp-col", "temp_c"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--temp-col") && err.contains("session"),
        "{err}"
    );
}

/// `--window-size` and `--validation` are checked before any window opens; a validation log
/// given with `gui LOG` is opened beside it (the held-out figures are those of that log).
#[test]
fn the_gui_command_takes_a_window_size_and_a_validation_log() {
    let bin = env!("CARGO_BIN_EXE_driftlab");
    let refused = |args: &[&str]| {
        let out = std::process::Command::new(bin)
            .arg("gui")
            .args(args)
            .env_remove("DISPLAY")
            .env_remove("WAYLAND_DISPLAY")
            .output()
            .unwrap();
        assert!(!out.status.success(), "{args:?}");
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    for size in [
        "100x100",
        "1280",
        "wide",
        "1e9x1e9",
        "1280x720x1",
        "nanxnan",
    ] {
        let e = refused(&["--window-size", size]);
        assert!(
            e.contains("--window-size") && e.contains("900x620"),
            "{size}: {e}"
        );
    }
    let dir = tempfile::tempdir().unwrap();
    let session = dir.path().join("s.session.json");
    std::fs::write(&session, "{}").unwrap();
    let e = refused(&[
        session.to_str().unwrap(),
        "--validation",
        sample("validation.csv").to_str().unwrap(),
    ]);
    assert!(e.contains("--validation") && e.contains("session"), "{e}");
    let missing = dir.path().join("gone.csv");
    let e = refused(&[
        sample("calibration.csv").to_str().unwrap(),
        "--validation",
        missing.to_str().unwrap(),
    ]);
    assert!(e.contains("gone.csv") && e.contains("no such file"), "{e}");
    for not_a_file in ["/dev/zero", dir.path().to_str().unwrap()] {
        let e = refused(&[not_a_file]);
        assert!(e.contains("not a file"), "{not_a_file}: {e}");
    }

    // As `driftlab gui LOG --validation VAL` starts its window.
    use driftlab::gui::dialogs::ScriptedDialogs;
    use driftlab::gui::settings::Settings;
    let mut wb = Workbench::new(Settings::default(), None, Box::new(ScriptedDialogs::new()));
    driftlab::gui::start(
        &mut wb,
        Some(sample("calibration.csv")),
        Default::default(),
        None,
    );
    wb.open_validation_after(sample("validation.csv"), Default::default());
    let mut h = harness(wb);
    settle(&mut h);
    let st = &h.state().state;
    let v = st
        .shown
        .validation
        .as_ref()
        .expect("the validation log is open");
    assert!(v.path.ends_with("validation.csv"));
    let held = st
        .shown
        .fit
        .as_ref()
        .unwrap()
        .outcome
        .held_out
        .as_ref()
        .unwrap();
    assert!(std::sync::Arc::ptr_eq(&held.log, &v.log));
    assert!(st.view.show_validation);
}

/// The workbench's fit warns as `driftlab calibrate` does: the papers' parabola for K0 through
/// three plateaus at two set points (fitted as the line they determine; the workbench opens
/// such a log on the line itself, so the engineer picks the parabola), and every warning the
/// command line gives is in the workbench's list.
#[test]
fn the_workbench_gives_the_warnings_calibrate_gives() {
    let log = sample("yan-steps-low.csv");
    let dir = tempfile::tempdir().unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_driftlab"))
        .args(["calibrate", log.to_str().unwrap()])
        .arg("--out")
        .arg(dir.path().join("cal.json"))
        .output()
        .unwrap();
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    let cli: Vec<&str> = err
        .lines()
        .filter_map(|l| l.strip_prefix("warning: "))
        .collect();
    assert!(
        cli.iter().any(|w| w.contains("at only 2 temperatures")),
        "{err}"
    );
    let mut wb = Workbench::new_for_test(&log);
    wb.state.recipe_mut().k0 = driftlab::models::recipe::Recipe::default().k0;
    wb.wait_for_jobs();
    let fit = wb.state.shown.fit.as_ref().expect("calibrated");
    for w in cli {
        assert!(
            fit.outcome.warnings.iter().any(|g| g == w),
            "{w:?} not in {:?}",
            fit.outcome.warnings
        );
    }
}
