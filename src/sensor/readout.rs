//! Electrode charges and voltages from a plate solution and the direct support loads.

use serde::Serialize;

use crate::fe::edge_spring;
use crate::fe::{Axis as FeAxis, EdgeSpring, PlateSolution, RectUm};
use crate::process::{Axis, SupportModel};

use super::footing::SupportFooting;
use super::geometry::{ElectrodeSide, SensorGeometry};
use super::scene::DirectLoad;
use super::support_section::{SupportSection, SupportSections};

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

/// The plate's state on a support's clamp line at one quadrature point of an island's extent.
struct EdgeSample {
    /// Where along the wall (um).
    x_um: f64,
    /// Quadrature weight: the length it stands for (m).
    dx_m: f64,
    /// w (m) and the slope pointing into the support, as [`EdgeSpring`] takes them.
    w: f64,
    theta: f64,
    /// The mid-plane's in-plane displacement towards the span (m), on a solution that has one.
    u: Option<f64>,
}

/// The clamp line's state at 4-point Gauss points per mesh segment over the island's extent
/// along the wall (w and the slope are cubic along the edge, the in-plane displacement linear).
fn edge_samples(
    g: &SensorGeometry,
    sol: &PlateSolution,
    side: ElectrodeSide,
    e: &super::geometry::ElectrodeArea,
) -> Vec<EdgeSample> {
    let (y_line, outward) = match side {
        ElectrodeSide::Support1 => (g.plate_y0_um, -1.0),
        _ => (g.plate_y1_um, 1.0),
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
        along_wall: None,
    };
    let mut out = Vec::new();
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
            if let Some((w, theta)) = edge_spring::edge_state(&line, &segs, sol.dofs(), x) {
                // v at the segment's nodes, linear between them; towards the span is -outward.
                let u = sol.membrane().map(|uv| {
                    let s = (x - seg.t_um[0]) / (seg.t_um[1] - seg.t_um[0]);
                    let [na, nb] = seg.nodes;
                    -outward * ((1.0 - s) * uv[2 * na + 1] + s * uv[2 * nb + 1])
                });
                out.push(EdgeSample {
                    x_um: x,
                    dx_m: 0.5 * (b - a) * 1e-6 * wq,
                    w,
                    theta,
                    u,
                });
            }
        }
    }
    out
}

/// [`FootingIsland`] of an electrode: the foundation pressure under the support (Hetenyi's w(s)
/// times k for the plate's w and slope at the clamp line) and the beam's bottom-fibre strain,
/// each integrated over the island's extent from the footing's edge and along the wall.
pub(super) fn footing_island(
    g: &SensorGeometry,
    ft: &SupportFooting,
    sol: &PlateSolution,
    side: ElectrodeSide,
    e: &super::geometry::ElectrodeArea,
) -> FootingIsland {
    let (s0, s1) = match side {
        ElectrodeSide::Support1 => {
            let edge = g.etched.support_edge_y_um;
            (edge - e.y1_um, edge - e.y0_um)
        }
        _ => {
            let edge = g.width_um - g.etched.support_edge_y_um;
            (e.y0_um - edge, e.y1_um - edge)
        }
    };
    let mut out = FootingIsland::default();
    for p in edge_samples(g, sol, side, e) {
        out.force_n += p.dx_m * ft.force_per_length(p.w, p.theta, s0, s1);
        out.strain_m2 += p.dx_m * ft.bottom_strain_integral_m(p.w, p.theta, s0, s1);
    }
    out
}

/// Charge (pC) of a support island under the solid section: the film charge per unit
/// clamp-line motion over the island's width ([`SupportSection::island_charge`]) of the section
/// at each point of the wall (a tooth standing on the support or not) times the plate's (w,
/// theta, u) there, integrated over the island's length. The in-plane displacement is the
/// plate's own where its large-deflection solve held the edge on the section's coupled spring
/// (`held_in_plane`); elsewhere the plate had the section's condensed springs, membrane force
/// zero at the edge, and u is what that leaves: -(k_uw w + k_ut theta) / k_uu. Loads straight
/// onto the support add the laterally bonded film's d33 (as the footing's).
fn section_island_charge_pc(
    g: &SensorGeometry,
    sections: &SupportSections,
    sol: &PlateSolution,
    side: ElectrodeSide,
    e: &super::geometry::ElectrodeArea,
    held_in_plane: bool,
) -> f64 {
    let (y0, y1, index) = match side {
        ElectrodeSide::Support1 => (e.y0_um, e.y1_um, 0),
        _ => (g.width_um - e.y1_um, g.width_um - e.y0_um, 1),
    };
    let charge = |s: &SupportSection| s.island_charge(y0, y1);
    let (bare, tooth) = (
        charge(&sections.bare),
        sections.under_tooth.as_ref().map(charge),
    );
    edge_samples(g, sol, side, e)
        .into_iter()
        .map(|p| {
            let s = sections.at(index, p.x_um);
            let r = match (&sections.under_tooth, tooth) {
                (Some(t), Some(r)) if std::ptr::eq(s, t) => r,
                _ => bare,
            };
            let k = s.stiffness;
            let u = match p.u {
                Some(u) if held_in_plane => u,
                _ => -(k[2][0] * p.w + k[2][1] * p.theta) / k[2][2],
            };
            p.dx_m * (r[0] * p.w + r[1] * p.theta + r[2] * u)
        })
        .sum()
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
    // The film's axis 1 is the drawn axis; the walls run along x.
    let (across, along) = match g.drawn_axis {
        Axis::Y => (g.d31_pc_per_n, g.d32_pc_per_n),
        Axis::X => (g.d32_pc_per_n, g.d31_pc_per_n),
    };
    bonded_d33(g) * (island.force_n + direct_n) - (across + nu * along) * e_plane * island.strain_m2
}

/// The film's d33 when it is bonded in plane and pressed through its thickness (pC/N): d33 + nu /
/// (1 - nu) (d31 + d32), from s_in-plane = -c p with c = nu / (1 - nu) ([`footing_charge_pc`]).
fn bonded_d33(g: &SensorGeometry) -> f64 {
    let c = g.pvdf_nu / (1.0 - g.pvdf_nu);
    g.d33_pc_per_n + c * (g.d31_pc_per_n + g.d32_pc_per_n)
}

/// Thickness mode Q = d33 F for support electrodes on the clamp (fe-validation.md, piezo
/// relations; paper 001 Eq. 6), the bonded film's [`footing_charge_pc`] on the elastic footing;
/// extension mode Q = integral of (d31 s1 + d32 s2) dA over each middle electrode with s the
/// plane-stress PVDF stress from the strain at the film's mid-plane, half a film thickness under
/// the plate's bottom surface (fe-validation.md takes the surface itself; the solid rung reads
/// the film's own stresses and shows the film's mean strain is the one read, 27 % more on the
/// bundled plate); V = Q / C, C = eps0 eps_r A / t.
pub fn read(
    g: &SensorGeometry,
    sol: Option<&PlateSolution>,
    direct: &[DirectLoad],
    held_in_plane: bool,
) -> Readout {
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
    let section = match (&g.support_model, &g.support_section) {
        (SupportModel::SolidSection, Some(Ok(s))) => Some(s),
        _ => None,
    };
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
                let charge = match (island, section, sol) {
                    (Some(i), _, _) => footing_charge_pc(g, i, direct_n),
                    (None, Some(sec), Some(s)) => {
                        section_island_charge_pc(g, sec, s, side, e, held_in_plane)
                            + bonded_d33(g) * direct_n
                    }
                    _ => g.d33_pc_per_n * f,
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
