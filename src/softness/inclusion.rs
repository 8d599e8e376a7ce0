//! A hidden feature in grasped tissue (paper 002 sec. V.B, Figs. 8-9): a plane-strain tissue slab
//! between the jaws with a lump (a stiffer disc), a void or nothing, and the contact pressure it
//! puts on the sensor's surface, P(x), against the featureless slab's P0(x).
//!
//! The slab (width W, thickness H, y up from the sensor) is bonded to both jaws: the sensor face
//! y = 0 is held, the opposite jaw y = H moves down by `compression` H; the ends are free. Elements
//! are the Q2/P1 (B-bar) quadrilaterals of [`super::continuum`], locking-free at nu = 0.49. An element the
//! disc's edge crosses takes the disc's share f of its area as a mix of the two stiffnesses (Voigt:
//! K = (1 - f) E_t K(nu_t) + f E_l K(nu_l), f sampled on 16 x 16 points), so the edge moves
//! smoothly with the mesh instead of in element steps; an element at least 99 % void is left out.
//! P(x) is the reaction of the sensor-face nodes over their Q2 tributary lengths (h / 6, 4 h / 6, h / 6), so a
//! uniform traction is recovered exactly; P / P0 on the same mesh cancels what the lumping and
//! the free ends leave.

use std::fmt::Write as _;

use serde::Serialize;

use super::continuum::{
    lame, lame_combined, Assembler, DofExpr, ElementCache, Order, QuadMesh, Volumetric,
};
use super::SoftnessError;

/// The feature in the slab.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Feature {
    /// No feature: the background P0.
    None,
    /// A stiffer disc (paper 002: 200 kPa, nu 0.4, in 20 kPa tissue).
    Lump { e_pa: f64, nu: f64 },
    /// An empty disc.
    Void,
}

/// The slab and its feature (SI units).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Slab {
    pub width_m: f64,
    pub thickness_m: f64,
    pub tissue_e_pa: f64,
    pub tissue_nu: f64,
    /// Shortening of the slab between the jaws, as a fraction of its thickness.
    pub compression: f64,
    pub feature: Feature,
    /// Centre of the disc: along the sensor and its height above the sensor face.
    pub centre_x_m: f64,
    pub centre_height_m: f64,
    pub radius_m: f64,
}

impl Slab {
    /// Paper 002's tissue (sec. V.B: 20 kPa, nu 0.49) in a 30 x 10 mm slab squeezed by 10 %, with
    /// `feature` as a disc of radius 2 mm centred 4 mm above the sensor at x = 15 mm [choice: the
    /// paper gives no geometry; `tactfab tissue`'s defaults].
    pub fn paper_002(feature: Feature) -> Slab {
        Slab {
            width_m: 30e-3,
            thickness_m: 10e-3,
            tissue_e_pa: 20e3,
            tissue_nu: 0.49,
            compression: 0.1,
            feature,
            centre_x_m: 15e-3,
            centre_height_m: 4e-3,
            radius_m: 2e-3,
        }
    }
}

/// Contact pressure on the sensor face (compression positive, Pa) at the face's nodes.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PressureProfile {
    pub x_m: Vec<f64>,
    pub p_pa: Vec<f64>,
    pub p0_pa: Vec<f64>,
    /// P / P0 node by node.
    pub ratio: Vec<f64>,
    /// The largest and smallest P / P0 and where.
    pub peak_ratio: f64,
    pub peak_x_m: f64,
    pub min_ratio: f64,
    pub min_x_m: f64,
    /// Elements across and through.
    pub elements: (usize, usize),
}

/// Largest mesh \[choice\]: 80,000 Q2 elements (400 x 200), about 0.6 M unknowns.
pub const MAX_ELEMENTS: usize = 80_000;

/// The tissue's and the lump's elastic constants and the compression, as every slab model
/// (plane, axisymmetric, 3-D) takes them.
pub(crate) fn check_materials(
    tissue_e_pa: f64,
    tissue_nu: f64,
    compression: f64,
    feature: Feature,
) -> Result<(), SoftnessError> {
    let bad = |field: &'static str, value: f64, hint: &'static str| {
        Err(SoftnessError::BadInput { field, value, hint })
    };
    if !(tissue_e_pa > 0.0 && tissue_e_pa.is_finite()) {
        return bad("tissue_e_pa", tissue_e_pa, "tissue E must be positive");
    }
    if !(0.0..0.5).contains(&tissue_nu) {
        return bad("tissue_nu", tissue_nu, "nu must lie in [0, 0.5)");
    }
    if !(compression > 0.0 && compression < 0.5) {
        return bad(
            "compression",
            compression,
            "a compression in (0, 0.5) of the thickness",
        );
    }
    if let Feature::Lump { e_pa, nu } = feature {
        if !(e_pa > 0.0 && e_pa.is_finite() && (0.0..0.5).contains(&nu)) {
            return bad("lump e_pa", e_pa, "a lump needs E > 0 and nu in [0, 0.5)");
        }
    }
    Ok(())
}

fn check(s: &Slab, nx: usize, ny: usize) -> Result<(), SoftnessError> {
    let bad = |field: &'static str, value: f64, hint: &'static str| {
        Err(SoftnessError::BadInput { field, value, hint })
    };
    if !(s.width_m > 0.0 && s.width_m.is_finite()) {
        return bad("width_m", s.width_m, "the slab needs a positive width");
    }
    if !(s.thickness_m > 0.0 && s.thickness_m.is_finite()) {
        return bad(
            "thickness_m",
            s.thickness_m,
            "the slab needs a positive thickness",
        );
    }
    check_materials(s.tissue_e_pa, s.tissue_nu, s.compression, s.feature)?;
    if s.feature != Feature::None {
        let r = s.radius_m;
        if !(r > 0.0
            && s.centre_height_m - r > 0.0
            && s.centre_height_m + r < s.thickness_m
            && s.centre_x_m - r > 0.0
            && s.centre_x_m + r < s.width_m)
        {
            return bad("radius_m", r, "the disc must lie inside the slab");
        }
    }
    if nx == 0 || ny == 0 || nx.saturating_mul(ny) > MAX_ELEMENTS {
        return bad(
            "elements",
            (nx * ny) as f64,
            "use between 1 and 80,000 elements",
        );
    }
    Ok(())
}

/// Sensor-face pressure of the slab with its feature, on `nx` x `ny` Q2/P1 elements: squeezed
/// by the jaws, or (`wall_pa` Some) with the jaws held and a pressure on the void's wall.
fn face_pressure(
    s: &Slab,
    nx: usize,
    ny: usize,
    feature: Feature,
    wall_pa: Option<f64>,
) -> Result<Vec<f64>, SoftnessError> {
    let (w, h) = (s.width_m, s.thickness_m);
    let qm = QuadMesh {
        order: Order::Q2,
        x_m: (0..=nx).map(|i| w * i as f64 / nx as f64).collect(),
        y_m: (0..=ny).map(|j| h * j as f64 / ny as f64).collect(),
    };
    let (nxs, nys) = (qm.node_x(), qm.node_y());
    // The disc's share of each element's area, sampled on 16 x 16 points.
    const SAMPLES: usize = 16;
    let fraction = |ex: usize, ey: usize| -> f64 {
        if feature == Feature::None {
            return 0.0;
        }
        let (x0, x1, y0, y1) = (qm.x_m[ex], qm.x_m[ex + 1], qm.y_m[ey], qm.y_m[ey + 1]);
        let r2 = s.radius_m * s.radius_m;
        let mut n = 0;
        for a in 0..SAMPLES {
            for b in 0..SAMPLES {
                let x = x0 + (x1 - x0) * (a as f64 + 0.5) / SAMPLES as f64 - s.centre_x_m;
                let y = y0 + (y1 - y0) * (b as f64 + 0.5) / SAMPLES as f64 - s.centre_height_m;
                n += usize::from(x * x + y * y < r2);
            }
        }
        n as f64 / (SAMPLES * SAMPLES) as f64
    };
    // Tissue share of the element (None: left out as void).
    let material = |ex: usize, ey: usize| -> Option<f64> {
        let f = fraction(ex, ey);
        match feature {
            Feature::Void if f >= 0.99 => None,
            _ => Some(f),
        }
    };
    let mut used = vec![false; qm.n_nodes()];
    for ey in 0..ny {
        for ex in 0..nx {
            if material(ex, ey).is_some() {
                for n in qm.element_nodes(ex, ey) {
                    used[n] = true;
                }
            }
        }
    }
    let top = nys.len() - 1;
    let delta = if wall_pa.is_some() {
        0.0
    } else {
        s.compression * h
    };
    let mut unknowns = 0;
    let dofs: Vec<[DofExpr; 2]> = (0..qm.n_nodes())
        .map(|n| {
            let j = n / nxs.len();
            if j == 0 || !used[n] {
                [DofExpr::fixed(0.0), DofExpr::fixed(0.0)]
            } else if j == top {
                [DofExpr::fixed(0.0), DofExpr::fixed(-delta)]
            } else {
                unknowns += 2;
                [DofExpr::free(unknowns - 2), DofExpr::free(unknowns - 1)]
            }
        })
        .collect();
    let lump_nu = match feature {
        Feature::Lump { nu, .. } => nu,
        _ => s.tissue_nu,
    };
    // K = E_t K(nu_t) + E_lump K(nu_lump): per unit modulus, scaled at solve time.
    let units = [lame(1.0, s.tissue_nu), lame(1.0, lump_nu)];
    let mut cache = ElementCache::new(Order::Q2, Volumetric::Bbar);
    let mut asm = Assembler::new(unknowns, 2);
    let mut elements = Vec::new();
    for ey in 0..ny {
        for ex in 0..nx {
            let Some(f) = material(ex, ey) else {
                continue;
            };
            let (kmu, klam) = cache.get(qm.x_m[ex + 1] - qm.x_m[ex], qm.y_m[ey + 1] - qm.y_m[ey]);
            let unit = |m: usize, share: f64| -> Vec<f64> {
                let (lam, mu) = units[m];
                lame_combined(kmu, klam, share * mu, share * lam)
            };
            let (kt, kl) = (unit(0, 1.0 - f), unit(1, f));
            let nodes = qm.element_nodes(ex, ey);
            let map: Vec<&DofExpr> = nodes
                .iter()
                .flat_map(|&nd| [&dofs[nd][0], &dofs[nd][1]])
                .collect();
            asm.add(0, &kt, &map);
            if f > 0.0 {
                asm.add(1, &kl, &map);
            }
            if ey == 0 {
                elements.push((ex, kt, kl));
            }
        }
    }
    if let Some(p) = wall_pa {
        // The void's wall is the staircase of the left-out elements: each edge shared with a
        // kept element carries p towards it, lumped on the Q2 edge nodes (h / 6, 4 h / 6, h / 6).
        for ey in 0..ny {
            for ex in 0..nx {
                if material(ex, ey).is_some() {
                    continue;
                }
                // (neighbour, edge nodes (i, j), direction into the tissue)
                let sides = [
                    (
                        ex + 1 < nx,
                        (ex + 1, ey),
                        [(2 * ex + 2, 2 * ey); 3],
                        (1.0, 0.0),
                        1,
                    ),
                    (
                        ex > 0,
                        (ex.wrapping_sub(1), ey),
                        [(2 * ex, 2 * ey); 3],
                        (-1.0, 0.0),
                        1,
                    ),
                    (
                        ey + 1 < ny,
                        (ex, ey + 1),
                        [(2 * ex, 2 * ey + 2); 3],
                        (0.0, 1.0),
                        0,
                    ),
                    (
                        ey > 0,
                        (ex, ey.wrapping_sub(1)),
                        [(2 * ex, 2 * ey); 3],
                        (0.0, -1.0),
                        0,
                    ),
                ];
                for (exists, nb, start, dir, along) in sides {
                    if !exists || material(nb.0, nb.1).is_none() {
                        continue;
                    }
                    let len = if along == 1 {
                        qm.y_m[ey + 1] - qm.y_m[ey]
                    } else {
                        qm.x_m[ex + 1] - qm.x_m[ex]
                    };
                    for (k, wgt) in [(0, 1.0), (1, 4.0), (2, 1.0)] {
                        let (i, j) = if along == 1 {
                            (start[k].0, start[k].1 + k)
                        } else {
                            (start[k].0 + k, start[k].1)
                        };
                        let nd = qm.node(i, j);
                        let f = p * len * wgt / 6.0;
                        asm.force(&dofs[nd][0], f * dir.0);
                        asm.force(&dofs[nd][1], f * dir.1);
                    }
                }
            }
        }
    }
    let lump_e = match feature {
        Feature::Lump { e_pa, .. } => e_pa,
        _ => 0.0,
    };
    let u = asm.finish()?.solve(&[s.tissue_e_pa, lump_e])?;
    let value = |e: &DofExpr| e.constant + e.terms.iter().map(|&(g, c)| c * u[g]).sum::<f64>();
    // Reactions on the sensor face: the bottom row's internal forces at its face nodes (nothing
    // else acts there), compression positive.
    let mut force = vec![0.0; nxs.len()];
    for (ex, kt, kl) in elements {
        let nodes = qm.element_nodes(ex, 0);
        let ue: Vec<f64> = nodes
            .iter()
            .flat_map(|&nd| [value(&dofs[nd][0]), value(&dofs[nd][1])])
            .collect();
        let nd = ue.len();
        for (a, &node) in nodes.iter().enumerate().take(3) {
            // Local nodes 0..3 are the bottom edge (j = 0) of the Q2 element.
            let row = 2 * a + 1;
            let f: f64 = (0..nd)
                .map(|c| (s.tissue_e_pa * kt[row * nd + c] + lump_e * kl[row * nd + c]) * ue[c])
                .sum();
            force[node] += f;
        }
    }
    // Tributary lengths of the Q2 edge nodes.
    let mut trib = vec![0.0; nxs.len()];
    for ex in 0..nx {
        let hx = qm.x_m[ex + 1] - qm.x_m[ex];
        for (a, wgt) in [(0, 1.0), (1, 4.0), (2, 1.0)] {
            trib[2 * ex + a] += hx * wgt / 6.0;
        }
    }
    Ok(force.iter().zip(&trib).map(|(f, t)| f / t).collect())
}

/// P(x) with the feature and P0(x) without, on `nx` x `ny` elements.
pub fn pressure_profile(s: &Slab, nx: usize, ny: usize) -> Result<PressureProfile, SoftnessError> {
    check(s, nx, ny)?;
    let p = face_pressure(s, nx, ny, s.feature, None)?;
    let p0 = face_pressure(s, nx, ny, Feature::None, None)?;
    let x_m: Vec<f64> = (0..=2 * nx)
        .map(|i| s.width_m * i as f64 / (2 * nx) as f64)
        .collect();
    let ratio: Vec<f64> = p.iter().zip(&p0).map(|(a, b)| a / b).collect();
    let (mut peak, mut low) = ((f64::NEG_INFINITY, 0.0), (f64::INFINITY, 0.0));
    for (&r, &x) in ratio.iter().zip(&x_m) {
        if r > peak.0 {
            peak = (r, x);
        }
        if r < low.0 {
            low = (r, x);
        }
    }
    Ok(PressureProfile {
        x_m,
        p_pa: p,
        p0_pa: p0,
        ratio,
        peak_ratio: peak.0,
        peak_x_m: peak.1,
        min_ratio: low.0,
        min_x_m: low.1,
        elements: (nx, ny),
    })
}

/// The sensor-face pressure (Pa) at the face's 2 nx + 1 nodes of the slab with its own feature
/// only (no background solve): the cached building block of studies that share one background.
pub fn face_pressure_pa(s: &Slab, nx: usize, ny: usize) -> Result<Vec<f64>, SoftnessError> {
    check(s, nx, ny)?;
    face_pressure(s, nx, ny, s.feature, None)
}

/// A vessel (paper 002 Fig. 10): the sensor-face pressure (Pa) per pascal of pressure inside a
/// void, with the jaws held where the grasp put them (the slab is linear: the grasp's own
/// pressure, [`face_pressure_pa`], adds to p times this). The slab's feature must be a void.
pub fn wall_pressure_face_pa(s: &Slab, nx: usize, ny: usize) -> Result<Vec<f64>, SoftnessError> {
    check(s, nx, ny)?;
    if s.feature != Feature::Void {
        return Err(SoftnessError::BadInput {
            field: "feature",
            value: f64::NAN,
            hint: "a vessel is a void whose wall carries the pressure",
        });
    }
    face_pressure(s, nx, ny, Feature::Void, Some(1.0))
}

impl PressureProfile {
    /// One row per sensor-face node, units in the header.
    pub fn csv(&self) -> String {
        let p = self;
        let mut s = String::from("x_mm,P_pa,P0_pa,P_over_P0\n");
        for i in 0..p.x_m.len() {
            let _ = writeln!(
                s,
                "{:.6},{:.6e},{:.6e},{:.6}",
                p.x_m[i] * 1e3,
                p.p_pa[i],
                p.p0_pa[i],
                p.ratio[i]
            );
        }
        s
    }

    /// P / P0 along the jaw against the featureless 1.
    pub fn svg(&self, s: &Slab) -> String {
        let p = self;
        let points = p
            .x_m
            .iter()
            .zip(&p.ratio)
            .map(|(x, r)| (x * 1e3, *r))
            .collect();
        let name = match s.feature {
            Feature::Void => "void",
            _ => "lump",
        };
        crate::plot::xy_svg(
            &crate::plot::XyPlot {
                title: format!(
                    "Contact pressure over a hidden {name} (radius {} mm, {} mm above the sensor)",
                    crate::plot::tick(s.radius_m * 1e3),
                    crate::plot::tick(s.centre_height_m * 1e3)
                ),
                x: crate::plot::Axis::linear("x along the jaw (mm)"),
                y: crate::plot::Axis::linear("P / P0"),
                series: vec![
                    crate::plot::Series {
                        name: format!("with the {name}"),
                        points,
                        style: crate::plot::Style::Line,
                    },
                    crate::plot::Series {
                        name: "no feature".into(),
                        points: vec![(0.0, 1.0), (s.width_m * 1e3, 1.0)],
                        style: crate::plot::Style::Dashed,
                    },
                ],
            },
            800,
            480,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn slab(feature: Feature) -> Slab {
        Slab::paper_002(feature)
    }

    #[test]
    fn a_nearly_incompressible_bonded_layer_squeezes_out_parabolically() {
        // Gent & Lindley (Proc. IMechE 173, 1959), plane strain: an incompressible layer of width
        // 2a and thickness H bonded between rigid plates and shortened by delta carries
        // p(x) = 6 G delta (a^2 - x^2) / H^3. At nu = 0.4999 (bulk 5,000 G) and a = 5 H the FE
        // must give that, not the bulk response of a locked mesh.
        let s = Slab {
            width_m: 100e-3,
            thickness_m: 10e-3,
            tissue_nu: 0.4999,
            compression: 0.01,
            ..slab(Feature::None)
        };
        let p = pressure_profile(&s, 100, 8).unwrap();
        let g = s.tissue_e_pa / (2.0 * (1.0 + s.tissue_nu));
        let (a, h) = (0.5 * s.width_m, s.thickness_m);
        let exact = |x: f64| 6.0 * g * s.compression * h * (a * a - x * x) / h.powi(3);
        let n = p.p0_pa.len();
        for (i, frac) in [(n / 2, 0.0), (n / 2 + n / 4, 0.5)] {
            let want = exact(frac * a);
            let got = p.p0_pa[i];
            assert!(
                ((got - want) / want).abs() < 0.05,
                "x = {frac} a: {got} vs {want}"
            );
        }
    }

    #[test]
    fn a_wide_bonded_slab_is_in_uniaxial_strain_in_its_middle() {
        // Far from the free ends (W = 20 H) a compressible slab is in uniaxial strain:
        // P0 = (lambda + 2 mu) delta / H (plane strain, bonded faces).
        for nu in [0.0, 0.3] {
            let s = Slab {
                width_m: 200e-3,
                thickness_m: 10e-3,
                tissue_nu: nu,
                ..slab(Feature::None)
            };
            let p = pressure_profile(&s, 80, 4).unwrap();
            let (lam, mu) = lame(s.tissue_e_pa, nu);
            let want = (lam + 2.0 * mu) * s.compression;
            let mid = p.p0_pa[p.p0_pa.len() / 2];
            assert!(
                ((mid - want) / want).abs() < 1e-6,
                "nu {nu}: {mid} vs {want}"
            );
            assert!(p.ratio.iter().all(|r| (r - 1.0).abs() < 1e-12));
        }
    }

    #[test]
    fn a_lump_raises_and_a_void_lowers_the_pressure_over_it() {
        // Paper 002 reports > 40 % over a lump and ~65 % less over a void (its geometry unstated).
        let lump = pressure_profile(
            &slab(Feature::Lump {
                e_pa: 200e3,
                nu: 0.4,
            }),
            120,
            40,
        )
        .unwrap();
        assert!(lump.peak_ratio > 1.2, "{}", lump.peak_ratio);
        assert!((lump.peak_x_m - 15e-3).abs() < 1.5e-3, "{}", lump.peak_x_m);
        let void = pressure_profile(&slab(Feature::Void), 120, 40).unwrap();
        eprintln!(
            "lump: P/P0 up to {:.3}; void: down to {:.3}",
            lump.peak_ratio, void.min_ratio
        );
        assert!(void.min_ratio < 0.8, "{}", void.min_ratio);
        assert!((void.min_x_m - 15e-3).abs() < 1.5e-3, "{}", void.min_x_m);
        // Mirror symmetry about the disc's centre line.
        let n = lump.ratio.len();
        for i in 0..n {
            let (a, b) = (lump.ratio[i], lump.ratio[n - 1 - i]);
            assert!((a - b).abs() < 1e-6 * a.abs(), "{i}: {a} {b}");
        }
        // Equilibrium: the face carries what the jaw pushes; with the stiff lump, more.
        let total = |p: &[f64]| p.iter().sum::<f64>();
        assert!(total(&lump.p_pa) > total(&lump.p0_pa));
        assert!(total(&void.p_pa) < total(&void.p0_pa));
    }

    #[test]
    fn the_peak_converges_with_the_mesh() {
        let s = slab(Feature::Lump {
            e_pa: 200e3,
            nu: 0.4,
        });
        let peaks: Vec<f64> = [(60, 20), (120, 40), (240, 80)]
            .iter()
            .map(|&(nx, ny)| pressure_profile(&s, nx, ny).unwrap().peak_ratio)
            .collect();
        let (d1, d2) = ((peaks[1] - peaks[0]).abs(), (peaks[2] - peaks[1]).abs());
        eprintln!("P/P0 peak on 60x20, 120x40, 240x80: {peaks:?}");
        // Measured 1.482, 1.448, 1.429: monotone at about first order (the mixed elements on
        // the disc's edge), extrapolating to ~1.40; the finest mesh is within ~2 % of it.
        assert!(d2 < 0.7 * d1 && d2 < 0.02 * peaks[2], "{peaks:?}");
    }

    #[test]
    fn pressure_in_a_void_pushes_the_sensor_over_it() {
        // The jaws held, 1 Pa on the void's wall: the face is pushed over the vessel, mirror
        // symmetric, and the peak converges with the mesh.
        let s = slab(Feature::Void);
        let peaks: Vec<f64> = [(60, 20), (120, 40), (240, 80)]
            .iter()
            .map(|&(nx, ny)| {
                let w = wall_pressure_face_pa(&s, nx, ny).unwrap();
                let n = w.len();
                for i in 0..n {
                    assert!((w[i] - w[n - 1 - i]).abs() < 1e-9, "{i}");
                }
                assert!(w[n / 2] > 0.0 && w.iter().sum::<f64>() > 0.0);
                w[n / 2]
            })
            .collect();
        eprintln!("face pressure per Pa in the vessel, at its centre: {peaks:?}");
        // Measured 0.554, 0.546, 0.537: the staircase wall converges slowly (changes of
        // 1.5 % per halving, not shrinking yet); the finest is within a few % of the limit.
        let (d1, d2) = ((peaks[1] - peaks[0]).abs(), (peaks[2] - peaks[1]).abs());
        assert!(d1 < 0.03 * peaks[1] && d2 < 0.03 * peaks[2], "{peaks:?}");
        assert!(peaks[2] < peaks[1] && peaks[1] < peaks[0], "{peaks:?}");
        assert!(wall_pressure_face_pa(&slab(Feature::None), 10, 10).is_err());
    }

    #[test]
    fn bad_input_is_an_error() {
        let mut s = slab(Feature::Void);
        s.radius_m = 5e-3;
        assert!(pressure_profile(&s, 10, 10).is_err());
        let s = slab(Feature::None);
        assert!(pressure_profile(&s, 1000, 1000).is_err());
        assert!(pressure_profile(
            &Slab {
                tissue_nu: 0.5,
                ..s
            },
            10,
            10
        )
        .is_err());
    }
}
