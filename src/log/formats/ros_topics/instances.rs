//! The gyro instances of a log's kept messages: each Imu topic's samples parted by frame, a
//! gyro each; each Temperature topic's readings parted by frame too, a frame's readings the
//! temperature of that frame's gyro, paired with it by the clock `ros_clocks` chooses; an
//! accelerometer that the messages say they lack left out.

use super::{ImuSample, Stamped, TempSample, Topic, Topics};
use crate::log::formats::device_change::Part;
use crate::log::formats::error::{LIST_AT_MOST, listed, quoted};
use crate::log::formats::recording::{
    Axes, DeviceId, GyroInstance, Problem, RosTime, Timestamps, Values,
};
use crate::log::formats::ros_clocks::{self, Side, advances, log_stamp, stuck};
use crate::log::formats::ros_frames;
use std::collections::HashMap;

impl<T: Stamped> Topic<T> {
    /// The stamps of messages `rows`, or their log times when the stamps never advance
    /// (`by_clock`).
    fn times(&self, rows: &[usize], by_clock: bool) -> Vec<RosTime> {
        rows.iter()
            .map(|&i| {
                if by_clock {
                    log_stamp(self.msgs[i].0)
                } else {
                    self.msgs[i].1.stamp()
                }
            })
            .collect()
    }

    /// True when the topic's stamps never advance while its log times do: it is timed by the
    /// log's clock.
    fn by_clock(&self) -> bool {
        stuck(self.msgs.iter().map(|(_, m)| m.stamp()))
            && advances(&self.msgs.iter().map(|(t, _)| *t).collect::<Vec<u64>>())
    }

    /// The messages parted by frame ([`ros_frames::parted`]), told in `problems` when the
    /// frame changes (`words` as [`ros_frames::change_note`] takes them, `label` of each
    /// part).
    fn by_frame(
        &self,
        problems: &mut Vec<Problem>,
        words: (&str, &str, &str),
        label: impl Fn(usize, usize) -> String,
    ) -> Vec<Part<u16>> {
        let frames: Vec<u16> = self.msgs.iter().map(|(_, m)| m.frame()).collect();
        let (parts, left_out) = ros_frames::parted(&frames);
        if parts.len() > 1 {
            let by_clock = self.by_clock();
            let n = parts.len();
            problems.push(Problem::note(ros_frames::change_note(
                &self.name,
                &parts,
                left_out,
                &self.frame_names,
                words,
                |k| label(k, n),
                |i| self.times(&[i], by_clock)[0].seconds(),
            )));
        }
        parts
    }
}

/// A Temperature topic's readings of one frame: the temperature of that frame's gyro.
struct Source<'a> {
    topic: &'a Topic<TempSample>,
    frame: &'a str,
    rows: Vec<usize>,
}

impl Source<'_> {
    /// `name (frame_id "f")`, as messages list it.
    fn named(&self) -> String {
        format!(
            "{} (frame_id \"{}\")",
            quoted(&self.topic.name),
            quoted(self.frame)
        )
    }
}

/// The label of part `k` of `n` of topic `topic`: the topic alone when it is one frame.
fn part_label(topic: &str, k: usize, n: usize) -> String {
    if n == 1 {
        topic.to_string()
    } else {
        format!("{topic} frame {} of {n}", k + 1)
    }
}

impl Topics {
    /// One instance per Imu topic (per frame of it), in order of its first message, messages
    /// in log-time order (as rosbags and the mcap reader give them); and the Temperature
    /// topics (frames of them) taken as no gyro's temperature, each as `name (frame_id "f")`,
    /// for the message refusing a gyro without one.
    ///
    /// Each Temperature topic's readings are parted by frame as an Imu topic's samples are.
    /// A gyro's temperature is the readings on its frame_id of the first Temperature topic
    /// (by first message) that has some, else a log's only Temperature topic of one frame
    /// when the log has one gyro. When that leaves a choice unmade (several topics on the
    /// frame) or undone (several topics, none on the frame), a problem names every candidate:
    /// no setting picks a Temperature topic.
    ///
    /// A topic whose `header.stamp` never advances (a driver that leaves it 0) is timed by
    /// `clock` (the log time each message was recorded at, as the format names it: "the
    /// bag's record time") instead, with a note saying so; a gyro is paired with its
    /// temperature by the clock [`ros_clocks::paired`] chooses.
    pub(crate) fn into_instances(
        mut self,
        problems: &mut Vec<Problem>,
        clock: &str,
    ) -> (Vec<GyroInstance>, Vec<String>) {
        for t in &mut self.imu {
            t.msgs.sort_by_key(|(t, _)| *t);
        }
        for t in &mut self.temperature {
            t.msgs.sort_by_key(|(t, _)| *t);
        }
        // Each Temperature topic's readings parted by frame, topics in order of their first
        // message: the first on a frame is the frame's, as a walk in order would find it.
        let mut sources: Vec<Source<'_>> = Vec::new();
        for &slot in &self.temperature_order {
            let t = &self.temperature[slot];
            let words = (
                "each frame's readings are the temperature of that frame's gyro",
                "reading",
                "a temperature",
            );
            for p in t.by_frame(problems, words, |k, n| part_label(&t.name, k, n)) {
                sources.push(Source {
                    topic: t,
                    frame: t.frame_names.name(p.device),
                    rows: p.rows,
                });
            }
        }
        // Each Imu topic's gyros: its messages parted by frame_id, each frame's a gyro of its
        // own (one part when the frame never changes); messages of a frame past those a topic
        // tells apart are left out, counted.
        let words = (
            "each frame's samples are a gyro of their own, never one calibration over two \
             sensors",
            "sample",
            "a gyro",
        );
        let gyros: Vec<(usize, Vec<Part<u16>>)> = self
            .imu_order
            .iter()
            .map(|&slot| {
                let t = &self.imu[slot];
                (
                    slot,
                    t.by_frame(problems, words, |k, n| part_label(&t.name, k, n)),
                )
            })
            .collect();
        let single = gyros.iter().map(|g| g.1.len()).sum::<usize>() == 1 && sources.len() == 1;
        let mut by_frame: HashMap<&str, Vec<usize>> = HashMap::new();
        for (k, s) in sources.iter().enumerate() {
            by_frame.entry(s.frame).or_default().push(k);
        }
        let mut used = vec![false; sources.len()];
        // Imu topics left without a temperature although the log has Temperature topics.
        let mut without: Vec<String> = Vec::new();
        // The frames of every gyro.
        let mut imu_frames: std::collections::HashSet<&str> = std::collections::HashSet::new();
        let mut out = Vec::new();
        for (slot, parts) in &gyros {
            let t = &self.imu[*slot];
            let by_clock = t.by_clock();
            if by_clock {
                problems.push(Problem::note(format!(
                    "{}: header.stamp never advances (all {} messages are stamped {} s, as a \
                     driver that does not fill it leaves them): its samples are timed by {clock} \
                     instead, and its temperature paired by it, which lags each sample by the \
                     transport's delay and jitter; to time them by the sensor, have the driver \
                     fill header.stamp",
                    quoted(&t.name),
                    t.msgs.len(),
                    t.msgs[0].1.stamp().seconds()
                )));
            }
            for (k, part) in parts.iter().enumerate() {
                let frame = t.frame_names.name(part.device);
                imu_frames.insert(frame);
                let label = part_label(&t.name, k, parts.len());
                // Its temperature: a Temperature topic on the same frame, else the only one of
                // a log with one gyro and one temperature.
                let on_frame = by_frame.get(frame);
                if let Some(ks) = on_frame.filter(|ks| ks.len() > 1) {
                    problems.push(Problem::note(format!(
                        "{}: {} Temperature topics are on its frame_id \"{}\": {}; its \
                         temperature is the first in the file, {} (temp_from own), and no \
                         setting picks another: to use another, cut the others out of the log \
                         (e.g. rosbag filter or mcap filter)",
                        quoted(&label),
                        ks.len(),
                        quoted(frame),
                        listed(
                            ks.iter()
                                .map(|k| quoted(&sources[*k].topic.name).into_owned()),
                            ", "
                        ),
                        quoted(&sources[ks[0]].topic.name)
                    )));
                }
                let matched = on_frame.map(|ks| ks[0]).or(single.then_some(0));
                if matched.is_none() && !sources.is_empty() {
                    without.push(format!(
                        "{} (frame_id \"{}\")",
                        quoted(&label),
                        quoted(frame)
                    ));
                }
                let rows = &part.rows;
                let stamps = t.times(rows, by_clock);
                let part_log_times: Vec<u64> = rows.iter().map(|&i| t.msgs[i].0).collect();
                if let Some(s) = matched.map(|k| &sources[k])
                    && s.frame != frame
                {
                    problems.push(Problem::note(format!(
                        "{}: temperature taken from {}, the log's only Temperature topic, \
                         although its frame_id \"{}\" is not the IMU's \"{}\"",
                        quoted(&label),
                        quoted(&s.topic.name),
                        quoted(s.frame),
                        quoted(frame)
                    )));
                }
                let source = matched.map(|k| {
                    used[k] = true;
                    let s = &sources[k];
                    let stamps = s.topic.times(&s.rows, false);
                    let log_times: Vec<u64> = s.rows.iter().map(|&i| s.topic.msgs[i].0).collect();
                    (s, stamps, log_times)
                });
                let temp_name = source.as_ref().map(|(s, _, _)| quoted(&s.topic.name));
                let temp_side = source.as_ref().zip(temp_name.as_deref()).map(
                    |((_, stamps, log_times), name)| Side {
                        name,
                        stamps,
                        log_times,
                    },
                );
                let pairing = ros_clocks::paired(
                    &Side {
                        name: &quoted(&label),
                        stamps: &stamps,
                        log_times: &part_log_times,
                    },
                    temp_side.as_ref(),
                    by_clock,
                    clock,
                    problems,
                );
                let temp_c = Values::F64(match &source {
                    Some((s, _, _)) => pairing
                        .readings
                        .iter()
                        .map(|r| {
                            r.map_or(f64::NAN, |r| {
                                r.celsius(|j| s.topic.msgs[s.rows[j]].1.celsius)
                            })
                        })
                        .collect(),
                    None => vec![f64::NAN; rows.len()],
                });
                // A gyro whose stamps change clock is timed by the record time, one clock
                // throughout (told by the pairing).
                let stamps = if pairing.gyro_by_record_time {
                    part_log_times.iter().map(|&x| log_stamp(x)).collect()
                } else {
                    stamps
                };
                let accel = acceleration(&label, &t.msgs, rows, problems);
                let column = |f: &dyn Fn(&ImuSample) -> f64| {
                    Values::F64(rows.iter().map(|&i| f(&t.msgs[i].1)).collect())
                };
                let gyro = Axes {
                    xyz: [
                        column(&|m| m.angular_velocity[0]),
                        column(&|m| m.angular_velocity[1]),
                        column(&|m| m.angular_velocity[2]),
                    ],
                };
                out.push(GyroInstance {
                    index: out.len(),
                    label,
                    device: Some(DeviceId::Ros {
                        topic: t.name.clone(),
                        frame_id: frame.to_string(),
                    }),
                    time: Timestamps::Ros(stamps),
                    time_sample_us: None,
                    log_time_ns: Some(part_log_times),
                    gyro,
                    temp_c,
                    accel,
                    accel_device_id: None,
                    alt_temps: Vec::new(),
                });
            }
        }
        let unused: Vec<usize> = (0..sources.len()).filter(|&k| !used[k]).collect();
        if !without.is_empty() {
            // Every Temperature topic could have been theirs, had it been the only one or on
            // their frame.
            let many = without.len() > 1;
            problems.push(Problem::note(format!(
                "Imu topic{} {} ha{} no Temperature topic on {} frame_id, and the log's {} \
                 Temperature topic{} on other frames: {}; none is taken as {} temperature \
                 (a log's only Temperature topic stands in for its only Imu topic), and no \
                 setting picks one (temp_from takes own, accel, imu-status or none): to use \
                 one, cut the log to the gyro's topic and that Temperature topic (e.g. rosbag \
                 filter or mcap filter)",
                if many { "s" } else { "" },
                listed(without.into_iter(), ", "),
                if many { "ve" } else { "s" },
                if many { "their" } else { "its" },
                self.temperature_order.len(),
                if self.temperature_order.len() == 1 {
                    " is"
                } else {
                    "s are"
                },
                listed(sources.iter().map(Source::named), ", "),
                if many { "their" } else { "its" },
            )));
        } else {
            // Those on a frame of no Imu topic (the others, a frame's second or third, are in
            // the note on that frame's gyro).
            let alone: Vec<&usize> = unused
                .iter()
                .filter(|k| !imu_frames.contains(sources[**k].frame))
                .collect();
            for k in alone.iter().take(LIST_AT_MOST) {
                problems.push(Problem::note(format!(
                    "Temperature topic {} matches no Imu topic's frame; not used",
                    sources[**k].named()
                )));
            }
            if alone.len() > LIST_AT_MOST {
                problems.push(Problem::note(format!(
                    "and {} more Temperature topics match no Imu topic's frame; not used",
                    alone.len() - LIST_AT_MOST
                )));
            }
        }
        let untied = unused.iter().map(|&k| sources[k].named()).collect();
        (out, untied)
    }
}

/// The accelerometer of gyro `label`, messages `rows` of `msgs`: none when every message says
/// it has no acceleration (a gyro-only IMU, `Imu::no_acceleration`), as a CSV log without
/// accelerometer columns; else NaN on the messages that say so, told.
fn acceleration(
    label: &str,
    msgs: &[(u64, ImuSample)],
    rows: &[usize],
    problems: &mut Vec<Problem>,
) -> Option<Axes> {
    let without = rows.iter().filter(|&&i| msgs[i].1.no_acceleration).count();
    if without == rows.len() {
        return None;
    }
    if without > 0 {
        problems.push(Problem::note(format!(
            "{}: {without} of {} messages have no acceleration (linear_acceleration_covariance[0] \
             is -1): their accelerometer axes are NaN",
            quoted(label),
            rows.len()
        )));
    }
    let axis = |a: usize| {
        Values::F64(
            rows.iter()
                .map(|&i| {
                    let m = &msgs[i].1;
                    if m.no_acceleration {
                        f64::NAN
                    } else {
                        m.linear_acceleration[a]
                    }
                })
                .collect(),
        )
    };
    Some(Axes {
        xyz: [axis(0), axis(1), axis(2)],
    })
}

#[cfg(test)]
mod tests {
    use super::super::tests::{imu, temp};
    use super::*;
    use crate::log::formats::ros_msgs::Kind;

    #[test]
    fn a_temperature_topic_of_the_same_frame_is_the_gyros_own() {
        let mut t = Topics::for_file(0);
        // Slots made in another order than the first messages: the instances follow the
        // messages.
        let other = t.slot(Kind::Imu, "/other/imu");
        let data = t.slot(Kind::Imu, "/imu/data");
        let board = t.slot(Kind::Temperature, "/board/temperature");
        let own = t.slot(Kind::Temperature, "/imu/temperature");
        for s in 0..6 {
            t.push_imu(data, s as u64, &imu(s, "imu_link", s as f64))
                .unwrap();
            t.push_imu(other, s as u64, &imu(s, "other", 0.0)).unwrap();
        }
        // Half as often as the gyro, on its frame; another frame's topic is not used.
        for s in [0, 2, 4] {
            t.push_temperature(own, s as u64, &temp(s, "imu_link", 30.0 + s as f64))
                .unwrap();
            t.push_temperature(board, s as u64, &temp(s, "board", 99.0))
                .unwrap();
        }
        let mut problems = Vec::new();
        let (inst, _) = t.into_instances(&mut problems, "the log time");
        assert_eq!(inst.len(), 2);
        assert_eq!(inst[0].label, "/imu/data");
        // The line between the readings around each gyro sample; past the last, the last
        // reading, within the pairing's tolerance (a step of the temperature topic).
        assert_eq!(
            inst[0].temp_c,
            Values::F64(vec![30.0, 31.0, 32.0, 33.0, 34.0, 34.0])
        );
        assert!(!inst[1].temp_c.has_numbers());
        assert!(
            problems
                .iter()
                .any(|p| p.message.contains("/board/temperature")),
            "{problems:?}"
        );
    }
}
