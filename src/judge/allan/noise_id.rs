//! Noise identification by the lag-1 autocorrelation method (Riley & Greenhall 2004): the
//! power-law exponent α that chooses the degrees of freedom of each point's interval. Apart
//! because it looks at the rate's averages, not at the deviation's sums.

/// Noise type α at averaging factor m by the lag-1 autocorrelation method (Riley & Greenhall
/// 2004, frequency data): average the rate over m samples, remove a linear drift, difference
/// until the lag-1 autocorrelation r1 gives δ = r1/(1+r1) < 0.25 (at most twice, as for the
/// Allan variance), then α = −round(2δ) − 2d, kept within the Allan range −2..=2.
///
/// `None` with fewer than 30 averages, where the estimate is too scattered to trust.
pub fn identify_noise(rate: &[f64], m: usize) -> Option<i32> {
    const MIN_POINTS: usize = 30;
    if m == 0 || rate.len() / m < MIN_POINTS {
        return None;
    }
    let z: Vec<f64> = rate
        .chunks_exact(m)
        .map(|c| c.iter().sum::<f64>() / m as f64)
        .collect();
    lag1_noise_type(z)
}

/// [`identify_noise`] from the phase: the rate averaged over block k is
/// (x\[(k+1)m\] − x\[km\]) / (m·τ0), and the method is blind to scale and offset, so the phase
/// differences serve as they are. O(N/m) instead of O(N).
pub(super) fn identify_noise_from_phase(x: &[f64], m: usize) -> Option<i32> {
    if m == 0 || x.len() < 2 || (x.len() - 1) / m < 30 {
        return None;
    }
    let blocks = (x.len() - 1) / m;
    let z: Vec<f64> = (0..blocks).map(|k| x[(k + 1) * m] - x[k * m]).collect();
    lag1_noise_type(z)
}

/// The lag-1 autocorrelation steps of [`identify_noise`] on block averages `z`.
fn lag1_noise_type(mut z: Vec<f64>) -> Option<i32> {
    const D_MAX: i32 = 2;
    detrend_linear(&mut z);
    let mut d = 0;
    loop {
        let r1 = lag1_autocorrelation(&z)?;
        let delta = r1 / (1.0 + r1);
        if !delta.is_finite() {
            return None;
        }
        if delta < 0.25 || d >= D_MAX {
            let alpha = -(2.0 * delta).round() as i32 - 2 * d;
            return Some(alpha.clamp(-2, 2));
        }
        for i in 0..z.len() - 1 {
            z[i] = z[i + 1] - z[i];
        }
        z.pop();
        d += 1;
        if z.len() < 2 {
            return None;
        }
    }
}

/// Removes the least-squares line through (i, z\[i\]).
fn detrend_linear(z: &mut [f64]) {
    let n = z.len() as f64;
    if z.len() < 2 {
        return;
    }
    let tm = (n - 1.0) / 2.0;
    let zm = z.iter().sum::<f64>() / n;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (i, &v) in z.iter().enumerate() {
        let t = i as f64 - tm;
        sxy += t * (v - zm);
        sxx += t * t;
    }
    let slope = sxy / sxx;
    for (i, v) in z.iter_mut().enumerate() {
        *v -= zm + slope * (i as f64 - tm);
    }
}

/// Lag-1 autocorrelation about the mean; `None` for a constant series.
fn lag1_autocorrelation(z: &[f64]) -> Option<f64> {
    let n = z.len();
    if n < 2 {
        return None;
    }
    let mu = z.iter().sum::<f64>() / n as f64;
    let den: f64 = z.iter().map(|v| (v - mu) * (v - mu)).sum();
    if den <= 0.0 || !den.is_finite() {
        return None;
    }
    let num: f64 = z.windows(2).map(|w| (w[0] - mu) * (w[1] - mu)).sum();
    Some(num / den)
}
