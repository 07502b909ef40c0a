//! Reading test-stand logs: every dialect the stands write, units, mappings, and every kind of
//! broken file, checked against values written into the test itself.

use driftlab::Log;
use driftlab::ingest::{
    ColumnRef, IngestError, RateUnit, ReadOptions, TimeUnit, parse_delimiter, preview,
    preview_bytes, read_bytes, read_path, read_path_with_progress,
};
use driftlab::log::{ColumnRole, ProblemKind};
use std::f64::consts::PI;
use std::io::Write;

fn read(text: &str) -> Log {
    read_with(text, &ReadOptions::default())
}

fn read_with(text: &str, opts: &ReadOptions) -> Log {
    match read_bytes("t.csv", text.as_bytes(), opts) {
        Ok(log) => log,
        Err(e) => panic!("read failed: {e}\n--- input ---\n{text}"),
    }
}

fn fail(text: &[u8], opts: &ReadOptions) -> IngestError {
    match read_bytes("t.csv", text, opts) {
        Ok(log) => panic!(
            "expected an error, read {} rows\n--- input ---\n{}",
            log.len(),
            String::from_utf8_lossy(text)
        ),
        Err(e) => e,
    }
}

fn close(a: &[f64], b: &[f64]) {
    assert_eq!(a.len(), b.len(), "{a:?} vs {b:?}");
    for (x, y) in a.iter().zip(b) {
        assert!(
            (x - y).abs() <= 1e-9 * (1.0 + y.abs()),
            "{a:?} vs {b:?} ({x} != {y})"
        );
    }
}

fn role_of(log: &Log, name: &str) -> ColumnRole {
    log.info
        .columns
        .iter()
        .find(|c| c.name == name)
        .map(|c| c.role)
        .unwrap_or_else(|| panic!("no column {name} in {:?}", log.info.columns))
}

fn unit_of(log: &Log, role: ColumnRole) -> String {
    log.info
        .columns
        .iter()
        .find(|c| c.role == role)
        .map(|c| c.unit.clone())
        .unwrap_or_default()
}

fn opts() -> ReadOptions {
    ReadOptions::default()
}

// ---------------------------------------------------------------------------------------------
// Dialects

#[test]
fn comma_with_header() {
    let log = read("time_s,omega_dph,temp_c\n0,0.5,20\n1,0.25,20.5\n2,-1e-3,21\n");
    close(&log.time_s, &[0.0, 1.0, 2.0]);
    close(&log.omega_dph, &[0.5, 0.25, -0.001]);
    close(&log.temp_c, &[20.0, 20.5, 21.0]);
    assert_eq!(log.info.delimiter, ',');
    assert!(log.info.has_header);
    assert!(!log.info.decimal_comma);
    assert_eq!(log.info.rows_read, 3);
    assert!(log.info.problems.is_empty(), "{:?}", log.info.problems);
    assert_eq!(log.source, "t.csv");
    assert_eq!(role_of(&log, "time_s"), ColumnRole::Time);
    assert_eq!(role_of(&log, "omega_dph"), ColumnRole::Rate);
    assert_eq!(role_of(&log, "temp_c"), ColumnRole::Temperature);
    assert_eq!(unit_of(&log, ColumnRole::Rate), "deg/h");
    assert_eq!(unit_of(&log, ColumnRole::Time), "s");
    assert_eq!(unit_of(&log, ColumnRole::Temperature), "°C");
}

#[test]
fn semicolon_with_decimal_comma() {
    let log = read("Time;Omega;Temp\n0;1,234;20,5\n1;-2,5;20,75\n2;3;21\n");
    assert_eq!(log.info.delimiter, ';');
    assert!(log.info.decimal_comma);
    close(&log.time_s, &[0.0, 1.0, 2.0]);
    close(&log.omega_dph, &[1.234, -2.5, 3.0]);
    close(&log.temp_c, &[20.5, 20.75, 21.0]);
}

#[test]
fn semicolon_with_decimal_point() {
    let log = read("t;w;T1\n0.5;1.5;20.5\n1.5;2.5;21.5\n");
    assert_eq!(log.info.delimiter, ';');
    assert!(!log.info.decimal_comma);
    close(&log.time_s, &[0.5, 1.5]);
    close(&log.omega_dph, &[1.5, 2.5]);
    close(&log.temp_c, &[20.5, 21.5]);
}

#[test]
fn tab_separated() {
    let log = read("time\trate\ttemp\n0\t1.5\t20\n1\t2.5\t20.1\n");
    assert_eq!(log.info.delimiter, '\t');
    close(&log.omega_dph, &[1.5, 2.5]);
    close(&log.temp_c, &[20.0, 20.1]);
}

#[test]
fn tab_separated_with_decimal_comma() {
    let log = read("time\trate\ttemp\n0\t1,5\t20\n1\t2,5\t20,1\n");
    assert_eq!(log.info.delimiter, '\t');
    assert!(log.info.decimal_comma);
    close(&log.omega_dph, &[1.5, 2.5]);
    close(&log.temp_c, &[20.0, 20.1]);
}

#[test]
fn whitespace_aligned_columns_with_spaced_names() {
    let text = "  Time [s]    Rate [deg/h]    Temp [°C]\n\
                      0.0          1.5           20.0\n\
                      1.0         -2.5           20.25   \n\
                      2.0          3.0           20.5\n";
    let log = read(text);
    assert_eq!(log.info.delimiter, ' ');
    close(&log.time_s, &[0.0, 1.0, 2.0]);
    close(&log.omega_dph, &[1.5, -2.5, 3.0]);
    close(&log.temp_c, &[20.0, 20.25, 20.5]);
    assert_eq!(role_of(&log, "Rate [deg/h]"), ColumnRole::Rate);
}

#[test]
fn whitespace_with_decimal_comma() {
    let log = read("0 1,5 20,5\n1 2,5 21,5\n2 3,5 22,5\n");
    assert_eq!(log.info.delimiter, ' ');
    assert!(log.info.decimal_comma);
    close(&log.time_s, &[0.0, 1.0, 2.0]);
    close(&log.omega_dph, &[1.5, 2.5, 3.5]);
    close(&log.temp_c, &[20.5, 21.5, 22.5]);
}

#[test]
fn no_header_means_time_rate_temperature() {
    let log = read("0,1.5,20\n1,2.5,21\n2,3.5,22\n");
    assert!(!log.info.has_header);
    close(&log.time_s, &[0.0, 1.0, 2.0]);
    close(&log.omega_dph, &[1.5, 2.5, 3.5]);
    close(&log.temp_c, &[20.0, 21.0, 22.0]);
    let names: Vec<&str> = log.info.columns.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["col1", "col2", "col3"]);
}

#[test]
fn no_header_extra_columns_are_kept() {
    let log = read("0,1.5,20,7\n1,2.5,21,8\n");
    assert_eq!(log.extra.len(), 1);
    assert_eq!(log.extra[0].name, "col4");
    close(&log.extra[0].values, &[7.0, 8.0]);
}

#[test]
fn forced_header_and_no_header() {
    // A numeric first line taken as a header when told so.
    let log = read_with(
        "1,2,3\n0,1.5,20\n1,2.5,21\n",
        &ReadOptions {
            has_header: Some(true),
            time_col: Some(ColumnRef::Index(1)),
            rate_col: Some(ColumnRef::Index(2)),
            temp_col: Some(ColumnRef::Index(3)),
            ..opts()
        },
    );
    assert!(log.info.has_header);
    close(&log.time_s, &[0.0, 1.0]);
    // A text first line read as data when told so is an error at line 1, column 1.
    let e = fail(
        b"time,omega,temp\n0,1,2\n",
        &ReadOptions {
            has_header: Some(false),
            ..opts()
        },
    );
    assert_eq!((e.line, e.column), (1, 1), "{e}");
}

#[test]
fn explicit_dialect_options() {
    let log = read_with(
        "0|1,5|20\n1|2,5|21\n",
        &ReadOptions {
            delimiter: Some(b'|'),
            decimal_comma: Some(true),
            ..opts()
        },
    );
    assert_eq!(log.info.delimiter, '|');
    close(&log.omega_dph, &[1.5, 2.5]);
}

#[test]
fn comments_and_blank_lines_anywhere() {
    let text = "# stand 4, gyro SN 1234\n\
                # started 2024-03-01\n\
                \n\
                time,omega,temp\n\
                # chamber door closed\n\
                0,1,20\n\
                \n\
                   # indented comment\n\
                1,2,21\n\
                2,3,22\n\
                # end\n";
    let log = read(text);
    close(&log.time_s, &[0.0, 1.0, 2.0]);
    close(&log.omega_dph, &[1.0, 2.0, 3.0]);
    assert_eq!(log.info.rows_read, 3);
    // Line numbers count every physical line, comments included.
    let bad = text.replace("2,3,22", "2,x,22");
    let e = fail(bad.as_bytes(), &opts());
    assert_eq!((e.line, e.column), (10, 2), "{e}");
}

#[test]
fn bom_and_crlf() {
    let log = read("\u{feff}time,omega,temp\r\n0,1.5,20\r\n1,2.5,21\r\n");
    assert_eq!(log.info.columns[0].name, "time");
    assert_eq!(role_of(&log, "time"), ColumnRole::Time);
    close(&log.time_s, &[0.0, 1.0]);
    close(&log.temp_c, &[20.0, 21.0]);
    // Without a header too, and with a missing final line end.
    let log = read("\u{feff}0;1,5;20\r\n1;2,5;21");
    close(&log.omega_dph, &[1.5, 2.5]);
    close(&log.temp_c, &[20.0, 21.0]);
}

#[test]
fn quoted_fields() {
    let log = read("\"time\",\"omega\",\"temp\"\n\"0\",\"1,5\",\"20,25\"\n\"1\",\"2,5\",\"21\"\n");
    assert_eq!(log.info.delimiter, ',');
    assert!(log.info.decimal_comma);
    close(&log.omega_dph, &[1.5, 2.5]);
    close(&log.temp_c, &[20.25, 21.0]);
    // Quoted header with a comma inside a name, plain numbers.
    let log = read(
        "\"Time, s\",\"Rate, deg/s\",\"Temp, °C\",note\n0,1,20,\"a, b\"\n1,2,21,\"c \"\"d\"\"\"\n",
    );
    close(&log.omega_dph, &[3600.0, 7200.0]);
    assert_eq!(role_of(&log, "note"), ColumnRole::Ignored);
}

#[test]
fn quoted_field_spanning_lines_keeps_line_numbers() {
    let text = "time,omega,temp,note\n\
                0,1,20,\"first\n\
                second\"\n\
                1,2,21,ok\n\
                2,3,22,\"x\"\n\
                3,zz,23,\n";
    let e = fail(text.as_bytes(), &opts());
    assert_eq!((e.line, e.column), (6, 2), "{e}");
    let good = text.replace("zz", "4");
    let log = read(&good);
    close(&log.time_s, &[0.0, 1.0, 2.0, 3.0]);
    close(&log.omega_dph, &[1.0, 2.0, 3.0, 4.0]);
}

// ---------------------------------------------------------------------------------------------
// Units

#[test]
fn rate_units_from_headers() {
    let log = read("time,Rate (deg/s),temp\n0,1,20\n1,-0.5,20\n");
    close(&log.omega_dph, &[3600.0, -1800.0]);
    assert_eq!(unit_of(&log, ColumnRole::Rate), "deg/s");

    let log = read("time,gyro_x_rad_s,temp\n0,1,20\n1,0.001,20\n");
    let k = 180.0 / PI * 3600.0;
    close(&log.omega_dph, &[k, 0.001 * k]);
    assert_eq!(unit_of(&log, ColumnRole::Rate), "rad/s");

    let log = read("time,rate_dps,temp\n0,2,20\n");
    close(&log.omega_dph, &[7200.0]);

    let log = read("time;Rate [°/h];temp\n0;2,5;20\n");
    close(&log.omega_dph, &[2.5]);
    assert_eq!(unit_of(&log, ColumnRole::Rate), "deg/h");
}

#[test]
fn time_units_from_headers() {
    let log = read("time_ms,omega,temp\n0,1,20\n1500,1,20\n3000,1,20\n");
    close(&log.time_s, &[0.0, 1.5, 3.0]);
    assert_eq!(unit_of(&log, ColumnRole::Time), "ms");

    let log = read("Time [ms],omega,temp\n250,1,20\n500,1,20\n");
    close(&log.time_s, &[0.25, 0.5]);

    let log = read("t [min],omega,temp\n0,1,20\n1.5,1,20\n");
    close(&log.time_s, &[0.0, 90.0]);
    assert_eq!(unit_of(&log, ColumnRole::Time), "min");

    let log = read("t_h,omega,temp\n0,1,20\n2,1,20\n");
    close(&log.time_s, &[0.0, 7200.0]);
}

#[test]
fn temperature_units_from_headers() {
    let log = read("time,omega,Temp [K]\n0,1,293.15\n1,1,300\n");
    close(&log.temp_c, &[20.0, 26.85]);
    assert_eq!(unit_of(&log, ColumnRole::Temperature), "K");

    let log = read("time,omega,Temp [°F]\n0,1,212\n1,1,32\n");
    close(&log.temp_c, &[100.0, 0.0]);

    let log = read("time,omega,Temp [°C]\n0,1,21.5\n");
    close(&log.temp_c, &[21.5]);
    assert_eq!(unit_of(&log, ColumnRole::Temperature), "°C");
}

#[test]
fn unit_options_override_headers() {
    let log = read_with(
        "time_ms,omega_dph,temp\n0,1,20\n2,2,20\n",
        &ReadOptions {
            rate_unit: Some(RateUnit::RadPerSec),
            time_unit: Some(TimeUnit::Seconds),
            ..opts()
        },
    );
    close(&log.time_s, &[0.0, 2.0]);
    let k = 180.0 / PI * 3600.0;
    close(&log.omega_dph, &[k, 2.0 * k]);
    assert_eq!(unit_of(&log, ColumnRole::Rate), "rad/s");
    assert_eq!(unit_of(&log, ColumnRole::Time), "s");

    let log = read_with(
        "0,1,20\n1,2,20\n",
        &ReadOptions {
            rate_unit: Some(RateUnit::DegPerSec),
            time_unit: Some(TimeUnit::Minutes),
            ..opts()
        },
    );
    close(&log.time_s, &[0.0, 60.0]);
    close(&log.omega_dph, &[3600.0, 7200.0]);
}

#[test]
fn unit_parsing_and_display() {
    for (s, u) in [
        ("dph", RateUnit::DegPerHour),
        ("deg/h", RateUnit::DegPerHour),
        ("°/h", RateUnit::DegPerHour),
        ("dps", RateUnit::DegPerSec),
        ("deg/s", RateUnit::DegPerSec),
        ("rad/s", RateUnit::RadPerSec),
        ("rps", RateUnit::RadPerSec),
    ] {
        assert_eq!(s.parse::<RateUnit>(), Ok(u), "{s}");
        assert_eq!(u.to_string().parse::<RateUnit>(), Ok(u));
    }
    assert!("furlong".parse::<RateUnit>().is_err());
    assert_eq!(RateUnit::DegPerSec.to_dph_factor(), 3600.0);
    assert!((RateUnit::RadPerSec.to_dph_factor() - 180.0 / PI * 3600.0).abs() < 1e-6);
    for (s, u) in [
        ("s", TimeUnit::Seconds),
        ("ms", TimeUnit::Millis),
        ("min", TimeUnit::Minutes),
        ("h", TimeUnit::Hours),
        ("samples", TimeUnit::Samples),
    ] {
        assert_eq!(s.parse::<TimeUnit>(), Ok(u), "{s}");
        assert_eq!(u.to_string(), s);
    }
    assert_eq!("3".parse::<ColumnRef>(), Ok(ColumnRef::Index(3)));
    assert_eq!(
        "omega".parse::<ColumnRef>(),
        Ok(ColumnRef::Name("omega".into()))
    );
    assert_eq!(parse_delimiter("tab"), Ok(b'\t'));
    assert_eq!(parse_delimiter(";"), Ok(b';'));
    assert_eq!(parse_delimiter("space"), Ok(b' '));
}

#[test]
fn options_round_trip_through_json() {
    let o = ReadOptions {
        time_col: Some(ColumnRef::Name("t".into())),
        rate_col: Some(ColumnRef::Index(2)),
        temp_col: None,
        rate_unit: Some(RateUnit::DegPerSec),
        time_unit: Some(TimeUnit::Samples),
        sample_rate_hz: Some(100.0),
        delimiter: Some(b'\t'),
        decimal_comma: Some(true),
        has_header: Some(false),
        skip_extras: false,
    };
    let json = serde_json::to_string(&o).unwrap();
    assert!(json.contains("\"deg/s\""), "{json}");
    let back: ReadOptions = serde_json::from_str(&json).unwrap();
    assert_eq!(back, o);
    let parsed: ReadOptions =
        serde_json::from_str(r#"{"rate_col": "omega", "rate_unit": "rad/s", "delimiter": ";"}"#)
            .unwrap();
    assert_eq!(parsed.rate_col, Some(ColumnRef::Name("omega".into())));
    assert_eq!(parsed.rate_unit, Some(RateUnit::RadPerSec));
    assert_eq!(parsed.delimiter, Some(b';'));
    assert!(serde_json::from_str::<ReadOptions>(r#"{"rate_unit": "furlong"}"#).is_err());
}

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
    close(&log.temp_c, &[20.0, 21.0]);
    close(&log.omega_dph, &[1.0, 2.0]);
    let t2 = log.channel("T2 [K]").expect("T2 kept");
    close(&t2.values, &[300.0 - 273.15, 301.0 - 273.15]);
    assert_eq!(t2.unit, "°C");
    let p = log.channel("laser_power [mW]").expect("power kept");
    assert_eq!(p.unit, "mW");
    close(&p.values, &[5.5, 5.6]);
    let piezo = log.channel("piezo").expect("piezo kept");
    assert!(piezo.values[0].is_nan());
    assert_eq!(piezo.values[1], 0.25);
    assert!(log.channel("status").is_none());
    assert_eq!(role_of(&log, "status"), ColumnRole::Ignored);
    assert_eq!(role_of(&log, "T1"), ColumnRole::Temperature);
    assert_eq!(role_of(&log, "T2 [K]"), ColumnRole::Extra);
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
    for name in ["T2 [K]", "laser_power [mW]", "piezo", "status"] {
        assert_eq!(role_of(&only, name), ColumnRole::Ignored, "{name}");
    }
    assert_eq!(role_of(&only, "T1"), ColumnRole::Temperature);
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

// ---------------------------------------------------------------------------------------------
// Problems and errors

#[test]
fn bad_cell_is_an_error_with_file_line_and_column() {
    let mut text = String::from("time,omega_dph,temp\n");
    for i in 0..820 {
        let omega = if i == 810 {
            "1.2.3".to_string()
        } else {
            format!("{}", i as f64 * 0.5)
        };
        text += &format!("{i},{omega},20\n");
    }
    let e = match read_bytes("run7.csv", text.as_bytes(), &opts()) {
        Err(e) => e,
        Ok(_) => panic!("expected an error"),
    };
    assert_eq!(e.file, "run7.csv");
    assert_eq!(e.line, 812);
    assert_eq!(e.column, 2);
    assert_eq!(
        e.to_string(),
        "run7.csv:812:2: cannot read \"1.2.3\" as a number (column \"omega_dph\")"
    );
}

#[test]
fn bad_cells_in_every_used_column() {
    let e = fail(b"time;omega;temp\n0;1;2\n1;2;2,5,5\n", &opts());
    assert_eq!((e.line, e.column), (3, 3), "{e}");
    let e = fail(b"time,omega,temp\n0,1,2\nabc,2,2\n", &opts());
    assert_eq!((e.line, e.column), (3, 1), "{e}");
    assert!(e.message.contains("\"abc\""), "{e}");
    // Decimal comma in a comma file without quotes: the cell is split, the row is ragged or
    // wrong, but never silently read.
    let e = fail(b"time;omega;temp\n0;1;20\n1;0x10;20\n", &opts());
    assert_eq!((e.line, e.column), (3, 2), "{e}");
}

#[test]
fn blank_and_nan_cells_drop_the_row() {
    let text =
        "time,omega,temp,extra\n0,1,20,1\n1,,20,1\n2,nan,20,1\n3,4,NaN,1\n4,5,20,\n5,6,20,1\n";
    let log = read(text);
    close(&log.time_s, &[0.0, 4.0, 5.0]);
    close(&log.omega_dph, &[1.0, 5.0, 6.0]);
    assert_eq!(log.info.rows_read, 6);
    let miss: Vec<_> = log
        .info
        .problems
        .iter()
        .filter(|p| p.kind == ProblemKind::MissingValue)
        .collect();
    assert_eq!(miss.len(), 2, "{:?}", log.info.problems);
    assert_eq!(
        (miss[0].line, miss[0].count, miss[0].column),
        (3, 2, Some(2))
    );
    assert_eq!(
        (miss[1].line, miss[1].count, miss[1].column),
        (5, 1, Some(3))
    );
    // Blanks in extras are NaN, no problem reported.
    assert!(log.extra[0].values[1].is_nan());
}

#[test]
fn time_backwards_and_repeated_rows_are_dropped() {
    let text = "time,omega,temp\n0,0,20\n1,1,20\n2,2,20\n2,99,20\n3,3,20\n1.5,99,20\n4,4,20\n3.5,99,20\n5,5,20\n";
    let log = read(text);
    close(&log.time_s, &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
    close(&log.omega_dph, &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
    assert_eq!(log.info.rows_read, 9);
    let p = |k| log.info.problems.iter().find(|p| p.kind == k).cloned();
    let rep = p(ProblemKind::TimeRepeated).expect("repeat reported");
    assert_eq!((rep.line, rep.count, rep.column), (5, 1, Some(1)));
    let back = p(ProblemKind::TimeBackwards).expect("backwards reported");
    assert_eq!((back.line, back.count), (7, 2));
    assert!(p(ProblemKind::Gap).is_none());
}

#[test]
fn gaps_are_reported_and_kept() {
    let mut text = String::from("# header follows\ntime,omega,temp\n");
    let mut times = Vec::new();
    let mut t = 0.0;
    for i in 0..50 {
        if i == 20 {
            t += 10.0;
        } else if i == 40 {
            t += 3.0;
        } else {
            t += 1.0;
        }
        times.push(t);
        text += &format!("{t},1,20\n");
    }
    let log = read(&text);
    close(&log.time_s, &times);
    let gap = log
        .info
        .problems
        .iter()
        .find(|p| p.kind == ProblemKind::Gap)
        .expect("gap reported");
    // Row i is on line i + 3.
    assert_eq!((gap.line, gap.count), (23, 2), "{gap:?}");
}

#[test]
fn ragged_rows() {
    // Too few fields for a used column: an error at that line.
    let e = fail(b"time,omega,temp\n0,1,20\n1,2\n2,3,20\n", &opts());
    assert_eq!(e.line, 3, "{e}");
    assert!(e.message.contains("temp"), "{e}");
    // Extra trailing fields are fine.
    let log = read("time,omega,temp\n0,1,20,9,9\n1,2,21,\n");
    close(&log.temp_c, &[20.0, 21.0]);
    // Too few fields for an extra column: NaN and a problem.
    let log = read("time,omega,temp,aux\n0,1,20,5\n1,2,21\n2,3,22,6\n");
    close(&log.time_s, &[0.0, 1.0, 2.0]);
    assert!(log.extra[0].values[1].is_nan());
    let r = log
        .info
        .problems
        .iter()
        .find(|p| p.kind == ProblemKind::RaggedRow)
        .expect("ragged reported");
    assert_eq!((r.line, r.count), (3, 1));
}

#[test]
fn unreadable_extra_cells_are_nan_and_reported() {
    let log = read("time,omega,temp,aux\n0,1,20,5\n1,2,21,6\n2,3,22,oops\n");
    assert!(log.extra[0].values[2].is_nan());
    assert!(
        log.info
            .problems
            .iter()
            .any(|p| p.line == 4 && p.column == Some(4) && p.kind == ProblemKind::BadExtraValue),
        "{:?}",
        log.info.problems
    );
}

#[test]
fn broken_files_give_clear_errors() {
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        ("empty", vec![], "empty"),
        ("bom only", b"\xEF\xBB\xBF".to_vec(), "empty"),
        ("comments only", b"# a\n\n# b\n".to_vec(), "no data"),
        ("header only", b"time,omega,temp\n".to_vec(), "no data rows"),
        ("one column", b"1\n2\n3\n".to_vec(), "one column"),
        ("one named column", b"omega\n1\n2\n".to_vec(), "one column"),
        ("binary", b"\x00\x01\x02\xff\xfe\x00abc".to_vec(), "binary"),
        (
            "invalid utf-8 header",
            b"time,\xff\xfe,temp\n0,1,2\n".to_vec(),
            "UTF-8",
        ),
        (
            "invalid utf-8 cell",
            b"time,omega,temp\n0,1,\xff\n".to_vec(),
            "cannot read",
        ),
        (
            "all rows blank",
            b"time,omega,temp\n0,,1\n1,,2\n".to_vec(),
            "none of the 2",
        ),
        (
            "lone CRs",
            b"time,omega,temp\r0,1,2\r1,2,3\r".to_vec(),
            "CR",
        ),
    ];
    for (what, bytes, needle) in cases {
        let e = match read_bytes("t.csv", &bytes, &opts()) {
            Err(e) => e,
            Ok(l) => panic!("{what}: expected an error, got {} rows", l.len()),
        };
        assert!(e.message.contains(needle), "{what}: {e}");
        assert_eq!(e.file, "t.csv");
    }
}

#[test]
fn huge_lines_are_refused() {
    let mut big = b"time,omega,temp\n0,1,20\n".to_vec();
    big.extend(std::iter::repeat_n(b'7', 9 << 20));
    big.extend_from_slice(b"\n1,2,3\n");
    let e = fail(&big, &opts());
    assert_eq!(e.line, 3, "{e}");
    assert!(e.message.contains("longer"), "{e}");
    let e = fail(&vec![b'x'; 6 << 20], &opts());
    assert!(e.message.contains("longer"), "{e}");
}

#[test]
fn error_display_leaves_out_unknown_positions() {
    let e = IngestError {
        file: "a.csv".into(),
        line: 0,
        column: 0,
        message: "cancelled".into(),
    };
    assert_eq!(e.to_string(), "a.csv: cancelled");
    let e = IngestError { line: 4, ..e };
    assert_eq!(e.to_string(), "a.csv:4: cancelled");
}

// ---------------------------------------------------------------------------------------------
// Files, blocks, progress, preview

/// A log large enough for several parallel blocks, with known values and some faults.
fn big_text(rows: usize) -> (String, Vec<f64>, Vec<f64>) {
    let mut s = String::from("# long run\ntime_s,omega_dph,temp_c,aux\n");
    let (mut t, mut w) = (Vec::new(), Vec::new());
    for i in 0..rows {
        let ti = i as f64 * 0.5;
        let wi = ((i * 7919) % 1000) as f64 * 0.001 - 0.5;
        s += &format!("{ti},{wi},{:.4},{}\n", 20.0 + i as f64 * 1e-4, i % 13);
        t.push(ti);
        w.push(wi);
    }
    (s, t, w)
}

#[test]
fn large_file_is_read_exactly_across_blocks() {
    let rows = 400_000;
    let (text, t, w) = big_text(rows);
    assert!(text.len() > 12 << 20, "several blocks");
    let log = read(&text);
    assert_eq!(log.len(), rows);
    assert_eq!(log.time_s, t);
    assert_eq!(log.omega_dph, w);
    assert_eq!(log.extra.len(), 1);
    assert_eq!(log.extra[0].values[rows - 1], ((rows - 1) % 13) as f64);
    assert!(log.info.problems.is_empty());

    // A fault deep in the file is reported at its exact line.
    let line_of_row = |r: usize| r + 3;
    let row = 333_333;
    let needle = format!("\n{},", t[row]);
    let pos = text.find(&needle).expect("row present") + 1;
    let mut bad = text.clone();
    bad.replace_range(pos..pos + needle.len() - 2, "1e");
    let e = fail(bad.as_bytes(), &opts());
    assert_eq!((e.line, e.column), (line_of_row(row), 1), "{e}");

    // Dropped rows deep in the file too; three in a row leave a gap.
    let mut holes = text.clone();
    let row = 250_001;
    for r in row..row + 3 {
        let needle = format!("\n{},{},", t[r], w[r]);
        let pos = holes.find(&needle).expect("row present");
        holes.replace_range(pos + 1..pos + needle.len() - 1, &format!("{},", t[r]));
    }
    let log = read(&holes);
    assert_eq!(log.len(), rows - 3);
    let p = &log.info.problems;
    assert_eq!(p.len(), 2, "{p:?}");
    assert_eq!(
        (p[0].kind, p[0].line, p[0].count),
        (ProblemKind::MissingValue, line_of_row(row), 3)
    );
    assert_eq!(
        (p[1].kind, p[1].line, p[1].count),
        (ProblemKind::Gap, line_of_row(row + 3), 1)
    );
}

#[test]
fn files_progress_and_cancel() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.csv");
    let (text, t, _) = big_text(300_000);
    std::fs::File::create(&path)
        .unwrap()
        .write_all(text.as_bytes())
        .unwrap();
    let log = read_path(&path, &opts()).unwrap();
    assert_eq!(log.time_s, t);
    assert_eq!(log.source, path.display().to_string());

    let seen = std::sync::Mutex::new(Vec::new());
    let log = read_path_with_progress(&path, &opts(), &|f| {
        seen.lock().unwrap().push(f);
        true
    })
    .unwrap();
    assert_eq!(log.len(), t.len());
    let seen = seen.into_inner().unwrap();
    assert!(seen.len() >= 2, "{seen:?}");
    assert!(seen.windows(2).all(|w| w[0] <= w[1]), "{seen:?}");
    assert_eq!(seen.last(), Some(&1.0));

    let calls = std::sync::atomic::AtomicUsize::new(0);
    let e = read_path_with_progress(&path, &opts(), &|_| {
        calls.fetch_add(1, std::sync::atomic::Ordering::Relaxed) < 1
    })
    .unwrap_err();
    assert_eq!(e.message, "cancelled");

    let e = read_path(&dir.path().join("missing.csv"), &opts()).unwrap_err();
    assert!(e.message.contains("cannot open"), "{e}");
    let e = read_path(dir.path(), &opts()).unwrap_err();
    assert!(e.message.contains("directory"), "{e}");
}

#[test]
fn preview_shows_dialect_rows_and_mapping() {
    let text =
        "# stand 2\nTime [ms];Rate [deg/s];Temp [°C];note\n0;1,5;20;a\n10;2,5;21;b\n20;3,5;22;c\n";
    let p = preview_bytes("p.csv", text.as_bytes(), &opts(), 2).unwrap();
    assert_eq!(p.delimiter, ';');
    assert!(p.decimal_comma);
    assert!(p.has_header);
    assert_eq!(p.header_line, 2);
    assert_eq!(p.names, ["Time [ms]", "Rate [deg/s]", "Temp [°C]", "note"]);
    assert_eq!(p.rows, [["0", "1,5", "20", "a"], ["10", "2,5", "21", "b"]]);
    assert_eq!(p.row_lines, [3, 4]);
    let roles: Vec<_> = p
        .columns
        .iter()
        .map(|c| (c.role, c.unit.as_str()))
        .collect();
    assert_eq!(
        roles,
        [
            (ColumnRole::Time, "ms"),
            (ColumnRole::Rate, "deg/s"),
            (ColumnRole::Temperature, "°C"),
            (ColumnRole::Ignored, "")
        ]
    );
    assert!(p.mapping_error.is_none());

    // A mapping that cannot be made still previews.
    let p = preview_bytes("p.csv", b"a,b\n1,2\n", &opts(), 10).unwrap();
    assert!(p.mapping_error.is_some());
    assert_eq!(p.rows.len(), 1);

    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("p.csv");
    std::fs::write(&path, text).unwrap();
    let q = preview(&path, &opts(), 2).unwrap();
    assert_eq!(q.rows.len(), 2);
}

// ---------------------------------------------------------------------------------------------
// Robustness

struct XorShift(u64);

impl XorShift {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
}

/// Options of every kind, some of them nonsensical, chosen by the generator.
fn random_options(rng: &mut XorShift) -> ReadOptions {
    let pick = |rng: &mut XorShift, n: u64| rng.next() % n;
    let col = |rng: &mut XorShift| match rng.next() % 5 {
        0 => Some(ColumnRef::Index((rng.next() % 5) as usize)),
        1 => Some(ColumnRef::Name(
            ["time", "omega", "temp", "x", ""][(rng.next() % 5) as usize].into(),
        )),
        _ => None,
    };
    ReadOptions {
        time_col: col(rng),
        rate_col: col(rng),
        temp_col: col(rng),
        rate_unit: [None, Some(RateUnit::DegPerSec), Some(RateUnit::RadPerSec)]
            [pick(rng, 3) as usize],
        time_unit: [None, Some(TimeUnit::Millis), Some(TimeUnit::Samples)][pick(rng, 3) as usize],
        sample_rate_hz: [None, Some(10.0), Some(0.0), Some(f64::NAN)][pick(rng, 4) as usize],
        delimiter: [
            None,
            None,
            Some(b','),
            Some(b';'),
            Some(b' '),
            Some(b'\t'),
            Some(b'"'),
            Some(b'\n'),
        ][pick(rng, 8) as usize],
        decimal_comma: [None, Some(true), Some(false)][pick(rng, 3) as usize],
        has_header: [None, Some(true), Some(false)][pick(rng, 3) as usize],
        skip_extras: pick(rng, 4) == 0,
    }
}

fn fuzz_iterations() -> usize {
    std::env::var("DRIFTLAB_FUZZ_ITERS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(600)
}

/// A read that returned must have returned a consistent log.
fn check_consistent(log: &Log) {
    assert_eq!(log.time_s.len(), log.omega_dph.len());
    assert_eq!(log.time_s.len(), log.temp_c.len());
    assert!(!log.is_empty());
    assert!(log.time_s.windows(2).all(|w| w[0] < w[1]));
    assert!(
        log.time_s
            .iter()
            .chain(&log.omega_dph)
            .chain(&log.temp_c)
            .all(|v| v.is_finite())
    );
    for ch in &log.extra {
        assert_eq!(ch.values.len(), log.len());
    }
}

#[test]
fn random_bytes_never_panic() {
    let mut rng = XorShift(0x2545_F491_4F6C_DD1D);
    let alphabet = b"0123456789.,;\t \n\r\"#-+eE naNtimeomgarp[]()/\xEF\xBB\xBF\xff\x00";
    for i in 0..fuzz_iterations() {
        let len = (rng.next() % 400) as usize;
        let bytes: Vec<u8> = (0..len)
            .map(|_| {
                let r = rng.next();
                if i % 3 == 0 {
                    r as u8
                } else {
                    alphabet[(r % alphabet.len() as u64) as usize]
                }
            })
            .collect();
        if let Ok(log) = read_bytes("fuzz", &bytes, &opts()) {
            check_consistent(&log);
        }
        let _ = preview_bytes("fuzz", &bytes, &opts(), 5);
        let o = random_options(&mut rng);
        if let Ok(log) = read_bytes("fuzz", &bytes, &o) {
            check_consistent(&log);
        }
        let _ = preview_bytes("fuzz", &bytes, &o, 3);
    }
}

#[test]
fn mutated_logs_never_panic() {
    let base = b"time,omega,temp,aux\n0,1.5,20,\"a\"\n1,2.5,21,7\n# c\n2,3.5,22,8\n3,4.5,23,9\n";
    let mut rng = XorShift(0x9E37_79B9_7F4A_7C15);
    let swaps = b",;\t \n\r\"#.-e0x";
    for i in 0..fuzz_iterations() {
        let mut b = base.to_vec();
        for _ in 0..(1 + rng.next() % 4) {
            let at = (rng.next() % b.len() as u64) as usize;
            match rng.next() % 3 {
                0 => b[at] = swaps[(rng.next() % swaps.len() as u64) as usize],
                1 => {
                    b.remove(at);
                }
                _ => b.insert(at, swaps[(rng.next() % swaps.len() as u64) as usize]),
            }
            if b.is_empty() {
                break;
            }
        }
        if let Ok(log) = read_bytes("m", &b, &opts()) {
            check_consistent(&log);
        }
        if i % 4 == 0 {
            let o = random_options(&mut rng);
            if let Ok(log) = read_bytes("m", &b, &o) {
                check_consistent(&log);
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Speed (run by hand: cargo test --release --no-default-features --test ingest -- --ignored
// --nocapture)

fn vm_hwm_kb() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// Generates (once, in /tmp) and reads a large log, printing the time and peak memory.
///
/// `DRIFTLAB_BENCH_ROWS` (default 10 000 000) sets the size; `DRIFTLAB_BENCH_STYLE` the
/// dialect: `csv` (default: `time_s,omega_dph,temp_c,aux`), `csv3` (no extra column),
/// `semicolon` (decimal comma) or `spaces` (aligned columns).
#[test]
#[ignore]
fn bench_ten_million_rows() {
    let rows: usize = std::env::var("DRIFTLAB_BENCH_ROWS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(10_000_000);
    let style = std::env::var("DRIFTLAB_BENCH_STYLE").unwrap_or_else(|_| "csv".into());
    // `DRIFTLAB_BENCH_PATH` reads an existing log instead (e.g. /tmp/driftlab-bench/big.csv).
    let given = std::env::var_os("DRIFTLAB_BENCH_PATH").map(std::path::PathBuf::from);
    let path = given
        .clone()
        .unwrap_or_else(|| format!("/tmp/driftlab_bench_{style}_{rows}.csv").into());
    if given.is_none() && !path.exists() {
        let t0 = std::time::Instant::now();
        let tmp = path.with_extension("tmp");
        let mut w =
            std::io::BufWriter::with_capacity(1 << 20, std::fs::File::create(&tmp).unwrap());
        let (d, header) = match style.as_str() {
            "csv3" => (",", "time_s,omega_dph,temp_c"),
            "semicolon" => (";", "time_s;omega_dph;temp_c;aux"),
            "spaces" => ("  ", "time_s  omega_dph  temp_c  aux"),
            _ => (",", "time_s,omega_dph,temp_c,aux"),
        };
        writeln!(w, "{header}").unwrap();
        let mut rng = XorShift(42);
        for i in 0..rows {
            let noise = (rng.next() >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            let temp = 25.0 + 40.0 * (i as f64 * 2e-6).sin();
            let mut line = format!(
                "{}.{:03}{d}{:.7}{d}{:.6}",
                i,
                (rng.next() % 3),
                0.01234 + 0.05 * noise,
                temp
            );
            if style != "csv3" {
                line += &format!("{d}{:.4}", 12.5 + noise);
            }
            if style == "semicolon" {
                line = line.replace('.', ",");
            }
            writeln!(w, "{line}").unwrap();
        }
        w.flush().unwrap();
        drop(w);
        std::fs::rename(&tmp, &path).unwrap();
        println!("generated {} in {:.2?}", path.display(), t0.elapsed());
    }
    let size = std::fs::metadata(&path).unwrap().len();
    // Warm the page cache (streaming, so memory stays low) so the timing is the reader's.
    std::io::copy(
        &mut std::fs::File::open(&path).unwrap(),
        &mut std::io::sink(),
    )
    .unwrap();
    let before = vm_hwm_kb();
    let t0 = std::time::Instant::now();
    let log = read_path(&path, &opts()).unwrap();
    let first = t0.elapsed().as_secs_f64();
    let after = vm_hwm_kb();
    let cols = (3 + log.extra.len()) * log.len() * 8;
    println!(
        "read {} rows ({:.0} MB) in {:.3} s; result columns {:.0} MB; VmHWM before {:?} kB, \
         after {:?} kB; problems {:?}",
        log.len(),
        size as f64 / 1e6,
        first,
        cols as f64 / 1e6,
        before,
        after,
        log.info.problems
    );
    drop(log);
    let mut times = Vec::new();
    let repeat: usize = std::env::var("DRIFTLAB_BENCH_REPEAT")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3);
    for _ in 0..repeat {
        let t0 = std::time::Instant::now();
        let log = read_path(&path, &opts()).unwrap();
        times.push(t0.elapsed().as_secs_f64());
        drop(log);
    }
    let mut sorted = times.clone();
    sorted.sort_by(f64::total_cmp);
    let median = sorted.get(sorted.len() / 2).copied().unwrap_or(f64::NAN);
    println!("{repeat} more reads: {times:.3?} s; median {median:.3} s");
}
