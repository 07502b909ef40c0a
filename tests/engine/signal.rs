//! Filters and derivatives against closed-form truth.
#![allow(clippy::needless_range_loop)] // tests index several columns by sample number

use driftlab::signal::{self, DerivativeSteps};

fn quadratic(a: f64, b: f64, c: f64, n: usize, dt: f64) -> Vec<f64> {
    (0..n)
        .map(|i| {
            let t = i as f64 * dt;
            a + b * t + c * t * t
        })
        .collect()
}

#[test]
fn backward_difference_is_exact_for_quadratics() {
    let (b, c, dt) = (0.3, -0.0125, 0.5);
    let x = quadratic(20.0, b, c, 400, dt);
    for step in [1, 3, 10] {
        let d = signal::backward_derivative(&x, step, dt);
        for i in 2 * step..x.len() {
            let t = i as f64 * dt;
            assert!(
                (d[i] - (b + 2.0 * c * t)).abs() < 1e-9,
                "step {step} sample {i}: {} vs {}",
                d[i],
                b + 2.0 * c * t
            );
        }
        assert!(
            d[..2 * step].iter().all(|&v| v == 0.0),
            "no rate before the history is full"
        );
    }
}

#[test]
fn second_derivative_of_quadratic_is_constant_and_exact() {
    let (c, dt) = (0.004, 1.0);
    let x = quadratic(-5.0, 0.1, c, 300, dt);
    let d = signal::derivatives(&x, DerivativeSteps { smooth: 1, step: 4 }, dt);
    assert_eq!(d.ready_from, 16);
    for i in d.ready_from..x.len() {
        assert!(
            (d.tddot[i] - 2.0 * c).abs() < 1e-9,
            "sample {i}: {}",
            d.tddot[i]
        );
    }
}

#[test]
fn causal_smoothing_delays_a_quadratic_by_half_the_window() {
    // The mean of a quadratic over the last w samples is the quadratic at the window's centre
    // plus a constant c·(w²−1)/12·dt²: its derivative is the true rate (w−1)/2 samples earlier.
    let (b, c, dt, w) = (0.02, 1e-4, 1.0, 9);
    let x = quadratic(10.0, b, c, 500, dt);
    let d = signal::derivatives(&x, DerivativeSteps { smooth: w, step: 5 }, dt);
    for i in (w + 20)..x.len() {
        let t_centre = (i as f64 - (w as f64 - 1.0) / 2.0) * dt;
        assert!((d.tdot[i] - (b + 2.0 * c * t_centre)).abs() < 1e-10);
        assert!((d.tddot[i] - 2.0 * c).abs() < 1e-10);
    }
}

#[test]
fn one_pass_derivatives_are_the_three_passes_bit_for_bit() {
    // `derivatives` fuses the causal mean and both differences into one pass; it must give the
    // very bits of the three separate passes (the streaming corrector makes those).
    let x: Vec<f64> = (0..5000)
        .map(|i| {
            let t = i as f64;
            20.0 + 30.0 * (t / 700.0).sin() + 0.001 * ((i * 7919) % 13) as f64
        })
        .collect();
    for (smooth, step, n) in [
        (1, 1, 5000),
        (9, 5, 5000),
        (60, 30, 5000),
        (300, 7, 200),
        (3, 50, 60),
    ] {
        let x = &x[..n];
        let dt = 0.5;
        let d = signal::derivatives(x, DerivativeSteps { smooth, step }, dt);
        let sm = signal::moving_average_causal(x, smooth);
        let tdot = signal::backward_derivative(&sm, step, dt);
        let mut tddot = signal::backward_derivative(&tdot, step, dt);
        tddot[..(4 * step).min(n)].fill(0.0);
        // Full history: the smoothing window filled, then 4 steps.
        let ready = (4 * step + smooth.max(1) - 1).min(n);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(
            bits(&d.tdot),
            bits(&tdot),
            "Tdot, smooth {smooth} step {step}"
        );
        assert_eq!(
            bits(&d.tddot),
            bits(&tddot),
            "Tddot, smooth {smooth} step {step}"
        );
        assert_eq!(d.ready_from, ready);
    }
}

#[test]
fn centred_average_leaves_a_line_unchanged() {
    let x: Vec<f64> = (0..200).map(|i| 3.0 - 0.25 * i as f64).collect();
    for w in [1, 2, 7, 100] {
        let m = signal::moving_average_centered(&x, w);
        // Away from the ends an odd window is symmetric; an even one is centred half a sample late.
        let shift = if w % 2 == 0 { -0.125 } else { 0.0 };
        for i in w..200 - w {
            assert!((m[i] - (x[i] + shift)).abs() < 1e-9, "w {w} i {i}");
        }
    }
    let valid = signal::moving_average_valid(&x, 11);
    assert_eq!(valid.len(), 190);
    assert!((valid[0] - x[5]).abs() < 1e-12);
}

#[test]
fn causal_average_fills_its_window_then_slides() {
    let x = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
    assert_eq!(
        signal::moving_average_causal(&x, 3),
        vec![1.0, 1.5, 2.0, 3.0, 4.0, 5.0]
    );
}

#[test]
fn seconds_become_whole_samples() {
    assert_eq!(signal::seconds_to_samples(100.0, 1.0), 100);
    assert_eq!(signal::seconds_to_samples(30.0, 0.01), 3000);
    assert_eq!(signal::seconds_to_samples(0.2, 1.0), 1);
    assert_eq!(signal::seconds_to_samples(f64::NAN, 1.0), 1);
}

/// A plateau is marked outside the detector's limits when T moves on average faster than the
/// detector's rate, or when it is shorter than the settled half of its shortest stretch; a
/// steady plateau of the detector's length is not.
#[test]
fn a_plateau_outside_the_detectors_limits_says_why() {
    use driftlab::signal::plateau::{DetectOptions, PlateauRange, PlateauStats, outside_detector};
    let plateau = |start_s: f64, end_s: f64, spread: f64| PlateauStats {
        range: PlateauRange { start_s, end_s },
        temp_c: 20.0,
        omega_dph: 0.0,
        omega_std_dph: Some(0.01),
        omega_sem_dph: Some(0.001),
        temp_spread_c: spread,
        samples: (end_s - start_s) as usize,
    };
    let opts = DetectOptions::default();
    // 0.016 °C over 30 min: a hold.
    assert!(outside_detector(&plateau(0.0, 1800.0, 0.016), &opts).is_empty());
    // 1 °C over 10 min: 0.1 °C/min, twice the detector's 0.05.
    let ramp = outside_detector(&plateau(0.0, 600.0, 1.0), &opts);
    assert_eq!(ramp.len(), 1, "{ramp:?}");
    assert!(
        ramp[0].contains("0.1 °C/min") && ramp[0].contains("0.05"),
        "{ramp:?}"
    );
    // 5 min: shorter than the 600 s (half of 1200 s) a detected plateau lasts at least.
    let short = outside_detector(&plateau(0.0, 300.0, 0.01), &opts);
    assert_eq!(short.len(), 1, "{short:?}");
    assert!(
        short[0].contains("300 s") && short[0].contains("600 s"),
        "{short:?}"
    );
    // Both at once.
    assert_eq!(outside_detector(&plateau(0.0, 300.0, 1.0), &opts).len(), 2);
}
