//! Electrode charges and voltages from a plate solution and the direct support loads.

use serde::Serialize;

use crate::fe::edge_spring;
use crate::fe::{Axis as FeAxis, EdgeSpring, PlateSolution, RectUm};
use crate::process::{Axis, SupportModel};

use super::footing::SupportFooting;
use super::geometry::{ElectrodeSide, SensorGeometry};
use super::scene::DirectLoad;

/// One electrode's reading.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ElectrodeReading {
    pub name: String,
    pub charge_pc: f64,
    pub voltage_mv: f64,
    /// Force through the electrode (support electrodes, thickness mode); positive = compression.
    pub force_n: Option<f64>,
}

/// All electrodes plus the support totals.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Readout {
    pub electrodes: Vec<ElectrodeReading>,
    pub support1_n: f64,
    pub support2_n: f64,
}

/// Reaction group of a support's clamped edge (where its etched wall meets the plate).
pub fn group_for(side: ElectrodeSide) -> &'static str {
    match side {
        ElectrodeSide::Support1 => "support1",
        ElectrodeSide::Support2 => "support2",
        ElectrodeSide::Middle => unreachable!("the middle carries no reaction"),
    }
}

/// Force through an electrode's x-extent: each nodal reaction spread over its tributary length
/// (half-way to its neighbours) and counted by the overlap with [x0, x1], so a node on an
/// electrode edge is shared, not given to one side.
fn edge_force(sol: &PlateSolution, side: ElectrodeSide, x0: f64, x1: f64) -> f64 {
    let mut nodes: Vec<(f64, f64)> = sol
        .nodal_reactions(group_for(side))
        .iter()
        .map(|r| (r.x_um, r.force_n))
        .collect();
    nodes.sort_by(|a, b| a.0.total_cmp(&b.0));
    let n = nodes.len();
    let mut f = 0.0;
    for i in 0..n {
        let lo = if i == 0 {
            nodes[0].0
        } else {
            0.5 * (nodes[i - 1].0 + nodes[i].0)
        };
        let hi = if i + 1 == n {
            nodes[n - 1].0
        } else {
            0.5 * (nodes[i].0 + nodes[i + 1].0)
        };
        if hi <= lo {
            // A lone end node: all of it if it lies inside.
            if nodes[i].0 >= x0 && nodes[i].0 <= x1 {
                f += nodes[i].1;
            }
            continue;
        }
        let overlap = (hi.min(x1) - lo.max(x0)).max(0.0);
        f += nodes[i].1 * overlap / (hi - lo);
    }
    f
}

/// What an island on an elastic footing takes from the support above it.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct FootingIsland {
    /// Force through the island (N, compressive): the foundation pressure integrated.
    pub force_n: f64,
    /// Integral over the island of the support's bottom-face strain across the wall (m^2),
    /// which the film bonded under it follows.
    pub strain_m2: f64,
}

/// [`FootingIsland`] of an electrode: the foundation pressure under the support (Hetenyi's w(s)
/// times k for the plate's w and slope at the clamp line) and the beam's bottom-fibre strain,
/// each integrated over the island's extent from the footing's edge and along the wall (4-point
/// Gauss per mesh segment: w and the slope are cubic along the edge, both linear in them).
pub(super) fn footing_island(
    g: &SensorGeometry,
    ft: &SupportFooting,
    sol: &PlateSolution,
    side: ElectrodeSide,
    e: &super::geometry::ElectrodeArea,
) -> FootingIsland {
    let (y_line, outward, s0, s1) = match side {
        ElectrodeSide::Support1 => {
            let edge = g.etched.support_edge_y_um;
            (g.plate_y0_um, -1.0, edge - e.y1_um, edge - e.y0_um)
        }
        _ => {
            let edge = g.width_um - g.etched.support_edge_y_um;
            (g.plate_y1_um, 1.0, e.y0_um - edge, e.y1_um - edge)
        }
    };
    let mesh = sol.mesh();
    let line = EdgeSpring {
        group: String::new(),
        along: FeAxis::X,
        at_um: y_line,
        from_um: mesh.x_um[0],
        to_um: *mesh.x_um.last().unwrap_or(&0.0),
        outward,
        stiffness: [[0.0; 2]; 2],
        normal_in_plane_pa: None,
        coupled: None,
    };
    let mut out = FootingIsland::default();
    let Ok(segs) = edge_spring::segments(mesh, &line) else {
        return out;
    };
    const G: [(f64, f64); 4] = [
        (-0.861_136_311_594_052_6, 0.347_854_845_137_453_85),
        (-0.339_981_043_584_856_26, 0.652_145_154_862_546_2),
        (0.339_981_043_584_856_26, 0.652_145_154_862_546_2),
        (0.861_136_311_594_052_6, 0.347_854_845_137_453_85),
    ];
    for seg in &segs {
        let (a, b) = (seg.t_um[0].max(e.x0_um), seg.t_um[1].min(e.x1_um));
        if b <= a {
            continue;
        }
        for (xi, wq) in G {
            let x = 0.5 * (a + b) + 0.5 * (b - a) * xi;
            if let Some((w, t)) = edge_spring::edge_state(&line, &segs, sol.dofs(), x) {
                let dx = 0.5 * (b - a) * 1e-6 * wq;
                out.force_n += dx * ft.force_per_length(w, t, s0, s1);
                out.strain_m2 += dx * ft.bottom_strain_integral_m(w, t, s0, s1);
            }
        }
    }
    out
}

/// Charge of a support island on the elastic footing (pC, the plate rungs' polarity: d33 times
/// the compressive force). The film is bonded between the support and the base, so it follows
/// the support's bottom face in plane (the solid rung shows it: its in-plane strain matches the
/// silicon's above it): across the wall the footing beam's bottom strain e, along it none
/// (cylindrical bending), and through it the foundation pressure p. Hooke's law for the
/// isotropic film with eps_along = 0, eps_across = e, s3 = -p gives s_across = E' e - c p,
/// s_along = nu E' e - c p (E' = E / (1 - nu^2), c = nu / (1 - nu)). With D3 = d31 s1 +
/// d32 s2 + d33 s3 (IEEE Std 176) and the island's compressive force F, Q = (d33 + c (d31 +
/// d32)) F - (d_across + nu d_along) E' integral of e dA.
fn footing_charge_pc(g: &SensorGeometry, island: FootingIsland, direct_n: f64) -> f64 {
    let nu = g.pvdf_nu;
    let e_plane = g.pvdf_e_pa / (1.0 - nu * nu);
    let c = nu / (1.0 - nu);
    // The film's axis 1 is the drawn axis; the walls run along x.
    let (across, along) = match g.drawn_axis {
        Axis::Y => (g.d31_pc_per_n, g.d32_pc_per_n),
        Axis::X => (g.d32_pc_per_n, g.d31_pc_per_n),
    };
    let d33_constrained = g.d33_pc_per_n + c * (g.d31_pc_per_n + g.d32_pc_per_n);
    d33_constrained * (island.force_n + direct_n)
        - (across + nu * along) * e_plane * island.strain_m2
}

/// Thickness mode Q = d33 F for support electrodes on the clamp (fe-validation.md, piezo
/// relations; paper 001 Eq. 6), the bonded film's [`footing_charge_pc`] on the elastic footing;
/// extension mode Q = integral of (d31 s1 + d32 s2) dA over each middle electrode with s the
/// plane-stress PVDF stress from the strain at the film's mid-plane, half a film thickness under
/// the plate's bottom surface (fe-validation.md takes the surface itself; the solid rung reads
/// the film's own stresses and shows the film's mean strain is the one read, 27 % more on the
/// bundled plate); V = Q / C, C = eps0 eps_r A / t.
pub fn read(g: &SensorGeometry, sol: Option<&PlateSolution>, direct: &[DirectLoad]) -> Readout {
    let mut out = Vec::new();
    let (mut s1, mut s2) = (0.0, 0.0);
    // Reactions of edge segments outside every electrode still count towards the support totals.
    if let Some(sol) = sol {
        for r in sol.reactions() {
            if r.group.starts_with("support1") {
                s1 += r.force_n;
            } else if r.group.starts_with("support2") {
                s2 += r.force_n;
            }
        }
    }
    for d in direct {
        match d.side {
            ElectrodeSide::Support1 => s1 += d.force_n,
            ElectrodeSide::Support2 => s2 += d.force_n,
            ElectrodeSide::Middle => {}
        }
    }
    let ep = g.pvdf_e_pa / (1.0 - g.pvdf_nu * g.pvdf_nu);
    let footing = (g.support_model == SupportModel::ElasticFooting).then(|| SupportFooting::new(g));
    for e in &g.electrodes {
        let c_f = g.capacitance_f(e.area_um2);
        let (charge_pc, force_n) = match e.side {
            ElectrodeSide::Middle => {
                let (ix, iy) = sol
                    .map(|s| {
                        s.integrate_strain_below(
                            RectUm {
                                x0_um: e.x0_um,
                                y0_um: e.y0_um,
                                x1_um: e.x1_um,
                                y1_um: e.y1_um,
                            },
                            0.5 * g.film_thickness_um,
                        )
                    })
                    .unwrap_or((0.0, 0.0));
                // Integrated PVDF stresses (N): s_x = E'(e_x + nu e_y), s_y = E'(e_y + nu e_x).
                let sx = ep * (ix + g.pvdf_nu * iy);
                let sy = ep * (iy + g.pvdf_nu * ix);
                let (s1_, s2_) = match g.drawn_axis {
                    Axis::Y => (sy, sx),
                    Axis::X => (sx, sy),
                };
                (g.d31_pc_per_n * s1_ + g.d32_pc_per_n * s2_, None)
            }
            side => {
                let island = footing.as_ref().map(|ft| {
                    sol.map_or_else(FootingIsland::default, |s| {
                        footing_island(g, ft, s, side, e)
                    })
                });
                let mut f = match island {
                    Some(i) => i.force_n,
                    None => sol.map_or(0.0, |s| edge_force(s, side, e.x0_um, e.x1_um)),
                };
                let mut direct_n = 0.0;
                for d in direct.iter().filter(|d| d.side == side) {
                    let overlap = (d.x1_um.min(e.x1_um) - d.x0_um.max(e.x0_um)).max(0.0);
                    let span = d.x1_um - d.x0_um;
                    direct_n += if span > 0.0 {
                        d.force_n * overlap / span
                    } else if d.x0_um >= e.x0_um && d.x0_um <= e.x1_um {
                        d.force_n
                    } else {
                        0.0
                    };
                }
                f += direct_n;
                let charge = match island {
                    Some(i) => footing_charge_pc(g, i, direct_n),
                    None => g.d33_pc_per_n * f,
                };
                (charge, Some(f))
            }
        };
        out.push(ElectrodeReading {
            name: e.name.clone(),
            charge_pc,
            voltage_mv: charge_pc * 1e-12 / c_f * 1e3,
            force_n,
        });
    }
    Readout {
        electrodes: out,
        support1_n: s1,
        support2_n: s2,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn geometry() -> SensorGeometry {
        crate::sensor::geometry::bundled(&[])
    }

    /// The footing island's charge against Hooke's law solved numerically: the film's in-plane
    /// stresses from its compliance with eps_along = 0, eps_across = e and s3 = -p given, then
    /// Q = -(d31 s1 + d32 s2 + d33 s3) A with 1 the drawn axis, for both drawn axes.
    #[test]
    fn the_footing_charge_is_the_laterally_bonded_films_d3() {
        let mut g = geometry();
        let (e_pa, nu) = (g.pvdf_e_pa, g.pvdf_nu);
        let area_m2 = 2.0e-6;
        for axis in [Axis::Y, Axis::X] {
            g.drawn_axis = axis;
            for (e, p, direct) in [(-3e-5, 2e3, 0.0), (1e-5, -4e4, 0.01), (0.0, 1e4, -0.05)] {
                // Compliance rows of the in-plane strains, unknowns (s_along, s_across), s3 known.
                let s3 = -p - direct / area_m2;
                let (r_along, r_across) = (nu * s3 / e_pa, e + nu * s3 / e_pa);
                let a = [[1.0 / e_pa, -nu / e_pa], [-nu / e_pa, 1.0 / e_pa]];
                let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
                let s_along = (r_along * a[1][1] - a[0][1] * r_across) / det;
                let s_across = (a[0][0] * r_across - a[1][0] * r_along) / det;
                let (s1, s2) = match axis {
                    Axis::Y => (s_across, s_along),
                    Axis::X => (s_along, s_across),
                };
                let d3 = g.d31_pc_per_n * s1 + g.d32_pc_per_n * s2 + g.d33_pc_per_n * s3;
                let want = -d3 * area_m2;
                let island = FootingIsland {
                    force_n: p * area_m2,
                    strain_m2: e * area_m2,
                };
                let got = footing_charge_pc(&g, island, direct);
                assert!(
                    (got - want).abs() < 1e-9 * want.abs(),
                    "{axis:?} e {e} p {p}: {got} vs {want}"
                );
            }
        }
        // The bonded film reads a third of the free film's d33 under pure compression.
        g.drawn_axis = Axis::Y;
        let q = footing_charge_pc(&g, FootingIsland::default(), 1.0);
        assert!(q.abs() < 0.5 * g.d33_pc_per_n.abs(), "{q}");
    }
}
