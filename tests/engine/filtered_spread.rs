//! The peak-to-peak and std of the filtered drift need two filter windows that share no
//! sample (`MIN_DISJOINT_FILTER_WINDOWS`): a stretch shorter than twice the filter gives
//! filtered values that all average overlapping windows, and their figures are n/a with that
//! reason (NaN, `null` in JSON), never 0 and never a ratio of two such spreads (the twenty-first
//! attack: one filtered value printed 0.0000 "reproduces the record to its rounding", 23 of
//! them 1.00x). The records are ramps, whose filtered values are known: the moving average of
//! `i, i + 1, … i + w - 1` is `i + (w - 1) / 2`, so their peak-to-peak is the number of values
//! less one.

use driftlab::judge::metrics::{
    Comparison, MIN_DISJOINT_FILTER_WINDOWS, MeritOptions, Unavailable, figures, figures_over,
};

/// A ramp of `n` samples a second apart rising 1 deg/h a sample from `from`.
fn ramp(n: usize, from: f64) -> Vec<f64> {
    (0..n).map(|i| from + i as f64).collect()
}

/// A filter of `w` samples (at 1 s) and windows as long as the records.
fn opts(w: usize) -> MeritOptions {
    MeritOptions {
        filter_s: w as f64,
        window_s: 10.0,
    }
}

#[test]
fn two_windows_apart_are_the_least_a_spread_is_computed_from() {
    assert_eq!(MIN_DISJOINT_FILTER_WINDOWS, 2);
    let w = 100;
    // Twice the filter: the first and last filtered values average samples 0..100 and
    // 100..200, apart; 101 values of a ramp span 100 deg/h.
    let f = figures(&ramp(2 * w, 5.0), 1.0, 0, &opts(w));
    assert_eq!(f.filtered_unavailable, None);
    assert!((f.p2p_dph - w as f64).abs() < 1e-9, "{f:?}");
    // Every value: 5 + (w - 1) / 2 + j, j = 0..=w; their std is that of 0..=w.
    let m = w as f64 / 2.0;
    let var = (0..=w).map(|j| (j as f64 - m).powi(2)).sum::<f64>() / (w + 1) as f64;
    assert!((f.std_dph - var.sqrt()).abs() < 1e-9, "{f:?}");
    // One sample shorter down to as long as the filter: every value overlaps every other.
    for n in [2 * w - 1, w + 23, w] {
        let f = figures(&ramp(n, 5.0), 1.0, 0, &opts(w));
        assert_eq!(
            f.filtered_unavailable,
            Some(Unavailable::FilterOverlapsItself),
            "{n} samples"
        );
        assert!(f.p2p_dph.is_nan() && f.std_dph.is_nan(), "{n}: {f:?}");
        let json = serde_json::to_value(f).unwrap();
        assert!(
            json["p2p_dph"].is_null() && json["std_dph"].is_null(),
            "{json}"
        );
        assert_eq!(json["filtered_unavailable"], "filter_overlaps_itself");
        // The other figures still are: the mean of the ramp.
        assert!((f.mean_dph - (5.0 + (n - 1) as f64 / 2.0)).abs() < 1e-9);
    }
    // Shorter than the filter: no value at all, as before.
    let f = figures(&ramp(w - 1, 5.0), 1.0, 0, &opts(w));
    assert_eq!(f.filtered_unavailable, Some(Unavailable::ShorterThanFilter));
    // The warm-up left out counts: 2w samples of which 1 is skipped are too few.
    let f = figures(&ramp(2 * w, 5.0), 1.0, 1, &opts(w));
    assert_eq!(
        f.filtered_unavailable,
        Some(Unavailable::FilterOverlapsItself)
    );
}

#[test]
fn stretches_of_a_log_each_count_their_windows_apart() {
    let w = 50;
    // Two stretches, each exactly one filter long: one value each, and the two average
    // samples of different stretches: a spread, the difference of the two stretches' means.
    let mut x = ramp(w, 0.0);
    x.extend(ramp(w, 1000.0));
    let ready = [0..w, w..2 * w];
    let f = figures_over(&x, 1.0, &ready, &opts(w));
    assert_eq!(f.filtered_unavailable, None, "{f:?}");
    assert!((f.p2p_dph - 1000.0).abs() < 1e-9, "{f:?}");
    // One stretch of one value and a stretch shorter than the filter: one value in all.
    let ready = [0..w, w..2 * w - 1];
    let f = figures_over(&x, 1.0, &ready, &opts(w));
    assert_eq!(
        f.filtered_unavailable,
        Some(Unavailable::FilterOverlapsItself)
    );
    assert!(f.p2p_dph.is_nan());
}

#[test]
fn raw_and_corrected_of_one_filtered_value_give_no_ratio_and_the_filters_reason() {
    let w = 100;
    let raw = ramp(w, 3.0);
    let corrected: Vec<f64> = raw.iter().map(|v| v - 3.0 - 0.5 * (v - 3.0)).collect();
    let ready = [std::ops::Range { start: 0, end: w }];
    let c = Comparison::of(&raw, &corrected, 1.0, &ready, &opts(w));
    assert!(c.p2p_ratio.is_nan() && c.std_ratio.is_nan(), "{c:?}");
    // Not "the correction reproduces the record to its rounding": both figures are n/a.
    assert_eq!(c.ratios_unavailable, None);
    assert!(
        c.unavailable()
            .contains(&("peak-to-peak and std", Unavailable::FilterOverlapsItself)),
        "{:?}",
        c.unavailable()
    );
    let why = Unavailable::FilterOverlapsItself.describe();
    assert!(
        why.contains("filter") && why.contains("shorten the filter or judge a longer log"),
        "{why}"
    );
}
