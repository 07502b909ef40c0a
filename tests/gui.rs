//! The workbench driven headless, as an engineer would use it: open the sample log, suggest
//! plateaus, edit them by mouse and keyboard, change an approximation and see the figures
//! change, export files the engine reads back, save and reopen a session, survive a bad file.

use driftlab::compare::Outcome;
use driftlab::drift_model::DriftModel;
use driftlab::gui::{Action, FileKind, Page, ScriptedDialogs, Target, Workbench};
use driftlab::presets::Preset;
use driftlab::recipe::PlateauChoice;
use driftlab::regression::{DelaySpec, LagSpec};
use eframe::egui::accesskit::Role;
use eframe::egui::{self, Event, Key, Modifiers, PointerButton, Pos2};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use std::path::{Path, PathBuf};

fn sample(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("sample_logs")
        .join(name)
}

fn harness(wb: Workbench) -> Harness<'static, Workbench> {
    Harness::builder()
        .with_size(egui::vec2(1600.0, 1000.0))
        .build_ui_state(|ui, wb: &mut Workbench| wb.ui(ui), wb)
}

/// The workbench on the sample log, settled, whose next file dialog answers `out`.
fn answering(out: &Path) -> Harness<'static, Workbench> {
    let mut wb = Workbench::new_for_test(&sample("calibration.csv"));
    let dialogs = with_dialogs(&mut wb);
    let mut h = harness(wb);
    settle(&mut h);
    dialogs.answer(Some(out.to_path_buf()));
    h
}

/// Lets the workers finish and the UI show their results.
fn settle(h: &mut Harness<'_, Workbench>) {
    for _ in 0..3 {
        h.state_mut().wait_for_jobs();
        h.run_ok();
    }
}

fn with_dialogs(wb: &mut Workbench) -> ScriptedDialogs {
    let d = ScriptedDialogs::new();
    wb.set_dialogs(Box::new(d.clone()));
    d
}

fn p2p_corrected(h: &Harness<'_, Workbench>) -> f64 {
    let f = h.state().state.fit.as_ref().expect("calibrated");
    f.outcome.in_sample.evaluation.comparison.corrected.p2p_dph
}

#[test]
fn the_sample_log_opens_calibrated_with_its_figures() {
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    h.get_by_label("peak-to-peak");
    h.get_by_label_contains("4 plateaus found by the detector");
    let e = &h
        .state()
        .state
        .fit
        .as_ref()
        .unwrap()
        .outcome
        .in_sample
        .evaluation;
    assert!(
        e.comparison.p2p_ratio > 3.0,
        "in-sample ratio {}",
        e.comparison.p2p_ratio
    );
    // The figures on screen are the engine's.
    h.get_by_label(&format!("{:.2}×", e.comparison.p2p_ratio));
}

#[test]
fn suggest_plateaus_fills_the_table_from_the_detector() {
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    h.get_by_label("Suggest plateaus").click();
    settle(&mut h);
    let s = &h.state().state;
    let PlateauChoice::Manual { ranges } = &s.recipe().plateaus else {
        panic!("suggested plateaus are editable ranges");
    };
    assert_eq!(ranges.len(), 4);
    assert_eq!(*ranges, s.fit.as_ref().unwrap().outcome.ranges);
    h.get_by_label_contains("4 plateaus set by hand");
}

#[test]
fn changing_an_approximation_changes_the_figures() {
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    let before = p2p_corrected(&h);
    h.get_by_label("K1+ approximation").click();
    h.run_ok();
    let options = h.get_all_by_label("spline").collect::<Vec<_>>();
    options
        .last()
        .expect("the spline choice in the open list")
        .click();
    settle(&mut h);
    assert_eq!(
        h.state().state.recipe().k1_plus.kind,
        driftlab::approx::ApproxKind::Spline
    );
    let fit = h.state().state.fit.clone().unwrap();
    assert_eq!(
        fit.outcome.calibration.k1_plus.kind(),
        driftlab::approx::ApproxKind::Spline
    );
    let after = p2p_corrected(&h);
    assert_ne!(before, after, "the figures follow the new K1+");
    // And undo brings the linear K1+ (and its figures) back.
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    settle(&mut h);
    assert_eq!(
        h.state().state.recipe().k1_plus.kind,
        driftlab::approx::ApproxKind::Linear
    );
    assert_eq!(p2p_corrected(&h), before);
}

#[test]
fn export_writes_a_calibration_the_engine_loads() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("gyro7.json");
    let mut h = answering(&out);
    h.key_press_modifiers(Modifiers::COMMAND, Key::E);
    settle(&mut h);
    let cal = driftlab::calfile::load(&out).expect("the engine reads the exported file");
    let fitted = h
        .state()
        .state
        .fit
        .as_ref()
        .unwrap()
        .outcome
        .calibration
        .clone();
    assert_eq!(cal.k0, fitted.k0);
    assert_eq!(cal.k1_plus, fitted.k1_plus);
    assert_eq!(cal.k2_minus, fitted.k2_minus);
    assert_eq!(cal.source.name, "calibration.csv");
    assert_eq!(
        cal.source.sha256,
        driftlab::calfile::sha256_file(&sample("calibration.csv")).unwrap()
    );
    // It corrects a log as the workbench showed it.
    let log = driftlab::ingest::read_path(&sample("calibration.csv"), &Default::default()).unwrap();
    let c = cal.correct(&log);
    assert_eq!(
        c.cor_dph,
        h.state()
            .state
            .fit
            .as_ref()
            .unwrap()
            .outcome
            .in_sample
            .corrected
            .cor_dph
    );
}

#[test]
fn export_corrected_log_from_the_menu() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("corrected.csv");
    let mut h = answering(&out);
    h.get_by_label("File").click();
    h.run_ok();
    h.get_by_label_contains("Export corrected log").click();
    settle(&mut h);
    let text = std::fs::read_to_string(&out).expect("written");
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("time_s,omega_raw_dph,omega_pred_dph,omega_cor_dph,temp_c")
    );
    assert_eq!(
        lines.count(),
        h.state().state.log.as_ref().unwrap().log.len()
    );
}

#[test]
fn a_saved_session_reopens_as_it_was_left() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.session.json");
    let mut wb = Workbench::new_for_test(&sample("calibration.csv"));
    let dialogs = with_dialogs(&mut wb);
    let mut h = harness(wb);
    settle(&mut h);
    h.get_by_label("Suggest plateaus").click();
    settle(&mut h);
    h.state_mut().state.recipe_mut().filter_s = 150.0;
    settle(&mut h);
    // A held-out log, through the import view.
    dialogs.answer(Some(sample("validation.csv")));
    // (the button in the Data panel; the result plot's header has one too)
    h.get_all_by_label("Open validation log…")
        .next()
        .unwrap()
        .click();
    h.run_ok();
    h.get_by_label("Load").click();
    settle(&mut h);
    assert!(h.state().state.validation.is_some());
    h.get_by_label_contains("Held out · validation.csv");
    h.state_mut().state.view.show_validation = false;
    assert!(h.state().state.dirty());
    dialogs.answer(Some(path.clone()));
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    settle(&mut h);
    assert!(!h.state().state.dirty(), "saved");
    let choices = h.state().state.choices.clone();

    // A fresh workbench on another log opens the session.
    let mut other = harness(Workbench::new_for_test(&sample("validation.csv")));
    settle(&mut other);
    let ctx = other.ctx.clone();
    other.state_mut().act(&ctx, Action::OpenSessionPath(path));
    settle(&mut other);
    let s = &other.state().state;
    assert_eq!(s.choices, choices);
    assert!(s.log.as_ref().unwrap().path.ends_with("calibration.csv"));
    assert!(!s.dirty(), "a reopened session has nothing unsaved");
    assert!(
        s.validation
            .as_ref()
            .unwrap()
            .path
            .ends_with("validation.csv")
    );
    assert!(
        !s.view.show_validation,
        "the result plot shows what it showed"
    );
    let fit = s.fit.as_ref().unwrap();
    assert_eq!(fit.outcome.calibration.recipe.filter_s, 150.0);
    assert!(fit.outcome.held_out.is_some());
}

#[test]
fn a_bad_file_leaves_the_work_as_it_was() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.csv");
    let mut text = String::from("time_s,omega_dph,temp_c\n");
    for i in 0..200 {
        if i == 120 {
            text.push_str("120,0.1x,20.0\n");
        } else {
            text.push_str(&format!("{i},0.1,20.0\n"));
        }
    }
    std::fs::write(&bad, text).unwrap();
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    h.get_by_label("Suggest plateaus").click();
    settle(&mut h);
    let choices = h.state().state.choices.clone();
    let ctx = h.ctx.clone();
    h.state_mut().act(&ctx, Action::OpenLogPath(bad.clone()));
    h.run_ok();
    // Unsaved plateaus: asked first.
    h.get_by_label("Unsaved work");
    h.get_by_label("Discard").click();
    h.run_ok();
    // The import view previews the first rows; the bad cell is further down.
    assert!(h.state_mut().import_view().is_some());
    h.get_by_label("Load").click();
    settle(&mut h);
    h.get_by_label_contains("bad.csv:122:2");
    let s = &h.state().state;
    assert!(s.log.as_ref().unwrap().path.ends_with("calibration.csv"));
    assert_eq!(s.choices, choices);
    assert!(s.fit.is_some());
    h.get_by_label("OK").click();
    h.run_ok();
    assert!(h.query_by_label_contains("bad.csv:122:2").is_none());
}

#[test]
fn the_import_view_reads_semicolons_and_decimal_commas() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("stand.csv");
    let mut text = String::from("Zeit [s];Drift [deg/h];Temp [°C]\n");
    for i in 0..2000 {
        text.push_str(&format!("{i};0,{};20,5\n", i % 7));
    }
    std::fs::write(&log, text).unwrap();
    let mut wb = Workbench::new_for_test(&sample("calibration.csv"));
    let dialogs = with_dialogs(&mut wb);
    let mut h = harness(wb);
    settle(&mut h);
    dialogs.answer(Some(log.clone()));
    h.key_press_modifiers(Modifiers::COMMAND, Key::O);
    h.run_ok();
    {
        let view = h
            .state_mut()
            .import_view()
            .expect("Ctrl+O opens the import view");
        let p = view.preview().unwrap();
        assert_eq!(p.delimiter, ';');
        assert!(p.decimal_comma);
        assert_eq!(p.rows[0], vec!["0", "0,0", "20,5"]);
    }
    h.get_by_label("Load").click();
    settle(&mut h);
    let l = h.state().state.log.as_ref().unwrap();
    assert!(l.path.ends_with("stand.csv"));
    assert_eq!(l.log.omega_dph[3], 0.3);
    assert_eq!(l.log.temp_c[0], 20.5);
}

#[test]
fn plateaus_are_edited_by_mouse_and_undone_by_keyboard() {
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    h.get_by_label("Suggest plateaus").click();
    settle(&mut h);
    let ranges = |h: &Harness<'_, Workbench>| h.state().state.ranges();
    let before = ranges(&h);
    let rect = h
        .state()
        .plot_rect("time_temp")
        .expect("the T plot is drawn");
    let log_end = *h
        .state()
        .state
        .log
        .as_ref()
        .unwrap()
        .log
        .time_s
        .last()
        .unwrap();

    // Shift+drag across the plot marks a new plateau.
    let y = rect.center().y;
    let (x0, x1) = (
        rect.left() + 0.45 * rect.width(),
        rect.left() + 0.52 * rect.width(),
    );
    drag(&mut h, Pos2::new(x0, y), Pos2::new(x1, y), Modifiers::SHIFT);
    settle(&mut h);
    let after = ranges(&h);
    assert_eq!(after.len(), before.len() + 1, "{after:?}");
    let new = after.iter().find(|r| !before.contains(r)).unwrap();
    assert!(new.end_s > new.start_s && new.start_s > 0.0 && new.end_s < log_end);

    // Delete removes the selected (new) plateau; Ctrl+Z brings it back, Ctrl+Y removes it again.
    h.key_press(Key::Delete);
    settle(&mut h);
    assert_eq!(ranges(&h), before);
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    settle(&mut h);
    assert_eq!(ranges(&h), after);
    h.key_press_modifiers(Modifiers::COMMAND, Key::Y);
    settle(&mut h);
    assert_eq!(ranges(&h), before);
}

/// A primary-button drag with `modifiers` held, in a few moves.
fn drag(h: &mut Harness<'_, Workbench>, from: Pos2, to: Pos2, modifiers: Modifiers) {
    h.event(Event::ModifiersChanged(modifiers));
    h.event(Event::PointerMoved(from));
    h.run_ok();
    h.event(Event::PointerButton {
        pos: from,
        button: PointerButton::Primary,
        pressed: true,
        modifiers,
    });
    h.step();
    for k in 1..=5 {
        let p = from + (to - from) * (k as f32 / 5.0);
        h.event(Event::PointerMoved(p));
        h.step();
    }
    h.event(Event::PointerButton {
        pos: to,
        button: PointerButton::Primary,
        pressed: false,
        modifiers,
    });
    h.step();
    h.event(Event::ModifiersChanged(Modifiers::NONE));
    h.run_ok();
}

#[test]
fn a_plateau_edge_is_dragged() {
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    h.get_by_label("Suggest plateaus").click();
    settle(&mut h);
    let before = h.state().state.ranges();
    let rect = h.state().plot_rect("time_temp").unwrap();
    let px = |h: &Harness<'_, Workbench>, t: f64| h.state().time_plot_x(t).unwrap();
    let start = before[1].start_s;
    let y = rect.center().y;
    let x = px(&h, start);
    drag(
        &mut h,
        Pos2::new(x, y),
        Pos2::new(x - 15.0, y),
        Modifiers::NONE,
    );
    settle(&mut h);
    let after = h.state().state.ranges();
    assert_eq!(after.len(), before.len());
    assert!(
        after[1].start_s < start - 100.0,
        "start moved earlier: {} → {}",
        start,
        after[1].start_s
    );
    assert_eq!(after[1].end_s, before[1].end_s);
}

#[test]
fn a_spline_knot_is_dragged_and_the_figures_follow() {
    use driftlab::session::Coefficient;
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    h.state_mut().state.recipe_mut().k1_plus = driftlab::approx::ApproxSpec {
        kind: driftlab::approx::ApproxKind::Spline,
        knots: 5,
        extrapolate: false,
    };
    settle(&mut h);
    let fitted = h
        .state()
        .state
        .fit
        .as_ref()
        .unwrap()
        .outcome
        .calibration
        .k1_plus
        .clone();
    let before = p2p_corrected(&h);
    let p = h
        .state()
        .knot_screen_pos(Coefficient::K1Plus, 2)
        .expect("knot 2 drawn");
    drag(&mut h, p, p - egui::vec2(0.0, 30.0), Modifiers::NONE);
    settle(&mut h);
    let s = &h.state().state;
    let edited = s
        .choices
        .knots
        .get(Coefficient::K1Plus)
        .expect("knot values set by hand");
    assert!(
        edited[2] > fitted.knots().1[2],
        "dragged up: {} → {}",
        fitted.knots().1[2],
        edited[2]
    );
    assert_eq!(edited[0], fitted.knots().1[0], "the other knots stay");
    let cal = &s.fit.as_ref().unwrap().outcome.calibration;
    assert_eq!(cal.k1_plus.knots().1, &edited[..]);
    assert_ne!(p2p_corrected(&h), before);
    // "reset knots" goes back to the fitted curve.
    h.get_by_label("reset knots").click();
    settle(&mut h);
    assert!(h.state().state.choices.knots.is_empty());
    assert_eq!(p2p_corrected(&h), before);
}

#[test]
fn unsaved_work_is_not_lost_silently() {
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    h.get_by_label("Suggest plateaus").click();
    settle(&mut h);
    let choices = h.state().state.choices.clone();
    let ctx = h.ctx.clone();
    h.state_mut()
        .act(&ctx, Action::OpenLogPath(sample("validation.csv")));
    h.run_ok();
    h.get_by_label("Unsaved work");
    h.get_by_label("Cancel").click();
    h.run_ok();
    assert!(h.query_by_label("Unsaved work").is_none());
    assert!(h.state_mut().import_view().is_none());
    assert_eq!(h.state().state.choices, choices);
    assert!(h.state().state.dirty());
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

/// Frame cost on a big log (`DRIFTLAB_BIG_LOG=/path/to/10M.csv cargo test --release --test gui
/// -- --ignored --nocapture big_log`): layout and shapes of the whole window, then
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

/// Ticks the custom model, presses Compare on the Models page and lets the comparison finish.
fn compare_on_models_page(h: &mut Harness<'_, Workbench>) {
    h.key_press_modifiers(Modifiers::COMMAND, Key::Num2);
    h.run_ok();
    assert_eq!(h.state().page(), Page::Models);
    h.get_by_role_and_label(Role::Button, "Compare").click();
    h.run_ok();
    assert!(
        h.state().busy() || h.state().state.models.is_some(),
        "the comparison runs in the background"
    );
    settle(h);
}

#[test]
fn the_models_page_compares_every_model_in_sample_and_held_out_and_exports_one() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("coil-lag.json");
    let mut wb = Workbench::new_for_test(&sample("calibration.csv"));
    let dialogs = with_dialogs(&mut wb);
    wb.start_load(
        sample("validation.csv"),
        Default::default(),
        Target::Validation,
    );
    wb.wait_for_jobs();
    assert!(wb.state.validation.is_some());
    let mut h = harness(wb);
    settle(&mut h);
    // The custom model from the builder: T, Tdot and a bias.
    h.key_press_modifiers(Modifiers::COMMAND, Key::Num2);
    h.run_ok();
    h.get_by_label("Custom model").click();
    h.run_ok();
    h.get_by_label("T*Tdot").click();
    h.run_ok();
    compare_on_models_page(&mut h);

    let c = h.state().state.models.clone().expect("compared");
    let mut expected: Vec<String> = Preset::ALL.iter().map(|p| p.name().to_string()).collect();
    expected.push("custom".into());
    let names: Vec<String> = c.reports.iter().map(|r| r.model.clone()).collect();
    assert_eq!(names, expected);
    let custom = c.reports.last().unwrap();
    assert_eq!(custom.description, "1 + T + Tdot");
    for r in &c.reports {
        assert!(r.error.is_none(), "{}: {:?}", r.model, r.error);
        assert_eq!(r.logs.len(), 2, "{}: in-sample and held out", r.model);
    }
    // The table: a row per model and log, the engine's figures in it.
    assert_eq!(h.get_all_by_label("in-sample").count(), expected.len());
    assert_eq!(h.get_all_by_label("held out").count(), expected.len());
    for r in &c.reports {
        assert!(
            h.query_all_by_label(&r.model).count() >= 1,
            "{} is in the table",
            r.model
        );
        for j in &r.logs {
            let Outcome::Evaluation(e) = &j.result else {
                panic!("{} judged", r.model)
            };
            let shown = format!("{:.2}×", e.comparison.p2p_ratio);
            assert!(h.query_all_by_label(&shown).count() >= 1, "{shown} shown");
        }
    }
    // Each fitted model's corrected drift is there to draw, on both logs.
    assert!(
        c.series
            .iter()
            .all(|s| s.len() == 2 && s.iter().all(Option::is_some))
    );

    // Export the coil-lag model: the engine reads back the same model.
    h.get_by_role_and_label(Role::RadioButton, "coil-lag")
        .click();
    h.run_ok();
    dialogs.answer(Some(out.clone()));
    h.get_by_label("Export model…").click();
    settle(&mut h);
    assert_eq!(dialogs.asked().last(), Some(&FileKind::Model));
    let back = driftlab::calfile::load_model(&out).expect("the engine reads the exported model");
    assert_eq!(back.name(), "coil-lag");
    let DriftModel::Regression(read) = &back else {
        panic!("a regression model")
    };
    let fitted = c
        .reports
        .iter()
        .find(|r| r.model == "coil-lag")
        .and_then(|r| r.fitted.clone())
        .unwrap();
    let DriftModel::Regression(fitted) = fitted else {
        panic!("a regression model")
    };
    assert_eq!(read.model.coefficients, fitted.model.coefficients);
    assert_eq!(read.model.lag_s, fitted.model.lag_s);
    assert_eq!(read.source.name, "calibration.csv");
    // Its details: the lag found and the cost curve of its search.
    h.get_by_role_and_label(Role::Button, "coil-lag").click();
    h.run_ok();
    h.get_by_label("Cost of the searches");
}

#[test]
fn a_model_that_cannot_be_fitted_shows_why() {
    // The calibration log without its second temperature sensor: no Sukhanov model.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("one-sensor.csv");
    let text = std::fs::read_to_string(sample("calibration.csv")).unwrap();
    let cut: String = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.rsplit_once(',').map_or(l, |(head, _)| head).to_string() + "\n")
        .collect();
    std::fs::write(&path, cut).unwrap();
    let mut h = harness(Workbench::new_for_test(&path));
    settle(&mut h);
    compare_on_models_page(&mut h);
    let c = h.state().state.models.clone().expect("compared");
    let sukhanov = c.reports.iter().find(|r| r.model == "sukhanov").unwrap();
    let why = sukhanov.error.clone().expect("not fitted");
    assert!(why.contains("second temperature sensor"), "{why}");
    h.get_by_label("not fitted");
    h.get_by_label_contains("sukhanov not fitted:");
    // The others still compare.
    assert!(c.reports.iter().filter(|r| r.fitted.is_some()).count() == Preset::ALL.len() - 1);
}

#[test]
fn the_custom_model_builder_makes_the_spec_the_command_line_would() {
    use driftlab::gui::view_models::{CustomBuilder, DelayChoice, LagChoice};
    let b = CustomBuilder {
        enabled: true,
        name: "mine".into(),
        terms: driftlab::regression::terms::parse_terms("1,T,T*Tdot").unwrap(),
        delay: DelayChoice::Bands,
        bands: 4,
        delay_max_s: 1200.0,
        lag: LagChoice::Fixed,
        lag_s: 90.0,
        samples: driftlab::regression::FitSamples::Staged,
        ..CustomBuilder::default()
    };
    let s = b.spec().unwrap();
    assert_eq!(s.name, "mine");
    assert_eq!(s.samples, driftlab::regression::FitSamples::Staged);
    assert_eq!(
        s.delay,
        DelaySpec::Bands {
            bands: 4,
            max_s: 1200.0
        }
    );
    assert_eq!(
        s.lag,
        LagSpec::Fixed {
            seconds: 90.0,
            per_c: 0.0
        }
    );
    assert!(
        CustomBuilder {
            terms: vec![],
            ..b.clone()
        }
        .spec()
        .is_err(),
        "no terms"
    );
    assert!(CustomBuilder { bands: 0, ..b }.spec().is_err(), "no bands");
}

#[test]
fn the_allan_page_shows_raw_and_corrected_deviations_and_read_outs() {
    let mut h = harness(Workbench::new_for_test(&sample("calibration.csv")));
    settle(&mut h);
    h.key_press_modifiers(Modifiers::COMMAND, Key::Num3);
    h.run_ok();
    assert_eq!(h.state().page(), Page::Allan);
    settle(&mut h);
    let a = h
        .state()
        .state
        .allan
        .clone()
        .expect("computed in the background");
    let raw = a.raw.as_ref().expect("raw deviation");
    let cor = a.corrected.as_ref().expect("corrected deviation");
    assert!(!raw.points.is_empty() && raw.points.len() == cor.points.len());
    // The drift the calibration removes shows at the longest τ.
    let (r, c) = (raw.points.last().unwrap(), cor.points.last().unwrap());
    assert!(c.adev < r.adev, "corrected {} < raw {}", c.adev, r.adev);
    for label in ["ARW", "bias instability", "RRW"] {
        h.get_by_label(label);
    }
    let arw = raw
        .readouts
        .arw
        .as_ref()
        .expect("white noise on the sample log");
    let shown = format!("{} °/√h", driftlab::gui::plot_items::num(arw.value));
    assert!(
        h.query_all_by_label_contains(&shown).count() >= 1,
        "{shown} shown"
    );
}

/// Frame cost of the Models and Allan pages on a big log (`DRIFTLAB_BIG_LOG=/path/to/1M.csv
/// cargo test --release --test gui -- --ignored --nocapture big_log_pages`): every model's
/// corrected drift is drawn from its pyramid, so a frame stays cheap whatever the length.
#[test]
#[ignore = "needs a big log: set DRIFTLAB_BIG_LOG"]
fn big_log_pages_stay_cheap() {
    let Ok(path) = std::env::var("DRIFTLAB_BIG_LOG") else {
        return;
    };
    let mut h = harness(Workbench::new_for_test(Path::new(&path)));
    settle(&mut h);
    let t = std::time::Instant::now();
    compare_on_models_page(&mut h);
    eprintln!(
        "{} samples: compared {} models in {:.2?}",
        h.state().state.log.as_ref().unwrap().log.len(),
        h.state().state.models.as_ref().unwrap().reports.len(),
        t.elapsed()
    );
    for (page, key) in [(Page::Models, Key::Num2), (Page::Allan, Key::Num3)] {
        h.key_press_modifiers(Modifiers::COMMAND, key);
        settle(&mut h);
        assert_eq!(h.state().page(), page);
        let (mut worst, mut sum) = (0.0f64, 0.0);
        for _ in 0..10 {
            let t = std::time::Instant::now();
            h.step();
            let shapes = h.output().shapes.clone();
            let _ = h.ctx.tessellate(shapes, 1.0);
            let ms = t.elapsed().as_secs_f64() * 1e3;
            worst = worst.max(ms);
            sum += ms;
        }
        eprintln!(
            "{page:?}: frames (layout + tessellation) {:.1} ms on average, worst {worst:.1} ms",
            sum / 10.0
        );
        assert!(worst < 100.0, "{page:?}: {worst:.1} ms");
    }
}
