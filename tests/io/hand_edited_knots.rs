//! A calibration file whose recipe's knots placed or set by hand (`at`, `values`) are not the
//! knots of its curve: edited in one place and not the other. It loaded, corrected with the
//! curve, and `calibrate --recipe` of the same file made another calibration; it is refused,
//! naming both fields. The file as driftlab writes it loads.

use super::hand_edited_calibrations::{body, edited, refused, vakhrameev_file};
use driftlab::files::calibration;
use driftlab::models::approx::{ApproxKind, ApproxSpec};
use driftlab::models::recipe::Recipe;
use serde_json::json;

#[test]
fn recipe_knots_that_are_not_the_curves_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    // K1+ as a pwl curve, then its knots and values set by hand where the fit put them.
    let pwl = Recipe {
        k1_plus: ApproxSpec::of(ApproxKind::Pwl),
        ..Recipe::default()
    };
    let (_, fitted) = vakhrameev_file(dir.path(), "even.json", &pwl);
    let (xs, ys) = fitted.k1_plus.knots();
    let mut hand = pwl.clone();
    hand.k1_plus.at = Some(xs.to_vec());
    hand.k1_plus.values = Some(ys.iter().map(|y| y + 1.0).collect());
    let (cal, _) = vakhrameev_file(dir.path(), "hand.json", &hand);
    calibration::load_unit(&cal).expect("the file as written loads");
    let moved = edited(&cal, "moved.json", |v| {
        let at = &mut body(v)["recipe"]["k1_plus"]["at"][1];
        *at = json!(at.as_f64().unwrap() * 0.5);
    });
    refused(
        &moved,
        "recipe.k1_plus.at",
        "are not the knots of the curve k1_plus",
    );
    let valued = edited(&cal, "valued.json", |v| {
        body(v)["recipe"]["k1_plus"]["values"][0] = json!(-300.0);
    });
    refused(
        &valued,
        "recipe.k1_plus.values",
        "are not the knot values of the curve k1_plus",
    );
    // The curve edited alone is refused by the same rule, from the other side.
    let curve = edited(&cal, "curve.json", |v| {
        let y = &mut body(v)["k1_plus"]["curve"]["knots_y"][0];
        *y = json!(y.as_f64().unwrap() + 5.0);
    });
    refused(&curve, "recipe.k1_plus.values", "its knots_y");
}
