//! Knot values set by hand: the knot values of a piecewise-linear or spline coefficient that the
//! engineer set in the workbench, replacing the fitted ones. The recipe holds them
//! (`ApproxSpec::values`, beside the positions placed by hand, `ApproxSpec::at`); the staged
//! pipeline (`staged.rs`) reads them as a [`KnotEdits`] and applies them after each set's fit.
//! Sessions written before the recipe held them kept them beside it (`knots`); a session read
//! moves them into its recipe ([`KnotEdits::fold_into`]).

use super::Calibration;
use crate::error::Invalid;
use crate::models::approx::{Approx, ApproxSpec};
use crate::models::recipe::Recipe;
use serde::{Deserialize, Serialize};

/// Knot values set by hand, per coefficient: the whole list of knot values of a
/// piecewise-linear or spline approximation, replacing the fitted values. A list applies only
/// while the approximation has that many knots.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct KnotEdits {
    /// K0(T) knot values, °/h.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub k0: Option<Vec<f64>>,
    /// K1+(Ṫ) knot values.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub k1_plus: Option<Vec<f64>>,
    /// K1−(Ṫ) knot values.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub k1_minus: Option<Vec<f64>>,
    /// K2+(T̈) knot values.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub k2_plus: Option<Vec<f64>>,
    /// K2−(T̈) knot values.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub k2_minus: Option<Vec<f64>>,
}

/// Which coefficient a knot edit is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Coefficient {
    /// K0(T).
    K0,
    /// K1+(Ṫ).
    K1Plus,
    /// K1−(Ṫ).
    K1Minus,
    /// K2+(T̈).
    K2Plus,
    /// K2−(T̈).
    K2Minus,
}

impl Coefficient {
    /// All five, in the order the calibration lists them.
    pub const ALL: [Coefficient; 5] = [
        Coefficient::K0,
        Coefficient::K1Plus,
        Coefficient::K1Minus,
        Coefficient::K2Plus,
        Coefficient::K2Minus,
    ];

    /// The name used in recipes and calibration files (`k1_plus`).
    pub fn key(self) -> &'static str {
        match self {
            Coefficient::K0 => "k0",
            Coefficient::K1Plus => "k1_plus",
            Coefficient::K1Minus => "k1_minus",
            Coefficient::K2Plus => "k2_plus",
            Coefficient::K2Minus => "k2_minus",
        }
    }

    /// The name people read (`K1+`).
    pub fn label(self) -> &'static str {
        match self {
            Coefficient::K0 => "K0",
            Coefficient::K1Plus => "K1+",
            Coefficient::K1Minus => "K1−",
            Coefficient::K2Plus => "K2+",
            Coefficient::K2Minus => "K2−",
        }
    }

    /// The recipe's choice for this coefficient.
    pub fn spec(self, recipe: &Recipe) -> &ApproxSpec {
        match self {
            Coefficient::K0 => &recipe.k0,
            Coefficient::K1Plus => &recipe.k1_plus,
            Coefficient::K1Minus => &recipe.k1_minus,
            Coefficient::K2Plus => &recipe.k2_plus,
            Coefficient::K2Minus => &recipe.k2_minus,
        }
    }

    /// The recipe's choice for this coefficient, to change it.
    pub fn spec_mut(self, recipe: &mut Recipe) -> &mut ApproxSpec {
        match self {
            Coefficient::K0 => &mut recipe.k0,
            Coefficient::K1Plus => &mut recipe.k1_plus,
            Coefficient::K1Minus => &mut recipe.k1_minus,
            Coefficient::K2Plus => &mut recipe.k2_plus,
            Coefficient::K2Minus => &mut recipe.k2_minus,
        }
    }

    /// How a face describes the knots of `spec`, this coefficient's, in one line
    /// ([`ApproxSpec::knots_text`]): K0's knots not placed by hand are not equally spaced but
    /// at the plateaus' temperatures, their count a maximum
    /// ([`super::knots_at_temperatures`]): `at most 5 knots, at the plateaus' temperatures`.
    pub fn knots_text(self, spec: &ApproxSpec) -> String {
        let text = spec.knots_text();
        if self != Coefficient::K0 || !spec.kind.has_knots() || spec.at.is_some() {
            return text;
        }
        let even = format!("{} knots, equally spaced", spec.knots);
        text.replacen(
            &even,
            &format!(
                "at most {} knots, at the plateaus' temperatures",
                spec.knots
            ),
            1,
        )
    }

    /// The fitted approximation of this coefficient in a calibration.
    pub fn approx(self, cal: &Calibration) -> &Approx {
        match self {
            Coefficient::K0 => &cal.k0,
            Coefficient::K1Plus => &cal.k1_plus,
            Coefficient::K1Minus => &cal.k1_minus,
            Coefficient::K2Plus => &cal.k2_plus,
            Coefficient::K2Minus => &cal.k2_minus,
        }
    }
}

impl KnotEdits {
    /// The hand-set knot values of every coefficient of `recipe`.
    pub fn of(recipe: &Recipe) -> KnotEdits {
        let mut k = KnotEdits::default();
        for c in Coefficient::ALL {
            k.set(c, c.spec(recipe).values.clone());
        }
        k
    }

    /// Moves these values into `recipe` (a session written before the recipe held them):
    /// each list becomes its coefficient's `values`, when the recipe sets none of its own or
    /// the same.
    ///
    /// # Errors
    /// The key of a coefficient whose values both this and the recipe set, and differently
    /// (one of them would be dropped without a word).
    pub fn fold_into(self, recipe: &mut Recipe) -> std::result::Result<(), &'static str> {
        for c in Coefficient::ALL {
            let spec = c.spec_mut(recipe);
            match (&spec.values, self.get(c)) {
                (Some(own), Some(old)) if own != old => return Err(c.key()),
                (None, old) => spec.values = old.cloned(),
                _ => {}
            }
        }
        Ok(())
    }

    /// The hand-set knot values of one coefficient.
    pub fn get(&self, c: Coefficient) -> Option<&Vec<f64>> {
        self.slot(c).as_ref()
    }

    /// Sets (or clears, with `None`) the hand-set knot values of one coefficient.
    pub fn set(&mut self, c: Coefficient, values: Option<Vec<f64>>) {
        *self.slot_mut(c) = values;
    }

    /// True when no knot was moved by hand.
    pub fn is_empty(&self) -> bool {
        Coefficient::ALL.iter().all(|&c| self.get(c).is_none())
    }

    /// Refuses knot values no calibration could hold: a list for an approximation without
    /// knots or of another count, a value that is not finite or beyond the largest rate a
    /// gyro log may plausibly hold.
    ///
    /// # Errors
    /// [`Invalid`] naming the coefficient (`k0`) and the value.
    pub fn check(&self, recipe: &Recipe) -> std::result::Result<(), Invalid> {
        use crate::log::mapping_check::MAX_PLAUSIBLE_RATE_DPH;
        use crate::number::readable;
        for c in Coefficient::ALL {
            let Some(values) = self.get(c) else {
                continue;
            };
            let spec = c.spec(recipe);
            if !spec.kind.has_knots() || values.len() != spec.knots {
                return Err(Invalid::new(
                    c.key(),
                    format!(
                        "{} values set by hand, but recipe.{} {}",
                        values.len(),
                        c.key(),
                        if spec.kind.has_knots() {
                            format!("has {} knots", spec.knots)
                        } else {
                            "has no knots".to_string()
                        }
                    ),
                ));
            }
            if let Some((j, v)) = values
                .iter()
                .enumerate()
                .find(|(_, v)| !(v.is_finite() && v.abs() <= MAX_PLAUSIBLE_RATE_DPH))
            {
                return Err(Invalid::new(
                    format!("{}[{j}]", c.key()),
                    format!(
                        "{}: a knot value is a finite number of at most {} in magnitude (10⁴ \
                         °/s, the largest rate a gyro log may plausibly hold)",
                        readable(*v),
                        readable(MAX_PLAUSIBLE_RATE_DPH)
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Drops the edits that no longer fit the recipe (another kind or knot count).
    pub fn retain_matching(&mut self, recipe: &Recipe) {
        for c in Coefficient::ALL {
            let spec = c.spec(recipe);
            if let Some(v) = self.get(c)
                && !(spec.kind.has_knots() && v.len() == spec.knots)
            {
                self.set(c, None);
            }
        }
    }

    fn slot(&self, c: Coefficient) -> &Option<Vec<f64>> {
        match c {
            Coefficient::K0 => &self.k0,
            Coefficient::K1Plus => &self.k1_plus,
            Coefficient::K1Minus => &self.k1_minus,
            Coefficient::K2Plus => &self.k2_plus,
            Coefficient::K2Minus => &self.k2_minus,
        }
    }

    fn slot_mut(&mut self, c: Coefficient) -> &mut Option<Vec<f64>> {
        match c {
            Coefficient::K0 => &mut self.k0,
            Coefficient::K1Plus => &mut self.k1_plus,
            Coefficient::K1Minus => &mut self.k1_minus,
            Coefficient::K2Plus => &mut self.k2_plus,
            Coefficient::K2Minus => &mut self.k2_minus,
        }
    }
}

/// `approx` with its knot values replaced by `values`, when the counts agree.
pub fn with_knots(approx: &Approx, values: Option<&Vec<f64>>) -> Approx {
    let Some(values) = values else {
        return approx.clone();
    };
    if approx.knots().1.len() != values.len() {
        return approx.clone();
    }
    values
        .iter()
        .enumerate()
        .fold(approx.clone(), |a, (j, &y)| a.with_knot_value(j, y))
}

/// Refuses a calibration whose recipe's knots placed or set by hand (`at`, `values`) are not
/// the knots of its curves: a file edited in one place and not the other. Its corrections
/// would follow the curve while `calibrate --recipe` of the same file made another
/// calibration, and the recipe, the summary and the workbench showed knots no curve has. The
/// fit keeps them as given ([`check_hand_kept`], the same tolerance), so a file driftlab wrote
/// always passes.
///
/// # Errors
/// [`Invalid`], naming the recipe's field and the curve's.
pub fn check_hand_in_curves(cal: &Calibration) -> std::result::Result<(), Invalid> {
    let same = |a: &[f64], b: &[f64]| {
        a.len() == b.len()
            && a.iter()
                .zip(b)
                .all(|(x, y)| (x - y).abs() <= 1e-12 * (1.0 + x.abs()))
    };
    for c in Coefficient::ALL {
        let spec = c.spec(&cal.recipe);
        let (xs, ys) = c.approx(cal).knots();
        for (part, hand, got, what) in [
            ("at", spec.at.as_deref(), xs, "knots_x"),
            ("values", spec.values.as_deref(), ys, "knots_y"),
        ] {
            let Some(hand) = hand else { continue };
            if !same(hand, got) {
                return Err(Invalid::new(
                    format!("recipe.{}.{part}", c.key()),
                    format!(
                        "{} are not the {} of the curve {} (its {what}: {}): the file was edited \
                         in one place and not the other; set both alike, or remove recipe.{}.{part}",
                        list(hand),
                        if part == "at" { "knots" } else { "knot values" },
                        c.key(),
                        list(got),
                        c.key()
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// A short list of numbers for a message: the first few, and how many more.
fn list(v: &[f64]) -> String {
    let shown: Vec<String> = v
        .iter()
        .take(6)
        .map(|x| crate::number::readable(*x))
        .collect();
    match v.len() {
        0 => "none".to_string(),
        n if n > 6 => format!("[{}, … {} in all]", shown.join(", "), n),
        _ => format!("[{}]", shown.join(", ")),
    }
}

/// Refuses `fitted`, coefficient `c`'s curve fitted for `spec`, when it could not keep what
/// `spec` sets by hand: knots placed by hand (`at`) that are not its knots, or knot values set
/// by hand (`values`) that are not as many as its knots (its points carried only a simpler
/// curve: fewer knots, a line, a constant, or nothing). The values would be dropped and the
/// knots spread otherwise while the recipe, the summary and the workbench said they were used.
/// `warnings` holds what the fit said of its points (the reason given).
///
/// # Errors
/// [`FitError::HandKnotsNotKept`](crate::models::FitError::HandKnotsNotKept), naming the field.
pub fn check_hand_kept(
    c: Coefficient,
    spec: &ApproxSpec,
    fitted: &Approx,
    warnings: &[String],
) -> crate::error::Result<()> {
    let (xs, ys) = fitted.knots();
    let same_kind = fitted.kind() == spec.kind;
    let kept_at = spec.at.as_ref().is_none_or(|at| {
        same_kind
            && at.len() == xs.len()
            && at
                .iter()
                .zip(xs)
                .all(|(a, x)| (a - x).abs() <= 1e-12 * (1.0 + a.abs()))
    });
    let kept_values = spec
        .values
        .as_ref()
        .is_none_or(|v| same_kind && v.len() == ys.len());
    if kept_at && kept_values {
        return Ok(());
    }
    let label = c.label();
    let why = warnings
        .iter()
        .rev()
        .find(|w| w.starts_with(&format!("{label}:")))
        // The fit's own advice after its first sentence gives way to the remedy below.
        .map(|w| {
            let w = w[label.len() + 1..].trim();
            w.split_once(". ").map_or(w, |(first, _)| first).to_string()
        })
        .unwrap_or_else(|| format!("its points carry {} with {} knots", fitted.kind(), xs.len()));
    let (field, what, remedy) = if !kept_at {
        let n = spec.at.as_ref().map_or(0, Vec::len);
        (
            format!("{}.at", c.key()),
            format!("{n} knots placed"),
            if c == Coefficient::K0 {
                "place no more knots than the plateaus have temperatures, or hold a plateau at \
                 another temperature"
            } else {
                "place fewer knots, or narrow the dead-bands so that the set has more points"
            },
        )
    } else {
        let n = spec.values.as_ref().map_or(0, Vec::len);
        (
            format!("{}.values", c.key()),
            format!("{n} knot values set"),
            if c == Coefficient::K0 {
                "set as many values as the curve fitted has knots, or hold a plateau at another \
                 temperature"
            } else {
                "set as many values as the curve fitted has knots, or narrow the dead-bands so \
                 that the set has more points"
            },
        )
    };
    let dropped = crate::models::HandKnotsNotKept {
        field,
        what,
        label,
        why,
        remedy,
    };
    Err(crate::models::FitError::HandKnotsNotKept(Box::new(dropped)).into())
}
