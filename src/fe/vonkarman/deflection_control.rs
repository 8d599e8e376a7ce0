//! Displacement control: the load factor at which the plate's largest deflection reaches a
//! target (the touch-down on the channel floor), found in one Newton solve instead of a search
//! over load factors.
//!
//! The unknowns are the field u and the load factor lambda, with the constraint that w at one
//! node equals the target (Batoz & Dhatt, Int. J. Numer. Meth. Eng. 14 (1979) 1262: the
//! bordered Newton step). Each iteration factors the tangent K once and solves it for two
//! right-hand sides, the residual R = lambda f - r(u) and the load pattern f:
//! K du_r = R, K du_f = f, d lambda = (w* - w_n - du_r,n) / du_f,n, du = du_r + d lambda du_f.
//! The node is the one at the largest deflection; when the peak between nodes moves off it, the
//! nodal target is rescaled by target / peak and the solve continues, until the peak itself is
//! within `PEAK_TOL` of the target.

use faer::sparse::SparseColMat;
use faer::Mat;

use super::{VonKarman, M};
use crate::fe::dofs::CONSTRAINED;
use crate::fe::error::{FeError, FeResult};
use crate::fe::problem::Load;
use crate::fe::solution::PlateSolution;

/// The largest deflection matches the target to this fraction.
pub const PEAK_TOL: f64 = 1e-4;

/// Outer passes that move the controlled node to the peak.
const MAX_PASSES: usize = 6;

/// The plate at a prescribed largest deflection.
#[derive(Debug, Clone)]
pub struct AtDeflection {
    /// Load factor on the load pattern.
    pub lambda: f64,
    /// The converged field at that factor.
    pub solution: PlateSolution,
    /// d ln w / d ln lambda there (1 in bending, 1/3 as a membrane): how the deflection scales
    /// with the load near the answer.
    pub exponent: f64,
    /// Newton iterations (each one factorisation and a two-column solve).
    pub iterations: usize,
}

impl VonKarman {
    /// The load factor on `loads` at which the largest |w| reaches `target_m`, starting from
    /// `guess` (a converged field of this plate at load factor `lambda0` of the same pattern,
    /// e.g. the scene's own answer at 1).
    ///
    /// Errors ([`FeError::Newton`]): a target that is not positive and finite, a guess without
    /// deflection (no direction to scale), a peak on a held node, Newton that does not converge.
    pub fn solve_to_deflection(
        &self,
        loads: &[Load],
        guess: &PlateSolution,
        lambda0: f64,
        target_m: f64,
    ) -> FeResult<AtDeflection> {
        let f = self.force(loads)?;
        let peak0 = guess.max_deflection();
        if !(target_m > 0.0 && target_m.is_finite() && peak0.w_m != 0.0 && lambda0 > 0.0) {
            return Err(FeError::Newton {
                detail: format!(
                    "target deflection {target_m} m from a guess with peak {} m at load factor \
                     {lambda0}",
                    peak0.w_m
                ),
                hint: "the target must be positive and the guess must deflect",
            });
        }
        let sign = peak0.w_m.signum();
        let mut u = self.start_from(guess);
        let mut lambda = lambda0;
        let mut nodal_target = target_m;
        let mut peak = peak0;
        let mut iterations = 0;
        for _ in 0..MAX_PASSES {
            let nearest = |axis: &[f64], s: f64| {
                (0..axis.len())
                    .min_by(|&a, &b| (axis[a] - s).abs().total_cmp(&(axis[b] - s).abs()))
                    .expect("a mesh has nodes")
            };
            let node = self.mesh.node(
                nearest(&self.mesh.x_um, peak.x_um),
                nearest(&self.mesh.y_um, peak.y_um),
            );
            let wd = M * node;
            let row = self.free_index[wd];
            if row == CONSTRAINED {
                return Err(FeError::Newton {
                    detail: format!(
                        "the largest deflection sits on a held node ({:.1}, {:.1}) um",
                        peak.x_um, peak.y_um
                    ),
                    hint: "a held node cannot be driven to a deflection",
                });
            }
            let (exponent, its) =
                self.bordered_newton(&f, &mut u, &mut lambda, wd, row, sign * nodal_target)?;
            iterations += its;
            let scaled: Vec<f64> = f.iter().map(|v| lambda * v).collect();
            let solution = self.solution(u.clone(), &scaled)?;
            peak = solution.max_deflection();
            let reached = peak.w_m.abs();
            if (reached - target_m).abs() <= PEAK_TOL * target_m {
                return Ok(AtDeflection {
                    lambda,
                    solution,
                    exponent,
                    iterations,
                });
            }
            nodal_target *= target_m / reached;
        }
        Err(FeError::Newton {
            detail: format!(
                "the largest deflection did not settle at {:.3} um in {MAX_PASSES} passes",
                target_m * 1e6
            ),
            hint: "the peak moves between nodes: refine the mesh near it",
        })
    }

    /// Bordered Newton at w(dof `wd`, free row `row`) = `w_target`: updates `u` and `lambda`,
    /// returns d ln w / d ln lambda at the last tangent and the iterations.
    fn bordered_newton(
        &self,
        f: &[f64],
        u: &mut [f64],
        lambda: &mut f64,
        wd: usize,
        row: usize,
        w_target: f64,
    ) -> FeResult<(f64, usize)> {
        let n = self.free_dofs.len();
        let mut first: Option<f64> = None;
        for it in 1..=self.opts.max_iterations {
            let (r_int, vals) = self.internal(u, true);
            let vals = vals.expect("asked for the tangent");
            let llt = self.symbolic.factor(
                SparseColMat::<usize, f64>::new(self.pattern.symbolic.clone(), vals).as_ref(),
            )?;
            let mut rhs = Mat::<f64>::zeros(n, 2);
            for (i, &d) in self.free_dofs.iter().enumerate() {
                rhs[(i, 0)] = *lambda * f[d] - r_int[d];
                rhs[(i, 1)] = f[d];
            }
            let r0: Vec<f64> = (0..n).map(|i| rhs[(i, 0)]).collect();
            llt.solve_in_place(rhs.as_mut());
            let dwf = rhs[(row, 1)];
            if !(dwf.is_finite() && dwf != 0.0) {
                return Err(FeError::Newton {
                    detail: "the load no longer moves the controlled node".into(),
                    hint: "the plate may snap at this deflection",
                });
            }
            let dl = (w_target - u[wd] - rhs[(row, 0)]) / dwf;
            let mut energy = 0.0;
            for (i, &d) in self.free_dofs.iter().enumerate() {
                let du = rhs[(i, 0)] + dl * rhs[(i, 1)];
                if !du.is_finite() {
                    return Err(FeError::Newton {
                        detail: "the correction is not finite".into(),
                        hint: "the plate may snap at this deflection",
                    });
                }
                energy += du * (r0[i] + dl * f[d]);
                u[d] += du;
            }
            *lambda += dl;
            let e0 = *first.get_or_insert(energy.abs().max(f64::MIN_POSITIVE));
            if energy.abs() <= self.opts.energy_tol * e0 || energy == 0.0 {
                // At the answer: w_n = w_target, so d ln w / d ln lambda = lambda dw/dlambda / w.
                return Ok((*lambda * dwf / w_target, it));
            }
        }
        Err(FeError::Newton {
            detail: format!(
                "Newton at a prescribed deflection of {:.3} um did not converge in {} iterations",
                w_target.abs() * 1e6,
                self.opts.max_iterations
            ),
            hint: "the plate may snap at this deflection",
        })
    }
}
