//! The thermal side of the simulator: chamber program, housing lag, heat diffusion in the coil.

use super::profile::{GyroParams, Profile, Segment};

/// The chamber program as a piecewise-linear setpoint over time.
#[derive(Debug, Clone)]
pub(crate) struct Program {
    /// Breakpoint times, s, non-decreasing, starting at 0.
    times: Vec<f64>,
    /// Air temperature at each breakpoint, °C.
    temps: Vec<f64>,
}

impl Program {
    pub(crate) fn new(profile: &Profile) -> Program {
        let mut times = vec![0.0];
        let mut temps = vec![profile.start_c];
        let (mut t, mut temp) = (0.0, profile.start_c);
        for seg in &profile.program {
            t += seg.duration_from(temp);
            if let Segment::Ramp { to_c, .. } = *seg {
                temp = to_c;
            }
            times.push(t);
            temps.push(temp);
        }
        Program { times, temps }
    }

    /// Air temperature at time `t`, °C (held at the ends).
    pub(crate) fn air_c(&self, t: f64) -> f64 {
        // First breakpoint strictly after t: t lies in [times[k-1], times[k]).
        let k = self.times.partition_point(|&x| x <= t);
        if k == 0 {
            return self.temps[0];
        }
        if k == self.times.len() {
            return *self.temps.last().expect("a program has a start");
        }
        let (t0, t1) = (self.times[k - 1], self.times[k]);
        let (a, b) = (self.temps[k - 1], self.temps[k]);
        if t1 > t0 {
            a + (b - a) * (t - t0) / (t1 - t0)
        } else {
            b
        }
    }
}

/// First-order lag over one step of length `dt` whose input moves linearly from `u0` to `u1`:
/// the exact solution, so the housing is right at any step length.
pub(crate) fn lag_step(y0: f64, u0: f64, u1: f64, dt: f64, tau: f64) -> f64 {
    let slope = (u1 - u0) / dt;
    let a = (-dt / tau).exp();
    u1 - slope * tau + (y0 - u0 + slope * tau) * a
}

/// The fibre winding as a stack of radial layers exchanging heat by diffusion.
///
/// Finite volumes in cylindrical geometry between `coil_inner_radius_m` (adiabatic: the spool
/// side) and `coil_outer_radius_m` (held by the housing through half a layer). The diffusivity
/// of each face is evaluated at the mean temperature of its two sides, so the winding conducts
/// faster when warm. Steps are explicit (forward Euler) with as many sub-steps as stability
/// needs, so any step length is safe.
#[derive(Debug, Clone)]
pub struct Coil {
    params: GyroParams,
    /// Layer temperatures, inner (index 0) to outer, °C.
    temps: Vec<f64>,
    /// Cell-centre radii, m.
    radii: Vec<f64>,
    /// Layer thickness, m.
    dr: f64,
    /// Share of the fibre length in each layer (∝ radius), summing to 1.
    fibre: Vec<f64>,
    /// Fibre share times the centred radial coordinate (−1 inner … +1 outer), summing to 0:
    /// the weights of the Shupe and stress terms.
    weights: Vec<f64>,
    scratch: Vec<f64>,
}

impl Coil {
    /// A winding in equilibrium at `temp_c`.
    ///
    /// # Panics
    /// When `params.check()` fails.
    pub fn new(params: &GyroParams, temp_c: f64) -> Coil {
        if let Err(e) = params.check() {
            panic!("invalid gyro parameters: {e}");
        }
        let n = params.coil_layers;
        let (r_in, r_out) = (params.coil_inner_radius_m, params.coil_outer_radius_m);
        let dr = (r_out - r_in) / n as f64;
        let radii: Vec<f64> = (0..n).map(|i| r_in + (i as f64 + 0.5) * dr).collect();
        let sum_r: f64 = radii.iter().sum();
        let fibre: Vec<f64> = radii.iter().map(|r| r / sum_r).collect();
        let r_mean: f64 = fibre.iter().zip(&radii).map(|(f, r)| f * r).sum();
        let half = 0.5 * (r_out - r_in);
        let weights = fibre
            .iter()
            .zip(&radii)
            .map(|(f, r)| f * (r - r_mean) / half)
            .collect();
        Coil {
            params: params.clone(),
            temps: vec![temp_c; n],
            radii,
            dr,
            fibre,
            weights,
            scratch: vec![0.0; n],
        }
    }

    /// Makes this winding's temperatures those of `other` (a winding of the same gyro)
    /// without allocating.
    pub(crate) fn copy_from(&mut self, other: &Coil) {
        self.temps.copy_from_slice(&other.temps);
    }

    /// Makes this winding's temperatures, layer by layer, the straight line from `a` (at
    /// `f` = 0) to `b` (at `f` = 1), windings of the same gyro.
    pub(crate) fn interpolate(&mut self, a: &Coil, b: &Coil, f: f64) {
        for ((t, x), y) in self.temps.iter_mut().zip(&a.temps).zip(&b.temps) {
            *t = x + (y - x) * f;
        }
    }

    /// Layer temperatures, inner layer first, °C.
    pub fn layers_c(&self) -> &[f64] {
        &self.temps
    }

    /// Fibre-length-weighted mean temperature of the winding, °C (what K0 depends on).
    pub fn mean_c(&self) -> f64 {
        self.fibre.iter().zip(&self.temps).map(|(f, t)| f * t).sum()
    }

    /// Fibre-weighted radial temperature difference, °C: positive when the outside is warmer.
    pub fn gradient_c(&self) -> f64 {
        self.weights
            .iter()
            .zip(&self.temps)
            .map(|(w, t)| w * t)
            .sum()
    }

    /// Fibre-weighted radial difference of heating rates with the outer surface at `outer_c`,
    /// °C/s: positive when the outside heats faster. Exact for the current state (the
    /// right-hand side of the diffusion equation), not a finite difference.
    pub fn rate_gradient_c_per_s(&mut self, outer_c: f64) -> f64 {
        let mut rates = std::mem::take(&mut self.scratch);
        self.rates(outer_c, &mut rates);
        let g = self.weights.iter().zip(&rates).map(|(w, r)| w * r).sum();
        self.scratch = rates;
        g
    }

    /// dT/dt of every layer with the outer surface at `outer_c`, °C/s; returns the largest
    /// exchange coefficient, 1/s (the explicit step must stay below its inverse).
    fn rates(&self, outer_c: f64, out: &mut [f64]) -> f64 {
        let p = &self.params;
        let n = self.temps.len();
        let dr = self.dr;
        let r_in = p.coil_inner_radius_m;
        let mut max_coeff: f64 = 0.0;
        // Conductance of the face below layer i (0 for the adiabatic inner face) and the
        // temperature on its other side.
        let mut g_below = 0.0;
        let mut t_below = 0.0;
        for (i, (rate, &t)) in out.iter_mut().zip(&self.temps).enumerate() {
            let (g_above, t_above) = if i + 1 < n {
                let r_face = r_in + (i + 1) as f64 * dr;
                let k = p.diffusivity_m2_per_s(0.5 * (t + self.temps[i + 1]));
                (k * r_face / dr, self.temps[i + 1])
            } else {
                let k = p.diffusivity_m2_per_s(0.5 * (t + outer_c));
                (k * p.coil_outer_radius_m / (0.5 * dr), outer_c)
            };
            let vol = self.radii[i] * dr;
            *rate = (g_below * (t_below - t) + g_above * (t_above - t)) / vol;
            max_coeff = max_coeff.max((g_below + g_above) / vol);
            g_below = g_above;
            t_below = t;
        }
        max_coeff
    }

    /// Advances the winding by `dt_s` while the outer surface moves linearly from `outer_from_c`
    /// to `outer_to_c`.
    pub fn step(&mut self, outer_from_c: f64, outer_to_c: f64, dt_s: f64) {
        if dt_s <= 0.0 {
            return;
        }
        let mut rates = std::mem::take(&mut self.scratch);
        // Stability of forward Euler needs dt·max_coeff ≤ 1; 0.5 keeps it well damped. The
        // diffusivity can grow a little within the step, which the margin covers.
        let max_coeff = self.rates(outer_from_c.max(outer_to_c), &mut rates);
        let subs = ((dt_s * max_coeff / 0.5).ceil() as usize).max(1);
        let h = dt_s / subs as f64;
        for k in 0..subs {
            let frac = (k as f64 + 0.5) / subs as f64;
            let outer = outer_from_c + (outer_to_c - outer_from_c) * frac;
            self.rates(outer, &mut rates);
            for (t, r) in self.temps.iter_mut().zip(&rates) {
                *t += h * r;
            }
        }
        self.scratch = rates;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn program_interpolates_and_holds() {
        let mut p = super::super::profile("calibration").unwrap();
        p.program = vec![
            Segment::Hold { duration_s: 10.0 },
            Segment::Ramp {
                to_c: 30.0,
                rate_c_per_min: 60.0,
            },
        ];
        let prog = Program::new(&p);
        assert_eq!(prog.air_c(0.0), 20.0);
        assert_eq!(prog.air_c(10.0), 20.0);
        assert!((prog.air_c(15.0) - 25.0).abs() < 1e-12);
        assert_eq!(prog.air_c(20.0), 30.0);
        assert_eq!(prog.air_c(1e6), 30.0);
    }

    #[test]
    fn lag_step_is_exact_for_a_ramp() {
        // y' = (u - y)/tau, u = s·t, y(0) = 0: y = s·(t - tau·(1 - e^(-t/tau))).
        let (s, tau) = (0.1, 50.0);
        let mut y = 0.0;
        for i in 0..100 {
            y = lag_step(y, s * i as f64, s * (i + 1) as f64, 1.0, tau);
        }
        let exact = s * (100.0 - tau * (1.0 - (-100.0f64 / tau).exp()));
        assert!((y - exact).abs() < 1e-10, "{y} vs {exact}");
    }
}
