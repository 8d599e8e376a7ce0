//! Compensation sizing by simulation (issue 19, item 3): for the recipe's etchant and time, the
//! compensator size a (ratio h / a) whose simulated corner lies within
//! `etchants.etched_corner_tolerance_um`, for each geometry the layout draws (corner-attached
//! and centred squares, <110> bars of length a), by bracketing and bisection on the corner,
//! compared with the paper's KOH rule a = h / 0.544.
//!
//! A larger compensator leaves more silicon at the corner (the corner deviation rises with a;
//! `tests_tooth` checks it), so the corner's zero is bracketed by a = 0 (no compensator: the
//! corner rounds) and the largest a the street and the die allow; bisection then halves the
//! bracket until it is no wider than the grid step (the raster cannot resolve less) or
//! [`MAX_BISECTION_STEPS`]. Every probe is judged on its Richardson-extrapolated corner
//! ([`super::richardson`]): on 5 um the corner is not converged by more than a typical
//! tolerance.

use serde::Serialize;

use crate::etch::compensation::{default_bar_width_um, design, largest_a_um};
use crate::etch::{CompensationDesign, EtchPlan};
use crate::layout::{LayerKind, MaskSet};
use crate::process::{CompensationGeometry, Process};

use super::run::{front_step, simulate};
use super::SimError;

/// Most bisection steps per geometry after the two ends \[choice: 8 halvings of a ~500 um
/// bracket reach 2 um, below any grid step used\].
pub const MAX_BISECTION_STEPS: usize = 8;
/// The paper's rule a = h / 0.544 (paper 002 sec. VI.A, a KOH rule; process-physics.md).
pub const RULE_RATIO: f64 = 0.544;
/// Geometries the layout draws (`src/layout/teeth.rs`). The <110> bar (Bao 1993) has no sizing
/// rule in reference/process-physics.md; its L is judged against the squares' a = h / 0.544.
pub const GEOMETRIES: [CompensationGeometry; 3] = [
    CompensationGeometry::CornerAttached,
    CompensationGeometry::Centred,
    CompensationGeometry::Bar110,
];

/// One simulated compensator size.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Probe {
    pub a_um: f64,
    /// h / a; none for a = 0 (no compensator).
    pub ratio: Option<f64>,
    /// The corner on the sizing grid.
    pub corner_deviation_um: f64,
    /// Its Richardson extrapolation; none when the top bridges to the neighbour.
    pub extrapolated_corner_deviation_um: Option<f64>,
    pub error_um: Option<f64>,
    pub bridged: bool,
}

impl Probe {
    /// The best estimate: extrapolated, else the grid's (a bridged cap).
    pub fn best_um(&self) -> f64 {
        self.extrapolated_corner_deviation_um
            .unwrap_or(self.corner_deviation_um)
    }
}

/// The paper's rule against the sizing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RuleVerdict {
    /// The rule's a leaves the corner within the tolerance.
    Confirmed,
    /// It does not; the sized a does.
    Corrected,
    /// Neither the rule's a nor any a that fits meets the tolerance.
    NoneMeetsTolerance,
    /// The rule's a is beyond the largest that fits (not simulated).
    DoesNotFit,
}

/// The sizing of one geometry.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GeometrySizing {
    pub geometry: CompensationGeometry,
    /// A bar's width b (its a is the length L); absent for squares.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bar_width_um: Option<f64>,
    /// The largest a the teeth can carry ([`largest_a_um`]) and what limits it.
    pub largest_a_um: f64,
    pub limited_by: &'static str,
    /// Every probe, in the order simulated.
    pub probes: Vec<Probe>,
    /// The probe whose best corner lies nearest the drawn corner (the smaller a on a tie: a
    /// change of a within a grid cell may not change the raster).
    pub sized_a_um: f64,
    pub sized_ratio: Option<f64>,
    pub sized_corner_deviation_um: f64,
    /// Whether that corner is within the tolerance (when not, it is the best achievable).
    pub within_tolerance: bool,
    /// The final bracket of the corner's zero: the a whose corner is still < 0 and the a whose
    /// corner is > 0, with their corners; none when the corner does not change sign over
    /// [0, largest a].
    pub bracket_a_um: Option<[f64; 2]>,
    pub bracket_corner_um: Option<[f64; 2]>,
    /// a between which the corner is within +/- tolerance, linear between the probes (an
    /// estimate for the test die's range); none when no probe interval reaches it.
    pub tolerance_band_a_um: Option<[f64; 2]>,
    /// The rule a = h / 0.544 and its corner (when it fits).
    pub rule_a_um: f64,
    pub rule_corner_deviation_um: Option<f64>,
    pub rule: RuleVerdict,
}

/// The sizing for the recipe.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Sizing {
    /// The grid the probes ran on, and its double (Richardson).
    pub grid_um: f64,
    pub coarse_grid_um: f64,
    pub depth_um: f64,
    pub time_h: f64,
    pub tolerance_um: f64,
    pub rule_ratio: f64,
    pub max_bisection_steps: usize,
    /// Simulations run (each a grid and its double).
    pub evaluations: usize,
    pub geometries: Vec<GeometrySizing>,
}

impl Sizing {
    /// The sizing of one geometry.
    pub fn of(&self, g: CompensationGeometry) -> Option<&GeometrySizing> {
        self.geometries.iter().find(|s| s.geometry == g)
    }
}

/// Sizes every geometry of [`GEOMETRIES`] for the process's front etch on `grid_um`.
pub fn size(
    p: &Process,
    plan: &EtchPlan,
    masks: &MaskSet,
    grid_um: f64,
) -> Result<Sizing, SimError> {
    let step = front_step(plan).ok_or(SimError::NoFrontEtch)?;
    let name = masks.tooth_cell.clone().ok_or(SimError::NoTeeth)?;
    let h = step.depth_um;
    let tol = p.etchants.etched_corner_tolerance_um;
    let overlap = p.layout.compensation_overlap_um;
    // A bar is as wide as the front etch's, else the plan's default width.
    let bar_width_um = step
        .compensation
        .and_then(|c| c.bar_width_um)
        .unwrap_or_else(|| {
            default_bar_width_um(
                step.undercut_um,
                p.drc.min_width_um,
                p.geometry.teeth.top_um,
            )
        });
    let mut m = masks.clone();
    // The plan says what the masks draw (a bar's consumption is read along the bar).
    let mut pl = plan.clone();
    let front = plan
        .steps
        .iter()
        .position(|s| std::ptr::eq(s, step))
        .expect("the front step is the plan's");
    let mut evaluations = 0;
    let mut coarse_grid_um = 2.0 * grid_um;
    let mut eval = |kind: CompensationGeometry, a: f64| -> Result<Probe, SimError> {
        // A corner-attached square no larger than its overlap lies inside the tooth: none.
        let d: Option<CompensationDesign> = (a > 0.0
            && !(kind == CompensationGeometry::CornerAttached && a <= overlap))
            .then(|| {
                let b = (kind == CompensationGeometry::Bar110).then_some(bar_width_um);
                design(h, h / a, kind, b)
            });
        let cell = m
            .cells
            .get_mut(&name)
            .expect("the tooth cell is in the mask set");
        cell.shapes.insert(
            LayerKind::FrontSi,
            crate::layout::teeth::tooth_cell(p.geometry.teeth.top_um, d.as_ref(), overlap),
        );
        pl.steps[front].compensation = d;
        let s = simulate(p, &pl, &m, grid_um)?;
        evaluations += 1;
        if let Some(e) = s.corner_error {
            coarse_grid_um = e.coarse_grid_um;
        }
        Ok(Probe {
            a_um: a,
            ratio: d.map(|d| d.ratio),
            corner_deviation_um: s.corner_deviation_um,
            extrapolated_corner_deviation_um: s
                .corner_error
                .map(|e| e.extrapolated_corner_deviation_um),
            error_um: s.corner_error.map(|e| e.error_um),
            bridged: s.corner_bridged,
        })
    };
    let mut zero: Option<Probe> = None;
    let mut geometries = Vec::new();
    for kind in GEOMETRIES {
        let (a_max, limited_by) = largest_a_um(&p.geometry, kind, p.drc.min_space_um);
        let a_rule = h / RULE_RATIO;
        // a = 0 is the same mask for every geometry: simulated once.
        let lo = match zero {
            Some(z) => z,
            None => *zero.insert(eval(kind, 0.0)?),
        };
        let mut probes = vec![lo];
        let hi = eval(kind, a_max)?;
        probes.push(hi);
        let (mut lo, mut hi) = (lo, hi);
        let mut rule_probe = None;
        if lo.best_um() < 0.0 && hi.best_um() > 0.0 {
            for k in 0..MAX_BISECTION_STEPS {
                if hi.a_um - lo.a_um <= grid_um {
                    break;
                }
                // The first probe is the rule's a when it lies inside the bracket.
                let a = if k == 0 && a_rule > lo.a_um && a_rule < hi.a_um {
                    a_rule
                } else {
                    0.5 * (lo.a_um + hi.a_um)
                };
                let q = eval(kind, a)?;
                probes.push(q);
                if a == a_rule {
                    rule_probe = Some(q);
                }
                if q.best_um() < 0.0 {
                    lo = q;
                } else {
                    hi = q;
                }
            }
        }
        if rule_probe.is_none() && a_rule <= a_max {
            let q = eval(kind, a_rule)?;
            probes.push(q);
            rule_probe = Some(q);
        }
        let best = *probes
            .iter()
            .min_by(|x, y| {
                // Ties (the same raster) go to the smaller compensator.
                (x.best_um().abs(), x.a_um)
                    .partial_cmp(&(y.best_um().abs(), y.a_um))
                    .expect("finite")
            })
            .expect("two probes at least");
        let within_tolerance = best.best_um().abs() <= tol;
        let bracket = (lo.best_um() < 0.0 && hi.best_um() > 0.0).then_some((lo, hi));
        let rule = match rule_probe {
            None => RuleVerdict::DoesNotFit,
            Some(r) if r.best_um().abs() <= tol => RuleVerdict::Confirmed,
            Some(_) if within_tolerance => RuleVerdict::Corrected,
            Some(_) => RuleVerdict::NoneMeetsTolerance,
        };
        geometries.push(GeometrySizing {
            geometry: kind,
            bar_width_um: (kind == CompensationGeometry::Bar110).then_some(bar_width_um),
            largest_a_um: a_max,
            limited_by,
            sized_a_um: best.a_um,
            sized_ratio: best.ratio,
            sized_corner_deviation_um: best.best_um(),
            within_tolerance,
            bracket_a_um: bracket.map(|(l, h)| [l.a_um, h.a_um]),
            bracket_corner_um: bracket.map(|(l, h)| [l.best_um(), h.best_um()]),
            tolerance_band_a_um: tolerance_band(&probes, tol),
            rule_a_um: a_rule,
            rule_corner_deviation_um: rule_probe.map(|r| r.best_um()),
            rule,
            probes,
        });
    }
    Ok(Sizing {
        grid_um,
        coarse_grid_um,
        depth_um: h,
        time_h: step.time_h,
        tolerance_um: tol,
        rule_ratio: RULE_RATIO,
        max_bisection_steps: MAX_BISECTION_STEPS,
        evaluations,
        geometries,
    })
}

/// The a range whose corner lies within +/- `tol`, linear between the probes sorted by a (the
/// corner taken as monotone in a); an end at the first or last probe when that probe is already
/// within.
pub fn tolerance_band(probes: &[Probe], tol: f64) -> Option<[f64; 2]> {
    let mut pts: Vec<(f64, f64)> = probes.iter().map(|p| (p.a_um, p.best_um())).collect();
    pts.sort_by(|x, y| x.0.total_cmp(&y.0));
    pts.dedup_by(|x, y| x.0 == y.0);
    let cross = |level: f64| {
        pts.windows(2).find_map(|w| {
            let ((a0, c0), (a1, c1)) = (w[0], w[1]);
            (c0 < level && c1 >= level).then(|| a0 + (a1 - a0) * (level - c0) / (c1 - c0))
        })
    };
    let (first, last) = (*pts.first()?, *pts.last()?);
    let lower = if first.1.abs() <= tol {
        Some(first.0)
    } else {
        cross(-tol)
    };
    let upper = if last.1.abs() <= tol {
        Some(last.0)
    } else {
        cross(tol)
    };
    match (lower, upper) {
        (Some(l), Some(u)) if l <= u => Some([l, u]),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn probe(a_um: f64, c: f64) -> Probe {
        Probe {
            a_um,
            ratio: None,
            corner_deviation_um: c,
            extrapolated_corner_deviation_um: Some(c),
            error_um: Some(0.0),
            bridged: false,
        }
    }

    #[test]
    fn tolerance_band_is_linear_between_probes() {
        // Corner = a - 300 sampled at 0, 200, 400: within +/- 25 for a in 275..325.
        let ps = [
            probe(0.0, -300.0),
            probe(400.0, 100.0),
            probe(200.0, -100.0),
        ];
        let b = tolerance_band(&ps, 25.0).unwrap();
        assert!(
            (b[0] - 275.0).abs() < 1e-9 && (b[1] - 325.0).abs() < 1e-9,
            "{b:?}"
        );
        // Never within: none; within at the last probe: the band ends there.
        assert!(tolerance_band(&[probe(0.0, -300.0), probe(100.0, -200.0)], 25.0).is_none());
        let b = tolerance_band(&[probe(0.0, -300.0), probe(300.0, 0.0)], 25.0).unwrap();
        assert!((b[0] - 275.0).abs() < 1e-9 && b[1] == 300.0, "{b:?}");
    }
}
