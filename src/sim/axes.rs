//! A unit with several gyro axes and accelerometers: a three-axis FOG IMU in one housing.
//!
//! **One thermal field.** The axes share the housing and the winding model of the profile's
//! [`GyroParams`] (lag, radii, layers, diffusivity): every coil sees the same housing and so the
//! same layer temperatures, radial gradient and difference of heating rates. What differs from
//! axis to axis is how the gyro answers that field: its own K0(T) curve, Shupe and
//! thermal-stress coefficients (the K2-like and K1-like transient terms) and heating/cooling
//! asymmetry, with different signs and sizes, and its own noise from its own random stream.
//! An axis's drift is therefore the single-axis formula of the module doc of [`crate::sim`] with
//! the axis's constants: a single-axis run of the gyro [`AxisParams::gyro`] gives the same
//! drift, and for the first axis (which draws from the single-axis gyro's noise stream) the
//! same noise too.
//!
//! **Accelerometers** ([`AccelParams`]) sit on the housing and read gravity (the unit stands
//! level: 0, 0, +1 g) with a small bias and scale factor that follow the true housing
//! temperature, plus white noise, quantised to their resolution.

use serde::{Deserialize, Serialize};

use crate::error::Invalid;

use super::profile::GyroParams;

/// How one gyro axis of a multi-axis unit answers the shared thermal field, and its noise.
///
/// The fields mean what the fields of the same name of [`GyroParams`] mean; units are in the
/// names.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AxisParams {
    /// Axis name (`x`, `y`, `z`): the column names are made of it (`omega_x_dph`, `gx_dps`).
    pub name: String,
    /// As [`GyroParams::bias_20c_dph`].
    pub bias_20c_dph: f64,
    /// As [`GyroParams::bias_slope_dph_per_c`].
    pub bias_slope_dph_per_c: f64,
    /// As [`GyroParams::bias_curvature_dph_per_c2`].
    pub bias_curvature_dph_per_c2: f64,
    /// As [`GyroParams::shupe_dph_per_c_per_s`].
    pub shupe_dph_per_c_per_s: f64,
    /// As [`GyroParams::stress_dph_per_c`].
    pub stress_dph_per_c: f64,
    /// As [`GyroParams::heating_asymmetry`].
    pub heating_asymmetry: f64,
    /// As [`GyroParams::arw_deg_per_sqrt_h`].
    pub arw_deg_per_sqrt_h: f64,
    /// As [`GyroParams::bias_instability_dph`].
    pub bias_instability_dph: f64,
    /// As [`GyroParams::bias_correlation_s`].
    pub bias_correlation_s: f64,
    /// As [`GyroParams::rrw_dph_per_sqrt_h`].
    pub rrw_dph_per_sqrt_h: f64,
}

impl AxisParams {
    /// The axis named `name` that answers like the single-axis gyro `g`.
    pub fn of_gyro(name: &str, g: &GyroParams) -> AxisParams {
        AxisParams {
            name: name.to_string(),
            bias_20c_dph: g.bias_20c_dph,
            bias_slope_dph_per_c: g.bias_slope_dph_per_c,
            bias_curvature_dph_per_c2: g.bias_curvature_dph_per_c2,
            shupe_dph_per_c_per_s: g.shupe_dph_per_c_per_s,
            stress_dph_per_c: g.stress_dph_per_c,
            heating_asymmetry: g.heating_asymmetry,
            arw_deg_per_sqrt_h: g.arw_deg_per_sqrt_h,
            bias_instability_dph: g.bias_instability_dph,
            bias_correlation_s: g.bias_correlation_s,
            rrw_dph_per_sqrt_h: g.rrw_dph_per_sqrt_h,
        }
    }

    /// The single-axis gyro with the housing, winding and temperature sensor of `unit` and
    /// this axis's drift and noise constants: its run is this axis's drift.
    pub fn gyro(&self, unit: &GyroParams) -> GyroParams {
        GyroParams {
            bias_20c_dph: self.bias_20c_dph,
            bias_slope_dph_per_c: self.bias_slope_dph_per_c,
            bias_curvature_dph_per_c2: self.bias_curvature_dph_per_c2,
            shupe_dph_per_c_per_s: self.shupe_dph_per_c_per_s,
            stress_dph_per_c: self.stress_dph_per_c,
            heating_asymmetry: self.heating_asymmetry,
            arw_deg_per_sqrt_h: self.arw_deg_per_sqrt_h,
            bias_instability_dph: self.bias_instability_dph,
            bias_correlation_s: self.bias_correlation_s,
            rrw_dph_per_sqrt_h: self.rrw_dph_per_sqrt_h,
            ..unit.clone()
        }
    }

    /// The true static bias K0(T) of this axis at coil temperature `temp_c`, °/h.
    pub fn static_bias_dph(&self, temp_c: f64) -> f64 {
        let d = temp_c - 20.0;
        self.bias_20c_dph + self.bias_slope_dph_per_c * d + self.bias_curvature_dph_per_c2 * d * d
    }

    /// Checks the name (letters and digits, so that it can be part of a column name) and every
    /// constant, with a sentence naming the axis and the constant.
    pub fn check(&self) -> Result<(), Invalid> {
        check_name("axis", &self.name)?;
        self.gyro(&GyroParams::default()).check().map_err(|e| {
            let constant = e.field.strip_prefix("gyro.").unwrap_or(&e.field);
            Invalid::new(
                format!("axis {}", self.name),
                format!("{constant} {}", e.reason),
            )
        })
    }
}

/// The default axes of a unit of `n` gyros (1 to 3): `x` is driftlab's reference gyro (the
/// single-axis one), `y` and `z` answer the same thermal field with other signs and sizes:
///
/// | axis | K0(20 °C) | K0 slope | K0 curvature | Shupe | stress | asymmetry | ARW | GM σ, τ |
/// |---|---|---|---|---|---|---|---|---|
/// | x | 0 | +0.003 | +8·10⁻⁵ | +280 | +0.56 | +0.15 | 0.003 | 0.006, 600 s |
/// | y | +0.08 | −0.0045 | +5·10⁻⁵ | −190 | −0.38 | +0.10 | 0.0035 | 0.007, 900 s |
/// | z | −0.05 | +0.0015 | −6·10⁻⁵ | +120 | +0.85 | −0.08 | 0.0025 | 0.005, 450 s |
///
/// (°/h, °/h/°C, °/h/°C², °/h per °C/s, °/h/°C, 1, °/√h, °/h.) Rate random walk 0.001,
/// 0.0012 and 0.0008 °/h/√h.
///
/// # Errors
/// When `n` is not 1, 2 or 3.
pub fn default_axes(n: usize) -> Result<Vec<AxisParams>, Invalid> {
    if !(1..=3).contains(&n) {
        return Err(Invalid::new(
            "--axes",
            format!("takes 1, 2 or 3 (x, y, z), got {n}; a profile file can list more axes"),
        ));
    }
    let x = AxisParams::of_gyro("x", &GyroParams::default());
    let y = AxisParams {
        name: "y".into(),
        bias_20c_dph: 0.08,
        bias_slope_dph_per_c: -0.0045,
        bias_curvature_dph_per_c2: 5.0e-5,
        shupe_dph_per_c_per_s: -190.0,
        stress_dph_per_c: -0.38,
        heating_asymmetry: 0.10,
        arw_deg_per_sqrt_h: 0.0035,
        bias_instability_dph: 0.007,
        bias_correlation_s: 900.0,
        rrw_dph_per_sqrt_h: 0.0012,
    };
    let z = AxisParams {
        name: "z".into(),
        bias_20c_dph: -0.05,
        bias_slope_dph_per_c: 0.0015,
        bias_curvature_dph_per_c2: -6.0e-5,
        shupe_dph_per_c_per_s: 120.0,
        stress_dph_per_c: 0.85,
        heating_asymmetry: -0.08,
        arw_deg_per_sqrt_h: 0.0025,
        bias_instability_dph: 0.005,
        bias_correlation_s: 450.0,
        rrw_dph_per_sqrt_h: 0.0008,
    };
    let mut axes = vec![x, y, z];
    axes.truncate(n);
    Ok(axes)
}

/// One accelerometer axis of the unit, on the housing.
///
/// Reading, g: `gravity·(1 + s·d) + b0 + b1·d + b2·d² + b3·d³ + noise` with `d = T_h − 20`,
/// T_h the true housing temperature, quantised to `resolution_g`: a bias that is a known cubic
/// in T (what a MEMS accelerometer's drifts like, and what PX4 and ArduPilot fit), and on the
/// axis that carries gravity a scale factor that moves with T too. The white noise of a sample taken at `rate` Hz
/// has σ = `noise_g_per_sqrt_hz`·√(rate/2) (the density over the Nyquist band).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AccelParams {
    /// Axis name (`x`, `y`, `z`): the column is `acc_x_g` (driftlab) or `ax_g` (a stand).
    pub name: String,
    /// Gravity along the axis for the unit at rest, g.
    pub gravity_g: f64,
    /// Bias at 20 °C, g.
    pub bias_20c_g: f64,
    /// Bias change per °C of housing temperature, g/°C.
    pub bias_slope_g_per_c: f64,
    /// Quadratic coefficient of the bias around 20 °C, g/°C² (0 when a profile file leaves
    /// it out: the accelerometers of the FOG unit have a linear bias).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub bias_curvature_g_per_c2: f64,
    /// Cubic coefficient of the bias around 20 °C, g/°C³.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub bias_cubic_g_per_c3: f64,
    /// Relative change of the scale factor per °C, 1/°C.
    pub scale_tempco_per_c: f64,
    /// White-noise density, g/√Hz.
    pub noise_g_per_sqrt_hz: f64,
    /// Resolution of the logged value, g.
    pub resolution_g: f64,
}

impl AccelParams {
    /// The noise-free reading at true housing temperature `housing_c`, g.
    pub fn true_g(&self, housing_c: f64) -> f64 {
        let d = housing_c - 20.0;
        self.gravity_g * (1.0 + self.scale_tempco_per_c * d) + self.bias_g(housing_c)
    }

    /// The bias alone at housing temperature `housing_c`, g: the reading less the gravity
    /// the axis carries (and its scale factor's change with T).
    pub fn bias_g(&self, housing_c: f64) -> f64 {
        let d = housing_c - 20.0;
        self.bias_20c_g
            + d * (self.bias_slope_g_per_c
                + d * (self.bias_curvature_g_per_c2 + d * self.bias_cubic_g_per_c3))
    }

    /// Checks the name and the constants, with a sentence naming the one that is wrong.
    pub fn check(&self) -> Result<(), Invalid> {
        check_name("accelerometer", &self.name)?;
        for (what, v) in [
            ("gravity_g", self.gravity_g),
            ("bias_20c_g", self.bias_20c_g),
            ("bias_slope_g_per_c", self.bias_slope_g_per_c),
            ("bias_curvature_g_per_c2", self.bias_curvature_g_per_c2),
            ("bias_cubic_g_per_c3", self.bias_cubic_g_per_c3),
            ("scale_tempco_per_c", self.scale_tempco_per_c),
        ] {
            if !v.is_finite() {
                return Err(Invalid::new(
                    format!("accelerometer {}", self.name),
                    format!("{what} must be a finite number, got {v}"),
                ));
            }
        }
        if !(self.noise_g_per_sqrt_hz.is_finite() && self.noise_g_per_sqrt_hz >= 0.0) {
            return Err(Invalid::new(
                format!("accelerometer {}", self.name),
                format!(
                    "noise_g_per_sqrt_hz must be zero or positive, got {}",
                    self.noise_g_per_sqrt_hz
                ),
            ));
        }
        if !(self.resolution_g.is_finite() && self.resolution_g > 0.0) {
            return Err(Invalid::new(
                format!("accelerometer {}", self.name),
                format!(
                    "resolution_g must be a positive number, got {}",
                    self.resolution_g
                ),
            ));
        }
        Ok(())
    }
}

/// The three accelerometers of a level unit (`--accel`): gravity 0, 0, +1 g; biases +1.2,
/// −0.8, +0.5 mg at 20 °C moving +20, −15, +10 µg/°C; scale factors +100, −60, −80 ppm/°C;
/// 30 µg/√Hz of white noise; 1 µg resolution. Over −50…+60 °C the z axis moves by about
/// 10 mg: small beside its 1 g, as a navigation-grade accelerometer.
pub fn default_accelerometers() -> Vec<AccelParams> {
    let axis =
        |name: &str, gravity_g, bias_20c_g, bias_slope_g_per_c, scale_tempco_per_c| AccelParams {
            name: name.to_string(),
            gravity_g,
            bias_20c_g,
            bias_slope_g_per_c,
            bias_curvature_g_per_c2: 0.0,
            bias_cubic_g_per_c3: 0.0,
            scale_tempco_per_c,
            noise_g_per_sqrt_hz: 30e-6,
            resolution_g: 1e-6,
        };
    vec![
        axis("x", 0.0, 1.2e-3, 2.0e-5, 1.0e-4),
        axis("y", 0.0, -0.8e-3, -1.5e-5, -0.6e-4),
        axis("z", 1.0, 0.5e-3, 1.0e-5, -0.8e-4),
    ]
}

/// Whether a constant a profile file may leave out is its default, zero (so that a profile
/// written without it reads and writes as it was).
fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

pub(super) fn check_name(what: &str, name: &str) -> Result<(), Invalid> {
    if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric()) {
        return Err(Invalid::new(
            format!("{what} name {name:?}"),
            "must be letters and digits (it becomes part of a column name)",
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_default_axis_is_the_reference_gyro() {
        let g = GyroParams::default();
        let axes = default_axes(3).unwrap();
        assert_eq!(axes[0].gyro(&g), g);
        assert!(axes.iter().all(|a| a.check().is_ok()));
        assert_eq!(default_axes(4).unwrap_err().field, "--axes");
        let bad = AxisParams {
            name: "x y".into(),
            ..axes[0].clone()
        };
        assert!(
            bad.check()
                .unwrap_err()
                .reason
                .contains("letters and digits")
        );
        let bad = AxisParams {
            bias_correlation_s: 0.0,
            ..axes[1].clone()
        };
        assert!(
            bad.check()
                .unwrap_err()
                .to_string()
                .starts_with("axis y: bias_correlation_s must be a positive number")
        );
        assert!(default_accelerometers().iter().all(|a| a.check().is_ok()));
    }
}
