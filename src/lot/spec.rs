//! A lot's acceptance spec: the limits a unit's calibration and figures are held to, read from
//! a small JSON file. Every limit is optional (a spec of `{}` passes every unit that fits); a
//! key the spec does not know is refused by name, so that a misspelt limit
//! (`max_corected_p2p_dph`) is never a limit silently not checked.

use super::LotError;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The reference temperatures K0 is reported at when a spec names none, °C: the ends and the
/// middle of the range a navigation-grade gyro is specified over.
pub const DEFAULT_REFERENCE_TEMPS_C: [f64; 3] = [-40.0, 20.0, 60.0];

/// How many robust standard deviations from the lot's median make a figure an outlier, when a
/// spec does not say.
pub const DEFAULT_OUTLIER_SIGMAS: f64 = 5.0;

/// The most reference temperatures a spec may name (each is a column of `lot.csv`).
pub const MAX_REFERENCE_TEMPS: usize = 32;

/// How close two reference temperatures may be, °C: a chamber sensor resolves no finer, so
/// two closer are one temperature, and a figure's name writes its temperature to this.
pub const REFERENCE_RESOLUTION_C: f64 = 0.01;

/// The largest file read as a spec: a spec is a few lines, and anything larger is not one.
const MAX_SPEC_BYTES: u64 = 1 << 20;

/// The limits a unit is held to. Each applies to every axis of the unit; an absent one is not
/// checked. A limit whose figure could not be computed on an axis fails that axis, with why:
/// what cannot be measured cannot be accepted.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Spec {
    /// Largest peak-to-peak of the corrected drift (filtered as the recipe filters Ω) on the
    /// unit's own log, °/h.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_corrected_p2p_dph: Option<f64>,
    /// Smallest raw/corrected peak-to-peak: how much the calibration must take out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_p2p_ratio: Option<f64>,
    /// Fewest plateaus K0 was fitted on.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_plateaus: Option<usize>,
    /// Largest share (0 to 1) of the log's samples outside the calibrated ranges of T, Ṫ, T̈.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_outside_fraction: Option<f64>,
    /// Largest angle random walk of the corrected rate, °/√h.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_arw_deg_rt_h: Option<f64>,
    /// Largest bias instability of the corrected rate, °/h.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_bias_instability_dph: Option<f64>,
    /// Largest rate random walk of the corrected rate, °/h/√h.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_rrw_dph_rt_h: Option<f64>,
    /// Largest standard deviation of the corrected, filtered drift, °/h.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_corrected_std_dph: Option<f64>,
    /// Largest |10-min mean| of the corrected drift, °/h.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_corrected_win_mean_dph: Option<f64>,
    /// `[lo, hi]`, °/h: K0(T) must stay within it over the whole fitted T range.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k0_range_dph: Option<[f64; 2]>,
    /// Largest |dK0/dT| over the fitted T range, °/h per °C: the bias's temperature
    /// sensitivity.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_k0_slope_dph_per_c: Option<f64>,
    /// `[lo, hi]`, °C: the plateaus K0 was fitted on must reach from lo to hi (the unit was
    /// calibrated over the range it is sold for).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub temp_range_c: Option<[f64; 2]>,
    /// Fail a unit whose correction makes any figure of its own log worse than raw.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub refuse_worse_than_raw: bool,
    /// Where K0 is reported, °C ([`DEFAULT_REFERENCE_TEMPS_C`] when absent). Not a limit: the
    /// values are figures of the table, and their outliers are looked for.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference_temps_c: Option<Vec<f64>>,
    /// How many robust standard deviations from the lot's median make an outlier
    /// ([`DEFAULT_OUTLIER_SIGMAS`] when absent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub outlier_sigmas: Option<f64>,
}

impl Spec {
    /// Reads and checks the spec at `path`.
    ///
    /// # Errors
    /// An unreadable or oversized file, JSON that is no spec (an unknown key named, with its
    /// line and column), or a value [`Spec::check`] refuses.
    pub fn load(path: &Path) -> Result<Spec, LotError> {
        let refused = |message: String| LotError::Spec {
            path: path.to_path_buf(),
            message,
        };
        let text = crate::files::calibration::read_json_text(
            path,
            MAX_SPEC_BYTES,
            "which no spec is: a spec is a few lines of limits",
        )
        .map_err(|e| match e {
            crate::Error::File { message, .. } => refused(message),
            crate::Error::Io { source, .. } => refused(source.to_string()),
            other => refused(other.to_string()),
        })?;
        Spec::from_json(&text).map_err(refused)
    }

    /// Parses and checks a spec's text; the message names the key at fault.
    ///
    /// # Errors
    /// As [`Spec::load`], without the file.
    pub fn from_json(text: &str) -> Result<Spec, String> {
        // serde reads a struct from an array field by field, in order: `[]` would be a spec of
        // no limit, `[0.5]` a limit whose key is written nowhere.
        let value: serde_json::Value = serde_json::from_str(text).map_err(|e| e.to_string())?;
        if !value.is_object() {
            return Err(format!(
                "a spec is a JSON object of limits ({{\"max_corrected_p2p_dph\": 0.5, …}}), not \
                 {}",
                crate::files::calibration::json_kind(&value)
            ));
        }
        let spec: Spec = serde_json::from_str(text).map_err(|e| e.to_string())?;
        spec.check()?;
        Ok(spec)
    }

    /// Checks every value: limits finite and of their sign, a share within 0..1, ranges
    /// ordered, reference temperatures finite, apart and few enough.
    ///
    /// # Errors
    /// The first key at fault, with its value and what it must be.
    pub fn check(&self) -> Result<(), String> {
        let r = crate::number::readable;
        for (key, v) in [
            ("max_corrected_p2p_dph", self.max_corrected_p2p_dph),
            ("max_arw_deg_rt_h", self.max_arw_deg_rt_h),
            ("max_bias_instability_dph", self.max_bias_instability_dph),
            ("max_rrw_dph_rt_h", self.max_rrw_dph_rt_h),
            ("max_corrected_std_dph", self.max_corrected_std_dph),
            (
                "max_corrected_win_mean_dph",
                self.max_corrected_win_mean_dph,
            ),
            ("max_k0_slope_dph_per_c", self.max_k0_slope_dph_per_c),
        ] {
            if let Some(v) = v
                && !(v.is_finite() && v >= 0.0)
            {
                return Err(format!(
                    "{key}: is {}; a largest value is a finite number, zero or more",
                    r(v)
                ));
            }
        }
        if let Some(v) = self.min_p2p_ratio
            && !(v.is_finite() && v > 0.0)
        {
            return Err(format!(
                "min_p2p_ratio: is {}; a ratio of raw to corrected is a finite number above 0",
                r(v)
            ));
        }
        if let Some(v) = self.max_outside_fraction
            && !(v.is_finite() && (0.0..=1.0).contains(&v))
        {
            return Err(format!(
                "max_outside_fraction: is {}; a share of the samples lies from 0 to 1",
                r(v)
            ));
        }
        for (key, range) in [
            ("k0_range_dph", self.k0_range_dph),
            ("temp_range_c", self.temp_range_c),
        ] {
            if let Some([lo, hi]) = range
                && !(lo.is_finite() && hi.is_finite() && lo <= hi)
            {
                return Err(format!(
                    "{key}: is [{}, {}]; a range is [lo, hi], two finite numbers, lo not above hi",
                    r(lo),
                    r(hi)
                ));
            }
        }
        if let Some(temps) = &self.reference_temps_c {
            if temps.is_empty() || temps.len() > MAX_REFERENCE_TEMPS {
                return Err(format!(
                    "reference_temps_c: {} temperatures; give 1 to {MAX_REFERENCE_TEMPS} (or \
                     leave the key out for {:?} °C)",
                    temps.len(),
                    DEFAULT_REFERENCE_TEMPS_C
                ));
            }
            for (k, t) in temps.iter().enumerate() {
                if !(t.is_finite() && (-273.15..=1000.0).contains(t)) {
                    return Err(format!(
                        "reference_temps_c[{k}]: is {}; a temperature in °C, from -273.15 to 1000",
                        r(*t)
                    ));
                }
                if temps[..k].contains(t) {
                    return Err(format!(
                        "reference_temps_c[{k}]: {} °C is given twice",
                        r(*t)
                    ));
                }
                // Two temperatures no chamber sensor tells apart are one figure under two
                // names; the figures are named at that resolution, so they may not share one.
                if let Some(j) = temps[..k].iter().position(|u| {
                    (t - u).abs() < REFERENCE_RESOLUTION_C
                        || super::figures::k0_at(*t) == super::figures::k0_at(*u)
                }) {
                    let (named, earlier) =
                        (super::figures::k0_at(*t), super::figures::k0_at(temps[j]));
                    let names = if named == earlier {
                        format!("{named} for both")
                    } else {
                        format!("{earlier} and {named}")
                    };
                    return Err(format!(
                        // Each as given, to the last digit that tells them apart.
                        "reference_temps_c[{k}]: {t:?} °C is within {REFERENCE_RESOLUTION_C} °C \
                         of reference_temps_c[{j}], {:?} °C: K0 is reported at a resolution of \
                         {REFERENCE_RESOLUTION_C} °C ({names}); give one of them",
                        temps[j],
                    ));
                }
            }
        }
        if let Some(s) = self.outlier_sigmas
            && !(s.is_finite() && s > 0.0)
        {
            return Err(format!(
                "outlier_sigmas: is {}; a number of standard deviations above 0",
                r(s)
            ));
        }
        Ok(())
    }

    /// The temperatures K0 is reported at, °C.
    pub fn reference_temps(&self) -> Vec<f64> {
        self.reference_temps_c
            .clone()
            .unwrap_or_else(|| DEFAULT_REFERENCE_TEMPS_C.to_vec())
    }

    /// How many robust standard deviations make an outlier.
    pub fn outlier_sigmas(&self) -> f64 {
        self.outlier_sigmas.unwrap_or(DEFAULT_OUTLIER_SIGMAS)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_unknown_key_is_refused_by_name() {
        let e = Spec::from_json(r#"{"max_corected_p2p_dph": 0.1}"#).unwrap_err();
        assert!(e.contains("max_corected_p2p_dph"), "{e}");
    }

    #[test]
    fn values_are_checked_by_key() {
        for (text, key) in [
            (r#"{"max_arw_deg_rt_h": -1}"#, "max_arw_deg_rt_h"),
            (r#"{"min_p2p_ratio": 0}"#, "min_p2p_ratio"),
            (r#"{"max_outside_fraction": 1.5}"#, "max_outside_fraction"),
            (r#"{"k0_range_dph": [1, -1]}"#, "k0_range_dph"),
            (r#"{"reference_temps_c": [20, 20]}"#, "reference_temps_c[1]"),
            (
                r#"{"reference_temps_c": [0.1, 0.10000000000000002]}"#,
                "reference_temps_c[1]",
            ),
            (
                r#"{"reference_temps_c": [20, -40, 20.009]}"#,
                "reference_temps_c[2]",
            ),
            (r#"{"reference_temps_c": []}"#, "reference_temps_c"),
            (r#"{"outlier_sigmas": 0}"#, "outlier_sigmas"),
        ] {
            let e = Spec::from_json(text).unwrap_err();
            assert!(e.starts_with(key), "{text}: {e}");
        }
        assert_eq!(Spec::from_json("{}").unwrap(), Spec::default());
    }
}
