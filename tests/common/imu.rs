//! An IMU at rest simulated at 20 Hz with known noise, as Kalibr defines it: white rate noise
//! of density N (the angle random walk) and a bias random walk of K. A discrete sample of
//! white noise of density N at rate f is N·√f; a bias that random-walks with K steps by
//! K·√Δt each sample.

use super::Noise;
use std::fmt::Write as _;

/// The IMU's sampling rate, Hz.
pub const RATE_HZ: f64 = 20.0;

/// m/s² in one g: the standard gravity (ISO 80000-3, the CGPM's 1901 value).
pub const G_M_S2: f64 = 9.80665;

/// `seconds` at [`RATE_HZ`] of three gyro axes (rad/s, `gyro` = (N, K)) and three
/// accelerometer axes (`accel` = (N, K) in m/s², written divided by `unit`, m/s² in it: 1,
/// or [`G_M_S2`] for g) named by `pattern` with `{}` the axis (`accel_{}_m_s2`), each axis
/// scaled by its factor of `scale`, as `driftlab convert` writes a log.
pub fn imu_csv(
    seconds: f64,
    gyro: (f64, f64),
    accel: (f64, f64),
    scale: [f64; 3],
    pattern: &str,
    unit: f64,
) -> String {
    let n = (seconds * RATE_HZ) as usize;
    let dt = 1.0 / RATE_HZ;
    let factor = 1.0 / unit;
    let name = |axis: &str| pattern.replace("{}", axis);
    let mut noise = Noise::new(17);
    let mut bias = [0.0f64; 6];
    let mut text = format!(
        "time_s,gyro_x_rad_s,gyro_y_rad_s,gyro_z_rad_s,temp_c,{},{},{}\n",
        name("x"),
        name("y"),
        name("z")
    );
    for i in 0..n {
        let mut v = [0.0f64; 6];
        for k in 0..6 {
            let (density, walk) = if k < 3 { gyro } else { accel };
            let s = scale[k % 3];
            bias[k] += s * walk * dt.sqrt() * noise.normal();
            v[k] = s * density * RATE_HZ.sqrt() * noise.normal() + bias[k];
        }
        writeln!(
            text,
            "{},{},{},{},25.0,{},{},{}",
            i as f64 * dt,
            v[0],
            v[1],
            v[2],
            v[3] * factor,
            v[4] * factor,
            (v[5] - G_M_S2) * factor
        )
        .unwrap();
    }
    text
}
