//! How the chamber simulator writes its logs: a stand's dialect read back here by plain
//! splitting and by driftlab's reader (with the mapping a `gx_dps` log needs today) to the
//! same numbers, the raw temperature register converting back within a count, a run written
//! as it is simulated byte for byte the run collected and written, and the command on the
//! first line remaking the file.

use driftlab::log::ingest::{self, ColumnRef, RateUnit, ReadOptions, TimeUnit};
use driftlab::sim::{
    CsvDialect, HostJitter, Logging, Profile, RateNames, STAND_LINE, SimOptions, SimRun, profile,
    simulate_logged, write_simulated_csv,
};

use crate::common;
use common::sim::*;

/// The fast-ramps program cut after its first hold at 60 °C (about 1.4 h).
fn short(name: &str) -> Profile {
    let mut p = profile(name).unwrap();
    p.program.truncate(3);
    p
}

fn unit() -> Profile {
    short("fast-ramps")
        .with_axes(3)
        .unwrap()
        .with_accelerometers()
        .unwrap()
}

/// The run collected as `options` say it is logged, noise-only when they say so.
fn collected(p: &Profile, seed: u64, options: &SimOptions) -> SimRun {
    let run = simulate_logged(p, seed, &options.logging, &|_| {}).unwrap();
    if options.noise_only {
        run.noise_only()
    } else {
        run
    }
}

fn stand_options(rate_hz: f64) -> SimOptions {
    SimOptions {
        noise_only: false,
        logging: Logging {
            rate_hz: Some(rate_hz),
            ..Logging::default()
        },
        dialect: CsvDialect::stand(),
    }
}

/// Half a unit of the last decimal of deg/s written to 8 decimals, in °/h, and a little
/// more for the rounding of the conversion.
const DPS_HALF_STEP_DPH: f64 = 0.5e-8 * 3600.0 + 1e-9;

#[test]
fn the_stand_dialect_reads_back_to_the_same_numbers() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("imu.csv");
    let p = unit();
    let options = stand_options(10.0);
    let rows = write_simulated_csv(&p, 3, &options, &path, &|_| {}).unwrap();
    let run = collected(&p, 3, &options);
    assert_eq!(rows, run.len());

    // By plain splitting: the stand's line, the command, the header, ms and deg/s.
    let csv = Csv::read(&path, ';', true);
    assert_eq!(csv.comments[0], STAND_LINE);
    assert!(csv.comments[0].starts_with("stand: "));
    assert_eq!(
        csv.comments[1],
        "driftlab simulate --profile fast-ramps --seed 3 --axes 3 --accel --rate-hz 10 \
         --dialect stand"
    );
    let names = "time_ms;gx_dps;gy_dps;gz_dps;ax_g;ay_g;az_g;temp_c;temp_chamber_c";
    assert_eq!(csv.names.join(";"), names);
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(
        text.lines().nth(4).unwrap().starts_with("100;"),
        "time in ms"
    );
    for (i, ms) in csv.column("time_ms").iter().enumerate() {
        assert!((ms / 1000.0 - run.time_s[i]).abs() < 1e-9);
    }
    for (k, g) in ["gx_dps", "gy_dps", "gz_dps"].iter().enumerate() {
        for (i, v) in csv.column(g).iter().enumerate() {
            let want = run.axes[k].omega_dph[i];
            assert!(
                (v * 3600.0 - want).abs() <= DPS_HALF_STEP_DPH,
                "{g} row {i}"
            );
        }
    }
    for (k, a) in ["ax_g", "ay_g", "az_g"].iter().enumerate() {
        assert_eq!(csv.column(a), run.accelerometers[k].values_g);
    }
    assert_eq!(csv.column("temp_c"), run.temp_c);

    // By driftlab's reader, one axis at a time: it does not recognise `gx_dps` as a rate
    // unmapped yet, so the column and its unit are given.
    for (k, g) in ["gx_dps", "gy_dps", "gz_dps"].iter().enumerate() {
        let opts = ReadOptions {
            rate_col: Some(ColumnRef::Name(g.to_string())),
            rate_unit: Some(RateUnit::DegPerSec),
            ..ReadOptions::default()
        };
        let log = ingest::read_path(&path, &opts).unwrap();
        assert_eq!(log.info.delimiter, ';');
        assert!(log.info.decimal_comma);
        assert_eq!(log.len(), run.len());
        for i in 0..run.len() {
            assert!((log.time_s[i] - run.time_s[i]).abs() < 1e-9, "time row {i}");
            let want = run.axes[k].omega_dph[i];
            assert!(
                (log.omega_dph[i] - want).abs() <= DPS_HALF_STEP_DPH,
                "{g} row {i}"
            );
        }
        assert_eq!(log.temp_c, run.temp_c);
        assert_eq!(
            log.channel("az_g").unwrap().values,
            run.accelerometers[2].values_g
        );
        assert_eq!(
            log.channel("temp_chamber_c").unwrap().values.len(),
            run.len()
        );
    }
}

#[test]
fn a_single_axis_log_with_gx_dps_names_reads_back_with_its_mapping() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("gx.csv");
    let p = short("calibration");
    let options = SimOptions {
        dialect: CsvDialect {
            rate_names: RateNames::G,
            rate_unit: RateUnit::DegPerSec,
            ..CsvDialect::driftlab()
        },
        ..SimOptions::default()
    };
    write_simulated_csv(&p, 1, &options, &path, &|_| {}).unwrap();
    let run = collected(&p, 1, &options);
    let csv = Csv::read(&path, ',', false);
    assert_eq!(csv.names.join(","), "time_s,gx_dps,temp_c,temp_chamber_c");
    assert_eq!(
        csv.comments[0],
        "driftlab simulate --profile calibration --seed 1 --rate-names g --rate-unit dps"
    );
    let opts = ReadOptions {
        rate_col: Some(ColumnRef::Name("gx_dps".into())),
        rate_unit: Some(RateUnit::DegPerSec),
        ..ReadOptions::default()
    };
    let log = ingest::read_path(&path, &opts).unwrap();
    assert_eq!(log.time_s, run.time_s);
    assert_eq!(log.temp_c, run.temp_c);
    for i in 0..run.len() {
        assert!((log.omega_dph[i] - run.omega_dph[i]).abs() <= DPS_HALF_STEP_DPH);
    }
    // And in rad/s, tab-separated, time in ms: 10 decimals of rad/s.
    let options = SimOptions {
        dialect: CsvDialect {
            separator: '\t',
            time_unit: TimeUnit::Millis,
            rate_names: RateNames::Gyro,
            rate_unit: RateUnit::RadPerSec,
            ..CsvDialect::driftlab()
        },
        ..SimOptions::default()
    };
    write_simulated_csv(&p, 1, &options, &path, &|_| {}).unwrap();
    let csv = Csv::read(&path, '\t', false);
    assert_eq!(csv.names[1], "gyro_x_rad_s");
    let rad_dph = 180.0 / std::f64::consts::PI * 3600.0;
    for (i, v) in csv.column("gyro_x_rad_s").iter().enumerate() {
        assert!((v * rad_dph - run.omega_dph[i]).abs() <= 0.5e-10 * rad_dph + 1e-9);
    }
}

#[test]
fn the_raw_register_converts_back_to_the_real_temperature_within_a_count() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("raw.csv");
    let p = profile("calibration").unwrap();
    let options = SimOptions {
        dialect: CsvDialect {
            raw_temp_register: true,
            ..CsvDialect::driftlab()
        },
        ..SimOptions::default()
    };
    write_simulated_csv(&p, 2, &options, &path, &|_| {}).unwrap();
    let run = collected(&p, 2, &options);
    let csv = Csv::read(&path, ',', false);
    assert_eq!(
        csv.names.join(","),
        "time_s,omega_dph,temp_raw_int16,temp_C_est,temp_chamber_c"
    );
    let raw = csv.column("temp_raw_int16");
    let est = csv.column("temp_C_est");
    assert_eq!(est, run.temp_c);
    // The register's convention, written out here: T = counts / 340 + 36.53 °C.
    for (&r, &t) in raw.iter().zip(&est) {
        assert_eq!(r, r.round(), "an integer register");
        assert!((-32768.0..=32767.0).contains(&r));
        assert!(
            (r / 340.0 + 36.53 - t).abs() <= 1.0 / 340.0,
            "{r} counts vs {t} °C"
        );
    }
    // −50…+60 °C is −29 420…+7 980 counts.
    let (lo, hi) = (raw.iter().cloned().fold(f64::MAX, f64::min), p2p(&raw));
    assert!((lo + 29420.0).abs() <= 2.0, "lowest {lo}");
    assert!((hi - (29420.0 + 7980.0)).abs() <= 4.0, "span {hi}");
    // With the real temperature mapped, the reader gets the run's temperatures.
    let opts = ReadOptions {
        temp_col: Some(ColumnRef::Name("temp_C_est".into())),
        ..ReadOptions::default()
    };
    let log = ingest::read_path(&path, &opts).unwrap();
    assert_eq!(log.temp_c, run.temp_c);
    assert_eq!(log.time_s, run.time_s);
}

/// Option sets that between them use every logging and writing option.
fn option_sets() -> Vec<(Profile, SimOptions)> {
    let every = SimOptions {
        noise_only: true,
        logging: Logging {
            rate_hz: Some(10.0),
            gaps: vec!["600:300.5".parse().unwrap()],
            bursts: Some("20:60".parse().unwrap()),
            jitter: Some(HostJitter::default()),
        },
        dialect: CsvDialect {
            raw_temp_register: true,
            ..CsvDialect::stand()
        },
    };
    let laser = SimOptions {
        noise_only: false,
        logging: Logging {
            rate_hz: Some(2.0),
            bursts: Some("30:90".parse().unwrap()),
            ..Logging::default()
        },
        dialect: CsvDialect {
            separator: '\t',
            rate_names: RateNames::Gyro,
            rate_unit: RateUnit::RadPerSec,
            raw_temp_register: true,
            ..CsvDialect::driftlab()
        },
    };
    let odd_rate = SimOptions {
        noise_only: false,
        logging: Logging {
            rate_hz: Some(0.3),
            gaps: vec!["1000:2000".parse().unwrap()],
            ..Logging::default()
        },
        dialect: CsvDialect {
            rate_names: RateNames::W,
            rate_unit: RateUnit::DegPerSec,
            time_unit: TimeUnit::Millis,
            separator: ';',
            ..CsvDialect::driftlab()
        },
    };
    vec![
        (short("calibration"), SimOptions::default()),
        (unit(), every),
        (short("laser-gyro"), laser),
        (unit(), odd_rate),
    ]
}

#[test]
fn a_run_written_as_simulated_is_the_run_collected_and_written() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a.csv"), dir.path().join("b.csv"));
    for (p, options) in option_sets() {
        write_simulated_csv(&p, 5, &options, &a, &|_| {}).unwrap();
        collected(&p, 5, &options)
            .write_csv_as(&b, &options.dialect)
            .unwrap();
        let (x, y) = (std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
        assert!(x == y, "{}: {:?}", p.name, options);
    }
}

#[test]
fn noise_only_keeps_working_with_every_option() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("quiet.csv");
    let (p, options) = option_sets().swap_remove(1);
    write_simulated_csv(&p, 5, &options, &path, &|_| {}).unwrap();
    let full = simulate_logged(&p, 5, &options.logging, &|_| {}).unwrap();
    let csv = Csv::read(&path, ';', true);
    assert_eq!(csv.rows.len(), full.len());
    assert!(csv.comments[1].contains("--noise-only"));
    let stamps = full.stamp_s.as_ref().unwrap();
    for (i, ms) in csv.column("time_ms").iter().enumerate() {
        assert!((ms / 1000.0 - stamps[i]).abs() < 1e-9);
    }
    for (k, g) in ["gx_dps", "gy_dps", "gz_dps"].iter().enumerate() {
        for (i, v) in csv.column(g).iter().enumerate() {
            let noise = full.axes[k].noise_dph[i];
            assert!(
                (v * 3600.0 - noise).abs() <= DPS_HALF_STEP_DPH,
                "{g} row {i}"
            );
        }
    }
    assert_eq!(csv.column("temp_C_est"), full.temp_c);
    // Samples in bursts of 20 s every minute, none in the gap.
    for &t in &full.time_s {
        assert!(
            t % 60.0 < 20.0 - 1e-9 && !(600.0..900.5).contains(&t),
            "{t}"
        );
    }
}

#[test]
fn the_command_on_the_first_line_remakes_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let (lib, cli) = (dir.path().join("lib.csv"), dir.path().join("cli.csv"));
    for (p, options) in option_sets() {
        if !["calibration", "fast-ramps", "laser-gyro"].contains(&p.name.as_str()) {
            continue;
        }
        // The command names the built-in profile; these are shortened, so use whole ones.
        let whole = {
            let mut w = profile(&p.name).unwrap();
            w.axes.clone_from(&p.axes);
            w.accelerometers.clone_from(&p.accelerometers);
            w
        };
        write_simulated_csv(&whole, 9, &options, &lib, &|_| {}).unwrap();
        let text = std::fs::read_to_string(&lib).unwrap();
        let command = text
            .lines()
            .take_while(|l| l.starts_with('#'))
            .find_map(|l| l.strip_prefix("# driftlab "))
            .unwrap();
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_driftlab"))
            .args(command.split_whitespace())
            .arg("--out")
            .arg(&cli)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{command}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(std::fs::read(&cli).unwrap() == text.as_bytes(), "{command}");
    }
}

#[test]
fn a_dialect_that_cannot_be_read_back_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("x.csv");
    let p = short("calibration");
    for (dialect, word) in [
        (
            CsvDialect {
                decimal_comma: true,
                ..CsvDialect::driftlab()
            },
            "--decimal-mark",
        ),
        (
            CsvDialect {
                separator: '|',
                ..CsvDialect::driftlab()
            },
            "--separator",
        ),
        (
            CsvDialect {
                time_unit: TimeUnit::Hours,
                ..CsvDialect::driftlab()
            },
            "--time-unit",
        ),
    ] {
        let options = SimOptions {
            dialect,
            ..SimOptions::default()
        };
        let e = write_simulated_csv(&p, 1, &options, &path, &|_| {}).unwrap_err();
        assert!(e.to_string().contains(word), "{e}");
        assert!(!path.exists(), "nothing written");
    }
}
