//! The solid rung (issue 16): the sensor as a 3D solid on a sequence of meshes, each quantity
//! with its own three-mesh error estimate, and its difference from the linear plate rung, which
//! is that rung's model error measured rather than assumed.

use std::time::Instant;

use serde::Serialize;

use crate::fe::solid::{SolidModel, TlOptions, TlSolid, TransverseShear};
use crate::fe::{FeError, ThreeMesh};
use crate::process::{Scene, SceneLoad};

use super::check::{check_scene, SensorError};
use super::edge_stress::{thickness_checks, EdgeKind, EdgeThicknessCheck, FINE_BRICK_BOX};
use super::geometry::{ElectrodeSide, SensorGeometry};
use super::solid_mesh::{build, Base, SensorSolid, SolidMeshOptions, TopLoad};
use super::solid_readout::{read, SolidReadout};

/// Coarsest in-plane element of the solid rung (um) \[choice\]: the tooth pitch's third, so the
/// first level already resolves each tooth and street.
pub const COARSE_ELEMENT_UM: f64 = 1000.0;

/// Largest number of levels (each sqrt 2 finer in plane) \[choice\]: the fifth is 250 um.
pub const MAX_SOLID_LEVELS: usize = 5;

/// The thickness check's third mesh: `doubled` (level 0 with four bricks through the plate and
/// the teeth) with eight in a square of [`FINE_BRICK_BOX`] plate thicknesses either side of each
/// of `readings` (the edges' sections and vertices), whose halves merge back into the four
/// elsewhere: the four-brick field lies in its space.
fn eight_brick_mesh(
    doubled: SolidMeshOptions,
    readings: &[super::edge_stress::EdgeStress],
    g: &SensorGeometry,
) -> SolidMeshOptions {
    let half = FINE_BRICK_BOX * g.plate_thickness_um;
    SolidMeshOptions {
        brick_halvings: doubled.brick_halvings + 1,
        brick_halvings_outside: doubled.brick_halvings,
        fine_brick_boxes_um: readings
            .iter()
            .map(|e| {
                let [x, y, _] = e.at_um;
                [x - half, x + half, y - half, y + half]
            })
            .collect(),
        ..doubled
    }
}

/// Newton's tolerances for the thickness check \[choice\]. It is read only for the edges'
/// stresses, against level 0's, and starts from level 0's field (in its space), so its first
/// correction is what the doubled bricks change. It stops once the next correction, estimated
/// with the factor at hand, is under a tenth of `energy_tol` of that one in energy (1e-6, so
/// 1e-3 in displacement; on `centre-1n` 1.0e-7 after the first) and the largest residual under
/// `residual_tol` of the force scale (3.5e-4 there). The check's stresses then lie within 1e-3
/// of the difference they measure of the fully converged check's (README, "Linear solves only as
/// exact as Newton needs"). The levels keep the default tolerances: their reactions must
/// balance the load.
fn thickness_check_newton() -> TlOptions {
    TlOptions {
        energy_tol: 1e-5,
        residual_tol: 1e-3,
        ..TlOptions::default()
    }
}

/// Width of the strip a line load acts on in the solid (a line force is singular in 3D): the
/// plate's thickness, over which plate theory spreads it anyway.
fn line_strip_um(g: &SensorGeometry) -> f64 {
    g.plate_thickness_um
}

/// One mesh level of the solid rung.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SolidLevel {
    pub element_um: f64,
    /// The largest cell across the span (y between the channel walls; [`SolidMeshOptions`]).
    pub span_element_um: f64,
    pub dofs: usize,
    /// Newton iterations (each a tangent assembly and a correction) of the geometrically
    /// nonlinear solve; None for the linear one (one factorisation).
    pub newton_iterations: Option<usize>,
    /// Numeric factorisations of the nonlinear solve: one per iteration with full Newton, fewer
    /// where the corrections are conjugate gradients on the last factor
    /// ([`crate::fe::solid::TlOptions::krylov_iterations`]); None for the linear one.
    pub factorisations: Option<usize>,
    /// Of those, the ones in single precision (preconditioners of conjugate gradients, half
    /// the memory); None for the linear solve.
    pub single_precision_factorisations: Option<usize>,
    /// Entries of the Cholesky factor (f64), a measure of the memory it takes.
    pub factor_entries: usize,
    /// How far a feature line stands off its mesh line (um; left out when none does:
    /// [`super::solid_mesh::SensorSolid::edge_moved_um`]).
    #[serde(skip_serializing_if = "is_zero")]
    pub edge_moved_um: f64,
    #[serde(skip)]
    pub seconds: f64,
    pub readout: SolidReadout,
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

/// One quantity of the solid rung with its discretisation estimate and the linear plate's value.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SolidQuantity {
    pub name: String,
    pub unit: &'static str,
    pub value: f64,
    /// Three-mesh estimate relative to the quantity's scale; None before three levels.
    pub discretisation: Option<f64>,
    /// Richardson's limit of the three meshes when they converge monotonically, else the finest
    /// value: the solid's best value, `discretisation` its uncertainty.
    pub extrapolated: f64,
    /// The plate rung's value (linear or large-deflection, as `SolidReport::plate_rung`) and its
    /// difference from `extrapolated`, relative to the quantity's scale: the plate's model error
    /// as the solid sees it, known to within `discretisation`.
    pub plate_value: Option<f64>,
    pub plate_difference: Option<f64>,
}

/// The solid rung's answer to one scene.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SolidReport {
    pub scene: String,
    pub force_n: f64,
    /// "quarter, mirrors x = 15 mm and y = 7.5 mm" or "whole die".
    pub part_solved: String,
    pub base: String,
    /// Geometrically nonlinear (Total Lagrangian, St. Venant-Kirchhoff, dead load) rather than
    /// linear: chosen when the plate ladder answers the scene with the large-deflection plate.
    pub nonlinear: bool,
    /// The levels graded at every tooth's base edges (`--graded`).
    pub graded: bool,
    /// The bricks' transverse shears tied (the default; `--plain-shear` unties them).
    pub tied_shear: bool,
    /// The hot teeth's edges and the channel walls graded locally: bisected cells that merge
    /// back away from the tooth, with hanging nodes between (else by lines across the die).
    pub local_refinement: bool,
    /// Under [`SolidGrading::Auto`], the finest level's factor sizes that chose it, or, where
    /// one grading's analysis was refused, why the other was solved.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub grading_choice: Option<GradingChoice>,
    /// How many teeth's base edges the levels are graded at: every tooth under `graded`, else
    /// the plate answer's hot teeth ([`crate::sensor::edge_section::hot_teeth`]), where the worst
    /// edge is.
    pub graded_teeth: usize,
    /// The plate rung compared with: "plate" or "large_deflection_plate".
    pub plate_rung: String,
    pub levels: Vec<SolidLevel>,
    /// The edges' stresses at level 0 against twice the bricks through the thickness, whose
    /// error estimate their quantities' `discretisation` includes.
    pub edge_thickness: Vec<EdgeThicknessCheck>,
    pub quantities: Vec<SolidQuantity>,
    /// Every quantity's discretisation estimate under the tolerance.
    pub converged: bool,
    /// The smallest fraction of a contact that lies on upward faces (the rest over sidewalls).
    pub contact_on_top_faces: f64,
}

/// The top loads of a scene and its reference point (where the deflection is reported).
pub fn top_loads(g: &SensorGeometry, load: &SceneLoad) -> (Vec<TopLoad>, (f64, f64)) {
    let rect = |x0: f64, y0: f64, x1: f64, y1: f64| vec![(x0, y0), (x1, y0), (x1, y1), (x0, y1)];
    match *load {
        SceneLoad::Point {
            x_um,
            y_um,
            force_n,
            radius_um,
        } => {
            if radius_um > 0.0 {
                // The square of equal area, as the plate rungs use.
                let h = 0.5 * std::f64::consts::PI.sqrt() * radius_um;
                (
                    vec![TopLoad::Patch {
                        polygon_um: rect(x_um - h, y_um - h, x_um + h, y_um + h),
                        force_n,
                    }],
                    (x_um, y_um),
                )
            } else {
                (
                    vec![TopLoad::Point {
                        x_um,
                        y_um,
                        force_n,
                    }],
                    (x_um, y_um),
                )
            }
        }
        SceneLoad::Pressure { force_n, region } => {
            let (x0, y0, x1, y1) = match region {
                Some(r) => (r.x0_um, r.y0_um, r.x1_um, r.y1_um),
                None => (0.0, g.plate_y0_um, g.length_um, g.plate_y1_um),
            };
            (
                vec![TopLoad::Patch {
                    polygon_um: rect(x0, y0, x1, y1),
                    force_n,
                }],
                (0.5 * (x0 + x1), 0.5 * (y0 + y1)),
            )
        }
        SceneLoad::Probe {
            x_um,
            y_um,
            width_um,
            height_um,
            angle_deg,
            force_n,
        } => {
            let (s, c) = angle_deg.to_radians().sin_cos();
            let (a, b) = (0.5 * width_um, 0.5 * height_um);
            let polygon_um = [(-a, -b), (a, -b), (a, b), (-a, b)]
                .iter()
                .map(|&(u, v)| (x_um + c * u - s * v, y_um + s * u + c * v))
                .collect();
            (
                vec![TopLoad::Patch {
                    polygon_um,
                    force_n,
                }],
                (x_um, y_um),
            )
        }
        SceneLoad::Line { y_um, force_n } => {
            let h = 0.5 * line_strip_um(g);
            (
                vec![TopLoad::Patch {
                    polygon_um: rect(0.0, y_um - h, g.length_um, y_um + h),
                    force_n,
                }],
                (0.5 * g.length_um, y_um),
            )
        }
        SceneLoad::Patches { ref patches } => {
            let (x0, y0, x1, y1) = super::scene::patches_extent_um(patches).unwrap_or((
                0.0,
                0.0,
                g.length_um,
                g.width_um,
            ));
            let mut loads = Vec::with_capacity(patches.len());
            for p in patches {
                let r = p.region;
                if p.force_n != 0.0 {
                    loads.push(TopLoad::Patch {
                        polygon_um: rect(r.x0_um, r.y0_um, r.x1_um, r.y1_um),
                        force_n: p.force_n,
                    });
                }
            }
            (loads, (0.5 * (x0 + x1), 0.5 * (y0 + y1)))
        }
    }
}

/// True if the point set maps onto itself under the mirror `v -> 2 m - v` of coordinate `axis`.
fn mirrored(points: &[Vec<(f64, f64)>], axis: usize, m: f64) -> bool {
    let key = |p: &[(f64, f64)]| {
        let mut v: Vec<(i64, i64)> = p
            .iter()
            .map(|&(x, y)| ((x * 1e3).round() as i64, (y * 1e3).round() as i64))
            .collect();
        v.sort_unstable();
        v
    };
    let flip = |p: &Vec<(f64, f64)>| -> Vec<(f64, f64)> {
        p.iter()
            .map(|&(x, y)| {
                if axis == 0 {
                    (2.0 * m - x, y)
                } else {
                    (x, 2.0 * m - y)
                }
            })
            .collect()
    };
    let mut a: Vec<Vec<(i64, i64)>> = points.iter().map(|p| key(p)).collect();
    let mut b: Vec<Vec<(i64, i64)>> = points.iter().map(|p| key(&flip(p))).collect();
    a.sort();
    b.sort();
    a == b
}

/// The mirrors under which the teeth, the electrodes and the loads are all symmetric (loads of
/// each force onto loads of the same force).
pub(crate) fn mirrors(g: &SensorGeometry, loads: &[TopLoad]) -> (Option<f64>, Option<f64>) {
    let rect = |r: [f64; 4]| vec![(r[0], r[1]), (r[2], r[1]), (r[2], r[3]), (r[0], r[3])];
    let mut shapes: Vec<Vec<(f64, f64)>> =
        g.etched.tooth_tops_um.iter().map(|&t| rect(t)).collect();
    shapes.extend(
        g.electrodes
            .iter()
            .map(|e| rect([e.x0_um, e.y0_um, e.x1_um, e.y1_um])),
    );
    let load_shapes: Vec<(Vec<(f64, f64)>, f64)> = loads
        .iter()
        .map(|l| match l {
            TopLoad::Patch {
                polygon_um,
                force_n,
            } => (polygon_um.clone(), *force_n),
            TopLoad::Point {
                x_um,
                y_um,
                force_n,
            } => (vec![(*x_um, *y_um)], *force_n),
        })
        .collect();
    let ok = |axis: usize, m: f64| {
        mirrored(&shapes, axis, m)
            && load_shapes.iter().all(|(_, f)| {
                let same: Vec<Vec<(f64, f64)>> = load_shapes
                    .iter()
                    .filter(|(_, g)| (g - f).abs() <= 1e-12 * f.abs().max(1.0))
                    .map(|(p, _)| p.clone())
                    .collect();
                mirrored(&same, axis, m)
            })
    };
    let (mx, my) = (0.5 * g.length_um, 0.5 * g.width_um);
    (ok(0, mx).then_some(mx), ok(1, my).then_some(my))
}

/// Quantity names and units in the plate rungs' spelling, and the scale each is relative to.
fn quantity_table(
    g: &SensorGeometry,
    r: &SolidReadout,
    force_n: f64,
) -> Vec<(String, &'static str, f64, f64)> {
    let mut out = vec![(
        "deflection_at_load".to_string(),
        "um",
        r.deflection_at_load_um,
        r.deflection_at_load_um.abs(),
    )];
    // Charges relative to the largest of their kind (middle or support), as the plate rungs do.
    let largest = |middle: bool| {
        g.electrodes
            .iter()
            .zip(&r.charge_pc)
            .filter(|(e, _)| (e.side == ElectrodeSide::Middle) == middle)
            .map(|(_, q)| q.abs())
            .fold(0.0, f64::max)
    };
    for (e, q) in g.electrodes.iter().zip(&r.charge_pc) {
        let scale = largest(e.side == ElectrodeSide::Middle);
        out.push((format!("charge_{}", e.name), "pC", *q, scale));
    }
    out.push(("reaction_support1".into(), "N", r.support1_n, force_n.abs()));
    out.push(("reaction_support2".into(), "N", r.support2_n, force_n.abs()));
    out.push((
        "max_stress_averaged".into(),
        "MPa",
        r.stress_averaged_mpa,
        r.stress_averaged_mpa.abs(),
    ));
    // The sharp edges' stress at the critical distance (`edge_stress`): what fracture is judged
    // on there.
    // Relative to the largest of them: an edge in compression reads near zero.
    let edges = r
        .edge_stress
        .iter()
        .fold(0.0f64, |m, e| m.max(e.stress_mpa.abs()));
    for e in &r.edge_stress {
        out.push((
            format!("{}_stress", e.kind.as_str()),
            "MPa",
            e.stress_mpa,
            edges,
        ));
    }
    out.push((
        "max_principal_stress".into(),
        "MPa",
        r.max_principal_mpa,
        r.max_principal_mpa.abs(),
    ));
    out
}

/// The stress names the solid's safety factor is judged on: the plate rungs' averaged stress and
/// each sharp edge's stress at the critical distance.
pub const SAFETY_STRESSES: [&str; 4] = [
    "max_stress_averaged",
    "tooth_base_stress",
    "support_edge_stress",
    "tooth_vertex_stress",
];

impl super::SceneReport {
    /// Where the solid's governing stress ([`SolidReport::governing_stress`]: a sharp edge's at
    /// the critical distance, or the averaged one) gives a lower safety factor than this answer's
    /// averaged stress, the answer takes it, and the permissible load with it (linear in the
    /// load, as the plate rungs scale it), with an `EDGE_STRESS` warning naming the edge. A load
    /// wholly on a support, which no plate rung judges ([`super::StressFrom::OnSupport`]), takes
    /// the solid's stress itself ([`super::StressFrom::SolidOnSupport`]): the solid reads the
    /// support's edges.
    fn take_safety_from(&mut self, g: &SensorGeometry, solid: &SolidReport) {
        use crate::finding::{Finding, SceneCode};
        let Some((name, stress)) = solid.governing_stress() else {
            return;
        };
        // An edge in compression opens no crack: nothing to take.
        if stress.is_nan() || stress <= 0.0 {
            return;
        }
        // The plate rungs' own fracture strength and required factor.
        let sf = super::evaluate::safety_factor(g, stress * 1e6);
        let message = if self.stress_from == super::StressFrom::OnSupport {
            self.max_stress_mpa = stress;
            self.stress_from = super::StressFrom::SolidOnSupport;
            format!(
                "the load stands wholly on a support: the solid rung's {name} ({stress:.1} MPa \
                 with its estimate) gives safety factor {sf:.2}: taken"
            )
        } else if sf < self.safety_factor {
            // The answer keeps its own (averaged) stress; the factor is the solid edge's.
            format!(
                "the solid rung's {name} ({stress:.1} MPa with its estimate) gives safety \
                 factor {sf:.2}, below the plate answer's {:.2}: taken",
                self.safety_factor
            )
        } else {
            return;
        };
        self.safety_factor = sf;
        self.max_permissible_load_n =
            super::evaluate::permissible_load_n(g, stress * 1e6, self.force_n);
        self.warnings
            .push(Finding::warning(SceneCode::EdgeStress, message));
        self.note_safety_shortfall(g);
    }
}

impl SolidReport {
    /// True if a level read a tooth's base edge (the design has teeth whose corner the rung can
    /// submodel): what the uniform levels' caveat is about.
    pub fn reads_tooth_bases(&self) -> bool {
        self.levels.iter().any(|l| {
            l.readout
                .edge_stress
                .iter()
                .any(|e| e.kind == EdgeKind::ToothBase)
        })
    }

    /// The stress the safety factor is judged on, on its unsafe side: the largest of
    /// [`SAFETY_STRESSES`], each extrapolated and raised by its own estimate, with its name
    /// (None if none was read).
    pub fn governing_stress(&self) -> Option<(&str, f64)> {
        let safety = || {
            self.quantities
                .iter()
                .filter(|q| SAFETY_STRESSES.contains(&q.name.as_str()))
        };
        // The edges' estimates are relative to the largest edge stress (`quantity_table`).
        let edges = safety()
            .filter(|q| q.name != SAFETY_STRESSES[0])
            .fold(0.0f64, |m, q| m.max(q.value.abs()));
        safety()
            .map(|q| {
                let v = q.extrapolated.max(q.value);
                let scale = if q.name == SAFETY_STRESSES[0] {
                    v.abs()
                } else {
                    edges
                };
                (q.name.as_str(), v + q.discretisation.unwrap_or(0.0) * scale)
            })
            .filter(|(_, v)| v.is_finite())
            .max_by(|a, b| a.1.total_cmp(&b.1))
    }
}

/// A scene as the solid rung meshes it: its top loads, where its deflection is read, its
/// contact patch and the mirrors of the part solved. [`evaluate_solid`] and the export
/// ([`super::solid_export::export_scene`]) both start here, so the export is one of the rung's
/// levels by construction.
pub(crate) struct SceneModel {
    pub loads: Vec<TopLoad>,
    /// Where the deflection is read (um).
    pub at_um: (f64, f64),
    /// The contact patch (x0, y0, x1, y1), um.
    pub patch_um: [f64; 4],
    pub mirror_x_um: Option<f64>,
    pub mirror_y_um: Option<f64>,
}

impl SceneModel {
    /// The scene checked against the design; mirrored where `symmetry` and the die and load
    /// allow.
    pub(crate) fn new(
        g: &SensorGeometry,
        scene: &Scene,
        symmetry: bool,
    ) -> Result<Self, SensorError> {
        check_scene(scene, g)?;
        let (loads, at_um) = top_loads(g, &scene.load);
        let p = super::scene::split(&scene.load, g).patch;
        let (mirror_x_um, mirror_y_um) = if symmetry {
            mirrors(g, &loads)
        } else {
            (None, None)
        };
        Ok(SceneModel {
            loads,
            at_um,
            patch_um: [p.x0_um, p.y0_um, p.x1_um, p.y1_um],
            mirror_x_um,
            mirror_y_um,
        })
    }

    /// The total force of the loads (N).
    pub(crate) fn force_n(&self) -> f64 {
        self.loads
            .iter()
            .map(|l| match l {
                TopLoad::Patch { force_n, .. } | TopLoad::Point { force_n, .. } => *force_n,
            })
            .sum()
    }

    /// The solid of one mesh, graded at the base edges of `graded_teeth`.
    pub(crate) fn build(
        &self,
        g: &SensorGeometry,
        base: Base,
        opts: SolidMeshOptions,
        graded_teeth: &[usize],
    ) -> Result<SensorSolid, SensorError> {
        build(
            g,
            std::slice::from_ref(&self.loads),
            base,
            opts,
            graded_teeth,
            self.mirror_x_um,
            self.mirror_y_um,
        )
        .map_err(SensorError::Fe)
    }

    /// The read-out of a solved solid of this scene.
    pub(crate) fn read(
        &self,
        g: &SensorGeometry,
        solid: &SensorSolid,
        sol: &impl crate::fe::solid::SolidField,
    ) -> Result<SolidReadout, SensorError> {
        read(g, solid, sol, self.at_um, self.patch_um).map_err(SensorError::Fe)
    }
}

/// How the solid rung is run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolidRun {
    pub base: Base,
    /// Mesh levels, 1 to [`MAX_SOLID_LEVELS`] (three give an error estimate).
    pub levels: usize,
    pub tol: f64,
    /// Solve half or a quarter where the die and the load are mirror-symmetric.
    pub symmetry: bool,
    /// Geometrically nonlinear solve (Newton on the Total Lagrangian model).
    pub nonlinear: bool,
    /// Every level graded at the tooth base edges
    /// ([`super::solid_mesh::TOOTH_EDGE_GRADING`]): about 4 times the dofs and memory.
    pub graded: bool,
    /// The bricks' transverse shears tied ([`crate::fe::solid::TransverseShear::Tied`], what
    /// `fe` does unless `--plain-shear`): the plate's bricks of several thicknesses do not lock
    /// (README, "Tied transverse shear").
    pub tied_shear: bool,
    /// How the levels are graded at the hot teeth (and the walls).
    pub grading: SolidGrading,
}

/// How the solid's levels are graded at the edges: locally
/// ([`super::solid_mesh::SolidMeshOptions::local_refinement`]: the hot teeth's and the channel
/// walls' cells bisected toward them, merged back away from the teeth, hanging nodes between),
/// by lines at [`super::solid_mesh::TOOTH_EDGE_GRADING`] across the die, or whichever of the two
/// gives the finest level the smaller factor (`Auto`, the default). Measured on the bundled
/// design (README, "Local refinement"): the centre load's local factor is 16 % smaller, the
/// line load's 52 % larger (five hot teeth in a row on the whole die keep their bands fine along
/// it, both walls are graded, and bricks spanning planes constrain the order), so neither wins
/// everywhere; the symbolic analyses that decide take seconds. `Uniform` grades no tooth: the
/// feature lines only, about half the cost of one graded level on the short test die
/// (README), and it can miss the worst tooth base beyond its estimate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SolidGrading {
    Auto,
    Local,
    Lines,
    Uniform,
}

/// The factor sizes `SolidGrading::Auto` chose between, on the finest level. Where one grading's
/// analysis was refused (its factor over the memory there is, or the mesh over the size limit),
/// its size is None, `refused` says why, and auto solves the other.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct GradingChoice {
    pub local_factor_entries: Option<usize>,
    pub lines_factor_entries: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub refused: Option<String>,
}

/// Why auto could not analyse a grading: the refusal's message, without its hint.
fn refusal(e: &SensorError) -> String {
    let text = match e {
        SensorError::Fe(fe) => fe.to_string(),
        other => other.to_string(),
    };
    text.lines().next().unwrap_or_default().to_string()
}

/// Solves a scene on the solid rung over `run.levels` meshes and compares each quantity with
/// `plate` (the linear plate rung's values by quantity name); every level is graded at the base
/// edges of the teeth in `graded_teeth` (indices into the etched tooth tops), of every tooth
/// under `run.graded`.
pub fn evaluate_solid(
    g: &SensorGeometry,
    scene: &Scene,
    run: SolidRun,
    plate: &[(String, f64)],
    graded_teeth: &[usize],
) -> Result<SolidReport, SensorError> {
    let scene_model = SceneModel::new(g, scene, run.symmetry)?;
    let graded_teeth: &[usize] = if run.grading == SolidGrading::Uniform {
        &[]
    } else {
        graded_teeth
    };
    let (base, tol) = (run.base, run.tol);
    let levels = run.levels.clamp(1, MAX_SOLID_LEVELS);
    let force_n = scene_model.force_n();
    let mut out = Vec::new();
    let mut contact = 1.0f64;
    // One mesh solved and read; the nonlinear solve starts from a coarser field where there is
    // one and stops at `tolerances`.
    let solve =
        |opts: SolidMeshOptions,
         coarser: Option<&crate::fe::solid::TlSolution>,
         tolerances: TlOptions|
         -> Result<(SolidLevel, f64, Option<crate::fe::solid::TlSolution>), SensorError> {
            let start = Instant::now();
            let solid = scene_model.build(g, base, opts.clone(), graded_teeth)?;
            let (readout, dofs, factor_entries, newton, field) = if run.nonlinear {
                let model = TlSolid::new(&solid.problem, tolerances).map_err(SensorError::Fe)?;
                let loads = &solid.problem.load_cases[0];
                let sol = match coarser {
                    Some(c) => model.solve_from(loads, |p| c.displacement_m(p)),
                    None => model.solve(loads),
                }
                .map_err(SensorError::Fe)?;
                (
                    scene_model.read(g, &solid, &sol)?,
                    model.n_free_dofs(),
                    model.factor_len(),
                    Some(sol.stats()),
                    Some(sol),
                )
            } else {
                let model = SolidModel::new(&solid.problem).map_err(SensorError::Fe)?;
                let sol = model
                    .solve(&solid.problem.load_cases)
                    .map_err(SensorError::Fe)?;
                (
                    scene_model.read(g, &solid, &sol[0])?,
                    model.n_free_dofs(),
                    model.factor_len(),
                    None,
                    None,
                )
            };
            let level = SolidLevel {
                element_um: opts.element_um,
                span_element_um: opts.span_element_um,
                dofs,
                newton_iterations: newton.map(|n| n.iterations),
                factorisations: newton.map(|n| n.factorisations),
                single_precision_factorisations: newton.map(|n| n.single_precision),
                factor_entries,
                edge_moved_um: solid.edge_moved_um,
                seconds: start.elapsed().as_secs_f64(),
                readout,
            };
            Ok((level, solid.loaded_fraction[0], field))
        };
    let graded_mesh = |level: usize, local_refinement: bool| SolidMeshOptions {
        tooth_edge_grading: run.graded,
        shear: if run.tied_shear {
            TransverseShear::Tied
        } else {
            TransverseShear::Displacement
        },
        local_refinement,
        ..SolidMeshOptions::level(COARSE_ELEMENT_UM, level)
    };
    // A mesh built and analysed, not solved: its factor's size, or the refusal of a mesh that
    // cannot fit in memory (`fe::memory`).
    let analyse = |opts: SolidMeshOptions| -> Result<usize, SensorError> {
        let solid = scene_model.build(g, base, opts, graded_teeth)?;
        Ok(TlSolid::new(&solid.problem, TlOptions::default())
            .map_err(SensorError::Fe)?
            .factor_len())
    };
    // The finest level's factor size under either grading.
    let factor_size = |local: bool| analyse(graded_mesh(levels - 1, local));
    // Too large to solve here: auto then takes the other grading. Any other error is the run's.
    let too_large = |e: &SensorError| {
        matches!(
            e,
            SensorError::Fe(FeError::TooLarge { .. } | FeError::OutOfMemory { .. })
        )
    };
    let (local_refinement, grading_choice) = match run.grading {
        SolidGrading::Local => (true, None),
        SolidGrading::Lines | SolidGrading::Uniform => (false, None),
        // The smaller factor.
        SolidGrading::Auto => {
            let choice = |local, lines, refused: Option<&SensorError>| {
                Some(GradingChoice {
                    local_factor_entries: local,
                    lines_factor_entries: lines,
                    refused: refused.map(refusal),
                })
            };
            match (factor_size(true), factor_size(false)) {
                (Ok(local), Ok(lines)) => (local < lines, choice(Some(local), Some(lines), None)),
                (Ok(local), Err(e)) if too_large(&e) => (true, choice(Some(local), None, Some(&e))),
                (Err(e), Ok(lines)) if too_large(&e) => {
                    (false, choice(None, Some(lines), Some(&e)))
                }
                (Err(e), _) | (_, Err(e)) => return Err(e),
            }
        }
    };
    // Every mesh of the run, the thickness check's too, graded alike.
    let mesh = |level: usize| graded_mesh(level, local_refinement);
    // Level 0 again with every brick of the plate and the teeth bisected (the teeth's grading
    // kept): the edges' thickness check (below).
    let doubled = || {
        let mut opts = mesh(0);
        opts.brick_halvings += 1;
        opts
    };
    // The largest meshes first, analysed but not solved: a run whose finest level or thickness
    // check cannot fit in memory (`fe::memory`) stops in seconds, not after its first levels.
    if levels > 1 {
        // Auto analysed the finest level already.
        let finest = (grading_choice.is_none()).then(|| mesh(levels - 1));
        let largest = finest.into_iter().chain((levels >= 3).then(doubled));
        for opts in largest {
            analyse(opts)?;
        }
    }
    // The nonlinear solve of each level starts from the coarser level's field.
    let mut coarser: Option<crate::fe::solid::TlSolution> = None;
    // The levels refine in plane only; the edges' stresses also move with the bricks through
    // the thickness (their submodels sit inside the first one): level 0 again with twice the
    // bricks through the plate and the teeth measures it, where there is an estimate to add it
    // to (three levels). It is solved right after level 0, from its field: the doubled bricks
    // only halve level 0's, so that field lies in its space and its first correction is what
    // the doubled bricks change ([`thickness_check_newton`]).
    let mut edge_thickness = Vec::new();
    for level in 0..levels {
        let (answer, loaded, field) = solve(mesh(level), coarser.as_ref(), TlOptions::default())?;
        contact = contact.min(loaded);
        coarser = field;
        if level == 0 && levels >= 3 && !answer.readout.edge_stress.is_empty() {
            let (thick, _, thick_field) =
                solve(doubled(), coarser.as_ref(), thickness_check_newton())?;
            // Eight bricks in boxes round the readings, four elsewhere, from the four-brick
            // field (whose space it holds): the third value gives the thickness its own rate.
            let finer = eight_brick_mesh(doubled(), &answer.readout.edge_stress, g);
            // One that cannot fit in memory (refused at its symbolic analysis, before any
            // numeric work) leaves the check at two values (the corner's rate).
            let eight = match solve(finer, thick_field.as_ref(), thickness_check_newton()) {
                Ok((l, ..)) => Some(l),
                Err(e) if too_large(&e) => None,
                Err(e) => return Err(e),
            };
            edge_thickness = thickness_checks(
                &answer.readout.edge_stress,
                &thick.readout.edge_stress,
                eight.as_ref().map(|l| l.readout.edge_stress.as_slice()),
            );
        }
        out.push(answer);
    }
    let tables: Vec<Vec<(String, &'static str, f64, f64)>> = out
        .iter()
        .map(|l| quantity_table(g, &l.readout, force_n))
        .collect();
    let finest = tables.last().expect("at least one level");
    let r = 2f64.sqrt();
    let quantities: Vec<SolidQuantity> = finest
        .iter()
        .map(|(name, unit, value, scale)| {
            // By name: a level may lack a quantity another has (an edge outside the part).
            let at = |t: &Vec<(String, &'static str, f64, f64)>| {
                t.iter().find(|q| q.0 == *name).map(|q| q.2)
            };
            let n = tables.len();
            let three = (n >= 3)
                .then(|| Some((at(&tables[n - 3])?, at(&tables[n - 2])?, *value)))
                .flatten()
                .map(|(a, b, c)| ThreeMesh::new(a, b, c, r, r));
            // An edge stress takes the thickness check's correction and adds its corner
            // submodel's own estimate and the check's.
            let is = |kind: EdgeKind| format!("{}_stress", kind.as_str()) == *name;
            let check = edge_thickness.iter().find(|c| is(c.kind));
            let correction = check.map_or(0.0, |c| c.correction_mpa);
            let submodel = out
                .last()
                .and_then(|l| l.readout.edge_stress.iter().find(|e| is(e.kind)))
                .map_or(0.0, |e| e.submodel_error_mpa)
                + check.map_or(0.0, |c| c.error_mpa);
            let scale = scale.max(f64::MIN_POSITIVE);
            let submodel = submodel / scale;
            let extrapolated = three.map_or(*value, |t| t.richardson.extrapolated) + correction;
            let plate_value = plate.iter().find(|(n, _)| n == name).map(|p| p.1);
            SolidQuantity {
                name: name.clone(),
                unit,
                value: *value + correction,
                discretisation: three.map(|t| t.fine_error() / scale + submodel),
                extrapolated,
                plate_value,
                plate_difference: plate_value.map(|p| (p - extrapolated).abs() / scale),
            }
        })
        .collect();
    let converged = quantities
        .iter()
        .filter(|q| q.name != "max_principal_stress")
        .all(|q| q.discretisation.is_some_and(|d| d <= tol));
    let part_solved = match (scene_model.mirror_x_um, scene_model.mirror_y_um) {
        (None, None) => "whole die".to_string(),
        (Some(x), None) => format!("half, mirror x = {:.3} mm", x * 1e-3),
        (None, Some(y)) => format!("half, mirror y = {:.3} mm", y * 1e-3),
        (Some(x), Some(y)) => format!(
            "quarter, mirrors x = {:.3} mm and y = {:.3} mm",
            x * 1e-3,
            y * 1e-3
        ),
    };
    Ok(SolidReport {
        scene: scene.name.clone(),
        force_n,
        part_solved,
        base: match base {
            Base::Rigid => "rigid".into(),
            Base::Elastic {
                thickness_um, e_pa, ..
            } => {
                // MPa below 1 GPa: a 1 MPa rubber base read "E 0.00 GPa".
                let e = if e_pa >= 1e9 {
                    format!("{:.2} GPa", e_pa * 1e-9)
                } else {
                    format!("{:.2} MPa", e_pa * 1e-6)
                };
                format!("elastic, {thickness_um:.0} um, E {e}")
            }
        },
        nonlinear: run.nonlinear,
        graded: run.graded,
        tied_shear: run.tied_shear,
        local_refinement,
        grading_choice,
        graded_teeth: if run.graded {
            g.etched.tooth_tops_um.len()
        } else {
            graded_teeth
                .iter()
                .filter(|&&i| i < g.etched.tooth_tops_um.len())
                .count()
        },
        plate_rung: String::new(),
        levels: out,
        edge_thickness,
        quantities,
        converged,
        contact_on_top_faces: contact,
    })
}

/// The solid rung on `scene` beside the plate rung the ladder picks for it at `acc` (its
/// tolerance and levels): where that is the large-deflection plate the solid is solved
/// geometrically nonlinear and compared with it, else linear and compared with the linear plate.
/// Each quantity's difference is that plate rung's model error as the solid measures it.
/// `answered` is the caller's own answer to `scene` at `acc`, if it has one: when `acc` is auto
/// it is auto's answer, so the plate ladder is not solved again for the comparison.
pub fn solid_against_plate(
    g: &SensorGeometry,
    scene: &Scene,
    run: SolidRun,
    acc: super::Accuracy,
    answered: Option<&super::SceneReport>,
) -> Result<SolidReport, SensorError> {
    use super::evaluate::ModelKind;
    let is_plate = |r: &super::SceneReport| {
        matches!(
            r.model.kind,
            ModelKind::LargeDeflectionPlate | ModelKind::Plate
        )
    };
    let solved;
    let auto = match answered {
        Some(r) if acc.model == super::ModelChoice::Auto => r,
        _ => {
            solved = super::evaluate(g, scene, acc.with_model(super::ModelChoice::Auto))?;
            &solved
        }
    };
    let nonlinear = auto.model.kind == ModelKind::LargeDeflectionPlate;
    // The solid is compared with a plate rung: auto's answer when it is one, else the linear plate.
    let linear;
    let plate = if is_plate(auto) {
        auto
    } else {
        linear = super::evaluate(g, scene, acc.with_model(super::ModelChoice::Plate))?;
        &linear
    };
    let values: Vec<(String, f64)> = plate
        .quantities
        .iter()
        .map(|q| (q.name.clone(), q.value))
        .collect();
    // Graded where the plate finds the worst tooth base: the uniform levels read that edge a
    // quarter low on the bundled design, beyond their estimate (README).
    let mut report = evaluate_solid(
        g,
        scene,
        SolidRun { nonlinear, ..run },
        &values,
        &plate.hot_teeth,
    )?;
    report.plate_rung = plate.model.kind.to_string();
    Ok(report)
}

impl SolidReport {
    /// Quantities where the plate rung and the solid may differ by more than `tol` (relative to
    /// the quantity's scale), worst first, as the difference plus the solid's own discretisation
    /// estimate: agreement is only claimed where the solid is fine enough to show it (without
    /// an estimate, the difference is taken as it is). The peak stress at a re-entrant corner is
    /// left out (the plate has no such value).
    pub fn disagreements(&self, tol: f64) -> Vec<(&str, f64)> {
        let mut v: Vec<(&str, f64)> = self
            .quantities
            .iter()
            .filter_map(|q| {
                q.plate_difference
                    .map(|d| (q.name.as_str(), d + q.discretisation.unwrap_or(0.0)))
            })
            .filter(|&(_, d)| d.is_nan() || d > tol)
            .collect();
        v.sort_by(|a, b| b.1.total_cmp(&a.1));
        v
    }
}

impl super::SceneReport {
    /// Takes the plate rung's model error from the solid (issue 16, item 4): each quantity the
    /// solid also read gets as its `model` part the difference from the solid's value plus the
    /// solid's own estimate (what [`SolidReport::disagreements`] weighs), or the part it had when
    /// that is larger; the totals, the scene's worst error and `converged` follow. Only where the
    /// solid was compared with this report's rung; the singular peak stress is left as it is.
    /// Returns how many quantities took a model part from the solid.
    pub fn take_model_error_from(
        &mut self,
        g: &SensorGeometry,
        solid: &SolidReport,
        tol: f64,
    ) -> usize {
        self.take_safety_from(g, solid);
        if solid.plate_rung != self.model.kind.to_string() {
            return 0;
        }
        let mut taken = 0;
        for q in self
            .quantities
            .iter_mut()
            .filter(|q| q.name != super::rung::STRESS_PEAK)
        {
            let Some(s) = solid.quantities.iter().find(|s| s.name == q.name) else {
                continue;
            };
            let Some(d) = s.plate_difference else {
                continue;
            };
            // A NaN difference (no scale) is unknown: an infinite model error, never a pass.
            let m = if d.is_finite() {
                d + s.discretisation.unwrap_or(0.0)
            } else {
                f64::INFINITY
            };
            let model = q.error.model.map_or(m, |old| old.max(m));
            q.error = super::ErrorParts::new(q.error.discretisation, Some(model));
            q.converged = q.error.met(tol);
            taken += 1;
        }
        self.error = super::rung::worst(&self.quantities);
        self.error_estimate = self.error.total;
        let was = self.converged;
        self.converged = self
            .quantities
            .iter()
            .filter(|q| q.name != super::rung::STRESS_PEAK)
            .all(|q| q.converged);
        if was && !self.converged {
            use crate::finding::{Finding, SceneCode};
            self.warnings.push(Finding::warning(
                SceneCode::NotConverged,
                format!(
                    "with the model error the solid rung measured ({}), the estimated error \
                     {} is above the tolerance {tol:.0e}",
                    self.error
                        .model
                        .map_or_else(|| "unknown".into(), |m| format!("{m:.2e}")),
                    self.error
                        .total
                        .map_or_else(|| "unknown".into(), |t| format!("{t:.2e}")),
                ),
            ));
        }
        taken
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A solid report that read only `stresses` (name, MPa), as its extrapolated values with no
    /// estimate, compared with `plate_rung`.
    fn solid_reading(stresses: &[(&str, f64)], plate_rung: &str) -> SolidReport {
        SolidReport {
            scene: "s".into(),
            force_n: 1.0,
            part_solved: "whole die".into(),
            base: "rigid".into(),
            nonlinear: false,
            graded: false,
            tied_shear: true,
            local_refinement: false,
            grading_choice: None,
            graded_teeth: 0,
            plate_rung: plate_rung.into(),
            levels: Vec::new(),
            edge_thickness: Vec::new(),
            quantities: stresses
                .iter()
                .map(|&(name, v)| SolidQuantity {
                    name: name.into(),
                    unit: "MPa",
                    value: v,
                    discretisation: None,
                    extrapolated: v,
                    plate_value: None,
                    plate_difference: None,
                })
                .collect(),
            converged: true,
            contact_on_top_faces: 1.0,
        }
    }

    /// The bundled design with `centre-1n` at `y_um`, its declared limits and the auto answer.
    fn answer(
        y_um: f64,
    ) -> (
        SensorGeometry,
        super::super::SceneReport,
        crate::process::Limits,
    ) {
        let text = std::fs::read_to_string("process/mis-grasper.yaml").expect("bundled file");
        let sets = vec![format!("checks.scenes[0].load.point.y_um={y_um}")];
        let p = crate::process::load_str(&text, "mis-grasper.yaml", &sets)
            .expect("valid process")
            .process;
        let scene = p.checks.scenes[0].clone();
        let g = SensorGeometry::new(&crate::design::Design::new(p).expect("design"));
        let r = super::super::evaluate(&g, &scene, super::super::Accuracy::new(0.01, 3))
            .expect("solved");
        (g, r, scene.limits)
    }

    /// A load wholly on a support is judged by the solid's governing stress (`--verify-solid`),
    /// which reads the support's edges; the plate rungs alone leave it not judged, and a solid
    /// that finds only compression leaves it so.
    #[test]
    fn a_load_on_a_support_takes_the_solids_stress() {
        use super::super::StressFrom;
        let (g, mut r, limits) = answer(1000.0);
        assert_eq!(r.stress_from, StressFrom::OnSupport);
        let bound = limits
            .min_safety_factor
            .expect("centre-1n declares a safety factor");
        let failed = crate::report::limits::check_limits(&r, &limits);
        assert!(failed.iter().any(|c| !c.passed && c.value.is_none()));

        let mut squeezed = r.clone();
        let solid = solid_reading(&[("max_stress_averaged", -3.0)], "plate");
        squeezed.take_model_error_from(&g, &solid, 0.01);
        assert_eq!(squeezed, r, "compression alone judges nothing");

        let (vertex, edge) = (21.2, 0.8);
        let solid = solid_reading(
            &[
                ("max_stress_averaged", -0.3),
                ("tooth_vertex_stress", vertex),
                ("support_edge_stress", edge),
            ],
            "plate",
        );
        r.take_model_error_from(&g, &solid, 0.01);
        assert_eq!(r.stress_from, StressFrom::SolidOnSupport);
        assert_eq!(r.max_stress_mpa, vertex);
        let sf = g.fracture_strength_mpa / vertex;
        assert!((r.safety_factor - sf).abs() <= 1e-12 * sf);
        let load = r.force_n.abs() * g.fracture_strength_mpa / g.safety_factor / vertex;
        assert!((r.max_permissible_load_n - load).abs() <= 1e-12 * load);
        assert!(r
            .warnings
            .iter()
            .any(|w| w.message.contains("tooth_vertex_stress")));
        // The limits judge it now: the solid's value carries its estimate and is the top rung.
        let checks = crate::report::limits::check_limits(&r, &limits);
        let safety = checks
            .iter()
            .find(|c| c.limit == crate::process::LimitKind::MinSafetyFactor)
            .expect("checked");
        assert!(safety.passed && sf > bound, "{safety}");
        assert_eq!((safety.value, safety.error_rel), (Some(sf), 0.0));
        assert!(!safety.model_not_estimated);
    }

    /// A factor under the required one (`materials.silicon.safety_factor`) is one
    /// `BELOW_SAFETY_FACTOR` warning, renewed when the solid lowers the factor and gone when the
    /// requirement is met; a load not judged gets none.
    #[test]
    fn a_factor_under_the_required_one_is_a_warning() {
        use crate::finding::{Code, SceneCode};
        let below = |r: &super::super::SceneReport| -> Vec<String> {
            r.warnings
                .iter()
                .filter(|w| w.code == Code::Scene(SceneCode::BelowSafetyFactor))
                .map(|w| w.message.clone())
                .collect()
        };
        // The bundled centre load: 2.21 against the required 3 on the plate.
        let (g, mut r, _) = answer(7500.0);
        assert!(r.safety_factor < g.safety_factor, "{}", r.safety_factor);
        let first = below(&r);
        assert_eq!(first.len(), 1, "{first:?}");
        assert!(first[0].contains(&format!("safety factor {:.2}", r.safety_factor)));
        assert!(r.max_permissible_load_n < r.force_n.abs());
        let solid = solid_reading(&[("tooth_base_stress", 2.0 * r.max_stress_mpa)], "none");
        r.take_model_error_from(&g, &solid, 0.01);
        let lowered = below(&r);
        assert_eq!(lowered.len(), 1, "{lowered:?}");
        assert_ne!(lowered, first);
        assert!(lowered[0].contains(&format!("safety factor {:.2}", r.safety_factor)));
        let mut met = g.clone();
        met.safety_factor = 0.5 * r.safety_factor;
        r.note_safety_shortfall(&met);
        assert!(below(&r).is_empty());
        let (_, on_support, _) = answer(1000.0);
        assert!(below(&on_support).is_empty());
    }

    /// A plate answer takes the solid's factor only where it is lower, keeping its own stress.
    #[test]
    fn a_plate_answer_takes_a_lower_factor_from_the_solid() {
        let (g, r, _) = answer(7500.0);
        let (sf, stress) = (r.safety_factor, r.max_stress_mpa);
        assert!(r.stress_from.judged() && sf.is_finite());
        let mut higher = r.clone();
        let solid = solid_reading(&[("tooth_base_stress", 0.5 * stress)], "none");
        higher.take_model_error_from(&g, &solid, 0.01);
        assert_eq!(higher, r);
        let mut lower = r.clone();
        let solid = solid_reading(&[("tooth_base_stress", 2.0 * stress)], "none");
        lower.take_model_error_from(&g, &solid, 0.01);
        assert!((lower.safety_factor - 0.5 * sf).abs() <= 1e-12 * sf);
        assert!(
            (lower.max_permissible_load_n - 0.5 * r.max_permissible_load_n).abs()
                <= 1e-12 * r.max_permissible_load_n
        );
        assert_eq!(
            (lower.max_stress_mpa, lower.stress_from),
            (stress, r.stress_from)
        );
        // A plate that finds only compression (factor and load infinite) takes a solid edge in
        // tension: its factor and the permissible load from it, finite.
        let mut squeezed = r.clone();
        (squeezed.safety_factor, squeezed.max_permissible_load_n) = (f64::INFINITY, f64::INFINITY);
        squeezed.take_model_error_from(&g, &solid, 0.01);
        assert!((squeezed.safety_factor - 0.5 * sf).abs() <= 1e-12 * sf);
        assert!(
            (squeezed.max_permissible_load_n - 0.5 * r.max_permissible_load_n).abs()
                <= 1e-12 * r.max_permissible_load_n
        );
    }

    /// The bundled design with `sets`, and 1 N on a 500 um disc at `(x, y)` um.
    fn design_and_point(sets: &[&str], (x_um, y_um): (f64, f64)) -> (SensorGeometry, Scene) {
        let text = std::fs::read_to_string("process/mis-grasper.yaml").expect("bundled file");
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let p = crate::process::load_str(&text, "mis-grasper.yaml", &sets)
            .expect("valid process")
            .process;
        let g = SensorGeometry::new(&crate::design::Design::new(p).expect("design"));
        let scene = Scene {
            name: "p".into(),
            load: SceneLoad::Point {
                x_um,
                y_um,
                force_n: 1.0,
                radius_um: 500.0,
            },
            limits: Default::default(),
        };
        (g, scene)
    }

    /// The thickness check stops after one Newton correction from level 0's field (whose space
    /// its doubled bricks hold), and reads the edges' stresses as the check solved to the
    /// levels' tolerances does, to a hundredth of what the doubled bricks change.
    #[test]
    fn the_thickness_check_takes_one_correction_from_level_0() {
        let (g, scene) = design_and_point(
            &[
                "geometry.die_length_um=12000",
                "geometry.teeth.count_x=4",
                "checks.scenes[0].load.point.x_um=6000",
                "checks.scenes[1].load.point.x_um=6000",
            ],
            (4500.0, 5000.0),
        );
        let sm = SceneModel::new(&g, &scene, true).expect("scene");
        let level0 = SolidMeshOptions::level(COARSE_ELEMENT_UM, 0);
        let doubled = SolidMeshOptions {
            brick_halvings: level0.brick_halvings + 1,
            ..level0.clone()
        };
        let coarse = sm.build(&g, Base::Rigid, level0, &[]).expect("level 0");
        let start = TlSolid::new(&coarse.problem, TlOptions::default())
            .and_then(|m| m.solve(&coarse.problem.load_cases[0]))
            .expect("level 0 solved");
        let two = sm.read(&g, &coarse, &start).expect("read").edge_stress;
        let thick = sm.build(&g, Base::Rigid, doubled, &[]).expect("doubled");
        let solve = |newton: TlOptions| {
            let sol = TlSolid::new(&thick.problem, newton)
                .and_then(|m| {
                    m.solve_from(&thick.problem.load_cases[0], |p| start.displacement_m(p))
                })
                .expect("check solved");
            let read = sm.read(&g, &thick, &sol).expect("read").edge_stress;
            (sol.stats().iterations, read)
        };
        let (check_its, check) = solve(thickness_check_newton());
        let (full_its, full) = solve(TlOptions::default());
        assert_eq!(check_its, 1);
        assert!(full_its > 1, "{full_its}");
        assert_eq!(check.len(), 3, "{check:?}");
        for (c, f) in check.iter().zip(&full) {
            let at_level0 = two.iter().find(|e| e.kind == f.kind).expect("same edges");
            let change = (f.stress_mpa - at_level0.stress_mpa).abs();
            let off = (c.stress_mpa - f.stress_mpa).abs();
            eprintln!("{:?}: {off:.2e} MPa off, of {change:.3} MPa", f.kind);
            assert!(c.kind == f.kind && change > 0.0, "{c:?} {f:?}");
            assert!(
                off <= 1e-2 * change,
                "{:?}: {off} MPa off, of {change}",
                f.kind
            );
        }
    }

    /// The check's third solve, eight bricks in boxes round the readings and four elsewhere,
    /// reads the edges as eight bricks through the whole die do, at a fraction of the dofs, in
    /// one correction from the four-brick field (which its space holds). The tiny test die
    /// (6 x 9 mm, 2 x 3 teeth), its centre loaded with 1 N.
    #[test]
    fn eight_bricks_in_boxes_read_the_edges_as_eight_through_the_die() {
        let (g, scene) = design_and_point(
            &[
                "geometry.die_length_um=6000",
                "geometry.die_width_um=9000",
                "geometry.teeth.count_x=2",
                "geometry.teeth.count_y=3",
                "checks.scenes=[]",
            ],
            (3000.0, 4500.0),
        );
        let sm = SceneModel::new(&g, &scene, true).expect("scene");
        let level0 = SolidMeshOptions::level(COARSE_ELEMENT_UM, 0);
        let with = |halvings: u32| SolidMeshOptions {
            brick_halvings: halvings,
            ..level0.clone()
        };
        type Solved = (
            usize,
            usize,
            crate::fe::solid::TlSolution,
            Vec<super::super::edge_stress::EdgeStress>,
        );
        let solve = |opts: SolidMeshOptions,
                     from: Option<&crate::fe::solid::TlSolution>,
                     newton: TlOptions|
         -> Solved {
            let solid = sm.build(&g, Base::Rigid, opts, &[]).expect("mesh");
            let model = TlSolid::new(&solid.problem, newton).expect("model");
            let loads = &solid.problem.load_cases[0];
            let sol = match from {
                Some(f) => model.solve_from(loads, |p| f.displacement_m(p)),
                None => model.solve(loads),
            }
            .expect("solved");
            let read = sm.read(&g, &solid, &sol).expect("read").edge_stress;
            (model.n_free_dofs(), sol.stats().iterations, sol, read)
        };
        let (_, _, start, two) = solve(with(0), None, TlOptions::default());
        let (_, _, four_field, four) = solve(with(1), Some(&start), TlOptions::default());
        let boxed = eight_brick_mesh(with(1), &two, &g);
        assert_eq!(boxed.fine_brick_boxes_um.len(), two.len());
        let (box_dofs, box_its, _, in_boxes) =
            solve(boxed, Some(&four_field), thickness_check_newton());
        let (all_dofs, _, _, everywhere) = solve(with(2), Some(&four_field), TlOptions::default());
        assert_eq!(box_its, 1);
        assert!(box_dofs < all_dofs, "{box_dofs} {all_dofs}");
        assert_eq!(in_boxes.len(), everywhere.len());
        let checks = thickness_checks(&two, &four, Some(&in_boxes));
        for e in &everywhere {
            let find = |v: &[super::super::edge_stress::EdgeStress]| {
                v.iter()
                    .find(|b| b.kind == e.kind)
                    .expect("same edges")
                    .stress_mpa
            };
            let (s2, f, b) = (find(&two), find(&four), find(&in_boxes));
            let c = checks.iter().find(|c| c.kind == e.kind).expect("checked");
            eprintln!(
                "{:?}: 4 bricks {f:.3}, 8 in boxes {b:.3}, 8 everywhere {:.3} MPa, left {:.3}; \
                 dofs {box_dofs} against {all_dofs}",
                e.kind, e.stress_mpa, c.error_mpa
            );
            // The boxes take most of the step from four to eight bricks, and the corrected
            // value with the error left reaches the whole die's.
            let step = e.stress_mpa - f;
            assert!((b - f) * step > 0.0 && (b - f).abs() >= 0.5 * step.abs());
            assert!(
                (s2 + c.correction_mpa - e.stress_mpa).abs() <= c.error_mpa,
                "{:?}: boxes {b}, everywhere {}, four {f}: {c:?}",
                e.kind,
                e.stress_mpa
            );
        }
    }
}
