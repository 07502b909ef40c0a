//! A unit's figures held to the spec: every limit it breaks, each named by the spec's key, so
//! that a failed unit says all that is wrong with it at once (a station reworks a unit once,
//! not once per limit).

use super::figures::{self, AxisFigures};
use super::spec::Spec;

/// What kind of limit: a largest value, a smallest one.
#[derive(Clone, Copy)]
enum Bound {
    Max,
    Min,
}

/// Every limit of `spec` that an axis of `axes` breaks, or whose figure could not be computed
/// (what cannot be measured cannot be accepted); empty when the unit passes.
pub fn reasons(spec: &Spec, axes: &[AxisFigures]) -> Vec<String> {
    let mut out = Vec::new();
    for axis in axes {
        let on = if axis.axis.is_empty() {
            String::new()
        } else {
            format!(" (axis {})", axis.axis)
        };
        let limits = [
            (
                "max_corrected_p2p_dph",
                spec.max_corrected_p2p_dph,
                figures::CORRECTED_P2P,
                "corrected peak-to-peak",
                "°/h",
                Bound::Max,
            ),
            (
                "min_p2p_ratio",
                spec.min_p2p_ratio,
                figures::P2P_RATIO,
                "raw/corrected peak-to-peak",
                "",
                Bound::Min,
            ),
            (
                "min_plateaus",
                spec.min_plateaus.map(|n| n as f64),
                figures::PLATEAUS,
                "plateaus K0 was fitted on",
                "",
                Bound::Min,
            ),
            (
                "max_outside_fraction",
                spec.max_outside_fraction,
                figures::OUTSIDE_FRACTION,
                "share of samples outside the calibrated ranges",
                "",
                Bound::Max,
            ),
            (
                "max_arw_deg_rt_h",
                spec.max_arw_deg_rt_h,
                figures::ARW,
                "angle random walk",
                "°/√h",
                Bound::Max,
            ),
            (
                "max_bias_instability_dph",
                spec.max_bias_instability_dph,
                figures::BIAS_INSTABILITY,
                "bias instability",
                "°/h",
                Bound::Max,
            ),
            (
                "max_rrw_dph_rt_h",
                spec.max_rrw_dph_rt_h,
                figures::RRW,
                "rate random walk",
                "°/h/√h",
                Bound::Max,
            ),
            (
                "max_corrected_std_dph",
                spec.max_corrected_std_dph,
                figures::CORRECTED_STD,
                "corrected std",
                "°/h",
                Bound::Max,
            ),
            (
                "max_corrected_win_mean_dph",
                spec.max_corrected_win_mean_dph,
                figures::CORRECTED_WIN_MEAN,
                "corrected largest |10-min mean|",
                "°/h",
                Bound::Max,
            ),
            (
                "max_k0_slope_dph_per_c",
                spec.max_k0_slope_dph_per_c,
                figures::K0_MAX_SLOPE,
                "largest |dK0/dT|",
                "°/h/°C",
                Bound::Max,
            ),
        ];
        for (key, limit, name, what, unit, bound) in limits {
            let Some(limit) = limit else { continue };
            if let Some(reason) = against(axis, key, limit, name, what, unit, bound) {
                out.push(format!("{reason}{on}"));
            }
        }
        if let Some([lo, hi]) = spec.k0_range_dph {
            for (name, bound, limit) in [
                (figures::K0_MIN, Bound::Min, lo),
                (figures::K0_MAX, Bound::Max, hi),
            ] {
                let what = match bound {
                    Bound::Min => "lowest K0 over the fitted T range",
                    Bound::Max => "highest K0 over the fitted T range",
                };
                if let Some(reason) = against(axis, "k0_range_dph", limit, name, what, "°/h", bound)
                {
                    out.push(format!("{reason}{on}"));
                }
            }
        }
        if let Some([lo, hi]) = spec.temp_range_c {
            // The fitted range must reach each end: its lowest temperature at or below lo,
            // its highest at or above hi.
            for (name, bound, limit) in [
                (figures::TEMP_MIN, Bound::Max, lo),
                (figures::TEMP_MAX, Bound::Min, hi),
            ] {
                let what = match bound {
                    Bound::Max => "lowest temperature K0 was fitted at",
                    Bound::Min => "highest temperature K0 was fitted at",
                };
                if let Some(reason) = against(axis, "temp_range_c", limit, name, what, "°C", bound)
                {
                    out.push(format!("{reason}{on}"));
                }
            }
        }
        if spec.refuse_worse_than_raw && !axis.worse_than_raw.is_empty() {
            out.push(format!(
                "refuse_worse_than_raw: the correction makes its own log's {} worse than raw{on}",
                axis.worse_than_raw.join(", ")
            ));
        }
    }
    out
}

/// The reason `axis`'s figure `name` breaks the limit `key` (`limit`, a largest or a smallest
/// value), or could not be computed; `None` when it keeps to it.
fn against(
    axis: &AxisFigures,
    key: &str,
    limit: f64,
    name: &str,
    what: &str,
    unit: &str,
    bound: Bound,
) -> Option<String> {
    let r = crate::number::readable;
    let unit = if unit.is_empty() {
        String::new()
    } else {
        format!(" {unit}")
    };
    let Some(figure) = axis.get(name) else {
        return Some(format!("{key}: the {what} was not computed"));
    };
    match (figure.value, bound) {
        (Some(v), Bound::Max) if v > limit => Some(format!(
            "{key}: {what} {}{unit} is above {}{unit}",
            r(v),
            r(limit)
        )),
        (Some(v), Bound::Min) if v < limit => Some(format!(
            "{key}: {what} {}{unit} is below {}{unit}",
            r(v),
            r(limit)
        )),
        (Some(_), _) => None,
        (None, _) => Some(format!(
            "{key}: the {what} could not be computed: {}",
            figure
                .unavailable
                .as_deref()
                .unwrap_or("no reason was given")
        )),
    }
}
