//! A model's Tref against what its own file says it must be, and a model named as a preset
//! against that preset's spec: checks of a calibration file read back, apart from `fitted`
//! because they concern the `(T-Tref)^k` terms alone.
//!
//! Tref is what every `(T-Tref)^k` term is a power of T less: a Tref edited alone makes the
//! coefficients another polynomial. Fixed by the spec (ArduPilot's 35 °C), it must be the
//! spec's; in the middle of the fitted range ([`TRefSpec::MidRange`], PX4's
//! `TREF = 0.5·(TMIN + TMAX)`), it must be the middle of `ranges.temp`, the range the fit
//! took it from and the model holds T to (the fit takes both from T as the model reads it,
//! through its lag and delay, over the samples it covers, for every `--fit`).
//!
//! What cannot be checked: `ranges.temp` and `t_ref_c` edited together so that one is still
//! the middle of the other (say [-50, 1000] and 475). The file records no figure of the log's
//! temperatures for the range to be held to (`source` names the log and its samples, `stats`
//! the residuals, neither T), so such an edit is caught only by the bound on the drift the
//! coefficients predict over the range (`model.coefficients`), and by `evaluate` on the log.

use super::{RegressionModel, TRefSpec, Term};
use crate::error::Invalid;
use crate::models::MIN_TEMP_SPAN_C;
use crate::models::presets::Preset;

impl RegressionModel {
    /// Tref against the terms and the spec: given exactly when a `(T-Tref)^k` term reads it,
    /// a finite temperature, the spec's own when the spec fixes it.
    pub(super) fn check_t_ref(&self) -> std::result::Result<(), Invalid> {
        let centred = self.spec.terms.iter().any(|t| matches!(t, Term::Tc { .. }));
        match (centred, self.t_ref_c) {
            (false, None) => Ok(()),
            (false, Some(_)) => Err(Invalid::new(
                "model.t_ref_c",
                "is given, but no (T-Tref)^k term reads it",
            )),
            (true, None) => Err(Invalid::new(
                "model.t_ref_c",
                "is missing, and the (T-Tref)^k terms are powers of T less it",
            )),
            (true, Some(t)) if !(t.is_finite() && (-273.15..=1000.0).contains(&t)) => {
                Err(Invalid::new(
                    "model.t_ref_c",
                    format!(
                        "is {} °C: a reference temperature lies from -273.15 to 1000 °C",
                        crate::number::readable(t)
                    ),
                ))
            }
            (true, Some(t)) => match self.spec.t_ref {
                super::TRefSpec::Fixed { celsius } if celsius != t => Err(Invalid::new(
                    "model.t_ref_c",
                    format!(
                        "is {} °C, but the spec fixes Tref at {} °C (model.spec.t_ref)",
                        crate::number::readable(t),
                        crate::number::readable(celsius)
                    ),
                )),
                _ => Ok(()),
            },
        }
    }

    /// `ranges.temp` of a model with `(T-Tref)^k` terms (after the ranges are known finite
    /// and ordered): present, no narrower than [`MIN_TEMP_SPAN_C`], over which calibrate fits
    /// no such model, and with Tref in its middle when the spec puts it there.
    pub(super) fn check_centred_range(&self) -> std::result::Result<(), Invalid> {
        let readable = crate::number::readable;
        let (Some(t), true) = (
            self.t_ref_c,
            self.spec.terms.iter().any(|t| matches!(t, Term::Tc { .. })),
        ) else {
            return Ok(());
        };
        let Some([lo, hi]) = self.ranges.temp else {
            return Err(Invalid::new(
                "model.ranges.temp",
                "is missing, and the (T-Tref)^k terms read T",
            ));
        };
        if hi - lo < MIN_TEMP_SPAN_C {
            return Err(Invalid::new(
                "model.ranges.temp",
                format!(
                    "[{}, {}] spans {} °C: a calibration in T needs at least {} °C, and \
                     calibrate fits no (T-Tref)^k model over less",
                    readable(lo),
                    readable(hi),
                    readable(hi - lo),
                    MIN_TEMP_SPAN_C
                ),
            ));
        }
        let middle = 0.5 * (lo + hi);
        // The fit writes the middle it computed; the tolerance is for rounding only.
        if self.spec.t_ref == TRefSpec::MidRange
            && (t - middle).abs() > 1e-9 * (1.0 + lo.abs() + hi.abs())
        {
            return Err(Invalid::new(
                "model.t_ref_c",
                format!(
                    "is {} °C, but Tref is the middle of the fitted range model.ranges.temp \
                     [{}, {}], {} °C (model.spec.t_ref is the middle of the range)",
                    readable(t),
                    readable(lo),
                    readable(hi),
                    readable(middle)
                ),
            ));
        }
        Ok(())
    }

    /// A model named `px4`, `ardupilot`, `poly-tN`, `px4-script` or `ardupilot-script` has
    /// that preset's spec: its terms, its Tref, no delay, no lag, every sample. An exporter
    /// and a reader take the name for the form (ArduPilot's Tref of 35 °C), so a file whose
    /// spec differs is not that model.
    pub(super) fn check_named_preset(&self) -> std::result::Result<(), Invalid> {
        let Some(want) = Preset::from_name(&self.spec.name)
            .ok()
            .filter(|p| p.name() == self.spec.name)
            .and_then(Preset::centred_spec)
        else {
            return Ok(());
        };
        let s = &self.spec;
        let name = &s.name;
        let differs = |field: &str, has: String, should: String| {
            Err(Invalid::new(
                format!("model.spec.{field}"),
                format!(
                    "is {has}, but a model named {name} has {should}: this is not the {name} \
                     model"
                ),
            ))
        };
        let list = |t: &[Term]| {
            t.iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        };
        let tref = |t: &TRefSpec| match t {
            TRefSpec::MidRange => "Tref in the middle of the fitted range".to_string(),
            TRefSpec::Fixed { celsius } => {
                format!("Tref fixed at {} °C", crate::number::readable(*celsius))
            }
        };
        if s.terms != want.terms {
            return differs(
                "terms",
                list(&s.terms),
                format!("the terms {}", list(&want.terms)),
            );
        }
        if s.t_ref != want.t_ref {
            return differs("t_ref", tref(&s.t_ref), tref(&want.t_ref));
        }
        if s.delay != want.delay {
            return differs("delay", format!("{:?}", s.delay), "no delay".into());
        }
        if s.lag != want.lag {
            return differs("lag", format!("{:?}", s.lag), "no lag".into());
        }
        if s.temp2 != want.temp2 {
            return differs("temp2", format!("{:?}", s.temp2), "no second sensor".into());
        }
        if s.samples != want.samples {
            return differs(
                "samples",
                format!("{:?}", s.samples).to_lowercase(),
                "a fit over every sample".into(),
            );
        }
        Ok(())
    }
}
