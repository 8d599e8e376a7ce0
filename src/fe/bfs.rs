//! Bogner-Fox-Schmit bicubic Hermite rectangle for an orthotropic Kirchhoff plate
//! (Bogner, Fox & Schmit 1965; 16 dofs: w, w_x, w_y, w_xy at each of the 4 corners).
//!
//! Local coordinates x in [0, a], y in [0, b] (metres). Local dof `4 k + d`: corner
//! k = 0 (0,0), 1 (a,0), 2 (a,b), 3 (0,b); d = 0 w, 1 w_x, 2 w_y, 3 w_xy.
//! Curvature convention: kappa = (-w_xx, -w_yy, -2 w_xy) with w positive in the load direction,
//! so a positive (sagging) curvature puts the bottom surface (far side from the load) in tension.

// Index loops mirror the matrix formulas (K_ij, N_i) and read better than iterator chains here.
#![allow(clippy::needless_range_loop)]

use crate::fe::material::BendingStiffness;

/// 4-point Gauss-Legendre abscissae on [-1, 1] (exact for degree 7).
pub const GAUSS4_X: [f64; 4] = [
    -0.861_136_311_594_052_6,
    -0.339_981_043_584_856_3,
    0.339_981_043_584_856_3,
    0.861_136_311_594_052_6,
];
/// 4-point Gauss-Legendre weights on [-1, 1].
pub const GAUSS4_W: [f64; 4] = [
    0.347_854_845_137_453_8,
    0.652_145_154_862_546_1,
    0.652_145_154_862_546_1,
    0.347_854_845_137_453_8,
];

/// Corner positions (ix, iy) of the local corners 0..4.
pub const CORNERS: [(usize, usize); 4] = [(0, 0), (1, 0), (1, 1), (0, 1)];
/// Hermite type (px, py) of the local dof d: w, w_x, w_y, w_xy.
const DOF_TYPE: [(usize, usize); 4] = [(0, 0), (1, 0), (0, 1), (1, 1)];

/// Gauss points and weights mapped to [lo, hi].
pub fn gauss4_on(lo: f64, hi: f64) -> [(f64, f64); 4] {
    let h = 0.5 * (hi - lo);
    let m = 0.5 * (hi + lo);
    std::array::from_fn(|i| (m + h * GAUSS4_X[i], h * GAUSS4_W[i]))
}

/// 1D cubic Hermite basis on [0, len] at x: `[order][function]` for derivative orders 0, 1, 2
/// (H1 = 1-3s^2+2s^3, H2 = len(s-2s^2+s^3), H3 = 3s^2-2s^3, H4 = len(s^3-s^2), s = x/len).
pub fn hermite(x: f64, len: f64) -> [[f64; 4]; 3] {
    let s = x / len;
    let (s2, s3) = (s * s, s * s * s);
    [
        [
            1.0 - 3.0 * s2 + 2.0 * s3,
            len * (s - 2.0 * s2 + s3),
            3.0 * s2 - 2.0 * s3,
            len * (s3 - s2),
        ],
        [
            (-6.0 * s + 6.0 * s2) / len,
            1.0 - 4.0 * s + 3.0 * s2,
            (6.0 * s - 6.0 * s2) / len,
            -2.0 * s + 3.0 * s2,
        ],
        [
            (-6.0 + 12.0 * s) / (len * len),
            (-4.0 + 6.0 * s) / len,
            (6.0 - 12.0 * s) / (len * len),
            (-2.0 + 6.0 * s) / len,
        ],
    ]
}

/// Index of the 1D Hermite function in x and y used by local dof i.
#[inline]
pub fn factor_index(i: usize) -> (usize, usize) {
    let (ix, iy) = CORNERS[i / 4];
    let (px, py) = DOF_TYPE[i % 4];
    (2 * ix + px, 2 * iy + py)
}

/// Values of the 16 shape functions and their derivatives at local (x, y):
/// rows N, N_x, N_y, N_xx, N_yy, N_xy.
pub fn shape(x: f64, y: f64, a: f64, b: f64) -> [[f64; 16]; 6] {
    let hx = hermite(x, a);
    let hy = hermite(y, b);
    let mut out = [[0.0; 16]; 6];
    for i in 0..16 {
        let (fx, fy) = factor_index(i);
        out[0][i] = hx[0][fx] * hy[0][fy];
        out[1][i] = hx[1][fx] * hy[0][fy];
        out[2][i] = hx[0][fx] * hy[1][fy];
        out[3][i] = hx[2][fx] * hy[0][fy];
        out[4][i] = hx[0][fx] * hy[2][fy];
        out[5][i] = hx[1][fx] * hy[1][fy];
    }
    out
}

/// 1D moment matrices I[p][q][m][n] = int_0^len H_m^(p) H_n^(q) dx by 4-point Gauss (exact: degree
/// <= 6).
fn moments_1d(len: f64) -> [[[[f64; 4]; 4]; 3]; 3] {
    let mut out = [[[[0.0; 4]; 4]; 3]; 3];
    for (x, w) in gauss4_on(0.0, len) {
        let h = hermite(x, len);
        for p in 0..3 {
            for q in 0..3 {
                for m in 0..4 {
                    for n in 0..4 {
                        out[p][q][m][n] += w * h[p][m] * h[q][n];
                    }
                }
            }
        }
    }
    out
}

/// Element stiffness K_ij = int B_i^T D B_j dA, B = (-N_xx, -N_yy, -2 N_xy) (Kirchhoff plate
/// energy, Reddy Eq. 3.4.29), integrated by the 4x4 Gauss rule (exact), evaluated as tensor
/// products of 1D rules.
pub fn stiffness(a: f64, b: f64, d: &BendingStiffness) -> [[f64; 16]; 16] {
    let ix = moments_1d(a);
    let iy = moments_1d(b);
    let mut k = [[0.0; 16]; 16];
    for i in 0..16 {
        let (xi, yi) = factor_index(i);
        for j in 0..16 {
            let (xj, yj) = factor_index(j);
            k[i][j] = d.d11_nm * ix[2][2][xi][xj] * iy[0][0][yi][yj]
                + d.d22_nm * ix[0][0][xi][xj] * iy[2][2][yi][yj]
                + d.d12_nm
                    * (ix[2][0][xi][xj] * iy[0][2][yi][yj] + ix[0][2][xi][xj] * iy[2][0][yi][yj])
                + 4.0 * d.d66_nm * ix[1][1][xi][xj] * iy[1][1][yi][yj];
        }
    }
    k
}

/// Consistent mass M_ij = m int N_i N_j dA of an areal mass m (kg/m^2; rho t for a plate, Reddy,
/// Theory and Analysis of Elastic Plates and Shells, Eq. 6.2.6 without rotary inertia) for the
/// transverse motion w, integrated exactly (4-point Gauss per direction: N_i N_j is degree 6 in
/// each) as tensor products of 1D rules.
pub fn mass(a: f64, b: f64, areal_kg_per_m2: f64) -> [[f64; 16]; 16] {
    let ix = moments_1d(a);
    let iy = moments_1d(b);
    let mut m = [[0.0; 16]; 16];
    for i in 0..16 {
        let (xi, yi) = factor_index(i);
        for j in 0..16 {
            let (xj, yj) = factor_index(j);
            m[i][j] = areal_kg_per_m2 * ix[0][0][xi][xj] * iy[0][0][yi][yj];
        }
    }
    m
}

/// Consistent load of a point force F at local (x, y): f_i = F N_i(x, y).
pub fn point_load(x: f64, y: f64, a: f64, b: f64, force_n: f64) -> [f64; 16] {
    let n = shape(x, y, a, b)[0];
    n.map(|v| v * force_n)
}

/// Consistent load of a uniform pressure p over the local sub-rectangle \[x0,x1\] x \[y0,y1\]:
/// f_i = p int N_i dA (separable, 4-point Gauss per direction, exact). The whole element is x0=0,
/// x1=a, y0=0, y1=b.
pub fn rect_load(
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
    a: f64,
    b: f64,
    pressure_pa: f64,
) -> [f64; 16] {
    let mut gx = [0.0; 4];
    let mut gy = [0.0; 4];
    for (x, w) in gauss4_on(x0, x1) {
        let h = hermite(x, a)[0];
        for m in 0..4 {
            gx[m] += w * h[m];
        }
    }
    for (y, w) in gauss4_on(y0, y1) {
        let h = hermite(y, b)[0];
        for m in 0..4 {
            gy[m] += w * h[m];
        }
    }
    std::array::from_fn(|i| {
        let (fx, fy) = factor_index(i);
        pressure_pa * gx[fx] * gy[fy]
    })
}

/// Consistent load of a uniform line force q (N/m) along the local segment p0 -> p1:
/// f_i = q int N_i ds, 4-point Gauss along the segment (exact: N is degree <= 6 along a line).
pub fn line_load(p0: (f64, f64), p1: (f64, f64), a: f64, b: f64, force_per_m: f64) -> [f64; 16] {
    let len = ((p1.0 - p0.0).powi(2) + (p1.1 - p0.1).powi(2)).sqrt();
    let mut f = [0.0; 16];
    for (t, w) in gauss4_on(0.0, 1.0) {
        let n = shape(p0.0 + t * (p1.0 - p0.0), p0.1 + t * (p1.1 - p0.1), a, b)[0];
        for i in 0..16 {
            f[i] += force_per_m * len * w * n[i];
        }
    }
    f
}

/// Collapsed (Duffy) 4x4 Gauss rule on a triangle: exact for polynomials of total degree <= 6,
/// which covers the bicubic shape functions. Returns (x, y, weight) with weights summing to the
/// area.
pub fn triangle_rule(p: [(f64, f64); 3]) -> [(f64, f64, f64); 16] {
    let (ax, ay) = (p[1].0 - p[0].0, p[1].1 - p[0].1);
    let (bx, by) = (p[2].0 - p[0].0, p[2].1 - p[0].1);
    let jac = (ax * by - ay * bx).abs();
    let g = gauss4_on(0.0, 1.0);
    let mut out = [(0.0, 0.0, 0.0); 16];
    for (i, &(u, wu)) in g.iter().enumerate() {
        for (j, &(v, wv)) in g.iter().enumerate() {
            // (u, v) in the unit square -> (r, s) = (u, v (1 - u)) in the unit triangle, Jacobian
            // (1 - u).
            let r = u;
            let s = v * (1.0 - u);
            out[4 * i + j] = (
                p[0].0 + r * ax + s * bx,
                p[0].1 + r * ay + s * by,
                wu * wv * (1.0 - u) * jac,
            );
        }
    }
    out
}

/// Consistent load of uniform pressure p over a convex polygon inside the element (local
/// coordinates): fan triangulation, each triangle integrated with [`triangle_rule`] (exact).
pub fn polygon_load(poly: &[(f64, f64)], a: f64, b: f64, pressure_pa: f64) -> [f64; 16] {
    let mut f = [0.0; 16];
    for k in 1..poly.len().saturating_sub(1) {
        for (x, y, w) in triangle_rule([poly[0], poly[k], poly[k + 1]]) {
            let n = shape(x, y, a, b)[0];
            for i in 0..16 {
                f[i] += pressure_pa * w * n[i];
            }
        }
    }
    f
}

/// Deflection and curvature at local (x, y) from element dofs u: (w, [kappa_x, kappa_y, kappa_xy])
/// with kappa = (-w_xx, -w_yy, -2 w_xy) (Kirchhoff kinematics).
pub fn deflection_curvature(u: &[f64; 16], x: f64, y: f64, a: f64, b: f64) -> (f64, [f64; 3]) {
    let n = shape(x, y, a, b);
    let dot = |row: &[f64; 16]| row.iter().zip(u).map(|(p, q)| p * q).sum::<f64>();
    (dot(&n[0]), [-dot(&n[3]), -dot(&n[4]), -2.0 * dot(&n[5])])
}

/// (int kappa_x dA, int kappa_y dA) over a whole element, kappa = (-w_xx, -w_yy), in closed form:
/// by the divergence theorem int w_xx dA = int_0^b (w_x(a, y) - w_x(0, y)) dy, and w_x along an
/// edge is the cubic Hermite of its end values w_x and slopes w_xy, whose integral is
/// L (f0 + f1) / 2 + L^2 (f0' - f1') / 12. Equal to 4x4 Gauss to round-off at a sixteenth of the
/// cost.
pub fn curvature_integral(u: &[f64; 16], a: f64, b: f64) -> (f64, f64) {
    // Local dof c * 4 + t: corner c of CORNERS = (0,0), (1,0), (1,1), (0,1); t = w, w_x, w_y, w_xy.
    let edge = |len: f64, c0: usize, c1: usize, t: usize| {
        len * 0.5 * (u[4 * c0 + t] + u[4 * c1 + t])
            + len * len / 12.0 * (u[4 * c0 + 3] - u[4 * c1 + 3])
    };
    // w_x along x = a (corners 1 -> 2) minus along x = 0 (corners 0 -> 3), integrated in y.
    let wxx = edge(b, 1, 2, 1) - edge(b, 0, 3, 1);
    // w_y along y = b (corners 3 -> 2) minus along y = 0 (corners 0 -> 1), integrated in x.
    let wyy = edge(a, 3, 2, 2) - edge(a, 0, 1, 2);
    (-wxx, -wyy)
}

/// (int w_x^2 / 2 dA, int w_y^2 / 2 dA) over a whole element: the von Karman strain's slope terms
/// (Reddy Eq. 7.3.5), by the 4x4 Gauss rule (exact: w_x^2 is of degree 4 in x and 6 in y) with
/// sum factorisation over the tensor-product Hermite basis, w_x(x_p, y_q) =
/// sum_fy H_fy(y_q) sum_fx H'_fx(x_p) U_fx,fy: ~300 flops instead of 16 full shape evaluations.
pub fn slope_square_integral(u: &[f64; 16], a: f64, b: f64) -> (f64, f64) {
    let mut coef = [[0.0; 4]; 4];
    for (i, &v) in u.iter().enumerate() {
        let (fx, fy) = factor_index(i);
        coef[fx][fy] = v;
    }
    let gy = gauss4_on(0.0, b);
    let hy: [[[f64; 4]; 3]; 4] = std::array::from_fn(|q| hermite(gy[q].0, b));
    let (mut sx, mut sy) = (0.0, 0.0);
    for (x, wx) in gauss4_on(0.0, a) {
        let hx = hermite(x, a);
        // Along y at this x: the slope w_x's and the value w's Hermite coefficients.
        let mut dx = [0.0; 4];
        let mut val = [0.0; 4];
        for fy in 0..4 {
            for fx in 0..4 {
                dx[fy] += hx[1][fx] * coef[fx][fy];
                val[fy] += hx[0][fx] * coef[fx][fy];
            }
        }
        for (q, &(_, wy)) in gy.iter().enumerate() {
            let (mut px, mut py) = (0.0, 0.0);
            for fy in 0..4 {
                px += dx[fy] * hy[q][0][fy];
                py += val[fy] * hy[q][1][fy];
            }
            sx += wx * wy * 0.5 * px * px;
            sy += wx * wy * 0.5 * py * py;
        }
    }
    (sx, sy)
}

/// Moments per unit length M = D kappa: (Mx, My, Mxy) in N (N m / m), sagging positive (Reddy Eq.
/// 3.3.17).
pub fn moments(kappa: [f64; 3], d: &BendingStiffness) -> [f64; 3] {
    [
        d.d11_nm * kappa[0] + d.d12_nm * kappa[1],
        d.d12_nm * kappa[0] + d.d22_nm * kappa[1],
        d.d66_nm * kappa[2],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slope_square_integral_matches_gauss_on_shape_functions() {
        let (a, b) = (3.1e-4, 1.7e-4);
        let u: [f64; 16] = std::array::from_fn(|i| ((i * 7 + 3) % 11) as f64 * 1e-6 - 4e-6);
        let (mut ex, mut ey) = (0.0, 0.0);
        for (x, wx) in gauss4_on(0.0, a) {
            for (y, wy) in gauss4_on(0.0, b) {
                let s = shape(x, y, a, b);
                let px: f64 = s[1].iter().zip(&u).map(|(p, q)| p * q).sum();
                let py: f64 = s[2].iter().zip(&u).map(|(p, q)| p * q).sum();
                ex += wx * wy * 0.5 * px * px;
                ey += wx * wy * 0.5 * py * py;
            }
        }
        let (sx, sy) = slope_square_integral(&u, a, b);
        assert!((sx - ex).abs() <= 1e-12 * ex.abs(), "{sx} vs {ex}");
        assert!((sy - ey).abs() <= 1e-12 * ey.abs(), "{sy} vs {ey}");
    }
    use crate::fe::material::PlateMaterial;

    #[test]
    fn curvature_integral_equals_gauss() {
        let (a, b) = (3e-4, 7e-4);
        let u: [f64; 16] =
            std::array::from_fn(|i| ((i * 37 % 11) as f64 - 5.0) * [1e-6, 1e-3, -2e-3, 4.0][i % 4]);
        let (mut gx, mut gy) = (0.0, 0.0);
        for (x, wx) in gauss4_on(0.0, a) {
            for (y, wy) in gauss4_on(0.0, b) {
                let (_, k) = deflection_curvature(&u, x, y, a, b);
                gx += wx * wy * k[0];
                gy += wx * wy * k[1];
            }
        }
        let (cx, cy) = curvature_integral(&u, a, b);
        assert!(
            (cx - gx).abs() <= 1e-12 * gx.abs() && (cy - gy).abs() <= 1e-12 * gy.abs(),
            "{cx} {gx} / {cy} {gy}"
        );
    }

    #[test]
    fn shape_functions_interpolate_nodal_dofs() {
        let (a, b) = (0.3, 0.2);
        for (k, &(ix, iy)) in CORNERS.iter().enumerate() {
            let s = shape(ix as f64 * a, iy as f64 * b, a, b);
            for i in 0..16 {
                let expect = |_row: usize, d: usize| if i == 4 * k + d { 1.0 } else { 0.0 };
                assert!((s[0][i] - expect(0, 0)).abs() < 1e-12);
                assert!((s[1][i] - expect(1, 1)).abs() < 1e-12);
                assert!((s[2][i] - expect(2, 2)).abs() < 1e-12);
                assert!((s[5][i] - expect(5, 3)).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn stiffness_symmetric_and_rigid_modes_free() {
        let d = PlateMaterial::isotropic(1e9, 0.3).bending_stiffness(1e-3);
        let (a, b) = (0.02, 0.01);
        let k = stiffness(a, b, &d);
        // rigid modes: w = 1, w = x, w = y
        let mut modes = [[0.0; 16]; 3];
        for (c, &(ix, iy)) in CORNERS.iter().enumerate() {
            let (x, y) = (ix as f64 * a, iy as f64 * b);
            modes[0][4 * c] = 1.0;
            modes[1][4 * c] = x;
            modes[1][4 * c + 1] = 1.0;
            modes[2][4 * c] = y;
            modes[2][4 * c + 2] = 1.0;
        }
        let kmax = k.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        for i in 0..16 {
            for j in 0..16 {
                assert!((k[i][j] - k[j][i]).abs() <= 1e-12 * kmax);
            }
            for m in &modes {
                let r: f64 = (0..16).map(|j| k[i][j] * m[j]).sum();
                assert!(r.abs() < 1e-9 * kmax, "rigid mode energy {r}");
            }
        }
    }

    #[test]
    fn mass_carries_the_total_mass_and_is_symmetric() {
        // A rigid translation w = 1 has kinetic energy (1/2) m a b: 1^T M 1 over the w dofs is
        // the element's mass; w = x gives the first moment m a^2 b / 2 about x = 0.
        let (a, b, m) = (3e-4, 7e-4, 0.25);
        let me = mass(a, b, m);
        let mut unit = [0.0; 16];
        let mut ramp = [0.0; 16];
        for (c, &(ix, _)) in CORNERS.iter().enumerate() {
            unit[4 * c] = 1.0;
            ramp[4 * c] = ix as f64 * a;
            ramp[4 * c + 1] = 1.0;
        }
        let quad = |u: &[f64; 16], v: &[f64; 16]| -> f64 {
            (0..16)
                .map(|i| (0..16).map(|j| u[i] * me[i][j] * v[j]).sum::<f64>())
                .sum()
        };
        assert!((quad(&unit, &unit) - m * a * b).abs() < 1e-14 * m * a * b);
        let first = m * a * a * b / 2.0;
        assert!((quad(&unit, &ramp) - first).abs() < 1e-13 * first);
        for i in 0..16 {
            for j in 0..16 {
                assert!((me[i][j] - me[j][i]).abs() <= 1e-15 * me[0][0]);
            }
        }
    }

    #[test]
    fn polygon_load_matches_rect_load() {
        let (a, b) = (0.3, 0.2);
        let r = rect_load(0.05, 0.25, 0.02, 0.15, a, b, 7.0);
        let p = polygon_load(
            &[(0.05, 0.02), (0.25, 0.02), (0.25, 0.15), (0.05, 0.15)],
            a,
            b,
            7.0,
        );
        for i in 0..16 {
            assert!((r[i] - p[i]).abs() < 1e-13, "{i}: {} {}", r[i], p[i]);
        }
        let total: f64 = (0..4).map(|c| r[4 * c]).sum();
        assert!((total - 7.0 * 0.2 * 0.13).abs() < 1e-14);
    }
}
