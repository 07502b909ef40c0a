//! The seventeenth attack's findings about commands: `convert` wrote flight logs whose time
//! runs backwards, repeats or jumps to a stray stamp that every other command refuses or
//! drops; `inspect` listed a log written newest first as having "fewer than two distinct
//! stamps" and its accelerometer temperature as all NaN.

use crate::common::run::{driftlab, fails, ok, p};

// ------------------------------------------------------------------ crafted flight logs

/// A PX4 ULog of one `sensor_gyro` and the `sensor_accel` of the same device (its stamps
/// `accel_lag_us` after the gyro's), each with a temperature: the gyro at `temp_c`, the
/// accelerometer 0.5 °C above it. Time stamps in µs, written as given (in any order). A second
/// gyro (`multi_id` 1, of another device, without an accelerometer) beside it at 25 °C, its
/// stamps in order.
fn ulog(stamps_us: &[u64], temp_c: &[f32], accel_lag_us: u64) -> Vec<u8> {
    fn message(ty: u8, body: &[u8]) -> Vec<u8> {
        let mut m = (body.len() as u16).to_le_bytes().to_vec();
        m.push(ty);
        m.extend_from_slice(body);
        m
    }
    let mut b = b"ULog\x01\x12\x35".to_vec();
    b.push(1);
    b.extend_from_slice(&0u64.to_le_bytes());
    b.extend(message(b'B', &[0u8; 40]));
    for topic in ["sensor_gyro", "sensor_accel"] {
        let format = format!(
            "{topic}:uint64_t timestamp;uint32_t device_id;float x;float y;float z;\
             float temperature;"
        );
        b.extend(message(b'F', format.as_bytes()));
    }
    for (multi, id, topic) in [
        (0u8, 0u8, "sensor_gyro"),
        (0, 1, "sensor_accel"),
        (1, 2, "sensor_gyro"),
    ] {
        let mut a = vec![multi, id, 0];
        a.extend_from_slice(topic.as_bytes());
        b.extend(message(b'A', &a));
    }
    for (k, (&t, &temp)) in stamps_us.iter().zip(temp_c).enumerate() {
        let w = 0.001 * k as f32;
        let second = 100_000_000 + k as u64 * 1_000_000;
        for (id, at, device, xyz, temp) in [
            (0u8, t, 2_424_842u32, [w, -w, 0.002], temp),
            (1, t + accel_lag_us, 2_424_842, [0.1, 0.2, -9.8], temp + 0.5),
            (2, second, 3_670_050, [w, w, 0.001], 25.0),
        ] {
            let mut d = vec![id, 0];
            d.extend_from_slice(&at.to_le_bytes());
            d.extend_from_slice(&device.to_le_bytes());
            for v in [xyz[0], xyz[1], xyz[2], temp] {
                d.extend_from_slice(&v.to_le_bytes());
            }
            b.extend(message(b'D', &d));
        }
    }
    b
}

/// An ArduPilot DataFlash log of IMU 0's messages stamped `stamps_us` (as given, in any
/// order), its temperature rising 0.01 °C a message from 30 °C.
fn dataflash(stamps_us: &[u64]) -> Vec<u8> {
    fn message(ty: u8, payload: &[u8]) -> Vec<u8> {
        let mut m = vec![0xA3, 0x95, ty];
        m.extend_from_slice(payload);
        m
    }
    let fmt = |ty: u8, length: u8, name: &str, format: &str, labels: &str| {
        let fixed = |s: &str, n: usize| {
            let mut v = s.as_bytes().to_vec();
            v.resize(n, 0);
            v
        };
        let mut p = vec![ty, length];
        p.extend(fixed(name, 4));
        p.extend(fixed(format, 16));
        p.extend(fixed(labels, 64));
        message(0x80, &p)
    };
    let mut b = fmt(0x80, 89, "FMT", "BBnNZ", "Type,Length,Name,Format,Columns");
    b.extend(fmt(
        163,
        54,
        "IMU",
        "QBffffffIIfBBHH",
        "TimeUS,I,GyrX,GyrY,GyrZ,AccX,AccY,AccZ,EG,EA,T,GH,AH,GHz,AHz",
    ));
    for (k, &t) in stamps_us.iter().enumerate() {
        let mut p = t.to_le_bytes().to_vec();
        p.push(0);
        for v in [0.01f32, 0.0, 0.0, 0.0, 0.0, -9.8] {
            p.extend_from_slice(&v.to_le_bytes());
        }
        p.extend_from_slice(&[0; 8]);
        p.extend_from_slice(&(30.0 + 0.01 * k as f32).to_le_bytes());
        p.extend_from_slice(&[1, 1, 0xE8, 0x03, 0xE8, 0x03]);
        b.extend(message(163, &p));
    }
    b
}

/// The time column of a CSV `convert` wrote.
fn times(csv: &str) -> Vec<f64> {
    std::fs::read_to_string(csv)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect()
}

/// Ten stamps one second apart from 100 s, in µs.
fn in_order() -> Vec<u64> {
    (0..10).map(|k| 100_000_000 + k * 1_000_000).collect()
}

// ------------------------------------------------------------------ 1. convert's time checks

/// A log written newest first is refused by `convert` as by every other command (it wrote a
/// CSV whose time ran backwards), naming the gyro and the first sample that goes back, and
/// nothing is written.
#[test]
fn convert_refuses_a_flight_log_written_newest_first_as_inspect_does() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut reversed = in_order();
    reversed.reverse();
    let temps: Vec<f32> = (0..10).map(|k| 30.0 + 0.01 * k as f32).collect();
    std::fs::write(d.join("rev.bin"), dataflash(&reversed)).unwrap();
    std::fs::write(d.join("rev.ulg"), ulog(&reversed, &temps, 300)).unwrap();
    for log in ["rev.bin", "rev.ulg"] {
        let out = p(d, "out.csv");
        let err = fails(&["convert", &p(d, log), "-o", &out]);
        assert!(
            err.contains("9 of the 10 samples")
                && err.contains("go back in time (first at sample 2: 108 s after 109 s)")
                && err.contains("not in time order"),
            "{log}: {err}"
        );
        assert!(!d.join("out.csv").exists(), "{log}");
        // The same refusal, word for word, as inspect's.
        let inspect = driftlab(&["inspect", &p(d, log)]);
        assert!(!inspect.status.success());
        let refusal = |s: &str| {
            s.lines()
                .find(|l| l.starts_with("error:"))
                .map(String::from)
        };
        assert_eq!(
            refusal(&err),
            refusal(&String::from_utf8_lossy(&inspect.stderr)),
            "{log}"
        );
    }
}

/// A stray stamp far past the rest and stamps that repeat are dropped by `convert` as every
/// reader drops them, told by sample number; the CSV holds the stamps written in order.
#[test]
fn convert_drops_stray_and_repeated_stamps_as_every_reader_does() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Sample 10 at 2^64 - 1 µs (a counter read as -1): a stray stamp.
    let mut huge = in_order();
    huge[9] = u64::MAX;
    let temps: Vec<f32> = (0..10).map(|k| 30.0 + 0.01 * k as f32).collect();
    std::fs::write(d.join("huge.ulg"), ulog(&huge, &temps, 300)).unwrap();
    let out = p(d, "huge.csv");
    let o = driftlab(&["convert", &p(d, "huge.ulg"), "-o", &out]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("a stray time stamp (sample 10)"), "{err}");
    let want: Vec<f64> = (0..9).map(|k| 100.0 + k as f64).collect();
    assert_eq!(times(&out), want);
    assert!(err.contains("9 samples of sensor_gyro"), "{err}");

    // Every stamp the same: one sample kept, the nine repeats dropped and told.
    std::fs::write(d.join("same.bin"), dataflash(&[100_000_000; 10])).unwrap();
    let out = p(d, "same.csv");
    let o = driftlab(&["convert", &p(d, "same.bin"), "-o", &out]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("9 samples dropped: time repeats an earlier stamp (first at sample 2)"),
        "{err}"
    );
    assert!(err.contains("1 sample of IMU written"), "{err}");
    assert_eq!(times(&out), [100.0]);
}

// ------------------------------------------------------------------ 2. inspect's listing

/// A ULog written newest first: its gyro's rate is "not in time order" (not "fewer than two
/// distinct stamps": it has ten), its accelerometer's temperature is matched to it and has a
/// range (it was listed as all NaN), and `--temp-from accel` picks that gyro (then refused
/// for its time order, not for a missing temperature).
#[test]
fn inspect_lists_a_log_written_newest_first_as_it_is() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut reversed = in_order();
    reversed.reverse();
    let temps: Vec<f32> = (0..10).map(|k| 40.0 - 0.1 * k as f32).collect();
    std::fs::write(d.join("rev.ulg"), ulog(&reversed, &temps, 300)).unwrap();
    let o = driftlab(&["inspect", &p(d, "rev.ulg")]);
    let listing = String::from_utf8_lossy(&o.stdout);
    let gyro = listing
        .lines()
        .find(|l| l.trim_start().starts_with("gyro 0"))
        .unwrap_or_else(|| panic!("{listing}"));
    assert!(
        gyro.contains("10 samples at n/a Hz (not in time order: 9 of its 9 steps go back)")
            && !gyro.contains("fewer than two distinct stamps"),
        "{gyro}"
    );
    // The accelerometer's temperature, 0.5 °C above the gyro's 39.1 .. 40.0.
    assert!(
        gyro.contains("--temp-from accel: sensor_accel[0].temperature 39.60 .. 40.50 degC")
            && !gyro.contains("all NaN"),
        "{gyro}"
    );
    let err = fails(&[
        "convert",
        &p(d, "rev.ulg"),
        "--temp-from",
        "accel",
        "-o",
        &p(d, "x.csv"),
    ]);
    assert!(
        err.contains("gyro 0 (sensor_gyro multi_id 0")
            && err.contains("the first of 2 with an accel temperature")
            && err.contains("not in time order"),
        "{err}"
    );
    // In order, the same log lists its rate.
    std::fs::write(d.join("fwd.ulg"), ulog(&in_order(), &temps, 300)).unwrap();
    let listing = ok(&["inspect", &p(d, "fwd.ulg")]);
    assert!(
        listing.contains("10 samples at 1.000 Hz over 9.000 s"),
        "{listing}"
    );
}

// ------------------------------------------------------------------ 3. knots told apart

/// Knots placed by hand closer than six digits tell apart are printed with the digits that
/// do (they read "-0.01, -0.01, 0.01, 0.01", as if two knots were placed twice each); the
/// values, whole numbers, stay short.
#[test]
fn knots_placed_close_together_are_printed_apart() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let recipe = p(d, "recipe.json");
    std::fs::write(
        &recipe,
        r#"{"k1_plus": {"kind": "pwl", "knots": 4,
            "at": [-0.01000002, -0.01000001, 0.01, 0.01000001],
            "values": [10, 20, 30, 40]}}"#,
    )
    .unwrap();
    let out = ok(&[
        "calibrate",
        &crate::common::run::sample("calibration.csv"),
        "--recipe",
        &recipe,
        "-o",
        &p(d, "cal.json"),
    ]);
    assert!(
        out.contains(
            "K1+ 4 knots placed by hand at -0.01000002, -0.01000001, 0.01, 0.01000001; \
             values set by hand: 10, 20, 30, 40"
        ),
        "{out}"
    );
}

// ------------------------------------------------------------------ 4. the longest window

/// The longest window `evaluate` names is one that gives a figure: the stretch judged after
/// the warm-up, not the whole log (it named 37801 s on validation.csv, whose 179 warm-up
/// samples leave 37622 s judged, so the window it named gave only n/a). One sample above it is
/// refused with the same bound.
#[test]
fn the_longest_window_named_gives_a_figure() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cal = p(d, "cal.json");
    let validation = crate::common::run::sample("validation.csv");
    ok(&[
        "calibrate",
        &crate::common::run::sample("calibration.csv"),
        "-o",
        &cal,
    ]);
    // What is judged, as the evaluation counts it (1 s a sample).
    let said = ok(&["evaluate", &cal, &validation]);
    let judged: usize = said
        .lines()
        .find_map(|l| l.trim().split_once(" samples (")?.0.parse().ok())
        .unwrap_or_else(|| panic!("{said}"));
    assert!(said.contains("warm-up samples left out"), "{said}");
    let err = fails(&["evaluate", &cal, &validation, "--window", "40000"]);
    let most = err
        .split("give at most ")
        .nth(1)
        .and_then(|r| r.split(" s").next())
        .unwrap_or_else(|| panic!("{err}"));
    assert_eq!(most, judged.to_string(), "{err}");
    let out = ok(&["evaluate", &cal, &validation, "--window", most]);
    let row = out
        .lines()
        .find(|l| l.contains(&format!("max |{most}-s mean|")))
        .unwrap_or_else(|| panic!("{out}"));
    assert!(!row.contains("n/a"), "{row}");
    assert!(out.contains(", 1 windows"), "{out}");
    let above = (judged + 1).to_string();
    let err = fails(&["evaluate", &cal, &validation, "--window", &above]);
    assert!(err.contains(&format!("give at most {most} s")), "{err}");
}

// ------------------------------------------------------------------ 5. a unit's recipe

/// A unit's calibration given as `--recipe` for a log of one axis: the hint named
/// `--axis-recipe` for each axis, which a log of one axis refuses. It now also names
/// `--recipe FILE --recipe-axis AXIS`, and that command calibrates the log with that axis's
/// recipe (gx's spline K0 of 6 knots, not gy's default parabola); a file of one recipe is
/// refused with --recipe-axis, by name.
#[test]
fn a_units_recipe_on_a_log_of_one_axis_is_taken_by_the_command_the_hint_names() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (one_axis, unit) = (p(d, "one.json"), p(d, "unit.json"));
    std::fs::write(&one_axis, r#"{"k0": {"kind": "spline", "knots": 6}}"#).unwrap();
    ok(&[
        "calibrate",
        &crate::common::run::sample("imu3-calibration.csv"),
        "--axis-recipe",
        &format!("gx={one_axis}"),
        "-o",
        &unit,
    ]);
    let log = crate::common::run::sample("calibration.csv");
    let out = p(d, "cal.json");
    let err = fails(&["calibrate", &log, "--recipe", &unit, "-o", &out]);
    let named = format!("--recipe {unit} --recipe-axis gx");
    assert!(err.contains(&named), "{err}");
    let k0 = |axis: &str| -> serde_json::Value {
        ok(&[
            "calibrate",
            &log,
            "--recipe",
            &unit,
            "--recipe-axis",
            axis,
            "-o",
            &out,
        ]);
        let cal: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
        cal["calibration"]["recipe"]["k0"].clone()
    };
    let gx = k0("gx");
    assert_eq!(
        (gx["kind"].as_str(), gx["knots"].as_u64()),
        (Some("spline"), Some(6))
    );
    assert_eq!(k0("gy")["kind"].as_str(), Some("parabolic"));
    // An axis the unit lacks, and a file of one recipe, are refused by name.
    let err = fails(&[
        "calibrate",
        &log,
        "--recipe",
        &unit,
        "--recipe-axis",
        "gq",
        "-o",
        &out,
    ]);
    assert!(
        err.contains("--recipe-axis gq") && err.contains("gx, gy, gz"),
        "{err}"
    );
    let err = fails(&[
        "calibrate",
        &log,
        "--recipe",
        &one_axis,
        "--recipe-axis",
        "gx",
        "-o",
        &out,
    ]);
    assert!(
        err.contains("--recipe-axis gx") && err.contains("no unit's calibration"),
        "{err}"
    );
}
