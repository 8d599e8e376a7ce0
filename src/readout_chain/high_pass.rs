//! The first-order high-pass dy/dt + y / tau = dx/dt, integrated exactly for an input that is
//! linear between samples (an exponential integrator): no step-size error for piecewise-linear
//! input, and a jump (two samples at the same time) passes straight through.

/// phi(z) = (1 - e^-z) / z, with phi(0) = 1, accurate for small z (expm1).
fn phi(z: f64) -> f64 {
    if z == 0.0 {
        1.0
    } else {
        -(-z).exp_m1() / z
    }
}

/// The output of the high-pass with time constant `tau_s` for the input `x` sampled at `t_s`
/// (non-decreasing; equal times make a jump), starting at rest: y(t_0) = 0 (the input had been
/// x(t_0) forever before).
///
/// Between samples x has the slope s = dx / h, so y(t + h) = y(t) e^(-h/tau) + s tau (1 -
/// e^(-h/tau)) = y(t) e^(-h/tau) + dx phi(h/tau) exactly (variation of constants; Hochbruck &
/// Ostermann, Exponential integrators, Acta Numerica 2010, sec. 2). Panics if the lengths
/// differ, a time step is negative or not finite, or tau is not positive (misuse).
#[track_caller]
pub fn high_pass(t_s: &[f64], x: &[f64], tau_s: f64) -> Vec<f64> {
    assert_eq!(t_s.len(), x.len(), "one input value per time");
    assert!(tau_s > 0.0 && tau_s.is_finite(), "tau must be positive");
    let mut y = Vec::with_capacity(x.len());
    if x.is_empty() {
        return y;
    }
    y.push(0.0);
    for k in 1..x.len() {
        let h = t_s[k] - t_s[k - 1];
        assert!(h >= 0.0 && h.is_finite(), "times must be non-decreasing");
        let z = h / tau_s;
        let prev = y[k - 1];
        y.push(prev * (-z).exp() + (x[k] - x[k - 1]) * phi(z));
    }
    y
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::readout_chain::front_end::high_pass_response;
    use std::f64::consts::PI;

    fn grid(t_end: f64, n: usize) -> Vec<f64> {
        (0..=n).map(|k| t_end * k as f64 / n as f64).collect()
    }

    #[test]
    fn a_step_decays_as_exp_minus_t_over_tau() {
        let tau = 0.37;
        // A unit step at t = 0: two samples at t = 0, then held.
        let mut t = vec![0.0];
        t.extend(grid(2.0, 40));
        let mut x = vec![0.0];
        x.extend(std::iter::repeat_n(1.0, 41));
        let y = high_pass(&t, &x, tau);
        let worst = t
            .iter()
            .zip(&y)
            .skip(1)
            .map(|(&t, &y)| (y - (-t / tau).exp()).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-14, "step response off by {worst}");
    }

    #[test]
    fn a_ramp_is_exact_at_any_step_size() {
        // Ramp of slope 3 for 0.5 s, then held: y = 3 tau (1 - e^-t/tau) while ramping, then
        // decays from there. The closed form at the sample times, for coarse and fine steps.
        let tau = 0.2;
        let exact = |t: f64| {
            let at_end = 3.0 * tau * (1.0 - (-0.5f64 / tau).exp());
            if t <= 0.5 {
                3.0 * tau * (1.0 - (-t / tau).exp())
            } else {
                at_end * (-(t - 0.5) / tau).exp()
            }
        };
        let input = |t: f64| 3.0 * t.min(0.5);
        for n in [4, 10, 1000] {
            // The corner at 0.5 s is on every grid.
            let t = grid(1.5, 3 * n);
            let x: Vec<f64> = t.iter().map(|&t| input(t)).collect();
            let y = high_pass(&t, &x, tau);
            for (&t, &y) in t.iter().zip(&y) {
                assert!(
                    (y - exact(t)).abs() < 1e-13,
                    "n {n}, t {t}: {y} vs {}",
                    exact(t)
                );
            }
        }
    }

    #[test]
    fn a_sine_settles_to_the_first_order_gain_and_phase() {
        let (tau, f) = (0.05, 5.0);
        let w = 2.0 * PI * f;
        let n = 20_000;
        let t = grid(2.0, n);
        let x: Vec<f64> = t.iter().map(|&t| (w * t).sin()).collect();
        let y = high_pass(&t, &x, tau);
        let (gain, lead) = high_pass_response(f, tau);
        // After 40 tau the transient is e^-40: compare with A sin(w t + lead).
        let worst = t
            .iter()
            .zip(&y)
            .filter(|(t, _)| **t > 40.0 * tau)
            .map(|(&t, &y)| (y - gain * (w * t + lead).sin()).abs())
            .fold(0.0, f64::max);
        // Linear interpolation of the sine between samples: error ~ (w h)^2 / 8.
        let h = 2.0 / n as f64;
        assert!(worst < (w * h).powi(2), "worst {worst:.2e}");
        assert!((gain - w * tau / (1.0 + (w * tau).powi(2)).sqrt()).abs() < 1e-15);
    }

    #[test]
    fn a_constant_input_decays_to_zero_and_the_filter_is_linear() {
        let tau = 0.1;
        let t = grid(3.0, 300);
        let ramp_hold: Vec<f64> = t.iter().map(|&t| (t / 0.2).min(1.0)).collect();
        let y = high_pass(&t, &ramp_hold, tau);
        // 28 tau after the hold begins.
        assert!(
            y.last().unwrap().abs() < 1e-12 * 1.0,
            "DC left: {}",
            y.last().unwrap()
        );
        let other: Vec<f64> = t.iter().map(|&t| (7.0 * t).cos()).collect();
        let yo = high_pass(&t, &other, tau);
        let mix: Vec<f64> = ramp_hold
            .iter()
            .zip(&other)
            .map(|(a, b)| 2.5 * a - 0.7 * b)
            .collect();
        let ym = high_pass(&t, &mix, tau);
        for k in 0..t.len() {
            assert!((ym[k] - (2.5 * y[k] - 0.7 * yo[k])).abs() < 1e-13);
        }
    }
}
