//! Checks of a process, returned as values with stable codes.

use serde::Serialize;

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Severity {
    Warning,
    Error,
}

/// One finding: a stable `code` for tools, a message with the numbers for people.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Check {
    pub code: &'static str,
    pub severity: Severity,
    pub message: String,
}

impl Check {
    pub fn warning(code: &'static str, message: impl Into<String>) -> Self {
        Check {
            code,
            severity: Severity::Warning,
            message: message.into(),
        }
    }
    pub fn error(code: &'static str, message: impl Into<String>) -> Self {
        Check {
            code,
            severity: Severity::Error,
            message: message.into(),
        }
    }
    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }
}

impl std::fmt::Display for Check {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = match self.severity {
            Severity::Warning => "warning",
            Severity::Error => "error",
        };
        write!(f, "{s}[{}]: {}", self.code, self.message)
    }
}

/// Every code a plan can raise, with what it means (the README and the traveler list them).
pub const CODES: &[(&str, &str)] = &[
    (
        "ETCH_TIME_DEPTH_MISMATCH",
        "the recipe's etch time does not reach the target depth",
    ),
    (
        "PLATE_THICKNESS_MISMATCH",
        "wafer - front - back differs from geometry.plate_thickness_um",
    ),
    (
        "PLATE_TOLERANCE",
        "the wafer thickness tolerance is a large part of the plate: measure, then finish",
    ),
    (
        "DEPTH_EXCEEDS_WAFER",
        "front plus back etch depth reaches through the wafer",
    ),
    (
        "DEPTH_GEOMETRY_MISMATCH",
        "an etch depth differs from the tooth height or channel depth",
    ),
    (
        "GEOMETRY_INCONSISTENT",
        "wafer - tooth height - channel depth differs from the plate thickness",
    ),
    (
        "OXIDE_CLAIM",
        "the oxidation model disagrees with the thickness the source claims",
    ),
    (
        "MASK_CONSUMED",
        "the etch mask is eroded before the etch ends",
    ),
    (
        "MASK_MARGIN_LOW",
        "less than 25 % of the etch mask is left at the end",
    ),
    (
        "NO_OXIDE_MASK",
        "an oxide-masked etch with no oxidation step before it",
    ),
    (
        "RESIST_NOT_A_MASK",
        "photoresist used as a TMAH/KOH mask (its developer is TMAH)",
    ),
    (
        "COMP_RATIO_FROM_KOH",
        "a KOH-derived compensation ratio used in TMAH",
    ),
    (
        "NO_COMPENSATION",
        "convex tooth corners etched without compensation",
    ),
    (
        "COMPENSATORS_COLLIDE",
        "compensators of neighbouring teeth overlap and leave a bridge",
    ),
    (
        "COMPENSATOR_OUTSIDE_DIE",
        "a compensator crosses the die edge",
    ),
    (
        "STREET_TOO_NARROW",
        "a street between teeth self-stops as a V-groove before full depth",
    ),
    (
        "HILLOCK_RISK",
        "TMAH below ~22 wt % forms hillocks on (100)",
    ),
    (
        "RATE_EXTRAPOLATED",
        "the TMAH table does not cover the bath concentration",
    ),
    (
        "RATE_MODEL_DISAGREES",
        "the measured rate and the model differ by more than 30 %",
    ),
    (
        "PIEZO_CONSTANTS_INCONSISTENT",
        "g = d / (eps0 eps_r) does not hold for the given constants",
    ),
];
