//! The chamber simulator's laser gyro: its channels logged and read back by name, its drift
//! recovered as Sukhanov's model with the self-heating term, and the noise-only run.

use driftlab::log::ingest::{self, ReadOptions};
use driftlab::sim::{LaserParams, SimRun, profile, simulate, simulate_noise_only};

use crate::common;
use common::sim::*;

/// Solves the least-squares problem `X·b ≈ y` for the columns `cols` (each standardised, so
/// that the normal equations stay well conditioned), returning b and the residual sum of
/// squares.
fn least_squares(cols: &[Vec<f64>], y: &[f64]) -> (Vec<f64>, f64) {
    let k = cols.len();
    let n = y.len() as f64;
    // Scale of each column: its root mean square (a constant column keeps scale 1).
    let scale: Vec<f64> = cols
        .iter()
        .map(|c| {
            (c.iter().map(|v| v * v).sum::<f64>() / n)
                .sqrt()
                .max(1e-300)
        })
        .collect();
    let mut a = vec![vec![0.0; k + 1]; k];
    for i in 0..k {
        for j in 0..k {
            a[i][j] = cols[i]
                .iter()
                .zip(&cols[j])
                .map(|(x, z)| x * z)
                .sum::<f64>()
                / (scale[i] * scale[j]);
        }
        a[i][k] = cols[i].iter().zip(y).map(|(x, v)| x * v).sum::<f64>() / scale[i];
    }
    // Gauss-Jordan with partial pivoting.
    for c in 0..k {
        let piv = (c..k)
            .max_by(|&p, &q| a[p][c].abs().total_cmp(&a[q][c].abs()))
            .unwrap();
        a.swap(c, piv);
        let pivot = a[c].clone();
        for (r, row) in a.iter_mut().enumerate() {
            if r != c {
                let f = row[c] / pivot[c];
                for (x, p) in row[c..].iter_mut().zip(&pivot[c..]) {
                    *x -= f * p;
                }
            }
        }
    }
    let b: Vec<f64> = (0..k).map(|i| a[i][k] / a[i][i] / scale[i]).collect();
    let sse = y
        .iter()
        .enumerate()
        .map(|(s, v)| {
            let pred: f64 = (0..k).map(|i| b[i] * cols[i][s]).sum();
            (v - pred) * (v - pred)
        })
        .sum();
    (b, sse)
}

/// The laser-gyro run written as CSV and read back by the engine's reader.
fn laser_log(seed: u64) -> (SimRun, driftlab::Log) {
    let dir = tempfile::tempdir().unwrap();
    let run = simulate(&profile("laser-gyro").unwrap(), seed);
    let path = dir.path().join("laser.csv");
    run.write_csv(&path).unwrap();
    let log = ingest::read_path(&path, &ReadOptions::default()).unwrap();
    (run, log)
}

#[test]
fn laser_channels_are_logged_and_read_back_by_name() {
    let (run, log) = laser_log(1);
    assert_eq!(log.len(), run.len());
    assert!(log.time_s == run.time_s);
    // The resonator-base sensor is the first temperature column: the calibration temperature.
    assert!(log.temp_c == run.temp_c);
    assert_eq!(
        log.extra
            .iter()
            .map(|c| c.name.as_str())
            .collect::<Vec<_>>(),
        [
            "temp_chamber_c",
            "temp_housing_c",
            "laser_power_mw",
            "piezo_v",
            "dither_amp_arcsec"
        ]
    );
    for c in &run.channels {
        // The channels are quantised to the decimals written: they read back exactly.
        assert!(
            log.channel(&c.name).unwrap().values == c.values,
            "{}",
            c.name
        );
    }
    assert_eq!(log.channel("temp_housing_c").unwrap().unit, "°C");
    let from_run = run.to_log("sim:laser-gyro");
    let names = |l: &driftlab::Log| l.extra.iter().map(|c| c.name.clone()).collect::<Vec<_>>();
    assert_eq!(names(&from_run), names(&log));
    assert!(from_run.temp_c == log.temp_c);
    assert_eq!(from_run.channel("laser_power_mw").unwrap().unit, "mW");

    // Realistic, slowly varying channels within their ranges.
    let l = LaserParams::default();
    let range = |name: &str| {
        let v = &log.channel(name).unwrap().values;
        (
            v.iter().cloned().fold(f64::INFINITY, f64::min),
            v.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
        )
    };
    let (pmin, pmax) = range("laser_power_mw");
    assert!(
        pmin > 0.6 && pmax < 0.95 && pmax - pmin > 0.1,
        "{pmin}..{pmax}"
    );
    let (umin, umax) = range("piezo_v");
    assert!(
        umin > 40.0 && umax < 170.0 && umax - umin > 60.0,
        "{umin}..{umax}"
    );
    let (amin, amax) = range("dither_amp_arcsec");
    let band = l.dither_band_arcsec + l.dither_drive_step_arcsec;
    assert!(
        amin > l.dither_setpoint_arcsec - band - 0.5
            && amax < l.dither_setpoint_arcsec + band + 0.5,
        "stabilised: {amin}..{amax}"
    );
    assert!(amax - amin > 2.0, "but moving: {amin}..{amax}");

    // Self-heating: powered on in a constant chamber, the base warms by both self-heating
    // rises, the housing by its own, within the first two hours.
    let i = index_at(&run, 7000.0);
    let rise_base = log.temp_c[i] - log.temp_c[0];
    let rise_housing = log.channel("temp_housing_c").unwrap().values[i] - 20.0;
    let want_base = l.housing_self_heating_c + l.base_self_heating_c;
    assert!(
        (rise_base - want_base).abs() < 0.1,
        "base rose {rise_base} °C"
    );
    assert!((rise_housing - l.housing_self_heating_c).abs() < 0.05);
}

#[test]
fn laser_drift_is_sukhanovs_model_with_its_self_heating_term() {
    // Fit Ω = k0 + k1·T + k2·T² + B1·(1 − e^(−t/λ)) + B2·ΔT + B3·ΔT² + B4·A + B5·P + B6·U on the
    // noise-free drift, with the channels as the reader gets them from the CSV, λ by a search:
    // the profile's constants come back.
    let (run, log) = laser_log(2);
    let l = LaserParams::default();
    let t = &log.time_s;
    let tr: Vec<f64> = log.temp_c.iter().map(|v| v - 20.0).collect();
    let th = &log.channel("temp_housing_c").unwrap().values;
    let dt: Vec<f64> = th.iter().zip(&log.temp_c).map(|(h, r)| h - r).collect();
    let ch = |name: &str, offset: f64| -> Vec<f64> {
        log.channel(name)
            .unwrap()
            .values
            .iter()
            .map(|v| v - offset)
            .collect()
    };
    let fixed = vec![
        vec![1.0; t.len()],
        tr.clone(),
        tr.iter().map(|v| v * v).collect(),
        dt.clone(),
        dt.iter().map(|v| v * v).collect(),
        ch("dither_amp_arcsec", 400.0),
        ch("laser_power_mw", 0.8),
        ch("piezo_v", 100.0),
    ];
    let fit = |lambda: f64| {
        let mut cols = fixed.clone();
        cols.push(t.iter().map(|s| 1.0 - (-s / lambda).exp()).collect());
        least_squares(&cols, &run.thermal_dph)
    };
    let mut best = (f64::INFINITY, 0.0);
    for lambda in (6..=144).map(|k| k as f64 * 50.0) {
        best = best.min_by_key_sse(lambda, fit(lambda).1);
    }
    let coarse = best.1;
    for lambda in (-50..=50).map(|k| coarse + k as f64) {
        best = best.min_by_key_sse(lambda, fit(lambda).1);
    }
    let lambda = best.1;
    let (b, _) = fit(lambda);
    let rel = |got: f64, want: f64| (got / want - 1.0).abs();
    assert!(
        rel(lambda, l.self_heating_tau_s) < 0.03,
        "λ {lambda} s, want {}",
        l.self_heating_tau_s
    );
    assert!(
        rel(b[8], l.b1_self_heating_dph) < 0.03,
        "B1 {}, want {}",
        b[8],
        l.b1_self_heating_dph
    );
    for (i, want, what) in [
        (1, l.bias_slope_dph_per_c, "k1"),
        (3, l.b2_dph_per_c, "B2"),
        (4, l.b3_dph_per_c2, "B3"),
        (5, l.b4_dph_per_arcsec, "B4"),
        (6, l.b5_dph_per_mw, "B5"),
        (7, l.b6_dph_per_v, "B6"),
    ] {
        assert!(rel(b[i], want) < 0.05, "{what} {} want {want}", b[i]);
    }

    // The self-heating term itself is in the truth, with its shape.
    let truth = run.laser.as_ref().unwrap();
    for &s in &[0.0, 1800.0, 7200.0] {
        let i = index_at(&run, s);
        let want = l.b1_self_heating_dph * (1.0 - (-s / l.self_heating_tau_s).exp());
        assert!((truth.self_heating_dph[i] - want).abs() < 1e-12);
    }
    // The drift spans a few tenths of °/h filtered, several times the filtered noise.
    let drift = p2p(&centred_ma(&run.thermal_dph, 100));
    let noise = p2p(&centred_ma(&run.noise_dph, 100));
    assert!((0.25..=1.0).contains(&drift), "filtered drift p2p {drift}");
    assert!(drift > 2.0 * noise, "{drift} vs noise {noise}");
}

/// Keeps the (SSE, λ) pair of the smaller SSE.
trait MinSse {
    fn min_by_key_sse(self, lambda: f64, sse: f64) -> Self;
}

impl MinSse for (f64, f64) {
    fn min_by_key_sse(self, lambda: f64, sse: f64) -> Self {
        if sse < self.0 { (sse, lambda) } else { self }
    }
}

#[test]
fn noise_only_run_is_the_noise_of_the_full_run() {
    for name in ["fast-ramps", "laser-gyro"] {
        let p = profile(name).unwrap();
        let full = simulate(&p, 9);
        let quiet = simulate_noise_only(&p, 9);
        assert!(quiet.noise_only && !full.noise_only);
        assert!(quiet.time_s == full.time_s, "{name}: same time grid");
        assert!(
            quiet.omega_dph == full.noise_dph,
            "{name}: same noise samples"
        );
        assert!(quiet.noise_dph == full.noise_dph);
        assert!(quiet.thermal_dph.iter().all(|&x| x == 0.0));
        assert!(quiet.temp_c == full.temp_c);
        assert!(quiet.chamber_c == full.chamber_c);
        assert!(quiet.channels == full.channels);
        for i in 0..full.len() {
            // Full output minus the noise floor is the deterministic drift (to the rounding of
            // the one addition that made the output).
            let d = full.omega_dph[i] - quiet.omega_dph[i];
            assert!(
                (d - full.thermal_dph[i]).abs() <= 1e-12,
                "{name} sample {i}"
            );
        }
        if let Some(l) = &quiet.laser {
            assert!(l.self_heating_dph.iter().all(|&x| x == 0.0));
        }
        // Its CSV says what it is and differs from the full one by the drift alone.
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("full.csv"), dir.path().join("noise.csv"));
        full.write_csv(&a).unwrap();
        quiet.write_csv(&b).unwrap();
        let text = std::fs::read_to_string(&b).unwrap();
        assert_eq!(
            text.lines().next().unwrap(),
            format!("# driftlab simulate --profile {name} --seed 9 --noise-only")
        );
        let la = ingest::read_path(&a, &ReadOptions::default()).unwrap();
        let lb = ingest::read_path(&b, &ReadOptions::default()).unwrap();
        assert!(la.time_s == lb.time_s);
        assert!(la.temp_c == lb.temp_c);
        assert!(la.extra == lb.extra);
        for i in 0..la.len() {
            let d = la.omega_dph[i] - lb.omega_dph[i];
            assert!(
                (d - full.thermal_dph[i]).abs() <= 1e-4 + 1e-9,
                "{name} row {i}"
            );
        }
    }
}
