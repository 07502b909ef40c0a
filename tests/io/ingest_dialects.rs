//! Reading test-stand logs: every dialect the stands write (separators, decimal commas,
//! headers, comments, BOM, CRLF, quoting) and the units read from headers and options, checked
//! against values written into the test itself.

use driftlab::log::ColumnRole;
use driftlab::log::ingest::{ColumnRef, RateUnit, ReadOptions, TimeUnit, parse_delimiter};
use std::f64::consts::PI;

use crate::common;
use common::ingest::*;

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

#[test]
fn quote_left_open_is_refused_where_it_opened() {
    // A header, a quote opened in the rate cell, then lines of blank cells: the field runs on
    // past what a cell can be, and is refused at its line and column however long the file.
    for after in [17, 200_000] {
        let text = format!(
            "time_s,omega_dph,temp_c\n0,\"1,20\n{}",
            ",,\n".repeat(after)
        );
        let e = fail(text.as_bytes(), &opts());
        assert_eq!((e.line, e.column), (2, 2), "{e}");
        assert!(e.message.contains("still open after 17 lines"), "{e}");
    }
    // Closed at the end of the file, it is refused just the same.
    let text = format!(
        "time_s,omega_dph,temp_c\n0,\"1,20\n{}\",1,20\n",
        ",,\n".repeat(200_000)
    );
    let e = fail(text.as_bytes(), &opts());
    assert_eq!((e.line, e.column), (2, 2), "{e}");
    // Left open on the last lines, it is never closed: named where it opened.
    let e = fail(b"time,omega,temp,note\n0,1,20,ok\n1,2,21,\"a\nb\n", &opts());
    assert_eq!((e.line, e.column), (3, 4), "{e}");
    assert!(e.message.contains("never closed"), "{e}");
    // A short word on a few lines is still one cell.
    let text = "time,omega,temp,note\n0,1,20,ok\n1,2,21,\"a\nb\nc\"\n2,3,22,\"\"\"x\"\"\"\n\
                3,4,23,ok\n4,5,24,ok\n";
    let log = read(text);
    close(&log.omega_dph, &[1.0, 2.0, 3.0, 4.0, 5.0]);
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
        axis_cols: vec![ColumnRef::Name("gy".into()), ColumnRef::Index(4)],
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
