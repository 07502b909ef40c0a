//! K0(T) is fitted through the plateaus' temperatures, not their count: three plateaus held at
//! two set points (the papers' square waves, −25/−45/−25 °C) determine a line, and a parabola
//! through them takes its curvature from the hundredths of a degree between the two at one set
//! point.

use driftlab::models::recipe::Recipe;
use driftlab::models::vakhrameev;

#[test]
fn plateaus_at_two_set_points_give_no_curve_between_them() {
    for (name, (lo, hi)) in [
        ("yan-steps-low", (-45.0, -25.0)),
        ("yan-steps-mid", (-10.0, 10.0)),
    ] {
        let profile = driftlab::sim::profile(name).unwrap();
        let log = driftlab::sim::simulate(&profile, 1).to_log(name);
        let fit = vakhrameev::fit(&log, &Recipe::default().checked().unwrap()).unwrap();
        let plateaus = &fit.calibration.plateaus;
        let (ws, ts): (Vec<f64>, Vec<f64>) =
            plateaus.iter().map(|p| (p.omega_dph, p.temp_c)).unzip();
        assert!(plateaus.len() >= 3, "{name}: {ts:?}");
        let (t_lo, t_hi) = ts
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &t| {
                (a.min(t), b.max(t))
            });
        assert!(
            (t_lo - lo).abs() < 1.0 && (t_hi - hi).abs() < 1.0,
            "{name}: {ts:?}"
        );
        // Between the set points, K0 stays between what the plateaus measured (a line does;
        // the parabola reached 7.5 °/h between plateaus of 0.03 and 0.15).
        let (w_lo, w_hi) = ws
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &w| {
                (a.min(w), b.max(w))
            });
        let margin = 0.05 * (w_hi - w_lo) + 1e-3;
        for k in 0..=20 {
            let t = t_lo + (t_hi - t_lo) * k as f64 / 20.0;
            let k0 = fit.calibration.k0.eval(t);
            assert!(
                k0 >= w_lo - margin && k0 <= w_hi + margin,
                "{name}: K0({t:.1}) = {k0} beyond the plateaus' {w_lo} … {w_hi}"
            );
        }
        assert!(
            fit.warnings
                .iter()
                .any(|w| w.starts_with("K0:") && w.contains("at only 2 temperatures")),
            "{name}: {:?}",
            fit.warnings
        );
    }
}
