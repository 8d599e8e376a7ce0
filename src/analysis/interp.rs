//! Monotone piecewise-cubic interpolation (PCHIP: Fritsch & Carlson, SIAM J. Numer. Anal. 17(2)
//! 1980, with the Fritsch-Butland harmonic-mean slopes), its inverse on a monotone branch, and a
//! tensor-product version on a grid. Calibration curves go through the FE samples exactly and do
//! not overshoot between them, so a monotone sampled curve stays invertible.

/// A PCHIP curve through (x_i, y_i), x strictly increasing.
#[derive(Debug, Clone, PartialEq)]
pub struct Pchip {
    x: Vec<f64>,
    y: Vec<f64>,
    d: Vec<f64>,
}

impl Pchip {
    /// Panics (misuse) unless there are two or more points with strictly increasing x.
    #[track_caller]
    pub fn new(x: &[f64], y: &[f64]) -> Self {
        assert!(
            x.len() >= 2 && x.len() == y.len(),
            "PCHIP needs >= 2 points and as many y as x"
        );
        assert!(
            x.windows(2).all(|w| w[1] > w[0]),
            "PCHIP needs strictly increasing x"
        );
        let n = x.len();
        let h: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
        let delta: Vec<f64> = (0..n - 1).map(|i| (y[i + 1] - y[i]) / h[i]).collect();
        let mut d = vec![0.0; n];
        if n == 2 {
            d = vec![delta[0]; 2];
        } else {
            for i in 1..n - 1 {
                // Weighted harmonic mean where the secants agree in sign, else a flat slope.
                if delta[i - 1] * delta[i] > 0.0 {
                    let w1 = 2.0 * h[i] + h[i - 1];
                    let w2 = h[i] + 2.0 * h[i - 1];
                    d[i] = (w1 + w2) / (w1 / delta[i - 1] + w2 / delta[i]);
                }
            }
            d[0] = end_slope(h[0], h[1], delta[0], delta[1]);
            d[n - 1] = end_slope(h[n - 2], h[n - 3], delta[n - 2], delta[n - 3]);
        }
        Pchip {
            x: x.to_vec(),
            y: y.to_vec(),
            d,
        }
    }

    pub fn x_range(&self) -> (f64, f64) {
        (self.x[0], self.x[self.x.len() - 1])
    }

    /// Value at `t`; outside the data the end cubic is continued (callers clamp where it matters).
    pub fn eval(&self, t: f64) -> f64 {
        let n = self.x.len();
        let i = self.x.partition_point(|&v| v <= t).clamp(1, n - 1) - 1;
        let h = self.x[i + 1] - self.x[i];
        let s = (t - self.x[i]) / h;
        // Cubic Hermite basis.
        let h00 = (1.0 + 2.0 * s) * (1.0 - s) * (1.0 - s);
        let h10 = s * (1.0 - s) * (1.0 - s);
        let h01 = s * s * (3.0 - 2.0 * s);
        let h11 = s * s * (s - 1.0);
        h00 * self.y[i] + h10 * h * self.d[i] + h01 * self.y[i + 1] + h11 * h * self.d[i + 1]
    }

    /// The t in [lo, hi] with eval(t) = target, by bisection; None unless target lies between the
    /// end values (the caller picks a monotone branch).
    pub fn solve(&self, target: f64, lo: f64, hi: f64) -> Option<f64> {
        let (mut a, mut b) = (lo, hi);
        let (fa, fb) = (self.eval(a) - target, self.eval(b) - target);
        if fa == 0.0 {
            return Some(a);
        }
        if fb == 0.0 {
            return Some(b);
        }
        if fa * fb > 0.0 {
            return None;
        }
        let rising = fb > fa;
        for _ in 0..200 {
            let m = 0.5 * (a + b);
            if m <= a || m >= b {
                break;
            }
            let fm = self.eval(m) - target;
            if (fm < 0.0) == rising {
                a = m;
            } else {
                b = m;
            }
        }
        Some(0.5 * (a + b))
    }
}

/// Three-point end slope, limited so the end interval stays monotone (Moler, NCM, pchip.m).
fn end_slope(h0: f64, h1: f64, del0: f64, del1: f64) -> f64 {
    let d = ((2.0 * h0 + h1) * del0 - h0 * del1) / (h0 + h1);
    if d.signum() != del0.signum() {
        0.0
    } else if del0.signum() != del1.signum() && d.abs() > 3.0 * del0.abs() {
        3.0 * del0
    } else {
        d
    }
}

/// Tensor-product PCHIP on a grid: `values[j][i]` at (`xs[i]`, `ys[j]`); PCHIP in x along each row,
/// then PCHIP in y through the row values.
pub fn grid_eval(xs: &[f64], ys: &[f64], values: &[Vec<f64>], x: f64, y: f64) -> f64 {
    let col: Vec<f64> = values
        .iter()
        .map(|row| Pchip::new(xs, row).eval(x))
        .collect();
    Pchip::new(ys, &col).eval(y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passes_through_the_data_and_reproduces_a_line_exactly() {
        let x = [0.0, 1.0, 2.5, 4.0, 7.0];
        let line: Vec<f64> = x.iter().map(|t| 3.0 - 2.0 * t).collect();
        let p = Pchip::new(&x, &line);
        for t in [0.0, 0.3, 1.7, 3.9, 6.5, 7.0] {
            assert!((p.eval(t) - (3.0 - 2.0 * t)).abs() < 1e-12, "t = {t}");
        }
        let y = [0.0, 0.1, 2.0, 2.05, 5.0];
        let q = Pchip::new(&x, &y);
        for (a, b) in x.iter().zip(&y) {
            assert!((q.eval(*a) - b).abs() < 1e-14);
        }
    }

    #[test]
    fn stays_monotone_on_monotone_data_and_inverts_it() {
        // A step-like data set where a natural cubic spline overshoots.
        let x = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0];
        let y = [0.0, 0.0, 0.1, 0.9, 1.0, 1.0];
        let p = Pchip::new(&x, &y);
        let mut prev = p.eval(0.0);
        for k in 1..=500 {
            let v = p.eval(5.0 * k as f64 / 500.0);
            assert!(v >= prev - 1e-15 && (-1e-15..=1.0 + 1e-15).contains(&v));
            prev = v;
        }
        for target in [0.05, 0.5, 0.95] {
            let t = p.solve(target, 1.0, 4.0).expect("bracketed");
            assert!((p.eval(t) - target).abs() < 1e-12);
        }
        assert!(p.solve(1.5, 1.0, 4.0).is_none());
    }

    #[test]
    fn converges_at_third_order_or_better_on_a_smooth_function() {
        // Max error on sin over [0, pi/2] with n and 2n intervals; PCHIP is O(h^3) at worst here.
        let err = |n: usize| {
            let x: Vec<f64> = (0..=n)
                .map(|i| std::f64::consts::FRAC_PI_2 * i as f64 / n as f64)
                .collect();
            let y: Vec<f64> = x.iter().map(|t| t.sin()).collect();
            let p = Pchip::new(&x, &y);
            (0..=1000)
                .map(|k| std::f64::consts::FRAC_PI_2 * k as f64 / 1000.0)
                .map(|t| (p.eval(t) - t.sin()).abs())
                .fold(0.0, f64::max)
        };
        let (e1, e2) = (err(8), err(16));
        assert!(e2 < 1e-3 && e1 / e2 > 4.0, "{e1} {e2}");
    }

    #[test]
    fn grid_reproduces_a_bilinear_function() {
        let xs = [0.0, 1.0, 3.0];
        let ys = [0.0, 2.0, 3.0, 5.0];
        let f = |x: f64, y: f64| 1.0 + 2.0 * x - y + 0.5 * x * y;
        let v: Vec<Vec<f64>> = ys
            .iter()
            .map(|&y| xs.iter().map(|&x| f(x, y)).collect())
            .collect();
        for (x, y) in [(0.5, 1.0), (2.2, 4.1), (3.0, 0.0)] {
            assert!((grid_eval(&xs, &ys, &v, x, y) - f(x, y)).abs() < 1e-12);
        }
    }
}
