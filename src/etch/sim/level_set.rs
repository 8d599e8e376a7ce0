//! The etched surface as a height field z = h(x, y) on a (100) wafer and its 2.5-D level-set
//! advance.
//!
//! Silicon lies below z = h. A surface point with outward normal n moves into the silicon at
//! R(n), so the graph obeys h_t + H(grad h) = 0 with H(p, q) = R(n) sqrt(1 + p^2 + q^2),
//! n = (-p, -q, 1) / sqrt(1 + p^2 + q^2) (Osher & Fedkiw, Level Set Methods, 2003, eq. 6.1 for a
//! graph). It holds for mesas and cavities whose facets do not overhang, which is the case for a
//! {111}-bounded (100) etch with convex-corner bevels.
//!
//! Exposed nodes advance by the Lax-Friedrichs scheme (Osher & Fedkiw eq. 5.7: H at the central
//! gradient, minus alpha (D+ - D-) / 2 per axis), monotone for any H, hence convergent to the
//! viscosity solution where R(n) is not convex; ViennaPS's wet-etch example uses the local form
//! of the same scheme. Alpha is a global bound of |dH/dp|: H is F(-p, -q, 1) with F(v) = |v|
//! R(v / |v|) homogeneous of degree 1, so dH/dp depends only on the normal and its bound over
//! the upper half sphere holds for every slope. The step obeys dt (ax / dx + ay / dy) <= CFL.
//!
//! The oxide mask at z = 0 is a lid the silicon under it is released from only sideways: a
//! covered node stays at 0 until the wall of an exposed axis neighbour, continued to it, is
//! below 0, and an exposed node beside the lid sees the surface rise into it along that wall
//! (`Field::rise`). Under a straight edge the wall is the slowest-undercutting one (the tilt
//! theta minimising R / sin theta: {111} at 54.74 deg under a <110> edge, the undercut R111 t /
//! sin 54.74 deg of `etch::geometry::undercut_um`), so vicinal (100) planes never eat the lid;
//! near a convex corner it is the plane of the fast-plane fan the exposed surface has there,
//! which is how the corner undercut comes in. Measured against closed forms in
//! `tests_closed_form.rs`: the pit depth and wall angle to 0.03 % and 0.01 deg (extrapolated),
//! the straight edge within two cells, the convex corner's undercut 8 % below the {110}-facet
//! closed form.
//!
//! The four sides of the grid are mirror planes (symmetry lines of the simulated cell).

use rayon::prelude::*;

use super::rate_table::RateModel;
use super::SimError;

/// Most grid nodes one simulation may allocate (4 million: 32 MB per height field).
pub const MAX_NODES: usize = 4_000_000;
/// Most time steps one advance may take.
pub const MAX_STEPS: usize = 200_000;
/// Courant number of the Lax-Friedrichs step (<= 1 for monotonicity).
pub const CFL: f64 = 0.9;

/// A node grid with spacing dx, dy; node (i, j) at (x0 + i dx, y0 + j dy).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid {
    pub nx: usize,
    pub ny: usize,
    pub dx_um: f64,
    pub dy_um: f64,
    pub x0_um: f64,
    pub y0_um: f64,
}

impl Grid {
    /// The grid with nodes on both ends of [x0, x0 + lx] x [y0, y0 + ly] and spacing as close to
    /// `step_um` as divides the lengths; an error if it would exceed [`MAX_NODES`].
    pub fn covering(
        x0_um: f64,
        y0_um: f64,
        lx_um: f64,
        ly_um: f64,
        step_um: f64,
    ) -> Result<Grid, SimError> {
        let ok = |v: f64| v.is_finite() && v > 0.0;
        if !(ok(lx_um) && ok(ly_um) && ok(step_um)) {
            return Err(SimError::BadGrid {
                what: format!("cell {lx_um} x {ly_um} um at a {step_um} um step"),
            });
        }
        let cx = (lx_um / step_um).round().max(2.0);
        let cy = (ly_um / step_um).round().max(2.0);
        let nodes = (cx + 1.0) * (cy + 1.0);
        if nodes > MAX_NODES as f64 {
            return Err(SimError::GridTooLarge {
                nodes,
                max: MAX_NODES,
                step_um,
            });
        }
        Ok(Grid {
            nx: cx as usize + 1,
            ny: cy as usize + 1,
            dx_um: lx_um / cx,
            dy_um: ly_um / cy,
            x0_um,
            y0_um,
        })
    }

    pub fn len(&self) -> usize {
        self.nx * self.ny
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub fn x_um(&self, i: usize) -> f64 {
        self.x0_um + i as f64 * self.dx_um
    }

    pub fn y_um(&self, j: usize) -> f64 {
        self.y0_um + j as f64 * self.dy_um
    }

    /// Mirror index: -1 -> 1, n -> n - 2.
    fn mirror(k: isize, n: usize) -> usize {
        if k < 0 {
            (-k) as usize
        } else if k as usize >= n {
            2 * (n - 1) - k as usize
        } else {
            k as usize
        }
    }
}

/// The silicon surface and its mask at one time.
#[derive(Debug, Clone)]
pub struct Surface {
    pub grid: Grid,
    /// Height of the silicon surface (um, <= 0; 0 is the wafer top), row-major in x.
    pub h_um: Vec<f64>,
    /// The node is under the drawn mask and still touches it.
    pub covered: Vec<bool>,
    pub time_h: f64,
}

impl Surface {
    /// A flat wafer with the mask where `drawn` is true (a closed raster: nodes on a drawn
    /// edge are true).
    ///
    /// The lid is the drawn raster eroded by one node: an exposed node beside the lid stands at
    /// the top of the wall that rises into it (`Field::rise`), so the first exposed node, not the
    /// last covered one, is where the drawn edge is. Without this the mask would act one cell
    /// larger.
    #[track_caller]
    pub fn new(grid: Grid, drawn: Vec<bool>) -> Surface {
        assert_eq!(drawn.len(), grid.len(), "mask raster does not fit the grid");
        let (nx, ny) = (grid.nx, grid.ny);
        let at = |i: isize, j: isize| drawn[Grid::mirror(j, ny) * nx + Grid::mirror(i, nx)];
        let mut covered = vec![false; grid.len()];
        for j in 0..ny as isize {
            for i in 0..nx as isize {
                covered[j as usize * nx + i as usize] =
                    at(i, j) && at(i - 1, j) && at(i + 1, j) && at(i, j - 1) && at(i, j + 1);
            }
        }
        Surface {
            grid,
            h_um: vec![0.0; grid.len()],
            covered,
            time_h: 0.0,
        }
    }

    /// Height at node (i, j).
    pub fn h(&self, i: usize, j: usize) -> f64 {
        self.h_um[j * self.grid.nx + i]
    }
}

/// The scheme's constants for one rate model on one grid.
#[derive(Debug, Clone)]
pub struct Stepper {
    model: RateModel,
    alpha_x: f64,
    alpha_y: f64,
    /// Slope of the slowest-undercutting wall behind an x (y) neighbour.
    release_slope_x: f64,
    release_slope_y: f64,
    dt_max_h: f64,
}

impl Stepper {
    pub fn new(model: RateModel, grid: &Grid) -> Stepper {
        let (alpha_x, alpha_y) = dissipation(&model);
        let release_slope_x = slowest_wall(&model, [1.0, 0.0]).tan();
        let release_slope_y = slowest_wall(&model, [0.0, 1.0]).tan();
        let dt_max_h = CFL / (alpha_x / grid.dx_um + alpha_y / grid.dy_um);
        Stepper {
            model,
            alpha_x,
            alpha_y,
            release_slope_x,
            release_slope_y,
            dt_max_h,
        }
    }

    pub fn model(&self) -> &RateModel {
        &self.model
    }

    /// The largest stable time step.
    pub fn dt_max_h(&self) -> f64 {
        self.dt_max_h
    }

    /// The Lax-Friedrichs dissipation coefficients (um/h).
    pub fn alphas(&self) -> (f64, f64) {
        (self.alpha_x, self.alpha_y)
    }

    /// The wall slopes (x, y) a covered node is released behind.
    pub fn release_slopes(&self) -> (f64, f64) {
        (self.release_slope_x, self.release_slope_y)
    }

    /// The signed height whose zero level is the top edge of the etched silicon (where the
    /// surface leaves the mask): the surface height at exposed nodes; at covered nodes the
    /// height the nearest exposed wall would have there (`Field::rise`), > 0, or one wall
    /// step above 0 when no neighbour is exposed. Linear interpolation of its zero places the
    /// edge within a cell instead of at the last covered node.
    pub fn top_field(&self, s: &Surface) -> Vec<f64> {
        let g = s.grid;
        let f = Field {
            h: &s.h_um,
            cov: &s.covered,
            g,
            wall: [self.release_slope_x, self.release_slope_y],
        };
        let far = g.dx_um.max(g.dy_um) * self.release_slope_x.max(self.release_slope_y);
        let mut out = s.h_um.clone();
        for j in 0..g.ny {
            for i in 0..g.nx {
                let (ii, jj) = (i as isize, j as isize);
                if f.covered(ii, jj) {
                    out[j * g.nx + i] = f.release_height(ii, jj).min(far).max(0.0);
                }
            }
        }
        out
    }

    /// H(p, q) = R(n) sqrt(1 + p^2 + q^2).
    fn hamiltonian(&self, p: f64, q: f64) -> f64 {
        self.model.rate_wafer([-p, -q, 1.0]) * (1.0 + p * p + q * q).sqrt()
    }

    /// Advances `s` to `t_end_h` in equal steps no longer than the stable one.
    pub fn advance(&self, s: &mut Surface, t_end_h: f64) -> Result<(), SimError> {
        let span = t_end_h - s.time_h;
        if span <= 0.0 {
            return Ok(());
        }
        let steps = (span / self.dt_max_h).ceil();
        if steps.is_nan() || steps > MAX_STEPS as f64 {
            return Err(SimError::TooManySteps {
                steps,
                max: MAX_STEPS,
            });
        }
        let n = steps as usize;
        let dt = span / n as f64;
        let mut next = s.h_um.clone();
        let mut next_cov = s.covered.clone();
        for _ in 0..n {
            self.step(s, dt, &mut next, &mut next_cov);
            std::mem::swap(&mut s.h_um, &mut next);
            std::mem::swap(&mut s.covered, &mut next_cov);
        }
        s.time_h = t_end_h;
        Ok(())
    }

    /// One explicit step from `s` into `next` (Jacobi: every node reads the old field).
    fn step(&self, s: &Surface, dt: f64, next: &mut [f64], next_cov: &mut [bool]) {
        let g = s.grid;
        let f = Field {
            h: &s.h_um,
            cov: &s.covered,
            g,
            wall: [self.release_slope_x, self.release_slope_y],
        };
        next.par_chunks_mut(g.nx)
            .zip(next_cov.par_chunks_mut(g.nx))
            .enumerate()
            .for_each(|(j, (row, crow))| {
                for i in 0..g.nx {
                    let (ii, jj) = (i as isize, j as isize);
                    if f.covered(ii, jj) {
                        // Released only by an exposed neighbour's wall reaching it.
                        let wall = f.release_height(ii, jj).min(0.0);
                        row[i] = wall;
                        crow[i] = wall >= 0.0;
                        continue;
                    }
                    let hc = f.h(ii, jj);
                    let (dxm, dxp) = f.differences(ii, jj, 0);
                    let (dym, dyp) = f.differences(ii, jj, 1);
                    let ham = self.hamiltonian(0.5 * (dxm + dxp), 0.5 * (dym + dyp))
                        - 0.5 * self.alpha_x * (dxp - dxm)
                        - 0.5 * self.alpha_y * (dyp - dym);
                    // Not clamped to <= hc: at a V-bottom (a shock) the monotone scheme keeps
                    // the right speed by lifting the bottom node a little while its neighbours
                    // fall. Silicon never stands above the wafer top, though (a node beside the
                    // mask sees the wall rising into it and would otherwise be lifted).
                    row[i] = (hc - dt * ham).min(0.0);
                    crow[i] = false;
                }
            });
    }
}

/// The old field, read with mirror planes at the grid's sides.
struct Field<'a> {
    h: &'a [f64],
    cov: &'a [bool],
    g: Grid,
    /// Slope of the slowest-undercutting wall along x and along y.
    wall: [f64; 2],
}

impl Field<'_> {
    fn k(&self, i: isize, j: isize) -> usize {
        Grid::mirror(j, self.g.ny) * self.g.nx + Grid::mirror(i, self.g.nx)
    }

    fn h(&self, i: isize, j: isize) -> f64 {
        self.h[self.k(i, j)]
    }

    fn covered(&self, i: isize, j: isize) -> bool {
        self.cov[self.k(i, j)]
    }

    /// |slope| across `axis` at an exposed node: the central difference, or the one-sided one
    /// on the exposed side when the other neighbour is the mask.
    fn cross_slope(&self, i: isize, j: isize, axis: usize) -> f64 {
        let (d, a, b) = if axis == 0 {
            (self.g.dy_um, (i, j - 1), (i, j + 1))
        } else {
            (self.g.dx_um, (i - 1, j), (i + 1, j))
        };
        let hc = self.h(i, j);
        match (self.covered(a.0, a.1), self.covered(b.0, b.1)) {
            (false, false) => ((self.h(b.0, b.1) - self.h(a.0, a.1)) / (2.0 * d)).abs(),
            (true, false) => ((self.h(b.0, b.1) - hc) / d).abs(),
            (false, true) => ((hc - self.h(a.0, a.1)) / d).abs(),
            (true, true) => 0.0,
        }
    }

    /// How steeply the surface at an exposed node rises along `axis` into the mask next to it.
    ///
    /// Under a straight mask edge it is the slowest-undercutting wall's slope S (the Wulff
    /// construction of an etch from a line source: Jaccodine, J. Appl. Phys. 33 (1962) 2643): a
    /// flat floor beside the mask must not release the mask's nodes from the top. Near a convex
    /// corner the surface is a plane of the fan between the two walls' normals, and every such
    /// plane has p + q = S (they share the ridge direction, slope 1 along the <100> diagonal,
    /// when S = sqrt 2): so the slope along the axis is S less the slope across it. Kept in
    /// [S / 4, S] so that no flat neighbour releases a node.
    fn rise(&self, i: isize, j: isize, axis: usize) -> f64 {
        let s = self.wall[axis];
        (s - self.cross_slope(i, j, axis)).clamp(0.25 * s, s)
    }

    /// At a covered node: the lowest height the wall of an exposed axis neighbour reaches
    /// there (+inf with no exposed neighbour).
    fn release_height(&self, i: isize, j: isize) -> f64 {
        let mut wall = f64::INFINITY;
        for (axis, o) in [(0, -1), (0, 1), (1, -1), (1, 1)] {
            let (ni, nj) = if axis == 0 { (i + o, j) } else { (i, j + o) };
            if !self.covered(ni, nj) {
                let d = [self.g.dx_um, self.g.dy_um][axis];
                wall = wall.min(self.h(ni, nj) + self.rise(ni, nj, axis) * d);
            }
        }
        wall
    }

    /// The backward and forward differences along `axis` at an exposed node. A covered
    /// neighbour is the mask, not silicon that could be etched from above: the surface rises
    /// into it by [`Field::rise`].
    fn differences(&self, i: isize, j: isize, axis: usize) -> (f64, f64) {
        let (d, (mi, mj), (pi, pj)) = if axis == 0 {
            (self.g.dx_um, (i - 1, j), (i + 1, j))
        } else {
            (self.g.dy_um, (i, j - 1), (i, j + 1))
        };
        let hc = self.h(i, j);
        let dm = if self.covered(mi, mj) {
            -self.rise(i, j, axis)
        } else {
            (hc - self.h(mi, mj)) / d
        };
        let dp = if self.covered(pi, pj) {
            self.rise(i, j, axis)
        } else {
            (self.h(pi, pj) - hc) / d
        };
        (dm, dp)
    }
}

/// Bounds of |dH/dp| and |dH/dq| over every normal of the upper half sphere: the gradient of
/// the degree-1 extension F(v) = |v| R(v / |v|) by central differences on a fine sampling,
/// with a 10 % margin for what the sampling misses.
fn dissipation(m: &RateModel) -> (f64, f64) {
    let f = |v: [f64; 3]| {
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        l * m.rate_wafer(v)
    };
    let d = 1e-6;
    let (mut ax, mut ay) = (0.0f64, 0.0f64);
    let (nt, np) = (90, 360);
    for it in 0..=nt {
        let th = std::f64::consts::FRAC_PI_2 * it as f64 / nt as f64;
        for ip in 0..np {
            let ph = std::f64::consts::TAU * (ip as f64 + 0.5) / np as f64;
            let v = [th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()];
            let gx = (f([v[0] + d, v[1], v[2]]) - f([v[0] - d, v[1], v[2]])) / (2.0 * d);
            let gy = (f([v[0], v[1] + d, v[2]]) - f([v[0], v[1] - d, v[2]])) / (2.0 * d);
            ax = ax.max(gx.abs());
            ay = ay.max(gy.abs());
        }
    }
    (1.1 * ax, 1.1 * ay)
}

/// The tilt theta (from the wafer normal) of the wall that undercuts slowest behind a mask edge
/// whose outward horizontal direction is `m`: the minimiser of R(n) / sin theta, n = (sin theta
/// m, cos theta), by sampling and a golden-section polish.
pub fn slowest_wall(model: &RateModel, m: [f64; 2]) -> f64 {
    let speed = |th: f64| {
        let (s, c) = th.sin_cos();
        model.rate_wafer([s * m[0], s * m[1], c]) / s
    };
    let n = 4000;
    let lo = 1e-3;
    let hi = std::f64::consts::FRAC_PI_2;
    let th_k = |k: usize| lo + (hi - lo) * k as f64 / n as f64;
    let best = (0..=n)
        .min_by(|&a, &b| speed(th_k(a)).total_cmp(&speed(th_k(b))))
        .expect("samples");
    let (mut a, mut b) = (th_k(best.saturating_sub(1)), th_k((best + 1).min(n)));
    let gr = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..60 {
        let c = b - gr * (b - a);
        let d = a + gr * (b - a);
        if speed(c) < speed(d) {
            b = d;
        } else {
            a = c;
        }
    }
    0.5 * (a + b)
}
