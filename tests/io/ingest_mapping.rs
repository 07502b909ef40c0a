//! Reading test-stand logs: which column is time, rate and temperature, by name, by index or
//! by the header's words; sample-index time, a sample rate instead of a time column, several
//! temperatures and extra channels.

use driftlab::log::ingest::{ColumnRef, ReadOptions, TimeUnit};
use driftlab::log::{ColumnRole, ProblemKind};

use crate::common;
use common::ingest::*;

// ---------------------------------------------------------------------------------------------
// Mapping

#[test]
fn explicit_mapping_by_name_and_index() {
    let text = "a,b,c,d\n0,1,20,5\n1,2,21,6\n";
    let log = read_with(
        text,
        &ReadOptions {
            time_col: Some(ColumnRef::Name("A".into())),
            rate_col: Some(ColumnRef::Index(4)),
            temp_col: Some(ColumnRef::Name("c".into())),
            ..opts()
        },
    );
    close(&log.time_s, &[0.0, 1.0]);
    close(&log.omega_dph, &[5.0, 6.0]);
    close(&log.temp_c, &[20.0, 21.0]);
    assert_eq!(log.extra.len(), 1);
    assert_eq!(log.extra[0].name, "b");

    // A name matches without its unit.
    let log = read_with(
        "Time [ms],X [deg/s],Y\n0,1,20\n",
        &ReadOptions {
            rate_col: Some(ColumnRef::Name("x".into())),
            temp_col: Some(ColumnRef::Name("y".into())),
            ..opts()
        },
    );
    close(&log.omega_dph, &[3600.0]);

    // Explicit mapping beats names.
    let log = read_with(
        "time,omega,temp,temp2\n0,1,20,30\n",
        &ReadOptions {
            temp_col: Some(ColumnRef::Name("temp2".into())),
            ..opts()
        },
    );
    close(&log.temp_c, &[30.0]);
    assert_eq!(log.extra[0].name, "temp");
}

#[test]
fn unknown_mapping_lists_the_columns() {
    let e = fail(
        b"time,omega,temp\n0,1,2\n",
        &ReadOptions {
            rate_col: Some(ColumnRef::Name("gyro".into())),
            ..opts()
        },
    );
    assert!(e.message.contains("gyro"), "{e}");
    assert!(e.message.contains("\"time\", \"omega\", \"temp\""), "{e}");
    let e = fail(
        b"time,omega,temp\n0,1,2\n",
        &ReadOptions {
            temp_col: Some(ColumnRef::Index(7)),
            ..opts()
        },
    );
    assert!(
        e.message.contains('7') && e.message.contains("\"omega\""),
        "{e}"
    );
    let e = fail(
        b"time,omega,temp\n0,1,2\n",
        &ReadOptions {
            temp_col: Some(ColumnRef::Index(2)),
            rate_col: Some(ColumnRef::Index(2)),
            ..opts()
        },
    );
    assert!(e.message.contains("two roles"), "{e}");
}

#[test]
fn unrecognised_names_ask_for_a_mapping() {
    let e = fail(b"a,b,c\n0,1,2\n", &opts());
    assert!(e.message.contains("rate_col"), "{e}");
    let e = fail(b"time,omega,pressure\n0,1,2\n", &opts());
    assert!(e.message.contains("temp_col"), "{e}");
    let e = fail(b"omega,temp\n1,2\n", &opts());
    assert!(e.message.contains("sample_rate_hz"), "{e}");
}

#[test]
fn sample_index_time() {
    let text = "sample,omega,temp\n0,1,20\n1,2,20\n2,3,20\n10,4,20\n";
    let log = read_with(
        text,
        &ReadOptions {
            sample_rate_hz: Some(10.0),
            ..opts()
        },
    );
    close(&log.time_s, &[0.0, 0.1, 0.2, 1.0]);
    assert_eq!(unit_of(&log, ColumnRole::Time), "samples");
    let e = fail(text.as_bytes(), &opts());
    assert!(e.message.contains("sample_rate_hz"), "{e}");

    // A time column declared as a sample index.
    let log = read_with(
        "n,omega,temp\n0,1,20\n4,2,20\n",
        &ReadOptions {
            time_unit: Some(TimeUnit::Samples),
            sample_rate_hz: Some(4.0),
            ..opts()
        },
    );
    close(&log.time_s, &[0.0, 1.0]);
}

#[test]
fn no_time_column_with_a_sample_rate() {
    // Two columns without a header: rate and temperature.
    let o = ReadOptions {
        sample_rate_hz: Some(2.0),
        ..opts()
    };
    let log = read_with("1.5,20\n2.5,21\n,22\n3.5,23\n", &o);
    // Time counts every data row, the dropped one too.
    close(&log.time_s, &[0.0, 0.5, 1.5]);
    close(&log.omega_dph, &[1.5, 2.5, 3.5]);
    close(&log.temp_c, &[20.0, 21.0, 23.0]);
    let e = fail(b"1.5,20\n2.5,21\n", &opts());
    assert!(e.message.contains("sample_rate_hz"), "{e}");

    // With a header that has no time column.
    let log = read_with("omega,temp\n1,20\n2,20\n", &o);
    close(&log.time_s, &[0.0, 0.5]);
    assert!(log.info.columns.iter().all(|c| c.role != ColumnRole::Time));

    let e = fail(
        b"omega,temp\n1,20\n",
        &ReadOptions {
            sample_rate_hz: Some(-1.0),
            ..opts()
        },
    );
    assert!(e.message.contains("sample_rate_hz"), "{e}");
}

#[test]
fn several_temperatures_and_extra_channels() {
    let text = "time,T1,omega,T2 [K],laser_power [mW],status,piezo\n\
                0,20,1,300,5.5,OK,\n\
                1,21,2,301,5.6,OK,0.25\n";
    let log = read(text);
    // Of two temperature sensors, the one whose name states its unit is the calibration's.
    close(&log.temp_c, &[300.0 - 273.15, 301.0 - 273.15]);
    close(&log.omega_dph, &[1.0, 2.0]);
    let t1 = log.channel("T1").expect("T1 kept");
    close(&t1.values, &[20.0, 21.0]);
    assert_eq!(t1.unit, "°C");
    let p = log.channel("laser_power [mW]").expect("power kept");
    assert_eq!(p.unit, "mW");
    close(&p.values, &[5.5, 5.6]);
    let piezo = log.channel("piezo").expect("piezo kept");
    assert!(piezo.values[0].is_nan());
    assert_eq!(piezo.values[1], 0.25);
    assert!(log.channel("status").is_none());
    assert_eq!(role_of(&log, "status"), ColumnRole::Ignored);
    assert_eq!(role_of(&log, "T2 [K]"), ColumnRole::Temperature);
    assert_eq!(role_of(&log, "T1"), ColumnRole::Extra);
    assert_eq!(log.info.columns.len(), 7);
    assert!(log.info.problems.is_empty(), "{:?}", log.info.problems);
    for ch in &log.extra {
        assert_eq!(ch.values.len(), log.len());
    }
}

#[test]
fn skipped_extras_are_not_read_and_the_three_columns_are_the_same() {
    let text = "time,T1,omega,T2 [K],laser_power [mW],status,piezo\n\
                0,20,1,300,5.5,OK,\n\
                1,21,2,301,5.6,OK,0.25\n\
                2,22.5,-3e-2,302,oops,OK,1\n";
    let all = read(text);
    let only = read_with(
        text,
        &ReadOptions {
            skip_extras: true,
            ..opts()
        },
    );
    assert_eq!(all.extra.len(), 3);
    assert!(only.extra.is_empty(), "{:?}", only.extra);
    assert_eq!(only.time_s, all.time_s);
    assert_eq!(only.omega_dph, all.omega_dph);
    assert_eq!(only.temp_c, all.temp_c);
    for name in ["T1", "laser_power [mW]", "piezo", "status"] {
        assert_eq!(role_of(&only, name), ColumnRole::Ignored, "{name}");
    }
    assert_eq!(role_of(&only, "T2 [K]"), ColumnRole::Temperature);
    // The unreadable extra cell is not read, so not reported either.
    assert!(only.info.problems.is_empty(), "{:?}", only.info.problems);
    assert!(
        all.info
            .problems
            .iter()
            .any(|p| p.kind == ProblemKind::BadExtraValue)
    );
    // Not a setting of the file: recipes do not store it.
    let json = serde_json::to_string(&ReadOptions {
        skip_extras: true,
        ..opts()
    })
    .unwrap();
    assert!(!json.contains("skip"), "{json}");
}

#[test]
fn header_name_variants() {
    for (header, d, rate_factor) in [
        ("t,w,temp", ',', 1.0),
        ("sec,drift,temperature", ',', 1.0),
        ("timestamp,gyro,Temp [°C]", ',', 1.0),
        ("Time [s];Omega [deg/h];T, °C", ';', 1.0),
        ("time;omega_dph;t_c", ';', 1.0),
        ("TIME,RATE,TEMP", ',', 1.0),
        ("time,Rate [deg/s],temp", ',', 3600.0),
        ("Time (s)\tGyro (°/s)\tTemperature (°C)", '\t', 3600.0),
    ] {
        let text = format!("{header}\n0{d}2{d}20\n1{d}3{d}21\n");
        let log = read(&text);
        close(&log.time_s, &[0.0, 1.0]);
        close(&log.omega_dph, &[2.0 * rate_factor, 3.0 * rate_factor]);
        close(&log.temp_c, &[20.0, 21.0]);
    }
}
