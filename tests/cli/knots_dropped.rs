//! Knots placed or set by hand that an option drops are told: `--knots N` (another count
//! spreads a curve's knots evenly again) and `--k0/--k1/--k2` of a kind without knots. They
//! were placed on purpose, and the option that drops them says nothing of them.

use crate::common::run::{driftlab, p, sample};

#[test]
fn knots_placed_by_hand_that_an_option_drops_are_told() {
    let dir = tempfile::tempdir().unwrap();
    let recipe = p(dir.path(), "hand.json");
    std::fs::write(
        &recipe,
        r#"{"k0": {"kind": "pwl", "knots": 3, "at": [-50, 0, 60], "values": [0.2, 0, 0.3]},
            "k1_plus": {"kind": "pwl", "knots": 3, "at": [-0.015, 0, 0.015]}}"#,
    )
    .unwrap();
    let log = sample("calibration.csv");
    let out = p(dir.path(), "cal.json");
    let told = |extra: &[&str]| {
        let mut args = vec!["calibrate", &log, "--recipe", &recipe, "--out", &out];
        args.extend_from_slice(extra);
        let run = driftlab(&args);
        let err = String::from_utf8(run.stderr).unwrap();
        assert!(run.status.success(), "{err}");
        err
    };
    // The recipe as it is: nothing dropped, nothing said.
    assert!(!told(&[]).contains("are dropped"));
    let err = told(&["--knots", "4"]);
    for curve in ["K0", "K1+"] {
        let line = format!(
            "note: --knots 4: {curve}'s knots placed or set by hand in {recipe} are dropped"
        );
        assert!(err.contains(&line), "{curve}: {err}");
    }
    let err = told(&["--k1", "linear"]);
    assert!(
        err.contains("note: --k1 linear: K1+'s knots placed or set by hand in"),
        "{err}"
    );
    assert!(!err.contains("K0's knots"), "K0 keeps its knots: {err}");
    // The same count keeps them.
    assert!(!told(&["--knots", "3"]).contains("are dropped"));
}
