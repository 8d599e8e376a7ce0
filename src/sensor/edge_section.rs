//! The teeth's base-edge stress as the plate rungs answer it (issue 16, item 7). Plate theory
//! knows the moments and membrane forces at a tooth's base edge, not the stress its sharp {111}
//! corner concentrates there ([`super::edge_stress`]: singular, judged at the critical distance
//! L / 2). A section of that edge, solved once per design, gives the corner's stress at L / 2 per
//! unit of each plate resultant; a plate answer's stress at an edge point is their superposition
//! (the section and the corner submodel are linear).
//!
//! The section is a one-brick slice of the 3-D solid (x along the edge): the plate of thickness t
//! from the tooth's centre (a symmetry plane) under the tooth's frustum (height h, {111} sidewall
//! of run-out ro) to [`STREET_THICKNESSES`] t into the street, graded into the corner. Four unit
//! drives, in plate theory's terms at the edge on the street side:
//! - the bending moment M_n and membrane force N_n normal to the edge: pressures on the street's
//!   end face, u_x held on the slice's faces (no strain along the edge);
//! - the curvature kappa_t and stretch eps_t along the edge: u_x prescribed on a slice face
//!   (generalised plane strain), the end face free.
//!
//! The end's pressure distribution does not matter at the corner (Saint-Venant: it decays over
//! about t). Left out, and so part of the section's model error that `--verify-solid` measures:
//! the twisting moment and in-plane shear along the edge (anti-plane modes, a weaker
//! singularity), the shear force's own moment gradient over the corner region, the edge's ends
//! (the tooth's vertices), and what lies beyond the section (the channel wall under a tooth
//! that stands over it, the next tooth).

use std::sync::Mutex;

use rayon::prelude::*;
use serde::Serialize;

use crate::fe::convergence::ThreeMesh;
use crate::fe::solid::corner::{
    solve_corner, CornerFrame, CornerMesh, CornerSector, DriverKinematics, SectionPatterns,
    OCTAVES_INSIDE,
};
use crate::fe::solid::{
    merged_lines, principal_stresses_pa, Axis3, Constraint, FaceRect, HexGrid, NodeSet, Outward,
    Prescribed, SolidLoad, SolidProblem, SolidSolution,
};
use crate::fe::{FeError, FeResult, PlateSolution};

use super::edge_stress::{critical_distance_um, tooth_base_corner};
use super::geometry::SensorGeometry;

/// The street's length in the section, in plate thicknesses from the base edge to the loaded
/// end: the end's load distribution has decayed well before the corner (Saint-Venant, ~t).
pub const STREET_THICKNESSES: f64 = 6.0;
/// Smallest element at the corner as a fraction of the submodel's radius: the section answered
/// with, and the two coarser ones (each twice the last) of its three-mesh estimate. Measured on
/// the bundled design's unit moment with 8 rings: 1/8, 1/16, 1/32 read 12.068, 12.086, 12.093
/// GPa per N m/m (order 1.4, limit ~12.098); the answer, 1/16 with 4 rings, 12.082 (0.13 % low).
const CORNER_ELEMENT_FINE: f64 = 1.0 / 16.0;
const CORNER_ELEMENT_MEDIUM: f64 = 1.0 / 8.0;
const CORNER_ELEMENT_COARSE: f64 = 1.0 / 4.0;
/// Growth of the element sizes away from the corner, and the largest element in thicknesses.
const GROWTH: f64 = 1.5;
const LARGEST_THICKNESSES: f64 = 1.0;
/// Rings per octave of the corner submodels (as the solid rung's, `edge_stress`), and the half
/// and double densities of its three-mesh estimate (2, 4, 8 read 12.039, 12.064, 12.068 GPa per
/// N m/m on the 1/8 section: 4 is about 0.04 % from the rings' limit).
const RINGS_FINE: usize = 4;
const RINGS_COARSE: usize = 2;
const RINGS_FINER: usize = 8;

/// The section's answer per unit drive, and its estimate.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EdgeSection {
    /// L / 2, where the stress is read (um).
    pub read_at_um: f64,
    /// The corner submodel's radius (um).
    pub radius_um: f64,
    /// The narrowest tooth's half base, its centre to its base edge (um); the section keeps at
    /// most [`STREET_THICKNESSES`] plate thicknesses of it.
    pub tooth_half_base_um: f64,
    /// The largest principal stress at L / 2 for each unit drive alone, MPa per: N m/m of M_n,
    /// N/m of N_n, 1/m of kappa_t, unit eps_t (signed: the drive's sign that opens the corner
    /// is the positive one).
    pub unit_mpa: [f64; 4],
    /// The unit moment's stress's estimate relative to it: the three-mesh estimate of the
    /// section over three gradings plus that of the corner submodel's ring density (half and
    /// double), [`ThreeMesh`].
    pub error_rel: f64,
    /// Stress tensors (Voigt, Pa) on the read-out ring per unit drive, in the same order.
    #[serde(skip)]
    ring: [Vec<[f64; 6]>; 4],
    /// Per unit drive, the largest |principal stress| on the ring (Pa): sum |drive_i| norm_i
    /// bounds a drive's stress from above.
    #[serde(skip)]
    norm_pa: [f64; 4],
}

/// The plate's drives at one point of a base edge (street side): M_n (N m/m, sagging positive),
/// N_n (N/m, tension positive), kappa_t (1/m, sagging positive), eps_t.
pub type EdgeDrive = [f64; 4];

impl EdgeSection {
    /// An upper bound of [`Self::stress_pa`] (the largest principal stress of a sum is at most
    /// the sum of the parts' spectral radii).
    pub fn bound_pa(&self, drive: EdgeDrive) -> f64 {
        (0..4).map(|d| drive[d].abs() * self.norm_pa[d]).sum()
    }

    /// The corner's largest principal stress (Pa) at L / 2 under `drive` (superposition of the
    /// unit drives' stress tensors, largest principal over the ring).
    pub fn stress_pa(&self, drive: EdgeDrive) -> f64 {
        let n = self.ring[0].len();
        (0..n)
            .map(|i| {
                let s: [f64; 6] = std::array::from_fn(|c| {
                    (0..4).map(|d| drive[d] * self.ring[d][i][c]).sum::<f64>()
                });
                principal_stresses_pa(&s)[0]
            })
            .fold(f64::NEG_INFINITY, f64::max)
    }
}

/// Sections solved in this process, by their inputs' bits (a sweep or a study evaluates the same
/// design many times).
type SectionKey = Vec<u64>;
static SECTIONS: Mutex<Vec<(SectionKey, EdgeSection)>> = Mutex::new(Vec::new());
/// Sections kept at most.
const SECTIONS_KEPT: usize = 16;

/// The tooth base's corner (sectors, submodel radius), the narrowest tooth's half base (um) and
/// L / 2 (um), when the design has teeth and the corner's submodel fits around L / 2.
fn corner_of(g: &SensorGeometry) -> Option<(Vec<CornerSector>, f64, f64, f64)> {
    let (sectors, radius) = tooth_base_corner(g)?;
    let et = &g.etched;
    // The narrowest tooth's half base: the least silicon behind the corner.
    let half_top = et
        .tooth_tops_um
        .iter()
        .map(|tt| 0.5 * (tt[2] - tt[0]).min(tt[3] - tt[1]))
        .fold(f64::INFINITY, f64::min);
    let read = 0.5 * critical_distance_um(g.fracture_toughness_mpa_sqrt_m, g.fracture_strength_mpa);
    (half_top > 0.0 && radius > 8.0 * read).then_some((
        sectors,
        radius,
        half_top + et.tooth_run_out_um,
        read,
    ))
}

/// Mesh lines through the tooth-base stations [`plate_tooth_base_stress`] reads (um; x lines,
/// y lines): each tooth's base edges (where the stations stand) and the end stations on each
/// edge (two radii plus a run-out in from its base vertices). Off a line, a station's place
/// inside its element changes with every level and the three-mesh estimate reads it
/// optimistically: on the bundled design, clamped, the governing end station read 1793.1 MPa on
/// nine levels with an estimate of 0.70 %, where with the lines it rises from 1765.6 to 1806.7
/// MPa over splits 2-6 and stays within 0.25 % of that to split 16 (1802.8); on the support
/// sections its sequence (1551-1741 MPa over splits 1-32) was not monotone and did not converge
/// in nine levels.
/// Empty where the section does not [`applies`].
pub fn station_lines_um(g: &SensorGeometry) -> (Vec<f64>, Vec<f64>) {
    let Some((_, radius, _, _)) = corner_of(g) else {
        return (Vec::new(), Vec::new());
    };
    let ro = g.etched.tooth_run_out_um;
    let margin = 2.0 * radius + ro;
    let (mut xs, mut ys) = (Vec::new(), Vec::new());
    for tt in &g.etched.tooth_tops_um {
        let (bx0, by0, bx1, by1) = (tt[0] - ro, tt[1] - ro, tt[2] + ro, tt[3] + ro);
        for (lo, hi, lines) in [(bx0, bx1, &mut xs), (by0, by1, &mut ys)] {
            lines.extend([lo, hi]);
            if hi - lo >= 2.0 * margin {
                lines.extend([lo + margin, hi - margin]);
            }
        }
    }
    (xs, ys)
}

/// True if the plate rungs answer the teeth's base-edge stress for design `g` (it has teeth,
/// and their corner is wider than the critical distance).
pub fn applies(g: &SensorGeometry) -> bool {
    corner_of(g).is_some()
}

/// The tooth-base section of design `g`; None where it does not [`applies`].
pub fn tooth_base_section(g: &SensorGeometry) -> FeResult<Option<EdgeSection>> {
    let Some((sectors, radius, b, read)) = corner_of(g) else {
        return Ok(None);
    };
    let et = &g.etched;
    let (t, h, ro) = (
        g.plate_thickness_um,
        et.tooth_height_um,
        et.tooth_run_out_um,
    );
    let material = sectors[0].material;
    let key: SectionKey = [t, h, ro, b, read]
        .into_iter()
        .chain(material.c_pa.iter().flatten().copied())
        .map(f64::to_bits)
        .collect();
    if let Some((_, s)) = SECTIONS
        .lock()
        .ok()
        .and_then(|v| v.iter().find(|(k, _)| *k == key).cloned())
    {
        return Ok(Some(s));
    }
    let geo = Slice {
        t,
        h,
        ro,
        c: b.min(STREET_THICKNESSES * t),
        radius,
    };
    let frame = geo.frame();
    let patterns = SectionPatterns::default();
    let corner = |sol: &SolidSolution, rings: usize| -> FeResult<Vec<[f64; 6]>> {
        let field = |p: [f64; 3]| sol.displacement_m(p);
        let mesh = CornerMesh {
            radius_um: radius,
            read_at_um: read,
            rings_per_octave: rings,
            octaves_inside: OCTAVES_INSIDE,
        };
        let c = solve_corner(
            frame,
            &sectors,
            mesh,
            DriverKinematics::Linear,
            &field,
            &patterns,
        )?;
        let ring = c
            .ring_at(read)
            .expect("the mesh places a ring at the read-out");
        Ok(c.stresses_on_ring(ring, |_| true, &field)?
            .into_iter()
            .map(|(_, s)| s)
            .collect())
    };
    let mut slices = geo.solve(CORNER_ELEMENT_FINE, material, true)?;
    slices.extend(geo.solve(CORNER_ELEMENT_MEDIUM, material, false)?);
    slices.extend(geo.solve(CORNER_ELEMENT_COARSE, material, false)?);
    // The four drives; the moment at half and at twice the rings; the moment on the medium and
    // the coarse section.
    let jobs = vec![
        (0, RINGS_FINE),
        (1, RINGS_FINE),
        (2, RINGS_FINE),
        (3, RINGS_FINE),
        (0, RINGS_COARSE),
        (0, RINGS_FINER),
        (4, RINGS_FINE),
        (5, RINGS_FINE),
    ];
    let mut rings = jobs
        .into_par_iter()
        .map(|(k, n)| corner(&slices[k], n))
        .collect::<FeResult<Vec<_>>>()?;
    let mut next = || rings.pop().expect("eight jobs");
    let (coarse_slice, medium_slice, finer_rings, coarse_rings) = (next(), next(), next(), next());
    let fine = rings;
    // The drive's stress with the sign that opens the corner: the larger of the drive's and its
    // opposite's largest principal stress, signed by which.
    let opening = |ring: &Vec<[f64; 6]>| {
        let peak = |sign: f64| {
            ring.iter()
                .map(|s| principal_stresses_pa(&s.map(|v| sign * v))[0])
                .fold(f64::NEG_INFINITY, f64::max)
        };
        let (up, down) = (peak(1.0), peak(-1.0));
        if up >= down {
            up
        } else {
            -down
        }
    };
    let unit_pa: [f64; 4] = std::array::from_fn(|k| opening(&fine[k]));
    let m_fine = unit_pa[0];
    let by_grading = ThreeMesh::new(
        opening(&coarse_slice),
        opening(&medium_slice),
        m_fine,
        2.0,
        2.0,
    );
    let by_rings = ThreeMesh::new(
        opening(&coarse_rings),
        m_fine,
        opening(&finer_rings),
        2.0,
        2.0,
    );
    let error_rel =
        (by_grading.fine_error() + by_rings.error_of(m_fine)) / m_fine.abs().max(f64::MIN_POSITIVE);
    if !(m_fine.is_finite() && error_rel.is_finite()) {
        return Err(FeError::SolidInput {
            detail: "the tooth-base section gave a non-finite stress".into(),
            hint: "check the plate thickness, the tooth height and the run-out",
        });
    }
    let section = EdgeSection {
        read_at_um: read,
        radius_um: radius,
        tooth_half_base_um: b,
        unit_mpa: unit_pa.map(|v| v * 1e-6),
        error_rel,
        // max(|s1|, |s3|) = max(s1, -s3): the larger of the drive's and its opposite's peak.
        norm_pa: unit_pa.map(f64::abs),
        ring: fine.try_into().expect("four drives"),
    };
    if let Ok(mut v) = SECTIONS.lock() {
        if v.len() >= SECTIONS_KEPT {
            v.remove(0);
        }
        v.push((key, section.clone()));
    }
    Ok(Some(section))
}

/// The section's geometry (um): plate t, tooth h with run-out ro, the base edge at y = c (the
/// tooth's centre, or a symmetry plane [`STREET_THICKNESSES`] t inside a wider tooth, at y = 0:
/// the thick part carries the moment as a beam there), the corner submodel's radius.
struct Slice {
    t: f64,
    h: f64,
    ro: f64,
    c: f64,
    radius: f64,
}

/// Lines from `from` to `to` graded from `h0` by [`GROWTH`] up to `h_max`.
fn graded(from: f64, to: f64, h0: f64, h_max: f64) -> Vec<f64> {
    crate::fe::solid::graded_lines(from, to, h0, GROWTH, h_max)
}

impl Slice {
    fn width(&self) -> f64 {
        self.radius
    }
    fn end(&self) -> f64 {
        self.c + STREET_THICKNESSES * self.t
    }
    /// The corner's frame: the base edge at mid-slice, s into the tooth (-y), z up, t along x.
    fn frame(&self) -> CornerFrame {
        CornerFrame {
            origin_um: [0.5 * self.width(), self.c, self.t],
            e_s: [0.0, -1.0, 0.0],
            e_z: [0.0, 0.0, 1.0],
            e_t: [1.0, 0.0, 0.0],
        }
    }

    /// The slice's solutions for the four unit drives (`all`), or for the moment alone.
    fn solve(
        &self,
        corner_element: f64,
        silicon: crate::fe::solid::Elasticity,
        all: bool,
    ) -> FeResult<Vec<SolidSolution>> {
        let (t, h, b, w) = (self.t, self.h, self.c, self.width());
        let h0 = corner_element * self.radius;
        let h_max = LARGEST_THICKNESSES * t;
        let ys =
            merged_lines([graded(b, 0.0, h0, h_max), graded(b, self.end(), h0, h_max)].concat());
        let zm = 0.5 * t;
        let zs = merged_lines(
            [
                graded(t, 0.0, h0, h_max),
                vec![zm],
                graded(t, t + h, h0, h_max),
            ]
            .concat(),
        );
        let mut grid = HexGrid::new(&[0.0, w], &ys, &zs)?;
        grid.assign(|[_, y, z]| (z < t || y < b).then_some(0));
        // The frustum: its base edge (y = b at the plate's top) moves to the top edge (b - ro).
        let (ro, top) = (self.ro, t + h);
        let grid = grid.with_map(std::sync::Arc::new(move |[x, y, z]: [f64; 3]| {
            if z > t && y > 0.0 {
                let s = (z - t) / (top - t);
                // Inside the tooth the lines compress towards the centre, the street's stretch.
                // (The street's nodes there belong to void elements only: shifted with the edge.)
                let mapped = if y <= b { y * (b - ro) / b } else { y - ro };
                [x, y + s * (mapped - y), z]
            } else {
                [x, y, z]
            }
        }));
        let held = |group: &str, at_um: f64| Constraint::symmetry(group, Axis3::X, at_um);
        let pin = Constraint {
            group: "pin".into(),
            nodes: NodeSet::Box {
                min_um: [0.0, 0.0, zm],
                max_um: [0.0, 0.0, zm],
            },
            fixed: [false, false, true],
            value: Prescribed::Zero,
        };
        let centre = Constraint::symmetry("centre", Axis3::Y, 0.0);
        let base = |grid: HexGrid| {
            let mut p = SolidProblem::new(grid, vec![silicon]);
            p.constraints.push(held("x0", 0.0));
            p.constraints.push(centre.clone());
            p.constraints.push(pin.clone());
            p
        };
        // M_n = 1 N m/m and N_n = 1 N/m on the end face, u_x held on both faces.
        let mut p0 = base(grid.clone());
        p0.constraints.push(held("x1", w));
        let bands: Vec<(f64, f64)> = zs
            .windows(2)
            .filter(|z| z[1] <= t + 1e-9)
            .map(|z| (z[0], z[1]))
            .collect();
        let second: f64 = bands
            .iter()
            .map(|&(a, c)| (c - a) * 1e-6 * ((0.5 * (a + c) - zm) * 1e-6).powi(2))
            .sum();
        let face = |a: f64, c: f64| FaceRect {
            axis: Axis3::Y,
            at_um: self.end(),
            outward: Outward::Plus,
            from_um: [0.0, a],
            to_um: [w, c],
        };
        p0.load_cases.push(
            bands
                .iter()
                .map(|&(a, c)| SolidLoad::Pressure {
                    face: face(a, c),
                    pressure_pa: (0.5 * (a + c) - zm) * 1e-6 / second,
                })
                .collect(),
        );
        if !all {
            return p0.solve();
        }
        p0.load_cases.push(
            bands
                .iter()
                .map(|&(a, c)| SolidLoad::Pressure {
                    face: face(a, c),
                    pressure_pa: -1.0 / (t * 1e-6),
                })
                .collect(),
        );
        let mut out = p0.solve()?;
        // kappa_t = 1/m (eps_xx = -kappa (z - zm)) and eps_t = 1 along the edge (linear: any
        // size): u_x prescribed on the face x = w.
        let wm = w * 1e-6;
        for (g_xz, u0) in [(-wm, wm * zm * 1e-6), (0.0, wm)] {
            let mut p = base(grid.clone());
            p.constraints.push(Constraint {
                group: "x1".into(),
                nodes: NodeSet::Plane {
                    axis: Axis3::X,
                    at_um: w,
                },
                fixed: [true, false, false],
                value: Prescribed::Linear {
                    u0_m: [u0, 0.0, 0.0],
                    gradient: [[0.0, 0.0, g_xz], [0.0; 3], [0.0; 3]],
                },
            });
            p.load_cases.push(Vec::new());
            out.extend(p.solve()?);
        }
        Ok(out)
    }
}

/// Plate thicknesses the stations keep clear of where the support's section changes along a
/// wall (`support_model: solid_section`, at the ends of a tooth standing on the support): the
/// plate's edge springs jump there, a plate-theory singularity that is not the structure's (its
/// 3-D junction is the solid rung's to judge). Measured on the bundled design's line and
/// pressure scenes: within 3 t of the jump the stations move 1-4 % from level to level down to
/// 125 um meshes, beyond it they agree to 0.3 %.
pub const SECTION_CHANGE_CLEARANCE_THICKNESSES: f64 = 3.0;

/// Where the plate's edge springs change along the walls (um): each support's section pieces'
/// ends on its wall line, the die's ends left out (nothing changes there).
fn section_changes_um(g: &SensorGeometry) -> Vec<[f64; 2]> {
    // A section that failed to solve fails the plate's build before any station is read.
    let Some(Ok(s)) = &g.support_section else {
        return Vec::new();
    };
    let walls = [g.plate_y0_um, g.plate_y1_um];
    s.teeth_x_um
        .iter()
        .zip(walls)
        .flat_map(|(intervals, y)| {
            intervals
                .iter()
                .flatten()
                .filter(|&&x| x > 0.0 && x < g.length_um)
                .map(move |&x| [x, y])
        })
        .collect()
}

/// One station's answer: the stress (Pa) at L / 2 and where (um).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeReading {
    pub stress_pa: f64,
    pub at_um: [f64; 2],
}

/// One station of [`plate_tooth_base_stress`]'s search: an upper bound of its stress (Pa), the
/// plate's drives there, where it is (um) and the tooth (index into the etched tooth tops).
struct Station {
    bound_pa: f64,
    drive: EdgeDrive,
    at_um: [f64; 2],
    tooth: usize,
}

/// Every station of the plate answer on the teeth's base edges, largest bound first (ties by
/// place: the order is deterministic).
fn stations(g: &SensorGeometry, sol: &PlateSolution, section: &EdgeSection) -> Vec<Station> {
    let ro = g.etched.tooth_run_out_um;
    let margin = 2.0 * section.radius_um + ro;
    let r = section.radius_um;
    let nudge = 1e-3 * g.plate_thickness_um;
    let changes = section_changes_um(g);
    let clearance = SECTION_CHANGE_CLEARANCE_THICKNESSES * g.plate_thickness_um;
    let mut out: Vec<Station> = Vec::new();
    let mut visit = |x: f64, y: f64, along_x: bool, tooth: usize| {
        if changes
            .iter()
            .any(|c| (c[0] - x).hypot(c[1] - y) < clearance)
        {
            return;
        }
        let Some(p) = sol.resultants(x, y) else {
            return;
        };
        // Normal n and tangent t: an edge along x has its normal along y.
        let (n, t) = if along_x { (1, 0) } else { (0, 1) };
        let drive = [
            p.moments[n],
            p.membrane_forces[n],
            p.curvature[t],
            p.membrane_strain[t],
        ];
        out.push(Station {
            bound_pa: section.bound_pa(drive),
            drive,
            at_um: [x, y],
            tooth,
        });
    };
    for (tooth, tt) in g.etched.tooth_tops_um.iter().enumerate() {
        let (bx0, by0, bx1, by1) = (tt[0] - ro, tt[1] - ro, tt[2] + ro, tt[3] + ro);
        for (lo, hi, along_x) in [(bx0, bx1, true), (by0, by1, false)] {
            let (a, c) = (lo + margin, hi - margin);
            if c < a {
                continue;
            }
            let steps = (((c - a) / r).ceil() as usize).clamp(1, 256);
            for i in 0..=steps {
                let v = a + (c - a) * i as f64 / steps as f64;
                if along_x {
                    visit(v, by0 - nudge, true, tooth);
                    visit(v, by1 + nudge, true, tooth);
                } else {
                    visit(bx0 - nudge, v, false, tooth);
                    visit(bx1 + nudge, v, false, tooth);
                }
            }
        }
    }
    out.sort_by(|a, b| {
        b.bound_pa
            .total_cmp(&a.bound_pa)
            .then(a.at_um[0].total_cmp(&b.at_um[0]))
            .then(a.at_um[1].total_cmp(&b.at_um[1]))
    });
    out
}

/// The plate answer's largest tooth-base stress at L / 2: every base edge of every tooth in the
/// part solved, at stations one submodel radius apart, the plate's drives read just on the street
/// side of the edge. The stations keep two radii plus a run-out clear of the edge's ends: within
/// a run-out of a base vertex the frustum's hip (two sidewalls meeting) makes the section 3-D,
/// and the plate's step (where it bends as the sidewall) has its corner there, a plate-theory
/// singularity that is not the structure's. What the vertices add is the section's model error,
/// measured against the solid rung. Likewise the stations keep
/// [`SECTION_CHANGE_CLEARANCE_THICKNESSES`] clear of where the support's section changes.
pub fn plate_tooth_base_stress(
    g: &SensorGeometry,
    sol: &PlateSolution,
    section: &EdgeSection,
) -> Option<EdgeReading> {
    let mut best: Option<EdgeReading> = None;
    // The exact stress only where the bound can still win.
    for st in stations(g, sol, section) {
        if best.is_some_and(|b| st.bound_pa <= b.stress_pa) {
            break;
        }
        let s = section.stress_pa(st.drive);
        if best.is_none_or(|b| s > b.stress_pa) {
            best = Some(EdgeReading {
                stress_pa: s,
                at_um: st.at_um,
            });
        }
    }
    best
}

/// Teeth within this fraction of the plate's largest tooth-base stress are the solid rung's
/// candidates for the worst edge \[choice\]: the plate's edge section reads the corner about a
/// fifth low against the graded solid on the bundled design (README), so a tooth the plate puts
/// a quarter below the largest may still be the solid's worst.
pub const HOT_TOOTH_FRACTION: f64 = 0.75;

/// The teeth (indices into the etched tooth tops, ascending) whose largest base-edge stress in
/// the plate answer is at least [`HOT_TOOTH_FRACTION`] of the largest: where the solid rung
/// grades its mesh by default.
pub fn hot_teeth(g: &SensorGeometry, sol: &PlateSolution, section: &EdgeSection) -> Vec<usize> {
    let all = stations(g, sol, section);
    let mut best = 0f64;
    let mut by_tooth = vec![0f64; g.etched.tooth_tops_um.len()];
    for st in &all {
        // Bounds fall: once one is under the fraction of the largest, no later station counts.
        if st.bound_pa < HOT_TOOTH_FRACTION * best {
            break;
        }
        let s = section.stress_pa(st.drive);
        best = best.max(s);
        by_tooth[st.tooth] = by_tooth[st.tooth].max(s);
    }
    (0..by_tooth.len())
        .filter(|&i| best > 0.0 && by_tooth[i] >= HOT_TOOTH_FRACTION * best)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::solid::corner::tooth_base_exponent;
    use crate::sensor::solid_mesh::silicon_elasticity;

    use crate::sensor::geometry::bundled as geometry;

    #[test]
    fn strain_along_the_edge_gives_the_uniaxial_stress() {
        // Stretch and bending along the edge leave the corner unloaded across it: the slice's
        // field is Saint-Venant's uniaxial one, sigma_xx = E_x eps(z), exactly.
        let g = geometry(&[]);
        let s = tooth_base_section(&g)
            .unwrap()
            .expect("the bundled design has teeth");
        let e_x = silicon_elasticity(g.silicon).young_x_pa().unwrap();
        assert!((s.unit_mpa[3] * 1e6 / e_x - 1.0).abs() < 1e-6, "{s:?}");
        // kappa_t = +1/m compresses the top: the opening sign is the hogging one, -E t / 2.
        let half_t = 0.5 * g.plate_thickness_um * 1e-6;
        assert!(
            (-s.unit_mpa[2] * 1e6 / (e_x * half_t) - 1.0).abs() < 1e-3,
            "{s:?}"
        );
        // The moment concentrates: hogging opens the corner, far above the plate's 6 M / t^2.
        let nominal = 6.0 / (4.0 * half_t * half_t) * 1e-6;
        assert!(s.unit_mpa[0] < -5.0 * nominal, "{s:?}");
        assert!(s.unit_mpa[1] > 0.0, "tension opens it: {s:?}");
        // The section's own estimate (two gradings, two ring densities).
        assert!(s.error_rel < 0.01, "{s:?}");
        // Superposition: the stress of a drive is linear in it.
        let d = [-0.1, 300.0, -2.0, 1e-4];
        let one = s.stress_pa(d);
        assert!((s.stress_pa(d.map(|v| 3.0 * v)) - 3.0 * one).abs() < 1e-9 * one.abs());
        // The bound the station search prunes with is one.
        for d in [
            d,
            [0.1, -300.0, 2.0, -1e-4],
            [0.0, 0.0, 5.0, 0.0],
            [-0.2, 0.0, 0.0, 0.0],
        ] {
            assert!(s.bound_pa(d) >= s.stress_pa(d), "{d:?}");
        }
    }

    #[test]
    fn stations_keep_clear_of_the_support_sections_changes() {
        // The clamp has one condition along each wall: nothing to keep clear of.
        assert!(section_changes_um(&geometry(&[])).is_empty());
        // Under solid_section the checkered rows on the supports cut each wall into bare and
        // under-tooth pieces: both ends of each tooth's piece, on that support's wall line.
        let g = geometry(&["materials.base.support_model=solid_section"]);
        let c = section_changes_um(&g);
        let on_support = |t: &[f64; 4]| {
            t[1] < g.etched.support_edge_y_um || t[3] > g.width_um - g.etched.support_edge_y_um
        };
        let teeth = g
            .etched
            .tooth_tops_um
            .iter()
            .filter(|t| on_support(t))
            .count();
        assert!(teeth > 0 && c.len() == 2 * teeth, "{} for {teeth}", c.len());
        let grow = g.etched.tooth_run_out_um * (1.0 - g.etched.tooth_step_inset);
        for t in g.etched.tooth_tops_um.iter().filter(|t| on_support(t)) {
            let y = if t[1] < g.etched.support_edge_y_um {
                g.plate_y0_um
            } else {
                g.plate_y1_um
            };
            for x in [t[0] - grow, t[2] + grow] {
                assert!(
                    c.iter().any(|p| (p[0] - x).abs() < 1e-9 && p[1] == y),
                    "{x}, {y}"
                );
            }
        }
    }

    #[test]
    fn the_moment_stress_falls_off_as_williams_field() {
        // Four times the critical distance (twice the toughness): sigma ~ r^(lambda - 1) with
        // lambda the 234.74 deg wedge's exponent (Williams 1952), 4^(lambda - 1) = 0.602.
        let near = tooth_base_section(&geometry(&[])).unwrap().unwrap();
        let far = tooth_base_section(&geometry(&[
            "materials.silicon.fracture_toughness_mpa_sqrt_m=1.44",
        ]))
        .unwrap()
        .unwrap();
        assert!((far.read_at_um / near.read_at_um - 4.0).abs() < 1e-9);
        let lambda = tooth_base_exponent();
        let want = 4f64.powf(lambda - 1.0);
        let got = far.unit_mpa[0] / near.unit_mpa[0];
        assert!((got - want).abs() < 0.02, "{got} against {want}");
    }
}
