//! Post-processing of one load case: deflection, curvature, moments, strains, stress and reactions.
//! Conventions: w positive in the load direction; kappa = (-w_xx, -w_yy, -2 w_xy); the bottom
//! surface is the side facing +w (z = +t/2 along w), so eps_bottom = (t/2) kappa and sagging puts
//! it in tension.

use crate::fe::bfs;
use crate::fe::dofs::element_dofs;
use crate::fe::material::PlateMaterial;
use crate::fe::mesh::RectMesh;
use crate::fe::problem::RectUm;
use serde::Serialize;
use std::sync::Arc;

/// Deflection beyond this fraction of the thickness leaves the linear (small-deflection) range.
pub const LINEAR_RANGE_LIMIT: f64 = 0.2;

/// Data shared by all load cases of one factorisation.
#[derive(Debug, Clone, PartialEq)]
pub struct SolutionContext {
    pub mesh: RectMesh,
    pub thickness_um: Vec<f64>,
    /// Mid-plane rise of each element's section ([`crate::fe::ThicknessRegion::rise_um`]) on a
    /// von Karman solution, whose membrane strain is the reference plane's; empty otherwise (each
    /// section about its own mid-plane).
    pub rise_um: Vec<f64>,
    pub material: PlateMaterial,
    pub groups: Vec<String>,
}

/// Force (N) carried by a support group in the load direction (sum over its w dofs of f - K u).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GroupReaction {
    pub group: String,
    pub force_n: f64,
}

/// Location and value of an extreme deflection.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DeflectionPeak {
    pub x_um: f64,
    pub y_um: f64,
    pub w_m: f64,
}

/// Plate surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Surface {
    /// Side facing +w (away from the load).
    Bottom,
    /// Loaded side.
    Top,
}

/// Location and value of the largest principal (tensile) bending stress.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StressPeak {
    pub x_um: f64,
    pub y_um: f64,
    pub sigma_pa: f64,
    pub surface: Surface,
}

/// The plate's resultants at a point ([`PlateSolution::resultants`]), in the mesh's axes: M = D
/// kappa (N m/m, sagging positive), N = Q t eps0 (N/m), kappa = (-w_xx, -w_yy, -2 w_xy) (1/m),
/// eps0 the mid-plane strain (zero on a linear solution).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Resultants {
    pub moments: [f64; 3],
    pub membrane_forces: [f64; 3],
    pub curvature: [f64; 3],
    pub membrane_strain: [f64; 3],
}

/// Serializable summary of one load case.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SolutionSummary {
    pub max_deflection: DeflectionPeak,
    pub applied_force_n: f64,
    pub reactions: Vec<GroupReaction>,
    pub linear_range_ratio: f64,
}

/// Solution of one load case.
#[derive(Debug, Clone)]
pub struct PlateSolution {
    ctx: Arc<SolutionContext>,
    u: Vec<f64>,
    reactions: Vec<GroupReaction>,
    nodal: Vec<NodalReaction>,
    applied_force_n: f64,
    /// In-plane displacements (u, v) per node in metres, bilinear per element: present on a von
    /// Karman solution ([`crate::fe::vonkarman`]), whose strains then add the membrane strain.
    membrane: Option<Vec<f64>>,
}

/// Support force at one constrained node (w dof), in the load direction.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NodalReaction {
    pub group: String,
    pub x_um: f64,
    pub y_um: f64,
    pub force_n: f64,
}

impl PlateSolution {
    pub(crate) fn new(
        ctx: Arc<SolutionContext>,
        u: Vec<f64>,
        reactions: Vec<GroupReaction>,
        applied_force_n: f64,
    ) -> Self {
        PlateSolution {
            membrane: None,
            nodal: Vec::new(),
            ctx,
            u,
            reactions,
            applied_force_n,
        }
    }

    /// The mesh of this solution.
    pub fn mesh(&self) -> &RectMesh {
        &self.ctx.mesh
    }
    /// Global dof vector (4 per node: w \[m\], w_x, w_y, w_xy [1/m]).
    pub fn dofs(&self) -> &[f64] {
        &self.u
    }
    /// Total applied force (N, positive in +w).
    pub fn applied_force_n(&self) -> f64 {
        self.applied_force_n
    }
    /// Support forces per group (in order of first appearance).
    pub fn reactions(&self) -> &[GroupReaction] {
        &self.reactions
    }
    pub(crate) fn with_nodal(mut self, nodal: Vec<NodalReaction>) -> Self {
        self.nodal = nodal;
        self
    }
    pub(crate) fn with_membrane(mut self, uv: Vec<f64>) -> Self {
        self.membrane = Some(uv);
        self
    }
    /// In-plane displacements (u, v per node, m) of a von Karman solution.
    pub(crate) fn membrane(&self) -> Option<&[f64]> {
        self.membrane.as_deref()
    }
    /// True for a geometrically nonlinear (von Karman) solution.
    pub fn is_nonlinear(&self) -> bool {
        self.membrane.is_some()
    }
    /// Mid-plane (membrane) strain (eps_x, eps_y, gamma_xy) of element `e` at local (x, y) in m:
    /// (u_x + w_x^2/2, v_y + w_y^2/2, u_y + v_x + w_x w_y) (von Karman; Reddy, Theory and
    /// Analysis of Elastic Plates and Shells, Eq. 3.3.10); zero on a linear solution.
    fn membrane_strain(&self, e: usize, x: f64, y: f64) -> [f64; 3] {
        if self.membrane.is_none() {
            return [0.0; 3];
        }
        let (a, b) = self.element_size_m(e);
        let s = bfs::shape(x, y, a, b);
        self.membrane_strain_with(e, x, y, &s, &self.element_u(e))
    }
    /// [`Self::membrane_strain`] with the shape functions and element dofs already at hand.
    fn membrane_strain_with(
        &self,
        e: usize,
        x: f64,
        y: f64,
        s: &[[f64; 16]; 6],
        u: &[f64; 16],
    ) -> [f64; 3] {
        let Some(uv) = &self.membrane else {
            return [0.0; 3];
        };
        let (a, b) = self.element_size_m(e);
        let nodes = self.ctx.mesh.element_nodes(e);
        let (dx, dy) = crate::fe::vonkarman::q4_gradients(x, y, a, b);
        let (mut ux, mut uy, mut vx, mut vy) = (0.0, 0.0, 0.0, 0.0);
        for (k, &n) in nodes.iter().enumerate() {
            ux += dx[k] * uv[2 * n];
            uy += dy[k] * uv[2 * n];
            vx += dx[k] * uv[2 * n + 1];
            vy += dy[k] * uv[2 * n + 1];
        }
        let wx: f64 = s[1].iter().zip(u).map(|(p, q)| p * q).sum();
        let wy: f64 = s[2].iter().zip(u).map(|(p, q)| p * q).sum();
        [ux + 0.5 * wx * wx, vy + 0.5 * wy * wy, uy + vx + wx * wy]
    }
    /// The six von Karman nodal values (w, w_x, w_y, w_xy, u, v) this field takes at a point, by
    /// element interpolation: the starting guess of a finer mesh's Newton solve.
    #[track_caller]
    pub(crate) fn node_values(&self, x_um: f64, y_um: f64) -> [f64; 6] {
        let Some((e, lx, ly)) = self.ctx.mesh.locate(x_um, y_um) else {
            panic!("point ({x_um}, {y_um}) um is outside the plate");
        };
        let (a, b) = self.element_size_m(e);
        let u = self.element_u(e);
        let s = bfs::shape(lx, ly, a, b);
        let dot = |row: &[f64; 16]| row.iter().zip(&u).map(|(p, q)| p * q).sum::<f64>();
        let (mut uu, mut vv) = (0.0, 0.0);
        if let Some(uv) = &self.membrane {
            for (k, &(ix, iy)) in bfs::CORNERS.iter().enumerate() {
                let fx = if ix == 1 { lx / a } else { 1.0 - lx / a };
                let fy = if iy == 1 { ly / b } else { 1.0 - ly / b };
                let n = self.ctx.mesh.element_nodes(e)[k];
                uu += fx * fy * uv[2 * n];
                vv += fx * fy * uv[2 * n + 1];
            }
        }
        [dot(&s[0]), dot(&s[1]), dot(&s[2]), dot(&s[5]), uu, vv]
    }
    /// Curvature (-w_xx, -w_yy, -2 w_xy) in 1/m and membrane strain (eps0_x, eps0_y, gamma0_xy)
    /// of element `e` at local (x, y) m, from one shape evaluation.
    fn curvature_and_membrane_strain(&self, e: usize, x: f64, y: f64) -> ([f64; 3], [f64; 3]) {
        let (a, b) = self.element_size_m(e);
        let u = self.element_u(e);
        let s = bfs::shape(x, y, a, b);
        let dot = |row: &[f64; 16]| row.iter().zip(&u).map(|(p, q)| p * q).sum::<f64>();
        let k = [-dot(&s[3]), -dot(&s[4]), -2.0 * dot(&s[5])];
        (k, self.membrane_strain_with(e, x, y, &s, &u))
    }
    /// Distances (m) from the reference plane to element `e`'s bottom and top faces, at
    /// z = t/2 - rise and -(t/2 + rise) along +w: t/2 each on a centred section.
    fn face_depths_m(&self, e: usize) -> [f64; 2] {
        self.face_depths_below_m(e, 0.0)
    }

    /// [`Self::face_depths_m`] with `below_um` added to each (one rounding, as before the rise).
    fn face_depths_below_m(&self, e: usize, below_um: f64) -> [f64; 2] {
        let (h, rise) = (
            0.5 * self.ctx.thickness_um[e],
            self.ctx.rise_um.get(e).copied().unwrap_or(0.0),
        );
        [(h - rise + below_um) * 1e-6, (h + rise + below_um) * 1e-6]
    }

    /// Surface stresses (sigma_x, sigma_y, tau_xy) in Pa of element `e` at local (x, y) m:
    /// [bottom, top], sigma = Q (eps0 + z kappa) at the faces' z ([`Self::face_depths_m`]).
    pub(crate) fn surface_stresses(&self, e: usize, x: f64, y: f64) -> [[f64; 3]; 2] {
        let (k, m) = self.curvature_and_membrane_strain(e, x, y);
        let [hb, ht] = self.face_depths_m(e);
        [hb, -ht].map(|h| {
            self.ctx
                .material
                .stress(m[0] + h * k[0], m[1] + h * k[1], m[2] + h * k[2])
        })
    }
    /// The plate's resultants at a point, from one element evaluation (None outside the
    /// plate): what a section of the structure there is driven by.
    pub fn resultants(&self, x_um: f64, y_um: f64) -> Option<Resultants> {
        let (e, lx, ly) = self.ctx.mesh.locate(x_um, y_um)?;
        let (curvature, mut membrane_strain) = self.curvature_and_membrane_strain(e, lx, ly);
        let t = self.ctx.thickness_um[e] * 1e-6;
        // The section's own mid-plane strain: eps0 + z kappa at z = -rise.
        let [hb, ht] = self.face_depths_m(e);
        if hb != ht {
            (0..3).for_each(|c| membrane_strain[c] += 0.5 * (hb - ht) * curvature[c]);
        }
        Some(Resultants {
            moments: bfs::moments(curvature, &self.ctx.material.bending_stiffness(t)),
            membrane_forces: self
                .ctx
                .material
                .stress(membrane_strain[0], membrane_strain[1], membrane_strain[2])
                .map(|v| v * t),
            curvature,
            membrane_strain,
        })
    }
    /// In-plane force resultants (N_x, N_y, N_xy) in N/m at a point, N = Q t eps0; zero on a
    /// linear solution.
    #[track_caller]
    pub fn membrane_forces(&self, x_um: f64, y_um: f64) -> [f64; 3] {
        self.resultants_or_panic(x_um, y_um).membrane_forces
    }
    pub(crate) fn context(&self) -> &SolutionContext {
        &self.ctx
    }
    pub(crate) fn all_nodal_reactions(&self) -> &[NodalReaction] {
        &self.nodal
    }

    /// Nodal support forces of one group, in mesh order (consistent nodal forces: each stands for
    /// its node's tributary length of the line).
    pub fn nodal_reactions(&self, group: &str) -> Vec<&NodalReaction> {
        self.nodal.iter().filter(|r| r.group == group).collect()
    }

    /// Support force of one group (N), None for an unknown group.
    pub fn reaction_n(&self, group: &str) -> Option<f64> {
        self.reactions
            .iter()
            .find(|r| r.group == group)
            .map(|r| r.force_n)
    }

    pub(crate) fn element_u(&self, e: usize) -> [f64; 16] {
        element_dofs(&self.ctx.mesh, e).map(|d| self.u[d])
    }

    pub(crate) fn element_size_m(&self, e: usize) -> (f64, f64) {
        let (x0, y0, x1, y1) = self.ctx.mesh.element_bounds_um(e);
        ((x1 - x0) * 1e-6, (y1 - y0) * 1e-6)
    }

    #[track_caller]
    fn at(&self, x_um: f64, y_um: f64) -> (usize, f64, [f64; 3]) {
        let Some((e, lx, ly)) = self.ctx.mesh.locate(x_um, y_um) else {
            panic!("point ({x_um}, {y_um}) um is outside the plate");
        };
        let (a, b) = self.element_size_m(e);
        let (w, k) = bfs::deflection_curvature(&self.element_u(e), lx, ly, a, b);
        (e, w, k)
    }

    /// Deflection w (m, positive in the load direction) at (x, y) by element interpolation. Panics
    /// outside the plate.
    #[track_caller]
    pub fn deflection_m(&self, x_um: f64, y_um: f64) -> f64 {
        self.at(x_um, y_um).1
    }

    /// Curvature (kappa_x, kappa_y, kappa_xy) in 1/m at a point (element on the upper/right side of
    /// mesh lines).
    #[track_caller]
    pub fn curvature(&self, x_um: f64, y_um: f64) -> [f64; 3] {
        self.resultants_or_panic(x_um, y_um).curvature
    }

    /// Bending moments per unit length (Mx, My, Mxy) in N, M = D kappa (sagging positive).
    #[track_caller]
    pub fn moments(&self, x_um: f64, y_um: f64) -> [f64; 3] {
        self.resultants_or_panic(x_um, y_um).moments
    }

    #[track_caller]
    fn resultants_or_panic(&self, x_um: f64, y_um: f64) -> Resultants {
        self.resultants(x_um, y_um)
            .unwrap_or_else(|| panic!("point ({x_um}, {y_um}) um is outside the plate"))
    }

    /// Bottom-surface strain (eps_x, eps_y, gamma_xy) = (t/2) kappa (Kirchhoff kinematics eps = z
    /// kappa), t = local thickness: each section bends about its own mid-plane, so on a stepped
    /// plate with a flat bottom the local neutral-axis offset is t/2 on the linear plate.
    /// On a von Karman solution the membrane strain is added: eps = eps0 + z_b kappa, with the
    /// bottom at z_b = t/2 - rise from the reference plane (`SolutionContext::rise_um`).
    #[track_caller]
    pub fn bottom_strain(&self, x_um: f64, y_um: f64) -> [f64; 3] {
        let (e, _, k) = self.at(x_um, y_um);
        let h = self.face_depths_m(e)[0];
        let (_, lx, ly) = self
            .ctx
            .mesh
            .locate(x_um, y_um)
            .expect("inside: at() checked");
        let m = self.membrane_strain(e, lx, ly);
        [0, 1, 2].map(|i| m[i] + h * k[i])
    }

    /// Clipped parts of a rectangle per element: (element, local x0, x1, y0, y1 in m).
    pub(crate) fn clipped(&self, r: &RectUm) -> Vec<(usize, f64, f64, f64, f64)> {
        let m = &self.ctx.mesh;
        let r = r.normalised();
        let mut out = Vec::new();
        for i in RectMesh::axis_range(&m.x_um, r.x0_um, r.x1_um) {
            for j in RectMesh::axis_range(&m.y_um, r.y0_um, r.y1_um) {
                let e = m.element(i, j);
                let (ex0, ey0, ex1, ey1) = m.element_bounds_um(e);
                let (cx0, cx1, cy0, cy1) = (
                    r.x0_um.max(ex0),
                    r.x1_um.min(ex1),
                    r.y0_um.max(ey0),
                    r.y1_um.min(ey1),
                );
                if cx1 >= cx0 && cy1 >= cy0 {
                    out.push((
                        e,
                        (cx0 - ex0) * 1e-6,
                        (cx1 - ex0) * 1e-6,
                        (cy0 - ey0) * 1e-6,
                        (cy1 - ey0) * 1e-6,
                    ));
                }
            }
        }
        out
    }

    /// (int eps_x dA, int eps_y dA) of the bottom-surface strain over a rectangle (m^2), clipped
    /// per element: whole elements in closed form ([`bfs::curvature_integral`], with a membrane
    /// its bilinear stretch in closed form and [`bfs::slope_square_integral`]), partly covered
    /// ones by 4x4 Gauss per clipped part (exact for the BFS curvature field).
    pub fn integrate_bottom_strain(&self, rect: RectUm) -> (f64, f64) {
        self.integrate_strain_below(rect, 0.0)
    }

    /// [`Self::integrate_bottom_strain`] of the strain `below_um` under the bottom surface, where
    /// a layer bonded under the plate (a PVDF film) has its mid-plane: eps = eps0 + z kappa with
    /// z = t/2 + below (Kirchhoff: plane sections stay plane through the bonded layer).
    pub fn integrate_strain_below(&self, rect: RectUm, below_um: f64) -> (f64, f64) {
        let (mut sx, mut sy) = (0.0, 0.0);
        for (e, x0, x1, y0, y1) in self.clipped(&rect) {
            let (a, b) = self.element_size_m(e);
            let u = self.element_u(e);
            let h = self.face_depths_below_m(e, below_um)[0];
            let whole = |lo: f64, hi: f64, len: f64| {
                lo.abs() <= 1e-9 * len && (hi - len).abs() <= 1e-9 * len
            };
            if whole(x0, x1, a) && whole(y0, y1, b) {
                let (ix, iy) = bfs::curvature_integral(&u, a, b);
                sx += h * ix;
                sy += h * iy;
                if let Some(uv) = &self.membrane {
                    // int u_x dA = b/2 (u_1 + u_2 - u_0 - u_3) for the bilinear u (corners in
                    // BFS order), likewise v_y; then the slope squares.
                    let n = self.ctx.mesh.element_nodes(e);
                    let (u_, v_) = (|k: usize| uv[2 * n[k]], |k: usize| uv[2 * n[k] + 1]);
                    let (qx, qy) = bfs::slope_square_integral(&u, a, b);
                    sx += 0.5 * b * (u_(1) + u_(2) - u_(0) - u_(3)) + qx;
                    sy += 0.5 * a * (v_(3) + v_(2) - v_(0) - v_(1)) + qy;
                }
                continue;
            }
            for (x, wx) in bfs::gauss4_on(x0, x1) {
                for (y, wy) in bfs::gauss4_on(y0, y1) {
                    let (_, k) = bfs::deflection_curvature(&u, x, y, a, b);
                    let m = self.membrane_strain(e, x, y);
                    sx += wx * wy * (m[0] + h * k[0]);
                    sy += wx * wy * (m[1] + h * k[1]);
                }
            }
        }
        (sx, sy)
    }

    /// Largest principal tensile bending stress on either surface over a rectangle (e.g. a contact
    /// patch), sampled on a 5x5 grid including the edges of every clipped element part; None if
    /// the rectangle does not overlap the plate.
    /// sigma = Q (eps0 +/- (t/2) kappa) on the bottom/top (eps0 = 0 on a linear solution); sigma_1 = (sx+sy)/2 +
    /// sqrt(((sx-sy)/2)^2 + txy^2).
    pub fn max_principal_stress(&self, rect: RectUm) -> Option<StressPeak> {
        let mut best = StressPeak {
            x_um: f64::NAN,
            y_um: f64::NAN,
            sigma_pa: f64::NEG_INFINITY,
            surface: Surface::Bottom,
        };
        let m = &self.ctx.mesh;
        for (e, x0, x1, y0, y1) in self.clipped(&rect) {
            let (a, b) = self.element_size_m(e);
            let u = self.element_u(e);
            let [hb, ht] = self.face_depths_m(e);
            let (ex0, ey0, _, _) = m.element_bounds_um(e);
            for p in 0..5 {
                for q in 0..5 {
                    let x = x0 + (x1 - x0) * p as f64 / 4.0;
                    let y = y0 + (y1 - y0) * q as f64 / 4.0;
                    let (_, k) = bfs::deflection_curvature(&u, x, y, a, b);
                    let m = self.membrane_strain(e, x, y);
                    let principal = |h: f64| {
                        let s = self.ctx.material.stress(
                            m[0] + h * k[0],
                            m[1] + h * k[1],
                            m[2] + h * k[2],
                        );
                        0.5 * (s[0] + s[1]) + (0.25 * (s[0] - s[1]).powi(2) + s[2] * s[2]).sqrt()
                    };
                    for (sigma, surface) in [
                        (principal(hb), Surface::Bottom),
                        (principal(-ht), Surface::Top),
                    ] {
                        if sigma > best.sigma_pa {
                            best = StressPeak {
                                x_um: ex0 + x * 1e6,
                                y_um: ey0 + y * 1e6,
                                sigma_pa: sigma,
                                surface,
                            };
                        }
                    }
                }
            }
        }
        best.sigma_pa.is_finite().then_some(best)
    }

    /// Largest |w| over nodes and 4x4 Gauss points of every element, polished by Newton steps on
    /// grad w = 0 inside the best element. Returns the signed value.
    pub fn max_deflection(&self) -> DeflectionPeak {
        let m = &self.ctx.mesh;
        let nxl = m.x_um.len();
        let mut best = DeflectionPeak {
            x_um: m.x_um[0],
            y_um: m.y_um[0],
            w_m: 0.0,
        };
        let mut best_e = 0;
        for n in 0..m.n_nodes() {
            let w = self.u[4 * n];
            if w.abs() > best.w_m.abs() {
                best = DeflectionPeak {
                    x_um: m.x_um[n % nxl],
                    y_um: m.y_um[n / nxl],
                    w_m: w,
                };
                best_e = m.locate(best.x_um, best.y_um).map_or(0, |l| l.0);
            }
        }
        for e in 0..m.n_elements() {
            let (a, b) = self.element_size_m(e);
            let u = self.element_u(e);
            // |w| <= max |w_i| + sum (4a/27 |w_x,i| + 4b/27 |w_y,i| + 16ab/729 |w_xy,i|) in the
            // element (the value Hermite cubics are in [0, 1] and sum to 1; the slope ones peak at
            // len 4/27): elements that cannot beat the best so far are skipped.
            let bound = (0..4).map(|c| u[4 * c].abs()).fold(0.0, f64::max)
                + (0..4)
                    .map(|c| {
                        4.0 / 27.0 * (a * u[4 * c + 1].abs() + b * u[4 * c + 2].abs())
                            + 16.0 / 729.0 * a * b * u[4 * c + 3].abs()
                    })
                    .sum::<f64>();
            if bound <= best.w_m.abs() {
                continue;
            }
            let (ex0, ey0, _, _) = m.element_bounds_um(e);
            for (x, _) in bfs::gauss4_on(0.0, a) {
                for (y, _) in bfs::gauss4_on(0.0, b) {
                    let w = bfs::shape(x, y, a, b)[0]
                        .iter()
                        .zip(&u)
                        .map(|(n, v)| n * v)
                        .sum::<f64>();
                    if w.abs() > best.w_m.abs() {
                        best = DeflectionPeak {
                            x_um: ex0 + x * 1e6,
                            y_um: ey0 + y * 1e6,
                            w_m: w,
                        };
                        best_e = e;
                    }
                }
            }
        }
        // Newton polish in the best element.
        let (a, b) = self.element_size_m(best_e);
        let u = self.element_u(best_e);
        let (ex0, ey0, _, _) = m.element_bounds_um(best_e);
        let (mut x, mut y) = (
            ((best.x_um - ex0) * 1e-6).clamp(0.0, a),
            ((best.y_um - ey0) * 1e-6).clamp(0.0, b),
        );
        for _ in 0..12 {
            let s = bfs::shape(x, y, a, b);
            let d = |k: usize| s[k].iter().zip(&u).map(|(n, v)| n * v).sum::<f64>();
            let (gx, gy, hxx, hyy, hxy) = (d(1), d(2), d(3), d(4), d(5));
            let det = hxx * hyy - hxy * hxy;
            if det.abs() < 1e-300 {
                break;
            }
            let (nx, ny) = (
                (x - (hyy * gx - hxy * gy) / det).clamp(0.0, a),
                (y - (hxx * gy - hxy * gx) / det).clamp(0.0, b),
            );
            let w = bfs::shape(nx, ny, a, b)[0]
                .iter()
                .zip(&u)
                .map(|(n, v)| n * v)
                .sum::<f64>();
            if w.abs() >= best.w_m.abs() {
                best = DeflectionPeak {
                    x_um: ex0 + nx * 1e6,
                    y_um: ey0 + ny * 1e6,
                    w_m: w,
                };
            }
            if (nx - x).abs() < 1e-12 * a && (ny - y).abs() < 1e-12 * b {
                break;
            }
            (x, y) = (nx, ny);
        }
        best
    }

    /// max |w| / t at the location of the largest deflection; above [`LINEAR_RANGE_LIMIT`] membrane
    /// stiffening matters and the linear model is leaving its range.
    pub fn linear_range_ratio(&self) -> f64 {
        self.linear_range_ratio_at(&self.max_deflection())
    }

    /// [`Self::linear_range_ratio`] for a peak already found by [`Self::max_deflection`].
    pub fn linear_range_ratio_at(&self, p: &DeflectionPeak) -> f64 {
        let e = self.ctx.mesh.locate(p.x_um, p.y_um).map_or(0, |l| l.0);
        p.w_m.abs() / (self.ctx.thickness_um[e] * 1e-6)
    }

    /// True when the deflection exceeds 0.2 x thickness (membrane stiffening ignored).
    pub fn exceeds_linear_range(&self) -> bool {
        self.linear_range_ratio() > LINEAR_RANGE_LIMIT
    }

    /// Serializable summary.
    pub fn summary(&self) -> SolutionSummary {
        SolutionSummary {
            max_deflection: self.max_deflection(),
            applied_force_n: self.applied_force_n,
            reactions: self.reactions.clone(),
            linear_range_ratio: self.linear_range_ratio(),
        }
    }
}
