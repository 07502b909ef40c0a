//! A simulated lot with known truth, for the lot's tests: ordinary units of the reference gyro
//! (other seeds), one whose angle random walk is ten times the others', one whose K0 slope is
//! three times theirs, one unit of two runs in a folder, and one corrupt file. The logs are a
//! short chamber program (20 → 50 → −10 → 20 °C, 5.7 h at 1 Hz), so that a lot is quick.

use driftlab::sim::{GyroParams, Profile, Segment, simulate};
use std::path::Path;

/// The ordinary units' files.
pub const ORDINARY: [&str; 5] = ["u01.csv", "u02.csv", "u03.csv", "u04.csv", "u05.csv"];
/// The unit whose noise floor is ten times the others'.
pub const NOISY: &str = "u06-noisy.csv";
/// The unit whose K0 slope is three times the others'.
pub const SLOPED: &str = "u07-sloped.csv";
/// The unit of two runs, a folder.
pub const CAMPAIGN: &str = "u08-two-runs";
/// The corrupt file.
pub const CORRUPT: &str = "u09-corrupt.csv";

/// The reference temperatures the tests' spec reports K0 at, within the program's range.
pub const REFERENCE_TEMPS_C: [f64; 3] = [0.0, 20.0, 40.0];

/// The reference gyro's K0 slope, °/h per °C, and the sloped unit's.
pub fn slopes() -> (f64, f64) {
    let ordinary = GyroParams::default().bias_slope_dph_per_c;
    (ordinary, 3.0 * ordinary)
}

/// The reference gyro's angle random walk, °/√h, and the noisy unit's.
pub fn arws() -> (f64, f64) {
    let ordinary = GyroParams::default().arw_deg_per_sqrt_h;
    (ordinary, 10.0 * ordinary)
}

/// The short chamber program, run by `gyro`.
pub fn profile(gyro: GyroParams) -> Profile {
    let ramp = |to_c: f64| Segment::Ramp {
        to_c,
        rate_c_per_min: 1.0,
    };
    let hold = |s: f64| Segment::Hold { duration_s: s };
    Profile {
        name: "lot-short".into(),
        description: "a short program for the lot's tests".into(),
        sample_rate_hz: 1.0,
        start_c: 20.0,
        program: vec![
            hold(3600.0),
            ramp(50.0),
            hold(3600.0),
            ramp(-10.0),
            hold(3600.0),
            ramp(20.0),
            hold(2400.0),
        ],
        gyro,
        laser: None,
        axes: Vec::new(),
        accelerometers: Vec::new(),
    }
}

/// Writes the lot into `dir`.
pub fn write_lot(dir: &Path) {
    let write = |name: &str, gyro: GyroParams, seed: u64| {
        simulate(&profile(gyro), seed)
            .write_csv(&dir.join(name))
            .unwrap();
    };
    for (k, name) in ORDINARY.iter().enumerate() {
        write(name, GyroParams::default(), 100 + k as u64);
    }
    write(
        NOISY,
        GyroParams {
            arw_deg_per_sqrt_h: arws().1,
            ..GyroParams::default()
        },
        200,
    );
    write(
        SLOPED,
        GyroParams {
            bias_slope_dph_per_c: slopes().1,
            ..GyroParams::default()
        },
        300,
    );
    let folder = dir.join(CAMPAIGN);
    std::fs::create_dir_all(&folder).unwrap();
    for (k, run) in ["run1.csv", "run2.csv"].iter().enumerate() {
        simulate(&profile(GyroParams::default()), 400 + k as u64)
            .write_csv(&folder.join(run))
            .unwrap();
    }
    // A log cut off mid-number, then noise where the rows go on.
    let mut corrupt = std::fs::read(dir.join(ORDINARY[0])).unwrap();
    corrupt.truncate(corrupt.len() / 3);
    corrupt.extend_from_slice(b"\n12.5,zz,\x00\x01\xff\n");
    std::fs::write(dir.join(CORRUPT), corrupt).unwrap();
}

/// A spec that the ordinary units meet with room, the noisy one breaks on its noise floor
/// (between the ordinary and the noisy ARW), and the sloped one meets.
pub fn spec_json() -> String {
    let (ordinary, noisy) = arws();
    format!(
        r#"{{
  "max_arw_deg_rt_h": {},
  "min_plateaus": 3,
  "k0_range_dph": [-1.0, 1.0],
  "reference_temps_c": [0, 20, 40]
}}
"#,
        (ordinary * noisy).sqrt()
    )
}

/// A lot that is refused before any unit is read: `dir/units` holding one log of a header
/// alone (`u.csv`), and `dir/spec.json` holding `spec`. Returns the folder of units and the
/// spec's path.
pub fn header_only_lot(dir: &Path, spec: &str) -> (String, String) {
    let units = dir.join("units");
    std::fs::create_dir(&units).unwrap();
    std::fs::write(units.join("u.csv"), "time_s,omega_dph,temp_c\n").unwrap();
    let spec_path = dir.join("spec.json");
    std::fs::write(&spec_path, spec).unwrap();
    (units.display().to_string(), spec_path.display().to_string())
}
