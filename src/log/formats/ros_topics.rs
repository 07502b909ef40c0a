//! Gyro instances from the decoded messages of a ROS 1 bag or an MCAP file: one instance per
//! `sensor_msgs/Imu` topic, its temperature from a `sensor_msgs/Temperature` topic of the
//! same frame.

use super::recording::{
    Axes, DeviceId, GyroInstance, Problem, RosTime, Timestamps, Values, median_step, nearest_within,
};
use super::ros_msgs::{Imu, Temperature};

/// The messages of a log, topic by topic in order of first appearance, each with its log
/// (bag) time in ns.
#[derive(Default)]
pub(crate) struct Topics {
    pub imu: Vec<(String, Vec<(u64, Imu)>)>,
    pub temperature: Vec<(String, Vec<(u64, Temperature)>)>,
}

fn push<T>(list: &mut Vec<(String, Vec<(u64, T)>)>, topic: &str, t: u64, m: T) {
    match list.iter_mut().find(|(n, _)| n == topic) {
        Some((_, v)) => v.push((t, m)),
        None => list.push((topic.to_string(), vec![(t, m)])),
    }
}

impl Topics {
    pub(crate) fn push_imu(&mut self, topic: &str, log_time_ns: u64, m: Imu) {
        push(&mut self.imu, topic, log_time_ns, m);
    }

    pub(crate) fn push_temperature(&mut self, topic: &str, log_time_ns: u64, m: Temperature) {
        push(&mut self.temperature, topic, log_time_ns, m);
    }

    /// One instance per Imu topic, messages in log-time order (as rosbags and the mcap
    /// reader give them).
    pub(crate) fn into_instances(mut self, problems: &mut Vec<Problem>) -> Vec<GyroInstance> {
        for (_, v) in &mut self.imu {
            v.sort_by_key(|(t, _)| *t);
        }
        for (_, v) in &mut self.temperature {
            v.sort_by_key(|(t, _)| *t);
        }
        let single = self.imu.len() == 1 && self.temperature.len() == 1;
        let mut used = vec![false; self.temperature.len()];
        let mut out = Vec::new();
        for (topic, msgs) in &self.imu {
            let frame = msgs
                .first()
                .map(|(_, m)| m.frame_id.clone())
                .unwrap_or_default();
            if let Some((_, m)) = msgs.iter().find(|(_, m)| m.frame_id != frame) {
                problems.push(Problem::note(format!(
                    "{topic}: frame_id changes from \"{frame}\" to \"{}\" within the topic",
                    m.frame_id
                )));
            }
            let stamps: Vec<RosTime> = msgs.iter().map(|(_, m)| m.stamp).collect();
            let column =
                |f: &dyn Fn(&Imu) -> f64| Values::F64(msgs.iter().map(|(_, m)| f(m)).collect());
            let gyro = Axes {
                xyz: [
                    column(&|m| m.angular_velocity[0]),
                    column(&|m| m.angular_velocity[1]),
                    column(&|m| m.angular_velocity[2]),
                ],
            };
            let accel = Axes {
                xyz: [
                    column(&|m| m.linear_acceleration[0]),
                    column(&|m| m.linear_acceleration[1]),
                    column(&|m| m.linear_acceleration[2]),
                ],
            };
            // Its temperature: a Temperature topic on the same frame, else the only one of a
            // log with one IMU and one temperature.
            let matched = self
                .temperature
                .iter()
                .position(|(_, t)| t.first().is_some_and(|(_, m)| m.frame_id == frame))
                .or(single.then_some(0));
            let temp_c = match matched {
                Some(k) => {
                    used[k] = true;
                    let (ttopic, t) = &self.temperature[k];
                    let tf = t.first().map(|(_, m)| m.frame_id.as_str()).unwrap_or("");
                    if tf != frame {
                        problems.push(Problem::note(format!(
                            "{topic}: temperature taken from {ttopic}, the log's only \
                             Temperature topic, although its frame_id \"{tf}\" is not the \
                             IMU's \"{frame}\""
                        )));
                    }
                    let g: Vec<i128> = stamps.iter().map(|s| s.nanos()).collect();
                    let tk: Vec<i128> = t.iter().map(|(_, m)| m.stamp.nanos()).collect();
                    let tol = median_step(&tk)
                        .unwrap_or(0)
                        .max(median_step(&g).unwrap_or(0));
                    let pick = nearest_within(&g, &tk, tol);
                    Values::F64(
                        pick.iter()
                            .map(|p| p.map_or(f64::NAN, |i| t[i].1.celsius))
                            .collect(),
                    )
                }
                None => Values::F64(vec![f64::NAN; msgs.len()]),
            };
            out.push(GyroInstance {
                index: out.len(),
                label: topic.clone(),
                device: Some(DeviceId::Ros {
                    topic: topic.clone(),
                    frame_id: frame,
                }),
                time: Timestamps::Ros(stamps),
                time_sample_us: None,
                log_time_ns: Some(msgs.iter().map(|(t, _)| *t).collect()),
                gyro,
                temp_c,
                accel: Some(accel),
                alt_temps: Vec::new(),
            });
        }
        for (k, (topic, t)) in self.temperature.iter().enumerate() {
            if !used[k] {
                let f = t.first().map(|(_, m)| m.frame_id.as_str()).unwrap_or("");
                problems.push(Problem::note(format!(
                    "Temperature topic {topic} (frame_id \"{f}\") matches no Imu topic's frame; \
                     not used"
                )));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn imu(sec: i64, frame: &str, w: f64) -> Imu {
        Imu {
            stamp: RosTime { sec, nsec: 0 },
            frame_id: frame.into(),
            angular_velocity: [w, 0.0, 0.0],
            linear_acceleration: [0.0, 0.0, 9.8],
        }
    }

    fn temp(sec: i64, frame: &str, c: f64) -> Temperature {
        Temperature {
            stamp: RosTime { sec, nsec: 0 },
            frame_id: frame.into(),
            celsius: c,
        }
    }

    #[test]
    fn a_temperature_topic_of_the_same_frame_is_the_gyros_own() {
        let mut t = Topics::default();
        for s in 0..6 {
            t.push_imu("/imu/data", s as u64, imu(s, "imu_link", s as f64));
            t.push_imu("/other/imu", s as u64, imu(s, "other", 0.0));
        }
        // Half as often as the gyro, on its frame; another frame's topic is not used.
        for s in [0, 2, 4] {
            t.push_temperature(
                "/imu/temperature",
                s as u64,
                temp(s, "imu_link", 30.0 + s as f64),
            );
            t.push_temperature("/board/temperature", s as u64, temp(s, "board", 99.0));
        }
        let mut problems = Vec::new();
        let inst = t.into_instances(&mut problems);
        assert_eq!(inst.len(), 2);
        // The nearest temperature beside each gyro sample (ties go to the earlier one).
        assert_eq!(
            inst[0].temp_c,
            Values::F64(vec![30.0, 30.0, 32.0, 32.0, 34.0, 34.0])
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
