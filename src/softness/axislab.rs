//! A sphere on the axis of a cylinder of tissue squeezed between bonded rigid jaws: the 3-D scene
//! of a spherical lump or void, axisymmetric, solved on the meridian (r, z) with the
//! axisymmetric Q2/P1 (B-bar) element of [`super::axisym`].
//!
//! The cylinder \[choice\]: radius [`CYLINDER_RADIUS_PER_HALF_WIDTH`] times half the plane
//! slab's width (15 mm for the default 30 mm slab: the sphere sees the free surface as far off
//! as the plane section's disc does), thickness and tissue as the [`Slab`]; bonded to the sensor
//! face z = 0 (held) and to the jaw z = H (moved down by `compression` H), free outside. The mesh
//! follows the sphere ([`super::sphere_mesh`]): every element is tissue or sphere (a void's
//! are left out), so the extreme P / P0 converges monotonically at a steady order, and
//! [`sphere_convergence`] gives it on three nested meshes with its Richardson estimate (the
//! earlier rectilinear mesh mixed both stiffnesses by area share in the cut elements and
//! converged slowly and unevenly). The face pressure P(r) is the consistent projection of the face nodes' reactions:
//! M p = f with M_ij = int N_i N_j r dr on the face (exact for any pressure in the Q2 trace
//! space; a lumped tributary would vanish at the axis node). d(r) = P / P0 - 1 on the same mesh.

use serde::Serialize;
use std::fmt::Write as _;

use super::axisym::axi_q2;
use super::continuum::{gauss, lagrange, lame, lame_combined, pair_dofs, Assembler, DofExpr};
use super::inclusion::{Feature, Slab};
use super::sphere_mesh::{sphere_mesh, Counts, Geometry, SphereMesh};
use super::SoftnessError;

/// The tissue cylinder's radius over half the slab's width \[choice\]: 1.
pub const CYLINDER_RADIUS_PER_HALF_WIDTH: f64 = 1.0;

/// Largest mesh \[choice\]: 40,000 elements.
pub const MAX_ELEMENTS: usize = 40_000;

/// The face pressure of the cylinder with and without its sphere.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AxiProfile {
    /// Face nodes' radii (m) and pressures (Pa, compression positive).
    pub r_m: Vec<f64>,
    pub p_pa: Vec<f64>,
    pub p0_pa: Vec<f64>,
    /// The largest and smallest P / P0.
    pub peak_ratio: f64,
    pub min_ratio: f64,
    /// Elements of the mesh.
    pub elements: usize,
}

/// The sphere's section must fit the cylinder; `slab.centre_x_m` is ignored (on the axis).
fn check(s: &Slab, nr: usize, nz: usize) -> Result<f64, SoftnessError> {
    let bad = |field: &'static str, value: f64, hint: &'static str| {
        Err(SoftnessError::BadInput { field, value, hint })
    };
    let rc = CYLINDER_RADIUS_PER_HALF_WIDTH * 0.5 * s.width_m;
    if !(rc > 0.0 && rc.is_finite() && s.thickness_m > 0.0 && s.thickness_m.is_finite()) {
        return bad("width_m", s.width_m, "the slab needs a positive size");
    }
    super::inclusion::check_materials(s.tissue_e_pa, s.tissue_nu, s.compression, s.feature)?;
    if s.feature != Feature::None {
        let (r, h) = (s.radius_m, s.centre_height_m);
        if !(r > 0.0 && h - r > 0.0 && h + r < s.thickness_m && r < rc) {
            return bad("radius_m", r, "the sphere must lie inside the tissue");
        }
    }
    if nr == 0 || nz == 0 || nr.saturating_mul(nz) > MAX_ELEMENTS {
        return bad(
            "elements",
            (nr * nz) as f64,
            "use between 1 and 40,000 elements",
        );
    }
    Ok(rc)
}

/// Solves a symmetric positive definite banded system (half bandwidth `b`, dense rows) in place
/// by Gaussian elimination without pivoting; returns x.
fn banded_solve(mut a: Vec<Vec<f64>>, mut f: Vec<f64>, b: usize) -> Vec<f64> {
    let n = f.len();
    for k in 0..n {
        for i in k + 1..(k + b + 1).min(n) {
            let m = a[i][k] / a[k][k];
            if m == 0.0 {
                continue;
            }
            let end = (k + b + 1).min(n);
            let (top, rest) = a.split_at_mut(i);
            for (x, y) in rest[0][k..end].iter_mut().zip(&top[k][k..end]) {
                *x -= m * y;
            }
            f[i] -= m * f[k];
        }
    }
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        let s: f64 = (i + 1..(i + b + 1).min(n)).map(|j| a[i][j] * x[j]).sum();
        x[i] = (f[i] - s) / a[i][i];
    }
    x
}

/// The rectilinear nr x nz mesh of the cylinder's meridian (no sphere: the background's).
fn grid_mesh(rc: f64, h: f64, nr: usize, nz: usize) -> SphereMesh {
    let rs: Vec<f64> = (0..=2 * nr)
        .map(|i| rc * i as f64 / (2 * nr) as f64)
        .collect();
    let zs: Vec<f64> = (0..=2 * nz)
        .map(|j| h * j as f64 / (2 * nz) as f64)
        .collect();
    let ni = rs.len();
    let nodes = zs
        .iter()
        .flat_map(|&z| rs.iter().map(move |&r| (r, z)))
        .collect();
    let elements = (0..nz)
        .flat_map(|ez| {
            (0..nr).map(move |er| {
                let e = std::array::from_fn(|q| (2 * ez + q / 3) * ni + 2 * er + q % 3);
                (e, false)
            })
        })
        .collect();
    SphereMesh { nodes, elements }
}

/// The face nodes' radii and pressures (Pa) of the cylinder meshed by `mesh`, its sphere's
/// elements of `feature` (left out for a void; tissue for none).
fn face_pressure(s: &Slab, mesh: &SphereMesh, feature: Feature) -> Result<AxiFace, SoftnessError> {
    let h = s.thickness_m;
    let used_by = |inside: bool| !(inside && feature == Feature::Void);
    let mut used = vec![false; mesh.nodes.len()];
    for (e, inside) in &mesh.elements {
        if used_by(*inside) {
            for &q in e {
                used[q] = true;
            }
        }
    }
    let delta = s.compression * h;
    let mut unknowns = 0;
    let mut dofs = Vec::with_capacity(2 * used.len());
    for (&(r, z), &u) in mesh.nodes.iter().zip(&used) {
        for c in 0..2 {
            let e = if z == 0.0 || !u || (r == 0.0 && c == 0) {
                DofExpr::fixed(0.0)
            } else if z == h {
                DofExpr::fixed(if c == 1 { -delta } else { 0.0 })
            } else {
                unknowns += 1;
                DofExpr::free(unknowns - 1)
            };
            dofs.push(e);
        }
    }
    let lump = match feature {
        Feature::Lump { e_pa, nu } => Some(lame(e_pa, nu)),
        _ => None,
    };
    let tissue = lame(s.tissue_e_pa, s.tissue_nu);
    let mut asm = Assembler::new(unknowns, 1);
    let mut on_face = Vec::new();
    for (nodes, inside) in &mesh.elements {
        if !used_by(*inside) {
            continue;
        }
        let rz: [(f64, f64); 9] = std::array::from_fn(|q| mesh.nodes[nodes[q]]);
        let m = axi_q2(&rz);
        let (lam, mu) = match (inside, lump) {
            (true, Some(l)) => l,
            _ => tissue,
        };
        let ke = lame_combined(&m.kmu, &m.klam, mu, lam);
        asm.add(0, &ke, &pair_dofs(nodes, &dofs));
        if rz.iter().any(|p| p.1 == 0.0) {
            on_face.push((*nodes, ke));
        }
    }
    let u = asm.finish()?.solve(&[1.0])?;
    let value = |e: &DofExpr| e.constant + e.terms.iter().map(|&(g, c)| c * u[g]).sum::<f64>();
    // The face nodes in order of radius, their axial reactions (per radian, compression
    // positive), and the face's Q2 edges.
    let mut face: Vec<usize> = (0..mesh.nodes.len())
        .filter(|&q| mesh.nodes[q].1 == 0.0)
        .collect();
    face.sort_by(|&p, &q| mesh.nodes[p].0.total_cmp(&mesh.nodes[q].0));
    let slot = |q: usize| face.binary_search_by(|&p| mesh.nodes[p].0.total_cmp(&mesh.nodes[q].0));
    let mut force = vec![0.0; face.len()];
    let mut edges = Vec::new();
    for (nodes, ke) in &on_face {
        let ue: Vec<f64> = nodes
            .iter()
            .flat_map(|&q| [value(&dofs[2 * q]), value(&dofs[2 * q + 1])])
            .collect();
        for (a, &q) in nodes.iter().enumerate() {
            if mesh.nodes[q].1 == 0.0 {
                let row = 2 * a + 1;
                force[slot(q).expect("a face node")] +=
                    (0..18).map(|c| ke[row * 18 + c] * ue[c]).sum::<f64>();
            }
        }
        for side in [[0, 1, 2], [6, 7, 8], [0, 3, 6], [2, 5, 8]] {
            let q = side.map(|k| nodes[k]);
            if q.iter().all(|&n| mesh.nodes[n].1 == 0.0) {
                let mut ends = q.map(|n| slot(n).expect("a face node"));
                ends.sort_unstable();
                edges.push(ends);
            }
        }
    }
    // M p = f, M_ij = int N_i N_j r dr over the face's Q2 edges (3-point Gauss: exact to
    // degree 5 = 2 + 2 + 1).
    let r_m: Vec<f64> = face.iter().map(|&q| mesh.nodes[q].0).collect();
    let mut mass = vec![vec![0.0; face.len()]; face.len()];
    for e in &edges {
        let (r0, r1) = (r_m[e[0]], r_m[e[2]]);
        for &(xi, w) in &gauss(3) {
            let (n, _) = lagrange(2, xi);
            let r = 0.5 * (r0 + r1) + 0.5 * (r1 - r0) * xi;
            for a in 0..3 {
                for b in 0..3 {
                    mass[e[a]][e[b]] += w * 0.5 * (r1 - r0) * r * n[a] * n[b];
                }
            }
        }
    }
    let p_pa = banded_solve(mass, force, 2);
    Ok(AxiFace { r_m, p_pa })
}

/// Face node radii (m) and pressures (Pa).
struct AxiFace {
    r_m: Vec<f64>,
    p_pa: Vec<f64>,
}

/// The fitted mesh's base counts for `nr` x `nz` elements' size: the meshes of
/// [`sphere_convergence`] scale them by [`SEQUENCE`], whose last (the finest,
/// [`sphere_profile`]'s mesh) has about that size near the sphere.
fn base_counts(s: &Slab, rc: f64, nr: usize, nz: usize) -> (Geometry, Counts) {
    let geo = Geometry {
        rc_m: rc,
        h_m: s.thickness_m,
        a_m: s.radius_m,
        centre_m: s.centre_height_m,
    };
    let e = (rc / nr as f64).min(s.thickness_m / nz as f64);
    (geo, geo.counts(SEQUENCE[2] as f64 * e))
}

/// The convergence sequence's scales of the base counts \[choice\]: 2, 3, 4. The base mesh
/// (four times coarser than asked, two elements across the default sphere's radius) is
/// pre-asymptotic (the default lump's peak 1.4383, 1.4433, 1.4465, 1.4473, 1.4476, 1.4476,
/// 1.4476 on scales 1, 2, 3, 4, 5, 6, 8), so the sequence starts at 2.
pub const SEQUENCE: [usize; 3] = [2, 3, 4];

/// The face nodes' radii (m) and pressures (Pa) of the cylinder with the slab's own feature
/// only, on `nr` x `nz` elements of the featureless cylinder (the building block of studies
/// that share one background).
pub fn face_pressure_pa(
    s: &Slab,
    nr: usize,
    nz: usize,
) -> Result<(Vec<f64>, Vec<f64>), SoftnessError> {
    let rc = check(s, nr, nz)?;
    let f = face_pressure(s, &grid_mesh(rc, s.thickness_m, nr, nz), s.feature)?;
    Ok((f.r_m, f.p_pa))
}

/// P with the slab's feature and P0 without, both on `mesh` (their ratio shares it).
fn profile_on(s: &Slab, mesh: &SphereMesh) -> Result<AxiProfile, SoftnessError> {
    let p = face_pressure(s, mesh, s.feature)?;
    let p0 = face_pressure(s, mesh, Feature::None)?;
    let ratio = p.p_pa.iter().zip(&p0.p_pa).map(|(a, b)| a / b);
    let (peak, low) = ratio.fold((f64::NEG_INFINITY, f64::INFINITY), |(a, b), v| {
        (a.max(v), b.min(v))
    });
    Ok(AxiProfile {
        r_m: p.r_m,
        p_pa: p.p_pa,
        p0_pa: p0.p_pa,
        peak_ratio: peak,
        min_ratio: low,
        elements: mesh.elements.len(),
    })
}

/// P(r) with the sphere and P0(r) without on the cylinder's meridian: for a lump or a void on
/// the finest mesh of [`sphere_convergence`]'s sequence (elements of about the size of `nr` x
/// `nz` over the meridian near the sphere, their edges on it); without a feature on the
/// rectilinear `nr` x `nz`.
pub fn sphere_profile(s: &Slab, nr: usize, nz: usize) -> Result<AxiProfile, SoftnessError> {
    let rc = check(s, nr, nz)?;
    if s.feature == Feature::None {
        return profile_on(s, &grid_mesh(rc, s.thickness_m, nr, nz));
    }
    let (geo, base) = base_counts(s, rc, nr, nz);
    profile_on(s, &sphere_mesh(&geo, base.scaled(SEQUENCE[2])))
}

/// The extreme P / P0 (the peak over a lump, the minimum over a void) on three nested fitted
/// meshes, and its Richardson extrapolation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SphereConvergence {
    /// Elements of each mesh, coarsest first, and the extreme P / P0 on it.
    pub elements: [usize; 3],
    pub extreme: [f64; 3],
    /// Observed order ([`richardson`]; None unless the sequence is monotone).
    pub order: Option<f64>,
    /// f3 + (f3 - f2) / (2^p - 1), and its distance from the finest mesh's answer.
    pub estimate: Option<f64>,
    pub error: Option<f64>,
    /// The finest mesh's profile ([`sphere_profile`]'s).
    pub finest: AxiProfile,
}

/// Richardson's extrapolation (L. F. Richardson, Phil. Trans. R. Soc. A 210, 1911) of `f` on
/// three similar meshes of sizes proportional to `h` (coarsest first), in the form for unequal
/// refinement ratios (Celik et al., J. Fluids Eng. 130, 078001, 2008, Eqs. 3-4 \[lit\]): the
/// order p solving (f1 - f2) / (f2 - f3) = (h1^p - h2^p) / (h2^p - h3^p) (by bisection on
/// 0.05-12), and f3 + (f3 - f2) / ((h2 / h3)^p - 1). None when the differences change sign or
/// no order in that range fits.
#[track_caller]
pub fn richardson(f: [f64; 3], h: [f64; 3]) -> Option<(f64, f64)> {
    assert!(
        h[0] > h[1] && h[1] > h[2] && h[2] > 0.0,
        "mesh sizes decreasing: {h:?}"
    );
    let (d1, d2) = (f[0] - f[1], f[1] - f[2]);
    if d1 * d2 <= 0.0 || d1.is_nan() || d2.is_nan() {
        return None;
    }
    let want = d1 / d2;
    let g = |p: f64| (h[0].powf(p) - h[1].powf(p)) / (h[1].powf(p) - h[2].powf(p)) - want;
    let (mut lo, mut hi) = (0.05, 12.0);
    if g(lo) * g(hi) > 0.0 {
        return None;
    }
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if g(lo) * g(mid) <= 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let p = 0.5 * (lo + hi);
    Some((p, f[2] + (f[2] - f[1]) / ((h[1] / h[2]).powf(p) - 1.0)))
}

/// [`sphere_profile`] with its two coarser meshes ([`SEQUENCE`]): the extreme P / P0
/// converging, and its Richardson estimate. The slab must have a feature.
pub fn sphere_convergence(
    s: &Slab,
    nr: usize,
    nz: usize,
) -> Result<SphereConvergence, SoftnessError> {
    let rc = check(s, nr, nz)?;
    if s.feature == Feature::None {
        return Err(SoftnessError::BadInput {
            field: "feature",
            value: f64::NAN,
            hint: "the convergence of P / P0 needs a lump or a void",
        });
    }
    let (geo, base) = base_counts(s, rc, nr, nz);
    let mut elements = [0; 3];
    let mut extreme = [0.0; 3];
    let mut finest = None;
    for (k, scale) in SEQUENCE.into_iter().enumerate() {
        let p = profile_on(s, &sphere_mesh(&geo, base.scaled(scale)))?;
        elements[k] = p.elements;
        extreme[k] = match s.feature {
            Feature::Void => p.min_ratio,
            _ => p.peak_ratio,
        };
        finest = Some(p);
    }
    let h = SEQUENCE.map(|k| 1.0 / k as f64);
    let r = richardson(extreme, h);
    Ok(SphereConvergence {
        elements,
        extreme,
        order: r.map(|r| r.0),
        estimate: r.map(|r| r.1),
        error: r.map(|r| (r.1 - extreme[2]).abs()),
        finest: finest.expect("three meshes"),
    })
}

impl SphereConvergence {
    /// `tissue-sphere.csv`: the finest mesh's face profile, one row per face node.
    pub fn profile_csv(&self) -> String {
        let p = &self.finest;
        let mut s = String::from("r_mm,P_pa,P0_pa,P_over_P0\n");
        for i in 0..p.r_m.len() {
            let _ = writeln!(
                s,
                "{:.6},{:.6e},{:.6e},{:.6}",
                p.r_m[i] * 1e3,
                p.p_pa[i],
                p.p0_pa[i],
                p.p_pa[i] / p.p0_pa[i]
            );
        }
        s
    }

    /// `tissue-sphere-convergence.csv`: the extreme P / P0 on each mesh, then the Richardson
    /// estimate (its order, and its distance from the finest as the error; empty when the
    /// sequence is not monotone).
    pub fn convergence_csv(&self) -> String {
        let mut s = String::from("mesh,elements,extreme_P_over_P0,order,error\n");
        for (k, scale) in SEQUENCE.iter().enumerate() {
            let _ = writeln!(
                s,
                "scale {scale},{},{:.6},,",
                self.elements[k], self.extreme[k]
            );
        }
        let o = |v: Option<f64>, d: usize| v.map_or_else(String::new, |v| format!("{v:.d$}"));
        let _ = writeln!(
            s,
            "richardson,,{},{},{}",
            o(self.estimate, 6),
            o(self.order, 3),
            self.error.map_or_else(String::new, |e| format!("{e:.3e}"))
        );
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_banded_solve_is_gaussian_elimination() {
        // A pentadiagonal SPD system against its known solution.
        let n: usize = 7;
        let x: Vec<f64> = (0..n).map(|i| 1.0 + i as f64 * 0.5).collect();
        let a: Vec<Vec<f64>> = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| match i.abs_diff(j) {
                        0 => 6.0,
                        1 => -1.0,
                        2 => 0.5,
                        _ => 0.0,
                    })
                    .collect()
            })
            .collect();
        let f: Vec<f64> = (0..n)
            .map(|i| (0..n).map(|j| a[i][j] * x[j]).sum())
            .collect();
        let y = banded_solve(a, f, 2);
        for (p, q) in x.iter().zip(&y) {
            assert!((p - q).abs() < 1e-13);
        }
    }

    fn slab(feature: Feature) -> Slab {
        Slab::paper_002(feature)
    }

    #[test]
    fn without_poisson_the_squeeze_is_uniform_and_with_it_uniaxial_in_the_middle() {
        // nu = 0: the bonded cylinder is in uniform uniaxial strain, P0 = E delta / H at every
        // face node, the axis included (the multi-element patch test of the hoop term). nu =
        // 0.3 on a cylinder 15 thicknesses wide: the middle is in uniaxial strain,
        // P0 = (lambda + 2 mu) delta / H.
        for (nu, width, tol) in [(0.0, 30e-3, 1e-9), (0.3, 300e-3, 2e-3)] {
            let s = Slab {
                tissue_nu: nu,
                width_m: width,
                ..slab(Feature::None)
            };
            let p = sphere_profile(&s, if nu == 0.0 { 6 } else { 60 }, 8).unwrap();
            let (lam, mu) = lame(s.tissue_e_pa, nu);
            let want = (lam + 2.0 * mu) * s.compression;
            let e = (p.p0_pa[0] / want - 1.0).abs();
            eprintln!("nu {nu}: P0 at the axis / ((lambda + 2 mu) delta / H) - 1 = {e:.2e}");
            assert!(e < tol, "{e}");
            if nu == 0.0 {
                let worst = p
                    .p0_pa
                    .iter()
                    .map(|v| (v / want - 1.0).abs())
                    .fold(0.0, f64::max);
                assert!(worst < tol, "{worst}");
            }
        }
    }

    #[test]
    fn a_nearly_incompressible_disc_squeezes_out_parabolically() {
        // Gent & Lindley (Proc. IMechE 173, 1959) for a bonded incompressible disc of radius a
        // and thickness H shortened by delta. Derivation (thin layer, lubrication): the radial
        // displacement is parabolic through the thickness, u = (1 / (2 G)) dp/dr (z^2 - H z),
        // so int_0^H u dz = -(H^3 / (12 G)) dp/dr; the volume squeezed inside r, pi r^2 delta,
        // leaves through 2 pi r: dp/dr = -6 G delta r / H^3, p = 3 G delta (a^2 - r^2) / H^3
        // (half the plane layer's 6 G delta (a^2 - x^2) / H^3). At nu = 0.4999 and a = 5 H:
        // the centre within 5 % (the thin-layer theory's own error is O(H^2 / a^2)); a locked
        // mesh would be thousands of times stiffer.
        let s = Slab {
            tissue_nu: 0.4999,
            width_m: 100e-3,
            ..slab(Feature::None)
        };
        let p = sphere_profile(&s, 40, 8).unwrap();
        let g = s.tissue_e_pa / (2.0 * (1.0 + s.tissue_nu));
        let (a, h) = (0.5 * s.width_m, s.thickness_m);
        let want = 3.0 * g * s.compression * h * a * a / h.powi(3);
        let e = p.p0_pa[0] / want - 1.0;
        eprintln!(
            "Gent-Lindley disc: P0(0) {:.4e} Pa against {want:.4e}: {e:+.3e}",
            p.p0_pa[0]
        );
        assert!(e.abs() < 0.05, "{e}");
    }

    #[test]
    fn richardson_recovers_a_power_law() {
        // f = 1.5 + 0.3 h^2.5 on h = 1/2, 1/3, 1/4: order 2.5 and the limit 1.5.
        let h = [0.5, 1.0 / 3.0, 0.25];
        let f = h.map(|x: f64| 1.5 + 0.3 * x.powf(2.5));
        let (p, est) = richardson(f, h).unwrap();
        assert!(
            (p - 2.5).abs() < 1e-9 && (est - 1.5).abs() < 1e-12,
            "{p} {est}"
        );
        assert!(richardson([1.0, 1.1, 1.05], h).is_none());
    }

    #[test]
    fn the_spheres_extreme_converges_monotonically_and_richardson_bounds_its_error() {
        // Paper 002's lump and a void (2 mm, 4 mm up) on the fitted meshes of the default size
        // (60 x 40: 0.25 mm near the sphere on the finest) and their two coarser ones (scales
        // 2, 3, 4 of the base counts); the reference is twice finer than the finest (scale 8). The extreme converges monotonically at a
        // steady observed order, and the Richardson estimate lies beyond the reference, seen
        // from the finest mesh: |estimate - finest| bounds the finest mesh's true error.
        for f in [
            Feature::Lump {
                e_pa: 200e3,
                nu: 0.4,
            },
            Feature::Void,
        ] {
            let s = slab(f);
            let c = sphere_convergence(&s, 60, 40).unwrap();
            let rc = check(&s, 60, 40).unwrap();
            let (geo, base) = base_counts(&s, rc, 60, 40);
            let fine = profile_on(&s, &sphere_mesh(&geo, base.scaled(8))).unwrap();
            let reference = match f {
                Feature::Void => fine.min_ratio,
                _ => fine.peak_ratio,
            };
            let (est, order) = (c.estimate.unwrap(), c.order.unwrap());
            let (truth, stated) = ((c.extreme[2] - reference).abs(), c.error.unwrap());
            eprintln!(
                "{f:?}: extreme {:?} on {:?} elements, order {order:.2}, estimate {est:.5} \
                 (stated error {stated:.2e}); reference {reference:.5} on {} elements (finest's \
                 true error {truth:.2e})",
                c.extreme, c.elements, fine.elements
            );
            assert!(order > 1.5 && order < 5.0, "{order}");
            assert!(truth <= stated, "{truth} > {stated}");
            // The reference lies between the finest mesh and the estimate.
            let (lo, hi) = (c.extreme[2].min(est), c.extreme[2].max(est));
            assert!(
                reference >= lo && reference <= hi,
                "{reference} outside {lo}..{hi}"
            );
        }
    }

    #[test]
    fn a_sphere_lump_and_void_against_the_plane_sections_disc() {
        // The same element size (0.25 mm) for the sphere (60 x 40 over the 15 mm radius: the
        // fitted mesh's finest) and the plane section's disc (120 x 40 over the 30 mm slab).
        // The sphere lump's peak converges to 1.4476 (`the_spheres_extreme_converges...`), the
        // cylinder's is 1.448 on 120 x 40 (falling: 1.482, 1.448, 1.429 on 60x20 to 240x80): a
        // stiff sphere collects about as much of the squeeze as a stiff cylinder (Eshelby's
        // interior stress under uniaxial stress is higher for the sphere: 1.78 S against 1.40
        // S for paper 002's lump, `far_field`); a void sphere lowers the pressure far less than
        // a void cylinder (0.56 against 0.31).
        use super::super::inclusion::pressure_profile;
        let lump = Feature::Lump {
            e_pa: 200e3,
            nu: 0.4,
        };
        let sphere = sphere_profile(&slab(lump), 60, 40).unwrap();
        let void = sphere_profile(&slab(Feature::Void), 60, 40).unwrap();
        let cyl = pressure_profile(&slab(lump), 120, 40).unwrap().peak_ratio;
        let cyl_void = pressure_profile(&slab(Feature::Void), 120, 40)
            .unwrap()
            .min_ratio;
        eprintln!(
            "sphere lump peak P / P0 {:.4}; cylinder (plane strain, 120 x 40) {cyl:.4}; void: \
             sphere min {:.4}, cylinder min {cyl_void:.4}",
            sphere.peak_ratio, void.min_ratio
        );
        assert!(
            sphere.peak_ratio > 1.3 && (sphere.peak_ratio / cyl - 1.0).abs() < 0.1,
            "{} {cyl}",
            sphere.peak_ratio
        );
        assert!(
            void.min_ratio < 0.7 && void.min_ratio > cyl_void + 0.1,
            "{}",
            void.min_ratio
        );
        // Lump up, void down, at the axis.
        assert!(sphere.p_pa[0] > sphere.p0_pa[0]);
        assert!(void.p_pa[0] < void.p0_pa[0]);
    }
}
