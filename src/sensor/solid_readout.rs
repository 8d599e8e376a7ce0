//! Readings of the solid model: each electrode's charge from the stresses of its own film, the
//! force through each support, the plate's deflection and silicon's largest principal stress.
//!
//! Piezo read-out (IEEE Std 176, short-circuit electrodes): D3 = d31 s1 + d32 s2 + d33 s3 in the
//! film's axes (1 = the drawn axis, 3 = the film normal), and an electrode's charge is the mean
//! of D3 through the film integrated over its area, Q = (1/t) integral of D3 dV. The support
//! electrodes are read with the plate rungs' polarity (Q = d33 x the compressive force, paper 001
//! Eq. 6), so their D3 is counted with the opposite sign. V = Q / C as for the plate rungs.

use serde::Serialize;

use crate::fe::solid::{hex27, SolidField};

use super::edge_stress::{critical_distance_um, edge_stresses, EdgeStress};
use super::evaluate::STRESS_AVERAGING_THICKNESSES;
use super::geometry::{ElectrodeSide, SensorGeometry};
use super::solid_mesh::{SensorSolid, PVDF, SILICON};
use crate::process::Axis;

/// Readings of one load case of the solid model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SolidReadout {
    /// Per electrode, in the order of `SensorGeometry::electrodes`.
    pub charge_pc: Vec<f64>,
    /// Each electrode's charge by the piezo term it comes from, [d31 s1, d32 s2, d33 s3] with
    /// the electrode's polarity (pC): they sum to `charge_pc`. What an island reads, and so what
    /// a cheaper model of it must get right (the support islands' d31 term is their bending).
    pub charge_terms_pc: Vec<[f64; 3]>,
    pub voltage_mv: Vec<f64>,
    /// Compressive force through the support films (N).
    pub support1_n: f64,
    pub support2_n: f64,
    /// Downward deflection of the plate's mid-plane at the load's reference point, and the most
    /// of it anywhere (um).
    pub deflection_at_load_um: f64,
    pub max_deflection_um: f64,
    /// Largest principal stress in the silicon over all Gauss points (MPa) and where: at a
    /// re-entrant corner (tooth base, channel wall) it grows with the mesh.
    pub max_principal_mpa: f64,
    pub max_principal_at_um: [f64; 3],
    /// The plate rungs' safety-factor stress: the largest in-plane principal stress of the stress
    /// averaged over a square of the plate rungs' averaging width (four plate thicknesses) on the
    /// plate's underside, centred in the contact patch (MPa); it converges with the mesh.
    pub stress_averaged_mpa: f64,
    /// The largest principal stress at the critical distance from each kind of sharp
    /// re-entrant edge (tooth bases, channel walls), from corner submodels
    /// ([`super::edge_stress`]): what fracture is judged on there.
    pub edge_stress: Vec<EdgeStress>,
}

/// In-plane principal stress of (s_xx, s_yy, s_xy): (sx + sy)/2 + sqrt(((sx - sy)/2)^2 + txy^2).
fn principal_in_plane(s: [f64; 3]) -> f64 {
    0.5 * (s[0] + s[1]) + (0.25 * (s[0] - s[1]).powi(2) + s[2] * s[2]).sqrt()
}

/// (x, y) carried into the part solved through the model's mirrors, and the sign the in-plane
/// shear takes there: s_xy is odd under a reflection of x or of y, s_xx and s_yy even.
fn fold(s: &SensorSolid, p: (f64, f64)) -> ((f64, f64), f64) {
    let (q, [fx, fy]) = s.mirror_image_um(p);
    (q, if fx != fy { -1.0 } else { 1.0 })
}

/// The stress tensor (xx, yy, xy) averaged over a square of side `side_um` centred at (x, y) on
/// the plate's underside of the whole die, clipped to the die as the plate rungs clip it (4 x 4
/// Gauss points, each beyond a mirror read at its image); None if a Gauss point falls off the
/// part meshed.
fn underside_mean(
    s: &SensorSolid,
    sol: &impl SolidField,
    g: &SensorGeometry,
    z_um: f64,
    (x, y): (f64, f64),
    side_um: f64,
) -> Option<[f64; 3]> {
    let h = 0.5 * side_um;
    let (x0, x1) = ((x - h).max(0.0), (x + h).min(g.length_um));
    let (y0, y1) = ((y - h).max(0.0), (y + h).min(g.width_um));
    if x1 <= x0 || y1 <= y0 {
        return None;
    }
    let mut sum = [0.0; 3];
    let mut area = 0.0;
    for (px, wx) in crate::fe::bfs::gauss4_on(x0, x1) {
        for (py, wy) in crate::fe::bfs::gauss4_on(y0, y1) {
            let ((qx, qy), shear) = fold(s, (px, py));
            let (e, xi) = sol.locate([qx, qy, z_um])?;
            let st = sol.stress_at(e, xi)?;
            for (acc, v) in sum.iter_mut().zip([st[0], st[1], shear * st[5]]) {
                *acc += wx * wy * v;
            }
            area += wx * wy;
        }
    }
    Some(sum.map(|v| v / area))
}

/// The largest [`underside_mean`] principal stress over centres on a grid (at most 12 x 12)
/// across `patch` (x0, y0, x1, y1) on the whole die, as the plate rungs read it on the mirrored
/// whole plate (until 2026-11-29 the patch was clipped to the part solved, and a contact on a
/// mirror reaching less than a square's width into that part read NaN: no square fitted).
fn averaged_stress(
    s: &SensorSolid,
    sol: &impl SolidField,
    g: &SensorGeometry,
    patch: [f64; 4],
) -> f64 {
    let side = STRESS_AVERAGING_THICKNESSES * g.plate_thickness_um;
    let r = [
        patch[0].max(0.0),
        patch[1].max(0.0),
        patch[2].min(g.length_um),
        patch[3].min(g.width_um),
    ];
    if r[2] < r[0] || r[3] < r[1] {
        return f64::NAN;
    }
    // Just inside the silicon above the film bonded under the plate.
    let z = s.layers.plate_bottom_um + 1e-6 * g.plate_thickness_um;
    let cells = |len: f64| ((len / side).ceil() as usize).clamp(1, 12);
    let (nx, ny) = (cells(r[2] - r[0]), cells(r[3] - r[1]));
    let mut best = f64::NAN;
    for i in 0..nx {
        for j in 0..ny {
            let x = r[0] + (r[2] - r[0]) * (i as f64 + 0.5) / nx as f64;
            let y = r[1] + (r[3] - r[1]) * (j as f64 + 0.5) / ny as f64;
            if let Some(m) = underside_mean(s, sol, g, z, (x, y), side) {
                best = best.max(principal_in_plane(m) * 1e-6);
            }
        }
    }
    best
}

/// Images of a rectangle under the model's mirrors, clipped to the part solved.
pub(crate) fn images(s: &SensorSolid, r: [f64; 4]) -> Vec<[f64; 4]> {
    let mut out = vec![r];
    if let Some(m) = s.mirror_x_um {
        let more: Vec<[f64; 4]> = out
            .iter()
            .map(|r| [2.0 * m - r[2], r[1], 2.0 * m - r[0], r[3]])
            .collect();
        out.extend(more);
    }
    if let Some(m) = s.mirror_y_um {
        let more: Vec<[f64; 4]> = out
            .iter()
            .map(|r| [r[0], 2.0 * m - r[3], r[2], 2.0 * m - r[1]])
            .collect();
        out.extend(more);
    }
    let (x0, x1, y0, y1) = s.domain_um;
    out.into_iter()
        .map(|r| [r[0].max(x0), r[1].max(y0), r[2].min(x1), r[3].min(y1)])
        .filter(|r| r[2] > r[0] && r[3] > r[1])
        .collect()
}

/// The readings of `sol` (a solution of `s`), with the load's reference point `at_um` (x, y) and
/// its contact patch (x0, y0, x1, y1). An edge's corner submodel that cannot be solved is an
/// error.
pub fn read(
    g: &SensorGeometry,
    s: &SensorSolid,
    sol: &impl SolidField,
    at_um: (f64, f64),
    patch_um: [f64; 4],
) -> crate::fe::FeResult<SolidReadout> {
    let grid = sol.grid();
    let pos = sol.node_positions_um();
    let lay = s.layers;
    let [nx, ny, nz] = grid.n_elements();
    let zs = grid.lines_um()[2];
    let t_film = g.film_thickness_um * 1e-6;
    // Electrode rectangles and their images in the part solved.
    let rects: Vec<Vec<[f64; 4]>> = g
        .electrodes
        .iter()
        .map(|e| images(s, [e.x0_um, e.y0_um, e.x1_um, e.y1_um]))
        .collect();
    let mut terms = vec![[0.0; 3]; g.electrodes.len()];
    let (mut s1, mut s2) = (0.0, 0.0);
    let gauss = hex27::gauss_points();
    for k in 0..nz {
        let zc = 0.5 * (zs[k] + zs[k + 1]);
        let support_film = zc > 0.0 && zc < lay.film_top_um;
        let floor_film = zc > lay.floor_film_bottom_um && zc < lay.plate_bottom_um;
        if !(support_film || floor_film) {
            continue;
        }
        for j in 0..ny {
            for i in 0..nx {
                let cell = grid.element([i, j, k]);
                if grid.cell_material(cell) != Some(PVDF) {
                    continue;
                }
                // The cell's Gauss points in the element holding it (a merged brick's field
                // integrated over each of its cells, so electrode edges on cell lines hold).
                let (e, offset, scale) = grid.cell_in_owner(cell);
                let owner = grid.element_ijk(e);
                let nodes_um = grid.element_nodes(e).map(|n| pos[n]);
                let nodes_m = nodes_um.map(|p| p.map(|c| c * 1e-6));
                let cell_volume: f64 = scale.iter().product();
                for &(xi_cell, wgt) in &gauss {
                    let xi: [f64; 3] = std::array::from_fn(|d| offset[d] + scale[d] * xi_cell[d]);
                    let p = hex27::position(&nodes_um, xi);
                    let dv = hex27::geometry(&nodes_m, xi).det_j * wgt * cell_volume;
                    let st = sol.stress_at(owner, xi).expect("active element");
                    let (sx, sy, sz) = (st[0], st[1], st[2]);
                    let (s1_, s2_) = match g.drawn_axis {
                        Axis::Y => (sy, sx),
                        Axis::X => (sx, sy),
                    };
                    // pC/m^2 from pC/N x Pa.
                    let d3_terms = [
                        g.d31_pc_per_n * s1_,
                        g.d32_pc_per_n * s2_,
                        g.d33_pc_per_n * sz,
                    ];
                    if support_film {
                        // Compressive force (N): the film's mean of the nominal -P_zz over its
                        // area (sigma_zz when linear).
                        let pzz = sol.traction_z_at(owner, xi).expect("active element")[2];
                        let f = -pzz * dv / t_film;
                        if p[1] < 0.5 * g.width_um {
                            s1 += f;
                        } else {
                            s2 += f;
                        }
                    }
                    for (parts, (el, rs)) in terms.iter_mut().zip(g.electrodes.iter().zip(&rects)) {
                        let wanted = match el.side {
                            ElectrodeSide::Middle => floor_film,
                            _ => support_film,
                        };
                        if !wanted {
                            continue;
                        }
                        // Each image holding the point counts: an electrode that is its own
                        // mirror image is solved in part and read in whole.
                        let images = rs
                            .iter()
                            .filter(|r| {
                                p[0] >= r[0] && p[0] <= r[2] && p[1] >= r[1] && p[1] <= r[3]
                            })
                            .count() as f64;
                        if images > 0.0 {
                            let sign = if el.side == ElectrodeSide::Middle {
                                1.0
                            } else {
                                -1.0
                            };
                            for (p, t) in parts.iter_mut().zip(d3_terms) {
                                *p += images * sign * t * dv / t_film;
                            }
                        }
                    }
                }
            }
        }
    }
    // The supports' totals over the whole die: the part solved times its images.
    let images_n = (1 + usize::from(s.mirror_x_um.is_some())) as f64;
    let (s1, s2) = match s.mirror_y_um {
        // One support solved: the other is its mirror image.
        Some(_) => (s1 * images_n, s1 * images_n),
        None => (s1 * images_n, s2 * images_n),
    };
    // Each charge is the sum of its terms (Q = (1/t) integral of D3 dV).
    let charge: Vec<f64> = terms.iter().map(|t| t[0] + t[1] + t[2]).collect();
    let voltage = charge
        .iter()
        .zip(&g.electrodes)
        .map(|(q, e)| q * 1e-12 / g.capacitance_f(e.area_um2) * 1e3)
        .collect();
    // Deflection: -u_z on the plate's mid-plane.
    let mid = lay.plate_mid_um();
    let at = sol
        .displacement_m([at_um.0, at_um.1, mid])
        .map_or(f64::NAN, |u| -u[2] * 1e6);
    let tol = 1e-6 * grid.extent_um();
    // Nodes of active elements only: a merged brick's face holds lattice nodes it does not use.
    let max_defl = (0..pos.len())
        .filter(|&n| (pos[n][2] - mid).abs() < tol)
        .filter(|&n| grid.node_elements(n).any(|e| grid.material(e).is_some()))
        .map(|n| -sol.node_displacement_m(n)[2] * 1e6)
        .fold(f64::NEG_INFINITY, f64::max);
    let silicon = (0..grid.element_count()).filter(|&e| grid.material(e) == Some(SILICON));
    let peak = sol.max_principal_stress(silicon);
    let read_at_um =
        0.5 * critical_distance_um(g.fracture_toughness_mpa_sqrt_m, g.fracture_strength_mpa);
    Ok(SolidReadout {
        charge_pc: charge,
        charge_terms_pc: terms,
        voltage_mv: voltage,
        support1_n: s1,
        support2_n: s2,
        deflection_at_load_um: at,
        max_deflection_um: max_defl,
        max_principal_mpa: peak.as_ref().map_or(f64::NAN, |p| p.stress_pa * 1e-6),
        max_principal_at_um: peak.map_or([f64::NAN; 3], |p| p.position_um),
        stress_averaged_mpa: averaged_stress(s, sol, g, patch_um),
        edge_stress: edge_stresses(g, s, sol, read_at_um)?,
    })
}

/// Squared coupling factor of the film in the 31 mode, k31^2 = d31^2 / (s11^E eps33^T) with
/// s11^E = 1 / E (IEEE Std 176-1987, Eq. 99): the fraction of the film's strain energy the
/// converse effect returns. The solid rung leaves the converse coupling out; its effect on the
/// structure is at most k31^2 times the film's share of the bending stiffness
/// ([`film_bending_share`]).
pub fn coupling_k31_squared(g: &SensorGeometry) -> f64 {
    let d31 = g.d31_pc_per_n * 1e-12;
    d31 * d31 * g.pvdf_e_pa / (crate::units::EPS0_F_PER_M * g.eps_r)
}

/// The film's share of the plate-plus-film bending stiffness: E_f t_f (t/2 + t_f/2)^2 against
/// the plate's D22 = Q22 t^3 / 12 per unit width (parallel-axis theorem, the film a thin layer
/// under the plate).
pub fn film_bending_share(g: &SensorGeometry) -> f64 {
    let (t, tf) = (g.plate_thickness_um * 1e-6, g.film_thickness_um * 1e-6);
    let film = g.pvdf_e_pa / (1.0 - g.pvdf_nu * g.pvdf_nu) * tf * (0.5 * (t + tf)).powi(2);
    let plate = g.material.bending_stiffness(t).d22_nm;
    film / (film + plate)
}
