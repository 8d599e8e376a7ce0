//! A spherical or cylindrical cavity or inclusion of radius a in a large body under uniaxial
//! tension S: the checks of the axisymmetric element ([`super::axisym`]) and of the plane-strain
//! one ([`super::mapped`]) against Goodier's cavity and Eshelby's inclusion (tests below).
//!
//! Mesh: a quarter of the meridian (sphere, axisymmetric about z) or of the cross-section
//! (cylinder along the third axis, plane strain) in polar coordinates rho, theta: (r, z) or
//! (x, y) = rho (cos theta, sin theta), theta from the symmetry plane z = 0 (y = 0) to the axis
//! theta = 90 deg, the tension S along that axis. Rings: `n_in` equal ones inside the inclusion
//! (the innermost collapsed onto the centre, one node), `n_out` geometric ones from a to `outer`
//! a. The far field is applied as the uniform field's traction S n_z e_z on rho = `outer` a: the
//! body is finite, so the answer departs from the infinite body's by the disturbance left there
//! (decaying as (a / rho)^3 around a sphere and (a / rho)^2 around a cylinder).

use super::axisym::{axi_q2, AxiQ2};
use super::continuum::{gauss, lagrange, lame, lame_combined, pair_dofs, Assembler, DofExpr};
use super::mapped::{mapped_q2, MappedQ2};
use super::SoftnessError;

/// Sphere (axisymmetric) or cylinder (plane strain).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Body {
    Sphere,
    Cylinder,
}

/// The inside of the radius a.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Inside {
    Cavity,
    /// An inclusion of (E, nu); the matrix has E = 1.
    Inclusion {
        e: f64,
        nu: f64,
    },
}

enum Element {
    Axi(AxiQ2),
    Plane(MappedQ2),
}

impl Element {
    fn parts(&self) -> (&[f64], &[f64]) {
        match self {
            Element::Axi(m) => (&m.kmu, &m.klam),
            Element::Plane(m) => (&m.kmu, &m.klam),
        }
    }
}

/// The solved body: stresses at any point of any element.
pub struct FarField {
    rho: Vec<f64>,
    theta: Vec<f64>,
    n_in: usize,
    body: Body,
    /// Per element: (local dof values, element, lambda, mu).
    elements: Vec<([f64; 18], Element, f64, f64)>,
    nt: usize,
}

/// Largest mesh \[choice\]: 20,000 elements.
const MAX_ELEMENTS: usize = 20_000;

/// The Q2 node lines of a quarter annulus around the unit circle (shared with
/// [`super::kirsch`]): rho with `n_in` equal rings from 0 to 1 (none around a hole), then `n_out`
/// rings from 1 to `outer` graded geometrically, mid-nodes halfway; theta on 0-90 deg in `nt`
/// elements.
pub(crate) fn quarter_annulus(
    n_in: usize,
    n_out: usize,
    outer: f64,
    nt: usize,
) -> (Vec<f64>, Vec<f64>) {
    let mut edges: Vec<f64> = (0..n_in).map(|i| i as f64 / n_in as f64).collect();
    edges.extend((0..=n_out).map(|i| outer.powf(i as f64 / n_out as f64)));
    let rho = (0..2 * (edges.len() - 1) + 1)
        .map(|i| {
            if i % 2 == 0 {
                edges[i / 2]
            } else {
                0.5 * (edges[i / 2] + edges[i / 2 + 1])
            }
        })
        .collect();
    let theta = (0..=2 * nt)
        .map(|j| std::f64::consts::FRAC_PI_2 * j as f64 / (2 * nt) as f64)
        .collect();
    (rho, theta)
}

/// Solves the body: matrix E = 1, Poisson `nu`, far-field tension S = 1 along the axis.
pub fn solve(
    body: Body,
    inside: Inside,
    nu: f64,
    outer: f64,
    (n_in, n_out, nt): (usize, usize, usize),
) -> Result<FarField, SoftnessError> {
    let cavity = inside == Inside::Cavity;
    let n_in = if cavity { 0 } else { n_in };
    if !(outer > 1.0 && outer.is_finite())
        || n_out == 0
        || nt == 0
        || (!cavity && n_in == 0)
        || (n_in + n_out) * nt > MAX_ELEMENTS
    {
        return Err(SoftnessError::BadInput {
            field: "far-field mesh",
            value: ((n_in + n_out) * nt) as f64,
            hint: "an outer radius > a, rings inside an inclusion, 1-20,000 elements",
        });
    }
    let (rho, theta) = quarter_annulus(n_in, n_out, outer, nt);
    let edges_len = rho.len().div_ceil(2);
    let (ni, nj) = (rho.len(), theta.len());
    let centre = !cavity;
    // Node numbering: the centre (rho = 0) is one node.
    let node = |i: usize, j: usize| -> usize {
        if centre && i == 0 {
            0
        } else {
            usize::from(centre) + j * ni + i
        }
    };
    let pos = |i: usize, j: usize| (rho[i] * theta[j].cos(), rho[i] * theta[j].sin());
    let n_nodes = usize::from(centre) + nj * ni;
    // Symmetry: u_z = 0 on theta = 0; u_r = 0 on the axis theta = 90 deg (and the centre).
    let mut n = 0;
    let mut dofs = Vec::with_capacity(2 * n_nodes);
    for q in 0..n_nodes {
        let (i, j) = if centre && q == 0 {
            (0, 0)
        } else {
            let k = q - usize::from(centre);
            (k % ni, k / ni)
        };
        for c in 0..2 {
            let fixed = (centre && q == 0) || (j == 0 && c == 1) || (j == nj - 1 && c == 0);
            // Orphan nodes (i = 0 of the collapsed rows, unused) are fixed too.
            if fixed || (centre && i == 0 && q != 0) {
                dofs.push(DofExpr::fixed(0.0));
            } else {
                dofs.push(DofExpr::free(n));
                n += 1;
            }
        }
    }
    let matrix = lame(1.0, nu);
    let mut asm = Assembler::new(n, 1);
    let mut built = Vec::new();
    let ne = edges_len - 1;
    for ej in 0..nt {
        for ei in 0..ne {
            let nodes: [usize; 9] = std::array::from_fn(|q| node(2 * ei + q % 3, 2 * ej + q / 3));
            let xy: [(f64, f64); 9] = std::array::from_fn(|q| pos(2 * ei + q % 3, 2 * ej + q / 3));
            let (lam, mu) = match inside {
                Inside::Inclusion { e, nu } if ei < n_in => lame(e, nu),
                _ => matrix,
            };
            let el = match body {
                Body::Sphere => Element::Axi(axi_q2(&xy)),
                Body::Cylinder => Element::Plane(mapped_q2(&xy)),
            };
            let (kmu, klam) = el.parts();
            let ke = lame_combined(kmu, klam, mu, lam);
            asm.add(0, &ke, &pair_dofs(&nodes, &dofs));
            built.push((nodes, el, lam, mu));
        }
    }
    // The uniform field's traction S n_z e_z on the outer arc (per radian for the sphere).
    for ej in 0..nt {
        let edge: Vec<(usize, (f64, f64))> = (0..3)
            .map(|b| (node(ni - 1, 2 * ej + b), pos(ni - 1, 2 * ej + b)))
            .collect();
        for &(eta, w) in &gauss(3) {
            let (nv, dv) = lagrange(2, eta);
            let (mut r, mut tr) = (0.0, 0.0);
            for (b, &(_, p)) in edge.iter().enumerate() {
                r += nv[b] * p.0;
                tr += dv[b] * p.0;
            }
            // n ds = (dz, -dr) along increasing theta; the traction's z part is S n_z ds.
            let fz = -tr;
            let weight = match body {
                Body::Sphere => r,
                Body::Cylinder => 1.0,
            };
            for (b, &(q, _)) in edge.iter().enumerate() {
                asm.force(&dofs[2 * q + 1], w * nv[b] * fz * weight);
            }
        }
    }
    let u = asm.finish()?.solve(&[1.0])?;
    let value = |e: &DofExpr| e.constant + e.terms.iter().map(|&(g, c)| c * u[g]).sum::<f64>();
    let elements = built
        .into_iter()
        .map(|(nodes, el, lam, mu)| {
            let ue: [f64; 18] = std::array::from_fn(|i| value(&dofs[2 * nodes[i / 2] + i % 2]));
            (ue, el, lam, mu)
        })
        .collect();
    Ok(FarField {
        rho,
        theta,
        n_in,
        body,
        elements,
        nt,
    })
}

impl FarField {
    /// Stress (sigma_rr or _xx, sigma_zz or _yy, sigma_thth or _zz, tau) at local
    /// (xi, eta) of ring `ring` (0 innermost), sector `sector` (0 at the symmetry plane).
    #[track_caller]
    pub fn stress(&self, ring: usize, sector: usize, xi: f64, eta: f64) -> [f64; 4] {
        let rings = (self.rho.len() - 1) / 2;
        assert!(ring < rings && sector < self.nt, "no such element");
        let (u, el, lam, mu) = &self.elements[sector * rings + ring];
        match el {
            Element::Axi(m) => m.stress(u, *lam, *mu, xi, eta),
            Element::Plane(m) => {
                let s = m.stress(u, *lam, *mu, xi, eta);
                // Plane strain: sigma_zz = lambda theta_bar, theta_bar taken as the in-plane
                // stresses' trace / (2 (lambda + mu)): exact where div u equals its projection.
                let szz = *lam * (s.0 + s.1) / (2.0 * (*lam + *mu));
                [s.0, s.1, szz, s.2]
            }
        }
    }

    /// Rings inside the inclusion, and the body.
    pub fn rings_inside(&self) -> usize {
        self.n_in
    }
    pub fn body(&self) -> Body {
        self.body
    }
    /// Polar coordinates of node line (i, j).
    pub fn node_polar(&self, i: usize, j: usize) -> (f64, f64) {
        (self.rho[i], self.theta[j])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Normal-stress block (x, y, z) of an isotropic stiffness: lambda 1 1^T + 2 mu I.
    fn stiffness(e: f64, nu: f64) -> [[f64; 3]; 3] {
        let (lam, mu) = lame(e, nu);
        std::array::from_fn(|i| std::array::from_fn(|j| lam + if i == j { 2.0 * mu } else { 0.0 }))
    }

    fn mul(a: &[[f64; 3]; 3], x: &[f64; 3]) -> [f64; 3] {
        std::array::from_fn(|i| (0..3).map(|k| a[i][k] * x[k]).sum())
    }

    fn matmul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
        std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|k| a[i][k] * b[k][j]).sum()))
    }

    /// Solves a x = b (3 x 3, Gaussian elimination with partial pivoting).
    fn solve3(a: [[f64; 3]; 3], b: [f64; 3]) -> [f64; 3] {
        let mut m: Vec<Vec<f64>> = (0..3)
            .map(|i| {
                let mut r = a[i].to_vec();
                r.push(b[i]);
                r
            })
            .collect();
        for c in 0..3 {
            let p = (c..3)
                .max_by(|&x, &y| m[x][c].abs().total_cmp(&m[y][c].abs()))
                .unwrap();
            m.swap(c, p);
            for r in c + 1..3 {
                let f = m[r][c] / m[c][c];
                let pivot = m[c].clone();
                for (x, y) in m[r][c..].iter_mut().zip(&pivot[c..]) {
                    *x -= f * y;
                }
            }
        }
        let mut x = [0.0; 3];
        for c in (0..3).rev() {
            x[c] = (m[c][3] - (c + 1..3).map(|k| m[c][k] * x[k]).sum::<f64>()) / m[c][c];
        }
        x
    }

    /// Eshelby's tensor of a sphere, normal block: S = alpha J + beta K with J = 1 1^T / 3 and
    /// K = I - J, alpha = (1 + nu) / (3 (1 - nu)), beta = 2 (4 - 5 nu) / (15 (1 - nu)) (Eshelby,
    /// Proc. R. Soc. A 241, 1957, sec. 3; Mura, Micromechanics of Defects in Solids, 1987,
    /// Eq. 11.21: S_1111 = (7 - 5 nu) / (15 (1 - nu)), S_1122 = (5 nu - 1) / (15 (1 - nu))).
    fn eshelby_sphere(nu: f64) -> [[f64; 3]; 3] {
        let alpha = (1.0 + nu) / (3.0 * (1.0 - nu));
        let beta = 2.0 * (4.0 - 5.0 * nu) / (15.0 * (1.0 - nu));
        std::array::from_fn(|i| {
            std::array::from_fn(|j| alpha / 3.0 + beta * (f64::from(u8::from(i == j)) - 1.0 / 3.0))
        })
    }

    /// Eshelby's tensor of a circular cylinder along z, normal block (Mura 1987, Eq. 11.22 with
    /// a1 = a2): S_1111 = S_2222 = (5 - 4 nu) / (8 (1 - nu)), S_1122 = (4 nu - 1) / (8 (1 - nu)),
    /// S_1133 = S_2233 = nu / (2 (1 - nu)), S_33kl = 0 (no strain along the axis).
    fn eshelby_cylinder(nu: f64) -> [[f64; 3]; 3] {
        let d = 8.0 * (1.0 - nu);
        [
            [(5.0 - 4.0 * nu) / d, (4.0 * nu - 1.0) / d, 4.0 * nu / d],
            [(4.0 * nu - 1.0) / d, (5.0 - 4.0 * nu) / d, 4.0 * nu / d],
            [0.0; 3],
        ]
    }

    /// The equivalent-inclusion method (Eshelby 1957; Mura 1987, sec. 22): the inhomogeneity C1
    /// in C0 under the far strain eps0 carries the uniform stress C1 (eps0 + S eps*) where
    /// C1 (eps0 + S eps*) = C0 (eps0 + S eps* - eps*), i.e.
    /// ((C1 - C0) S + C0) eps* = -(C1 - C0) eps0.
    fn equivalent_inclusion(
        s: &[[f64; 3]; 3],
        c0: &[[f64; 3]; 3],
        c1: &[[f64; 3]; 3],
        eps0: [f64; 3],
    ) -> [f64; 3] {
        let dc: [[f64; 3]; 3] =
            std::array::from_fn(|i| std::array::from_fn(|j| c1[i][j] - c0[i][j]));
        let a0 = matmul(&dc, s);
        let a: [[f64; 3]; 3] =
            std::array::from_fn(|i| std::array::from_fn(|j| a0[i][j] + c0[i][j]));
        let rhs = mul(&dc, &eps0).map(|v| -v);
        let es = solve3(a, rhs);
        let se = mul(s, &es);
        mul(c1, &std::array::from_fn(|i| eps0[i] + se[i]))
    }

    /// The worst deviation (in S) of the FE stress inside the inclusion (element centres and
    /// quarter points of every inner ring but the collapsed one) from `want` (r/x, z/y, theta/z).
    fn worst_inside(f: &FarField, nt: usize, want: [f64; 3]) -> f64 {
        let mut worst: f64 = 0.0;
        for ring in 1..f.rings_inside() {
            for sector in 0..nt {
                for (xi, eta) in [(0.0, 0.0), (-0.5, 0.5), (0.5, -0.5)] {
                    let s = f.stress(ring, sector, xi, eta);
                    for c in 0..3 {
                        worst = worst.max((s[c] - want[c]).abs());
                    }
                    worst = worst.max(s[3].abs());
                }
            }
        }
        worst
    }

    #[test]
    fn the_cavity_concentrates_stress_as_goodier_found() {
        // A spherical cavity under far-field tension S along the axis: sigma_zz at the equator is
        // (27 - 15 nu) / (2 (7 - 5 nu)) S (Goodier, J. Appl. Mech. 1, 1933; Timoshenko & Goodier,
        // Theory of Elasticity, 3rd ed., sec. 138): 2.045 S at nu = 0.3. The body ends at 20 a,
        // loaded there by the uniform field's traction.
        for nu in [0.3, 0.49, 0.4999] {
            let want = (27.0 - 15.0 * nu) / (2.0 * (7.0 - 5.0 * nu));
            let e: Vec<f64> = [(8, 6), (16, 12), (32, 24)]
                .iter()
                .map(|&(n, t)| {
                    let f = solve(Body::Sphere, Inside::Cavity, nu, 20.0, (0, n, t)).unwrap();
                    f.stress(0, 0, -1.0, -1.0)[1] / want - 1.0
                })
                .collect();
            eprintln!("Goodier nu {nu}: sigma_zz / ({want:.4} S) - 1 on 8x6, 16x12, 32x24: {e:?}");
            assert!(e[2].abs() < 2e-3, "{e:?}");
            assert!(e[1].abs() < 0.5 * e[0].abs() || e[1].abs() < 1e-3, "{e:?}");
        }
    }

    #[test]
    fn a_spherical_lump_carries_eshelbys_uniform_stress() {
        // Paper 002's lump (10x stiffer, nu 0.4) in the tissue (nu 0.49), uniaxial S along z.
        let (nu0, e1, nu1) = (0.49, 10.0, 0.4);
        let c0 = stiffness(1.0, nu0);
        let eps0 = solve3(c0, [0.0, 0.0, 1.0]);
        let want = equivalent_inclusion(&eshelby_sphere(nu0), &c0, &stiffness(e1, nu1), eps0);
        // Cylindrical (x, y, z) at a point of the meridian plane x = r: sigma_xx = sigma_rr,
        // sigma_yy = sigma_thth; uniform, so sigma_rr = sigma_thth.
        assert!((want[0] - want[1]).abs() < 1e-12);
        let want = [want[0], want[2], want[1]];
        let mut e = Vec::new();
        for (n_in, n_out, nt) in [(3, 8, 6), (6, 16, 12), (12, 32, 24)] {
            let inside = Inside::Inclusion { e: e1, nu: nu1 };
            let f = solve(Body::Sphere, inside, nu0, 20.0, (n_in, n_out, nt)).unwrap();
            e.push(worst_inside(&f, nt, want));
        }
        eprintln!("Eshelby sphere: interior stress {want:?} S; worst FE deviation {e:?} S");
        assert!(e[2] < 5e-3 && e[2] < e[1] && e[1] < e[0], "{e:?}");
    }

    #[test]
    fn a_cylindrical_lump_carries_eshelbys_uniform_stress_in_plane_strain() {
        // The plane-strain element: a circular lump, far-field tension S along y, plane strain
        // (sigma_zz = nu S far away so that eps_zz = 0). The body ends at 100 a (the disturbance
        // decays only as (a / rho)^2 in 2-D).
        let (nu0, e1, nu1) = (0.49, 10.0, 0.4);
        let c0 = stiffness(1.0, nu0);
        let eps0 = solve3(c0, [0.0, 1.0, nu0]);
        assert!(eps0[2].abs() < 1e-12);
        let want = equivalent_inclusion(&eshelby_cylinder(nu0), &c0, &stiffness(e1, nu1), eps0);
        let mut e = Vec::new();
        for (n_in, n_out, nt) in [(3, 10, 6), (6, 20, 12), (12, 40, 24)] {
            let inside = Inside::Inclusion { e: e1, nu: nu1 };
            let f = solve(Body::Cylinder, inside, nu0, 100.0, (n_in, n_out, nt)).unwrap();
            e.push(worst_inside(&f, nt, want));
        }
        eprintln!("Eshelby cylinder: interior stress {want:?} S; worst FE deviation {e:?} S");
        assert!(e[2] < 5e-3 && e[2] < e[1] && e[1] < e[0], "{e:?}");
    }
}
