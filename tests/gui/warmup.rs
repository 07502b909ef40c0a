//! The start of a log does not set the plots' scales: each segment's warm-up (before its
//! filter and rate histories are full) is drawn faded and left out of the y-range, and the
//! K1±/K2± clouds are scaled to their bulk with the far points counted and marked.

use driftlab::gui::Workbench;
use driftlab::gui::plot_items::{Segments, cloud_scale};
use driftlab::gui::view_result::RESULT_CAL_ID;
use driftlab::signal::lod::{MinMaxPyramid, ScatterLod};
use eframe::egui;

use crate::common;
use common::gui::*;

/// The y-range the plot `id` shows, as egui_plot keeps it.
fn plot_y(h: &egui_kittest::Harness<'_, Workbench>, id: &str) -> (f64, f64) {
    let mem = egui_plot::PlotMemory::load(&h.ctx, egui::Id::unique(id))
        .unwrap_or_else(|| panic!("plot {id} was not drawn"));
    let b = mem.bounds();
    (b.min()[1], b.max()[1])
}

fn range_of(values: impl Iterator<Item = f64>) -> (f64, f64) {
    values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        })
}

#[test]
fn settled_and_warmup_split_each_segment() {
    // Two segments, 0…99 s and 200…299 s; the rates ready 10 s into each.
    let time: Vec<f64> = (0..100).chain(200..300).map(f64::from).collect();
    let segments = Segments::from_ranges(&time, &[0..100, 100..200]);
    let ready = Segments::from_ranges(&time, &[10..100, 110..200]);
    let settled = ready.settled(5.0);
    assert_eq!(settled.spans(), &[(15.0, 99.0), (215.0, 299.0)]);
    // The warm-ups run from each segment's start to its settled start.
    assert_eq!(
        segments.minus(&settled).spans(),
        &[(0.0, 15.0), (200.0, 215.0)]
    );
    assert_eq!(
        ready.minus(&settled).spans(),
        &[(10.0, 15.0), (210.0, 215.0)]
    );
    // A segment shorter than its warm-up is all warm-up.
    assert_eq!(ready.settled(95.0).spans(), &[] as &[(f64, f64)]);
    assert_eq!(
        segments.minus(&ready.settled(95.0)).spans(),
        segments.spans()
    );
}

#[test]
fn a_single_stretch_starting_late_is_clipped_to() {
    // A spike over the first 50 samples, before the stretch that is ready (from 100 on): the
    // reduction over the whole log, as columns or as samples, must not reach it.
    let time: Vec<f64> = (0..1000).map(f64::from).collect();
    let values: Vec<f64> = (0..1000)
        .map(|i| if i < 50 { 100.0 } else { (i % 7) as f64 * 0.1 })
        .collect();
    let pyramid = MinMaxPyramid::new(&values);
    let ready = Segments::from_ranges(&time, std::slice::from_ref(&(100..1000)));
    for columns in [50, 5000] {
        let bands = ready.reduce(&time, &values, &pyramid, 0.0, 999.0, columns);
        let (lo, hi) = range_of(bands.iter().flat_map(|b| b.lo.iter().chain(&b.hi).copied()));
        assert!(
            hi < 1.0,
            "{columns} columns: the spike before the stretch drawn ({hi})"
        );
        assert!(lo >= 0.0);
        assert!(bands.iter().all(|b| b.x.iter().all(|&t| t >= 100.0)));
    }
}

#[test]
fn a_cloud_is_scaled_to_its_bulk_and_counts_the_rest() {
    // 10 000 points in [-1, 1] and 300 far ones at ±1e5 (beside a dead-band of ±0.2 in x).
    let n = 10_000;
    let mut x: Vec<f64> = (0..n).map(|i| 0.5 + i as f64 * 1e-4).collect();
    let mut y: Vec<f64> = (0..n)
        .map(|i| ((i * 7919) % 2001) as f64 / 1000.0 - 1.0)
        .collect();
    for k in 0..300 {
        x.push(0.21 + k as f64 * 1e-4);
        y.push(if k % 2 == 0 { 1e5 } else { -1e5 });
    }
    let lod = ScatterLod::new(&x, &y);
    let s = cloud_scale(&[&lod], Some((-0.5, 3.0)), 0.2, false).unwrap();
    assert!(s[3] < 10.0 && s[2] > -10.0, "scaled to the outliers: {s:?}");
    assert!(
        s[2] <= -1.0 && s[3] >= 3.0,
        "the bulk and the curve must show: {s:?}"
    );
    assert!(
        s[0] <= -0.2 && s[1] >= 1.49,
        "x: the dead-band and every point: {s:?}"
    );
    let (below, above) = lod.count_beyond_y(s[2], s[3]);
    assert_eq!((below, above), (150, 150));
    // Marks for them, at most one a side per few pixels, none for the bulk.
    let marks = lod.beyond(s, 400.0, 3.0);
    assert!(!marks.is_empty() && marks.len() <= 2 * 400 / 3 + 2);
    assert!(marks.iter().all(|&(mx, _)| (0.21..0.25).contains(&mx)));
    // "all points": every point.
    let all = cloud_scale(&[&lod], None, 0.2, true).unwrap();
    assert!(all[2] <= -1e5 && all[3] >= 1e5);
}

#[test]
fn the_drift_plot_is_scaled_to_the_settled_run() {
    // On the IMU's log the corrected warm-up swings to ±1.3 °/h, past raw's whole range;
    // on calibration.csv it stays within raw's (the plot must hold both all the same).
    drift_plot_on("imu3-calibration.csv", true);
    drift_plot_on("calibration.csv", false);
}

fn drift_plot_on(name: &str, spike: bool) {
    let mut h = harness(Workbench::new_for_test(&sample(name)));
    settle(&mut h);
    h.run_ok();
    let (settled, warm, raw, cor) = {
        let f = h.state().state.shown.fit.as_ref().expect("calibrated");
        let p = &f.outcome.prepared;
        let settled = f.lods.ready.settled(p.filter_samples as f64 * p.dt_s);
        let warm = f.lods.segments.minus(&settled);
        (
            settled,
            warm,
            f.outcome.in_sample.raw_filtered_dph.to_vec(),
            f.lods.cor_filtered_dph.clone(),
        )
    };
    let log = outcome(&h).in_sample.log.clone();
    let t = &log.time_s;
    let (r0, r1) = settled.value_range(t, &raw).unwrap();
    let (c0, c1) = settled.value_range(t, &cor).unwrap();
    let (w0, w1) = warm.value_range(t, &cor).unwrap();
    // The warm-up swings wider than the settled run (else this test proves nothing).
    assert!(
        !spike || w1 > r1.max(c1) + 0.2 || w0 < r0.min(c0) - 0.2,
        "{name}: no warm-up spike in the sample: {w0} … {w1}"
    );
    let (y0, y1) = plot_y(&h, RESULT_CAL_ID);
    let eps = 1e-9;
    assert!(
        y0 <= r0.min(c0) + eps && y1 >= r1.max(c1) - eps,
        "{name}: the plot {y0} … {y1} must hold raw {r0} … {r1} and corrected {c0} … {c1}"
    );
    let span = r1.max(c1) - r0.min(c0);
    assert!(
        y1 < r1.max(c1) + 0.2 * span && y0 > r0.min(c0) - 0.2 * span,
        "{name}: the plot {y0} … {y1} is stretched beyond the settled run ({w0} … {w1} in the warm-up)"
    );
}

#[test]
fn the_second_derivative_is_scaled_to_the_settled_run() {
    let mut h = harness(Workbench::new_for_test(&sample("laser-gyro.csv")));
    settle(&mut h);
    h.run_ok();
    let f = h.state().state.shown.fit.clone().expect("calibrated");
    let p = &f.outcome.prepared;
    let t = &f.outcome.in_sample.log.time_s;
    let settled = f.lods.ready.settled(p.filter_samples as f64 * p.dt_s);
    let (s0, s1) = settled.value_range(t, &p.deriv.tddot).unwrap();
    let (a0, a1) = range_of(p.deriv.tddot.iter().copied());
    let span = s1 - s0;
    assert!(
        a1 > s1 + span || a0 < s0 - span,
        "no spike at the start of laser-gyro's d²T/dt²: {a0} … {a1} against {s0} … {s1}"
    );
    let (y0, y1) = plot_y(&h, "time_tddot");
    // The dead-band lines are items of the plot too.
    let db = f.outcome.calibration.resolved.deadband_tddot;
    let (e0, e1) = (s0.min(-db), s1.max(db));
    assert!(y0 <= e0 && y1 >= e1, "{y0} … {y1} must hold {e0} … {e1}");
    let span = e1 - e0;
    assert!(
        y0 > e0 - 0.2 * span && y1 < e1 + 0.2 * span,
        "{y0} … {y1} stretched to the start's {a0} … {a1}"
    );
}
