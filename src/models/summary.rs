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
/// knots, for a knot curve; K1± and K2± a line a pair; the ranges they were fitted over as
/// detail), the filter, T smoothing and
/// step H, the plateaus, and the source; for a regression model its name and terms, its
/// windows and the source.
pub fn summary(model: &DriftModel) -> Vec<SummaryLine> {
    let mut out = Vec::new();
    match model {
        DriftModel::Vakhrameev(c) => {
            // K1± and K2± as one line each when their two curves are of one kind (the usual
            // case), each with what it was fitted over for one who asks.
            let lines = [
                ("K0(T)", vec![("K0", &c.k0)]),
                (
                    "K1±(dT/dt)",
                    vec![("K1+", &c.k1_plus), ("K1−", &c.k1_minus)],
                ),
                (
                    "K2±(d²T/dt²)",
                    vec![("K2+", &c.k2_plus), ("K2−", &c.k2_minus)],
                ),
            ];
            for (name, curves) in lines {
                let kinds: Vec<String> = curves.iter().map(|(_, ap)| kind(ap)).collect();
                let text = if kinds.windows(2).all(|w| w[0] == w[1]) {
                    kinds[0].clone()
                } else {
                    kinds.join(" / ")
                };
                let detail = curves
                    .iter()
                    .map(|(n, ap)| format!("{n}: {}", fitted_over(ap)))
                    .collect::<Vec<_>>()
                    .join("\n");
                out.push(SummaryLine {
                    detail: Some(detail),
                    ..line(name, text)
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
                format!("{}, the K0 points", c.plateaus.len()),
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

/// An approximation's kind, with its knots for a knot curve: `spline, 6 knots`.
fn kind(ap: &crate::models::approx::Approx) -> String {
    match ap.knots().0.len() {
        0 => ap.kind().to_string(),
        n => format!("{}, {n} knots", ap.kind()),
    }
}

/// The range an approximation was fitted over, and what it does beyond.
fn fitted_over(ap: &crate::models::approx::Approx) -> String {
    format!(
        "{}, fitted over {} … {}, {} beyond",
        kind(ap),
        readable(round4(ap.x_min())),
        readable(round4(ap.x_max())),
        if ap.extrapolates() {
            "extrapolated"
        } else {
            "held at its ends"
        }
    )
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
