//! The Vakhrameev model's part of a header (docs/method.md §1): its dead-bands and five curves,
//! and the two functions every model gives the corrector, `driftlab_predict` and
//! `driftlab_is_outside`, under the names of its axis. The regimes, `driftlab_regime` and
//! `driftlab_beyond` are the runtime's (`runtime.c`), one for every Vakhrameev axis of a header.

use super::c_curves::curve;
use super::c_names::rename_identifiers;
use super::{ExportError, comment_text, number};
use crate::models::vakhrameev::Calibration;

/// What the identifiers of one Vakhrameev model start with: `driftlab` and `DRIFTLAB` for the
/// model of a single-axis header, `driftlab_gx` and `DRIFTLAB_GX` for axis `gx` of a unit's
/// header, where every axis has its own curves beside the others'.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct ModelNames {
    /// Prefix of the curves and functions (`driftlab_gx`).
    pub lower: String,
    /// Prefix of the macros (`DRIFTLAB_GX`).
    pub upper: String,
    /// What the curves' comments and error messages start with (`axis gx: `), empty for a
    /// single axis.
    pub title: String,
}

impl ModelNames {
    /// The names of a single-axis header.
    pub fn single() -> ModelNames {
        ModelNames {
            lower: "driftlab".into(),
            upper: "DRIFTLAB".into(),
            title: String::new(),
        }
    }

    /// The names of axis `name` of a unit's header, its identifiers' part `ident` (`gx`).
    pub fn axis(name: &str, ident: &str) -> ModelNames {
        let lower = format!("driftlab_{ident}");
        ModelNames {
            upper: lower.to_ascii_uppercase(),
            lower,
            title: format!("axis {name}: "),
        }
    }

    /// `text` with every `driftlab_` and `DRIFTLAB_` name put under this prefix (the identity
    /// for [`ModelNames::single`]): a regression axis's constants and corrector in a unit.
    /// One pass over the identifiers ([`rename_identifiers`]): never inside a string literal,
    /// never twice.
    pub fn rename_all(&self, text: &str) -> String {
        rename_identifiers(text, |id, _| {
            if let Some(rest) = id.strip_prefix("driftlab_") {
                Some(format!("{}_{rest}", self.lower))
            } else {
                id.strip_prefix("DRIFTLAB_")
                    .map(|rest| format!("{}_{rest}", self.upper))
            }
        })
    }

    /// `text` with the single-axis header's names of this model's curves and functions
    /// (`driftlab_` followed by one of `names`) put under this prefix (the identity for
    /// [`ModelNames::single`]), in one pass over the identifiers.
    fn rename(&self, text: &str, names: &[&str]) -> String {
        rename_identifiers(text, |id, _| {
            let rest = id.strip_prefix("driftlab_")?;
            names
                .iter()
                .any(|n| rest.starts_with(n))
                .then(|| format!("{}_{rest}", self.lower))
        })
    }
}

/// One model's dead-bands and five curves, under `names`.
pub(super) fn model_constants(
    h: &mut String,
    cal: &Calibration,
    names: &ModelNames,
) -> Result<(), ExportError> {
    let r = &cal.resolved;
    let u = &cal.units;
    let upper = &names.upper;
    h.push_str(&format!(
        r#"
/* {title_dead}ead-bands of the fit, for the record: points with |Tdot| (|Tddot|) below them were left out
 * of the K1 (K2) fits. The correction does not use them. */
#define {upper}_DEADBAND_TDOT {db1}   /* {utd} */
#define {upper}_DEADBAND_TDDOT {db2} /* {utdd} */
"#,
        title_dead = if names.title.is_empty() {
            "D".to_string()
        } else {
            format!("{}d", comment_text(&names.title))
        },
        db1 = number(r.deadband_tdot, &format!("{}the Tdot dead-band", names.title))?,
        db2 = number(r.deadband_tddot, &format!("{}the Tddot dead-band", names.title))?,
        utd = comment_text(&u.tdot),
        utdd = comment_text(&u.tddot),
    ));
    // Each curve: its name, title, argument, the argument's unit and its own unit.
    let (temp, tdot, tddot) = (&u.temperature, &u.tdot, &u.tddot);
    let curves = [
        ("k0", "K0(T)", "T", temp, &u.rate, &cal.k0),
        ("k1_plus", "K1+(Tdot)", "Tdot", tdot, &u.k1, &cal.k1_plus),
        ("k1_minus", "K1-(Tdot)", "Tdot", tdot, &u.k1, &cal.k1_minus),
        ("k2_plus", "K2+(Tddot)", "Tddot", tddot, &u.k2, &cal.k2_plus),
        (
            "k2_minus",
            "K2-(Tddot)",
            "Tddot",
            tddot,
            &u.k2,
            &cal.k2_minus,
        ),
    ];
    for (name, title, arg, arg_unit, unit, a) in curves {
        let name = format!("{}_{name}", names.lower);
        let title = format!("{}{title}", comment_text(&names.title));
        let (arg_unit, unit) = (comment_text(arg_unit), comment_text(unit));
        curve(h, &name, &title, (arg, &arg_unit), &unit, a)?;
    }
    Ok(())
}

/// One model's `driftlab_predict`, under `names`.
pub(super) fn predict_fn(h: &mut String, names: &ModelNames) {
    let text = r#"
/* Predicted thermal drift, deg/h, of a sample at temperature temp_c with these rates; its regime
 * goes to *regime when regime is not NULL. */
static inline double driftlab_predict(double temp_c, double tdot_c_s, double tddot_c_s2,
                                      int *regime)
{
    int r = driftlab_regime(tdot_c_s, tddot_c_s2);
    double k0 = driftlab_curve_eval(&driftlab_k0, temp_c);
    double pred = k0;
    if (r == DRIFTLAB_REGIME_PLUS) {
        pred = k0 + driftlab_curve_eval(&driftlab_k1_plus, tdot_c_s) * tdot_c_s +
               driftlab_curve_eval(&driftlab_k2_plus, tddot_c_s2) * tddot_c_s2;
    } else if (r == DRIFTLAB_REGIME_MINUS) {
        pred = k0 + driftlab_curve_eval(&driftlab_k1_minus, tdot_c_s) * tdot_c_s +
               driftlab_curve_eval(&driftlab_k2_minus, tddot_c_s2) * tddot_c_s2;
    }
    if (regime != NULL) {
        *regime = r;
    }
    return pred;
}
"#;
    h.push_str(&names.rename(text, &["predict", "k0", "k1_", "k2_"]));
}

/// One model's `driftlab_is_outside`, under `names`.
pub(super) fn is_outside_fn(h: &mut String, names: &ModelNames) {
    let text = r#"
/* 1 when a sample lies beyond what the calibration saw: T outside K0's range, or a rate
 * outside the range of a curve its regime uses (the curve's edge value was held there). */
static inline int driftlab_is_outside(double temp_c, double tdot_c_s, double tddot_c_s2,
                                      int regime)
{
    if (driftlab_beyond(&driftlab_k0, temp_c)) {
        return 1;
    }
    if (regime == DRIFTLAB_REGIME_PLUS) {
        return driftlab_beyond(&driftlab_k1_plus, tdot_c_s) ||
               driftlab_beyond(&driftlab_k2_plus, tddot_c_s2);
    }
    if (regime == DRIFTLAB_REGIME_MINUS) {
        return driftlab_beyond(&driftlab_k1_minus, tdot_c_s) ||
               driftlab_beyond(&driftlab_k2_minus, tddot_c_s2);
    }
    return 0;
}
"#;
    h.push_str(&names.rename(text, &["is_outside", "k0", "k1_", "k2_"]));
}
