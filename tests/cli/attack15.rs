//! The fifteenth attack's findings about readers and commands: a flight log gets the column
//! checks a CSV gets; a stuck axis of a unit is refused by `calibrate` as by `evaluate`; a log
//! written newest row first is refused with the reason; `--decimal-comma` on a file that cannot
//! be written so is refused; two logs of one file name are told apart in a report.

use crate::common::run::{driftlab, fails, ok, sample};
use std::path::Path;

fn p(d: &Path, name: &str) -> String {
    d.join(name).display().to_string()
}

/// A ULog of a chamber run whose gyro y and z read 0 throughout and whose temperature is in
/// kelvin: the same doubts as the same samples in a CSV, in the flight log's terms.
#[test]
fn a_flight_log_with_dead_axes_and_kelvin_is_told_and_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let n = 4000usize;
    let time_s: Vec<f64> = (0..n).map(|k| k as f64).collect();
    // Held at 20 °C, a ramp to 60 °C, held there: two plateaus, in kelvin.
    let temp_k: Vec<f32> = (0..n)
        .map(|k| {
            let ramp = ((k as f32 - 1500.0) / 1500.0).clamp(0.0, 1.0);
            273.15 + 20.0 + 40.0 * ramp
        })
        .collect();
    let gyro: Vec<[f32; 3]> = (0..n)
        .map(|k| [1e-5 * (k as f32 * 0.7).sin() + 1e-5, 0.0, 0.0])
        .collect();
    let ulg = d.join("dead.ulg");
    std::fs::write(
        &ulg,
        crate::common::drone::ulog(&time_s, &gyro, &temp_k, 2_424_842),
    )
    .unwrap();
    let ulg = ulg.display().to_string();
    let out = driftlab(&["inspect", &ulg]);
    let said =
        String::from_utf8_lossy(&out.stderr).to_string() + &String::from_utf8_lossy(&out.stdout);
    for axis in ["gyro_y", "gyro_z"] {
        assert!(
            said.contains(&format!("the rate of axis {axis} holds one value, 0 °/h")),
            "{said}"
        );
    }
    assert!(
        said.contains("outside the -100 … 200 °C a chamber reaches"),
        "{said}"
    );
    // The remedy is one a flight log has (a CSV's --temp-col is refused on one); this log has
    // no other temperature, so --temp-from would choose nothing either.
    assert!(
        said.contains("the log holds no other temperature to choose"),
        "{said}"
    );
    assert!(!said.contains("--temp-col"), "{said}");
    assert!(!said.contains("--temp-from"), "{said}");
    assert!(!said.contains("(1 time)"), "{said}");
    let err = fails(&["calibrate", &ulg, "-o", &p(d, "c.json")]);
    assert!(
        err.contains("the rate of axis gyro_y never changes") && err.contains("--axes"),
        "{err}"
    );
    assert!(!d.join("c.json").exists());
}

/// The three-axis sample with axis gy zeroed: `calibrate` refuses it, naming the axis and
/// `--axes`, as `evaluate` does; the other two axes calibrate.
#[test]
fn a_stuck_axis_of_a_unit_is_refused_by_calibrate() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let text = std::fs::read_to_string(sample("imu3-calibration.csv")).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header = lines.next().unwrap();
    let gy = header
        .split(';')
        .position(|c| c.starts_with("gy"))
        .expect("a gy column");
    let mut out = format!("{header}\n");
    for l in lines.step_by(5) {
        let mut f: Vec<&str> = l.split(';').collect();
        f[gy] = "0,00000000";
        out.push_str(&f.join(";"));
        out.push('\n');
    }
    let stuck = p(d, "stuck.csv");
    std::fs::write(&stuck, out).unwrap();
    let err = fails(&["calibrate", &stuck, "-o", &p(d, "unit.json")]);
    assert!(
        err.contains("the rate of axis gy never changes") && err.contains("--axes"),
        "{err}"
    );
    assert!(!d.join("unit.json").exists());
    let names: Vec<&str> = header.split(';').collect();
    let others: Vec<&str> = names
        .iter()
        .filter(|c| c.starts_with('g') && !c.starts_with("gy"))
        .map(|c| c.split('_').next().unwrap())
        .collect();
    assert_eq!(others.len(), 2, "{header}");
    ok(&[
        "calibrate",
        &stuck,
        "--axes",
        &others.join(","),
        "-o",
        &p(d, "two.json"),
    ]);
}

/// `calibration.csv` written newest row first: refused with the reason and the remedy, not
/// read as its one first row (which `apply` wrote as a 1-row file with success).
#[test]
fn a_log_written_newest_first_is_refused_with_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let text = std::fs::read_to_string(sample("calibration.csv")).unwrap();
    let mut lines: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    let header = lines.remove(0);
    lines.reverse();
    let rev = p(d, "reversed.csv");
    std::fs::write(&rev, format!("{header}\n{}\n", lines.join("\n"))).unwrap();
    let cal = p(d, "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "-o", &cal]);
    for args in [
        vec!["apply", cal.as_str(), rev.as_str(), "-o", "/dev/null"],
        vec!["evaluate", cal.as_str(), rev.as_str()],
        vec!["calibrate", rev.as_str(), "-o", "/dev/null"],
    ] {
        let err = fails(&args);
        assert!(
            err.contains(&format!(
                "{} of the {} rows go back in time",
                lines.len() - 1,
                lines.len()
            )) && err.contains("sort the log by its time column"),
            "{args:?}: {err}"
        );
        assert!(!err.contains("--filter"), "{err}");
    }
}

/// `--decimal-comma` on the sample log (decimal points, `;`-separated? no: read what it is)
/// and on a comma-separated file: refused, naming the option.
#[test]
fn decimal_comma_on_a_file_that_cannot_be_so_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let points = p(d, "points.csv");
    let mut text = String::from("time_s;omega_dph;temp_c\n");
    for k in 0..50 {
        text.push_str(&format!(
            "{k};{:.4};{:.3}\n",
            0.1 + k as f64 * 1e-3,
            20.0 + k as f64 * 0.01
        ));
    }
    std::fs::write(&points, &text).unwrap();
    let err = fails(&["inspect", &points, "--decimal-comma"]);
    assert!(
        err.contains("--decimal-comma") && err.contains("decimal points"),
        "{err}"
    );
    let commas = p(d, "commas.csv");
    std::fs::write(&commas, text.replace(';', ",")).unwrap();
    let err = fails(&["inspect", &commas, "--decimal-comma"]);
    assert!(
        err.contains("--decimal-comma") && err.contains("separated by commas"),
        "{err}"
    );
    // A file written with decimal commas reads with it as without.
    let dc = p(d, "dc.csv");
    std::fs::write(&dc, text.replace('.', ",")).unwrap();
    assert_eq!(
        ok(&["inspect", &dc, "--decimal-comma"])
            .lines()
            .filter(|l| l.contains("omega"))
            .count(),
        ok(&["inspect", &dc])
            .lines()
            .filter(|l| l.contains("omega"))
            .count()
    );
}

/// A hand-edited K1+ that extrapolates with a slope of 1e13 over ±1e-6 °C/s: within its own
/// range it predicts nothing, past it 5e9 °/h at the first sample; refused on load as any
/// calibration predicting more than a gyro could show, where a chamber takes Ṫ.
#[test]
fn an_extrapolating_curve_is_bounded_where_a_chamber_takes_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cal = p(d, "cal.json");
    ok(&["calibrate", &sample("calibration.csv"), "-o", &cal]);
    let mut j: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&cal).unwrap()).unwrap();
    let k = &mut j["calibration"]["k1_plus"];
    k["extrapolate"] = true.into();
    k["x_min"] = (-1e-6).into();
    k["x_max"] = 1e-6.into();
    k["curve"]["coeffs"] = serde_json::json!([0.0, 1e13]);
    j["calibration"]["recipe"]["k1_plus"]["extrapolate"] = true.into();
    let edited = p(d, "edited.json");
    std::fs::write(&edited, serde_json::to_string(&j).unwrap()).unwrap();
    let err = fails(&["evaluate", &edited, &sample("validation.csv")]);
    assert!(
        err.contains("k1_plus.extrapolate")
            && err.contains("predicts a drift")
            && err.contains("without extrapolating"),
        "{err}"
    );
    // The same curve holding its edge values past its range predicts 1e7·1e-6² at most: kept.
    j["calibration"]["k1_plus"]["extrapolate"] = false.into();
    j["calibration"]["recipe"]["k1_plus"]["extrapolate"] = false.into();
    std::fs::write(&edited, serde_json::to_string(&j).unwrap()).unwrap();
    ok(&["evaluate", &edited, &sample("validation.csv")]);
}
