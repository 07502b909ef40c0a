//! A gyro whose device changes within the stream its samples come in: a PX4 `sensor_gyro`
//! subscription whose `device_id` changes (the chip was swapped, or the bus re-enumerated
//! it), a ROS Imu topic whose `frame_id` changes. Its samples after the change are another
//! sensor's, with another bias and another thermal drift, and one calibration over both fits
//! neither. Every reader tells the change in the one sentence [`changes`] words, naming the
//! sample and time where it happens; a format that names the device of every sample parts
//! the stream by device ([`parts`]), each device's samples a gyro of their own.

use super::error::LIST_AT_MOST;
use std::collections::HashMap;
use std::hash::Hash;

/// `stream: field changes from `from` to `to` within the `within` at sample N (time s)`: the
/// start of every reader's note on a device that changes, the consequence left to the
/// reader. `sample` is 1-based, as every sample number driftlab prints.
pub(crate) fn changes(
    stream: &str,
    field: &str,
    (from, to): (&str, &str),
    within: &str,
    sample: usize,
    time_s: f64,
) -> String {
    format!(
        "{stream}: {field} changes from {from} to {to} within the {within} at sample {sample} \
         ({} s)",
        crate::number::significant(time_s, 10)
    )
}

/// The samples of one device in a stream.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Part<D> {
    /// The device.
    pub device: D,
    /// Its samples' places in the stream (0-based), ascending.
    pub rows: Vec<usize>,
}

/// A stream's samples parted by the device of each (`devices`, one per sample): one part per
/// device in order of its first sample, the first [`LIST_AT_MOST`] devices only (a crafted
/// log of a new id on every sample is not a thousand gyros), and how many samples of further
/// devices were left out. One part when the device never changes.
pub(crate) fn parts<D: Eq + Hash + Clone>(devices: &[D]) -> (Vec<Part<D>>, usize) {
    let mut out: Vec<Part<D>> = Vec::new();
    let mut place: HashMap<&D, usize> = HashMap::new();
    let mut left_out = 0;
    for (i, d) in devices.iter().enumerate() {
        match place.get(d) {
            Some(&k) => out[k].rows.push(i),
            None if out.len() < LIST_AT_MOST => {
                place.insert(d, out.len());
                out.push(Part {
                    device: d.clone(),
                    rows: vec![i],
                });
            }
            None => left_out += 1,
        }
    }
    (out, left_out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_device_that_comes_back_is_one_part() {
        let (p, left) = parts(&[7, 7, 9, 9, 7]);
        assert_eq!(
            p,
            [
                Part {
                    device: 7,
                    rows: vec![0, 1, 4]
                },
                Part {
                    device: 9,
                    rows: vec![2, 3]
                }
            ]
        );
        assert_eq!(left, 0);
    }

    #[test]
    fn a_new_device_on_every_sample_keeps_the_first_few() {
        let ids: Vec<u32> = (0..100).collect();
        let (p, left) = parts(&ids);
        assert_eq!(p.len(), LIST_AT_MOST);
        assert_eq!(left, 100 - LIST_AT_MOST);
    }
}
