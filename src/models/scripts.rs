//! The fits the flight controllers' own calibration scripts make, as reference rows of
//! `compare` (`px4-script`, `ardupilot-script`): what an engineer's firmware script would
//! have given on the same log, shown beside driftlab's models.
//!
//! Each is written from the script's code and gives an ordinary regression model (a constant
//! and the powers of `T − Tref` to the third, T held to the script's `[TMIN, TMAX]`), so that
//! it is judged, saved, applied and exported as every other model is:
//!
//! * PX4, `Tools/process_sensor_caldata.py` (gyro section): `TMIN`, `TMAX` the lowest and
//!   highest raw temperature, `TREF = 0.5·(TMIN + TMAX)`; the rate through `medfilt(x, 31)`
//!   (a running median of 31 samples, the log's ends padded with zeros, as SciPy pads them);
//!   `resampleWithDeltaX`: `T − TREF` cut into 2,000 equal bins between its extremes, each
//!   non-empty bin's mean T and mean rate one point; `np.polyfit(temp, sens, 3)` on the
//!   points.
//! * ArduPilot, `Tools/scripts/tempcal_IMU.py`: `Filter(2)`, a moving average of
//!   `int(samples / seconds)·2` samples over the rate, T and time alike (NumPy's cumulative
//!   sum, the first window's end the first output, so the filtered log is shorter by the
//!   window less one); `TMIN`, `TMAX` the filtered T's extremes; `np.polyfit(T − 35, rate,
//!   3)` on every filtered sample, `POLY_ORDER = 3` and `TEMP_REF = 35`. The script writes
//!   the coefficients of orders 1 to 3 and leaves the constant to the offsets measured at
//!   boot; the model keeps it, as the script's own plot of the corrected rate does.
//!
//! Samples whose time, T or rate is not a number are left out first (the scripts read logs
//! that hold none). Neither script reads the recipe's smoothing, derivative step or plateaus.

use crate::error::Result;
use crate::log::Log;
use crate::models::FitError;
use crate::models::presets::ARDUPILOT_TEMP_REFERENCE_C;
use crate::models::regression::{
    Delay, InputRanges, RegressionModel, RegressionSpec, RegressionStats, TRefSpec, Term, terms,
};
use nalgebra::{DMatrix, DVector};

/// A firmware's calibration script.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Script {
    /// PX4's `Tools/process_sensor_caldata.py`.
    Px4,
    /// ArduPilot's `Tools/scripts/tempcal_IMU.py`.
    ArduPilot,
}

/// The window of PX4's median filter, samples (`medfilt(data, 31)`).
pub const PX4_MEDIAN_SAMPLES: usize = 31;

/// The temperature bins of PX4's `resampleWithDeltaX` (`nbInterval`).
pub const PX4_BINS: usize = 2000;

/// The width of ArduPilot's moving average, s (`data.Filter(2)`).
pub const ARDUPILOT_AVERAGE_S: f64 = 2.0;

/// The order of both scripts' polynomials.
pub const SCRIPT_ORDER: u8 = 3;

/// The points a script fits its polynomial to: T, rate, and the script's `[TMIN, TMAX]` and
/// Tref.
struct Points {
    temp: Vec<f64>,
    rate: Vec<f64>,
    t_min: f64,
    t_max: f64,
    t_ref: f64,
}

/// The model `script` fits on `log`: a constant and `(T − Tref)^1..3`, T held to the
/// script's `[TMIN, TMAX]`, named `name`.
///
/// # Errors
/// Fewer finite samples than the polynomial has coefficients, or a temperature that does
/// not change.
pub fn fit(log: &Log, script: Script, name: &str, spec: RegressionSpec) -> Result<RegressionModel> {
    let finite: Vec<usize> = (0..log.len())
        .filter(|&i| {
            log.time_s[i].is_finite() && log.temp_c[i].is_finite() && log.omega_dph[i].is_finite()
        })
        .collect();
    let time: Vec<f64> = finite.iter().map(|&i| log.time_s[i]).collect();
    let temp: Vec<f64> = finite.iter().map(|&i| log.temp_c[i]).collect();
    let rate: Vec<f64> = finite.iter().map(|&i| log.omega_dph[i]).collect();
    let p = match script {
        Script::Px4 => px4_points(&temp, &rate),
        Script::ArduPilot => ardupilot_points(&time, &temp, &rate),
    };
    let coefficients = usize::from(SCRIPT_ORDER) + 1;
    if p.temp.len() < coefficients
        || p.t_max.partial_cmp(&p.t_min) != Some(std::cmp::Ordering::Greater)
    {
        return Err(FitError::TooFewForModel {
            log: log.source.clone(),
            count: p.temp.len(),
            model: name.to_string(),
            coefficients,
        }
        .into());
    }
    if p.t_max - p.t_min < crate::models::MIN_TEMP_SPAN_C {
        // The span of the script's points (after ArduPilot's moving average), which the model
        // holds T to and its file is checked against.
        return Err(FitError::NarrowSpan {
            log: log.source.clone(),
            model: name.to_string(),
            span_c: Some((p.t_min, p.t_max)),
            minimum_c: crate::models::MIN_TEMP_SPAN_C,
        }
        .into());
    }
    let x: Vec<f64> = p.temp.iter().map(|t| t - p.t_ref).collect();
    let (beta, std_errors) =
        polyfit(&x, &p.rate, SCRIPT_ORDER).ok_or_else(|| FitError::Unsolvable {
            log: log.source.clone(),
            model: name.to_string(),
            used: p.temp.len(),
            coefficients,
        })?;
    let mut model = RegressionModel {
        names: terms::column_names(&spec.terms),
        spec,
        temp2: None,
        coefficients: beta,
        std_errors,
        lambda_s: None,
        delay: Delay::default(),
        lag_s: None,
        lag_per_c: 0.0,
        t_knots: Vec::new(),
        t_ref_c: Some(p.t_ref),
        ranges: InputRanges {
            temp: Some([p.t_min, p.t_max]),
            ..InputRanges::default()
        },
        dt_s: log.nominal_dt_s(),
        stats: RegressionStats::default(),
        searches: Vec::new(),
    };
    model.stats = stats_over(&model, &temp, &rate);
    Ok(model)
}

/// The spec a script's model is written with: a constant and `(T − Tref)^1..3`, Tref as the
/// script sets it.
pub fn spec(script: Script, name: &str) -> RegressionSpec {
    let mut s = RegressionSpec::new(
        name,
        std::iter::once(Term::One)
            .chain((1..=SCRIPT_ORDER).map(|power| Term::Tc { power }))
            .collect(),
    );
    s.t_ref = match script {
        Script::Px4 => TRefSpec::MidRange,
        Script::ArduPilot => TRefSpec::Fixed {
            celsius: ARDUPILOT_TEMP_REFERENCE_C,
        },
    };
    s
}

/// PX4's points: the raw T's range and middle, the rate median-filtered, both binned over
/// `T − TREF`.
fn px4_points(temp: &[f64], rate: &[f64]) -> Points {
    let (t_min, t_max) = extremes(temp);
    let t_ref = 0.5 * (t_min + t_max);
    let filtered = median_filter(rate, PX4_MEDIAN_SAMPLES);
    let rel: Vec<f64> = temp.iter().map(|t| t - t_ref).collect();
    let (x, y) = resample_with_delta_x(&rel, &filtered, PX4_BINS);
    Points {
        temp: x.iter().map(|v| v + t_ref).collect(),
        rate: y,
        t_min,
        t_max,
        t_ref,
    }
}

/// ArduPilot's points: every sample of the moving average over 2 s, T and rate alike.
fn ardupilot_points(time: &[f64], temp: &[f64], rate: &[f64]) -> Points {
    let (temp, rate) = match (time.first(), time.last()) {
        (Some(first), Some(last)) if last > first => {
            let per_second = (time.len() as f64 / (last - first)).floor();
            let window = (per_second * ARDUPILOT_AVERAGE_S) as usize;
            if window > 1 {
                (moving_average(temp, window), moving_average(rate, window))
            } else {
                (temp.to_vec(), rate.to_vec())
            }
        }
        _ => (temp.to_vec(), rate.to_vec()),
    };
    let (t_min, t_max) = extremes(&temp);
    Points {
        temp,
        rate,
        t_min,
        t_max,
        t_ref: ARDUPILOT_TEMP_REFERENCE_C,
    }
}

fn extremes(v: &[f64]) -> (f64, f64) {
    v.iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        })
}

/// SciPy's `medfilt(x, k)`: the median of the `k` samples centred on each, the ends padded
/// with zeros.
fn median_filter(x: &[f64], k: usize) -> Vec<f64> {
    let half = k / 2;
    let mut window = Vec::with_capacity(k);
    (0..x.len())
        .map(|i| {
            window.clear();
            for j in 0..k {
                let at = (i + j).checked_sub(half).filter(|&a| a < x.len());
                window.push(at.map_or(0.0, |a| x[a]));
            }
            window.sort_by(f64::total_cmp);
            window[half]
        })
        .collect()
}

/// PX4's `resampleWithDeltaX`: `x` cut into `bins` equal bins between its extremes (the
/// highest in the last), each non-empty bin's mean x and mean y.
fn resample_with_delta_x(x: &[f64], y: &[f64], bins: usize) -> (Vec<f64>, Vec<f64>) {
    let (lo, hi) = extremes(x);
    let interval = (hi - lo) / bins as f64;
    let mut sum_x = vec![0.0; bins];
    let mut sum_y = vec![0.0; bins];
    let mut count = vec![0usize; bins];
    for (&xi, &yi) in x.iter().zip(y) {
        let b = if xi < lo {
            0
        } else if xi < hi {
            (((xi - lo) / interval) as usize).min(bins - 1)
        } else {
            bins - 1
        };
        sum_x[b] += xi;
        sum_y[b] += yi;
        count[b] += 1;
    }
    (0..bins)
        .filter(|&b| count[b] > 0)
        .map(|b| (sum_x[b] / count[b] as f64, sum_y[b] / count[b] as f64))
        .unzip()
}

/// NumPy's `moving_average` of `tempcal_IMU.py`: the mean of each `w` consecutive samples,
/// from the first full window on (the cumulative sums' differences, as the script takes
/// them).
fn moving_average(v: &[f64], w: usize) -> Vec<f64> {
    if v.len() < w {
        return Vec::new();
    }
    let mut cum = Vec::with_capacity(v.len());
    let mut s = 0.0;
    for &x in v {
        s += x;
        cum.push(s);
    }
    (w - 1..v.len())
        .map(|i| {
            let before = if i >= w { cum[i - w] } else { 0.0 };
            (cum[i] - before) / w as f64
        })
        .collect()
}

/// Least squares of `y` on `1, x, …, x^order` (NumPy's `polyfit`, lowest power first here),
/// with the coefficients' standard errors; `None` when the points cannot determine them.
fn polyfit(x: &[f64], y: &[f64], order: u8) -> Option<(Vec<f64>, Vec<f64>)> {
    let p = usize::from(order) + 1;
    let n = x.len();
    let a = DMatrix::from_fn(n, p, |i, j| x[i].powi(j as i32));
    let b = DVector::from_column_slice(y);
    let svd = a.clone().svd(true, true);
    let beta = svd.solve(&b, 1e-12 * svd.singular_values.max()).ok()?;
    let residual = &b - &a * &beta;
    let dof = n.saturating_sub(p).max(1) as f64;
    let sigma2 = residual.norm_squared() / dof;
    let inv = (a.transpose() * &a).try_inverse()?;
    let se = (0..p)
        .map(|k| (sigma2 * inv[(k, k)].max(0.0)).sqrt())
        .collect();
    Some((beta.iter().copied().collect(), se))
}

/// The fit's figures over every finite sample of the log (the scripts fit filtered or
/// binned points; the figures say how the curve meets the log itself).
fn stats_over(m: &RegressionModel, temp: &[f64], rate: &[f64]) -> RegressionStats {
    let mut row = Vec::new();
    let (mut n, mut sum, mut sum2, mut ss_res) = (0usize, 0.0, 0.0, 0.0);
    for (&t, &y) in temp.iter().zip(rate) {
        let mut x = terms::Inputs {
            temp: t,
            ..terms::Inputs::default()
        };
        m.clamp(&mut x, &mut []);
        let pred = m.predict(&x, &[], &mut row);
        n += 1;
        sum += y;
        sum2 += y * y;
        ss_res += (y - pred) * (y - pred);
    }
    let ss_tot = sum2 - sum * sum / n.max(1) as f64;
    RegressionStats {
        n,
        rmse: (ss_res / n.max(1) as f64).sqrt(),
        r2: if ss_tot > 0.0 {
            (1.0 - ss_res / ss_tot).min(1.0)
        } else {
            0.0
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_filter_pads_the_ends_with_zeros_as_scipy_does() {
        // medfilt([5, 1, 4, 2, 3], 3) = [1, 4, 2, 3, 2] in SciPy.
        assert_eq!(
            median_filter(&[5.0, 1.0, 4.0, 2.0, 3.0], 3),
            vec![1.0, 4.0, 2.0, 3.0, 2.0]
        );
    }

    #[test]
    fn moving_average_keeps_full_windows_only() {
        assert_eq!(
            moving_average(&[1.0, 2.0, 3.0, 4.0], 2),
            vec![1.5, 2.5, 3.5]
        );
        assert!(moving_average(&[1.0], 2).is_empty());
    }

    #[test]
    fn bins_put_the_highest_value_in_the_last() {
        let (x, y) = resample_with_delta_x(&[0.0, 0.1, 1.0, 0.95], &[1.0, 3.0, 5.0, 7.0], 2);
        assert_eq!(x, vec![0.05, 0.975]);
        assert_eq!(y, vec![2.0, 6.0]);
    }
}
