//! Geometrically nonlinear (von Karman) Kirchhoff plate: the BFS bending field w plus bilinear
//! in-plane displacements (u, v) on the same mesh, 6 dofs per node (w, w_x, w_y, w_xy, u, v),
//! solved by Newton iterations with load stepping.
//!
//! Kinematics (von Karman; Reddy, Theory and Analysis of Elastic Plates and Shells, 2nd ed.,
//! Eq. 3.3.10): membrane strain eps0 = (u_x + w_x^2 / 2, v_y + w_y^2 / 2, u_y + v_x + w_x w_y),
//! curvature kappa = (-w_xx, -w_yy, -2 w_xy); resultants N = A eps0 with A = Q t, M = D kappa with
//! D = Q t^3 / 12 for a section centred on the reference plane. A section whose own mid-plane
//! sits at z from it (a tooth on the top face, [`crate::fe::ThicknessRegion::rise_um`]: z =
//! -rise along +w) stretches there: N = A (eps0 + z kappa), i.e. B = A z and D + A z^2 about the
//! reference (Reddy, Eq. 3.3.13). The tangent stiffness (Reddy, An Introduction to Nonlinear FEM, 2nd ed., Eq. 7.3.21)
//! is int B^T A B + B_b^T D B_b + K_sigma dA with B = [B_m | B_nl(w)] and the initial-stress
//! matrix K_sigma = int (N_x w,i_x w,j_x + N_y w,i_y w,j_y + N_xy (w,i_x w,j_y + w,i_y w,j_x)) dA.
//!
//! The sparsity pattern, the elimination order and the symbolic Cholesky analysis are built once
//! per mesh and constraint set and reused by every Newton iteration of every load step and scene.
//! Loads are dead loads (they do not follow the deformation). A support line holds u and v
//! (immovable) or only the displacement along it (sliding); an edge spring's line is held the
//! same way unless it has an in-plane stiffness, which then takes the normal displacement
//! (`in_plane_spring`: the footing's in-plane give).

// Index loops mirror the matrix formulas.
#![allow(clippy::needless_range_loop)]

use std::collections::HashMap;
use std::sync::Arc;

use faer::sparse::SparseColMat;
use faer::Mat;
use rayon::prelude::*;
use serde::Serialize;

use crate::fe::assemble::Pattern;
use crate::fe::bfs;
use crate::fe::cholesky::{CholeskyFactor, SymbolicFactor};
use crate::fe::dofs::{find_line, rank, DofMap, CONSTRAINED};
use crate::fe::error::{FeError, FeResult};
use crate::fe::loads::load_vector;
use crate::fe::material::{BendingStiffness, PlateMaterial};
use crate::fe::mesh::RectMesh;
use crate::fe::ordering::node_dof_order;
use crate::fe::problem::{Axis, LineSupport, Load, PlateProblem, SupportKind};
use crate::fe::solution::{GroupReaction, NodalReaction, PlateSolution, SolutionContext};

mod deflection_control;
mod in_plane_spring;
pub use deflection_control::{AtDeflection, PEAK_TOL};
use in_plane_spring::InPlaneSegment;

/// Energy-norm ratio below which a correction that stops shrinking is round-off: the displacement
/// correction is then ~1e-4 of the first, under any discretisation error the ladder reports
/// (>= 1e-3). Well-shaped meshes reach 1e-16; a batch of rotated probes leaves sliver elements
/// whose conditioning floors the ratio near 1e-9 (measured), where Newton only stirs round-off.
const ROUND_OFF_RATIO: f64 = 1e-8;

/// Energy contraction per iteration below which modified Newton keeps its factorisation (the
/// error then falls 10x per solve, each a fraction of a factorisation's cost).
const CHORD_CONTRACTION: f64 = 1e-2;

/// Dofs per node: w, w_x, w_y, w_xy, u, v.
const M: usize = 6;
/// Element dofs: 16 bending (BFS local order) then 8 membrane (u, v at each corner).
const NE: usize = 24;

/// What the supports do in the plate's own plane.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum InPlane {
    /// u = v = 0 on every support line: the support holds the plate (bonded to the support
    /// post); the plate must stretch to deflect (membrane stiffening). On an edge spring with an
    /// in-plane stiffness the normal displacement is held by that spring instead.
    Immovable,
    /// Only the displacement along the support line is held; the plate may pull in across it
    /// (one node is held across as well, to remove the rigid translation). Edge springs' in-plane
    /// stiffnesses are not applied.
    Sliding,
}

/// Newton and load-stepping controls.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct NonlinearOptions {
    pub in_plane: InPlane,
    /// Converged when the energy norm of the correction falls below this fraction of the first
    /// correction's in the step (squared-norm ratio, so 1e-14 is ~1e-7 in displacement).
    pub energy_tol: f64,
    /// Newton iterations per load step before the step is halved.
    pub max_iterations: usize,
    /// Most load steps (after halvings) before giving up.
    pub max_load_steps: usize,
}

impl Default for NonlinearOptions {
    fn default() -> Self {
        NonlinearOptions {
            in_plane: InPlane::Immovable,
            energy_tol: 1e-14,
            max_iterations: 25,
            max_load_steps: 64,
        }
    }
}

/// What the Newton solve cost (the default: nothing yet).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct NewtonStats {
    /// Load steps taken (accepted).
    pub load_steps: usize,
    /// Newton iterations over all steps (each one residual and one solve).
    pub iterations: usize,
    /// Numeric factorisations on the shared analysis (one per iteration except where modified
    /// Newton reused one).
    pub factorisations: usize,
    /// Of those, the ones in single precision, which only precondition conjugate gradients
    /// (the solid's large meshes; the plate's are all double).
    pub single_precision: usize,
}

/// Per element size and thickness: the shape-function derivatives at the 4x4 Gauss points and
/// the constant bending and membrane stiffnesses.
struct ElementKind {
    /// BFS: w_x and w_y of the 16 shape functions at each Gauss point.
    wx: [[f64; 16]; 16],
    wy: [[f64; 16]; 16],
    /// Q4: d/dx, d/dy of the 4 corner functions at each Gauss point.
    mx: [[f64; 4]; 16],
    my: [[f64; 4]; 16],
    /// The same slopes by shape function: `nt[i] = [w_x of i at the 16 points, w_y of i at them]`,
    /// so the tangent's sums over points are contiguous dot products.
    nt: [[f64; 32]; 16],
    /// Gauss weight times area Jacobian.
    wt: [f64; 16],
    kb: Box<[[f64; 16]; 16]>,
    /// int B_m^T A B_m dA over the 8 membrane dofs (constant).
    km: [[f64; 8]; 8],
    /// A B_m at each Gauss point ([`membrane_columns`]): constant, so computed once.
    am: [[[f64; 8]; 3]; 16],
    /// Membrane stiffness A = Q t (A11, A12, A22, A66) in N/m.
    a: [f64; 4],
    /// Position (m, along +w) of the section's own mid-plane from the mesh's reference plane, and
    /// the curvature (-w_xx, -w_yy, -2 w_xy) of the 16 bending functions at each Gauss point;
    /// empty when the section is centred (ecc = 0).
    ecc: f64,
    kappa: Vec<[[f64; 16]; 3]>,
}

/// Derivatives (d/dx, d/dy) of the bilinear corner functions at local (x, y), corners in BFS order.
pub fn q4_gradients(x: f64, y: f64, a: f64, b: f64) -> ([f64; 4], [f64; 4]) {
    let mut dx = [0.0; 4];
    let mut dy = [0.0; 4];
    for (k, &(ix, iy)) in bfs::CORNERS.iter().enumerate() {
        let (fx, gx) = if ix == 1 {
            (x / a, 1.0 / a)
        } else {
            (1.0 - x / a, -1.0 / a)
        };
        let (fy, gy) = if iy == 1 {
            (y / b, 1.0 / b)
        } else {
            (1.0 - y / b, -1.0 / b)
        };
        dx[k] = gx * fy;
        dy[k] = fx * gy;
    }
    (dx, dy)
}

/// A B_m: the membrane resultants (N_x, N_y, N_xy) per unit of each membrane dof (u, v per
/// corner) at one Gauss point.
fn membrane_columns(a: &[f64; 4], mx: &[f64; 4], my: &[f64; 4]) -> [[f64; 8]; 3] {
    let [a11, a12, a22, a66] = *a;
    let mut s = [[0.0; 8]; 3];
    for c in 0..4 {
        // u_c: eps = (mx, 0, my); v_c: eps = (0, my, mx).
        s[0][2 * c] = a11 * mx[c];
        s[1][2 * c] = a12 * mx[c];
        s[2][2 * c] = a66 * my[c];
        s[0][2 * c + 1] = a12 * my[c];
        s[1][2 * c + 1] = a22 * my[c];
        s[2][2 * c + 1] = a66 * mx[c];
    }
    s
}

impl ElementKind {
    fn new(a: f64, b: f64, t_m: f64, ecc_m: f64, mat: &PlateMaterial, d: BendingStiffness) -> Self {
        let gx = bfs::gauss4_on(0.0, a);
        let gy = bfs::gauss4_on(0.0, b);
        let mut k = ElementKind {
            wx: [[0.0; 16]; 16],
            wy: [[0.0; 16]; 16],
            mx: [[0.0; 4]; 16],
            my: [[0.0; 4]; 16],
            nt: [[0.0; 32]; 16],
            wt: [0.0; 16],
            kb: Box::new(bfs::stiffness(a, b, &d)),
            km: [[0.0; 8]; 8],
            am: [[[0.0; 8]; 3]; 16],
            a: [
                mat.q11_pa * t_m,
                mat.q12_pa * t_m,
                mat.q22_pa * t_m,
                mat.q66_pa * t_m,
            ],
            ecc: ecc_m,
            kappa: Vec::new(),
        };
        for (p, &(x, wxg)) in gx.iter().enumerate() {
            for (q, &(y, wyg)) in gy.iter().enumerate() {
                let g = 4 * p + q;
                let s = bfs::shape(x, y, a, b);
                if ecc_m != 0.0 {
                    k.kappa
                        .push([s[3].map(|v| -v), s[4].map(|v| -v), s[5].map(|v| -2.0 * v)]);
                }
                k.wx[g] = s[1];
                k.wy[g] = s[2];
                for i in 0..16 {
                    (k.nt[i][g], k.nt[i][16 + g]) = (s[1][i], s[2][i]);
                }
                (k.mx[g], k.my[g]) = q4_gradients(x, y, a, b);
                k.wt[g] = wxg * wyg;
                // B_m^T (A B_m), B_m's rows as in membrane_columns.
                k.am[g] = membrane_columns(&k.a, &k.mx[g], &k.my[g]);
                let s = &k.am[g];
                for c in 0..4 {
                    let (u, v) = (2 * c, 2 * c + 1);
                    for j in 0..8 {
                        k.km[u][j] += k.wt[g] * (k.mx[g][c] * s[0][j] + k.my[g][c] * s[2][j]);
                        k.km[v][j] += k.wt[g] * (k.my[g][c] * s[1][j] + k.mx[g][c] * s[2][j]);
                    }
                }
            }
        }
        k
    }

    /// Internal force (24) and, if asked, the tangent (24 x 24, row-major) of one element at its
    /// dofs `ue` (16 bending, then u, v per corner).
    ///
    /// With B = [B_nl(w) | B_m], B_nl's rows (w_x n_x, w_y n_y, w_x n_y + w_y n_x) for the slope
    /// shape functions n_x, n_y, the tangent's blocks are (Reddy Eq. 7.3.21 multiplied out):
    /// K_ww = K_b + int c_xx n_x n_x^T + c_yy n_y n_y^T + c_xy (n_x n_y^T + n_y n_x^T) with
    /// c_xx = A11 w_x^2 + A66 w_y^2 + N_x, c_yy = A22 w_y^2 + A66 w_x^2 + N_y,
    /// c_xy = (A12 + A66) w_x w_y + N_xy (material plus initial-stress part);
    /// K_wm = int n_x (w_x S_0 + w_y S_2) + n_y (w_y S_1 + w_x S_2) with S = A B_m; K_mm constant.
    fn evaluate(&self, ue: &[f64; NE], tangent: Option<&mut [f64]>) -> [f64; NE] {
        let mut r = [0.0; NE];
        // Bending: K_b w (linear), of w less the element's mean corner deflection. K_b annihilates
        // a rigid translation only to round-off (~1e-16 |K_b|), and on fine meshes |K_b| w_mean
        // is ~1e8 times the element's net force: the same round-off in every element of a kind
        // added up to a phantom vertical force (3.7e-5 N of 0.5 N on the bundled design's
        // 380k-dof level under the support sections, where the reactions are the springs'
        // forces, not f - K u). With the mean taken out: 7e-10 N.
        let wbar = 0.25 * (ue[0] + ue[4] + ue[8] + ue[12]);
        let mut ub = [0.0; 16];
        ub.copy_from_slice(&ue[..16]);
        for c in 0..4 {
            ub[4 * c] -= wbar;
        }
        for i in 0..16 {
            r[i] = (0..16).map(|j| self.kb[i][j] * ub[j]).sum();
        }
        // Membrane, linear part: K_mm u.
        for i in 0..8 {
            r[16 + i] = (0..8).map(|j| self.km[i][j] * ue[16 + j]).sum();
        }
        let mut kt = tangent;
        if let Some(k) = kt.as_deref_mut() {
            for i in 0..16 {
                k[i * NE..i * NE + 16].copy_from_slice(&self.kb[i]);
                k[i * NE + 16..(i + 1) * NE].fill(0.0);
            }
            for i in 0..8 {
                let row = &mut k[(16 + i) * NE..(17 + i) * NE];
                row[..16].fill(0.0);
                row[16..].copy_from_slice(&self.km[i]);
            }
        }
        let [a11, a12, a22, a66] = self.a;
        // Per shape function, the tangent's point-wise factors (w_x rows then w_y rows).
        let mut lw = [[0.0; 32]; 16];
        let mut lm = [[0.0; 32]; 8];
        for g in 0..16 {
            let (nx, ny, mx, my) = (&self.wx[g], &self.wy[g], &self.mx[g], &self.my[g]);
            let wx: f64 = (0..16).map(|i| nx[i] * ue[i]).sum();
            let wy: f64 = (0..16).map(|i| ny[i] * ue[i]).sum();
            let (mut ux, mut uy, mut vx, mut vy) = (0.0, 0.0, 0.0, 0.0);
            for c in 0..4 {
                ux += mx[c] * ue[16 + 2 * c];
                uy += my[c] * ue[16 + 2 * c];
                vx += mx[c] * ue[17 + 2 * c];
                vy += my[c] * ue[17 + 2 * c];
            }
            let mut e = [ux + 0.5 * wx * wx, vy + 0.5 * wy * wy, uy + vx + wx * wy];
            // An eccentric section stretches at its own mid-plane: eps0 + ecc kappa.
            let ek = self
                .kappa
                .get(g)
                .map(|kb| kb.map(|row| self.ecc * (0..16).map(|i| row[i] * ue[i]).sum::<f64>()));
            if let Some(ek) = ek {
                (0..3).for_each(|c| e[c] += ek[c]);
            }
            let n = [a11 * e[0] + a12 * e[1], a12 * e[0] + a22 * e[1], a66 * e[2]];
            let w = self.wt[g];
            // B_nl^T N on the w dofs; the membrane part's nonlinear share, B_m^T (N - A B_m u).
            let (fx, fy) = (w * (wx * n[0] + wy * n[2]), w * (wy * n[1] + wx * n[2]));
            for i in 0..16 {
                r[i] += fx * nx[i] + fy * ny[i];
            }
            let mut nq = [
                w * (a11 * 0.5 * wx * wx + a12 * 0.5 * wy * wy),
                w * (a12 * 0.5 * wx * wx + a22 * 0.5 * wy * wy),
                w * a66 * wx * wy,
            ];
            if let Some(ek) = ek {
                // ecc B_b^T N on the w dofs; A ecc kappa joins the membrane's nonlinear share.
                let kb = &self.kappa[g];
                for i in 0..16 {
                    r[i] += w * self.ecc * (kb[0][i] * n[0] + kb[1][i] * n[1] + kb[2][i] * n[2]);
                }
                nq[0] += w * (a11 * ek[0] + a12 * ek[1]);
                nq[1] += w * (a12 * ek[0] + a22 * ek[1]);
                nq[2] += w * a66 * ek[2];
            }
            for c in 0..4 {
                r[16 + 2 * c] += mx[c] * nq[0] + my[c] * nq[2];
                r[17 + 2 * c] += my[c] * nq[1] + mx[c] * nq[2];
            }
            if kt.is_none() {
                continue;
            }
            let cxx = w * (a11 * wx * wx + a66 * wy * wy + n[0]);
            let cyy = w * (a22 * wy * wy + a66 * wx * wx + n[1]);
            let cxy = w * ((a12 + a66) * wx * wy + n[2]);
            let s = &self.am[g];
            if let (Some(kb), Some(k)) = (self.kappa.get(g), kt.as_deref_mut()) {
                eccentric_tangent(
                    k,
                    w,
                    self.ecc,
                    kb,
                    [a11, a12, a22, a66],
                    (nx, ny, wx, wy),
                    s,
                );
            }
            for i in 0..16 {
                lw[i][g] = cxx * nx[i] + cxy * ny[i];
                lw[i][16 + g] = cyy * ny[i] + cxy * nx[i];
            }
            for j in 0..8 {
                lm[j][g] = w * (wx * s[0][j] + wy * s[2][j]);
                lm[j][16 + g] = w * (wy * s[1][j] + wx * s[2][j]);
            }
        }
        if let Some(k) = kt {
            // K_ww += sum_g (a_x n_x^T + a_y n_y^T), symmetric: the upper triangle, mirrored;
            // K_wm = sum_g (n_x p_x^T + n_y p_y^T) and its transpose.
            let dot = |a: &[f64; 32], b: &[f64; 32]| -> f64 {
                // Four partial sums: the order is fixed, so the result is deterministic, and
                // the loop vectorises.
                let mut acc = [0.0; 4];
                for c in 0..8 {
                    for l in 0..4 {
                        acc[l] += a[4 * c + l] * b[4 * c + l];
                    }
                }
                (acc[0] + acc[1]) + (acc[2] + acc[3])
            };
            for i in 0..16 {
                for j in i..16 {
                    let v = dot(&lw[i], &self.nt[j]);
                    k[i * NE + j] += v;
                    if j != i {
                        k[j * NE + i] += v;
                    }
                }
                for j in 0..8 {
                    let v = dot(&self.nt[i], &lm[j]);
                    k[i * NE + 16 + j] += v;
                    k[(16 + j) * NE + i] += v;
                }
            }
        }
        r
    }
}

/// An eccentric section's tangent terms at one Gauss point (weight `w`): with the strain's
/// w-rows G = B_nl + ecc B_b (B_b the curvature rows `kb`), K_ww gains
/// G^T A G - B_nl^T A B_nl and K_wm gains ecc B_b^T A B_m (`s` = A B_m), both mirrored.
fn eccentric_tangent(
    k: &mut [f64],
    w: f64,
    ecc: f64,
    kb: &[[f64; 16]; 3],
    [a11, a12, a22, a66]: [f64; 4],
    (nx, ny, wx, wy): (&[f64; 16], &[f64; 16], f64, f64),
    s: &[[f64; 8]; 3],
) {
    let a = |r: [f64; 3]| [a11 * r[0] + a12 * r[1], a12 * r[0] + a22 * r[1], a66 * r[2]];
    let nl = |i: usize| [wx * nx[i], wy * ny[i], wx * ny[i] + wy * nx[i]];
    let eb = |i: usize| [ecc * kb[0][i], ecc * kb[1][i], ecc * kb[2][i]];
    let dot = |p: [f64; 3], q: [f64; 3]| p[0] * q[0] + p[1] * q[1] + p[2] * q[2];
    for i in 0..16 {
        let (bi, ai_b) = (eb(i), a(eb(i)));
        let ai_nl = a(nl(i));
        for j in 0..16 {
            // G_i^T A G_j - nl_i^T A nl_j = b_i A nl_j + nl_i A b_j + b_i A b_j.
            k[i * NE + j] += w * (dot(ai_b, nl(j)) + dot(ai_nl, eb(j)) + dot(ai_b, eb(j)));
        }
        for j in 0..8 {
            let v = w * dot(bi, [s[0][j], s[1][j], s[2][j]]);
            k[i * NE + 16 + j] += v;
            k[(16 + j) * NE + i] += v;
        }
    }
}

/// A von Karman plate ready to solve: dofs, pattern and symbolic analysis built once.
pub struct VonKarman {
    mesh: RectMesh,
    opts: NonlinearOptions,
    free_index: Vec<usize>,
    free_dofs: Vec<usize>,
    /// (global dof, prescribed value, group) of every constrained dof.
    constrained: Vec<(usize, f64, usize)>,
    groups: Vec<String>,
    pattern: Pattern,
    symbolic: SymbolicFactor,
    kinds: Vec<ElementKind>,
    kind: Vec<u32>,
    ctx: Arc<SolutionContext>,
    /// Edge springs (bending dofs only; their lines hold the in-plane dofs as a support does,
    /// or leave the normal one to `in_plane_springs`).
    springs: Vec<crate::fe::solve::Springs>,
    in_plane_springs: Vec<InPlaneSegment>,
}

/// Global dofs (6 per node) of an element in the local order of [`ElementKind::evaluate`].
fn element_dofs6(mesh: &RectMesh, e: usize) -> [usize; NE] {
    let nodes = mesh.element_nodes(e);
    std::array::from_fn(|i| {
        if i < 16 {
            M * nodes[i / 4] + i % 4
        } else {
            let c = (i - 16) / 2;
            M * nodes[c] + 4 + (i - 16) % 2
        }
    })
}

/// Element corner and node dof of every local dof.
const CORNER: [usize; NE] = {
    let mut t = [0; NE];
    let mut i = 0;
    while i < NE {
        t[i] = if i < 16 { i / 4 } else { (i - 16) / 2 };
        i += 1;
    }
    t
};
const NODE_DOF: [usize; NE] = {
    let mut t = [0; NE];
    let mut i = 0;
    while i < NE {
        t[i] = if i < 16 { i % 4 } else { 4 + (i - 16) % 2 };
        i += 1;
    }
    t
};

/// Rigid in-plane modes (u = 1, v = 1, rotation) the in-plane constraints and springs leave
/// free.
fn free_in_plane_modes(
    mesh: &RectMesh,
    constrained: &[(usize, f64, usize)],
    springs: &[InPlaneSegment],
) -> usize {
    let (x0, y0, x1, y1) = mesh.bounds_um();
    let (xc, yc, l) = (0.5 * (x0 + x1), 0.5 * (y0 + y1), (x1 - x0).max(y1 - y0));
    let nxl = mesh.x_um.len();
    let mut cols: Vec<Vec<f64>> = vec![Vec::new(); 3];
    let sprung = springs.iter().flat_map(|s| s.dofs);
    let held = constrained.iter().map(|c| c.0).filter(|d| d % M >= 4);
    for d in held.chain(sprung) {
        let node = d / M;
        let (x, y) = (
            (mesh.x_um[node % nxl] - xc) / l,
            (mesh.y_um[node / nxl] - yc) / l,
        );
        let row = if d % M == 4 {
            [1.0, 0.0, -y]
        } else {
            [0.0, 1.0, x]
        };
        for k in 0..3 {
            cols[k].push(row[k]);
        }
    }
    3 - rank(cols)
}

/// The constrained dofs (6 per node): the bending constraints of the linear problem, plus the
/// in-plane ones of each support line by `in_plane` and the normal in-plane displacement on
/// every symmetry line. An edge spring's line is held as a support's, except that with an
/// in-plane stiffness its normal displacement is left to that spring ([`in_plane_spring`]).
fn constraints(
    problem: &PlateProblem,
    bending: &DofMap,
    in_plane: InPlane,
) -> FeResult<Vec<Option<(f64, usize)>>> {
    let mesh = &problem.mesh;
    let mut owner: Vec<Option<(f64, usize)>> = vec![None; M * mesh.n_nodes()];
    for &(d, v, g) in &bending.constrained {
        owner[M * (d / 4) + d % 4] = Some((v, g));
    }
    let group = |name: &str| bending.groups.iter().position(|g| g == name).unwrap_or(0);
    let mut sliding_anchor = None;
    let mut any_mirror_x = false;
    let spring_lines = problem.edge_springs.iter().map(|e| {
        let line = LineSupport {
            group: e.group.clone(),
            kind: SupportKind::Clamped,
            along: e.along,
            at_um: e.at_um,
            from_um: e.from_um,
            to_um: e.to_um,
        };
        (line, e.normal_in_plane_pa.is_some())
    });
    let lines = problem.supports.iter().map(|s| (s.clone(), false));
    for (s, normal_sprung) in lines.chain(spring_lines) {
        let s = &s;
        let (line_axis, span_axis) = match s.along {
            Axis::X => (&mesh.y_um, &mesh.x_um),
            Axis::Y => (&mesh.x_um, &mesh.y_um),
        };
        let Some(k) = find_line(line_axis, s.at_um) else {
            continue; // DofMap::new already refused it
        };
        let (lo, hi) = (s.from_um.min(s.to_um), s.from_um.max(s.to_um));
        let tol = 1e-9 * (span_axis.last().unwrap() - span_axis[0]);
        // Along the line: u for a line along x; across: v.
        let (along, across) = match s.along {
            Axis::X => (4, 5),
            Axis::Y => (5, 4),
        };
        let held: &[usize] = match (s.kind, in_plane) {
            (SupportKind::Symmetry, _) => &[across],
            (_, InPlane::Immovable) if !normal_sprung => &[4, 5],
            (_, InPlane::Immovable | InPlane::Sliding) => &[along],
        };
        if s.kind == SupportKind::Symmetry && s.along == Axis::X {
            any_mirror_x = true;
        }
        let nodes: Vec<usize> = span_axis
            .iter()
            .enumerate()
            .filter(|(_, &c)| c >= lo - tol && c <= hi + tol)
            .map(|(m, _)| match s.along {
                Axis::X => mesh.node(m, k),
                Axis::Y => mesh.node(k, m),
            })
            .collect();
        if in_plane == InPlane::Sliding && s.kind != SupportKind::Symmetry {
            sliding_anchor.get_or_insert((nodes[nodes.len() / 2], across, group(&s.group)));
        }
        for n in nodes {
            for &d in held {
                owner[M * n + d].get_or_insert((0.0, group(&s.group)));
            }
        }
    }
    if let Some((n, d, g)) = sliding_anchor {
        // Sliding supports along x leave the rigid v translation free unless a mirror holds it.
        if !(any_mirror_x && d == 5) {
            owner[M * n + d].get_or_insert((0.0, g));
        }
    }
    Ok(owner)
}

impl VonKarman {
    /// Number the dofs, check that rigid motion is prevented in and out of plane, build the
    /// pattern and analyse it. Panics on an invalid mesh (misuse).
    #[track_caller]
    pub fn new(problem: &PlateProblem, opts: NonlinearOptions) -> FeResult<Self> {
        let mesh = &problem.mesh;
        mesh.validate();
        let bending = DofMap::new(problem)?;
        bending.check_rigid_modes(mesh)?;
        let owner = constraints(problem, &bending, opts.in_plane)?;
        let mut free_index = vec![CONSTRAINED; owner.len()];
        let mut free_dofs = Vec::new();
        let mut constrained = Vec::new();
        for (d, o) in owner.iter().enumerate() {
            match o {
                None => {
                    free_index[d] = free_dofs.len();
                    free_dofs.push(d);
                }
                Some((v, g)) => constrained.push((d, *v, *g)),
            }
        }
        let in_plane_springs = match opts.in_plane {
            InPlane::Immovable => in_plane_spring::in_plane_segments(problem, M)?,
            InPlane::Sliding => Vec::new(),
        };
        let in_plane_free = free_in_plane_modes(mesh, &constrained, &in_plane_springs);
        if in_plane_free > 0 {
            return Err(FeError::Underconstrained {
                free_modes: in_plane_free,
                hint: "the plate can slide or turn in its own plane: hold it in-plane at a \
                       support",
            });
        }
        let pattern = Pattern::with_node_dofs(mesh, &free_index, &free_dofs, M)?;
        let order = node_dof_order(&free_index, M, mesh.x_um.len(), mesh.y_um.len());
        let symbolic = SymbolicFactor::new(pattern.symbolic.as_ref(), &order)?;
        let thickness = problem.element_thickness_um();
        let rise = problem.element_rise_um();
        let mut cache: HashMap<[u64; 4], u32> = HashMap::new();
        let mut kinds = Vec::new();
        let mut kind = Vec::with_capacity(mesh.n_elements());
        for (e, &t) in thickness.iter().enumerate() {
            if !(t > 0.0 && t.is_finite()) {
                return Err(FeError::InvalidStiffness {
                    element: e,
                    hint: "every thickness (base and regions) must be positive",
                });
            }
            let (x0, y0, x1, y1) = mesh.element_bounds_um(e);
            let (a, b) = ((x1 - x0) * 1e-6, (y1 - y0) * 1e-6);
            let id = *cache
                .entry([a.to_bits(), b.to_bits(), t.to_bits(), rise[e].to_bits()])
                .or_insert_with(|| {
                    kinds.push(ElementKind::new(
                        a,
                        b,
                        t * 1e-6,
                        // +w points down: a section rising above the reference sits at -rise.
                        -rise[e] * 1e-6,
                        &problem.material,
                        problem.bending_stiffness(t * 1e-6),
                    ));
                    (kinds.len() - 1) as u32
                });
            kind.push(id);
        }
        Ok(VonKarman {
            mesh: mesh.clone(),
            opts,
            free_index,
            free_dofs,
            constrained,
            groups: bending.groups.clone(),
            pattern,
            symbolic,
            kinds,
            kind,
            ctx: Arc::new(SolutionContext {
                mesh: mesh.clone(),
                thickness_um: thickness,
                rise_um: rise,
                material: problem.material,
                groups: bending.groups,
            }),
            springs: crate::fe::solve::springs_of(problem)?
                .into_iter()
                .map(|(mut s, segs)| {
                    // With the in-plane dofs held by springs the coupled block replaces the
                    // condensed one; sliding in plane, the condensed one (u free) stays.
                    if let (Some(k), InPlane::Immovable) = (s.coupled, opts.in_plane) {
                        s.stiffness = [[k[0][0], k[0][1]], [k[1][0], k[1][1]]];
                    }
                    (s, segs)
                })
                .collect(),
            in_plane_springs,
        })
    }

    /// Unknowns of the nonlinear system.
    pub fn n_free_dofs(&self) -> usize {
        self.free_dofs.len()
    }

    /// Internal force over all dofs and, if asked, the tangent's values on the pattern, element
    /// by element on the calling thread: the ladder runs levels and scenes side by side, and
    /// splitting one plate's elements over threads as well cost more in wake-ups than it saved
    /// (2 cores: 14 against 26 ms for the coarsest level's Newton solve).
    fn internal(&self, u: &[f64], with_tangent: bool) -> (Vec<f64>, Option<Vec<f64>>) {
        let mut r = vec![0.0; u.len()];
        let mut vals = with_tangent.then(|| vec![0.0; self.pattern.symbolic.row_idx().len()]);
        let mut k = vec![0.0; if with_tangent { NE * NE } else { 0 }];
        for e in 0..self.mesh.n_elements() {
            let dofs = element_dofs6(&self.mesh, e);
            let ue = dofs.map(|d| u[d]);
            let ke = with_tangent.then_some(k.as_mut_slice());
            let re = self.kinds[self.kind[e] as usize].evaluate(&ue, ke);
            for (d, v) in dofs.iter().zip(re) {
                r[*d] += v;
            }
            if let Some(vals) = vals.as_mut() {
                let free = dofs.map(|d| self.free_index[d]);
                self.pattern
                    .add_element(vals, &free, &CORNER, &NODE_DOF, &k);
            }
        }
        crate::fe::edge_spring::add_forces(&self.springs, u, M, &mut r);
        in_plane_spring::add_forces(&self.in_plane_springs, u, &mut r);
        if let Some(vals) = vals.as_mut() {
            crate::fe::edge_spring::add_to_values(
                &self.pattern,
                vals,
                &self.mesh,
                &self.free_index,
                &self.springs,
            );
            in_plane_spring::add_to_values(
                &self.pattern,
                vals,
                &self.mesh,
                &self.free_index,
                &self.in_plane_springs,
            );
        }
        (r, vals)
    }

    /// [`Self::solve`] starting from another solution of the same plate (a coarser mesh's): Newton
    /// at the full load from that field interpolated onto this mesh, falling back to load
    /// stepping from zero if it does not converge.
    pub fn solve_from(
        &self,
        loads: &[Load],
        guess: &PlateSolution,
    ) -> FeResult<(PlateSolution, NewtonStats)> {
        let f = self.force(loads)?;
        let mut u = self.start_from(guess);
        let mut stats = NewtonStats::default();
        // Converged relative to the work the load does on the guess, not to the (already
        // small) first correction.
        let work: f64 = f.iter().zip(&u).map(|(a, b)| a * b).sum::<f64>().abs();
        if work > 0.0
            && self
                .newton(&mut u, &f, 1.0, Some(work), true, &mut stats)?
                .is_some()
        {
            stats.load_steps = 1;
            return Ok((self.solution(u, &f)?, stats));
        }
        let (s, more) = self.solve(loads)?;
        stats.iterations += more.iterations;
        stats.factorisations += more.factorisations;
        stats.load_steps = more.load_steps;
        Ok((s, stats))
    }

    /// `guess` (a solution of the same plate on any mesh) interpolated onto this mesh's nodes,
    /// the prescribed values in place.
    fn start_from(&self, guess: &PlateSolution) -> Vec<f64> {
        let mesh = &self.mesh;
        let mut u = vec![0.0; M * mesh.n_nodes()];
        for j in 0..mesh.y_um.len() {
            for i in 0..mesh.x_um.len() {
                let n = mesh.node(i, j);
                u[M * n..M * n + M].copy_from_slice(&guess.node_values(mesh.x_um[i], mesh.y_um[j]));
            }
        }
        for &(d, v, _) in &self.constrained {
            u[d] = v;
        }
        u
    }

    /// The load vector over the 6 dofs per node.
    fn force(&self, loads: &[Load]) -> FeResult<Vec<f64>> {
        let f4 = load_vector(&self.mesh, loads, 0)?;
        let mut f = vec![0.0; M * self.mesh.n_nodes()];
        for (d, v) in f4.iter().enumerate() {
            f[M * (d / 4) + d % 4] = *v;
        }
        Ok(f)
    }

    /// Solve one load case by Newton iterations, stepping the load up from zero (steps halve when
    /// Newton fails to converge, and grow again when it converges fast).
    pub fn solve(&self, loads: &[Load]) -> FeResult<(PlateSolution, NewtonStats)> {
        let f = self.force(loads)?;
        let mut u = vec![0.0; f.len()];
        for &(d, v, _) in &self.constrained {
            u[d] = v;
        }
        let mut stats = NewtonStats::default();
        let (mut lambda, mut step) = (0.0f64, 1.0f64);
        let mut previous: Option<(f64, Vec<f64>)> = None;
        let mut attempts = 0;
        while lambda < 1.0 {
            attempts += 1;
            if attempts > self.opts.max_load_steps {
                return Err(FeError::Newton {
                    detail: format!(
                        "Newton did not converge within {} load steps (reached {:.1} % of the \
                         load)",
                        self.opts.max_load_steps,
                        lambda * 100.0
                    ),
                    hint: "the plate may buckle or snap at this load: lower the load or use the \
                           linear rung",
                });
            }
            let target = (lambda + step).min(1.0);
            // Predictor: extrapolate along the last converged step.
            let mut trial = u.clone();
            if let Some((l0, u0)) = &previous {
                let s = (target - lambda) / (lambda - l0);
                for ((t, a), b) in trial.iter_mut().zip(&u).zip(u0) {
                    *t = a + s * (a - b);
                }
            }
            match self.newton(&mut trial, &f, target, None, false, &mut stats)? {
                Some(iterations) => {
                    previous = Some((lambda, std::mem::replace(&mut u, trial)));
                    lambda = target;
                    stats.load_steps += 1;
                    if iterations <= 4 {
                        step *= 2.0;
                    }
                }
                None => {
                    step *= 0.5;
                    if step < 1e-4 {
                        return Err(FeError::Newton {
                            detail: format!(
                                "Newton failed at {:.1} % of the load even with tiny steps",
                                lambda * 100.0
                            ),
                            hint: "the plate may buckle or snap at this load",
                        });
                    }
                }
            }
        }
        Ok((self.solution(u, &f)?, stats))
    }

    /// A cheap estimate of the nonlinear field for many load cases at once: `corrections` modified
    /// Newton steps from the linear solution with the tangent at zero deflection, which is the
    /// linear bending stiffness beside the membrane stiffness (one factorisation for all cases,
    /// one multi-column solve per step). The first correction adds the membrane stretch the
    /// linear deflection implies and the tension's stiffening; for a weakly nonlinear case the
    /// result differs from the converged von Karman field by the square of its difference from
    /// the linear one, so it measures the linear plate's model error where that is small (and
    /// says "large" where it is not).
    pub fn modified_newton(
        &self,
        cases: &[Vec<Load>],
        corrections: usize,
    ) -> FeResult<Vec<PlateSolution>> {
        let mesh = &self.mesh;
        let n = self.free_dofs.len();
        let zero = vec![0.0; M * mesh.n_nodes()];
        let (_, vals) = self.internal(&zero, true);
        let vals = vals.expect("tangent requested");
        let llt = self.symbolic.factor(
            SparseColMat::<usize, f64>::new(self.pattern.symbolic.clone(), vals).as_ref(),
        )?;
        let forces: Vec<Vec<f64>> = cases
            .iter()
            .enumerate()
            .map(|(c, l)| {
                let f4 = load_vector(mesh, l, c)?;
                let mut f = vec![0.0; M * mesh.n_nodes()];
                for (d, v) in f4.iter().enumerate() {
                    f[M * (d / 4) + d % 4] = *v;
                }
                Ok(f)
            })
            .collect::<FeResult<_>>()?;
        let mut u: Vec<Vec<f64>> = vec![zero.clone(); cases.len()];
        for _ in 0..=corrections {
            let residuals: Vec<Vec<f64>> = u
                .par_iter()
                .map(|uc| {
                    if uc.iter().all(|v| *v == 0.0) {
                        zero.clone()
                    } else {
                        self.internal(uc, false).0
                    }
                })
                .collect();
            let mut rhs = Mat::<f64>::zeros(n, cases.len());
            for (c, (f, r)) in forces.iter().zip(&residuals).enumerate() {
                for (i, &d) in self.free_dofs.iter().enumerate() {
                    rhs[(i, c)] = f[d] - r[d];
                }
            }
            llt.solve_in_place(rhs.as_mut());
            for (c, uc) in u.iter_mut().enumerate() {
                for (i, &d) in self.free_dofs.iter().enumerate() {
                    uc[d] += rhs[(i, c)];
                }
            }
        }
        u.into_iter()
            .zip(&forces)
            .map(|(uc, f)| self.solution(uc, f))
            .collect()
    }

    /// Newton iterations at load factor `lambda` from `u`; the iteration count on convergence.
    /// Corrections are measured against `reference` (an energy), else against the first one.
    /// With `chord`, the factorisation is kept while it contracts the correction by at least
    /// [`CHORD_CONTRACTION`] per iteration (modified Newton from a close guess: a solve costs a
    /// fraction of a factorisation) and refreshed when it does not. None when the step fails
    /// (divergence, a tangent not positive definite); Err when a factor is refused for memory.
    fn newton(
        &self,
        u: &mut [f64],
        f: &[f64],
        lambda: f64,
        reference: Option<f64>,
        chord: bool,
        stats: &mut NewtonStats,
    ) -> FeResult<Option<usize>> {
        let mut first_energy = reference;
        let mut last_energy = f64::INFINITY;
        let mut llt: Option<CholeskyFactor> = None;
        let mut contraction = 1.0;
        for it in 1..=self.opts.max_iterations {
            let refactor = llt.is_none() || !chord || contraction > CHORD_CONTRACTION;
            let (r_int, vals) = self.internal(u, refactor);
            let mut rhs = Mat::<f64>::zeros(self.free_dofs.len(), 1);
            for (i, &d) in self.free_dofs.iter().enumerate() {
                rhs[(i, 0)] = lambda * f[d] - r_int[d];
            }
            if let Some(vals) = vals {
                // The old factor goes before the new one is built.
                drop(llt.take());
                // A tangent that is not positive definite fails the step; a factor refused for
                // memory ends the solve (smaller steps need the same factor).
                llt = match self.symbolic.factor(
                    SparseColMat::<usize, f64>::new(self.pattern.symbolic.clone(), vals).as_ref(),
                ) {
                    Ok(l) => Some(l),
                    Err(e @ FeError::OutOfMemory { .. }) => return Err(e),
                    Err(_) => return Ok(None),
                };
                stats.factorisations += 1;
            }
            stats.iterations += 1;
            let r0: Vec<f64> = (0..self.free_dofs.len()).map(|i| rhs[(i, 0)]).collect();
            let Some(l) = llt.as_ref() else {
                return Ok(None);
            };
            l.solve_in_place(rhs.as_mut());
            let mut energy = 0.0;
            for (i, &d) in self.free_dofs.iter().enumerate() {
                let du = rhs[(i, 0)];
                if !du.is_finite() {
                    return Ok(None);
                }
                energy += du * r0[i];
                u[d] += du;
            }
            let e0 = *first_energy.get_or_insert(energy.abs());
            let ratio = if e0 > 0.0 { energy.abs() / e0 } else { 0.0 };
            // Converged; or at the round-off floor (a Newton correction, from a fresh
            // factorisation, already small and no longer shrinking quadratically), where more
            // iterations only stir round-off. A kept factorisation (modified Newton) contracts
            // only linearly: its slow step is not the floor, and the next step refactors.
            let floor = refactor && ratio <= ROUND_OFF_RATIO && energy.abs() > 1e-2 * last_energy;
            if ratio <= self.opts.energy_tol || floor {
                return Ok(Some(it));
            }
            contraction = energy.abs() / last_energy;
            last_energy = energy.abs();
            if energy.abs() > 1e6 * e0 {
                return Ok(None);
            }
        }
        Ok(None)
    }

    /// The converged field as a plate solution: w part and membrane part, reactions f - R_int at
    /// the constrained w dofs.
    fn solution(&self, u: Vec<f64>, f: &[f64]) -> FeResult<PlateSolution> {
        if u.iter().any(|v| !v.is_finite()) {
            return Err(FeError::NonFinite {
                hint: "check material constants, thickness and load values for NaN/inf",
            });
        }
        let mesh = &self.mesh;
        let (r_int, _) = self.internal(&u, false);
        let mut by_group = vec![0.0; self.groups.len()];
        let mut nodal = Vec::new();
        let nxl = mesh.x_um.len();
        for &(d, _, g) in &self.constrained {
            if d % M == 0 {
                let r = f[d] - r_int[d];
                by_group[g] += r;
                let node = d / M;
                nodal.push(NodalReaction {
                    group: self.groups[g].clone(),
                    x_um: mesh.x_um[node % nxl],
                    y_um: mesh.y_um[node / nxl],
                    force_n: r,
                });
            }
        }
        let coupling = in_plane_spring::nodal_w_forces(&self.in_plane_springs, &u, M);
        for (i, node, force) in crate::fe::edge_spring::nodal_forces(&self.springs, &u, M)
            .into_iter()
            .chain(coupling)
        {
            let g = self
                .groups
                .iter()
                .position(|g| *g == self.springs[i].0.group)
                .expect("DofMap names every spring group");
            by_group[g] += force;
            nodal.push(NodalReaction {
                group: self.groups[g].clone(),
                x_um: mesh.x_um[node % nxl],
                y_um: mesh.y_um[node / nxl],
                force_n: force,
            });
        }
        let applied: f64 = f.iter().step_by(M).sum();
        let w: Vec<f64> = (0..mesh.n_nodes())
            .flat_map(|n| u[M * n..M * n + 4].to_vec())
            .collect();
        let uv: Vec<f64> = (0..mesh.n_nodes())
            .flat_map(|n| [u[M * n + 4], u[M * n + 5]])
            .collect();
        let reactions = self
            .groups
            .iter()
            .zip(by_group)
            .map(|(g, f)| GroupReaction {
                group: g.clone(),
                force_n: f,
            })
            .collect();
        Ok(PlateSolution::new(self.ctx.clone(), w, reactions, applied)
            .with_nodal(nodal)
            .with_membrane(uv))
    }
}

/// Centre deflection (m) and membrane force (N/m) of a strip of span `span_m` clamped along both
/// edges and held there in-plane, under a uniform pressure: cylindrical bending with
/// D w'''' - N w'' = q and the membrane force of the stretched line, N = A / (2 l) int w'^2 ds
/// (Timoshenko & Woinowsky-Krieger, Theory of Plates and Shells, 2nd ed., sec. 3). For a given N,
/// w(s) = C (cosh ks - cosh(kl/2)) + q (l^2/4 - s^2) / (2N) with k^2 = N / D and
/// C = q l / (2 N k sinh(kl/2)); N is found by bisection (the stretch falls as N grows) and the
/// integral by composite Gauss quadrature of the closed-form slope. The reference the plate is
/// tested and benchmarked against.
///
/// ```
/// use tactfab::fe::vonkarman::clamped_strip_reference;
/// // 100 um silicon-like strip (E' = 170 GPa) over 2 mm, 10 MPa: far beyond the linear range.
/// let (d, a) = (170e9 * 1e-12 / 12.0, 170e9 * 1e-4);
/// let (w0, n) = clamped_strip_reference(10e6, 2e-3, d, a);
/// let linear = 10e6 * (2e-3f64).powi(4) / (384.0 * d);
/// assert!(w0 < linear && n > 0.0);
/// ```
pub fn clamped_strip_reference(q_pa: f64, span_m: f64, d_nm: f64, a_n_per_m: f64) -> (f64, f64) {
    // w'(l/2) = 0: C k sinh(kl/2) = q l / (2N).
    strip_reference(q_pa, span_m, d_nm, a_n_per_m, |n, k| {
        q_pa * span_m / (2.0 * n * k * (0.5 * k * span_m).sinh())
    })
}

/// [`clamped_strip_reference`] for a strip simply supported along both edges (w = w'' = 0 there)
/// and held in-plane: the same w(s) with C = q / (N k^2 cosh(kl/2)) from w''(l/2) = 0 (Timoshenko
/// & Woinowsky-Krieger sec. 2).
///
/// ```
/// use tactfab::fe::vonkarman::simply_supported_strip_reference;
/// let (d, a) = (170e9 * 1e-12 / 12.0, 170e9 * 1e-4);
/// // w/t ~ 1.5e-3: the linear answer to ~1e-6 (much smaller loads lose digits to the
/// // cancellation of the two terms of w(s) as kl -> 0).
/// let (w0, _) = simply_supported_strip_reference(1e5, 2e-3, d, a);
/// let linear = 5.0 * 1e5 * (2e-3f64).powi(4) / (384.0 * d);
/// assert!((w0 - linear).abs() < 1e-3 * linear);
/// ```
pub fn simply_supported_strip_reference(
    q_pa: f64,
    span_m: f64,
    d_nm: f64,
    a_n_per_m: f64,
) -> (f64, f64) {
    strip_reference(q_pa, span_m, d_nm, a_n_per_m, |n, k| {
        q_pa / (n * k * k * (0.5 * k * span_m).cosh())
    })
}

/// Cylindrical bending with w(s) = C (cosh ks - cosh(kl/2)) + q (l^2/4 - s^2) / (2N), k^2 = N / D,
/// `c_of(N, k)` from the edge condition; N from the stretch of the held line by bisection.
fn strip_reference(
    q: f64,
    l: f64,
    d: f64,
    a_n_per_m: f64,
    c_of: impl Fn(f64, f64) -> f64,
) -> (f64, f64) {
    let slope_sq_integral = |n: f64| {
        let k = (n / d).sqrt();
        let c = c_of(n, k);
        let panels = 400;
        let mut sum = 0.0;
        for p in 0..panels {
            let s0 = -0.5 * l + l * p as f64 / panels as f64;
            for (s, w) in bfs::gauss4_on(s0, s0 + l / panels as f64) {
                let ws = c * k * (k * s).sinh() - q * s / n;
                sum += w * ws * ws;
            }
        }
        sum
    };
    let (mut lo, mut hi) = (1e-3f64, 1e9f64);
    for _ in 0..200 {
        let mid = (lo * hi).sqrt();
        if mid - a_n_per_m / (2.0 * l) * slope_sq_integral(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let n = (lo * hi).sqrt();
    let k = (n / d).sqrt();
    let c = c_of(n, k);
    (c * (1.0 - (0.5 * k * l).cosh()) + q * l * l / (8.0 * n), n)
}

#[cfg(test)]
mod element_tests {
    use super::*;
    use crate::fe::material::DieEdge;

    /// Strain energy of one element straight from the kinematics (1/2 eps^T A eps at the Gauss
    /// points plus the bending energy), independent of the factored force and tangent.
    fn energy(k: &ElementKind, ue: &[f64; NE]) -> f64 {
        let [a11, a12, a22, a66] = k.a;
        let mut u = 0.0;
        for i in 0..16 {
            for j in 0..16 {
                u += 0.5 * ue[i] * k.kb[i][j] * ue[j];
            }
        }
        for g in 0..16 {
            let wx: f64 = (0..16).map(|i| k.wx[g][i] * ue[i]).sum();
            let wy: f64 = (0..16).map(|i| k.wy[g][i] * ue[i]).sum();
            let (mut ux, mut uy, mut vx, mut vy) = (0.0, 0.0, 0.0, 0.0);
            for c in 0..4 {
                ux += k.mx[g][c] * ue[16 + 2 * c];
                uy += k.my[g][c] * ue[16 + 2 * c];
                vx += k.mx[g][c] * ue[17 + 2 * c];
                vy += k.my[g][c] * ue[17 + 2 * c];
            }
            let mut e = [ux + 0.5 * wx * wx, vy + 0.5 * wy * wy, uy + vx + wx * wy];
            if let Some(kb) = k.kappa.get(g) {
                for c in 0..3 {
                    e[c] += k.ecc * (0..16).map(|i| kb[c][i] * ue[i]).sum::<f64>();
                }
            }
            u += 0.5
                * k.wt[g]
                * (a11 * e[0] * e[0]
                    + 2.0 * a12 * e[0] * e[1]
                    + a22 * e[1] * e[1]
                    + a66 * e[2] * e[2]);
        }
        u
    }

    /// A state with every dof active: deflections of a few plate thicknesses, slopes ~1e-2,
    /// in-plane displacements of the size the membrane stretch gives.
    fn state() -> [f64; NE] {
        std::array::from_fn(|i| {
            let s = ((i * 7919 % 23) as f64 / 23.0 - 0.4) * if i % 2 == 0 { 1.0 } else { -1.3 };
            match (i < 16, i % 4) {
                (true, 0) => 3e-4 * s,
                (true, 3) => 20.0 * s,
                (true, _) => 3e-2 * s,
                (false, _) => 2e-6 * s,
            }
        })
    }

    #[test]
    fn force_is_the_energy_gradient_and_tangent_its_hessian() {
        let mat = PlateMaterial::silicon(DieEdge::Along110);
        // Centred, and a tooth's section rising 100 um above the reference plane.
        for ecc in [0.0, -100e-6] {
            let k = ElementKind::new(
                600e-6,
                400e-6,
                80e-6,
                ecc,
                &mat,
                mat.bending_stiffness(80e-6),
            );
            check_force_and_tangent(&k);
        }
    }

    /// A rigid translation does no work, so the element's vertical forces sum to zero, also far
    /// from w = 0. Before the mean deflection was taken out of K_b w the sum was ~1e-16 |K_b| w,
    /// the same in every element of a kind: on the bundled design's 380k-dof level a phantom
    /// force of 7.7e-5 of the load (the support sections' reactions). Here: 1.0e-13 of the
    /// element's largest force before, 3e-16 after.
    #[test]
    fn vertical_forces_balance_far_from_zero_deflection() {
        let mat = PlateMaterial::silicon(DieEdge::Along110);
        // A square and a sliver (feature lines 2 um apart run through the whole die), centred and
        // eccentric.
        for (b, ecc) in [(125e-6, 0.0), (2e-6, 0.0), (2e-6, -100e-6)] {
            let k = ElementKind::new(125e-6, b, 92e-6, ecc, &mat, mat.bending_stiffness(92e-6));
            let mut ue = state();
            let r0 = k.evaluate(&ue, None);
            for c in 0..4 {
                ue[4 * c] += 0.5;
            }
            let r = k.evaluate(&ue, None);
            let scale = r0.iter().fold(0f64, |m, v| m.max(v.abs()));
            let net: f64 = (0..4).map(|c| r[4 * c]).sum();
            assert!(net.abs() <= 1e-14 * scale, "net {net:.3e} of {scale:.3e}");
            for (a, b) in r.iter().zip(r0) {
                assert!((a - b).abs() <= 1e-9 * scale, "{a} vs {b}");
            }
        }
    }

    fn check_force_and_tangent(k: &ElementKind) {
        let ue = state();
        let mut kt = vec![0.0; NE * NE];
        let r = k.evaluate(&ue, Some(&mut kt));
        let r_only = k.evaluate(&ue, None);
        assert_eq!(
            r, r_only,
            "the force must not depend on whether the tangent is asked"
        );
        let scale = |i: usize| ue[i].abs().max(1e-12);
        let (mut worst_r, mut worst_k) = (0f64, 0f64);
        let r_max = r.iter().fold(0f64, |m, v| m.max(v.abs() * scale(0)));
        for j in 0..NE {
            let h = 1e-5 * scale(j);
            let (mut up, mut dn) = (ue, ue);
            up[j] += h;
            dn[j] -= h;
            // dU/du_j by central differences (exact for a quartic up to h^2 terms).
            let g = (energy(k, &up) - energy(k, &dn)) / (2.0 * h);
            worst_r = worst_r.max((g - r[j]).abs() / r[j].abs().max(1e-3 * r_max / scale(j)));
            let (rp, rn) = (k.evaluate(&up, None), k.evaluate(&dn, None));
            for i in 0..NE {
                let fd = (rp[i] - rn[i]) / (2.0 * h);
                let kij = kt[i * NE + j];
                let norm = (kt[i * NE + i] * kt[j * NE + j]).abs().sqrt();
                worst_k = worst_k.max((fd - kij).abs() / norm);
            }
        }
        assert!(worst_r < 1e-6, "force vs energy gradient: {worst_r:.2e}");
        assert!(
            worst_k < 1e-6,
            "tangent vs force differences: {worst_k:.2e}"
        );
        for i in 0..NE {
            for j in 0..i {
                let (a, b) = (kt[i * NE + j], kt[j * NE + i]);
                assert!(
                    (a - b).abs() <= 1e-12 * (a.abs() + b.abs() + 1.0),
                    "symmetric"
                );
            }
        }
    }
}
