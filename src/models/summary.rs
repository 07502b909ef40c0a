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
            let r = &c.recipe;
            let lines = [
                ("K0(T)", vec![("K0", &c.k0, &r.k0)]),
                (
                    "K1±(dT/dt)",
                    vec![
                        ("K1+", &c.k1_plus, &r.k1_plus),
                        ("K1−", &c.k1_minus, &r.k1_minus),
                    ],
                ),
                (
                    "K2±(d²T/dt²)",
                    vec![
                        ("K2+", &c.k2_plus, &r.k2_plus),
                        ("K2−", &c.k2_minus, &r.k2_minus),
                    ],
                ),
            ];
            for (name, curves) in lines {
                let kinds: Vec<String> = curves
                    .iter()
                    .map(|(_, ap, spec)| format!("{}{}", kind(ap), by_hand(spec)))
                    .collect();
                let text = if kinds.windows(2).all(|w| w[0] == w[1]) {
                    kinds[0].clone()
                } else {
                    kinds.join(" / ")
                };
                let detail = curves
                    .iter()
                    .map(|(n, ap, _)| format!("{n}: {}", fitted_over(ap)))
                    .collect::<Vec<_>>()
                    .join("\n");
                out.push(SummaryLine {
                    detail: Some(detail),
                    ..line(name, text)
                });
            }
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

/// What of a curve's knots the engineer placed or set by hand (the recipe keeps them): a
/// curve shaped by hand is not the fit's, and one comparing calibrations must see it.
fn by_hand(spec: &crate::models::approx::ApproxSpec) -> &'static str {
    match (spec.at.is_some(), spec.values.is_some()) {
        (true, true) => ", placed and set by hand",
        (true, false) => ", placed by hand",
        (false, true) => ", values set by hand",
        (false, false) => "",
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

    /// A calibration whose K1+ knots were placed and set by hand says so beside its kind; the
    /// fitted curves say nothing more.
    #[test]
    fn curves_shaped_by_hand_are_said_to_be() {
        use crate::models::approx::{ApproxKind, ApproxSpec};
        use crate::models::fitted::DriftModel;
        use crate::models::recipe::Recipe;
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs/calibration.csv");
        let log = crate::log::ingest::read_path(&path, &Default::default()).unwrap();
        let mut recipe = Recipe {
            k1_plus: ApproxSpec {
                knots: 4,
                ..ApproxSpec::of(ApproxKind::Pwl)
            },
            ..Recipe::default()
        };
        let fit = |r: &Recipe| {
            let cal = crate::models::vakhrameev::fit(&log, &r.clone().checked().unwrap())
                .unwrap()
                .calibration;
            super::summary(&DriftModel::Vakhrameev(Box::new(cal)))
        };
        let k1 = |lines: Vec<super::SummaryLine>| {
            lines
                .into_iter()
                .find(|l| l.what == "K1±(dT/dt)")
                .unwrap()
                .text
        };
        assert_eq!(k1(fit(&recipe)), "pwl, 4 knots / linear");
        let first = crate::models::vakhrameev::fit(&log, &recipe.clone().checked().unwrap())
            .unwrap()
            .calibration;
        let mut at = first.k1_plus.knots().0.to_vec();
        at[1] += 0.25 * (at[2] - at[1]);
        recipe.k1_plus.at = Some(at);
        assert_eq!(k1(fit(&recipe)), "pwl, 4 knots, placed by hand / linear");
        recipe.k1_plus.values = Some(vec![30.0, 40.0, 45.0, 50.0]);
        assert_eq!(
            k1(fit(&recipe)),
            "pwl, 4 knots, placed and set by hand / linear"
        );
    }

    #[test]
    fn ranges_are_read_to_four_digits() {
        assert_eq!(round4(23.456789), 23.46);
        assert_eq!(round4(-0.0012345), -0.001235);
        assert_eq!(round4(0.0), 0.0);
    }
}
