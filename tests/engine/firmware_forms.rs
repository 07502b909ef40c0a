//! The polynomial models in T (`px4`, `ardupilot`, `poly-tN`) recover the coefficients of
//! logs made with known cubic and quintic biases; the reference rows `px4-script` and
//! `ardupilot-script` are the fits PX4's `process_sensor_caldata.py` and ArduPilot's
//! `tempcal_IMU.py` make, computed here again from the scripts' steps (a median of 31 padded
//! with zeros, 2,000 temperature bins, a 2-s moving average, least squares by the normal
//! equations) written in this file.

use crate::common::Noise;
use driftlab::judge::compare;
use driftlab::judge::metrics::MeritOptions;
use driftlab::log::Log;
use driftlab::models::{self, CheckedRecipe, DriftModel, ModelChoice, Preset};
use std::f64::consts::TAU;

/// Six hours at 1 Hz (or `hz`) between 10 and 60 °C, the rate `Σ a_k·(T − 35)^k` °/h plus
/// white noise of `sigma`.
pub(crate) fn log_of(a: &[f64], sigma: f64, hz: f64, seconds: f64, seed: u64) -> Log {
    let mut noise = Noise::new(seed);
    let n = (seconds * hz) as usize;
    let time: Vec<f64> = (0..n).map(|i| i as f64 / hz).collect();
    let temp: Vec<f64> = time
        .iter()
        .map(|t| 35.0 - 25.0 * (TAU * t / 10_800.0).cos())
        .collect();
    let rate = temp
        .iter()
        .map(|&t| horner(a, t - 35.0) + sigma * noise.normal())
        .collect();
    Log::from_columns("poly.csv", time, rate, temp)
}

fn horner(a: &[f64], x: f64) -> f64 {
    a.iter().rev().fold(0.0, |v, c| v * x + c)
}

/// The coefficients of `Σ a_k·x^k` in powers of `x − by`.
fn shifted(a: &[f64], by: f64) -> Vec<f64> {
    let n = a.len();
    let mut b = a.to_vec();
    // Repeated synthetic division (Taylor shift).
    for i in 0..n {
        for j in (i..n - 1).rev() {
            b[j] += by * b[j + 1];
        }
    }
    b
}

fn fitted(log: &Log, name: &str) -> driftlab::models::regression::RegressionModel {
    let choice = ModelChoice::Preset(Preset::from_name(name).unwrap());
    match models::fit(log, &choice, &CheckedRecipe::default()).unwrap() {
        DriftModel::Regression(r) => r.model,
        DriftModel::Vakhrameev(_) => panic!("{name} is a regression"),
    }
}

/// The model's coefficients against the truth `a` (about 35 °C) moved to the model's Tref.
fn assert_recovered(name: &str, a: &[f64], log: &Log, tolerance: f64) {
    let m = fitted(log, name);
    let t_ref = m.t_ref_c.expect("a Tref");
    let want = shifted(a, t_ref - 35.0);
    assert_eq!(m.coefficients.len(), want.len(), "{name}");
    for (k, (got, want)) in m.coefficients.iter().zip(&want).enumerate() {
        let scale = 25f64.powi(k as i32); // the size of (T − Tref)^k over the range
        assert!(
            (got - want).abs() * scale <= tolerance,
            "{name}: coefficient {k} is {got}, the log was made with {want}"
        );
    }
}

#[test]
fn cubic_and_quintic_biases_are_recovered() {
    let cubic = [12.0, 0.8, -0.03, 4e-4];
    let quintic = [12.0, 0.8, -0.03, 4e-4, 3e-6, -8e-8];
    // Without noise the least squares must give the polynomial itself.
    let clean = log_of(&cubic, 0.0, 1.0, 21_600.0, 1);
    for name in ["px4", "ardupilot", "poly-t3"] {
        assert_recovered(name, &cubic, &clean, 1e-7);
    }
    let clean = log_of(&quintic, 0.0, 1.0, 21_600.0, 2);
    assert_recovered("poly-t5", &quintic, &clean, 1e-7);
    // Tref is the middle of the range fitted (the warm-up's first samples left out),
    // ArduPilot's a fixed 35 °C.
    let m = fitted(&clean, "poly-t5");
    let [lo, hi] = m.ranges.temp.unwrap();
    assert_eq!(m.t_ref_c, Some(0.5 * (lo + hi)));
    assert_eq!(fitted(&clean, "ardupilot").t_ref_c, Some(35.0));
    // With white noise of 0.05 deg/h, each term within 0.05 deg/h of its size over the
    // range (about six standard errors of the fifth power's).
    let noisy = log_of(&quintic, 0.05, 1.0, 21_600.0, 3);
    assert_recovered("poly-t5", &quintic, &noisy, 0.05);
    let noisy = log_of(&cubic, 0.05, 1.0, 21_600.0, 4);
    assert_recovered("px4", &cubic, &noisy, 0.05);
    // A cubic fitted to the quintic misses it, which is why an order is a choice.
    let m = fitted(&log_of(&quintic, 0.0, 1.0, 21_600.0, 5), "poly-t3");
    let x = 25.0;
    let at = |t_ref: f64| horner(&m.coefficients, 35.0 + x - t_ref) - horner(&quintic, x);
    assert!(at(m.t_ref_c.unwrap()).abs() > 0.05);
}

// ---- The scripts, step by step -------------------------------------------------------------

/// `scipy.signal.medfilt(x, k)`: the median of the k samples centred on each, zeros past the
/// ends.
fn medfilt(x: &[f64], k: usize) -> Vec<f64> {
    let h = k / 2;
    (0..x.len())
        .map(|i| {
            let mut w: Vec<f64> = (0..k)
                .map(|j| {
                    let at = i as i64 + j as i64 - h as i64;
                    if at < 0 || at >= x.len() as i64 {
                        0.0
                    } else {
                        x[at as usize]
                    }
                })
                .collect();
            w.sort_by(|a, b| a.partial_cmp(b).unwrap());
            w[h]
        })
        .collect()
}

/// `np.polyfit(x, y, 3)` by the normal equations and Gaussian elimination, lowest power
/// first.
fn cubic_fit(x: &[f64], y: &[f64]) -> [f64; 4] {
    let mut m = [[0.0f64; 5]; 4];
    for (&xi, &yi) in x.iter().zip(y) {
        let p = [1.0, xi, xi * xi, xi * xi * xi];
        for r in 0..4 {
            for c in 0..4 {
                m[r][c] += p[r] * p[c];
            }
            m[r][4] += p[r] * yi;
        }
    }
    for col in 0..4 {
        let pivot = (col..4)
            .max_by(|&a, &b| m[a][col].abs().partial_cmp(&m[b][col].abs()).unwrap())
            .unwrap();
        m.swap(col, pivot);
        let pivot_row = m[col];
        for (r, row) in m.iter_mut().enumerate() {
            if r != col {
                let f = row[col] / pivot_row[col];
                for (v, p) in row.iter_mut().zip(pivot_row).skip(col) {
                    *v -= f * p;
                }
            }
        }
    }
    [0, 1, 2, 3].map(|k| m[k][4] / m[k][k])
}

/// PX4's fit: (coefficients about TREF, TMIN, TMAX, TREF).
fn px4_script(log: &Log) -> ([f64; 4], f64, f64, f64) {
    let lo = log.temp_c.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = log.temp_c.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let t_ref = 0.5 * (lo + hi);
    let rel: Vec<f64> = log.temp_c.iter().map(|t| t - t_ref).collect();
    let y = medfilt(&log.omega_dph, 31);
    // resampleWithDeltaX
    let (x_min, x_max) = (lo - t_ref, hi - t_ref);
    let interval = (x_max - x_min) / 2000.0;
    let mut bins = vec![(0.0, 0.0, 0usize); 2000];
    for (&x, &v) in rel.iter().zip(&y) {
        let b = if x < x_max {
            ((x - x_min) / interval) as usize
        } else {
            1999
        };
        bins[b].0 += x;
        bins[b].1 += v;
        bins[b].2 += 1;
    }
    let (bx, by): (Vec<f64>, Vec<f64>) = bins
        .iter()
        .filter(|b| b.2 > 0)
        .map(|b| (b.0 / b.2 as f64, b.1 / b.2 as f64))
        .unzip();
    (cubic_fit(&bx, &by), lo, hi, t_ref)
}

/// ArduPilot's fit: (coefficients about 35 °C, TMIN, TMAX).
fn ardupilot_script(log: &Log) -> ([f64; 4], f64, f64) {
    let n = log.time_s.len();
    let seconds = log.time_s[n - 1] - log.time_s[0];
    let w = (n as f64 / seconds).floor() as usize * 2;
    let avg = |v: &[f64]| -> Vec<f64> {
        (w - 1..v.len())
            .map(|i| v[i + 1 - w..=i].iter().sum::<f64>() / w as f64)
            .collect()
    };
    let t = avg(&log.temp_c);
    let y = avg(&log.omega_dph);
    let lo = t.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = t.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let x: Vec<f64> = t.iter().map(|t| t - 35.0).collect();
    (cubic_fit(&x, &y), lo, hi)
}

/// A small log at 2 Hz: T climbing unevenly (fast, then slow), a cubic rate with noise and
/// spikes a median filter removes.
fn small_log() -> Log {
    let mut noise = Noise::new(23);
    let n = 4000;
    let time: Vec<f64> = (0..n).map(|i| i as f64 * 0.5).collect();
    let temp: Vec<f64> = time
        .iter()
        .map(|&t| 15.0 + 40.0 * (t / 2000.0).sqrt() + 0.02 * noise.normal())
        .collect();
    let rate = temp
        .iter()
        .enumerate()
        .map(|(i, &t)| {
            let x = t - 35.0;
            let spike = if i % 97 == 0 { 400.0 } else { 0.0 };
            30.0 + 2.0 * x - 0.05 * x * x + 0.002 * x * x * x + 3.0 * noise.normal() + spike
        })
        .collect();
    Log::from_columns("small.csv", time, rate, temp)
}

fn close(a: f64, b: f64, what: &str) {
    assert!(
        (a - b).abs() <= 1e-7 * (1.0 + a.abs().max(b.abs())),
        "{what}: {a} against {b}"
    );
}

#[test]
fn the_reference_rows_are_the_scripts_own_fits() {
    let log = small_log();
    let reports = compare::compare(
        &log,
        &[],
        &[
            ModelChoice::Preset(Preset::Px4),
            ModelChoice::Preset(Preset::Px4Script),
            ModelChoice::Preset(Preset::ArduPilotScript),
        ],
        &CheckedRecipe::default(),
        &MeritOptions::default(),
    );
    assert_eq!(
        reports.iter().map(|r| r.reference).collect::<Vec<_>>(),
        [false, true, true]
    );
    let model = |k: usize| match reports[k].fitted.as_ref().unwrap() {
        DriftModel::Regression(r) => r.model.clone(),
        DriftModel::Vakhrameev(_) => panic!("a regression"),
    };
    let (c, lo, hi, t_ref) = px4_script(&log);
    let m = model(1);
    close(m.t_ref_c.unwrap(), t_ref, "px4 TREF");
    assert_eq!(m.ranges.temp, Some([lo, hi]));
    for (k, want) in c.iter().enumerate() {
        close(m.coefficients[k], *want, &format!("px4 X{k}"));
    }
    let (c, lo, hi) = ardupilot_script(&log);
    let m = model(2);
    assert_eq!(m.t_ref_c, Some(35.0));
    close(m.ranges.temp.unwrap()[0], lo, "ardupilot TMIN");
    close(m.ranges.temp.unwrap()[1], hi, "ardupilot TMAX");
    for (k, want) in c.iter().enumerate() {
        close(m.coefficients[k], *want, &format!("ardupilot GYR{k}"));
    }
    // The rows' corrections are those polynomials, T held to the scripts' ranges.
    let pred = reports[2]
        .fitted
        .as_ref()
        .unwrap()
        .predict_log(&log)
        .unwrap()
        .pred_dph;
    // Past the rates' warm-up, which every model's figures leave out.
    for (i, &t) in log.temp_c.iter().enumerate().skip(400).step_by(37) {
        let x = t.clamp(lo, hi) - 35.0;
        close(
            pred[i],
            horner(&c, x),
            &format!("ardupilot prediction at sample {i}"),
        );
    }
    // The scripts' filtering differs from driftlab's least squares over every sample.
    let own = model(0);
    assert!((own.coefficients[3] - model(1).coefficients[3]).abs() > 0.0);
}
