//! A fitted model in a few lines a person reads: what it is made of (the approximations'
//! kinds and knots, or a regression's terms), the windows it reads T through, the plateaus it
//! took and the log it came from. The workbench shows it beside a calibration opened to be
//! compared, where the whole file would be too much and its name too little.

use crate::models::fitted::DriftModel;
use crate::number::readable;

/// One line of a summary: what it is about (`K0(T)`, `windows`), what it says, and what
/// more there is to it for one who asks (the range an approximation was fitted over).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SummaryLine {
    /// What the line is about.
    pub what: String,
    /// What it says.
    pub text: String,
    /// More, for one who asks.
    pub detail: Option<String>,
}

fn line(what: &str, text: String) -> SummaryLine {
    SummaryLine {
        what: what.to_string(),
        text,
        detail: None,
    }
}

/// The summary of `model`: for a Vakhrameev calibration each approximation's kind (with its
/// knots, for a knot curve; the range it was fitted over as detail), the filter, T smoothing and
/// step H, the plateaus, and the source; for a regression model its name and terms, its
/// windows and the source.
pub fn summary(model: &DriftModel) -> Vec<SummaryLine> {
    let mut out = Vec::new();
    match model {
        DriftModel::Vakhrameev(c) => {
            for (name, ap) in c.approximations() {
                let knots = ap.knots().0.len();
                let kind = if knots > 0 {
                    format!("{}, {knots} knots", ap.kind())
                } else {
                    ap.kind().to_string()
                };
                out.push(SummaryLine {
                    detail: Some(format!(
                        "fitted over {} … {}{}",
                        readable(round4(ap.x_min())),
                        readable(round4(ap.x_max())),
                        if ap.extrapolates() {
                            ", extrapolated beyond"
                        } else {
                            ", held at its ends beyond"
                        }
                    )),
                    ..line(name, kind)
                });
            }
            let r = &c.recipe;
            out.push(line(
                "windows",
                format!(
                    "filter {} s, T smoothing {} s, step H {} s",
                    readable(r.filter_s),
                    readable(r.temp_smoothing_s),
                    readable(r.step_h_s)
                ),
            ));
            out.push(line(
                "plateaus",
                format!("{} (K0 points)", c.plateaus.len()),
            ));
        }
        DriftModel::Regression(r) => {
            let spec = &r.model.spec;
            let terms: Vec<String> = spec.terms.iter().map(ToString::to_string).collect();
            out.push(line(
                "model",
                format!("{}: {}", spec.name, terms.join(" + ")),
            ));
            out.push(line(
                "windows",
                format!(
                    "T smoothing {} s, step H {} s",
                    readable(spec.smoothing_s),
                    readable(spec.step_h_s)
                ),
            ));
        }
    }
    let created = match model {
        DriftModel::Vakhrameev(c) => &c.created,
        DriftModel::Regression(r) => &r.created,
    };
    let source = model.source();
    let mut made = format!("from {}", source.name);
    // The date of an RFC 3339 stamp: `2026-11-02T09:14:00Z` → `2026-11-02`.
    if let Some(day) = created.get(..10) {
        made.push_str(&format!(" on {day}"));
    }
    if !model.gyro_id().is_empty() {
        made.push_str(&format!(", gyro {}", model.gyro_id()));
    }
    out.push(line("made", made));
    out
}

/// `v` to four significant digits, for a range read at a glance.
fn round4(v: f64) -> f64 {
    if v == 0.0 || !v.is_finite() {
        return v;
    }
    let digits = 3 - v.abs().log10().floor() as i32;
    let scale = 10f64.powi(digits.clamp(-300, 300));
    (v * scale).round() / scale
}

#[cfg(test)]
mod tests {
    use super::round4;

    #[test]
    fn ranges_are_read_to_four_digits() {
        assert_eq!(round4(23.456789), 23.46);
        assert_eq!(round4(-0.0012345), -0.001235);
        assert_eq!(round4(0.0), 0.0);
    }
}
