//! Inputs that once crashed driftlab, each kept as the exact bytes that did it, with the
//! answer the user gets now. Found by the fuzz targets in `fuzz/` (see TESTING.md) or by hand
//! while writing them.

use crate::common;

use common::{Program, Truth, log_from};
use driftlab::Log;
use driftlab::files::calibration;
use driftlab::models::CheckedRecipe;
use driftlab::models::fitted::DriftModel;
use driftlab::models::presets::{ModelChoice, Preset};
use std::path::Path;

const TRUTH: Truth = Truth {
    k0: [0.2, 0.004, -6e-5],
    k1_plus: 40.0,
    k1_minus: 25.0,
    k2_plus: 2e4,
    k2_minus: -1e4,
};

/// fuzz `calibration_file`, crash-15c01800ba631085e2f0649389a74a74c1d80ead: a Sukhanov
/// regression file whose derivative step was mutated to 3·10²⁸ s. It loaded, and making its
/// streaming corrector overflowed `2 * step + 1` (a ring buffer of the step in samples): a
/// panic, or in a release build an allocation of the whole address space.
const HUGE_STEP_CALIBRATION: &[u8] = b"{
  \"format\": \"driftlab-calibration\",
  \"version\": 1,
  \"model\": \"regression\",
  \"calibration\": {
    \"gyro_id\": \"\",
    \"source\": {
      \"name\": \"calibration.csv\",
      \"sha256\": \"8d62935945dc096bebfcd0154dac67\xe33a262c1cea9de9396b04a5486f49bdd4c\",
      \"samples\": 40201,
      \"duration_s\": 40200.0
    },
    \"created\": \"2026-11-22T05\xba28:29Z\",
    \"model\": {
      \"spec\": {
        \"name\": \"sukhanov\",
        \"terms\": [
          \"1\",
          \"selfheat\",
          \"dT\",
          \"dT^2\"
        ],
        \"temp2\": \"temp_chamber_c\",
        \"delay\": {
          \"kind\": \"none\"
        },
        \"lambda\": {
          \"kind\": \"search\",
          \"min_s\": 60.0,
          \"max_s\": 21600.0
        },
        \"lag\": {
          \"kind\": \"none\"
        },
        \"smoothing_s\": 60.0,
        \"step_h_s\": 30888888888888888888888888888.0
      },
      \"temp2\": \"temp_chamber_c\",
      \"names\":
[         \"1\",
        \"selfheat\",
        \"dT\",
        \"dT^2\"
      ],
      \"coefficients\": [
        -0.09682784277669629,
        0.248029723681359,
        -0.05444526905004694,
        -0.00016696063605434674
      ],
      \"std_errors\": [
        0.004761680091701567,
        0.00535519462052064,
        0.00016345040716222433,
        0.000000000000465705932
      ],
      \"lambda_s\": 4264.275919328885,
      \"delay\": {
        \"points\": []
      },
      \"lag_s\": null,
      \"t_knots\": [],
      \"ranges\": {
        \"temp\": null,
        \"tdot\": null,
        \"tddot\": null,
        \"dt\": [
          -11.965000000000002,
          11.999000000000002
        ],
        \"channels\": []
      },
      \"dt_s\": 1.0,
      \"stats\": {
        \"n\": 40081,
        \"rmse\": 0.204714273613219,
        \"r2\": 0.7395986435182964
      },
      \"searches\": [
        {
          \"parameter\": \"lambda_s\",
          \"x\": [
            59.999999999999986,
            76.67677787352697,
         277491458,
            4264.275919328885,
            4958.817508788694,
            6337.102477279125,
            8098.4766502018265,
            10349.418253691165,
            13226.000742641705,
            16902.11868497737,
            21600.000000000015
          ],
          \"rmse\": [
            0.21005124718084883,
            0.21003033555128822,
            0.21000389005169587,
            0.2099693015445281,
            0.20992309208131907,
            0.2098607150927341,
            0.2097761085157381,
            0.20966121003737126,
            0.20950561317969435,
            0.20929623726483798,
            0.2090165419947976,
            0.2086450777170103,
            0.20815528855917523,
            0.20752316105904567,
            0.20675226998302548,
            0.20591461971625183,
            0.20517517009633476,
            0.2047526805246316,
            0.20471427361363834,
            0.20471427361322073,
            0.2048139001919328,
            0.20536666265863865,
            0.20624219976541533,
            0.20719716390124007,
            0.20804419562741,
            0.2087033792089716,
            0.2091756230975624
          ],
          \"best\": 4264.275919328885,
          \"at_edge\": false
        }
      ]
    }
  }
}
";

#[test]
fn a_calibration_asking_for_an_impossible_window_is_refused() {
    // The fuzzed file's date is garbled too (refused on its own since `created` is checked):
    // mended, so that the step is what is refused.
    let text = String::from_utf8_lossy(HUGE_STEP_CALIBRATION)
        .replace("2026-11-22T05\u{FFFD}28:29Z", "2026-11-22T05:28:29Z");
    let e = calibration::model_from_json(Path::new("sukhanov.json"), &text)
        .expect_err("a step of 3e28 s cannot be used");
    let e = e.to_string();
    assert!(
        e.starts_with("sukhanov.json: spec.step_h_s spans 3.08889e28 s"),
        "{e}"
    );
    assert!(e.contains("no corrector can hold that much history"), "{e}");
    // The same file with a 30-s step loads, and its corrector runs.
    let fixed = text.replace("30888888888888888888888888888.0", "30.0");
    let model = calibration::model_from_json(Path::new("sukhanov.json"), &fixed).unwrap();
    let (_, channels) = model.inputs();
    let mut c = model.corrector_for(1.0).unwrap();
    let out = c.push(0.0, 0.1, 20.0, 19.0, &vec![0.0; channels.len()]);
    assert!(out.omega_cor_dph.is_finite());
}

/// Found by hand while writing the fuzz targets: a log sampled every nanosecond (any strictly
/// rising time column reads). The T smoothing window of 60 s is then 6·10¹⁰ samples, and
/// `driftlab apply` aborted with "memory allocation of 480000000000 bytes failed". A causal
/// window longer than the log now holds only the log.
fn nanosecond_log() -> Log {
    let n = 2000;
    let time: Vec<f64> = (0..n).map(|i| i as f64 * 1e-9).collect();
    let temp: Vec<f64> = (0..n).map(|i| 20.0 + 0.001 * i as f64).collect();
    let omega: Vec<f64> = (0..n).map(|i| 0.1 + 1e-4 * i as f64).collect();
    Log::from_columns("ns.csv", time, omega, temp)
}

#[test]
fn a_log_sampled_every_nanosecond_is_corrected_without_exhausting_memory() {
    let train = log_from(&Program::paper_like(), &TRUTH, 0.05, 0.001, 5);
    let log = nanosecond_log();
    for choice in [
        ModelChoice::Preset(Preset::Vakhrameev),
        ModelChoice::Preset(Preset::Ieee952),
    ] {
        let model: DriftModel =
            driftlab::models::fit(&train, &choice, &CheckedRecipe::default()).unwrap();
        let c = model.correct(&log).unwrap();
        assert_eq!(c.cor_dph.len(), log.len(), "{}", model.name());
        // Every window is longer than the log: T is the running mean of all of it so far and
        // no rate is ever ready, so the prediction is that of the temperature alone.
        assert_eq!(c.ready_from, log.len(), "{}", model.name());
        assert!(c.cor_dph.iter().all(|v| v.is_finite()), "{}", model.name());
    }
}

/// The streaming side of the nanosecond log: a corrector sized its rings from the caller's
/// step, so `corrector_for(1e-9)` asked for 6·10¹⁰ samples of history and aborted. Every
/// model's corrector now refuses such a step, and a step that is not a positive number, with
/// a message; at the log's real step it runs.
#[test]
fn a_streaming_corrector_refuses_a_step_it_cannot_keep_history_for() {
    let train = log_from(&Program::paper_like(), &TRUTH, 0.05, 0.001, 5);
    for choice in [
        ModelChoice::Preset(Preset::Vakhrameev),
        ModelChoice::Preset(Preset::YanDelayed),
    ] {
        let model: DriftModel =
            driftlab::models::fit(&train, &choice, &CheckedRecipe::default()).unwrap();
        let e = model.corrector_for(1e-9).expect_err("refused").to_string();
        assert!(
            e.contains("samples of 0.000000001 s") && e.contains("streaming corrector keeps"),
            "{}: {e}",
            model.name()
        );
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let e = model.corrector_for(bad).expect_err("refused").to_string();
            assert!(e.contains("positive number of seconds"), "{e}");
        }
        assert!(model.corrector_for(train.nominal_dt_s()).is_ok());
    }
}

/// The other side of the refusal above: `driftlab calibrate --smooth 1e30` made a calibration
/// whose smoothing window saturated to 2⁶⁴ − 1 samples. It is not written, since it could not
/// be read back; the file already there stays.
#[test]
fn a_calibration_that_could_not_be_read_back_is_not_written() {
    let train = log_from(&Program::paper_like(), &TRUTH, 0.05, 0.001, 5);
    let mut cal = driftlab::models::vakhrameev::fit(&train, &CheckedRecipe::default())
        .unwrap()
        .calibration;
    cal.resolved.smooth_samples = usize::MAX;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("cal.json");
    std::fs::write(&path, "old").unwrap();
    let e = calibration::save(&path, &cal).unwrap_err().to_string();
    assert!(
        e.contains("cal.json: not written: resolved.smooth_samples"),
        "{e}"
    );
    let e = calibration::save_model(&path, &DriftModel::Vakhrameev(Box::new(cal)))
        .unwrap_err()
        .to_string();
    assert!(e.contains("not written"), "{e}");
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "old");
}

/// fuzz `read_log`, minimized from crash-cf90ca0177c941950fd2deafb85b6ba4fb8a6dc5: a stamp
/// 6·10²¹ s after steps of 200 s. Sizing the window in which later stamps may make up a gap
/// cast `4 × lost / step` (10²⁰ samples) to an integer and added 16 past its largest: a panic
/// where overflow is checked (debug builds, the fuzz targets), a wrapped count elsewhere. The
/// stamp is a stray one, dropped and told; the three rows before it are the log.
#[test]
fn a_stamp_ten_to_the_twenty_one_seconds_ahead_is_a_stray_not_an_overflow() {
    let bytes = b"599800;-0;0\n600000;00;0\n600200;-,1;0\n6055555555555555555294;105;0\n";
    let log = driftlab::log::ingest::read_bytes(
        "stamps.csv",
        bytes,
        &driftlab::log::ingest::ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(log.time_s, [599800.0, 600000.0, 600200.0]);
    assert!(
        log.info
            .problems
            .iter()
            .any(|p| p.line == 4 && p.message.contains("stray")),
        "{:?}",
        log.info.problems
    );
}
