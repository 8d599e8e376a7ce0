//! Where the plate rungs put a tooth's edge (issue 16, item 5): the plate models a tooth as a
//! thickness step, and the step bends as the tooth's {111} sidewall does when it stands at the
//! inset this module measures on a plane-strain solid section of the sidewall.
//!
//! Euler-Bernoulli beam theory puts that step at c / r = a (b + 2 a) / (2 (a^2 + a b + b^2)) of
//! the run-out r from the base edge ([`beam_inset`]; a the plate, b = a + h), exact for a gentle
//! ramp. The {111} sidewall is steep (54.7 degrees): the silicon near its sloped face carries
//! less than plane sections say, the ramp bends more, and the step moves out. The section shows by
//! how much: on the bundled design (100 um plate, 200 um teeth) the inset is 0.41 against beam
//! theory's 0.19. Against the graded 3D solid the mid-height step (0.5) left the large-deflection
//! plate on the supports' sections 3.7 % soft at the 0.02 N centre load, beam theory's 2.5 %
//! stiff, the section's inset 1.0 % soft (README, "The teeth as steps").

use std::sync::Mutex;

use crate::fe::solid::{
    graded_lines, hex27, merged_lines, Constraint, HexGrid, NodeSet, SolidModel, SolidProblem,
};
use crate::fe::{FeError, FeResult};

use super::geometry::SiliconStiffness;
use super::solid_mesh::{silicon_elasticity, PiecewiseLinear, SILICON};
use super::support_section::end_stiffness;

/// Length of plate (and of tooth) either side of the sidewall, in plate thicknesses \[choice\]:
/// the sidewall's disturbance decays over about one (Saint-Venant).
pub const ARM_THICKNESSES: f64 = 6.0;

/// The finest element at the sidewall's corners, in plate thicknesses, and the growth away
/// from them \[choice\]: the inset moves by 0.002 when every element halves (`tests`).
const FINE_THICKNESSES: f64 = 0.1;
const GROWTH: f64 = 1.4;

/// The most elements of the coarse size across the section's length or height: bounds the work
/// on a tall tooth over a thin plate (the bundled design's section is 31 across).
const MAX_ELEMENTS_ACROSS: f64 = 40.0;

/// Beam theory's inset: a ramp from thickness a to b = a + h over the run-out r turns under a
/// moment by r (a + b) / (2 a^2 b^2) (the compliance integral of ds / t(s)^3), a step at c from
/// the base by c / a^3 + (r - c) / b^3; equal where c / r = a (b + 2 a) / (2 (a^2 + a b +
/// b^2)). Mid-height (1/2) is the limit of low teeth, the base edge (0) that of tall ones.
pub fn beam_inset(plate_um: f64, height_um: f64) -> f64 {
    let (a, b) = (plate_um, plate_um + height_um.max(0.0));
    a * (b + 2.0 * a) / (2.0 * (a * a + a * b + b * b))
}

/// Sections solved, by (plate, height, run-out, stiffness) bits.
type Key = Vec<u64>;
static INSETS: Mutex<Vec<(Key, f64)>> = Mutex::new(Vec::new());
const INSETS_KEPT: usize = 16;

/// The inset of the step that bends as the sidewall, as a fraction of the run-out from the base
/// edge, measured on the plane-strain section ([`measure_inset`]); beam theory's where the section
/// cannot be built (no tooth, no run-out).
pub fn inset(plate_um: f64, height_um: f64, run_out_um: f64, silicon: SiliconStiffness) -> f64 {
    if !(plate_um > 0.0 && height_um > 1e-3 * plate_um && run_out_um > 1e-3 * plate_um) {
        return beam_inset(plate_um, height_um);
    }
    let key: Key = [plate_um, height_um, run_out_um]
        .into_iter()
        .chain(silicon_elasticity(silicon).c_pa.iter().flatten().copied())
        .map(f64::to_bits)
        .collect();
    if let Some(v) = INSETS
        .lock()
        .ok()
        .and_then(|v| v.iter().find(|(k, _)| *k == key).map(|(_, c)| *c))
    {
        return v;
    }
    let c = measure_inset(plate_um, height_um, run_out_um, silicon, 0)
        .unwrap_or_else(|_| beam_inset(plate_um, height_um));
    if let Ok(mut v) = INSETS.lock() {
        if v.len() >= INSETS_KEPT {
            v.remove(0);
        }
        v.push((key, c));
    }
    c
}

/// What the section stands for: the stepped plate, or a plain one of either thickness (the
/// calibration that cancels the arms' end effects).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Part {
    Stepped,
    Thin,
    Thick,
}

/// The inset measured on a plane-strain section (the solid rung's hex27, one element along the
/// edge, u_x held): the plate of thickness a, a tooth of height h on it behind a {111} sidewall of
/// run-out r, arms of [`ARM_THICKNESSES`] either side. One arm end is clamped, the other moved by
/// w, its slope and its stretch; the moment compliance C with no shear and no axial force is the
/// turn per unit moment, C = (L + c) / EI_a + (L + r - c) / EI_b + e_a + e_b for a step at c
/// (e the ends' effects). The plain plates of either thickness and the same length give
/// 2 (L + r / 2) / EI + 2 e, so c = r / 2 + (C - (C_a + C_b) / 2) / (1 / EI_a - 1 / EI_b), the
/// ends' effects cancelled; 1 / EI from the plain plates' own compliances. `refine` halves every
/// element that many times.
pub fn measure_inset(
    plate_um: f64,
    height_um: f64,
    run_out_um: f64,
    silicon: SiliconStiffness,
    refine: u32,
) -> FeResult<f64> {
    let length = 2.0 * ARM_THICKNESSES * plate_um + run_out_um;
    let c = |part| turn_per_moment(plate_um, height_um, run_out_um, silicon, refine, part);
    let (stepped, thin, thick) = (c(Part::Stepped)?, c(Part::Thin)?, c(Part::Thick)?);
    let per_length = (thin - thick) / length;
    let c = 0.5 * run_out_um + (stepped - 0.5 * (thin + thick)) / per_length;
    if !(c.is_finite() && per_length > 0.0) {
        return Err(FeError::NonFinite {
            hint: "the tooth sidewall's section gave no bending compliance",
        });
    }
    Ok((c / run_out_um).clamp(0.0, 1.0))
}

/// The section's turn per unit moment (1/(N m) per m of edge) with no shear and no axial force
/// at the moved end.
fn turn_per_moment(
    t: f64,
    h: f64,
    r: f64,
    silicon: SiliconStiffness,
    refine: u32,
    part: Part,
) -> FeResult<f64> {
    let k = 0.5f64.powi(refine as i32);
    let arm = ARM_THICKNESSES * t;
    let (y_a, y_b) = (-arm, r + arm);
    // Tall or long sidewalls against a thin plate get coarser far elements, so the section
    // stays within about MAX_ELEMENTS_ACROSS elements each way whatever the design.
    let coarse = (0.5 * t).max((h + r + 2.0 * arm) / MAX_ELEMENTS_ACROSS) * k;
    let fine = (FINE_THICKNESSES * t * k).min(coarse);
    let mut ys = graded_lines(0.0, y_a, fine, GROWTH, coarse);
    ys.extend(graded_lines(0.0, y_b, fine, GROWTH, coarse));
    let mut zs = graded_lines(t, 0.0, fine, GROWTH, coarse);
    zs.extend(graded_lines(t, t + h, fine, GROWTH, coarse));
    let (ys, zs) = (merged_lines(ys), merged_lines(zs));
    let xs = [0.0, 0.25 * t];
    let mut grid = HexGrid::new(&xs, &ys, &zs)?;
    grid.assign(|[_, yc, zc]| match part {
        _ if zc < t => Some(SILICON),
        Part::Thin => None,
        Part::Thick => Some(SILICON),
        Part::Stepped => (yc > 0.0).then_some(SILICON),
    });
    if part == Part::Stepped {
        // The sidewall: the base edge (y = 0 at the plate's top) runs out by r at the top.
        let wall = PiecewiseLinear::new(vec![(y_a, y_a), (0.0, r), (y_b, y_b)])?;
        grid = grid.with_map(std::sync::Arc::new(move |[x, y, z]: [f64; 3]| {
            if z > t {
                let s = ((z - t) / h).min(1.0);
                [x, y + s * (wall.apply(y) - y), z]
            } else {
                [x, y, z]
            }
        }));
    }
    let mut problem = SolidProblem::new(grid, vec![silicon_elasticity(silicon)]);
    problem.constraints.push(Constraint::clamp(
        "moved",
        NodeSet::Plane {
            axis: crate::fe::solid::Axis3::Y,
            at_um: y_a,
        },
    ));
    problem.constraints.push(Constraint::clamp(
        "held",
        NodeSet::Plane {
            axis: crate::fe::solid::Axis3::Y,
            at_um: y_b,
        },
    ));
    problem
        .constraints
        .push(Constraint::plane_strain_x("plane_strain"));
    let model = SolidModel::new(&problem)?;
    let tol = 1e-6 * t;
    let z_mid = 0.5 * t;
    let is_moved = |p: [f64; 3]| (p[1] - y_a).abs() < tol;
    let kk = end_stiffness(
        &model,
        "moved",
        is_moved,
        z_mid,
        xs[1] - xs[0],
        |_, _, _| Ok(()),
    )?;
    let det = hex27::det3(&kk);
    if !(det.is_finite() && det.abs() > 0.0) {
        return Err(FeError::NonFinite {
            hint: "the tooth sidewall's section has a singular end stiffness",
        });
    }
    Ok(hex27::inverse3(&kk, det)[1][1])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::{
        Axis, DieEdge, LineSupport, Load, PlateMaterial, PlateProblem, RectMesh, SupportKind,
        ThicknessRegion,
    };

    fn silicon() -> SiliconStiffness {
        SiliconStiffness::Cubic {
            c11_pa: 165.7e9,
            c12_pa: 63.9e9,
            c44_pa: 79.6e9,
            die_edge: DieEdge::Along110,
        }
    }

    #[test]
    fn a_gentle_ramp_is_beam_theory_and_the_111_sidewall_sits_further_out() {
        // A ramp ten times longer than high bends as plane sections say: the section's inset
        // within 0.03 of beam theory's. The bundled {111} sidewall (100 um plate, 200 um
        // teeth, run-out h / sqrt 2) sits well outside beam theory's 0.19 (measured 0.406),
        // and halving every element moves it by under 0.01 (measured 0.002).
        let (t, h) = (100.0, 200.0);
        let gentle = measure_inset(t, 20.0, 200.0, silicon(), 0).unwrap();
        let beam = beam_inset(t, 20.0);
        eprintln!("gentle ramp: section {gentle:.4}, beam {beam:.4}");
        assert!((gentle - beam).abs() < 0.03, "{gentle} {beam}");
        let r = h / 2f64.sqrt();
        let (c0, c1) = (
            measure_inset(t, h, r, silicon(), 0).unwrap(),
            measure_inset(t, h, r, silicon(), 1).unwrap(),
        );
        eprintln!(
            "{{111}} sidewall: section {c0:.4} (refined {c1:.4}), beam {:.4}",
            beam_inset(t, h)
        );
        assert!(c0 > beam_inset(t, h) + 0.05, "{c0}");
        assert!((c0 - c1).abs() < 0.01, "{c0} {c1}");
    }

    /// Centre deflection (m) of a strip clamped along y = 0 and y = span (nu = 0: cylindrical
    /// bending exactly) under uniform pressure, with `bands` (y0, y1, thickness) across it.
    fn strip_deflection(bands: &[(f64, f64, f64)], plate_um: f64) -> f64 {
        let (length, span) = (1000.0, 6000.0);
        let mut ys = vec![0.0, 0.5 * span, span];
        for b in bands {
            ys.extend([b.0, b.1]);
        }
        ys.sort_by(f64::total_cmp);
        ys.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
        let mesh = RectMesh::build(&[0.0, length], &ys, 50.0, &[]);
        let mut p = PlateProblem::new(mesh, plate_um, PlateMaterial::isotropic(169e9, 0.0));
        for (group, at) in [("a", 0.0), ("b", span)] {
            p.supports.push(LineSupport {
                group: group.into(),
                kind: SupportKind::Clamped,
                along: Axis::X,
                at_um: at,
                from_um: 0.0,
                to_um: length,
            });
        }
        p.thickness_regions = bands
            .iter()
            .map(|&(y0, y1, t)| ThicknessRegion {
                x0_um: 0.0,
                y0_um: y0,
                x1_um: length,
                y1_um: y1,
                thickness_um: t,
                rise_um: 0.0,
            })
            .collect();
        p.load_cases.push(vec![Load::Pressure {
            region: None,
            total_force_n: 0.01,
        }]);
        p.solve()
            .unwrap()
            .remove(0)
            .deflection_m(0.5 * length, 0.5 * span)
    }

    #[test]
    fn the_step_bends_as_the_frustum_sidewall_it_stands_for() {
        // The bundled tooth's section: a 100 um plate, 200 um teeth, the {111} run-out h / sqrt 2,
        // base edges 1.5 mm from each clamp. Reference: the sidewall as 48 stairs per ramp.
        let (a, h) = (100.0, 200.0);
        let r = h / 2f64.sqrt();
        let (base0, base1) = (1500.0, 4500.0);
        let n = 48;
        let mut stairs = vec![(base0 + r, base1 - r, a + h)];
        for k in 0..n {
            let (s0, s1) = (r * k as f64 / n as f64, r * (k + 1) as f64 / n as f64);
            let t = a + h * (k as f64 + 0.5) / n as f64;
            stairs.push((base0 + s0, base0 + s1, t));
            stairs.push((base1 - s1, base1 - s0, t));
        }
        let ramp = strip_deflection(&stairs, a);
        let step_at = |c: f64| strip_deflection(&[(base0 + c, base1 - c, a + h)], a);
        let inset = beam_inset(a, h);
        let (equivalent, mid_height) = (step_at(inset * r), step_at(0.5 * r));
        let rel = |w: f64| w / ramp - 1.0;
        eprintln!(
            "inset {inset:.4}: ramp {ramp:.6e}, equivalent step {:+.2e}, mid-height {:+.2e}",
            rel(equivalent),
            rel(mid_height)
        );
        assert!((inset - 0.1923).abs() < 1e-4, "{inset}");
        assert!(rel(equivalent).abs() < 2e-3, "{}", rel(equivalent));
        assert!(rel(mid_height) > 10.0 * rel(equivalent).abs());
        // The limits: a low tooth's step sits at mid-height, a tall one's at its base.
        assert!((beam_inset(a, 1e-9) - 0.5).abs() < 1e-9);
        assert!(beam_inset(a, 1e6) < 1e-3);
    }
}
