//! The entry from a process: the front etch of the plan, its orientation rate table from the
//! process file's `etchants`, and the tooth cell of the generated masks.

use crate::etch::{EtchPlan, EtchStep};
use crate::finding::{EtchCode, Finding};
use crate::layout::MaskSet;
use crate::process::{Etchant, Etchants, Process, Side};

use super::back::{simulate_back_cell, with_errors, BackSimulation, BackStep};
use super::back_cell::{back_cell, reach_um};
use super::cell::tooth_cell;
use super::rate_table::RateTable;
use super::richardson::{corner_error, ToleranceDecision};
use super::tooth::{simulate_cell, CornerShape, ToothSimulation};
use super::SimError;

/// Default grid step of `tactfab etch --simulate` \[choice: the 5 um\].
pub const DEFAULT_GRID_UM: f64 = 5.0;
/// Plan-view contour frames kept for the SVG.
pub const FRAMES: usize = 4;

/// The plan's first front-side silicon etch (the one that makes the teeth).
pub fn front_step(plan: &EtchPlan) -> Option<&EtchStep> {
    plan.steps
        .iter()
        .find(|s| matches!(s.side, Side::Front | Side::Both))
}

/// The step's orientation table: (100), (110) and (111) as the plan computed them (measured
/// rate and its ratios), {311} and {411} from the `etchants` ratios of its etchant.
pub fn rate_table(step: &EtchStep, et: &Etchants) -> RateTable {
    let r100 = step.rate_um_per_h;
    let (r311, r411) = match step.etchant {
        Etchant::Tmah => (et.tmah_r311_over_r100, et.tmah_r411_over_r100),
        Etchant::Koh => (et.koh_r311_over_r100, et.koh_r411_over_r100),
    };
    RateTable {
        r100_um_per_h: r100,
        r110_um_per_h: step.rate_110_um_per_h,
        r111_um_per_h: step.rate_111_um_per_h,
        r311_um_per_h: Some(r311 * r100),
        r411_um_per_h: r411.map(|r| r * r100),
    }
}

/// Simulates the front etch of one tooth cell with the process's own table, for the recipe's
/// time, on `grid_um` and on its double for the corner's discretisation error
/// ([`with_corner_error`]; the double costs 1/8 more).
pub fn simulate(
    p: &Process,
    plan: &EtchPlan,
    masks: &MaskSet,
    grid_um: f64,
) -> Result<ToothSimulation, SimError> {
    let step = front_step(plan).ok_or(SimError::NoFrontEtch)?;
    let table = rate_table(step, &p.etchants);
    let fine = simulate_with(p, step, masks, grid_um, table)?;
    let coarse = simulate_with(p, step, masks, 2.0 * grid_um, table)?;
    Ok(with_corner_error(fine, &coarse))
}

/// The fine run with its corner's Richardson estimate from the `coarse` run of the same cell
/// (none when either corner is bridged: the cap does not converge); its `corner_shape` is then
/// judged on the extrapolated corner.
#[track_caller]
pub fn with_corner_error(mut fine: ToothSimulation, coarse: &ToothSimulation) -> ToothSimulation {
    assert!(
        coarse.grid_um > fine.grid_um && coarse.cell_um == fine.cell_um,
        "the coarse run must be the same cell on a coarser grid"
    );
    if fine.corner_bridged || coarse.corner_bridged {
        return fine;
    }
    let e = corner_error(
        fine.corner_deviation_um,
        fine.grid_um,
        coarse.corner_deviation_um,
        coarse.grid_um,
        fine.tolerance_um,
    );
    fine.corner_shape = CornerShape::of(e.extrapolated_corner_deviation_um, fine.tolerance_um);
    fine.corner_error = Some(e);
    fine
}

/// The same with another rate table (the sensitivity sweep). The step's compensation says what
/// the masks draw (a bar's consumption is read along the bar).
pub fn simulate_with(
    p: &Process,
    step: &EtchStep,
    masks: &MaskSet,
    grid_um: f64,
    table: RateTable,
) -> Result<ToothSimulation, SimError> {
    let cell = tooth_cell(masks, &p.geometry.teeth, grid_um)?;
    simulate_cell(
        table,
        &cell,
        step.time_h,
        p.etchants.etched_corner_tolerance_um,
        FRAMES,
        step.compensation.and_then(|c| c.bar_width_um),
    )
}

/// The plan's back-side silicon etches in order (the U-channel), each with its own table.
pub fn back_steps(plan: &EtchPlan, et: &Etchants) -> Vec<BackStep> {
    plan.steps
        .iter()
        .filter(|s| matches!(s.side, Side::Back | Side::Both))
        .map(|s| BackStep {
            name: s.name.clone(),
            time_h: s.time_h,
            rates: rate_table(s, et),
        })
        .collect()
}

/// Simulates the back etch of a support corner (the U-channel's wall and the supports'
/// corners) for the recipe's back-side steps, on `grid_um` and its double (Richardson); none
/// when the recipe etches nothing from the back or the back mask draws nothing.
pub fn simulate_back(
    p: &Process,
    plan: &EtchPlan,
    masks: &MaskSet,
    grid_um: f64,
) -> Result<Option<BackSimulation>, SimError> {
    let steps = back_steps(plan, &p.etchants);
    if steps.is_empty() || masks.die_layer(crate::layout::LayerKind::BackSi).is_empty() {
        return Ok(None);
    }
    let r110_t: f64 = steps.iter().map(|s| s.rates.r110_um_per_h * s.time_h).sum();
    let reach = reach_um(r110_t, plan.back_depth_um);
    let g = &p.geometry;
    let run = |step_um: f64| {
        let cell = back_cell(
            masks,
            g.dicing_street_um,
            g.support_width_um,
            reach,
            step_um,
        )?;
        simulate_back_cell(&cell, &steps, plan.channel_floor_y_um[0], FRAMES)
    };
    let fine = run(grid_um)?;
    let coarse = run(2.0 * grid_um)?;
    Ok(Some(with_errors(fine, &coarse)))
}

/// ETCHED_CORNER_DEVIATION when the simulated corner lies beyond the process's tolerance, or
/// when the tolerance falls within the corner's discretisation error (then the message says a
/// finer grid decides). Judged on the extrapolated corner when its error is known.
pub fn finding(sim: &ToothSimulation) -> Option<Finding> {
    let best = sim.corner_error.map_or(sim.corner_deviation_um, |e| {
        e.extrapolated_corner_deviation_um
    });
    let undecided = sim
        .corner_error
        .is_some_and(|e| e.decision == ToleranceDecision::WithinError);
    let what = match (CornerShape::of(best, sim.tolerance_um), undecided) {
        (_, true) if best < 0.0 => "rounded by about",
        (_, true) => "over-compensated by about",
        (CornerShape::Square, false) => return None,
        (CornerShape::Rounded, false) => "rounded: the corner receded",
        (CornerShape::OverCompensated, false) => "over-compensated: compensator silicon stands",
    };
    let grid = match sim.corner_error {
        Some(e) => format!(
            " (extrapolated from {:.1} um on the {} um grid and {:.1} um on {} um; \
             discretisation error +/- {:.1} um{})",
            sim.corner_deviation_um,
            sim.grid_um,
            e.coarse_corner_deviation_um,
            e.coarse_grid_um,
            e.error_um.abs(),
            if undecided {
                ": the tolerance lies within that error, a finer --grid-um decides"
            } else {
                ""
            }
        ),
        None if sim.corner_bridged => " (the top bridges to the neighbour tooth)".to_string(),
        None => format!(" (on the {} um grid, error not estimated)", sim.grid_um),
    };
    Some(Finding::warning(
        EtchCode::EtchedCornerDeviation,
        format!(
            "the simulated tooth-top corner after {:.2} h is {what} {:.1} um along the diagonal \
             from the drawn corner{grid} (tolerance etchants.etched_corner_tolerance_um = {} \
             um); edge undercut {:.1} um",
            sim.time_h,
            best.abs(),
            sim.tolerance_um,
            sim.edge_undercut_um
        ),
    ))
}
