//! Unit tests of the ULog reader: the format language and a small log written here byte by
//! byte.

use super::format::{FormatError, Sizes, parse_format};
use super::*;
use std::collections::HashMap;

#[test]
fn formats_parse_with_arrays_and_nesting() {
    let (name, f) = parse_format("a:uint64_t timestamp;float[3] x;b[2] inner;").unwrap();
    assert_eq!(name, "a");
    assert_eq!(f.len(), 3);
    assert_eq!(f[1].count, 3);
    let mut formats = HashMap::new();
    formats.insert("b".to_string(), parse_format("b:uint16_t v;").unwrap().1);
    formats.insert(name, f);
    let mut sizes = Sizes::for_file(0);
    assert_eq!(sizes.size("a", &formats), Ok(8 + 12 + 4));
    assert!(sizes.size("c", &formats).is_err());
}

use super::format::FieldDef;

fn message(ty: u8, body: &[u8]) -> Vec<u8> {
    let mut m = (body.len() as u16).to_le_bytes().to_vec();
    m.push(ty);
    m.extend_from_slice(body);
    m
}

/// A gyro without a temperature of its own, and newer firmware's `vehicle_imu_status`
/// with `temperature_gyro` at half its rate.
fn log_with_imu_status() -> Vec<u8> {
    let mut b = MAGIC.to_vec();
    b.push(1);
    b.extend_from_slice(&0u64.to_le_bytes());
    b.extend(message(b'B', &[0u8; 40]));
    b.extend(message(
        b'F',
        b"sensor_gyro:uint64_t timestamp;uint32_t device_id;float x;float y;float z;\
          float temperature;uint8_t[4] _padding0;",
    ));
    b.extend(message(
        b'F',
        b"vehicle_imu_status:uint64_t timestamp;uint32_t accel_device_id;\
          uint32_t gyro_device_id;float temperature_accel;float temperature_gyro;",
    ));
    let mut a = vec![0u8, 0, 0];
    a.extend_from_slice(b"sensor_gyro");
    b.extend(message(b'A', &a));
    let mut a = vec![0u8, 1, 0];
    a.extend_from_slice(b"vehicle_imu_status");
    b.extend(message(b'A', &a));
    for k in 0..10u64 {
        let mut d = vec![0u8, 0];
        d.extend_from_slice(&(1000 * k).to_le_bytes());
        d.extend_from_slice(&7u32.to_le_bytes());
        for v in [0.1f32, 0.2, 0.3, f32::NAN] {
            d.extend_from_slice(&v.to_le_bytes());
        }
        // The trailing padding is not logged.
        b.extend(message(b'D', &d));
        if k % 2 == 0 {
            let mut d = vec![1u8, 0];
            d.extend_from_slice(&(1000 * k).to_le_bytes());
            d.extend_from_slice(&7u32.to_le_bytes());
            d.extend_from_slice(&7u32.to_le_bytes());
            d.extend_from_slice(&20.0f32.to_le_bytes());
            d.extend_from_slice(&(30.0 + k as f32).to_le_bytes());
            b.extend(message(b'D', &d));
        }
    }
    b
}

#[test]
fn imu_status_temperature_is_offered_and_used_only_when_asked() {
    use crate::log::formats::{TempFrom, Values, read_bytes, select};
    let rec = read_bytes("status.ulg", &log_with_imu_status()).unwrap();
    assert_eq!(rec.instances.len(), 1);
    let g = &rec.instances[0];
    assert!(!g.temp_c.has_numbers());
    let alt = g.alt_temp(TempFrom::ImuStatus).unwrap();
    assert_eq!(alt.field, "vehicle_imu_status[0].temperature_gyro");
    // The nearest status beside each gyro sample (a tie goes to the earlier one).
    assert_eq!(
        alt.values,
        Values::F32(vec![
            30.0, 30.0, 32.0, 32.0, 34.0, 34.0, 36.0, 36.0, 38.0, 38.0
        ])
    );
    let e = select(&rec, None, None).unwrap_err().to_string();
    assert!(e.contains("temp_from imu-status"), "{e}");
    let s = select(&rec, None, Some(TempFrom::ImuStatus)).unwrap();
    assert_eq!(s.temp_c, alt.values);
    assert!(s.note.contains("may lag"), "{}", s.note);
    assert!(select(&rec, Some(0), Some(TempFrom::Accel)).is_err());
}

#[test]
fn self_nesting_is_an_error_not_a_stack_overflow() {
    let mut formats = HashMap::new();
    formats.insert("a".to_string(), parse_format("a:a x;").unwrap().1);
    let e = Sizes::for_file(0).size("a", &formats).unwrap_err();
    assert_eq!(e, FormatError::TooDeep("a".into()));
}

/// Formats `n0` .. `n{levels-1}`, each of four fields of the next, the last empty.
fn nested(levels: usize) -> HashMap<String, Vec<FieldDef>> {
    let mut formats = HashMap::new();
    for k in 0..levels {
        let text = if k + 1 == levels {
            format!("n{k}:")
        } else {
            let j = k + 1;
            format!("n{k}:n{j} a;n{j} b;n{j} c;n{j} d;")
        };
        let (name, fields) = parse_format(&text).unwrap();
        formats.insert(name, fields);
    }
    formats
}

#[test]
fn nested_formats_are_walked_once_each_and_no_deeper_than_16_levels() {
    // 4^16 walks without remembering sizes; 16 levels of 4 fields with it.
    let formats = nested(17);
    let mut sizes = Sizes::for_file(0);
    assert_eq!(sizes.size("n0", &formats), Ok(0));
    // Reached at another depth, a size already worked out still obeys the depth limit.
    let mut deeper = formats.clone();
    deeper.insert("top".into(), parse_format("top:n0 x;").unwrap().1);
    assert_eq!(
        sizes.size("top", &deeper),
        Err(FormatError::TooDeep("n0".into()))
    );
    // The same answer as a walk that never saw n0 alone.
    assert!(matches!(
        Sizes::for_file(0).size("top", &deeper),
        Err(FormatError::TooDeep(_))
    ));
}

#[test]
fn sizes_that_overflow_or_pass_a_message_are_errors() {
    let mut formats = HashMap::new();
    for text in [
        "big:uint8_t[1099511627776] _padding0;",
        "wrap:uint64_t[2305843009213693952] a;uint64_t b;",
        "sum:uint8_t[40000] a;uint8_t[40000] b;",
    ] {
        let (name, fields) = parse_format(text).unwrap();
        formats.insert(name, fields);
    }
    for t in ["big", "wrap", "sum"] {
        assert_eq!(
            Sizes::for_file(0).size(t, &formats),
            Err(FormatError::TooLarge(t.into()))
        );
    }
}

#[test]
fn a_long_name_in_a_format_error_is_quoted_short() {
    let field = "x".repeat(100_000);
    let e = parse_format(&format!("a:{field};"))
        .unwrap_err()
        .to_string();
    assert!(e.len() < 300, "{} bytes", e.len());
    assert!(e.contains("(100000 bytes)"), "{e}");
}
