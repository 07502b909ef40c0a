//! The workbench on logs with gaps and bursts: nothing drawn across a gap, the time axis on
//! the data when the calibration fails, and the import view's bins honoured by the read.

use driftlab::gui::Workbench;
use driftlab::gui::plot_items::Segments;
use driftlab::log::ingest::{self, ReadOptions};
use driftlab::signal::lod::MinMaxPyramid;
use egui_kittest::kittest::Queryable;
use std::path::Path;

use crate::common;
use common::gui::*;

/// A 1 Hz log of `hours` whose temperature ramps from 0 to 60 °C without a hold, with no
/// sample from `gap.0` for `gap.1` seconds.
fn ramp_with_gap(path: &Path, hours: f64, gap: (f64, f64)) -> Vec<f64> {
    let n = (hours * 3600.0) as usize;
    let mut text = String::from("time_s,omega_dph,temp_c\n");
    let mut times = Vec::new();
    for i in 0..n {
        let t = i as f64;
        if t >= gap.0 && t < gap.0 + gap.1 {
            continue;
        }
        let temp = 60.0 * t / n as f64;
        let omega = 0.01 * temp + 0.05 * ((i * 7919) % 13) as f64 / 13.0;
        text.push_str(&format!("{t},{omega:.5},{temp:.4}\n"));
        times.push(t);
    }
    std::fs::write(path, text).unwrap();
    times
}

#[test]
fn a_band_never_joins_two_segments() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("gap.csv");
    let times = ramp_with_gap(&path, 3.0, (3600.0, 1800.0));
    let log = ingest::read_path(&path, &ReadOptions::default()).unwrap();
    assert_eq!(log.time_s, times);
    let segments = Segments::of(&log);
    assert_eq!(segments.len(), 2);
    assert_eq!(segments.gaps().collect::<Vec<_>>(), vec![(3599.0, 5400.0)]);
    let pyramid = MinMaxPyramid::new(&log.omega_dph);
    let (t0, t1) = (log.time_s[0], *log.time_s.last().unwrap());
    // The whole log on 800 columns (min/max columns), and zoomed in on the gap so far that
    // the samples themselves are drawn: either way one band a side, none inside the gap.
    for (a, b, columns) in [(t0, t1, 800), (3500.0, 5500.0, 4000)] {
        let bands = segments.reduce(&log.time_s, &log.omega_dph, &pyramid, a, b, columns);
        assert_eq!(bands.len(), 2, "{a} … {b}");
        for band in &bands {
            let (lo, hi) = (band.x[0], *band.x.last().unwrap());
            assert!(
                hi <= 3599.0 + 1e-9 || lo >= 5400.0 - 1e-9,
                "a band spans {lo} … {hi}, across the gap 3599 … 5400"
            );
        }
        if columns == 4000 {
            // Samples: the last before the gap and the first after it end the two bands.
            assert!(bands[0].exact && bands[1].exact);
            assert_eq!(*bands[0].x.last().unwrap(), 3599.0);
            assert_eq!(bands[1].x[0], 5400.0);
            assert_eq!(*bands[0].lo.last().unwrap(), log.omega_dph[3599]);
        }
    }
}

#[test]
fn a_failed_calibration_leaves_the_time_axis_on_the_data() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("ramp.csv");
    let times = ramp_with_gap(&path, 3.0, (3600.0, 1800.0));
    let mut wb = Workbench::new(
        Default::default(),
        None,
        Box::new(driftlab::gui::ScriptedDialogs::new()),
    );
    wb.open_log(path, Default::default(), true);
    assert!(
        wb.import_view().is_none(),
        "nothing about the columns to ask"
    );
    let mut h = harness(wb);
    settle(&mut h);
    settle(&mut h);
    let s = &h.state().state;
    assert!(s.shown.fit.is_none());
    let error = s
        .shown
        .fit_error
        .as_deref()
        .expect("no plateau to fit K0 on");
    assert!(
        h.query_all_by_label_contains("Calibration failed")
            .next()
            .is_some()
    );
    assert!(!error.is_empty());
    let (a, b) = h
        .state()
        .visible_time_s()
        .expect("the time plots are drawn");
    let (t0, t1) = (times[0], *times.last().unwrap());
    let span = t1 - t0;
    assert!(
        (a - t0).abs() < 0.02 * span && (b - t1).abs() < 0.02 * span,
        "time axis {a} … {b}, data {t0} … {t1}"
    );
    // The segments are said.
    h.get_by_label_contains("2 segments between gaps");
}

#[test]
fn the_import_views_bins_are_the_read() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("fast.csv");
    // 20 minutes at 10 Hz.
    let mut text = String::from("time_s,omega_dph,temp_c\n");
    for i in 0..12_000 {
        let t = i as f64 * 0.1;
        text.push_str(&format!(
            "{t:.1},{:.4},{:.4}\n",
            0.3 * ((i * 37) % 11) as f64,
            20.0 + t / 600.0
        ));
    }
    std::fs::write(&path, text).unwrap();
    let mut wb = Workbench::new_for_test(&sample("calibration.csv"));
    let dialogs = with_dialogs(&mut wb);
    let mut h = harness(wb);
    settle(&mut h);
    dialogs.answer(Some(path.clone()));
    h.key_press_modifiers(eframe::egui::Modifiers::COMMAND, eframe::egui::Key::O);
    h.run_ok();
    h.get_by_label("Average into bins of").click();
    h.run_ok();
    let view = h.state_mut().import_view().expect("the import view");
    assert_eq!(view.bin_s, Some(1.0), "the box turns bins on, at 1 s");
    view.bin_s = Some(10.0);
    h.run_ok();
    h.get_by_label("Load").click();
    settle(&mut h);
    let l = h.state().state.shown.log.as_ref().unwrap();
    assert!(l.path.ends_with("fast.csv"));
    assert_eq!(l.options.bin_s, Some(10.0));
    // 1200 s in 10-s bins, each the mean of its 100 samples.
    assert_eq!(l.log.len(), 120);
    let first: f64 = (0..100).map(|i| 0.3 * ((i * 37) % 11) as f64).sum::<f64>() / 100.0;
    assert!(
        (l.log.omega_dph[0] - first).abs() < 1e-9,
        "{} vs {first}",
        l.log.omega_dph[0]
    );
    // The same as the engine's `--bin 10` on the same read.
    let cli = driftlab::log::resample::prepare(
        ingest::read_path(&path, &ReadOptions::default()).unwrap(),
        Some(10.0),
    )
    .unwrap()
    .0;
    assert_eq!(l.log.omega_dph, cli.omega_dph);
    assert_eq!(l.log.time_s, cli.time_s);
    assert!(l.resampled.is_some());
    // A session keeps the bins.
    assert_eq!(h.state().state.session().log.unwrap().bin_s, Some(10.0));
}

#[test]
fn the_corrected_drift_is_drawn_where_the_rates_have_their_history() {
    // The sample run with an hour lost in the middle of its second ramp.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("outage.csv");
    let text = std::fs::read_to_string(sample("calibration.csv")).unwrap();
    let kept: Vec<&str> = text
        .lines()
        .enumerate()
        .filter(|(i, _)| !(20_000..23_600).contains(i))
        .map(|(_, l)| l)
        .collect();
    std::fs::write(&path, kept.join("\n") + "\n").unwrap();
    let mut h = harness(Workbench::new_for_test(&path));
    settle(&mut h);
    let f = h.state().state.shown.fit.clone().expect("calibrated");
    let judged = &f.outcome.in_sample;
    let n = judged.log.len();
    let ready = &judged.corrected.ready;
    assert_eq!(ready.len(), 2, "{ready:?}");
    assert_eq!(f.lods.ready.len(), 2);
    assert_eq!(f.lods.segments.len(), 2);
    assert_eq!(f.lods.cor_filtered_dph.len(), n);
    assert_eq!(f.lods.pred_filtered.len(), n);
    // Inside a stretch, farther from its ends than the window, the drawn series is the
    // engine's own filtered correction.
    let w = f.outcome.prepared.filter_samples;
    for r in ready {
        for i in (r.start + w..r.end - w).step_by(997) {
            let (drawn, engine) = (f.lods.cor_filtered_dph[i], judged.cor_filtered_dph[i]);
            assert!(
                (drawn - engine).abs() < 1e-9,
                "sample {i}: {drawn} vs {engine}"
            );
        }
    }
    // At a stretch's start the window holds none of the samples before it.
    let r = &ready[1];
    let own: f64 = judged.corrected.cor_dph[r.start..r.start + w / 2 + 1]
        .iter()
        .sum::<f64>()
        / (w / 2 + 1) as f64;
    assert!(
        (f.lods.cor_filtered_dph[r.start] - own).abs() < 1e-9,
        "{} vs {own}",
        f.lods.cor_filtered_dph[r.start]
    );
}
