//! Solving scenes to a tolerance: successively refined meshes, three-mesh error estimates, and the
//! per-scene report (the JSON contract of `tactfab fe --json`).

use std::time::Instant;

use serde::Serialize;

use crate::fe::problem::Axis as FeAxis;
use crate::fe::solution::LINEAR_RANGE_LIMIT;
use crate::fe::{
    Factorised, InPlane, LineSupport, NonlinearOptions, PlateProblem, RectMesh, SupportKind,
    ThicknessRegion, VonKarman,
};
use crate::finding::{Finding, SceneCode};
use crate::process::{Scene, SceneLoad};

use super::beam_model::{beam_answer, beam_applies, beam_error_estimate};
use super::check::{check_scene, overhang, SensorError, MAX_SOLUTION_VALUES};
use super::edge_section::plate_tooth_base_stress;

use super::geometry::{ElectrodeSide, SensorGeometry};
use super::mesh_lines::{
    base_lines, grading_description, subdivide, MeshOptions, COARSE_ELEMENT_UM, SUBDIVISIONS,
};
use super::readout::{group_for, read, ElectrodeReading, Readout};
use super::rung::{
    discretisation, linear_model_error, quantities, quantity_names, worst, ErrorParts, ModelChoice,
    QuantityError, STRESS_PEAK, TOOTH_BASE_STRESS,
};
use super::scene::{split, SceneLoads};
use super::symmetry::Symmetry;
use super::touch_down::{find_factor, scaled_loads, TouchDown};

/// How accurate an answer must be: the estimated relative error to reach, and the most mesh
/// levels to spend on it (level k splits the coarse mesh [`SUBDIVISIONS`]`[k]` times).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Accuracy {
    pub tol_rel: f64,
    pub max_levels: usize,
    /// The rung to use ([`ModelChoice::Auto`]: the cheapest that meets `tol_rel`).
    pub model: ModelChoice,
    /// What the supports do in-plane on the large-deflection rung.
    pub in_plane: InPlane,
}

impl Accuracy {
    /// `tol_rel` in (0, 1) is the caller's to check (the CLI's value parsers do); levels beyond
    /// [`SUBDIVISIONS`] are capped. The rung is chosen automatically, supports immovable in-plane.
    pub const fn new(tol_rel: f64, max_levels: usize) -> Self {
        Accuracy {
            tol_rel,
            max_levels,
            model: ModelChoice::Auto,
            in_plane: InPlane::Immovable,
        }
    }

    /// The same accuracy on a forced rung.
    pub const fn with_model(mut self, model: ModelChoice) -> Self {
        self.model = model;
        self
    }
}

/// Which rung of the model ladder answered.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ModelKind {
    /// The fixed-fixed strip (paper 001 Eq. 3-6).
    Beam,
    /// The Kirchhoff BFS plate (linear).
    Plate,
    /// The von Karman plate: BFS bending with in-plane membrane displacements, Newton solved.
    LargeDeflectionPlate,
    /// The load lies wholly over a support: no plate solve.
    Direct,
}

impl ModelKind {
    /// A finite-element plate rung (linear or large-deflection): the answers with mesh levels.
    pub fn is_plate(self) -> bool {
        matches!(self, ModelKind::Plate | ModelKind::LargeDeflectionPlate)
    }
}

impl std::fmt::Display for ModelKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ModelKind::Beam => "beam",
            ModelKind::Plate => "plate",
            ModelKind::LargeDeflectionPlate => "large_deflection_plate",
            ModelKind::Direct => "direct",
        })
    }
}

/// Which model answered and what it cost.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModelInfo {
    pub kind: ModelKind,
    pub elements: usize,
    pub dofs: usize,
    /// Mesh levels solved (the last one answered).
    pub levels: usize,
    pub max_element_um: f64,
    /// Observed convergence order of the deflection at the load (never assumed).
    pub observed_order: Option<f64>,
    /// The part of the plate solved when the scenes are mirror-symmetric ("half, mirror y =
    /// 7.500 mm"); elements and dofs are those of that part. None: the whole plate.
    pub symmetry: Option<String>,
    /// How the coarsest mesh was graded ([`MeshOptions::graded`]); None: only feature lines.
    pub grading: Option<String>,
    /// Why this rung answered.
    pub reason: String,
    /// The in-plane support condition (large-deflection plate only).
    pub in_plane: Option<InPlane>,
    /// Newton iterations over all levels and load steps (large-deflection plate only); each is
    /// one numeric factorisation on the level's shared symbolic analysis.
    pub newton_iterations: Option<usize>,
}

impl ModelInfo {
    /// The load lies wholly over the supports: no plate solve.
    fn direct() -> Self {
        ModelInfo {
            kind: ModelKind::Direct,
            elements: 0,
            dofs: 0,
            levels: 1,
            max_element_um: 0.0,
            observed_order: None,
            symmetry: None,
            grading: None,
            reason: "the load lies wholly over the supports".into(),
            in_plane: None,
            newton_iterations: None,
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Reactions {
    pub support1: f64,
    pub support2: f64,
}

/// One mesh level of a scene's convergence history.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LevelRecord {
    pub max_element_um: f64,
    pub elements: usize,
    pub dofs: usize,
    pub time_ms: f64,
    pub deflection_at_load_um: f64,
    /// Charge of the electrode that is largest on the finest mesh.
    pub charge_pc: f64,
    /// Estimate after this level (needs three levels).
    pub error_estimate: Option<f64>,
    pub observed_order: Option<f64>,
}

/// Everything one scene reports.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SceneReport {
    pub scene: String,
    pub force_n: f64,
    pub model: ModelInfo,
    /// Wall time of every level solved for this answer.
    pub solve_ms: f64,
    /// Estimated relative error of the readings: the worst total (discretisation + model) over
    /// [`SceneReport::quantities`]; None before three levels.
    pub error_estimate: Option<f64>,
    /// The worst of each error part over the quantities.
    pub error: ErrorParts,
    /// Every quantity met the tolerance.
    pub converged: bool,
    pub deflection_at_load_um: f64,
    pub max_deflection_um: f64,
    /// The stress the safety factor is judged on ([`SceneReport::stress_from`]): the larger of
    /// the largest principal stress over the contact patch averaged over a square a few plate
    /// thicknesses wide and the teeth's base-edge stress at the critical distance (the point
    /// peak is in [`SceneReport::quantities`] with its convergence).
    pub max_stress_mpa: f64,
    /// Which stress that is.
    pub stress_from: StressFrom,
    pub safety_factor: f64,
    /// Load at which the stress reaches fracture / safety factor (linear scaling).
    pub max_permissible_load_n: f64,
    /// Largest |V| / F over the electrodes, and which one.
    pub sensitivity_mv_per_n: f64,
    pub most_sensitive: String,
    pub reactions_n: Reactions,
    pub electrodes: Vec<ElectrodeReading>,
    /// Each quantity with its own error (deflection, charges, reactions); a voltage has its
    /// charge's relative error (V = Q / C).
    pub quantities: Vec<QuantityError>,
    /// The load of this scene's pattern at which the plate reaches the channel floor.
    pub touch_down: Option<TouchDown>,
    pub warnings: Vec<Finding>,
    /// Per mesh level: size, cost, values and the estimate (`tactfab fe --convergence`).
    pub convergence: Vec<LevelRecord>,
    /// The teeth (indices into the etched tooth tops) whose base-edge stress on the finest mesh
    /// is within [`HOT_TOOTH_FRACTION`](super::edge_section::HOT_TOOTH_FRACTION) of the
    /// largest: where the solid rung grades its mesh. Empty without the edge section.
    #[serde(skip)]
    pub hot_teeth: Vec<usize>,
}

/// Solves one scene; see [`evaluate_many`].
pub fn evaluate(
    g: &SensorGeometry,
    scene: &Scene,
    acc: Accuracy,
) -> Result<SceneReport, SensorError> {
    Ok(evaluate_many(g, std::slice::from_ref(scene), acc)?.remove(0))
}

/// Answers every scene with the cheapest model whose estimated error is under `tol`: the
/// fixed-fixed strip ([`beam_answer`](super::beam_answer)) for line loads on plates without teeth when its bound
/// allows, else the plate, all plate scenes on a shared sequence of meshes (one factorisation per
/// level, all scenes as one multi-column solve) until every estimate is under `tol` or `max_levels`
/// is reached. Mirror symmetry is used when every plate scene has it ([`Symmetry`]).
pub fn evaluate_many(
    g: &SensorGeometry,
    scenes: &[Scene],
    acc: Accuracy,
) -> Result<Vec<SceneReport>, SensorError> {
    evaluate_many_with(g, scenes, acc, MeshOptions::default())
}

/// [`evaluate_many`] with a choice of mesh sequence: symmetry off solves the whole plate (the
/// cross-check of the half model, `tactfab fe --no-symmetry`); graded meshes refine towards the
/// loads and tooth corners (`tactfab fe --graded`).
#[track_caller]
pub fn evaluate_many_with(
    g: &SensorGeometry,
    scenes: &[Scene],
    acc: Accuracy,
    mesh: MeshOptions,
) -> Result<Vec<SceneReport>, SensorError> {
    assert!(acc.max_levels >= 1, "at least one mesh level");
    for s in scenes {
        check_scene(s, g)?;
    }
    let tol = acc.tol_rel;
    let beam_error = beam_error_estimate(g);
    let beam_fits = |s: &Scene| match s.load {
        SceneLoad::Line { y_um, .. } => beam_applies(g, y_um),
        _ => false,
    };
    if acc.model == ModelChoice::Solid {
        return Err(SensorError::Scene {
            scene: scenes.first().map_or_else(String::new, |s| s.name.clone()),
            problem: "the solid rung answers single scenes (`fe --model solid`), not studies"
                .into(),
            hint: "use --model auto, plate or large-deflection here",
        });
    }
    if acc.model == ModelChoice::Beam {
        if let Some(s) = scenes.iter().find(|s| !beam_fits(s)) {
            return Err(SensorError::Scene {
                scene: s.name.clone(),
                problem: "the strip (--model beam) answers only line loads across a plate \
                          without teeth"
                    .into(),
                hint: "use --model auto, plate or large-deflection for this scene",
            });
        }
    }
    // The strip is linear: its model error is its bound against the linear plate plus the
    // linear plate's own (membrane) model error, estimated on the coarsest mesh.
    let candidates: Vec<usize> = (0..scenes.len())
        .filter(|&k| match acc.model {
            ModelChoice::Beam => true,
            ModelChoice::Auto => beam_fits(&scenes[k]) && beam_error < tol,
            _ => false,
        })
        .collect();
    let mut strip_error = vec![None; scenes.len()];
    if !candidates.is_empty() {
        let cand: Vec<Scene> = candidates.iter().map(|&k| scenes[k].clone()).collect();
        let coarse = Accuracy {
            max_levels: 1,
            ..acc.with_model(ModelChoice::Plate)
        };
        for (&k, r) in candidates
            .iter()
            .zip(evaluate_plate(g, &cand, coarse, mesh)?)
        {
            let e = beam_error + r.error.model.unwrap_or(0.0);
            if acc.model == ModelChoice::Beam || e < tol {
                strip_error[k] = Some(e);
            }
        }
    }
    let by_beam = |k: usize| strip_error[k].is_some();
    let plate_scenes: Vec<Scene> = (0..scenes.len())
        .filter(|&k| !by_beam(k))
        .map(|k| scenes[k].clone())
        .collect();
    let mut plate = if plate_scenes.is_empty() {
        Vec::new()
    } else {
        evaluate_plate(g, &plate_scenes, acc, mesh)?
    }
    .into_iter();
    scenes
        .iter()
        .enumerate()
        .map(|(k, s)| match (s.load.clone(), strip_error[k]) {
            (SceneLoad::Line { y_um, force_n }, Some(e)) => {
                beam_report(g, s, y_um, force_n, e, acc)
            }
            _ => plate.next().expect("one plate report per plate scene"),
        })
        .zip(scenes)
        .map(|(mut r, scene)| {
            let l = split(&scene.load, g);
            if r.touch_down.is_none() {
                r.touch_down = touch_down(g, &r, &l, acc, mesh)?;
            }
            if let Some(t) = r
                .touch_down
                .as_ref()
                .filter(|_| r.max_deflection_um >= g.gap_um)
            {
                r.warnings.push(Finding::error(
                    SceneCode::TouchDown,
                    format!(
                        "the largest deflection {:.1} um reaches the channel floor ({:.1} um \
                         under the plate) at {}: beyond it the floor carries load, which is \
                         not modelled, so these readings are not answers",
                        r.max_deflection_um,
                        t.gap_um,
                        t.load_n
                            .map_or_else(|| "an unknown load".into(), |f| format!("{f:.3} N"))
                    ),
                ));
                r.converged = false;
            }
            r.note_safety_shortfall(g);
            Ok(r)
        })
        .collect()
}

/// A scene answered by the strip model.
fn beam_report(
    g: &SensorGeometry,
    scene: &Scene,
    y_um: f64,
    force_n: f64,
    error: f64,
    acc: Accuracy,
) -> SceneReport {
    let tol = acc.tol_rel;
    let t0 = Instant::now();
    let b = beam_answer(g, y_um, force_n);
    let r = b.readout;
    let stress = b.stress_at_load_pa;
    let (best, sens) = most_sensitive(&r, force_n);
    SceneReport {
        scene: scene.name.clone(),
        force_n,
        model: ModelInfo {
            kind: ModelKind::Beam,
            elements: 0,
            dofs: 0,
            levels: 1,
            max_element_um: 0.0,
            observed_order: None,
            symmetry: None,
            grading: None,
            reason: match acc.model {
                ModelChoice::Beam => "forced by --model beam".into(),
                _ => format!(
                    "the strip qualifies: a line load across a plate without teeth, its model \
                     error {error:.2e} (its bound against the linear plate plus the linear \
                     plate's membrane model error) is under the tolerance {tol:.0e}"
                ),
            },
            in_plane: None,
            newton_iterations: None,
        },
        solve_ms: t0.elapsed().as_secs_f64() * 1e3,
        error_estimate: Some(error),
        error: ErrorParts::new(Some(0.0), Some(error)),
        quantities: {
            let mut v = vec![b.deflection_at_load_m];
            v.extend(r.electrodes.iter().map(|e| e.charge_pc));
            v.extend([r.support1_n, r.support2_n]);
            let model = vec![error; v.len()];
            quantities(g, &v, &vec![Some(0.0); v.len()], Some(&model), tol)
        },
        converged: error < tol,
        deflection_at_load_um: b.deflection_at_load_m * 1e6,
        max_deflection_um: b.max_deflection_m * 1e6,
        max_stress_mpa: stress * 1e-6,
        stress_from: StressFrom::StripAtLoad,
        safety_factor: safety_factor(g, stress),
        max_permissible_load_n: permissible_load_n(g, stress, force_n),
        sensitivity_mv_per_n: sens,
        most_sensitive: best,
        reactions_n: Reactions {
            support1: r.support1_n,
            support2: r.support2_n,
        },
        electrodes: r.electrodes,
        touch_down: None,
        warnings: Vec::new(),
        convergence: Vec::new(),
        hot_teeth: Vec::new(),
    }
}

/// The touch-down of a scene: the linear rungs scale with the load; the large-deflection plate
/// is solved again at scaled loads on the coarsest mesh, each value corrected by the ratio of
/// the answer's largest deflection to the coarse one at the scene's load.
fn touch_down(
    g: &SensorGeometry,
    r: &SceneReport,
    l: &SceneLoads,
    acc: Accuracy,
    mesh: MeshOptions,
) -> Result<Option<TouchDown>, SensorError> {
    let w1 = r.max_deflection_um;
    if r.model.kind == ModelKind::Direct || w1.is_nan() || w1 <= 0.0 || r.force_n == 0.0 {
        return Ok(None);
    }
    let gap = g.gap_um;
    let (factor, basis) = if r.model.kind == ModelKind::LargeDeflectionPlate {
        let opts = NonlinearOptions {
            in_plane: r.model.in_plane.unwrap_or(acc.in_plane),
            ..Default::default()
        };
        // One coarse plate for the whole search, each load continued from the last one's field.
        let cases = vec![l.plate.clone()];
        let sym = if mesh.symmetry {
            Symmetry::detect(g, &cases)
        } else {
            Symmetry::none(g)
        };
        let base = base_lines(g, std::slice::from_ref(l), &sym, &mesh);
        let vk = VonKarman::new(&build_problem(g, &base, 0, &sym)?, opts)?;
        let part = sym.restrict(&l.plate);
        let mut last: Option<crate::fe::PlateSolution> = None;
        let mut coarse = |s: f64| -> Result<f64, SensorError> {
            let loads = scaled_loads(&part, s);
            let (sol, _) = match &last {
                Some(p) => vk.solve_from(&loads, p)?,
                None => vk.solve(&loads)?,
            };
            let w = sol.max_deflection().w_m.abs() * 1e6;
            last = Some(sol);
            Ok(w)
        };
        let c = w1 / coarse(1.0)?;
        let h0 = COARSE_ELEMENT_UM;
        (
            find_factor(gap, w1, |s| coarse(s).map(|w| c * w))?,
            format!(
                "large-deflection plate at scaled loads on the {h0:.0} um mesh, scaled by the \
                 answer's deflection ({c:.4} x)"
            ),
        )
    } else {
        (
            (gap / w1 <= super::touch_down::MAX_FACTOR).then_some(gap / w1),
            format!("{}: the deflection scales with the load", r.model.kind),
        )
    };
    Ok(Some(TouchDown {
        gap_um: gap,
        load_n: factor.map(|s| s * r.force_n.abs()),
        basis,
    }))
}

/// The stress a scene's safety factor is judged on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StressFrom {
    /// The plate's largest principal stress over the contact, averaged over a square
    /// four plate thicknesses wide (`max_stress_averaged`).
    AveragedOverContact,
    /// The teeth's base-edge stress at the critical distance (`tooth_base_stress`).
    ToothBase,
    /// The strip's bending stress at the load line.
    StripAtLoad,
    /// None: the load stands wholly on a support (the direct model), so the plate does not bend,
    /// and the support, the film and the base under the load, which the plate rungs do not judge
    /// for fracture, carry it (the solid rung reads the support's edges: `--verify-solid` turns
    /// this into [`StressFrom::SolidOnSupport`]). The stress reads 0, and the safety factor and
    /// the permissible load are not judged (infinite in the report, null in JSON; a declared
    /// stress or safety-factor limit fails).
    OnSupport,
    /// A load wholly on a support, judged by the solid rung (`--verify-solid`): the stress is the
    /// solid's governing one ([`crate::sensor::solid::SolidReport::governing_stress`]: a sharp
    /// edge's at the critical distance or the averaged one, raised by its own estimate), which
    /// reads the support's edges that the plate rungs leave out.
    SolidOnSupport,
}

impl SceneReport {
    /// The estimated relative error (discretisation plus model, where compared) of what the
    /// pass/fail limits judge, in the order sensitivity, stress (the one the safety factor is
    /// judged on), deflection: the most sensitive electrode's charge, the stress `stress_from`
    /// names, the deflection at the load (the largest deflection has no estimate of its own).
    /// Charges are relative to the largest of their kind, which the most sensitive electrode
    /// usually is. A number without its own estimate (the strip's stress) takes the scene's;
    /// none at all is 0. With each, whether its model error was estimated (a finer rung
    /// compared: the linear plate against the large-deflection one, any plate rung against the
    /// solid under `--verify-solid`, the strip by its bound).
    pub fn limit_errors(&self) -> [(f64, bool); 3] {
        let of = |name: &str| {
            let q = self.quantities.iter().find(|q| q.name == name);
            let total = q
                .and_then(|q| q.error.total)
                .or(self.error_estimate)
                .filter(|e| e.is_finite())
                .unwrap_or(0.0);
            let model = q.map_or(self.error.model.is_some(), |q| q.error.model.is_some());
            (total, model)
        };
        let stress = match self.stress_from {
            StressFrom::ToothBase => of(super::rung::TOOTH_BASE_STRESS),
            StressFrom::AveragedOverContact | StressFrom::StripAtLoad | StressFrom::OnSupport => {
                of(super::rung::STRESS_AVERAGED)
            }
            // The solid's governing stress already carries its estimate, and the solid is the
            // top rung: no model error left to add.
            StressFrom::SolidOnSupport => (0.0, true),
        };
        [
            of(&format!("charge_{}", self.most_sensitive)),
            stress,
            of("deflection_at_load"),
        ]
    }

    /// A `BELOW_SAFETY_FACTOR` warning when the judged safety factor is under the required one
    /// (`materials.silicon.safety_factor`, 3 in paper 001), replacing an earlier one: the
    /// solid rung may lower the factor after the plate answered
    /// ([`crate::sensor::solid`]'s `take_safety_from`). A declared `min_safety_factor` limit
    /// is what fails a build; this says so for every scene, limit or not.
    pub(super) fn note_safety_shortfall(&mut self, g: &SensorGeometry) {
        let code = crate::finding::Code::Scene(SceneCode::BelowSafetyFactor);
        self.warnings.retain(|w| w.code != code);
        if self.stress_from.judged() && self.safety_factor < g.safety_factor {
            self.warnings.push(Finding::warning(
                SceneCode::BelowSafetyFactor,
                format!(
                    "safety factor {:.2} is under the required {} (materials.silicon.\
                     safety_factor): this scene's {:.3} N is over its permissible load, {:.3} N",
                    self.safety_factor,
                    g.safety_factor,
                    self.force_n.abs(),
                    self.max_permissible_load_n
                ),
            ));
        }
    }
}

impl StressFrom {
    /// Whether a safety factor and a permissible load were judged from this stress (not for a
    /// load standing wholly on a support).
    pub fn judged(self) -> bool {
        self != StressFrom::OnSupport
    }

    /// `value` (a safety factor or a permissible load judged from this stress) with `decimals`
    /// decimals and its `unit`, or "not judged": how `fe`, `build` and the traveler show it.
    pub fn judged_text(self, value: f64, decimals: usize, unit: &str) -> String {
        if self.judged() {
            format!("{}{unit}", crate::units::fixed(value, decimals))
        } else {
            "not judged".into()
        }
    }

    /// What the text output says.
    pub fn describe(self) -> &'static str {
        match self {
            StressFrom::AveragedOverContact => "averaged over the contact",
            StressFrom::ToothBase => "at a tooth's base edge, at the critical distance",
            StressFrom::StripAtLoad => "the strip's, at the load",
            StressFrom::OnSupport => {
                "in the plate (the load stands wholly on a support; the support, the film and \
                 the base under it are not judged: `--verify-solid` takes the solid rung's \
                 reading of the support's edges)"
            }
            StressFrom::SolidOnSupport => {
                "from the solid rung, its governing stress with its estimate (the load stands \
                 wholly on a support, whose edges the plate rungs do not judge)"
            }
        }
    }

    /// The traveler's table label.
    pub fn short(self) -> &'static str {
        match self {
            StressFrom::AveragedOverContact => "contact",
            StressFrom::ToothBase => "tooth base",
            StressFrom::StripAtLoad => "strip",
            StressFrom::OnSupport => "on a support: not judged",
            StressFrom::SolidOnSupport => "on a support: solid rung",
        }
    }
}

/// Fracture strength over the stress (infinite when unstressed).
pub(super) fn safety_factor(g: &SensorGeometry, stress_pa: f64) -> f64 {
    if stress_pa > 0.0 {
        g.fracture_strength_mpa * 1e6 / stress_pa
    } else {
        f64::INFINITY
    }
}

/// The load at which the stress reaches the fracture strength over the required safety factor
/// (the model is linear in the load).
pub(super) fn permissible_load_n(g: &SensorGeometry, stress_pa: f64, force_n: f64) -> f64 {
    let allowed_pa = g.fracture_strength_mpa * 1e6 / g.safety_factor;
    if stress_pa > 0.0 {
        force_n.abs() * allowed_pa / stress_pa
    } else {
        f64::INFINITY
    }
}

/// Largest |V| / F over the electrodes, and which one.
fn most_sensitive(r: &Readout, force_n: f64) -> (String, f64) {
    r.electrodes
        .iter()
        .map(|e| {
            (
                e.name.clone(),
                if force_n != 0.0 {
                    (e.voltage_mv / force_n).abs()
                } else {
                    0.0
                },
            )
        })
        .fold((String::new(), 0.0), |a, b| if b.1 > a.1 { b } else { a })
}

/// The rung a level loop runs.
#[derive(Debug, Clone, Copy)]
enum Rung {
    Linear,
    LargeDeflection(NonlinearOptions),
    /// The large-deflection plate estimated by two modified-Newton corrections from the linear
    /// field ([`VonKarman::modified_newton`]): the linear plate's model-error estimate.
    Estimate(NonlinearOptions),
}

/// The plate path of [`evaluate_many`]: the rung of each scene (see [`ModelChoice`]), its level
/// loop, then one report per scene. The linear plate's model error is its difference from the
/// large-deflection plate on the coarsest mesh, where a nonlinear solve costs little.
fn evaluate_plate(
    g: &SensorGeometry,
    scenes: &[Scene],
    acc: Accuracy,
    mesh: MeshOptions,
) -> Result<Vec<SceneReport>, SensorError> {
    let tol = acc.tol_rel;
    let max_levels = acc.max_levels.min(SUBDIVISIONS.len());
    let loads: Vec<SceneLoads> = scenes.iter().map(|s| split(&s.load, g)).collect();
    let opts = NonlinearOptions {
        in_plane: acc.in_plane,
        energy_tol: LADDER_ENERGY_TOL,
        ..Default::default()
    };
    let nonlinear = Rung::LargeDeflection(opts);
    let report_all =
        |levels: &Levels, model: Option<&[Vec<f64>]>, reason: &dyn Fn(usize) -> String| {
            scenes
                .iter()
                .zip(&loads)
                .enumerate()
                .map(|(k, (scene, l))| {
                    let m = model.map(|m| m[k].as_slice());
                    scene_report(g, scene, l, k, levels, tol, m, reason(k))
                })
                .collect::<Vec<_>>()
        };
    if acc.model == ModelChoice::LargeDeflection {
        let levels = solve_levels_per_part(g, &loads, tol, max_levels, mesh, nonlinear)?;
        return Ok(report_all(&levels, None, &|_| {
            "forced by --model large-deflection".into()
        }));
    }
    // The linear plate's model error on the coarsest mesh: every scene by the cheap estimate
    // (one factorisation for all), and by the converged nonlinear solve where that estimate is
    // not small (it is accurate only for a mild nonlinearity). Only the coarsest linear level is
    // needed for it; the linear ladder is climbed below only by the scenes that stay linear.
    let linear0 = solve_levels(g, &loads, tol, 1, mesh, Rung::Linear)?;
    let estimate = solve_levels(g, &loads, tol, 1, mesh, Rung::Estimate(opts))?;
    let h0 = estimate
        .cost
        .first()
        .and_then(|c| c.first())
        .map_or(0.0, |c| c.0);
    let mut model: Vec<Vec<f64>> = (0..scenes.len())
        .map(|k| {
            linear_model_error(
                g,
                &linear0.history[k][0],
                &estimate.history[k][0],
                loads[k].total_force_n,
            )
        })
        .collect();
    let mut by_newton = vec![false; scenes.len()];
    // Forced linear plate: the estimate is what is reported (large means large); auto: a large
    // estimate is confirmed by Newton before the scene climbs or stays.
    let large: Vec<usize> = (0..scenes.len())
        .filter(|_| acc.model == ModelChoice::Auto)
        .filter(|&k| model[k].iter().any(|&e| e > 0.5 * tol))
        .collect();
    // A scene whose estimate alone is over the tolerance climbs at once (its level loop's first
    // level gives the Newton-converged comparison); one between half and the whole tolerance is
    // confirmed by a coarse Newton solve.
    let (climb_now, check): (Vec<usize>, Vec<usize>) = large
        .iter()
        .partition(|&&k| acc.model == ModelChoice::Auto && model[k].iter().any(|&e| e >= tol));
    let climbed = if climb_now.is_empty() {
        None
    } else {
        let sub: Vec<SceneLoads> = climb_now.iter().map(|&k| loads[k].clone()).collect();
        let levels = solve_levels_per_part(g, &sub, tol, max_levels, mesh, nonlinear)?;
        for (j, &k) in climb_now.iter().enumerate() {
            model[k] = linear_model_error(
                g,
                &linear0.history[k][0],
                &levels.history[j][0],
                loads[k].total_force_n,
            );
            by_newton[k] = true;
        }
        Some((sub, levels))
    };
    if !check.is_empty() {
        let sub: Vec<SceneLoads> = check.iter().map(|&k| loads[k].clone()).collect();
        let coarse = solve_levels(g, &sub, tol, 1, mesh, nonlinear)?;
        for (j, &k) in check.iter().enumerate() {
            model[k] = linear_model_error(
                g,
                &linear0.history[k][0],
                &coarse.history[j][0],
                loads[k].total_force_n,
            );
            by_newton[k] = true;
        }
    }
    // The linear ladder, for the scenes that did not climb at once.
    let stay: Vec<usize> = (0..scenes.len())
        .filter(|k| !climb_now.contains(k))
        .collect();
    let stay_loads: Vec<SceneLoads> = stay.iter().map(|&k| loads[k].clone()).collect();
    let linear = if stay.is_empty() {
        None
    } else {
        Some(solve_levels(
            g,
            &stay_loads,
            tol,
            max_levels,
            mesh,
            Rung::Linear,
        )?)
    };
    let worst_model = |k: usize| model[k].iter().copied().fold(0.0, f64::max);
    let basis = |k: usize| {
        format!(
            "model error {:.2e} = its difference from the large-deflection plate ({}) on the \
             {h0:.0} um mesh",
            worst_model(k),
            if by_newton[k] {
                "Newton-converged"
            } else {
                "two modified-Newton corrections"
            }
        )
    };
    let linear_reason = |k: usize| match acc.model {
        ModelChoice::Plate => format!("forced by --model plate; {}", basis(k)),
        _ => format!(
            "auto: the linear plate meets the tolerance {tol:.0e} ({})",
            basis(k)
        ),
    };
    let mut stay_reports = stay.iter().enumerate().map(|(j, &k)| {
        scene_report(
            g,
            &scenes[k],
            &loads[k],
            j,
            linear.as_ref().expect("a linear ladder when a scene stays"),
            tol,
            Some(&model[k]),
            linear_reason(k),
        )
    });
    // Scenes that climbed at once hold a placeholder until their report is made below.
    let mut reports: Vec<Option<SceneReport>> = (0..scenes.len())
        .map(|k| (!climb_now.contains(&k)).then(|| stay_reports.next().expect("one per stay")))
        .collect();
    if acc.model == ModelChoice::Plate {
        return Ok(reports.into_iter().flatten().collect());
    }
    // Auto: the scenes the linear plate cannot answer within the tolerance climb a rung.
    let reason = |k: usize, linear: Option<&SceneReport>| {
        format!(
            "auto: the linear plate misses the tolerance {tol:.0e} ({}{})",
            basis(k),
            linear.map_or_else(String::new, |r| format!(
                ", discretisation {}",
                discretisation_text(r)
            ))
        )
    };
    if let Some((sub, levels)) = &climbed {
        for (j, &k) in climb_now.iter().enumerate() {
            let why = reason(k, None);
            reports[k] = Some(scene_report(
                g, &scenes[k], &sub[j], j, levels, tol, None, why,
            ));
        }
    }
    let mut reports: Vec<SceneReport> = reports
        .into_iter()
        .map(|r| r.expect("every scene reported"))
        .collect();
    let unconverged: Vec<usize> = (0..scenes.len())
        .filter(|&k| !climb_now.contains(&k))
        .filter(|&k| !loads[k].plate.is_empty() && !reports[k].converged)
        .collect();
    let (climb, stay_short): (Vec<usize>, Vec<usize>) = unconverged
        .into_iter()
        .partition(|&k| the_model_is_the_miss(&reports[k], tol));
    for &k in &stay_short {
        reports[k].model.reason = format!(
            "auto: the linear plate stays, though it misses the tolerance {tol:.0e}: the miss \
             is discretisation ({}), which the large-deflection plate on the same meshes would \
             not close ({}); {}",
            discretisation_text(&reports[k]),
            basis(k),
            if max_levels < SUBDIVISIONS.len() {
                "more levels would (--max-levels)"
            } else {
                "the ladder's finest level is reached"
            }
        );
    }
    if climb.is_empty() {
        return Ok(reports);
    }
    let sub: Vec<SceneLoads> = climb.iter().map(|&k| loads[k].clone()).collect();
    let levels = solve_levels_per_part(g, &sub, tol, max_levels, mesh, nonlinear)?;
    for (j, &k) in climb.iter().enumerate() {
        let why = reason(k, Some(&reports[k]));
        reports[k] = scene_report(g, &scenes[k], &sub[j], j, &levels, tol, None, why);
    }
    Ok(reports)
}

/// A report's worst discretisation estimate as the rung's reason prints it.
fn discretisation_text(r: &SceneReport) -> String {
    r.error
        .discretisation
        .map_or_else(|| "unknown".to_string(), |d| format!("{d:.2e}"))
}

/// Whether climbing to the large-deflection plate can bring the linear plate's unconverged scene
/// closer to the tolerance: some quantity that misses it has a model error that either alone
/// tips it over (its discretisation meets the tolerance, or is unknown: one level) or is the
/// larger part of its error. A miss that is discretisation is not closed by another model on
/// the same meshes, at several times the cost per level.
fn the_model_is_the_miss(r: &SceneReport, tol: f64) -> bool {
    r.quantities
        .iter()
        .filter(|q| q.name != STRESS_PEAK && !q.converged)
        .any(|q| match (q.error.discretisation, q.error.model) {
            (Some(d), Some(m)) => m > 0.0 && (d < tol || m >= d),
            (None, Some(m)) => m > 0.0,
            _ => false,
        })
}

/// What the level loop leaves: per scene the history of its quantities
/// ([`quantity_names`](super::rung) order) and estimates, the cost of each level, and the last
/// level's solutions and readings.
struct Levels {
    /// Per scene, per level: [w at the load, charge of each electrode, reaction 1, reaction 2].
    history: Vec<Vec<Vec<f64>>>,
    /// Per scene, per level: (worst discretisation estimate, observed order) after that level.
    estimates: Vec<Vec<(Option<f64>, Option<f64>)>>,
    /// Per scene, per level solved: (element size, elements, dofs, ms).
    cost: Vec<Vec<(f64, usize, usize, f64)>>,
    /// Per scene: the time of the levels it was solved on, its model, last solution and readings
    /// (a large-deflection scene stops at the level that meets the tolerance, the others go on).
    elapsed_ms: Vec<f64>,
    solutions: Vec<Option<crate::fe::PlateSolution>>,
    info: Vec<ModelInfo>,
    readouts: Vec<Option<Readout>>,
    /// Per scene, the large-deflection plate's touch-down on the coarsest mesh, when found.
    touch: Vec<Option<CoarseTouch>>,
    /// The design's tooth-base section, when the plate was solved and it has teeth, and per
    /// scene the last level's worst tooth-base station.
    section: Option<super::edge_section::EdgeSection>,
    edges: Vec<Option<super::edge_section::EdgeReading>>,
}

impl Levels {
    /// Nothing solved yet for `n` scenes.
    fn new(n: usize) -> Self {
        Levels {
            history: vec![Vec::new(); n],
            estimates: vec![Vec::new(); n],
            cost: vec![Vec::new(); n],
            elapsed_ms: vec![0.0; n],
            solutions: vec![None; n],
            info: vec![ModelInfo::direct(); n],
            readouts: vec![None; n],
            touch: vec![None; n],
            section: None,
            edges: vec![None; n],
        }
    }
}

/// The touch-down found on the coarsest mesh: that mesh's largest deflection at the scene's
/// load, and the load factor (and local exponent d ln w / d ln F) at which it reaches the gap.
#[derive(Debug, Clone, Copy)]
struct CoarseTouch {
    w_max_um: f64,
    factor: f64,
    exponent: f64,
}

impl CoarseTouch {
    /// The answer's touch-down: the coarse mesh's, corrected by c = w1 / w_coarse, the ratio of
    /// the answer's largest deflection `w1_um` to the coarse one at the scene's load (as the
    /// search over load factors does), through the local power law w ~ F^p at the gap:
    /// F = F_gap c^(-1/p). The law's error is of second order in ln c (c = 1.02 on the bundled
    /// design: ~1e-4, under the search's 1e-3).
    fn touch_down(self, g: &SensorGeometry, w1_um: f64, force_n: f64) -> Option<TouchDown> {
        if !(w1_um > 0.0 && self.w_max_um > 0.0 && self.exponent > 0.0 && self.factor > 0.0) {
            return None;
        }
        let c = w1_um / self.w_max_um;
        let factor = self.factor * c.powf(-1.0 / self.exponent);
        Some(TouchDown {
            gap_um: g.gap_um,
            load_n: (factor <= super::touch_down::MAX_FACTOR).then_some(factor * force_n.abs()),
            basis: format!(
                "large-deflection plate driven to the gap on the {COARSE_ELEMENT_UM:.0} um mesh \
                 (displacement control), scaled by the answer's deflection ({c:.4} x, local \
                 exponent {:.3})",
                self.exponent
            ),
        })
    }
}

fn latest(est: &[(Option<f64>, Option<f64>)]) -> (Option<f64>, Option<f64>) {
    est.last().copied().unwrap_or((None, None))
}

/// [`solve_levels`] for the large-deflection plate, each scene on the part of the plate its own
/// mirrors allow. Its Newton solves are its own, so a symmetric scene need not solve the whole
/// plate because another scene breaks a mirror (on the bundled design `line-y5mm` would double
/// `centre-1n`'s dofs on every level). The linear plate's scenes share one multi-column
/// solve, and so one part: [`solve_levels`].
fn solve_levels_per_part(
    g: &SensorGeometry,
    loads: &[SceneLoads],
    tol: f64,
    max_levels: usize,
    mesh: MeshOptions,
    rung: Rung,
) -> Result<Levels, SensorError> {
    let mut parts: Vec<(Symmetry, Vec<usize>)> = Vec::new();
    if mesh.symmetry {
        for (k, l) in loads.iter().enumerate() {
            let sym = Symmetry::detect(g, std::slice::from_ref(&l.plate));
            match parts.iter_mut().find(|(s, _)| *s == sym) {
                Some((_, ks)) => ks.push(k),
                None => parts.push((sym, vec![k])),
            }
        }
    }
    if parts.len() <= 1 {
        return solve_levels(g, loads, tol, max_levels, mesh, rung);
    }
    let mut out = Levels::new(loads.len());
    for (_, ks) in parts {
        let sub: Vec<SceneLoads> = ks.iter().map(|&k| loads[k].clone()).collect();
        let mut part = solve_levels(g, &sub, tol, max_levels, mesh, rung)?;
        if part.section.is_some() {
            out.section = part.section.take();
        }
        for (j, k) in ks.into_iter().enumerate() {
            out.history[k] = std::mem::take(&mut part.history[j]);
            out.estimates[k] = std::mem::take(&mut part.estimates[j]);
            out.cost[k] = std::mem::take(&mut part.cost[j]);
            out.elapsed_ms[k] = part.elapsed_ms[j];
            out.solutions[k] = part.solutions[j].take();
            out.info[k] = std::mem::replace(&mut part.info[j], ModelInfo::direct());
            out.readouts[k] = part.readouts[j].take();
            out.touch[k] = part.touch[j];
            out.edges[k] = part.edges[j];
        }
    }
    Ok(out)
}

/// Solves all scenes on the shared mesh sequence until every plate scene's discretisation
/// estimate is under `tol` or `max_levels` ran.
fn solve_levels(
    g: &SensorGeometry,
    loads: &[SceneLoads],
    tol: f64,
    max_levels: usize,
    mesh: MeshOptions,
    rung: Rung,
) -> Result<Levels, SensorError> {
    let needs_plate = loads.iter().any(|l| !l.plate.is_empty());
    let cases: Vec<Vec<_>> = loads.iter().map(|l| l.plate.clone()).collect();
    let sym = if mesh.symmetry {
        Symmetry::detect(g, &cases)
    } else {
        Symmetry::none(g)
    };
    let part_cases: Vec<Vec<_>> = cases.iter().map(|c| sym.restrict(c)).collect();
    let n = loads.len();
    let mut out = Levels::new(n);
    if needs_plate {
        out.section = super::edge_section::tooth_base_section(g)?;
    }
    let levels = if needs_plate {
        max_levels.min(SUBDIVISIONS.len())
    } else {
        1
    };
    let base = base_lines(g, loads, &sym, &mesh);
    let (kind, in_plane) = match rung {
        Rung::Linear => (ModelKind::Plate, None),
        Rung::LargeDeflection(o) | Rung::Estimate(o) => {
            (ModelKind::LargeDeflectionPlate, Some(o.in_plane))
        }
    };
    let ctx = LevelContext {
        g,
        base: &base,
        sym: &sym,
        part_cases: &part_cases,
        loads,
        rung,
    };
    let mut newton = vec![0; n];
    // Each large-deflection scene leaves the ladder at the level that meets the tolerance (its
    // Newton solves are its own); the linear plate solves all scenes in one multi-column solve,
    // so they all go on to the level the last one needs.
    let mut active: Vec<bool> = loads.iter().map(|l| !l.plate.is_empty()).collect();
    let freeze = matches!(rung, Rung::LargeDeflection(_));
    let mut level = 0;
    while level < levels {
        // The first estimate needs three levels, so levels 1 and 2 are always both solved: side
        // by side, each from the coarsest field; beside level 1 the large-deflection plate's
        // touch-down is found on the coarsest mesh (it needs only that level's answer).
        let batch: Vec<LevelSolve> = if !needs_plate {
            vec![LevelSolve::direct(n)]
        } else if level == 0 && levels >= 3 {
            let (first, touch) = ctx.first_three(rung)?;
            out.touch = touch;
            first
        } else {
            vec![ctx.solve(level, &out.solutions, &active)?]
        };
        for solved in batch {
            for (k, (l, sol)) in loads.iter().zip(solved.solutions).enumerate() {
                // Scenes without a plate load are read at every level (directly, no plate).
                if l.plate.is_empty() || active[k] {
                    newton[k] += solved.iterations[k];
                    out.elapsed_ms[k] += solved.ms;
                    out.cost[k].push((solved.h_um, solved.elements, solved.dofs, solved.ms));
                    out.info[k] = if needs_plate {
                        ModelInfo {
                            kind,
                            elements: solved.elements,
                            dofs: solved.dofs,
                            levels: level + 1,
                            max_element_um: solved.h_um,
                            observed_order: None,
                            symmetry: sym.describe(),
                            grading: mesh.graded.then(|| grading_description(loads)),
                            reason: String::new(),
                            in_plane,
                            newton_iterations: in_plane.map(|_| newton[k]),
                        }
                    } else {
                        ModelInfo::direct()
                    };
                    out.solutions[k] = sol;
                }
            }
            let sols = &out.solutions;
            let readouts: Vec<Option<Readout>> = loads
                .iter()
                .enumerate()
                .map(|(k, l)| {
                    if !(l.plate.is_empty() || active[k]) {
                        return None;
                    }
                    let r = read(
                        g,
                        sols[k].as_ref(),
                        &l.direct,
                        in_plane == Some(InPlane::Immovable),
                    );
                    let w = sols[k]
                        .as_ref()
                        .map_or(0.0, |s| s.deflection_m(l.at_um.0, l.at_um.1));
                    let mut q = vec![w];
                    q.extend(r.electrodes.iter().map(|e| e.charge_pc));
                    q.extend([r.support1_n, r.support2_n]);
                    let [averaged, peak] =
                        stresses(g, sols[k].as_ref(), l).map(|p| p.map_or(0.0, |p| p.sigma_pa));
                    q.push(averaged);
                    if let Some(section) = &out.section {
                        out.edges[k] = sols[k]
                            .as_ref()
                            .and_then(|s| plate_tooth_base_stress(g, s, section));
                        q.push(out.edges[k].map_or(0.0, |r| r.stress_pa));
                    }
                    q.push(peak);
                    out.history[k].push(q);
                    let (errs, order) =
                        estimates(g, &out.history[k], l.total_force_n, out.section.as_ref());
                    // The peak point stress (last) may never converge: it does not hold the loop.
                    let worst = errs[..errs.len() - 1]
                        .iter()
                        .try_fold(0f64, |m, e| e.map(|e| m.max(e)));
                    out.estimates[k].push((worst, order));
                    Some(r)
                })
                .collect();
            for (k, r) in readouts.into_iter().enumerate() {
                if r.is_some() {
                    out.readouts[k] = r;
                }
            }
            level += 1;
        }
        if freeze {
            for (k, est) in out.estimates.iter().enumerate() {
                if latest(est).0.is_some_and(|e| e < tol) {
                    active[k] = false;
                }
            }
        }
        let done = out
            .estimates
            .iter()
            .zip(loads)
            .all(|(est, l)| l.plate.is_empty() || latest(est).0.is_some_and(|e| e < tol));
        if done || !needs_plate {
            break;
        }
    }
    Ok(out)
}

/// What one level needs, shared by the levels solved side by side.
struct LevelContext<'a> {
    g: &'a SensorGeometry,
    base: &'a (Vec<f64>, Vec<f64>),
    sym: &'a Symmetry,
    part_cases: &'a [Vec<crate::fe::Load>],
    loads: &'a [SceneLoads],
    rung: Rung,
}

/// One level's answer before its readings are taken.
struct LevelSolve {
    solutions: Vec<Option<crate::fe::PlateSolution>>,
    /// Per scene, the Newton iterations spent.
    iterations: Vec<usize>,
    h_um: f64,
    elements: usize,
    dofs: usize,
    ms: f64,
}

impl LevelSolve {
    /// No plate to solve: every scene is read directly.
    fn direct(n: usize) -> Self {
        LevelSolve {
            solutions: vec![None; n],
            iterations: vec![0; n],
            h_um: COARSE_ELEMENT_UM,
            elements: 0,
            dofs: 0,
            ms: 0.0,
        }
    }
}

/// A level set up before the coarser field it starts from is known: the linear rungs are
/// solved outright (they need no start), the large-deflection plate has its dofs, pattern and
/// symbolic analysis ready for Newton.
struct Prepared {
    rung: PreparedRung,
    h_um: f64,
    elements: usize,
    dofs: usize,
    ms: f64,
}

enum PreparedRung {
    Solved(Vec<Option<crate::fe::PlateSolution>>),
    Nonlinear(Box<VonKarman>),
}

impl LevelContext<'_> {
    /// Level `level` of the ladder for the `active` scenes, each from `previous` (a coarser
    /// level's field) where the rung can use one.
    fn solve(
        &self,
        level: usize,
        previous: &[Option<crate::fe::PlateSolution>],
        active: &[bool],
    ) -> Result<LevelSolve, SensorError> {
        self.finish(self.prepare(level)?, previous, active)
    }

    /// Everything of level `level` that does not need a coarser field: the linear plate solves
    /// every scene in one multi-column solve, the estimate runs its modified-Newton corrections
    /// for all scenes on one factorisation, the large-deflection plate builds its analysis.
    fn prepare(&self, level: usize) -> Result<Prepared, SensorError> {
        let t0 = Instant::now();
        let n = self.loads.len();
        let problem = build_problem(self.g, self.base, level, self.sym)?;
        let per_node = match self.rung {
            Rung::Linear => 4,
            _ => 6,
        };
        let dofs = per_node * problem.mesh.n_nodes();
        if dofs * n > MAX_SOLUTION_VALUES {
            return Err(SensorError::TooLarge {
                loads: n,
                dofs,
                level: level + 1,
            });
        }
        // One solution per case, kept where the scene loads the plate.
        let expand = |solved: Vec<crate::fe::PlateSolution>| {
            solved
                .into_iter()
                .zip(self.loads)
                .map(|(s, l)| (!l.plate.is_empty()).then(|| self.sym.expand(s)))
                .collect()
        };
        let rung = match self.rung {
            Rung::Linear => {
                PreparedRung::Solved(expand(Factorised::new(&problem)?.solve(self.part_cases)?))
            }
            Rung::Estimate(opts) => PreparedRung::Solved(expand(
                VonKarman::new(&problem, opts)?.modified_newton(self.part_cases, 2)?,
            )),
            Rung::LargeDeflection(opts) => {
                PreparedRung::Nonlinear(Box::new(VonKarman::new(&problem, opts)?))
            }
        };
        Ok(Prepared {
            rung,
            h_um: COARSE_ELEMENT_UM / SUBDIVISIONS[level] as f64,
            elements: problem.mesh.n_elements(),
            dofs,
            ms: t0.elapsed().as_secs_f64() * 1e3,
        })
    }

    /// The rest of a prepared level: Newton per active scene (in parallel; each factorisation
    /// is sequential) from the coarser field where there is one. Returns the whole-plate
    /// solutions (None for an inactive scene on the large-deflection plate).
    fn finish(
        &self,
        p: Prepared,
        previous: &[Option<crate::fe::PlateSolution>],
        active: &[bool],
    ) -> Result<LevelSolve, SensorError> {
        let t0 = Instant::now();
        let (solutions, iterations) = match p.rung {
            PreparedRung::Solved(s) => {
                let n = s.len();
                (s, vec![0; n])
            }
            PreparedRung::Nonlinear(vk) => {
                let cases: Vec<_> = self
                    .part_cases
                    .iter()
                    .zip(self.loads)
                    .zip(previous)
                    .zip(active)
                    .collect();
                let solved: Vec<Option<(crate::fe::PlateSolution, usize)>> =
                    crate::fe::memory::in_parallel_then_alone(&cases, |&(((c, l), prev), &on)| {
                        (on && !l.plate.is_empty())
                            .then(|| {
                                match prev {
                                    Some(p) => vk.solve_from(c, p),
                                    None => vk.solve(c),
                                }
                                .map(|(s, st)| (self.sym.expand(s), st.iterations))
                            })
                            .transpose()
                    })?;
                let iterations = solved
                    .iter()
                    .map(|s| s.as_ref().map_or(0, |s| s.1))
                    .collect();
                (
                    solved.into_iter().map(|s| s.map(|s| s.0)).collect(),
                    iterations,
                )
            }
        };
        Ok(LevelSolve {
            solutions,
            iterations,
            h_um: p.h_um,
            elements: p.elements,
            dofs: p.dofs,
            ms: p.ms + t0.elapsed().as_secs_f64() * 1e3,
        })
    }
}

impl LevelContext<'_> {
    /// Levels 0, 1 and 2, overlapped (the first estimate needs all three): level 2 is set up on
    /// a second thread while level 0 solves, then both finer levels start from level 0's field,
    /// and beside level 1 the large-deflection plate's touch-down is found on the coarsest mesh.
    /// Plain threads, not the rayon pool: the second waits for the first's field, which a pool
    /// of one thread could never deliver.
    fn first_three(
        &self,
        rung: Rung,
    ) -> Result<(Vec<LevelSolve>, Vec<Option<CoarseTouch>>), SensorError> {
        let n = self.loads.len();
        std::thread::scope(|scope| {
            let (tx, rx) = std::sync::mpsc::channel::<Vec<Option<crate::fe::PlateSolution>>>();
            let finest = scope.spawn(move || -> Result<Option<LevelSolve>, SensorError> {
                let p = self.prepare(2)?;
                // No field means level 0 failed: its error is the one reported.
                match rx.recv() {
                    Ok(from) => self.finish(p, &from, &vec![true; n]).map(Some),
                    Err(_) => Ok(None),
                }
            });
            let all = vec![true; n];
            let zero = self.solve(0, &vec![None; n], &all);
            let zero = match zero {
                Ok(z) => z,
                Err(e) => {
                    drop(tx);
                    let _ = finest.join();
                    return Err(e);
                }
            };
            let _ = tx.send(zero.solutions.clone());
            let one = self.solve(1, &zero.solutions, &all);
            let touch = match rung {
                Rung::LargeDeflection(o) => coarse_touch_down(self, o, &zero.solutions),
                _ => vec![None; n],
            };
            let two = finest
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic))?;
            let two = two.expect("level 0 delivered its field");
            Ok((vec![zero, one?, two], touch))
        })
    }
}

/// Per scene, the touch-down on the coarsest mesh: the large-deflection plate driven from the
/// scene's answer there (`coarse`) to the gap by displacement control
/// ([`VonKarman::solve_to_deflection`]). None where the scene does not load the plate, lifts it
/// (w < 0: it never touches) or the solve fails (the caller then searches over load factors).
fn coarse_touch_down(
    ctx: &LevelContext<'_>,
    opts: NonlinearOptions,
    coarse: &[Option<crate::fe::PlateSolution>],
) -> Vec<Option<CoarseTouch>> {
    let Ok(problem) = build_problem(ctx.g, ctx.base, 0, ctx.sym) else {
        return vec![None; coarse.len()];
    };
    let Ok(vk) = VonKarman::new(&problem, opts) else {
        return vec![None; coarse.len()];
    };
    let gap_m = ctx.g.gap_um * 1e-6;
    coarse
        .iter()
        .zip(ctx.part_cases)
        .map(|(sol, case)| {
            let sol = sol.as_ref()?;
            // A load that lifts the plate (w < 0: away from the floor) never touches it.
            let w0 = sol.max_deflection().w_m;
            if w0 <= 0.0 {
                return None;
            }
            let at = vk.solve_to_deflection(case, sol, 1.0, gap_m).ok()?;
            Some(CoarseTouch {
                w_max_um: w0 * 1e6,
                factor: at.lambda,
                exponent: at.exponent,
            })
        })
        .collect()
}

/// Newton's energy-ratio tolerance on the ladder: ~1e-6 in displacement for the correction
/// that stops it (full Newton leaves the square of that; modified Newton a hundredth), far under
/// the smallest discretisation error a level reports (~1e-3), and the load balanced to ~1e-9;
/// the default 1e-14 costs one more iteration per level.
const LADDER_ENERGY_TOL: f64 = 1e-12;

/// Side of the stress-averaging square in plate thicknesses: plate theory answers for the stress
/// only a few thicknesses from a step or a concentrated load (Saint-Venant), and a square this
/// size is resolved by the meshes the readings need; the concentration inside it is the 3D
/// solid's to answer.
pub const STRESS_AVERAGING_THICKNESSES: f64 = 4.0;

/// The largest principal stress over the scene's contact patch: averaged over a square
/// [`STRESS_AVERAGING_THICKNESSES`] plate thicknesses wide ([`crate::fe::PlateSolution::averaged_principal_stress`]), and the point peak.
fn stresses(
    g: &SensorGeometry,
    sol: Option<&crate::fe::PlateSolution>,
    l: &SceneLoads,
) -> [Option<crate::fe::StressPeak>; 2] {
    let Some(s) = sol else {
        return [None, None];
    };
    [
        s.averaged_principal_stress(l.patch, STRESS_AVERAGING_THICKNESSES * g.plate_thickness_um),
        s.max_principal_stress(l.patch),
    ]
}

/// Each quantity's discretisation estimate from the levels' `history` ([`discretisation`]), the
/// edge section's own estimate added to the tooth-base stress's: the level loop stops on these,
/// and the report states them.
fn estimates(
    g: &SensorGeometry,
    history: &[Vec<f64>],
    force_n: f64,
    section: Option<&super::edge_section::EdgeSection>,
) -> (Vec<Option<f64>>, Option<f64>) {
    let (mut errs, order) = discretisation(g, history, force_n);
    if let Some(sec) = section {
        let i = quantity_names(g)
            .iter()
            .position(|(n, ..)| n == TOOTH_BASE_STRESS);
        if let Some(Some(d)) = i.and_then(|i| errs.get_mut(i)) {
            *d += sec.error_rel;
        }
    }
    (errs, order)
}

/// The report of scene `k` from the level loop; `model` is the rung's model error per quantity
/// (None where no finer rung was compared).
#[allow(clippy::too_many_arguments)]
fn scene_report(
    g: &SensorGeometry,
    scene: &Scene,
    l: &SceneLoads,
    k: usize,
    levels: &Levels,
    tol: f64,
    model: Option<&[f64]>,
    reason: String,
) -> SceneReport {
    let sol = levels.solutions[k].as_ref();
    let r = levels.readouts[k]
        .clone()
        .expect("every scene is read on the first level");
    let (_, order_k) = latest(&levels.estimates[k]);
    let mut info = if sol.is_some() {
        levels.info[k].clone()
    } else {
        ModelInfo::direct()
    };
    info.observed_order = order_k;
    if sol.is_some() {
        info.reason = reason;
    }
    let history = &levels.history[k];
    let f = l.total_force_n;
    let (disc, _) = estimates(g, history, f, levels.section.as_ref());
    let values = history.last().cloned().unwrap_or_default();
    let quantities = if sol.is_some() {
        quantities(g, &values, &disc, model, tol)
    } else {
        quantities(g, &values, &vec![Some(0.0); values.len()], None, tol)
    };
    let error = worst(&quantities);
    let w_load = values.first().copied().unwrap_or(0.0);
    let peak = sol.map(|s| s.max_deflection());
    let w_max = peak.map_or(0.0, |p| p.w_m);
    let [averaged, peak_stress] = stresses(g, sol, l);
    // The safety factor is judged on the larger of the averaged stress and the teeth's
    // base-edge stress at the critical distance: both converge.
    let edge = levels.edges[k];
    let averaged_pa = averaged.map_or(0.0, |p| p.sigma_pa);
    let stress_pa = averaged_pa.max(edge.map_or(0.0, |e| e.stress_pa));
    let (best, sens) = most_sensitive(&r, f);
    let ratio = sol
        .zip(peak.as_ref())
        .map_or(0.0, |(s, p)| s.linear_range_ratio_at(p));
    let converged = sol.is_none()
        || quantities
            .iter()
            .filter(|q| q.name != STRESS_PEAK)
            .all(|q| q.converged);
    let mut warnings = scene_warnings(w_max, ratio, converged, &error, order_k, &info, tol);
    if let (Some(p), Some(q)) = (
        peak_stress,
        quantities.iter().find(|q| q.name == STRESS_PEAK),
    ) {
        if !q.converged {
            warnings.push(Finding::warning(
                SceneCode::StressSingular,
                format!(
                    "the peak point stress {:.1} MPa at ({:.0}, {:.0}) um on the {} surface does \
                     not converge with the mesh (estimated change {}): plate theory makes it \
                     singular at a thickness step or a point-like load; the safety factor uses \
                     the larger of the stress averaged over a {:.0} um square, {:.1} MPa, and {} \
                     (the solid rung answers every sharp edge: --verify-solid)",
                    p.sigma_pa * 1e-6,
                    p.x_um,
                    p.y_um,
                    match p.surface {
                        crate::fe::Surface::Bottom => "bottom",
                        crate::fe::Surface::Top => "top",
                    },
                    q.error
                        .discretisation
                        .map_or_else(|| "unknown".to_string(), |d| format!("{:.0} %", d * 100.0)),
                    STRESS_AVERAGING_THICKNESSES * g.plate_thickness_um,
                    averaged_pa * 1e-6,
                    match edge {
                        Some(e) => format!(
                            "the teeth's base-edge stress at the critical distance, {:.1} MPa at \
                             ({:.0}, {:.0}) um (tooth_base_stress, from the edge section)",
                            e.stress_pa * 1e-6,
                            e.at_um[0],
                            e.at_um[1]
                        ),
                        None => "no tooth base edge (the design has no teeth)".to_string(),
                    }
                ),
            ));
        }
    }

    warnings.extend(overhang(scene, g));
    SceneReport {
        scene: scene.name.clone(),
        force_n: f,
        solve_ms: levels.elapsed_ms[k],
        error_estimate: if sol.is_none() {
            Some(0.0)
        } else {
            error.total
        },
        error,
        converged,
        deflection_at_load_um: w_load * 1e6,
        max_deflection_um: w_max * 1e6,
        max_stress_mpa: stress_pa * 1e-6,
        stress_from: if info.kind == ModelKind::Direct {
            StressFrom::OnSupport
        } else if edge.is_some_and(|e| e.stress_pa > averaged_pa) {
            StressFrom::ToothBase
        } else {
            StressFrom::AveragedOverContact
        },
        safety_factor: safety_factor(g, stress_pa),
        max_permissible_load_n: permissible_load_n(g, stress_pa, f),
        sensitivity_mv_per_n: sens,
        most_sensitive: best,
        reactions_n: Reactions {
            support1: r.support1_n,
            support2: r.support2_n,
        },
        electrodes: r.electrodes,
        quantities,
        // Signed: a plate lifted off the floor has no touch-down.
        touch_down: levels.touch[k].and_then(|c| c.touch_down(g, w_max * 1e6, f)),
        warnings,
        convergence: convergence_records(
            history,
            g.electrodes.len(),
            &levels.cost[k],
            &levels.estimates[k],
        ),
        hot_teeth: sol
            .zip(levels.section.as_ref())
            .map_or_else(Vec::new, |(s, section)| {
                super::edge_section::hot_teeth(g, s, section)
            }),
        model: info,
    }
}

/// What a plate answer should be read with: the linear plate beyond its range, not converged,
/// no estimate or no observed order.
fn scene_warnings(
    w_max_m: f64,
    linear_range_ratio: f64,
    converged: bool,
    error: &ErrorParts,
    order: Option<f64>,
    info: &ModelInfo,
    tol: f64,
) -> Vec<Finding> {
    let mut warnings = Vec::new();
    if info.kind == ModelKind::Plate && linear_range_ratio > LINEAR_RANGE_LIMIT {
        warnings.push(Finding::warning(
            SceneCode::LinearRange,
            format!(
                "maximum deflection {:.1} um is {linear_range_ratio:.2} x the local thickness \
                 (limit {LINEAR_RANGE_LIMIT}): the linear plate neglects membrane stiffening \
                 (estimated model error {})",
                w_max_m.abs() * 1e6,
                error
                    .model
                    .map_or_else(|| "unknown".to_string(), |m| format!("{m:.2e}")),
            ),
        ));
    }
    if !converged {
        warnings.push(match (error.total, error.discretisation) {
            (Some(e), Some(d)) => Finding::warning(
                SceneCode::NotConverged,
                format!(
                    "estimated error {e:.2e} (discretisation {d:.2e} + model {:.2e}) is above \
                     the tolerance {tol:.0e} after {} mesh levels",
                    error.model.unwrap_or(0.0),
                    info.levels
                ),
            ),
            _ => Finding::warning(
                SceneCode::NoErrorEstimate,
                if info.levels == 1 {
                    "1 mesh level gives no three-mesh estimate".to_string()
                } else {
                    format!("{} mesh levels give no three-mesh estimate", info.levels)
                },
            ),
        });
    }
    if order.is_none()
        && error.discretisation.is_some()
        && matches!(
            info.kind,
            ModelKind::Plate | ModelKind::LargeDeflectionPlate
        )
    {
        warnings.push(Finding::warning(
            SceneCode::OrderUnknown,
            "the three finest meshes do not converge monotonically; the error estimate is the \
             last change",
        ));
    }
    warnings
}

/// Per level: size, cost, the deflection and the largest electrode's charge, and the estimate.
fn convergence_records(
    history: &[Vec<f64>],
    n_electrodes: usize,
    cost: &[(f64, usize, usize, f64)],
    estimates: &[(Option<f64>, Option<f64>)],
) -> Vec<LevelRecord> {
    // Charges are entries 1 ..= n_electrodes ([`quantity_names`]: reactions and stresses follow).
    let largest = history.last().and_then(|q| {
        (1..=n_electrodes.min(q.len().saturating_sub(1)))
            .max_by(|&a, &b| q[a].abs().total_cmp(&q[b].abs()))
    });
    cost.iter()
        .zip(history)
        .zip(estimates)
        .map(|((&(h, el, dofs, ms), q), &(e, p))| LevelRecord {
            max_element_um: h,
            elements: el,
            dofs,
            time_ms: ms,
            deflection_at_load_um: q[0] * 1e6,
            charge_pc: largest.map_or(0.0, |i| q[i]),
            error_estimate: e,
            observed_order: p,
        })
        .collect()
}

/// An elastic support's constants per unit length: the stiffness on (w, theta), the in-plane
/// one, and the coupled 3 x 3 on (w, theta, u) where the support has one.
type SpringConstants = ([[f64; 2]; 2], f64, Option<[[f64; 3]; 3]>);

/// The plate over the U-channel (or the part of it solved): clamped where the etched {111}
/// walls meet it, teeth as thicker regions, symmetry lines on the mirrors.
pub(super) fn build_problem(
    g: &SensorGeometry,
    base: &(Vec<f64>, Vec<f64>),
    level: usize,
    sym: &Symmetry,
) -> crate::fe::FeResult<PlateProblem> {
    let xs = subdivide(&base.0, level);
    let ys = subdivide(&base.1, level);
    let mesh = RectMesh { x_um: xs, y_um: ys };
    let mut p = PlateProblem::new(mesh, g.plate_thickness_um, g.material);
    // Tooth edges on the base lines, so every level sees the same footprint.
    let snap = |v: f64, lines: &[f64]| {
        lines
            .iter()
            .copied()
            .min_by(|a, b| (a - v).abs().total_cmp(&(b - v).abs()))
            .unwrap_or(v)
    };
    p.thickness_regions = g
        .teeth
        .iter()
        .map(|t| ThicknessRegion {
            x0_um: snap(t.x0_um, &base.0),
            x1_um: snap(t.x1_um, &base.0),
            y0_um: snap(t.y0_um, &base.1),
            y1_um: snap(t.y1_um, &base.1),
            thickness_um: t.thickness_um,
            rise_um: t.rise_um,
        })
        .filter(|t| t.x1_um > t.x0_um && t.y1_um > t.y0_um)
        .collect();
    let (x0, x1, y0, y1) = sym.domain_um;
    let springs: Option<SpringConstants> = match g.support_model {
        crate::process::SupportModel::Clamped => None,
        crate::process::SupportModel::ElasticFooting => {
            let ft = super::footing::SupportFooting::new(g);
            Some((ft.edge_stiffness(), ft.in_plane_pa, None))
        }
        crate::process::SupportModel::SolidSection => {
            let sections = g.support_sections()?;
            // The film the section bonds under the plate is part of the plate's stiffness too.
            p.bonded_film = Some(crate::fe::BondedFilm {
                material: crate::fe::PlateMaterial::isotropic(g.pvdf_e_pa, g.pvdf_nu),
                thickness_um: g.film_thickness_um,
            });
            // Each piece of each support's wall on its own section (a tooth standing on it or
            // not).
            for (side, y, outward) in [(0, g.plate_y0_um, -1.0), (1, g.plate_y1_um, 1.0)] {
                if !(y >= y0 && y <= y1) {
                    continue;
                }
                let group = group_for([ElectrodeSide::Support1, ElectrodeSide::Support2][side]);
                for (from_um, to_um, s) in sections.pieces(side, x0, x1) {
                    p.edge_springs.push(crate::fe::EdgeSpring {
                        group: group.to_string(),
                        along: FeAxis::X,
                        at_um: y,
                        from_um,
                        to_um,
                        outward,
                        stiffness: s.bending_stiffness(),
                        normal_in_plane_pa: Some(s.in_plane_pa()),
                        coupled: Some(s.stiffness),
                        along_wall: Some(sections.along_wall),
                    });
                }
            }
            None
        }
    };
    for (side, y, outward) in [
        (ElectrodeSide::Support1, g.plate_y0_um, -1.0),
        (ElectrodeSide::Support2, g.plate_y1_um, 1.0),
    ] {
        if y >= y0 && y <= y1 {
            let group = group_for(side).to_string();
            if g.support_model == crate::process::SupportModel::SolidSection {
                continue;
            }
            if let Some((stiffness, in_plane, coupled)) = springs {
                p.edge_springs.push(crate::fe::EdgeSpring {
                    group,
                    along: FeAxis::X,
                    at_um: y,
                    from_um: x0,
                    to_um: x1,
                    outward,
                    stiffness,
                    normal_in_plane_pa: Some(in_plane),
                    coupled,
                    along_wall: None,
                });
                continue;
            }
            p.supports.push(LineSupport {
                group,
                kind: SupportKind::Clamped,
                along: FeAxis::X,
                at_um: y,
                from_um: x0,
                to_um: x1,
            });
        }
    }
    for m in &sym.mirrors {
        let (from_um, to_um) = match m.along {
            FeAxis::X => (x0, x1),
            FeAxis::Y => (y0, y1),
        };
        p.supports.push(LineSupport {
            group: "symmetry".into(),
            kind: SupportKind::Symmetry,
            along: m.along,
            at_um: m.at_um,
            from_um,
            to_um,
        });
    }
    Ok(p)
}
