//! One gyro instance as the CSV driftlab reads back with no options: `time_s`, the three
//! gyro axes in rad/s, `temp_c`, then the accelerometer in m/s² when there is one.
//!
//! Every value is written in the shortest text that reads back to the same number in its
//! own precision: a float32 as a float32 (so parsing the cell as f32 gives the stored bits),
//! a float64 as a float64. A missing value is `nan`. The rows are numbers alone, which never
//! need quoting, formatted here directly; the header goes through the `csv` crate.

use super::recording::Values;
use super::select::Selected;
use std::io::Write;

/// The header `write_csv` writes for `selected`, without its line break: fixed names, written
/// as every CSV record with text is ([`crate::files::csv_cells`]).
pub fn csv_header(selected: &Selected<'_>) -> String {
    let mut cells = vec![
        "time_s",
        "gyro_x_rad_s",
        "gyro_y_rad_s",
        "gyro_z_rad_s",
        "temp_c",
    ];
    if selected.instance.accel.is_some() {
        cells.extend(["accel_x_m_s2", "accel_y_m_s2", "accel_z_m_s2"]);
    }
    let mut h = crate::files::csv_cells::text_record(&cells);
    h.pop();
    h
}

fn cell(out: &mut Vec<u8>, buf: &mut zmij::Buffer, v: &Values, i: usize) {
    match v {
        Values::F32(x) if x[i].is_finite() => out.extend_from_slice(buf.format(x[i]).as_bytes()),
        Values::F64(x) if x[i].is_finite() => out.extend_from_slice(buf.format(x[i]).as_bytes()),
        Values::F32(x) if x[i].is_infinite() => out.extend_from_slice(inf(x[i] > 0.0)),
        Values::F64(x) if x[i].is_infinite() => out.extend_from_slice(inf(x[i] > 0.0)),
        _ => out.extend_from_slice(b"nan"),
    }
}

fn inf(positive: bool) -> &'static [u8] {
    if positive { b"inf" } else { b"-inf" }
}

/// Writes the samples `rows` of `selected` (places in the instance, in the order given) as
/// CSV to `w`: `driftlab convert` passes the samples every reader keeps
/// ([`crate::log::kept_samples`]), so that the CSV holds what every command reads of the log.
///
/// # Errors
/// Those of `w`.
pub fn write_csv(
    selected: &Selected<'_>,
    rows: &[usize],
    w: &mut dyn Write,
) -> std::io::Result<()> {
    let inst = selected.instance;
    let mut out = Vec::with_capacity(1 << 16);
    out.extend_from_slice(csv_header(selected).as_bytes());
    out.push(b'\n');
    let mut buf = zmij::Buffer::new();
    let time = &inst.time;
    for &i in rows {
        let t = time.seconds(i);
        out.extend_from_slice(buf.format(t).as_bytes());
        for v in &inst.gyro.xyz {
            out.push(b',');
            cell(&mut out, &mut buf, v, i);
        }
        out.push(b',');
        cell(&mut out, &mut buf, &selected.temp_c, i);
        if let Some(a) = &inst.accel {
            for v in &a.xyz {
                out.push(b',');
                cell(&mut out, &mut buf, v, i);
            }
        }
        out.push(b'\n');
        if out.len() > 1 << 16 {
            w.write_all(&out)?;
            out.clear();
        }
    }
    w.write_all(&out)
}
