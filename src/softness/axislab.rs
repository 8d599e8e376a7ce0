//! A sphere on the axis of a cylinder of tissue squeezed between bonded rigid jaws: the 3-D scene
//! of a spherical lump or void, axisymmetric, solved on the meridian (r, z) with the
//! axisymmetric Q2/P1 (B-bar) element of [`super::axisym`].
//!
//! The cylinder \[choice\]: radius [`CYLINDER_RADIUS_PER_HALF_WIDTH`] times half the plane
//! slab's width (15 mm for the default 30 mm slab: the sphere sees the free surface as far off
//! as the plane section's disc does), thickness and tissue as the [`Slab`]; bonded to the sensor
//! face z = 0 (held) and to the jaw z = H (moved down by `compression` H), free outside. As in
//! [`super::inclusion`], an element the sphere's section crosses mixes both stiffnesses by the
//! sphere's share of its volume (r-weighted, 16 x 16 samples) and one at least 99 % void is left
//! out. The face pressure P(r) is the consistent projection of the face nodes' reactions:
//! M p = f with M_ij = int N_i N_j r dr on the face (exact for any pressure in the Q2 trace
//! space; a lumped tributary would vanish at the axis node). d(r) = P / P0 - 1 on the same mesh.

use serde::Serialize;

use super::axisym::axi_q2;
use super::continuum::{gauss, lagrange, lame, Assembler, DofExpr};
use super::inclusion::{Feature, Slab};
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
    pub elements: (usize, usize),
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
    if !(s.tissue_e_pa > 0.0 && s.tissue_e_pa.is_finite() && (0.0..0.5).contains(&s.tissue_nu)) {
        return bad(
            "tissue_e_pa",
            s.tissue_e_pa,
            "tissue E > 0 and nu in [0, 0.5)",
        );
    }
    if !(s.compression > 0.0 && s.compression < 0.5) {
        return bad("compression", s.compression, "a compression in (0, 0.5)");
    }
    if let Feature::Lump { e_pa, nu } = s.feature {
        if !(e_pa > 0.0 && e_pa.is_finite() && (0.0..0.5).contains(&nu)) {
            return bad("lump e_pa", e_pa, "a lump needs E > 0 and nu in [0, 0.5)");
        }
    }
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

/// The face pressure (Pa) at the 2 nr + 1 face nodes of the cylinder with `feature`.
fn face_pressure(
    s: &Slab,
    rc: f64,
    nr: usize,
    nz: usize,
    feature: Feature,
) -> Result<Vec<f64>, SoftnessError> {
    let h = s.thickness_m;
    let rs: Vec<f64> = (0..=2 * nr)
        .map(|i| rc * i as f64 / (2 * nr) as f64)
        .collect();
    let zs: Vec<f64> = (0..=2 * nz)
        .map(|j| h * j as f64 / (2 * nz) as f64)
        .collect();
    let ni = rs.len();
    let node = |i: usize, j: usize| j * ni + i;
    const SAMPLES: usize = 16;
    // The sphere's share of the element's volume (r-weighted samples).
    let fraction = |er: usize, ez: usize| -> f64 {
        if feature == Feature::None {
            return 0.0;
        }
        let (r0, r1, z0, z1) = (rs[2 * er], rs[2 * er + 2], zs[2 * ez], zs[2 * ez + 2]);
        let (mut inside, mut all) = (0.0, 0.0);
        for a in 0..SAMPLES {
            let r = r0 + (r1 - r0) * (a as f64 + 0.5) / SAMPLES as f64;
            for b in 0..SAMPLES {
                let z = z0 + (z1 - z0) * (b as f64 + 0.5) / SAMPLES as f64 - s.centre_height_m;
                all += r;
                if r * r + z * z < s.radius_m * s.radius_m {
                    inside += r;
                }
            }
        }
        inside / all
    };
    let material = |er: usize, ez: usize| -> Option<f64> {
        let f = fraction(er, ez);
        match feature {
            Feature::Void if f >= 0.99 => None,
            _ => Some(f),
        }
    };
    let mut used = vec![false; ni * zs.len()];
    let mut shares = Vec::with_capacity(nr * nz);
    for ez in 0..nz {
        for er in 0..nr {
            let m = material(er, ez);
            if m.is_some() {
                for q in 0..9 {
                    used[node(2 * er + q % 3, 2 * ez + q / 3)] = true;
                }
            }
            shares.push(m);
        }
    }
    let top = zs.len() - 1;
    let delta = s.compression * h;
    let mut unknowns = 0;
    let mut dofs = Vec::with_capacity(2 * used.len());
    for (q, &u) in used.iter().enumerate() {
        let (i, j) = (q % ni, q / ni);
        for c in 0..2 {
            let e = if j == 0 || !u || (i == 0 && c == 0) {
                DofExpr::fixed(0.0)
            } else if j == top {
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
    let mut bottom = Vec::with_capacity(nr);
    for ez in 0..nz {
        for er in 0..nr {
            let Some(f) = shares[ez * nr + er] else {
                continue;
            };
            let rz: [(f64, f64); 9] =
                std::array::from_fn(|q| (rs[2 * er + q % 3], zs[2 * ez + q / 3]));
            let m = axi_q2(&rz);
            let ke: Vec<f64> = m
                .kmu
                .iter()
                .zip(&m.klam)
                .map(|(a, b)| {
                    let t = (1.0 - f) * (tissue.1 * a + tissue.0 * b);
                    t + lump.map_or(0.0, |(lam, mu)| f * (mu * a + lam * b))
                })
                .collect();
            let nodes: [usize; 9] = std::array::from_fn(|q| node(2 * er + q % 3, 2 * ez + q / 3));
            let map: Vec<&DofExpr> = nodes
                .iter()
                .flat_map(|&q| [&dofs[2 * q], &dofs[2 * q + 1]])
                .collect();
            asm.add(0, &ke, &map);
            if ez == 0 {
                bottom.push((er, nodes, ke));
            }
        }
    }
    let u = asm.finish()?.solve(&[1.0])?;
    let value = |e: &DofExpr| e.constant + e.terms.iter().map(|&(g, c)| c * u[g]).sum::<f64>();
    // The face nodes' axial reactions (per radian), compression positive.
    let mut force = vec![0.0; ni];
    for (er, nodes, ke) in &bottom {
        let ue: Vec<f64> = nodes
            .iter()
            .flat_map(|&q| [value(&dofs[2 * q]), value(&dofs[2 * q + 1])])
            .collect();
        for a in 0..3 {
            let row = 2 * a + 1;
            force[2 * er + a] += (0..18).map(|c| ke[row * 18 + c] * ue[c]).sum::<f64>();
        }
    }
    // M p = f, M_ij = int N_i N_j r dr over the face's Q2 edges (3-point Gauss: exact to
    // degree 5 = 2 + 2 + 1).
    let mut mass = vec![vec![0.0; ni]; ni];
    for er in 0..nr {
        let (r0, r1) = (rs[2 * er], rs[2 * er + 2]);
        for &(xi, w) in &gauss(3) {
            let (n, _) = lagrange(2, xi);
            let r = 0.5 * (r0 + r1) + 0.5 * (r1 - r0) * xi;
            for a in 0..3 {
                for b in 0..3 {
                    mass[2 * er + a][2 * er + b] += w * 0.5 * (r1 - r0) * r * n[a] * n[b];
                }
            }
        }
    }
    Ok(banded_solve(mass, force, 2))
}

/// The face nodes' radii (m) and pressures (Pa) of the cylinder with the slab's own feature
/// only (the building block of studies that share one background), on `nr` x `nz` elements.
pub fn face_pressure_pa(
    s: &Slab,
    nr: usize,
    nz: usize,
) -> Result<(Vec<f64>, Vec<f64>), SoftnessError> {
    let rc = check(s, nr, nz)?;
    let r_m = (0..=2 * nr)
        .map(|i| rc * i as f64 / (2 * nr) as f64)
        .collect();
    Ok((r_m, face_pressure(s, rc, nr, nz, s.feature)?))
}

/// P(r) with the sphere and P0(r) without, on `nr` x `nz` elements over the cylinder's meridian.
pub fn sphere_profile(s: &Slab, nr: usize, nz: usize) -> Result<AxiProfile, SoftnessError> {
    let rc = check(s, nr, nz)?;
    let p = face_pressure(s, rc, nr, nz, s.feature)?;
    let p0 = face_pressure(s, rc, nr, nz, Feature::None)?;
    let r_m: Vec<f64> = (0..=2 * nr)
        .map(|i| rc * i as f64 / (2 * nr) as f64)
        .collect();
    let ratio = p.iter().zip(&p0).map(|(a, b)| a / b);
    let (peak, low) = ratio.fold((f64::NEG_INFINITY, f64::INFINITY), |(a, b), v| {
        (a.max(v), b.min(v))
    });
    Ok(AxiProfile {
        r_m,
        p_pa: p,
        p0_pa: p0,
        peak_ratio: peak,
        min_ratio: low,
        elements: (nr, nz),
    })
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
    fn a_sphere_lump_and_void_against_the_plane_sections_disc() {
        // The same element size (0.25 mm) for the sphere (60 x 40 over the 15 mm radius) and the
        // plane section's disc (120 x 40 over the 30 mm slab). Measured (release example, finer
        // meshes): the sphere lump's peak 1.564, 1.528, 1.492, 1.471 on 15x20 to 120x160, the
        // cylinder's 1.482, 1.448, 1.429 on 60x20 to 240x80: a stiff sphere collects more of the
        // squeeze than a stiff cylinder (Eshelby's interior stress under uniaxial stress: 1.78 S
        // against 1.40 S for paper 002's lump, `far_field`), so its peak is not lower; a void
        // sphere lowers the pressure far less than a void cylinder (0.55 against 0.31).
        use super::super::inclusion::pressure_profile;
        let lump = Feature::Lump {
            e_pa: 200e3,
            nu: 0.4,
        };
        let peaks: Vec<f64> = [(15, 10), (30, 20), (60, 40)]
            .iter()
            .map(|&(nr, nz)| sphere_profile(&slab(lump), nr, nz).unwrap().peak_ratio)
            .collect();
        let void = sphere_profile(&slab(Feature::Void), 60, 40).unwrap();
        let cyl = pressure_profile(&slab(lump), 120, 40).unwrap().peak_ratio;
        let cyl_void = pressure_profile(&slab(Feature::Void), 120, 40)
            .unwrap()
            .min_ratio;
        eprintln!(
            "sphere lump peak P / P0 on 15x10, 30x20, 60x40: {peaks:?}; cylinder (plane strain, \
             120 x 40) {cyl:.4}; void: sphere min {:.4}, cylinder min {cyl_void:.4}",
            void.min_ratio
        );
        // Falling with refinement as the plane section's peak does, by less each time.
        assert!(peaks[1] < peaks[0] && peaks[2] < peaks[1], "{peaks:?}");
        assert!(
            peaks[1] - peaks[2] < peaks[0] - peaks[1] + 5e-3,
            "{peaks:?}"
        );
        assert!(
            peaks[2] > 1.3 && (peaks[2] / cyl - 1.0).abs() < 0.1,
            "{peaks:?} {cyl}"
        );
        assert!(
            void.min_ratio < 0.7 && void.min_ratio > cyl_void + 0.1,
            "{}",
            void.min_ratio
        );
        // Lump up, void down, at the axis.
        assert!(void.p_pa[0] < void.p0_pa[0]);
    }
}
