//! Solving scenes to a tolerance: successively refined meshes, three-mesh error estimates, and the
//! per-scene report (the JSON contract of `tactfab fe --json`).

use std::time::Instant;

use serde::Serialize;

use crate::fe::problem::Axis as FeAxis;
use crate::fe::solution::LINEAR_RANGE_LIMIT;
use crate::fe::{
    Factorised, LineSupport, PlateProblem, RectMesh, SupportKind, ThicknessRegion, ThreeMesh,
};
use crate::finding::{Finding, SceneCode};
use crate::process::{Scene, SceneLoad};

use super::beam_model::{beam_answer, beam_applies, beam_error_estimate};
use super::check::{check_scene, overhang, SensorError, MAX_SOLUTION_VALUES};

use super::geometry::{ElectrodeSide, SensorGeometry};
use super::mesh_lines::{
    base_lines, grading_description, level_ratios, subdivide, MeshOptions, COARSE_ELEMENT_UM,
    SUBDIVISIONS,
};
use super::readout::{group_for, read, ElectrodeReading, Readout};
use super::scene::{split, SceneLoads};
use super::symmetry::Symmetry;

/// How accurate an answer must be: the estimated relative error to reach, and the most mesh
/// levels to spend on it (level k splits the coarse mesh [`SUBDIVISIONS`]`[k]` times).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Accuracy {
    pub tol_rel: f64,
    pub max_levels: usize,
}

impl Accuracy {
    /// `tol_rel` in (0, 1) is the caller's to check (the CLI's value parsers do); levels beyond
    /// [`SUBDIVISIONS`] are capped.
    pub const fn new(tol_rel: f64, max_levels: usize) -> Self {
        Accuracy {
            tol_rel,
            max_levels,
        }
    }
}

/// Which rung of the model ladder answered.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ModelKind {
    /// The fixed-fixed strip (paper 001 Eq. 3-6).
    Beam,
    /// The Kirchhoff BFS plate.
    Plate,
    /// The load lies wholly over a support: no plate solve.
    Direct,
}

impl std::fmt::Display for ModelKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ModelKind::Beam => "beam",
            ModelKind::Plate => "plate",
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
    /// Estimated relative error of the readings (three-mesh Richardson); None before three levels.
    pub error_estimate: Option<f64>,
    pub converged: bool,
    pub deflection_at_load_um: f64,
    pub max_deflection_um: f64,
    /// Largest principal bending stress over the contact patch.
    pub max_stress_mpa: f64,
    pub safety_factor: f64,
    /// Load at which the stress reaches fracture / safety factor (linear scaling).
    pub max_permissible_load_n: f64,
    /// Largest |V| / F over the electrodes, and which one.
    pub sensitivity_mv_per_n: f64,
    pub most_sensitive: String,
    pub reactions_n: Reactions,
    pub electrodes: Vec<ElectrodeReading>,
    pub warnings: Vec<Finding>,
    /// Per mesh level: size, cost, values and the estimate (`tactfab fe --convergence`).
    pub convergence: Vec<LevelRecord>,
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
    let (tol, max_levels) = (acc.tol_rel, acc.max_levels.min(SUBDIVISIONS.len()));
    let beam_error = beam_error_estimate(g);
    let by_beam = |s: &Scene| match s.load {
        SceneLoad::Line { y_um, .. } => beam_applies(g, y_um) && beam_error < tol,
        _ => false,
    };
    let plate_scenes: Vec<Scene> = scenes.iter().filter(|s| !by_beam(s)).cloned().collect();
    let mut plate = if plate_scenes.is_empty() {
        Vec::new()
    } else {
        evaluate_plate(g, &plate_scenes, tol, max_levels, mesh)?
    }
    .into_iter();
    Ok(scenes
        .iter()
        .map(|s| match s.load {
            SceneLoad::Line { y_um, force_n } if by_beam(s) => {
                beam_report(g, s, y_um, force_n, beam_error, tol)
            }
            _ => plate.next().expect("one plate report per plate scene"),
        })
        .collect())
}

/// A scene answered by the strip model.
fn beam_report(
    g: &SensorGeometry,
    scene: &Scene,
    y_um: f64,
    force_n: f64,
    error: f64,
    tol: f64,
) -> SceneReport {
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
        },
        solve_ms: t0.elapsed().as_secs_f64() * 1e3,
        error_estimate: Some(error),
        converged: error < tol,
        deflection_at_load_um: b.deflection_at_load_m * 1e6,
        max_deflection_um: b.max_deflection_m * 1e6,
        max_stress_mpa: stress * 1e-6,
        safety_factor: safety_factor(g, stress),
        max_permissible_load_n: permissible_load_n(g, stress, force_n),
        sensitivity_mv_per_n: sens,
        most_sensitive: best,
        reactions_n: Reactions {
            support1: r.support1_n,
            support2: r.support2_n,
        },
        electrodes: r.electrodes,
        warnings: Vec::new(),
        convergence: Vec::new(),
    }
}

/// Fracture strength over the stress (infinite when unstressed).
fn safety_factor(g: &SensorGeometry, stress_pa: f64) -> f64 {
    if stress_pa > 0.0 {
        g.fracture_strength_mpa * 1e6 / stress_pa
    } else {
        f64::INFINITY
    }
}

/// The load at which the stress reaches the fracture strength over the required safety factor
/// (the model is linear in the load).
fn permissible_load_n(g: &SensorGeometry, stress_pa: f64, force_n: f64) -> f64 {
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

/// The plate path of [`evaluate_many`]: the level loop, then one report per scene.
fn evaluate_plate(
    g: &SensorGeometry,
    scenes: &[Scene],
    tol: f64,
    max_levels: usize,
    mesh: MeshOptions,
) -> Result<Vec<SceneReport>, SensorError> {
    let loads: Vec<SceneLoads> = scenes.iter().map(|s| split(&s.load, g)).collect();
    let levels = solve_levels(g, &loads, tol, max_levels, mesh)?;
    Ok(scenes
        .iter()
        .zip(&loads)
        .enumerate()
        .map(|(k, (scene, l))| scene_report(g, scene, l, k, &levels, tol))
        .collect())
}

/// What the level loop leaves: per scene the history of its quantities (deflection at the load,
/// then each electrode's charge) and estimates, the cost of each level, and the last level's
/// solutions and readings.
struct Levels {
    /// Per scene, per level: [w at the load, charge of each electrode].
    history: Vec<Vec<Vec<f64>>>,
    /// Per scene, per level: (estimate, observed order) after that level.
    estimates: Vec<Vec<(Option<f64>, Option<f64>)>>,
    /// Per level: (element size, elements, dofs, ms).
    cost: Vec<(f64, usize, usize, f64)>,
    elapsed_ms: f64,
    solutions: Vec<Option<crate::fe::PlateSolution>>,
    info: ModelInfo,
    readouts: Vec<Readout>,
}

fn latest(est: &[(Option<f64>, Option<f64>)]) -> (Option<f64>, Option<f64>) {
    est.last().copied().unwrap_or((None, None))
}

/// Solves all scenes on the shared mesh sequence (one factorisation per level, the scenes as one
/// multi-column solve) until every plate scene's estimate is under `tol` or `max_levels` ran.
fn solve_levels(
    g: &SensorGeometry,
    loads: &[SceneLoads],
    tol: f64,
    max_levels: usize,
    mesh: MeshOptions,
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
    let mut out = Levels {
        history: vec![Vec::new(); n],
        estimates: vec![Vec::new(); n],
        cost: Vec::new(),
        elapsed_ms: 0.0,
        solutions: vec![None; n],
        info: ModelInfo::direct(),
        readouts: Vec::new(),
    };
    let levels = if needs_plate { max_levels } else { 1 };
    let base = base_lines(g, loads, &sym, mesh.graded);
    for (level, &sub) in SUBDIVISIONS.iter().enumerate().take(levels) {
        let t0 = Instant::now();
        let h = COARSE_ELEMENT_UM / sub as f64;
        let (sols, info) = if needs_plate {
            let problem = build_problem(g, &base, level, &sym);
            let values = 4 * problem.mesh.n_nodes() * n;
            if values > MAX_SOLUTION_VALUES {
                return Err(SensorError::TooLarge {
                    loads: n,
                    dofs: 4 * problem.mesh.n_nodes(),
                    level: level + 1,
                });
            }
            let solved = Factorised::new(&problem)?.solve(&part_cases)?;
            let sols: Vec<_> = solved
                .into_iter()
                .zip(loads)
                .map(|(s, l)| (!l.plate.is_empty()).then(|| sym.expand(s)))
                .collect();
            let info = ModelInfo {
                kind: ModelKind::Plate,
                elements: problem.mesh.n_elements(),
                dofs: 4 * problem.mesh.n_nodes(),
                levels: level + 1,
                max_element_um: h,
                observed_order: None,
                symmetry: sym.describe(),
                grading: mesh.graded.then(|| grading_description(loads)),
            };
            (sols, info)
        } else {
            (vec![None; n], ModelInfo::direct())
        };
        let dt = t0.elapsed().as_secs_f64() * 1e3;
        out.elapsed_ms += dt;
        out.cost.push((h, info.elements, info.dofs, dt));
        out.readouts = loads
            .iter()
            .enumerate()
            .map(|(k, l)| {
                let r = read(g, sols[k].as_ref(), &l.direct);
                let w = sols[k]
                    .as_ref()
                    .map_or(0.0, |s| s.deflection_m(l.at_um.0, l.at_um.1));
                let mut q = vec![w];
                q.extend(r.electrodes.iter().map(|e| e.charge_pc));
                out.history[k].push(q);
                let est = if out.history[k].len() >= 3 {
                    let (e, p) = estimate(&out.history[k], g);
                    (Some(e), p)
                } else {
                    latest(&out.estimates[k])
                };
                out.estimates[k].push(est);
                r
            })
            .collect();
        (out.solutions, out.info) = (sols, info);
        let done = out
            .estimates
            .iter()
            .zip(loads)
            .all(|(est, l)| l.plate.is_empty() || latest(est).0.is_some_and(|e| e < tol));
        if done {
            break;
        }
    }
    Ok(out)
}

/// The report of scene `k` from the level loop.
fn scene_report(
    g: &SensorGeometry,
    scene: &Scene,
    l: &SceneLoads,
    k: usize,
    levels: &Levels,
    tol: f64,
) -> SceneReport {
    let sol = levels.solutions[k].as_ref();
    let r = levels.readouts[k].clone();
    let (estimate_k, order_k) = latest(&levels.estimates[k]);
    let mut info = if sol.is_some() {
        levels.info.clone()
    } else {
        ModelInfo::direct()
    };
    info.observed_order = order_k;
    let history = &levels.history[k];
    let w_load = history.last().map_or(0.0, |q| q[0]);
    let peak = sol.map(|s| s.max_deflection());
    let w_max = peak.map_or(0.0, |p| p.w_m);
    let stress_pa = sol
        .and_then(|s| s.max_principal_stress(l.patch))
        .map_or(0.0, |p| p.sigma_pa);
    let f = l.total_force_n;
    let (best, sens) = most_sensitive(&r, f);
    let ratio = sol
        .zip(peak.as_ref())
        .map_or(0.0, |(s, p)| s.linear_range_ratio_at(p));
    let converged = sol.is_none() || estimate_k.is_some_and(|e| e < tol);
    let mut warnings = scene_warnings(w_max, ratio, converged, estimate_k, order_k, &info, tol);
    warnings.extend(overhang(scene, g));
    SceneReport {
        scene: scene.name.clone(),
        force_n: f,
        solve_ms: levels.elapsed_ms,
        error_estimate: if sol.is_none() { Some(0.0) } else { estimate_k },
        converged,
        deflection_at_load_um: w_load * 1e6,
        max_deflection_um: w_max * 1e6,
        max_stress_mpa: stress_pa * 1e-6,
        safety_factor: safety_factor(g, stress_pa),
        max_permissible_load_n: permissible_load_n(g, stress_pa, f),
        sensitivity_mv_per_n: sens,
        most_sensitive: best,
        reactions_n: Reactions {
            support1: r.support1_n,
            support2: r.support2_n,
        },
        electrodes: r.electrodes,
        warnings,
        convergence: convergence_records(history, &levels.cost, &levels.estimates[k]),
        model: info,
    }
}

/// What a plate answer should be read with: beyond the linear range, not converged, no estimate
/// or no observed order.
fn scene_warnings(
    w_max_m: f64,
    linear_range_ratio: f64,
    converged: bool,
    estimate: Option<f64>,
    order: Option<f64>,
    info: &ModelInfo,
    tol: f64,
) -> Vec<Finding> {
    let mut warnings = Vec::new();
    if linear_range_ratio > LINEAR_RANGE_LIMIT {
        warnings.push(Finding::warning(
            SceneCode::LinearRange,
            format!(
                "maximum deflection {:.1} um is {linear_range_ratio:.2} x the local thickness \
                 (limit {LINEAR_RANGE_LIMIT}): membrane stiffening is not modelled, readings \
                 overestimate",
                w_max_m.abs() * 1e6,
            ),
        ));
    }
    if !converged {
        warnings.push(match estimate {
            Some(e) => Finding::warning(
                SceneCode::NotConverged,
                format!(
                    "estimated error {e:.2e} is above the tolerance {tol:.0e} after {} mesh levels",
                    info.levels
                ),
            ),
            None => Finding::warning(
                SceneCode::NoErrorEstimate,
                format!("{} mesh level(s) give no three-mesh estimate", info.levels),
            ),
        });
    }
    if order.is_none() && estimate.is_some() && info.kind == ModelKind::Plate {
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
    cost: &[(f64, usize, usize, f64)],
    estimates: &[(Option<f64>, Option<f64>)],
) -> Vec<LevelRecord> {
    let largest = history.last().map(|q| {
        (1..q.len())
            .max_by(|&a, &b| q[a].abs().total_cmp(&q[b].abs()))
            .unwrap_or(0)
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

/// Relative error of the finest level: the worst quantity, each by the one three-mesh estimate
/// ([`ThreeMesh::fine_error`]) normalised by the largest magnitude of its kind (deflection; middle
/// charges; support charges), from the last three levels. The order is the deflection's.
fn estimate(history: &[Vec<f64>], g: &SensorGeometry) -> (f64, Option<f64>) {
    let n = history.len();
    let (f3, f2, f1) = (&history[n - 3], &history[n - 2], &history[n - 1]);
    let (r32, r21) = level_ratios(n - 1);
    let kind = |i: usize| -> usize {
        match i.checked_sub(1).map(|e| g.electrodes[e].side) {
            None => 0,
            Some(ElectrodeSide::Middle) => 1,
            Some(_) => 2,
        }
    };
    let mut scale = [0f64; 3];
    for (i, v) in f1.iter().enumerate() {
        scale[kind(i)] = scale[kind(i)].max(v.abs());
    }
    let mut worst: f64 = 0.0;
    for i in (0..f1.len()).filter(|&i| scale[kind(i)] > 0.0) {
        let e = ThreeMesh::new(f3[i], f2[i], f1[i], r32, r21).fine_error();
        worst = worst.max(e / scale[kind(i)]);
    }
    let order = ThreeMesh::new(f3[0], f2[0], f1[0], r32, r21)
        .richardson
        .observed_order;
    (worst, order)
}

/// The plate over the U-channel (or the part of it solved): clamped along the inner support
/// edges, teeth as thicker regions, symmetry lines on the mirrors.
fn build_problem(
    g: &SensorGeometry,
    base: &(Vec<f64>, Vec<f64>),
    level: usize,
    sym: &Symmetry,
) -> PlateProblem {
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
        })
        .filter(|t| t.x1_um > t.x0_um && t.y1_um > t.y0_um)
        .collect();
    let (x0, x1, y0, y1) = sym.domain_um;
    for (side, y) in [
        (ElectrodeSide::Support1, g.plate_y0_um),
        (ElectrodeSide::Support2, g.plate_y1_um),
    ] {
        if y >= y0 && y <= y1 {
            let group = group_for(side).to_string();
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
    p
}
