//! Drone logs in tests: the real samples of `../shared/data/formats/`, and a PX4 ULog and an
//! ArduPilot DataFlash log written from known samples.

use std::path::PathBuf;

/// The folder of real drone and robot samples with their reference CSVs; `None` (after saying
/// so) when it is missing, a failure when `CI` is set.
pub fn data_dir() -> Option<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/data/formats");
    if dir.is_dir() {
        return Some(dir);
    }
    assert!(
        std::env::var_os("CI").is_none(),
        "the reference data {} is missing (CI is set, so this fails)",
        dir.display()
    );
    eprintln!("skipping: reference data {} is missing", dir.display());
    None
}

/// The PX4 sample.
pub const ULOG: &str = "px4_ulog/sample_log_small.ulg";
/// The ArduPilot sample.
pub const DATAFLASH: &str = "ardupilot_dataflash/backend_log_80k.bin";

/// A PX4 ULog of one `sensor_gyro` (with its temperature) and `sensor_accel` of the same
/// device, at 1 Hz: the thermal-calibration profile's topics.
pub fn ulog(time_s: &[f64], gyro_rad_s: &[[f32; 3]], temp_c: &[f32], device_id: u32) -> Vec<u8> {
    ulog_of_devices(time_s, gyro_rad_s, temp_c, &vec![device_id; time_s.len()])
}

/// As [`ulog`], each sample of `sensor_gyro` with its own `device_id` (a chip swapped or
/// re-enumerated partway through the log).
pub fn ulog_of_devices(
    time_s: &[f64],
    gyro_rad_s: &[[f32; 3]],
    temp_c: &[f32],
    device_ids: &[u32],
) -> Vec<u8> {
    ulog_of_subscriptions(time_s, temp_c, &[(device_ids, gyro_rad_s)])
}

/// One ULog message: its size, type and body.
fn message(ty: u8, body: &[u8]) -> Vec<u8> {
    let mut m = (body.len() as u16).to_le_bytes().to_vec();
    m.push(ty);
    m.extend_from_slice(body);
    m
}

/// A ULog's header (version 1, timestamp 0) and its flag bits message, all zero.
fn ulog_head() -> Vec<u8> {
    let mut b = b"ULog\x01\x12\x35".to_vec();
    b.push(1);
    b.extend_from_slice(&0u64.to_le_bytes());
    b.extend(message(b'B', &[0u8; 40]));
    b
}

/// A PX4 ULog of several `sensor_gyro` subscriptions (`multi_id` 0, 1, … in the order given),
/// each a `(device_id, gyro in rad/s)` per sample, all stamped `time_s` and at `temp_c`.
pub fn ulog_of_subscriptions(
    time_s: &[f64],
    temp_c: &[f32],
    subscriptions: &[(&[u32], &[[f32; 3]])],
) -> Vec<u8> {
    let mut b = ulog_head();
    b.extend(message(
        b'F',
        b"sensor_gyro:uint64_t timestamp;uint32_t device_id;float x;float y;float z;\
          float temperature;",
    ));
    for k in 0..subscriptions.len() {
        // multi_id k, msg_id k.
        let mut a = vec![k as u8];
        a.extend_from_slice(&(k as u16).to_le_bytes());
        a.extend_from_slice(b"sensor_gyro");
        b.extend(message(b'A', &a));
    }
    for (i, (t, temp)) in time_s.iter().zip(temp_c).enumerate() {
        for (k, (device_ids, gyro)) in subscriptions.iter().enumerate() {
            let mut d = (k as u16).to_le_bytes().to_vec();
            d.extend_from_slice(&((t * 1e6) as u64).to_le_bytes());
            d.extend_from_slice(&device_ids[i].to_le_bytes());
            let g = gyro[i];
            for v in [g[0], g[1], g[2], *temp] {
                d.extend_from_slice(&v.to_le_bytes());
            }
            b.extend(message(b'D', &d));
        }
    }
    b
}

/// A PX4 ULog of one `sensor_gyro` (rad/s) and the `sensor_accel` of the same device (m/s²),
/// stamped alike and each with the temperature `temp_c`: a flight controller's IMU logged with
/// the thermal-calibration profile.
pub fn ulog_imu(
    time_s: &[f64],
    gyro_rad_s: &[[f32; 3]],
    accel_m_s2: &[[f32; 3]],
    temp_c: &[f32],
    device_id: u32,
) -> Vec<u8> {
    ulog_imu_stamped(time_s, time_s, gyro_rad_s, accel_m_s2, temp_c, device_id)
}

/// [`ulog_imu`] with the accelerometer's messages stamped `accel_time_s` (a clock of its own).
pub fn ulog_imu_stamped(
    time_s: &[f64],
    accel_time_s: &[f64],
    gyro_rad_s: &[[f32; 3]],
    accel_m_s2: &[[f32; 3]],
    temp_c: &[f32],
    device_id: u32,
) -> Vec<u8> {
    ulog_imu_of(
        time_s,
        accel_time_s,
        gyro_rad_s,
        accel_m_s2,
        temp_c,
        [device_id, device_id],
    )
}

/// [`ulog_imu_stamped`] with the gyro's and the accelerometer's `device_id`s, in that order
/// (a driver that numbers the chip's two sensors apart gives two).
pub fn ulog_imu_of(
    time_s: &[f64],
    accel_time_s: &[f64],
    gyro_rad_s: &[[f32; 3]],
    accel_m_s2: &[[f32; 3]],
    temp_c: &[f32],
    device_ids: [u32; 2],
) -> Vec<u8> {
    let mut b = ulog_head();
    for topic in ["sensor_gyro", "sensor_accel"] {
        b.extend(message(
            b'F',
            format!(
                "{topic}:uint64_t timestamp;uint32_t device_id;float x;float y;float z;\
                 float temperature;"
            )
            .as_bytes(),
        ));
    }
    for (k, topic) in ["sensor_gyro", "sensor_accel"].iter().enumerate() {
        // multi_id 0, msg_id k.
        let mut a = vec![0u8];
        a.extend_from_slice(&(k as u16).to_le_bytes());
        a.extend_from_slice(topic.as_bytes());
        b.extend(message(b'A', &a));
    }
    for (i, (t, temp)) in time_s.iter().zip(temp_c).enumerate() {
        for (k, v) in [gyro_rad_s[i], accel_m_s2[i]].iter().enumerate() {
            let t = if k == 0 { t } else { &accel_time_s[i] };
            let mut d = (k as u16).to_le_bytes().to_vec();
            d.extend_from_slice(&((t * 1e6) as u64).to_le_bytes());
            d.extend_from_slice(&device_ids[k].to_le_bytes());
            for x in [v[0], v[1], v[2], *temp] {
                d.extend_from_slice(&x.to_le_bytes());
            }
            b.extend(message(b'D', &d));
        }
    }
    b
}

/// One `IMU` message of an ArduPilot DataFlash log: its instance `I`, its gyro axes (rad/s)
/// and its temperature (°C), at `time_us`.
#[derive(Debug, Clone, Copy)]
pub struct DataFlashImu {
    /// `TimeUS`.
    pub time_us: u64,
    /// `I`: 0 for the first IMU (ArduPilot's `INS_TCAL1`).
    pub instance: u8,
    /// `GyrX`, `GyrY`, `GyrZ`, rad/s.
    pub gyro: [f32; 3],
    /// `T`, °C.
    pub temp_c: f32,
}

/// An ArduPilot DataFlash log of `IMU` messages in the order given, with the `FMT` ArduCopter
/// 4.6 writes for them (`QBffffffIIfBBHH`), the accelerometer at rest.
pub fn dataflash(messages: &[DataFlashImu]) -> Vec<u8> {
    fn message(ty: u8, payload: &[u8]) -> Vec<u8> {
        let mut m = vec![0xA3, 0x95, ty];
        m.extend_from_slice(payload);
        m
    }
    let fixed = |s: &str, n: usize| {
        let mut v = s.as_bytes().to_vec();
        v.resize(n, 0);
        v
    };
    let fmt = |ty: u8, length: u8, name: &str, format: &str, labels: &str| {
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
    for m in messages {
        let mut p = m.time_us.to_le_bytes().to_vec();
        p.push(m.instance);
        for v in m.gyro.into_iter().chain([0.0f32, 0.0, -9.8]) {
            p.extend_from_slice(&v.to_le_bytes());
        }
        p.extend_from_slice(&[0; 8]);
        p.extend_from_slice(&m.temp_c.to_le_bytes());
        p.extend_from_slice(&[1, 1, 0xE8, 0x03, 0xE8, 0x03]);
        b.extend(message(163, &p));
    }
    b
}
