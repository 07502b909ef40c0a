//! The calibration file reader on arbitrary text. A model that loads is also used the way
//! `driftlab apply` and a gyro's firmware use it: written back and read again, then applied to
//! a short log in batch and one sample at a time.
#![no_main]

use driftlab::log::{Channel, Log};
use driftlab::{files::calibration, models::fitted};
use libfuzzer_sys::fuzz_target;
use std::path::Path;

/// A short 1 Hz ramp with every channel the model reads.
fn short_log(model: &fitted::DriftModel) -> Log {
    let n = 48;
    let time: Vec<f64> = (0..n).map(|i| i as f64).collect();
    let temp: Vec<f64> = time.iter().map(|t| 20.0 + 0.05 * t).collect();
    let omega: Vec<f64> = time.iter().map(|t| 0.1 + 0.001 * t).collect();
    let mut log = Log::from_columns("fuzz.csv", time, omega, temp.clone());
    let (temp2, channels) = model.inputs();
    for name in temp2.into_iter().chain(channels) {
        if log.channel(&name).is_none() {
            log.extra.push(Channel {
                name,
                unit: String::new(),
                values: temp.iter().map(|t| t - 1.0).collect(),
            });
        }
    }
    log
}

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let path = Path::new("fuzz-cal.json");
    let _ = calibration::from_json(path, &text);
    if let Ok(model) = calibration::model_from_json(path, &text) {
        let back = calibration::model_to_json(&model);
        let again = calibration::model_from_json(path, &back);
        assert!(again.is_ok(), "a loaded model must read back: {again:?}");
        let log = short_log(&model);
        let _ = model.correct(&log);
        if let Ok((t2, ch)) = fitted::stream_inputs(&model, &log)
            && let Ok(mut c) = model.corrector_for(log.nominal_dt_s())
        {
            let mut row = vec![0.0; ch.len()];
            for i in 0..log.len() {
                for (v, c) in row.iter_mut().zip(&ch) {
                    *v = c[i];
                }
                let _ = c.push(log.time_s[i], log.omega_dph[i], log.temp_c[i], t2[i], &row);
            }
        }
    }
});
