//! A beam on a Winkler foundation, loaded at one end, free at the other: the elastic footing of a
//! plate edge (Hetenyi, Beams on Elastic Foundation, 1946, ch. II-III).
//!
//! Per unit length along the loaded end, the beam has bending stiffness `d_nm` (N m), the
//! foundation stiffness `k_pa_per_m` (N/m^3: pressure per deflection), length `length_m`
//! (infinite allowed). With lambda = (k / (4 D))^(1/4) the deflection is
//! w(s) = e^(-lambda s)(A cos + B sin)(lambda s) + e^(-lambda (L - s))(C cos + D sin)(lambda s)
//! (Hetenyi Eq. 7, the growing pair written from the far end so nothing overflows); the end
//! values (w0, theta0 = dw/ds at s = 0) and a free far end (w'' = w''' = 0) fix A..D.
//! s runs from the loaded end into the foundation; w is positive in the load direction.

/// One footing strip per unit length along its loaded end.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FootingBeam {
    /// Bending stiffness per unit width (N m).
    pub d_nm: f64,
    /// Foundation modulus (N/m^3).
    pub k_pa_per_m: f64,
    /// Length from the loaded end to the free end (m); `f64::INFINITY` for a semi-infinite beam.
    pub length_m: f64,
}

/// The four basis functions' coefficients for a given end state (A, B, C, D of the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FootingShape {
    lambda: f64,
    length_m: f64,
    coef: [f64; 4],
}

type C = (f64, f64);

fn cmul(a: C, b: C) -> C {
    (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0)
}

fn cdiv(a: C, b: C) -> C {
    let n = b.0 * b.0 + b.1 * b.1;
    ((a.0 * b.0 + a.1 * b.1) / n, (a.1 * b.0 - a.0 * b.1) / n)
}

fn cpow(a: C, n: i32) -> C {
    let mut r = (1.0, 0.0);
    for _ in 0..n {
        r = cmul(r, a);
    }
    r
}

impl FootingBeam {
    /// lambda = (k / (4 D))^(1/4) (1/m), Hetenyi Eq. 4.
    #[track_caller]
    pub fn lambda_per_m(&self) -> f64 {
        assert!(
            self.d_nm > 0.0 && self.k_pa_per_m > 0.0 && self.length_m > 0.0,
            "a footing needs D > 0, k > 0 and a length > 0"
        );
        (self.k_pa_per_m / (4.0 * self.d_nm)).powf(0.25)
    }

    /// (mu, origin, c) of basis k; None for the far pair of a semi-infinite beam.
    fn pair(lambda: f64, length_m: f64, k: usize) -> Option<(C, f64, C)> {
        let c = [(1.0, 0.0), (0.0, -1.0)][k & 1];
        if k < 2 {
            Some(((-lambda, lambda), 0.0, c))
        } else if length_m.is_finite() {
            Some(((lambda, lambda), length_m, c))
        } else {
            None
        }
    }

    /// Basis k (0..4) and its n-th derivative at s: Re(c mu^n e^(mu (s - s_k))) with
    /// (mu, c, s_k) = (lambda(-1 + i), 1 or -i, 0) for the decaying pair and
    /// (lambda(1 + i), 1 or -i, L) for the pair decaying from the far end.
    fn basis(lambda: f64, length_m: f64, k: usize, n: i32, s: f64) -> f64 {
        let Some((mu, origin, c)) = Self::pair(lambda, length_m, k) else {
            return 0.0;
        };
        // e^(mu (s - origin)) with the phase of lambda s, not lambda (s - origin): the far pair
        // is e^(lambda (s - L)) (cos, sin)(lambda s).
        let amp = (mu.0 * (s - origin)).exp();
        let ph = (lambda * s).cos();
        let ps = (lambda * s).sin();
        let e = (amp * ph, amp * ps);
        cmul(cmul(c, cpow(mu, n)), e).0
    }

    /// Integral of basis k from s0 to s1 (its antiderivative Re(c e / mu)).
    fn basis_integral(lambda: f64, length_m: f64, k: usize, s0: f64, s1: f64) -> f64 {
        let Some((mu, origin, c)) = Self::pair(lambda, length_m, k) else {
            return 0.0;
        };
        let anti = |s: f64| {
            if s.is_infinite() {
                return 0.0;
            }
            let amp = (mu.0 * (s - origin)).exp();
            let e = (amp * (lambda * s).cos(), amp * (lambda * s).sin());
            cdiv(cmul(c, e), mu).0
        };
        anti(s1) - anti(s0)
    }

    /// The shape for end deflection `w0_m` and end slope `theta0` (dw/ds at s = 0).
    pub fn shape(&self, w0_m: f64, theta0: f64) -> FootingShape {
        let lambda = self.lambda_per_m();
        let l = self.length_m;
        let b = |k, n, s| Self::basis(lambda, l, k, n, s);
        let coef = if l.is_finite() {
            // Rows: w(0), w'(0), w''(L), w'''(L).
            let a = [(0, 0.0), (1, 0.0), (2, l), (3, l)]
                .map(|(n, at)| [0, 1, 2, 3].map(|k| b(k, n, at)));
            solve4(a, [w0_m, theta0, 0.0, 0.0])
        } else {
            // A = w0, B = w0 + theta0 / lambda (Hetenyi Eq. 12 with the end values).
            [w0_m, w0_m + theta0 / lambda, 0.0, 0.0]
        };
        FootingShape {
            lambda,
            length_m: l,
            coef,
        }
    }

    /// End stiffness per unit length: [V, M] = K [w0, theta0] with V the force the end takes in
    /// the load direction and M its moment work-conjugate to theta0, from the principle of
    /// virtual work on the equilibrium shape: V = D w'''(0), M = -D w''(0). Symmetric; for the
    /// semi-infinite beam K = [[4 D l^3, 2 D l^2], [2 D l^2, 2 D l]] (l = lambda; its inverse is
    /// Hetenyi's end compliance, Eq. 13).
    pub fn end_stiffness(&self) -> [[f64; 2]; 2] {
        let mut k = [[0.0; 2]; 2];
        for (j, (w0, t0)) in [(1.0, 0.0), (0.0, 1.0)].into_iter().enumerate() {
            let s = self.shape(w0, t0);
            k[0][j] = self.d_nm * s.derivative(3, 0.0);
            k[1][j] = -self.d_nm * s.derivative(2, 0.0);
        }
        // Symmetrise the round-off of the finite beam's solve.
        let off = 0.5 * (k[0][1] + k[1][0]);
        k[0][1] = off;
        k[1][0] = off;
        k
    }
}

impl FootingShape {
    /// n-th derivative of the deflection at s (m).
    pub fn derivative(&self, n: i32, s_m: f64) -> f64 {
        (0..4)
            .map(|k| self.coef[k] * FootingBeam::basis(self.lambda, self.length_m, k, n, s_m))
            .sum()
    }

    /// Deflection w(s) (m).
    pub fn deflection_m(&self, s_m: f64) -> f64 {
        self.derivative(0, s_m)
    }

    /// Integral of w over [s0, s1] clipped to the beam (m^2); times k it is the foundation force
    /// per unit width there.
    pub fn deflection_integral_m2(&self, s0_m: f64, s1_m: f64) -> f64 {
        let (a, b) = (s0_m.max(0.0), s1_m.min(self.length_m));
        if b <= a {
            return 0.0;
        }
        (0..4)
            .map(|k| {
                self.coef[k] * FootingBeam::basis_integral(self.lambda, self.length_m, k, a, b)
            })
            .sum()
    }
}

/// Gaussian elimination with partial pivoting on a 4 x 4 system (the finite beam's constants).
fn solve4(mut a: [[f64; 4]; 4], mut b: [f64; 4]) -> [f64; 4] {
    for c in 0..4 {
        let p = (c..4)
            .max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))
            .unwrap_or(c);
        a.swap(c, p);
        b.swap(c, p);
        let (pivot, pb) = (a[c], b[c]);
        for (row, br) in a.iter_mut().zip(b.iter_mut()).skip(c + 1) {
            let f = row[c] / pivot[c];
            for (v, p) in row.iter_mut().zip(pivot).skip(c) {
                *v -= f * p;
            }
            *br -= f * pb;
        }
    }
    let mut x = [0.0; 4];
    for r in (0..4).rev() {
        let s: f64 = (r + 1..4).map(|k| a[r][k] * x[k]).sum();
        x[r] = (b[r] - s) / a[r][r];
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    fn beam(l: f64) -> FootingBeam {
        FootingBeam {
            d_nm: 0.4,
            k_pa_per_m: 2e13,
            length_m: l,
        }
    }

    /// Energy 1/2 int (D w''^2 + k w^2) by composite Gauss: an independent route to K.
    fn energy(b: &FootingBeam, w0: f64, t0: f64) -> f64 {
        let s = b.shape(w0, t0);
        let l = if b.length_m.is_finite() {
            b.length_m
        } else {
            40.0 / b.lambda_per_m()
        };
        let n = 4000;
        let h = l / n as f64;
        let g = [-0.774_596_669_241_483_4, 0.0, 0.774_596_669_241_483_4];
        let wg = [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0];
        let mut e = 0.0;
        for i in 0..n {
            for q in 0..3 {
                let x = h * (i as f64 + 0.5 + 0.5 * g[q]);
                let (w, c) = (s.deflection_m(x), s.derivative(2, x));
                e += 0.5 * h * wg[q] * 0.5 * (b.d_nm * c * c + b.k_pa_per_m * w * w);
            }
        }
        e
    }

    #[test]
    fn semi_infinite_end_stiffness_is_hetenyis() {
        let b = beam(f64::INFINITY);
        let l = b.lambda_per_m();
        let k = b.end_stiffness();
        let d = b.d_nm;
        let want = [
            [4.0 * d * l.powi(3), 2.0 * d * l * l],
            [2.0 * d * l * l, 2.0 * d * l],
        ];
        for i in 0..2 {
            for j in 0..2 {
                assert!(
                    (k[i][j] - want[i][j]).abs() < 1e-12 * want[i][j].abs(),
                    "{k:?}"
                );
            }
        }
        // Hetenyi's end force alone: w0 = 2 P lambda / k.
        let det = k[0][0] * k[1][1] - k[0][1] * k[1][0];
        let c_ww = k[1][1] / det;
        assert!((c_ww - 2.0 * l / b.k_pa_per_m).abs() < 1e-12 * c_ww);
    }

    #[test]
    fn end_stiffness_is_the_energy_hessian_and_the_foundation_carries_the_end_force() {
        for l in [f64::INFINITY, 3e-3, 1e-3, 2e-4] {
            let b = beam(l);
            let k = b.end_stiffness();
            for (w0, t0) in [(1e-6, 0.0), (0.0, 1e-3), (1e-6, -2e-3)] {
                let e = energy(&b, w0, t0);
                let want = 0.5 * (k[0][0] * w0 * w0 + 2.0 * k[0][1] * w0 * t0 + k[1][1] * t0 * t0);
                assert!((e - want).abs() < 1e-6 * want, "L {l}: {e} vs {want}");
                // Equilibrium: k int w ds = V = D w'''(0).
                let s = b.shape(w0, t0);
                let v = k[0][0] * w0 + k[0][1] * t0;
                let p = b.k_pa_per_m * s.deflection_integral_m2(0.0, f64::INFINITY);
                assert!(
                    (p - v).abs() < 1e-9 * v.abs().max(1e-30),
                    "L {l}: {p} vs {v}"
                );
                // The far end is free.
                if l.is_finite() {
                    let scale =
                        s.derivative(2, 0.0).abs() + s.derivative(3, 0.0).abs() / b.lambda_per_m();
                    assert!(s.derivative(2, l).abs() < 1e-9 * scale);
                }
            }
        }
    }

    #[test]
    fn a_long_finite_beam_is_the_semi_infinite_one() {
        let (a, b) = (beam(f64::INFINITY), beam(0.05));
        let (ka, kb) = (a.end_stiffness(), b.end_stiffness());
        for i in 0..2 {
            for j in 0..2 {
                assert!((ka[i][j] - kb[i][j]).abs() < 1e-9 * ka[i][j].abs());
            }
        }
    }
}
