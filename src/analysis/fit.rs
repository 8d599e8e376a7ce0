//! Least-squares fits of a curve y(theta) in well-conditioned bases, solved by Householder QR
//! (faer dense `qr`), with the basis matrix's 2-norm condition number from its singular values.
//!
//! Paper 000 (Eq. 1-3) fits charge against probe angle with degree-10 monomials in radians; that
//! basis has condition number ~5e8 (fe-validation.md, "Fitting"), so here the angle is either
//! mapped to [-1, 1] for Chebyshev polynomials T_k (T_0 = 1, T_1 = t, T_k+1 = 2 t T_k - T_k-1), or
//! expanded in a Fourier series in 2 theta (probe rotation is pi-periodic: a rectangle turned by
//! 180 deg is the same load).

use faer::prelude::SolveLstsq;
use faer::Mat;
use serde::Serialize;

use super::AnalysisError;

/// Which basis a fit uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum BasisKind {
    /// T_0..T_degree of the angle mapped linearly from [lo, hi] onto [-1, 1].
    Chebyshev,
    /// 1, cos 2k theta, sin 2k theta for k = 1..degree (theta in degrees in, radians inside).
    Fourier2Theta,
}

/// A basis over an angle interval.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Basis {
    pub kind: BasisKind,
    pub degree: usize,
    /// The interval the Chebyshev map uses (deg); Fourier ignores it.
    pub lo_deg: f64,
    pub hi_deg: f64,
}

impl Basis {
    pub fn n_terms(&self) -> usize {
        match self.kind {
            BasisKind::Chebyshev => self.degree + 1,
            BasisKind::Fourier2Theta => 2 * self.degree + 1,
        }
    }

    /// The basis functions at `theta_deg`.
    pub fn row(&self, theta_deg: f64) -> Vec<f64> {
        let mut r = Vec::with_capacity(self.n_terms());
        match self.kind {
            BasisKind::Chebyshev => {
                let t = (2.0 * theta_deg - self.lo_deg - self.hi_deg) / (self.hi_deg - self.lo_deg);
                let (mut a, mut b) = (1.0, t);
                r.push(a);
                for _ in 0..self.degree {
                    r.push(b);
                    (a, b) = (b, 2.0 * t * b - a);
                }
                r.truncate(self.degree + 1);
            }
            BasisKind::Fourier2Theta => {
                let th = theta_deg.to_radians();
                r.push(1.0);
                for k in 1..=self.degree {
                    let w = 2.0 * k as f64 * th;
                    r.push(w.cos());
                    r.push(w.sin());
                }
            }
        }
        r
    }
}

/// A fitted curve with how well it is posed and how well it fits.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Fit {
    pub basis: Basis,
    /// Coefficients in the basis (reported, never compared in tests: other bases give other ones).
    pub coefficients: Vec<f64>,
    /// sigma_max / sigma_min of the basis matrix at the samples.
    pub condition_number: f64,
    pub rms_residual: f64,
    pub max_abs_residual: f64,
}

impl Fit {
    pub fn eval(&self, theta_deg: f64) -> f64 {
        self.basis
            .row(theta_deg)
            .iter()
            .zip(&self.coefficients)
            .map(|(a, c)| a * c)
            .sum()
    }
}

/// Least-squares fit of `y` at `theta_deg` in `basis` by QR; errors if the system is
/// under-determined or rank deficient (condition number over 1e12).
pub fn fit(basis: Basis, theta_deg: &[f64], y: &[f64]) -> Result<Fit, AnalysisError> {
    let (m, n) = (theta_deg.len(), basis.n_terms());
    if y.len() != m {
        return Err(AnalysisError::Fit {
            reason: format!("{m} angles but {} values", y.len()),
        });
    }
    if basis.kind == BasisKind::Chebyshev && basis.hi_deg <= basis.lo_deg {
        return Err(AnalysisError::Fit {
            reason: "the Chebyshev interval is empty".into(),
        });
    }
    if m < n {
        return Err(AnalysisError::Fit {
            reason: format!("{n} basis terms but only {m} samples"),
        });
    }
    let rows: Vec<Vec<f64>> = theta_deg.iter().map(|&t| basis.row(t)).collect();
    let a = Mat::<f64>::from_fn(m, n, |i, j| rows[i][j]);
    let sv = a.singular_values().map_err(|e| AnalysisError::Fit {
        reason: format!("SVD did not converge: {e:?}"),
    })?;
    let (smax, smin) = (sv[0], sv[sv.len() - 1]);
    let condition_number = if smin > 0.0 {
        smax / smin
    } else {
        f64::INFINITY
    };
    if condition_number > 1e12 {
        return Err(AnalysisError::Fit {
            reason: format!(
                "the basis matrix is rank deficient at these samples (condition number \
                 {condition_number:.1e}); distinct samples may be fewer than the {n} terms"
            ),
        });
    }
    let b = Mat::<f64>::from_fn(m, 1, |i, _| y[i]);
    let x = a.qr().solve_lstsq(&b);
    let coefficients: Vec<f64> = (0..n).map(|j| x[(j, 0)]).collect();
    let mut f = Fit {
        basis,
        coefficients,
        condition_number,
        rms_residual: 0.0,
        max_abs_residual: 0.0,
    };
    let res: Vec<f64> = theta_deg
        .iter()
        .zip(y)
        .map(|(&t, &v)| f.eval(t) - v)
        .collect();
    f.rms_residual = (res.iter().map(|r| r * r).sum::<f64>() / m as f64).sqrt();
    f.max_abs_residual = res.iter().fold(0.0, |a, r| a.max(r.abs()));
    Ok(f)
}

/// Condition number of the monomial basis 1, theta, .., theta^degree (theta in radians) at the same
/// samples: what paper 000's Eq. 1 fit was posed with, for comparison in reports.
pub fn monomial_condition_number(theta_deg: &[f64], degree: usize) -> f64 {
    let a = Mat::<f64>::from_fn(theta_deg.len(), degree + 1, |i, j| {
        theta_deg[i].to_radians().powi(j as i32)
    });
    match a.singular_values() {
        Ok(sv) if sv[sv.len() - 1] > 0.0 => sv[0] / sv[sv.len() - 1],
        _ => f64::INFINITY,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn angles(step: f64) -> Vec<f64> {
        (0..)
            .map(|k| k as f64 * step)
            .take_while(|t| *t <= 180.0 + 1e-9)
            .collect()
    }

    fn cheb(degree: usize) -> Basis {
        Basis {
            kind: BasisKind::Chebyshev,
            degree,
            lo_deg: 0.0,
            hi_deg: 180.0,
        }
    }

    #[test]
    fn chebyshev_is_well_conditioned_where_monomials_are_not() {
        let t = angles(10.0);
        let f = fit(
            cheb(10),
            &t,
            &t.iter().map(|a| a.to_radians().cos()).collect::<Vec<_>>(),
        )
        .unwrap();
        // ~3 for Chebyshev against ~5e8 for monomials in radians (fe-validation.md).
        assert!(f.condition_number < 10.0, "{}", f.condition_number);
        let mono = monomial_condition_number(&t, 10);
        assert!(mono > 1e7, "{mono}");
    }

    #[test]
    fn reproduces_a_polynomial_of_its_degree_exactly_and_a_smooth_function_closely() {
        let t = angles(10.0);
        // A degree-4 polynomial in the angle is in the span of T_0..T_10.
        let p = |a: f64| 3.0 - 0.02 * a + 1e-4 * a * a - 3e-7 * a.powi(3) + 4e-10 * a.powi(4);
        let f = fit(cheb(10), &t, &t.iter().map(|&a| p(a)).collect::<Vec<_>>()).unwrap();
        for a in [0.0, 5.0, 47.3, 133.0, 180.0] {
            assert!((f.eval(a) - p(a)).abs() < 1e-11, "{a}");
        }
        // A smooth non-polynomial: the degree-10 fit is close between the samples too (numpy's
        // chebvander + lstsq on the same samples gives 1.9e-3 at 4 deg, the largest error).
        let g = |a: f64| (a.to_radians() * 1.3).sin().exp();
        let f = fit(cheb(10), &t, &t.iter().map(|&a| g(a)).collect::<Vec<_>>()).unwrap();
        for k in 0..=360 {
            let a = k as f64 * 0.5;
            assert!(
                (f.eval(a) - g(a)).abs() < 2.5e-3,
                "{a}: {}",
                f.eval(a) - g(a)
            );
        }
    }

    #[test]
    fn fourier_in_two_theta_reproduces_a_pi_periodic_curve() {
        let t = angles(10.0);
        let c = |a: f64| {
            800.0 + 30.0 * (2.0 * a.to_radians()).cos() - 4.0 * (4.0 * a.to_radians()).sin()
        };
        let basis = Basis {
            kind: BasisKind::Fourier2Theta,
            degree: 4,
            lo_deg: 0.0,
            hi_deg: 180.0,
        };
        let f = fit(basis, &t, &t.iter().map(|&a| c(a)).collect::<Vec<_>>()).unwrap();
        assert!(
            f.max_abs_residual < 1e-10 && f.condition_number < 2.0,
            "{} {}",
            f.max_abs_residual,
            f.condition_number
        );
        for a in [3.0, 91.0, 177.5, 200.0] {
            assert!((f.eval(a) - c(a)).abs() < 1e-10);
        }
    }

    #[test]
    fn too_many_terms_is_an_error_not_a_silent_fit() {
        let t = angles(10.0);
        let y = vec![1.0; t.len()];
        // 9 harmonics = 19 terms on 18 distinct angles (0 and 180 deg coincide for cos/sin 2k
        // theta).
        let fourier = Basis {
            kind: BasisKind::Fourier2Theta,
            degree: 9,
            lo_deg: 0.0,
            hi_deg: 180.0,
        };
        assert!(matches!(
            fit(fourier, &t, &y),
            Err(AnalysisError::Fit { .. })
        ));
        assert!(matches!(
            fit(cheb(30), &t, &y),
            Err(AnalysisError::Fit { .. })
        ));
    }
}
