//! The thresholds of the plan's checks. The traveler's tolerances and hold-point criteria are these
//! same numbers, so a step the run sheet accepts is one the plan does not flag.

use std::ops::RangeInclusive;

/// OXIDE_CLAIM: the oxidation model against the source's claimed thickness, relative [choice: a
/// furnace run repeats to a few %].
pub const OXIDE_CLAIM_REL: f64 = 0.05;
/// ETCH_TIME_DEPTH_MISMATCH and PLATE_THICKNESS_MISMATCH: beyond this relative difference a time
/// or a thickness "does not add up" \[choice\].
pub const MISMATCH_REL: f64 = 0.01;
/// PLATE_THICKNESS_MISMATCH is an error, not a warning, beyond this relative difference: the plate
/// is another device \[choice\].
pub const PLATE_MISMATCH_ERROR_REL: f64 = 0.25;
/// PLATE_TOLERANCE: the wafer's thickness tolerance as a share of the plate beyond which the etch
/// must stop early and be finished after a measurement \[choice\].
pub const PLATE_TOLERANCE_REL: f64 = 0.05;
/// HILLOCK_RISK: TMAH below this concentration forms hillocks on (100) (Tabata et al. 1992, via
/// `reference/process-physics.md`).
pub const TMAH_HILLOCK_WT_PCT: f64 = 22.0;
/// RATE_MODEL_DISAGREES: a measured (100) rate this far from the model, relative \[choice\].
pub const RATE_MODEL_REL: f64 = 0.3;
/// MASK_MARGIN_LOW: oxide left after the silicon etch below this share of the grown oxide.
pub const MASK_MARGIN_REL: f64 = 0.25;
/// COMP_RATIO_FROM_KOH: compensation ratios in this range are the KOH rule a = h / 0.544 (paper
/// 002 ref. \[33\]).
pub const KOH_RULE_RATIO: RangeInclusive<f64> = 0.53..=0.56;
/// PIEZO_CONSTANTS_INCONSISTENT: eps_r implied by g = d / (eps0 eps_r) this far from the given one,
/// relative \[choice\].
pub const PIEZO_EPS_REL: f64 = 0.1;
