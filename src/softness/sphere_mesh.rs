//! A meridian (r, z) mesh of the tissue cylinder whose element edges follow the sphere on its
//! axis, for [`super::axislab`]: no element is cut by the sphere, so no element mixes the two
//! materials (the area-share mixing of a rectilinear mesh converged slowly and not
//! monotonically: 1.564, 1.528, 1.492, 1.471 for the lump's peak on 15x20 to 120x160).
//!
//! Blocks (all Q2, nodes shared by exact coordinates), the sphere of radius a centred at
//! (0, h_c), a half-square box of half-side b = min(2 a, h_c, H - h_c, R_c) around it:
//! - the core, the box scaled by c / b (c = a / 2) about the centre, a rectilinear grid;
//! - the inner ring from the core's edge to the circle and the outer ring from the circle to the
//!   box, each along straight rays through the box's edge nodes (the circle's nodes are the
//!   box's, projected radially onto it: Q2 edges interpolate the arc through three points);
//! - the rest of the cylinder, a rectilinear grid whose lines include the box's edges.
//!
//! Refining by an integer factor multiplies every block's counts ([`Counts::scaled`]): the
//! meshes of a Richardson sequence are similar (and nested when one factor divides the other).

/// Element counts of the blocks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Counts {
    /// Along the box's bottom (and top) edge; its side has twice as many.
    pub box_r: usize,
    /// Rows below and above the box, columns beyond it.
    pub below: usize,
    pub above: usize,
    pub beyond: usize,
    /// Radially in the inner (core to circle) and outer (circle to box) rings.
    pub inner_ring: usize,
    pub outer_ring: usize,
}

impl Counts {
    /// Every count times `k`.
    pub fn scaled(self, k: usize) -> Counts {
        Counts {
            box_r: k * self.box_r,
            below: k * self.below,
            above: k * self.above,
            beyond: k * self.beyond,
            inner_ring: k * self.inner_ring,
            outer_ring: k * self.outer_ring,
        }
    }

    pub fn elements(&self) -> usize {
        let n = self.box_r;
        let rows = self.below + 2 * n + self.above;
        let grid = (n + self.beyond) * rows - 2 * n * n;
        2 * n * n + 4 * n * (self.inner_ring + self.outer_ring) + grid
    }
}

/// The geometry: cylinder radius, thickness, sphere radius and centre height (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geometry {
    pub rc_m: f64,
    pub h_m: f64,
    pub a_m: f64,
    pub centre_m: f64,
}

impl Geometry {
    /// The box's half-side: twice the radius, no further than the faces and the free edge.
    fn half_box(&self) -> f64 {
        (2.0 * self.a_m)
            .min(self.centre_m)
            .min(self.h_m - self.centre_m)
            .min(self.rc_m)
    }

    /// Counts for elements of about `e_m` (at least two along the box's edge and one per ring).
    #[track_caller]
    pub fn counts(&self, e_m: f64) -> Counts {
        assert!(
            e_m > 0.0 && self.a_m > 0.0 && self.half_box() > self.a_m,
            "the sphere must lie inside the tissue: {self:?}"
        );
        let b = self.half_box();
        let n = |len: f64| {
            if len > 1e-9 * self.h_m {
                (len / e_m).ceil() as usize
            } else {
                0
            }
        };
        let box_r = n(b).max(2);
        let h = b / box_r as f64;
        Counts {
            box_r,
            below: n(self.centre_m - b),
            above: n(self.h_m - self.centre_m - b),
            beyond: n(self.rc_m - b),
            inner_ring: ((0.5 * self.a_m / h).ceil() as usize).max(1),
            outer_ring: (((b - self.a_m) / h).ceil() as usize).max(1),
        }
    }
}

/// The mesh: node coordinates (r, z) and elements (9 nodes, local k = 3 j + i counter-clockwise
/// in (r, z), and whether the element lies inside the sphere).
#[derive(Debug, Clone, PartialEq)]
pub struct SphereMesh {
    pub nodes: Vec<(f64, f64)>,
    pub elements: Vec<([usize; 9], bool)>,
}

/// Q2 node coordinates of `n` elements from `x0` to `x1` (2 n + 1 values, ends exact).
fn line(x0: f64, x1: f64, n: usize, out: &mut Vec<f64>) {
    for i in 0..=2 * n {
        let v = if i == 2 * n {
            x1
        } else {
            x0 + (x1 - x0) * i as f64 / (2 * n) as f64
        };
        if out.last() != Some(&v) {
            out.push(v);
        }
    }
}

/// The point a fraction `s` from `p` to `q` (the ends exact).
fn lerp(p: (f64, f64), q: (f64, f64), s: f64) -> (f64, f64) {
    if s == 0.0 {
        p
    } else if s == 1.0 {
        q
    } else {
        (p.0 + s * (q.0 - p.0), p.1 + s * (q.1 - p.1))
    }
}

/// The fitted mesh of `geo` with `c` counts.
#[track_caller]
pub fn sphere_mesh(geo: &Geometry, c: Counts) -> SphereMesh {
    let b = geo.half_box();
    let (hc, a) = (geo.centre_m, geo.a_m);
    let n = c.box_r;
    let z_lo = if c.below == 0 { 0.0 } else { hc - b };
    let z_hi = if c.above == 0 { geo.h_m } else { hc + b };
    let r_box = if c.beyond == 0 { geo.rc_m } else { b };
    let mut rs = Vec::new();
    line(0.0, r_box, n, &mut rs);
    if c.beyond > 0 {
        line(r_box, geo.rc_m, c.beyond, &mut rs);
    }
    let mut zs = Vec::new();
    if c.below > 0 {
        line(0.0, z_lo, c.below, &mut zs);
    }
    let j0 = zs.len().saturating_sub(1);
    line(z_lo, z_hi, 2 * n, &mut zs);
    if c.above > 0 {
        line(z_hi, geo.h_m, c.above, &mut zs);
    }
    let mut mesh = SphereMesh {
        nodes: Vec::new(),
        elements: Vec::new(),
    };
    let mut index = std::collections::HashMap::new();
    let mut id = |p: (f64, f64), nodes: &mut Vec<(f64, f64)>| -> usize {
        let key = ((p.0 + 0.0).to_bits(), (p.1 + 0.0).to_bits());
        *index.entry(key).or_insert_with(|| {
            nodes.push(p);
            nodes.len() - 1
        })
    };
    // The box's edge nodes counter-clockwise from the axis at its bottom: 8 n + 1.
    let edge: Vec<(f64, f64)> = (0..=8 * n)
        .map(|k| {
            if k <= 2 * n {
                (rs[k], zs[j0])
            } else if k <= 6 * n {
                (rs[2 * n], zs[j0 + k - 2 * n])
            } else {
                (rs[8 * n - k], zs[j0 + 4 * n])
            }
        })
        .collect();
    let sigma = 0.5 * a / b;
    let core = |p: (f64, f64)| (sigma * p.0, hc + sigma * (p.1 - hc));
    let circle = |p: (f64, f64)| {
        let rho = p.0.hypot(p.1 - hc);
        (a * p.0 / rho, hc + a * (p.1 - hc) / rho)
    };
    // The core: the box's grid scaled about the centre.
    for ej in 0..2 * n {
        for ei in 0..n {
            let e: [usize; 9] = std::array::from_fn(|q| {
                let (i, j) = (2 * ei + q % 3, 2 * ej + q / 3);
                id(core((rs[i], zs[j0 + j])), &mut mesh.nodes)
            });
            mesh.elements.push((e, true));
        }
    }
    // The rings: xi outward along a ray, eta counter-clockwise along the edge.
    for (m, inside) in [(c.inner_ring, true), (c.outer_ring, false)] {
        for ek in 0..4 * n {
            for es in 0..m {
                let e: [usize; 9] = std::array::from_fn(|q| {
                    let (si, k) = (2 * es + q % 3, 2 * ek + q / 3);
                    let s = si as f64 / (2 * m) as f64;
                    let s = if si == 2 * m { 1.0 } else { s };
                    let (from, to) = if inside {
                        (core(edge[k]), circle(edge[k]))
                    } else {
                        (circle(edge[k]), edge[k])
                    };
                    id(lerp(from, to, s), &mut mesh.nodes)
                });
                mesh.elements.push((e, inside));
            }
        }
    }
    // The rest: the rectilinear grid outside the box.
    let (nr, nz) = ((rs.len() - 1) / 2, (zs.len() - 1) / 2);
    let (box_j0, box_j1) = (j0 / 2, j0 / 2 + 2 * n);
    for ey in 0..nz {
        for ex in 0..nr {
            if ex < n && (box_j0..box_j1).contains(&ey) {
                continue;
            }
            let e: [usize; 9] = std::array::from_fn(|q| {
                id((rs[2 * ex + q % 3], zs[2 * ey + q / 3]), &mut mesh.nodes)
            });
            mesh.elements.push((e, false));
        }
    }
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    fn geo() -> Geometry {
        Geometry {
            rc_m: 15e-3,
            h_m: 10e-3,
            a_m: 2e-3,
            centre_m: 4e-3,
        }
    }

    /// The area of a Q2 element (3 x 3 Gauss) and r-weighted volume.
    fn measure(m: &SphereMesh, e: &[usize; 9]) -> (f64, f64) {
        use crate::softness::continuum::{gauss, lagrange};
        let (mut area, mut vol) = (0.0, 0.0);
        for &(xi, wx) in &gauss(3) {
            for &(eta, wy) in &gauss(3) {
                let (nx, dx) = lagrange(2, xi);
                let (ny, dy) = lagrange(2, eta);
                let (mut j, mut r) = ([0.0; 4], 0.0);
                for (q, &node) in e.iter().enumerate() {
                    let (p, s) = m.nodes[node];
                    let (a, b) = (q % 3, q / 3);
                    let (gx, gy, nn) = (dx[a] * ny[b], nx[a] * dy[b], nx[a] * ny[b]);
                    j[0] += gx * p;
                    j[1] += gx * s;
                    j[2] += gy * p;
                    j[3] += gy * s;
                    r += nn * p;
                }
                let det = j[0] * j[3] - j[1] * j[2];
                assert!(det > 0.0, "inverted element {e:?}");
                area += wx * wy * det;
                vol += wx * wy * det * r;
            }
        }
        (area, vol)
    }

    #[test]
    fn the_blocks_tile_the_cylinder_and_the_sphere_converges_at_high_order() {
        // Every element positively oriented; the elements' areas sum to the meridian's R H to
        // rounding (the blocks neither overlap nor leave gaps); the sphere's elements hold
        // pi a^2 / 2 of area and (2 / 3) a^3 of r-weighted volume (the sphere's volume over
        // 2 pi), the error falling at the quadratic edges' rate (~h^4 for the area).
        let g = geo();
        let base = g.counts(1e-3);
        let mut errs = Vec::new();
        for k in [1, 2, 4] {
            let c = base.scaled(k);
            let m = sphere_mesh(&g, c);
            assert_eq!(m.elements.len(), c.elements());
            let (mut total, mut ball, mut ball_v) = (0.0, 0.0, 0.0);
            for (e, inside) in &m.elements {
                let (ar, v) = measure(&m, e);
                total += ar;
                if *inside {
                    ball += ar;
                    ball_v += v;
                }
            }
            let want = g.rc_m * g.h_m;
            assert!((total / want - 1.0).abs() < 1e-12, "{total} vs {want}");
            let half_disc = 0.5 * std::f64::consts::PI * g.a_m * g.a_m;
            let e_area = ball / half_disc - 1.0;
            let e_vol = ball_v / (2.0 / 3.0 * g.a_m.powi(3)) - 1.0;
            eprintln!(
                "x{k}: {} elements, {} nodes; sphere area {e_area:.2e}, volume {e_vol:.2e}",
                m.elements.len(),
                m.nodes.len()
            );
            errs.push(e_area.abs());
        }
        assert!(errs[0] < 1e-3, "{errs:?}");
        // Fourth order: 16x per halving (at least 10x).
        assert!(
            errs[0] / errs[1] > 10.0 && errs[1] / errs[2] > 10.0,
            "{errs:?}"
        );
    }

    #[test]
    fn a_sphere_near_the_face_puts_the_box_on_it() {
        // Centre 3 mm up, radius 2 mm: the box's half-side is the 3 mm height, no rows below it.
        let g = Geometry {
            centre_m: 3e-3,
            ..geo()
        };
        let c = g.counts(0.5e-3);
        assert_eq!(c.below, 0);
        let m = sphere_mesh(&g, c);
        let face = m.nodes.iter().filter(|p| p.1 == 0.0).count();
        // The face's Q2 nodes: 2 per element along it, plus one.
        assert_eq!(face, 2 * (c.box_r + c.beyond) + 1);
        for (e, _) in &m.elements {
            measure(&m, e);
        }
    }
}
