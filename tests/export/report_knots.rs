//! The test report says which knots were placed and set by hand (issue 22, item 1): a row per
//! knot curve of the recipe, in the engine's words, beside the recipe as the file holds it.

use driftlab::export::report::{self, ReportOptions};
use driftlab::log::ingest::{self, ReadOptions};
use driftlab::models::approx::{ApproxKind, ApproxSpec};
use driftlab::models::recipe::Recipe;
use driftlab::models::vakhrameev;
use std::path::Path;

#[test]
fn the_report_shows_the_knots_placed_and_set_by_hand() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("sample_logs/calibration.csv");
    let log = ingest::read_path(&path, &ReadOptions::default()).unwrap();
    let recipe = Recipe {
        k1_plus: ApproxSpec {
            knots: 4,
            at: Some(vec![0.0002, 0.0055, 0.0125, 0.021]),
            ..ApproxSpec::of(ApproxKind::Pwl)
        },
        k2_minus: ApproxSpec {
            knots: 3,
            values: Some(vec![-50.0, 25.5, 4000.0]),
            ..ApproxSpec::of(ApproxKind::Spline)
        },
        k1_minus: ApproxSpec::of(ApproxKind::Spline),
        ..Recipe::default()
    };
    let cal = vakhrameev::fit(&log, &recipe.checked().unwrap())
        .unwrap()
        .calibration;
    assert_eq!(cal.k1_plus.knots().0, &[0.0002, 0.0055, 0.0125, 0.021][..]);
    let dir = tempfile::tempdir().unwrap();
    let summary = report::write(
        &cal,
        &[(path.clone(), log)],
        dir.path(),
        &ReportOptions::default(),
    )
    .unwrap();
    let html = std::fs::read_to_string(&summary.html).unwrap();
    for want in [
        "knots of K1+",
        "4 knots placed by hand at 0.0002, 0.0055, 0.0125, 0.021",
        "knots of K1−",
        "5 knots, equally spaced",
        "knots of K2−",
        "3 knots, equally spaced; values set by hand: -50, 25.5, 4000",
        "&quot;at&quot;: [",
    ] {
        assert!(html.contains(want), "the page lacks {want:?}");
    }
    // Curves without knots get no row.
    assert!(!html.contains("knots of K0") && !html.contains("knots of K2+"));
}
