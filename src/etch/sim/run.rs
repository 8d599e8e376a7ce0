//! The entry from a process: the front etch of the plan, its orientation rate table from the
//! process file's `etchants`, and the tooth cell of the generated masks.

use crate::etch::{EtchPlan, EtchStep};
use crate::finding::{EtchCode, Finding};
use crate::layout::MaskSet;
use crate::process::{Etchant, Etchants, Process, Side};

use super::cell::tooth_cell;
use super::rate_table::RateTable;
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
/// time.
pub fn simulate(
    p: &Process,
    plan: &EtchPlan,
    masks: &MaskSet,
    grid_um: f64,
) -> Result<ToothSimulation, SimError> {
    let step = front_step(plan).ok_or(SimError::NoFrontEtch)?;
    simulate_with(p, step, masks, grid_um, rate_table(step, &p.etchants))
}

/// The same with another rate table (the sensitivity sweep).
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
    )
}

/// ETCHED_CORNER_DEVIATION when the simulated corner lies beyond the process's tolerance.
pub fn finding(sim: &ToothSimulation) -> Option<Finding> {
    let what = match sim.corner_shape {
        CornerShape::Square => return None,
        CornerShape::Rounded => "rounded: the corner receded",
        CornerShape::OverCompensated => "over-compensated: compensator silicon stands",
    };
    Some(Finding::warning(
        EtchCode::EtchedCornerDeviation,
        format!(
            "the simulated tooth-top corner after {:.2} h is {what} {:.1} um along the diagonal \
             from the drawn corner (tolerance etchants.etched_corner_tolerance_um = {} um); \
             edge undercut {:.1} um",
            sim.time_h,
            sim.corner_deviation_um.abs(),
            sim.tolerance_um,
            sim.edge_undercut_um
        ),
    ))
}
