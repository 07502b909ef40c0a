//! One axis of a unit exported alone (`export UNIT --axis gy`): a flight controller's file
//! holds that axis's numbers in the parameters the whole unit's file holds them in, and the
//! other axes at zero; the C header and the table name the axis.
//!
//! The truth is the whole unit's export, read independently here by parameter name: the `--axis`
//! file must carry the same text under the same names, for axes placed by the letter their
//! names end with and for axes placed in the unit's order.

use super::flight_exports::{Curve, DPH_PER_RAD_S, custom, fit, log_of, unit_file};
use crate::common::run::ok;
use driftlab::export::firmware::{self, ExportOptions, Format};
use driftlab::models::DriftModel;
use std::collections::BTreeMap;

/// Every parameter of a PX4 `.params` or ArduPilot `.parm` file, its value as written.
fn params(text: &str) -> BTreeMap<String, String> {
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|l| {
            let f: Vec<&str> = l.split(['\t', ' ']).collect();
            if f.len() == 5 {
                (f[2].to_string(), f[3].to_string())
            } else {
                assert_eq!(f.len(), 2, "{l}");
                (f[0].to_string(), f[1].to_string())
            }
        })
        .collect()
}

/// Which gyro axis (0 = X, 1 = Y, 2 = Z) a parameter holds a coefficient of, `None` for one
/// every axis shares (range, reference, id, enable) or for the accelerometer's.
fn gyro_axis_of(name: &str) -> Option<usize> {
    if let Some(rest) = name.strip_prefix("TC_G0_X") {
        // TC_G0_X{order}_{axis}
        return rest.split('_').nth(1).map(|a| a.parse().unwrap());
    }
    if name.contains("_GYR") {
        return Some(match name.chars().last().unwrap() {
            'X' => 0,
            'Y' => 1,
            'Z' => 2,
            c => panic!("{name}: axis {c}"),
        });
    }
    None
}

/// Three cubic models of the MEMS size the flight tests use, each its own curve.
fn three_models() -> Vec<DriftModel> {
    [
        Curve([0.012, 2.1e-4, -3.0e-6, 4.0e-8]),
        Curve([-0.004, -1.3e-4, 2.0e-6, 0.0]),
        Curve([0.020, 0.6e-4, 1.0e-6, -2.0e-8]),
    ]
    .iter()
    .enumerate()
    .map(|(k, &c)| {
        fit(
            &log_of(c, DPH_PER_RAD_S, 0.002, 70 + k as u64),
            &custom("1,T,T^2,T^3"),
        )
    })
    .collect()
}

/// `names` in the unit in that order (each a model of `three_models`); `place[k]` is where the
/// whole unit's file puts axis `k`.
fn check_each_axis_alone(names: [&str; 3], place: [usize; 3]) {
    let dir = tempfile::tempdir().unwrap();
    let models = three_models();
    let axes: Vec<(&str, &DriftModel)> = names.iter().copied().zip(&models).collect();
    let path = unit_file(dir.path(), &axes);
    let formats: [&[&str]; 2] = [
        &["--format", "px4-params", "--device-id", "2424842"],
        &["--format", "ardupilot-parm", "--imu", "1"],
    ];
    for format in formats {
        let whole = params(&ok(&[&["export", path.as_str()][..], format].concat()));
        for (k, name) in names.iter().enumerate() {
            let alone_text = ok(&[&["export", path.as_str(), "--axis", name][..], format].concat());
            let alone = params(&alone_text);
            assert_eq!(
                alone.keys().collect::<Vec<_>>(),
                whole.keys().collect::<Vec<_>>(),
                "{format:?} --axis {name}: the same parameters"
            );
            let mut own = 0;
            for (p, v) in &alone {
                match gyro_axis_of(p) {
                    // This axis's coefficients: the whole unit's, digit for digit.
                    Some(a) if a == place[k] => {
                        assert_eq!(v, &whole[p], "{format:?} --axis {name}: {p}");
                        own += 1;
                    }
                    // The other axes: at zero.
                    Some(_) => assert_eq!(
                        v.parse::<f64>().unwrap(),
                        0.0,
                        "{format:?} --axis {name}: {p} = {v}"
                    ),
                    // The range, reference and ids: the whole unit's (every axis covers one).
                    None => assert_eq!(v, &whole[p], "{format:?} --axis {name}: {p}"),
                }
            }
            assert!(own >= 3, "{format:?} --axis {name}: {own} own parameters");
            // The file says what it holds, and claims no nameless axis.
            assert!(!alone_text.contains("names no axis"), "{alone_text}");
            assert!(
                alone_text
                    .lines()
                    .any(|l| l.starts_with("# gyro ") && l.contains(name)),
                "{alone_text}"
            );
            let zero: Vec<&str> = (0..3)
                .filter(|&a| a != place[k])
                .map(|a| ["X", "Y", "Z"][a])
                .collect();
            assert!(
                alone_text.contains(&format!("axis {}: its coefficients", zero.join(", "))),
                "{alone_text}"
            );
        }
    }
}

#[test]
fn one_axis_of_a_unit_lands_in_the_parameters_the_whole_unit_gives_it() {
    // Out of order in the unit: the letters place them (gz in Z, gy in Y).
    check_each_axis_alone(["gz", "gx", "gy"], [2, 0, 1]);
}

#[test]
fn one_axis_of_a_unit_named_without_letters_lands_in_its_place_in_the_order() {
    // No x, y or z in the names: the unit's order places them, for one axis as for three.
    check_each_axis_alone(["fog1", "fog2", "fog3"], [0, 1, 2]);
}

#[test]
fn one_axis_header_and_table_name_the_axis_and_are_its_single_axis_files_otherwise() {
    let dir = tempfile::tempdir().unwrap();
    let models = three_models();
    let path = unit_file(
        dir.path(),
        &[("gx", &models[0]), ("gy", &models[1]), ("gz", &models[2])],
    );
    let opts = ExportOptions::default();
    for (format, flag) in [
        (Format::CHeader, "c-header"),
        (Format::CsvTable, "csv-table"),
    ] {
        let alone = ok(&["export", &path, "--format", flag, "--axis", "gy"]);
        let single = firmware::export_model(&models[1], format, &opts).unwrap();
        let naming: Vec<&str> = alone
            .lines()
            .filter(|l| l.contains("gy (rate column gy_dps), one of the unit's axes gx, gy, gz"))
            .collect();
        assert_eq!(naming.len(), 1, "{flag}: {alone}");
        // Apart from the lines naming the axis, the single-axis file of gy's model: the same
        // code, bit for bit as driftlab.
        // The "created" line is the moment each file was written, which may fall a second
        // apart on a loaded machine.
        let written = |l: &&str| l.contains("created:");
        let rest: Vec<&str> = alone
            .lines()
            .filter(|l| !naming.contains(l) && !l.starts_with("#define DRIFTLAB_AXIS "))
            .filter(|l| !written(l))
            .collect();
        let single: Vec<&str> = single.lines().filter(|l| !written(l)).collect();
        assert_eq!(rest, single, "{flag}");
        if format == Format::CHeader {
            assert!(
                alone.contains("\n#define DRIFTLAB_AXIS \"gy\"\n"),
                "{alone}"
            );
        }
    }
}
