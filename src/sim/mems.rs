//! The six-axis MEMS IMU of the `mems-imu` profile: three gyros and three accelerometers on one
//! board, as a flight controller's IMU sits in a chamber for its thermal calibration.
//!
//! It runs through the simulator's one path (the housing lag, the sensor, the noise streams and
//! the writer of the fibre-optic unit); only its constants are its own:
//!
//! * **The board** follows the chamber air with a 5-min lag; the die under it is a "winding" of
//!   1 mm of silicon, which the heat crosses in seconds, so the gyro's bias follows the board's
//!   temperature with no lag worth a model. The temperature sensor reads the board to 1/256 °C
//!   with 0.02 °C of noise, as an IMU's own sensor does.
//! * **The gyros** have a MEMS gyro's bias (hundreds of °/h) moving by tens of °/h per °C on a
//!   parabola, no Shupe or stress term (no fibre), and a MEMS gyro's noise.
//! * **The accelerometers** read gravity on z (the board level, z up) with biases that are
//!   known cubics in T, and on z a scale factor that falls by 150 ppm/°C: the truth the
//!   accelerometer axes are held to ([`super::AccelParams::bias_g`]).

use super::axes::{AccelParams, AxisParams};
use super::profile::GyroParams;

/// The board, its die and its temperature sensor, with the x gyro's constants.
pub(crate) fn board() -> GyroParams {
    let x = &gyros()[0];
    GyroParams {
        housing_tau_s: 300.0,
        coil_inner_radius_m: 0.001,
        coil_outer_radius_m: 0.002,
        coil_layers: 4,
        // Silicon conducts a thousand times faster than a potted fibre; a diffusivity this size
        // is already lag enough for nothing to see it.
        coil_diffusivity_20c_m2_per_s: 2.0e-7,
        coil_diffusivity_coeff_per_c: 0.0,
        sensor_noise_c: 0.02,
        sensor_resolution_c: 1.0 / 256.0,
        ..x.gyro(&GyroParams::default())
    }
}

/// The three gyro axes (°/h, °/h/°C, °/h/°C²; noise in °/√h, °/h, s, °/h/√h):
///
/// | axis | bias at 20 °C | slope | curvature | ARW | GM σ, τ | RRW |
/// |---|---|---|---|---|---|---|
/// | x | +720 | +18 | +0.05 | 0.2 | 5, 100 s | 0.5 |
/// | y | −540 | −12 | +0.08 | 0.25 | 6, 120 s | 0.6 |
/// | z | +360 | +9 | −0.06 | 0.2 | 4, 90 s | 0.4 |
pub(crate) fn gyros() -> Vec<AxisParams> {
    let axis = |name: &str, bias: f64, slope: f64, curvature: f64, arw: f64, gm: f64, tau: f64| {
        AxisParams {
            name: name.to_string(),
            bias_20c_dph: bias,
            bias_slope_dph_per_c: slope,
            bias_curvature_dph_per_c2: curvature,
            shupe_dph_per_c_per_s: 0.0,
            stress_dph_per_c: 0.0,
            heating_asymmetry: 0.0,
            arw_deg_per_sqrt_h: arw,
            bias_instability_dph: gm,
            bias_correlation_s: tau,
            rrw_dph_per_sqrt_h: 0.1 * gm,
        }
    };
    vec![
        axis("x", 720.0, 18.0, 0.05, 0.2, 5.0, 100.0),
        axis("y", -540.0, -12.0, 0.08, 0.25, 6.0, 120.0),
        axis("z", 360.0, 9.0, -0.06, 0.2, 4.0, 90.0),
    ]
}

/// The three accelerometers (g, g/°C, g/°C², g/°C³ about 20 °C; scale factor per °C):
///
/// | axis | gravity | bias at 20 °C | slope | curvature | cubic | scale factor |
/// |---|---|---|---|---|---|---|
/// | x | 0 | +8 mg | +0.15 mg/°C | −2 µg/°C² | +0.05 µg/°C³ | |
/// | y | 0 | −5 mg | −0.10 mg/°C | +3 µg/°C² | −0.04 µg/°C³ | |
/// | z | +1 g | +15 mg | +0.20 mg/°C | −1.5 µg/°C² | +0.03 µg/°C³ | −150 ppm/°C |
///
/// 150 µg/√Hz of white noise each, logged to 1 µg. Over −20…+60 °C each bias moves by 10 to
/// 20 mg, the cubic term alone by up to 3 mg; z's scale factor moves 1 g by 12 mg.
pub(crate) fn accelerometers() -> Vec<AccelParams> {
    let axis = |name: &str, gravity_g, b0, b1, b2, b3, scale| AccelParams {
        name: name.to_string(),
        gravity_g,
        bias_20c_g: b0,
        bias_slope_g_per_c: b1,
        bias_curvature_g_per_c2: b2,
        bias_cubic_g_per_c3: b3,
        scale_tempco_per_c: scale,
        noise_g_per_sqrt_hz: 150e-6,
        resolution_g: 1e-6,
    };
    vec![
        axis("x", 0.0, 8.0e-3, 1.5e-4, -2.0e-6, 5.0e-8, 0.0),
        axis("y", 0.0, -5.0e-3, -1.0e-4, 3.0e-6, -4.0e-8, 0.0),
        axis("z", 1.0, 15.0e-3, 2.0e-4, -1.5e-6, 3.0e-8, -1.5e-4),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_mems_constants_are_usable() {
        assert!(board().check().is_ok());
        assert!(gyros().iter().all(|a| a.check().is_ok()));
        assert!(accelerometers().iter().all(|a| a.check().is_ok()));
        // The bias alone is the reading less gravity and its scale factor.
        let z = &accelerometers()[2];
        let d: f64 = 40.0;
        let bias = 15.0e-3 + 2.0e-4 * d - 1.5e-6 * d * d + 3.0e-8 * d * d * d;
        assert!((z.bias_g(60.0) - bias).abs() < 1e-15);
        assert!((z.true_g(60.0) - (1.0 - 1.5e-4 * d + bias)).abs() < 1e-15);
    }
}
