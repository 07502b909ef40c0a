//! Campaigns: several chamber runs of one gyro, as a gyro maker makes them to fit one
//! calibration on all of them and to judge its bias repeatability and thermal hysteresis.
//!
//! A [`Campaign`] is a list of [`CampaignRun`]s, each a [`Profile`] (its chamber program), a
//! seed and a **turn-on offset**: a constant bias, °/h, that the gyro takes at power-on and
//! keeps for the run, which no temperature explains (a repeat "on another day"). Every run's
//! profile has the same gyro (`gyro`, `axes`, `accelerometers`, `laser`): one unit,
//! [`Campaign::check`] refuses anything else.
//!
//! [`simulate_campaign`] simulates each run as [`simulate`] does with its own seed (its
//! temperature starting in equilibrium at its profile's `start_c`, its noise from its seed's
//! streams) and then adds the run's offset to every gyro axis's `omega_dph` **and**
//! `thermal_dph`: the truth of a campaign run is what a perfect calibration plus that run's
//! offset would predict. The parts of the drift (`static_dph`, `shupe_dph`, `stress_dph`) stay
//! the gyro's own, the same curve in every run, so that in a campaign run `thermal_dph =
//! static_dph + shupe_dph + stress_dph + turn-on offset`. Each run records its place,
//! [`SimRun::campaign`] ([`RunOfCampaign`]: the campaign, the run's name, the offset).
//!
//! # Hysteresis
//!
//! The simulated gyro has **no static thermal hysteresis**. Its static bias K0 is a function of
//! the winding's mean temperature alone; the heating/cooling asymmetry of the model (the factor
//! `1 + a·tanh(Σwᵢ·Tᵢ / 0.5 °C)`, see the module doc of [`crate::sim`]) multiplies only the
//! transient Shupe and stress terms, which die out as the winding settles on a plateau. A
//! plateau long enough for the winding to settle therefore reads K0(T) plus the run's offset
//! whichever way the chamber approached it: biases at a temperature approached heating and
//! cooling agree to the noise. What the direction does change is the transient at the start of
//! a plateau (opposite sign, and ×(1 ± a)), so on plateaus too short to settle (the `tiny`
//! campaign's) a plateau mean can differ by direction; that is the unsettled transient, not
//! hysteresis. There is no hysteresis knob: the model holds none to turn.
//!
//! # Built-in campaigns
//!
//! [`campaign_names`] lists them, [`campaign`] gives one:
//!
//! * `fog-three-runs`: (1) `heating`, the `calibration` profile (plateaus 20, 60, −50, 20 °C,
//!   heating first at 1 °C/min, 670 min), seed 1, no offset; (2) `repeat`, the same program on
//!   another day, seed 2, turn-on offset +0.05 °/h; (3) `cooling`, seed 3, no offset: soaked at
//!   60 °C, then cooling at 0.5 °C/min through plateaus at 40, 20, 0 and −20 °C (80 min each,
//!   560 min). 20 °C is approached heating in run 1 (its last plateau) and cooling in run 3; 60 °C
//!   heating in run 1 and from a soak in run 3; 0, 40 and −20 °C are visited by run 3 alone.
//!   At the end of every plateau of this campaign the drift is K0 plus the offset to 0.001 °/h,
//!   and the mean of its second half to 0.003 °/h: the settled plateaus it is made for.
//! * `tiny-three-runs`, for fast tests: (1) `heating`, 20, 40, 0, 20 °C at 1 °C/min, 25-min
//!   plateaus (180 min), seed 1; (2) `repeat`, seed 2, offset +0.05 °/h; (3) `cooling`, seed 3:
//!   soaked at 40 °C, then 30, 20 and 10 °C at 0.5 °C/min (160 min). 20 °C is approached
//!   heating in run 1 and cooling in run 3. Its plateaus are too short for the winding to
//!   settle: after a ramp, the drift still differs from K0 by 0.03–0.04 °/h at a plateau's end
//!   (0.02 after the cooling run's slower ramps) and by 0.03–0.08 °/h over its second half, the
//!   size of the offset, with the sign of the ramp. It exercises the shapes and the plumbing
//!   of campaigns; a bias repeatability or hysteresis judged on it measures that transient
//!   (take the truth, or `fog-three-runs`).

use serde_json::Value;

use crate::error::Invalid;

use super::profile::{Profile, Segment, profile};
use super::{SimRun, simulate};

/// One chamber run of a campaign.
#[derive(Debug, Clone, PartialEq)]
pub struct CampaignRun {
    /// The run's name, unique in its campaign (`heating`, `repeat`): a file of it is named
    /// `<campaign>-<run>.csv`.
    pub name: String,
    /// The chamber program and the gyro.
    pub profile: Profile,
    /// Seed of the run's noise.
    pub seed: u64,
    /// Constant bias the gyro took at this run's power-on, °/h: added to every gyro axis's
    /// output and truth.
    pub turn_on_offset_dph: f64,
}

/// Several chamber runs of one gyro.
#[derive(Debug, Clone, PartialEq)]
pub struct Campaign {
    /// Short name (`fog-three-runs`).
    pub name: String,
    /// One sentence on what the campaign is for.
    pub description: String,
    /// The runs, in the order they were made.
    pub runs: Vec<CampaignRun>,
}

/// Where a simulated run sits in its campaign ([`SimRun::campaign`]).
#[derive(Debug, Clone, PartialEq)]
pub struct RunOfCampaign {
    /// The campaign's name.
    pub campaign: String,
    /// The run's name in it.
    pub run: String,
    /// The turn-on offset in the run's `omega_dph` and `thermal_dph` (every axis's), °/h.
    pub turn_on_offset_dph: f64,
}

impl Campaign {
    /// Checks that the campaign can be simulated and is one gyro: at least one run, names
    /// that are not empty and not given twice, finite offsets, every profile valid
    /// ([`Profile::check`]), and every run's `gyro`, `axes`, `accelerometers` and `laser`
    /// those of the first run.
    ///
    /// # Errors
    /// The first problem, naming the run (`runs.cooling`) and, for another gyro, the constant
    /// that differs and both its values.
    pub fn check(&self) -> Result<(), Invalid> {
        let Some(first) = self.runs.first() else {
            return Err(Invalid::new("runs", "a campaign needs at least one run"));
        };
        let mut names = std::collections::HashSet::new();
        for run in &self.runs {
            let field = format!("runs.{}", run.name);
            if run.name.is_empty() {
                return Err(Invalid::new("runs", "a run has no name"));
            }
            if !names.insert(run.name.as_str()) {
                return Err(Invalid::new(
                    "runs",
                    format!("two runs are named {:?}", run.name),
                ));
            }
            if !run.turn_on_offset_dph.is_finite() {
                return Err(Invalid::new(
                    format!("{field}.turn_on_offset_dph"),
                    format!("must be finite, got {}", run.turn_on_offset_dph),
                ));
            }
            run.profile
                .check()
                .map_err(|e| Invalid::new(format!("{field}.profile.{}", e.field), e.reason))?;
            if let Some((path, theirs, ours)) = gyro_difference(&first.profile, &run.profile) {
                return Err(Invalid::new(
                    format!("{field}.profile.{path}"),
                    format!(
                        "a campaign is one gyro: run {:?} has {ours} where run {:?} has {theirs}",
                        run.name, first.name
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The run named `name`.
    pub fn run(&self, name: &str) -> Option<&CampaignRun> {
        self.runs.iter().find(|r| r.name == name)
    }

    /// The file name of run `run` of this campaign: `<campaign>-<run>.csv`.
    pub fn file_name(&self, run: &CampaignRun) -> String {
        format!("{}-{}.csv", self.name, run.name)
    }
}

/// The first constant in which the gyro of `b` differs from that of `a` (its path, as
/// `gyro.bias_slope_dph_per_c` or `axes[1].name`, then `a`'s and `b`'s values), or `None`
/// for the same gyro.
fn gyro_difference(a: &Profile, b: &Profile) -> Option<(String, String, String)> {
    let parts = |p: &Profile| -> [(&'static str, Value); 4] {
        // Plain data of derived Serialize: its JSON cannot fail.
        let json = |v: Result<Value, serde_json::Error>| v.unwrap_or(Value::Null);
        [
            ("gyro", json(serde_json::to_value(&p.gyro))),
            ("axes", json(serde_json::to_value(&p.axes))),
            (
                "accelerometers",
                json(serde_json::to_value(&p.accelerometers)),
            ),
            ("laser", json(serde_json::to_value(&p.laser))),
        ]
    };
    parts(a)
        .into_iter()
        .zip(parts(b))
        .find_map(|((name, x), (_, y))| first_difference(name.to_string(), &x, &y))
}

fn first_difference(path: String, a: &Value, b: &Value) -> Option<(String, String, String)> {
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            let keys = x.keys().chain(y.keys().filter(|k| !x.contains_key(*k)));
            for k in keys {
                let (u, v) = (
                    x.get(k).unwrap_or(&Value::Null),
                    y.get(k).unwrap_or(&Value::Null),
                );
                if let Some(d) = first_difference(format!("{path}.{k}"), u, v) {
                    return Some(d);
                }
            }
            None
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => x
            .iter()
            .zip(y)
            .enumerate()
            .find_map(|(i, (u, v))| first_difference(format!("{path}[{i}]"), u, v)),
        (Value::Array(x), Value::Array(y)) => Some((
            path,
            format!("{} of them", x.len()),
            format!("{} of them", y.len()),
        )),
        _ if a == b => None,
        _ => Some((path, shown(a), shown(b))),
    }
}

fn shown(v: &Value) -> String {
    match v {
        Value::Null => "none".to_string(),
        Value::Object(_) => "one".to_string(),
        other => other.to_string(),
    }
}

/// Simulates every run of `campaign` with its seed, each as [`simulate`] would (temperature
/// starting in equilibrium at its profile's `start_c`), then adds the run's turn-on offset to
/// `omega_dph` and `thermal_dph` and to every axis's: a campaign run's truth is a perfect
/// calibration's prediction plus its offset. Each returned run carries its
/// [`SimRun::campaign`]. The runs come in the campaign's order.
///
/// # Panics
/// When `campaign.check()` fails; callers holding a hand-made campaign check it first.
pub fn simulate_campaign(campaign: &Campaign) -> Vec<SimRun> {
    if let Err(e) = campaign.check() {
        panic!("invalid campaign {:?}: {e}", campaign.name);
    }
    campaign
        .runs
        .iter()
        .map(|r| {
            let mut run = simulate(&r.profile, r.seed);
            run.add_turn_on_offset(r.turn_on_offset_dph);
            run.campaign = Some(RunOfCampaign {
                campaign: campaign.name.clone(),
                run: r.name.clone(),
                turn_on_offset_dph: r.turn_on_offset_dph,
            });
            run
        })
        .collect()
}

impl SimRun {
    /// Adds `offset_dph` to the output and the truth of every gyro axis.
    fn add_turn_on_offset(&mut self, offset_dph: f64) {
        let mut columns = vec![&mut self.omega_dph, &mut self.thermal_dph];
        for a in &mut self.axes {
            columns.push(&mut a.omega_dph);
            columns.push(&mut a.thermal_dph);
        }
        for col in columns {
            col.iter_mut().for_each(|x| *x += offset_dph);
        }
    }

    /// The turn-on offset in this run's output, °/h: its campaign's
    /// ([`RunOfCampaign::turn_on_offset_dph`]), 0 for a run of one profile.
    pub fn turn_on_offset_dph(&self) -> f64 {
        self.campaign.as_ref().map_or(0.0, |c| c.turn_on_offset_dph)
    }
}

/// Names of the built-in campaigns, in the order a listing shows them.
pub fn campaign_names() -> &'static [&'static str] {
    &["fog-three-runs", "tiny-three-runs"]
}

fn hold_min(minutes: f64) -> Segment {
    Segment::Hold {
        duration_s: minutes * 60.0,
    }
}

fn ramp(to_c: f64, rate_c_per_min: f64) -> Segment {
    Segment::Ramp {
        to_c,
        rate_c_per_min,
    }
}

/// A profile of the reference gyro (that of the built-in profiles) named `name`.
fn program(name: &str, description: &str, start_c: f64, program: Vec<Segment>) -> Profile {
    let mut p = profile("calibration").expect("the calibration profile is built in");
    p.name = name.to_string();
    p.description = description.to_string();
    p.start_c = start_c;
    p.program = program;
    p
}

fn run(name: &str, profile: Profile, seed: u64, turn_on_offset_dph: f64) -> CampaignRun {
    CampaignRun {
        name: name.to_string(),
        profile,
        seed,
        turn_on_offset_dph,
    }
}

/// A built-in campaign by name, or `None` for an unknown name (callers list
/// [`campaign_names`]). The module doc says what each holds.
pub fn campaign(name: &str) -> Option<Campaign> {
    let (description, runs) = match name {
        "fog-three-runs" => {
            let heating = profile("calibration").expect("the calibration profile is built in");
            let cooling = program(
                "fog-three-runs-cooling",
                "Soaked at 60 °C, then cooling at 0.5 °C/min through plateaus at 40, 20, 0 and \
                 -20 °C, 80 min each, about 9.3 h at 1 Hz.",
                60.0,
                vec![
                    hold_min(80.0),
                    ramp(40.0, 0.5),
                    hold_min(80.0),
                    ramp(20.0, 0.5),
                    hold_min(80.0),
                    ramp(0.0, 0.5),
                    hold_min(80.0),
                    ramp(-20.0, 0.5),
                    hold_min(80.0),
                ],
            );
            (
                "Three runs of the reference FOG: the calibration run (heating first), its \
                 repeat on another day (+0.05 °/h turn-on offset), and a cooling run at \
                 0.5 °C/min from 60 to -20 °C; about 31.7 h at 1 Hz in all.",
                vec![
                    run("heating", heating.clone(), 1, 0.0),
                    run("repeat", heating, 2, 0.05),
                    run("cooling", cooling, 3, 0.0),
                ],
            )
        }
        "tiny-three-runs" => {
            let heating = program(
                "tiny-three-runs-heating",
                "20, 40, 0, 20 °C at 1 °C/min, 25-min plateaus, 3 h at 1 Hz.",
                20.0,
                vec![
                    hold_min(25.0),
                    ramp(40.0, 1.0),
                    hold_min(25.0),
                    ramp(0.0, 1.0),
                    hold_min(25.0),
                    ramp(20.0, 1.0),
                    hold_min(25.0),
                ],
            );
            let cooling = program(
                "tiny-three-runs-cooling",
                "Soaked at 40 °C, then 30, 20, 10 °C at 0.5 °C/min, 25-min plateaus, about \
                 2.7 h at 1 Hz.",
                40.0,
                vec![
                    hold_min(25.0),
                    ramp(30.0, 0.5),
                    hold_min(25.0),
                    ramp(20.0, 0.5),
                    hold_min(25.0),
                    ramp(10.0, 0.5),
                    hold_min(25.0),
                ],
            );
            (
                "The fog-three-runs campaign in small, for fast tests: a heating-first run, its \
                 repeat (+0.05 °/h turn-on offset) and a cooling run at 0.5 °C/min, 25-min \
                 plateaus, about 8.7 h at 1 Hz in all.",
                vec![
                    run("heating", heating.clone(), 1, 0.0),
                    run("repeat", heating, 2, 0.05),
                    run("cooling", cooling, 3, 0.0),
                ],
            )
        }
        _ => return None,
    };
    Some(Campaign {
        name: name.to_string(),
        description: description.to_string(),
        runs,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fog() -> Campaign {
        campaign("fog-three-runs").expect("built in")
    }

    /// Mean of `values` over the last `seconds` of the hold that ends at sample `end`.
    fn tail_mean(values: &[f64], end: usize, seconds: usize) -> f64 {
        values[end - seconds..end].iter().sum::<f64>() / seconds as f64
    }

    #[test]
    fn every_built_in_campaign_is_one_gyro_and_checks() {
        for name in campaign_names() {
            let c = campaign(name).expect("listed names are built in");
            assert_eq!(c.name, *name);
            c.check().expect("built-in campaigns check");
            let gyro = &c.runs[0].profile;
            for r in &c.runs {
                assert_eq!(r.profile.gyro, gyro.gyro, "{name} {}", r.name);
                assert_eq!(r.profile.axes, gyro.axes);
                assert_eq!(r.profile.laser, gyro.laser);
            }
        }
        assert!(campaign("no-such-campaign").is_none());
    }

    #[test]
    fn turn_on_offset_is_exactly_in_output_and_truth() {
        let c = fog();
        let repeat = c.run("repeat").expect("fog-three-runs has a repeat");
        assert_eq!(repeat.turn_on_offset_dph, 0.05);
        let runs = simulate_campaign(&c);
        let with = &runs[1];
        let without = simulate(&repeat.profile, repeat.seed);
        assert_eq!(with.turn_on_offset_dph(), 0.05);
        assert_eq!(without.turn_on_offset_dph(), 0.0);
        assert_eq!(with.len(), without.len());
        for i in 0..with.len() {
            assert!((with.omega_dph[i] - without.omega_dph[i] - 0.05).abs() < 1e-12);
            assert!((with.thermal_dph[i] - without.thermal_dph[i] - 0.05).abs() < 1e-12);
            assert!((with.axes[0].omega_dph[i] - without.omega_dph[i] - 0.05).abs() < 1e-12);
            assert_eq!(with.noise_dph[i], without.noise_dph[i]);
            assert_eq!(with.temp_c[i], without.temp_c[i]);
            assert_eq!(with.axes[0].static_dph[i], without.axes[0].static_dph[i]);
        }
        // Run 1 has no offset: the calibration profile's run of seed 1, unchanged.
        let first = simulate(&c.runs[0].profile, 1);
        assert_eq!(runs[0].omega_dph, first.omega_dph);
        // The noise alone holds no offset.
        let floor = with.noise_only();
        assert_eq!(floor.omega_dph, without.noise_dph);
        assert_eq!(floor.turn_on_offset_dph(), 0.0);
    }

    #[test]
    fn offset_reaches_every_axis_of_a_unit() {
        let mut c = campaign("tiny-three-runs").expect("built in");
        for r in &mut c.runs {
            r.profile = r.profile.clone().with_axes(3).expect("a FOG takes 3 axes");
        }
        c.check().expect("three axes in every run: one unit");
        let runs = simulate_campaign(&c);
        let plain = simulate(&c.runs[1].profile, c.runs[1].seed);
        for (a, b) in runs[1].axes.iter().zip(&plain.axes) {
            for i in (0..a.omega_dph.len()).step_by(97) {
                assert!(
                    (a.omega_dph[i] - b.omega_dph[i] - 0.05).abs() < 1e-12,
                    "{}",
                    a.name
                );
                assert!((a.thermal_dph[i] - b.thermal_dph[i] - 0.05).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn runs_last_as_documented() {
        let minutes = |c: &Campaign| -> Vec<f64> {
            c.runs
                .iter()
                .map(|r| r.profile.duration_s() / 60.0)
                .collect()
        };
        assert_eq!(minutes(&fog()), [670.0, 670.0, 560.0]);
        let tiny = campaign("tiny-three-runs").expect("built in");
        assert_eq!(minutes(&tiny), [180.0, 180.0, 160.0]);
        for r in fog().runs.iter().chain(&tiny.runs) {
            assert_eq!(r.profile.sample_rate_hz, 1.0);
            assert!(r.profile.duration_s() <= 12.0 * 3600.0);
        }
        let runs = simulate_campaign(&tiny);
        assert_eq!(
            runs.iter().map(SimRun::len).collect::<Vec<_>>(),
            [10_801, 10_801, 9_601]
        );
        assert_eq!(
            runs[2].campaign.as_ref().map(|c| c.run.as_str()),
            Some("cooling")
        );
    }

    #[test]
    fn cooling_run_goes_down_first_and_shares_temperatures_with_the_heating_run() {
        for name in campaign_names() {
            let c = campaign(name).expect("built in");
            // Holds keep the temperature: the first ramp starts at `start_c`.
            let first_ramp = |p: &Profile| match p.program.iter().find_map(|s| match *s {
                Segment::Ramp { to_c, .. } => Some(to_c),
                Segment::Hold { .. } => None,
            }) {
                Some(to_c) => to_c - p.start_c,
                None => panic!("{name}: no ramp"),
            };
            let heating = &c.run("heating").expect("a heating run").profile;
            let cooling = &c.run("cooling").expect("a cooling run").profile;
            assert!(first_ramp(heating) > 0.0, "{name}");
            assert!(first_ramp(cooling) < 0.0, "{name}");
            // Plateaus: the start and every hold's temperature.
            let plateaus = |p: &Profile| {
                let mut at = p.start_c;
                let mut out = Vec::new();
                for seg in &p.program {
                    match *seg {
                        Segment::Hold { .. } => out.push(at),
                        Segment::Ramp { to_c, .. } => at = to_c,
                    }
                }
                out
            };
            let (h, k) = (plateaus(heating), plateaus(cooling));
            let shared = k.iter().filter(|t| h.contains(t)).count();
            let new = k.iter().filter(|t| !h.contains(t)).count();
            assert!(shared >= 2 && new >= 2, "{name}: {h:?} {k:?}");
            // 20 °C is the heating run's last plateau, reached heating, and is reached cooling
            // in the cooling run.
            assert_eq!(h.last(), Some(&20.0));
            let rate =
                |p: &Profile| match p.program.iter().find(|s| matches!(s, Segment::Ramp { .. })) {
                    Some(Segment::Ramp { rate_c_per_min, .. }) => *rate_c_per_min,
                    _ => f64::NAN,
                };
            assert_ne!(rate(heating), rate(cooling), "{name}: another ramp rate");
        }
    }

    #[test]
    fn settled_plateaus_read_the_same_bias_heating_and_cooling() {
        // No static hysteresis in the model: at 20 °C, the heating run's last plateau (reached
        // heating) and the cooling run's 20 °C plateau (reached cooling) read K0(20) once the
        // winding has settled; the truth agrees to far below the noise.
        let c = fog();
        let runs = simulate_campaign(&c);
        let k0 = c.runs[0].profile.gyro.static_bias_dph(20.0);
        let heating = &runs[0];
        let heating_end = heating.len() - 1;
        let cooling = &runs[2];
        // The cooling run's 20 °C hold ends at 80 + 40 + 80 + 40 + 80 min.
        let cooling_end = 320 * 60;
        assert!((cooling.chamber_c[cooling_end] - 20.0).abs() < 1e-9);
        let h = tail_mean(&heating.thermal_dph, heating_end, 600);
        let k = tail_mean(&cooling.thermal_dph, cooling_end, 600);
        assert!((h - k0).abs() < 0.005, "heating {h} vs K0 {k0}");
        assert!((k - k0).abs() < 0.005, "cooling {k} vs K0 {k0}");
    }

    #[test]
    fn check_refuses_runs_of_another_gyro_naming_the_run_and_the_constant() {
        let mut c = fog();
        c.runs[2].profile.gyro.bias_slope_dph_per_c = 0.004;
        let e = c.check().expect_err("another gyro");
        assert_eq!(e.field, "runs.cooling.profile.gyro.bias_slope_dph_per_c");
        assert!(
            e.reason.contains("0.004") && e.reason.contains("0.003"),
            "{e}"
        );
        assert!(e.reason.contains("\"heating\""), "{e}");

        let mut c = fog();
        c.runs[1].profile = c.runs[1].profile.clone().with_axes(3).expect("3 axes");
        let e = c.check().expect_err("a unit of three axes is another gyro");
        assert_eq!(e.field, "runs.repeat.profile.axes");
        assert!(e.reason.contains("3 of them"), "{e}");

        let mut c = fog();
        c.runs[1].profile = profile("laser-gyro").expect("built in");
        let e = c.check().expect_err("a laser gyro is another gyro");
        assert!(e.field.starts_with("runs.repeat.profile."), "{e}");
    }

    #[test]
    fn check_refuses_names_offsets_and_profiles_it_cannot_use() {
        let mut c = fog();
        c.runs[2].name = "heating".into();
        assert_eq!(c.check().expect_err("twice").field, "runs");
        let mut c = fog();
        c.runs[1].turn_on_offset_dph = f64::NAN;
        assert_eq!(
            c.check().expect_err("NaN").field,
            "runs.repeat.turn_on_offset_dph"
        );
        let mut c = fog();
        c.runs[2].profile.sample_rate_hz = 0.0;
        assert_eq!(
            c.check().expect_err("no rate").field,
            "runs.cooling.profile.sample_rate_hz"
        );
        let mut c = fog();
        c.runs.clear();
        assert!(c.check().is_err());
    }

    #[test]
    fn a_campaign_run_names_its_campaign_in_its_command() {
        let c = campaign("tiny-three-runs").expect("built in");
        let runs = simulate_campaign(&c);
        assert_eq!(
            runs[1].command(),
            "driftlab simulate --campaign tiny-three-runs"
        );
        assert_eq!(c.file_name(&c.runs[1]), "tiny-three-runs-repeat.csv");
    }
}
