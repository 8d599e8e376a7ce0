//! Running a range of designs in parallel, the matching family and the error estimate.

use rayon::prelude::*;
use serde::Serialize;

use crate::fe::{FeResult, ThreeMesh};
use crate::sweep::design::{Design, DesignModel, DesignSolver, Grid, Response};

/// One CSV row: a design, its response and whether it belongs to the prototype's family.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Row {
    pub design: Design,
    pub response: Response,
    /// elongation / prototype elongation.
    pub elongation_ratio: f64,
    /// |ratio - 1| <= tol: "an elongation very close to that of the prototyped sensor" (paper 001 sec. 4.1).
    pub matches: bool,
    /// max stress <= fracture strength / safety factor (paper 001: 4 GPa / 3).
    pub within_strength: bool,
}

/// What the family is matched against.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Matching {
    pub prototype: Design,
    pub prototype_response: Response,
    /// Relative tolerance on the elongation (paper 001 gives none; default 0.01).
    pub tol: f64,
    /// Allowed stress (MPa) = fracture strength / safety factor.
    pub allowed_stress_mpa: f64,
}

impl Matching {
    /// Solve the prototype with the sweep's own mesh and model, so a design equal to the prototype
    /// matches exactly.
    pub fn new(
        prototype: Design,
        model: &DesignModel,
        tol: f64,
        allowed_stress_mpa: f64,
    ) -> FeResult<Self> {
        let prototype_response = DesignSolver::new(*model).solve(&prototype)?;
        Ok(Matching {
            prototype,
            prototype_response,
            tol,
            allowed_stress_mpa,
        })
    }

    /// Row of a design's response.
    pub fn row(&self, design: Design, response: Response) -> Row {
        let ratio = response.elongation_um / self.prototype_response.elongation_um;
        Row {
            design,
            response,
            elongation_ratio: ratio,
            matches: (ratio - 1.0).abs() <= self.tol,
            within_strength: response.max_stress_mpa <= self.allowed_stress_mpa,
        }
    }
}

/// How the thickness axis is computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Mode {
    /// One FE solve per (length, width) at [`REFERENCE_THICKNESS_UM`], scaled to every thickness:
    /// a uniform Kirchhoff plate has K proportional to t^3, so w ~ t^-3, elongation ~ t^-6 and the
    /// bending stress ~ t^-2 exactly (checked against direct solves in the tests). The numeric
    /// factorisation of the reference thickness serves all 20 thicknesses (only a scale changes).
    ScaledThickness,
    /// One numeric refactorisation per design on the shared symbolic factorisation.
    Direct,
}

/// Thickness of the reference solve in [`Mode::ScaledThickness`] (fixed, so shards agree bit for
/// bit).
pub const REFERENCE_THICKNESS_UM: f64 = 100.0;

/// A response at thickness t from the one at the reference thickness (uniform Kirchhoff plate).
pub fn scale_to_thickness(r: &Response, thickness_um: f64) -> Response {
    let s = REFERENCE_THICKNESS_UM / thickness_um;
    Response {
        deflection_um: r.deflection_um * s.powi(3),
        elongation_um: r.elongation_um * s.powi(6),
        max_stress_mpa: r.max_stress_mpa * s * s,
    }
}

/// Rows for the design indices `range` of the grid, in index order. Work runs in parallel (rayon),
/// each worker keeps one symbolic factorisation; `progress(n)` is called as designs finish.
/// Results do not depend on the thread count or on how the range is cut into shards.
pub fn run_range(
    grid: &Grid,
    model: &DesignModel,
    matching: &Matching,
    range: std::ops::Range<usize>,
    mode: Mode,
    progress: &(dyn Fn(u64) + Sync),
) -> FeResult<Vec<Row>> {
    match mode {
        Mode::Direct => range
            .into_par_iter()
            .map_init(
                || DesignSolver::new(*model),
                |solver, i| {
                    let d = grid.design(i);
                    let r = solver.solve(&d)?;
                    progress(1);
                    Ok(matching.row(d, r))
                },
            )
            .collect(),
        Mode::ScaledThickness => {
            let nt = grid.thickness_um.steps;
            let groups: Vec<usize> = if range.is_empty() {
                Vec::new()
            } else {
                (range.start / nt..=(range.end - 1) / nt).collect()
            };
            let per_group: Vec<Vec<Row>> = groups
                .into_par_iter()
                .map_init(
                    || DesignSolver::new(*model),
                    |solver, g| {
                        let first = grid.design(g * nt);
                        let r0 = solver.solve(&Design {
                            thickness_um: REFERENCE_THICKNESS_UM,
                            ..first
                        })?;
                        let rows: Vec<Row> = (g * nt..(g + 1) * nt)
                            .filter(|i| range.contains(i))
                            .map(|i| {
                                let d = grid.design(i);
                                matching.row(d, scale_to_thickness(&r0, d.thickness_um))
                            })
                            .collect();
                        progress(rows.len() as u64);
                        Ok(rows)
                    },
                )
                .collect::<FeResult<_>>()?;
            Ok(per_group.into_iter().flatten().collect())
        }
    }
}

/// Estimated discretisation error of the sweep mesh for one design: three nested meshes (the
/// sweep's, 2x and 4x finer) and the one three-mesh estimate per quantity
/// ([`ThreeMesh::relative_error_of`] the sweep mesh's value).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DesignError {
    pub design: Design,
    pub deflection_rel: f64,
    pub elongation_rel: f64,
    pub max_stress_rel: f64,
}

/// Error of the sweep mesh at `designs` (e.g. the grid corners and the prototype).
pub fn estimate_error(model: &DesignModel, designs: &[Design]) -> FeResult<Vec<DesignError>> {
    designs
        .par_iter()
        .map(|d| {
            let levels: Vec<Response> = [1.0, 2.0, 4.0]
                .iter()
                .map(|&r| {
                    DesignSolver::new(DesignModel {
                        mesh: model.mesh.refined(r),
                        ..*model
                    })
                    .solve(d)
                })
                .collect::<FeResult<_>>()?;
            // Error of the coarsest (the sweep's) level against the best estimate of the limit.
            let rel = |f: fn(&Response) -> f64| {
                let (f3, f2, f1) = (f(&levels[0]), f(&levels[1]), f(&levels[2]));
                ThreeMesh::new(f3, f2, f1, 2.0, 2.0).relative_error_of(f3)
            };
            Ok(DesignError {
                design: *d,
                deflection_rel: rel(|r| r.deflection_um),
                elongation_rel: rel(|r| r.elongation_um),
                max_stress_rel: rel(|r| r.max_stress_mpa),
            })
        })
        .collect()
}

/// The eight corners of the grid (error-estimate sample).
pub fn corner_designs(grid: &Grid) -> Vec<Design> {
    let (nl, nw, nt) = (
        grid.length_um.steps,
        grid.width_um.steps,
        grid.thickness_um.steps,
    );
    let mut v = Vec::new();
    for il in [0, nl - 1] {
        for iw in [0, nw - 1] {
            for it in [0, nt - 1] {
                v.push(grid.design((il * nw + iw) * nt + it));
            }
        }
    }
    v.dedup_by_key(|d| d.index);
    v
}
