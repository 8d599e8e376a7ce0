//! Findings: every warning, error and rule violation tactfab reports, as one typed value.
//!
//! A [`Finding`] has a [`Code`] (an enum per domain: the etch plan, the layout, the design rules,
//! an FE scene), a [`Severity`], a message with the numbers for people, and where it is ([`At`]).
//! Codes are written (JSON, text, waivers in the process file) in their stable SCREAMING_SNAKE
//! spelling; each has a one-line meaning that the DRC report and the README list.

use serde::{Serialize, Serializer};

/// How bad a finding is: an error fails the build (exit 1), a warning is read with the result.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Severity {
    Warning,
    Error,
}

impl Severity {
    pub fn as_str(self) -> &'static str {
        match self {
            Severity::Warning => "warning",
            Severity::Error => "error",
        }
    }
}

/// Declares a code enum: variant, stable spelling, meaning.
macro_rules! codes {
    ($(#[$m:meta])* $name:ident { $($(#[$vm:meta])* $v:ident = $s:literal : $meaning:literal,)* }) => {
        $(#[$m])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum $name { $($(#[$vm])* $v,)* }
        impl $name {
            /// Every code of the domain, in the order reports list them.
            pub const ALL: &'static [$name] = &[$($name::$v,)*];
            /// The stable spelling (JSON, text, `drc.waive`).
            pub fn as_str(self) -> &'static str { match self { $($name::$v => $s,)* } }
            /// What the code means, in one line.
            pub fn meaning(self) -> &'static str { match self { $($name::$v => $meaning,)* } }
        }
        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.as_str())
            }
        }
    };
}

codes! {
    /// What the etch plan finds in the recipe (`tactfab check`, `tactfab etch`).
    EtchCode {
        EtchTimeDepthMismatch = "ETCH_TIME_DEPTH_MISMATCH":
            "the recipe's etch time does not reach the target depth",
        PlateThicknessMismatch = "PLATE_THICKNESS_MISMATCH":
            "wafer - front - back differs from geometry.plate_thickness_um",
        PlateTolerance = "PLATE_TOLERANCE":
            "the wafer thickness tolerance is a large part of the plate: measure, then finish",
        DepthExceedsWafer = "DEPTH_EXCEEDS_WAFER":
            "front plus back etch depth reaches through the wafer",
        DepthGeometryMismatch = "DEPTH_GEOMETRY_MISMATCH":
            "an etch depth differs from the tooth height or channel depth",
        GeometryInconsistent = "GEOMETRY_INCONSISTENT":
            "wafer - tooth height - channel depth differs from the plate thickness",
        OxideClaim = "OXIDE_CLAIM":
            "the oxidation model disagrees with the thickness the source claims",
        MaskConsumed = "MASK_CONSUMED": "the etch mask is eroded before the etch ends",
        MaskMarginLow = "MASK_MARGIN_LOW": "less than 25 % of the etch mask is left at the end",
        NoOxideMask = "NO_OXIDE_MASK": "an oxide-masked etch with no oxidation step before it",
        ResistNotAMask = "RESIST_NOT_A_MASK":
            "photoresist used as a TMAH/KOH mask (its developer is TMAH)",
        ResistInBath = "RESIST_IN_BATH":
            "resist still on the wafer goes into a TMAH/KOH bath, which dissolves it",
        CompRatioFromKoh = "COMP_RATIO_FROM_KOH": "a KOH-derived compensation ratio used in TMAH",
        NoCompensation = "NO_COMPENSATION": "convex tooth corners etched without compensation",
        HillockRisk = "HILLOCK_RISK": "TMAH below ~22 wt % forms hillocks on (100)",
        RateExtrapolated = "RATE_EXTRAPOLATED":
            "the TMAH table does not cover the bath concentration",
        RateModelDisagrees = "RATE_MODEL_DISAGREES":
            "the measured rate and the model differ by more than 30 %",
        PiezoConstantsInconsistent = "PIEZO_CONSTANTS_INCONSISTENT":
            "g = d / (eps0 eps_r) does not hold for the given constants",
        EtchedCornerDeviation = "ETCHED_CORNER_DEVIATION":
            "the simulated etched tooth corner lies beyond etchants.etched_corner_tolerance_um",
    }
}

codes! {
    /// Design rules of the drawn masks (`tactfab masks`; `drc.waive` names these). The etch plan
    /// raises the geometric ones too, from its numbers, before anything is drawn.
    DrcCode {
        MinWidth = "MIN_WIDTH": "a shape is narrower than drc.min_width_um",
        MinSpace = "MIN_SPACE": "two shapes are closer than drc.min_space_um",
        CompensatorsCollide = "COMPENSATORS_COLLIDE":
            "compensated teeth touch or come closer than drc.min_space_um: a bridge",
        CompensatorOutsideDie = "COMPENSATOR_OUTSIDE_DIE": "a tooth's compensators cross the die edge",
        TeethBasesMerge = "TEETH_BASES_MERGE":
            "etched tooth bases (top + 2 sidewall run-outs) overlap",
        StreetTooNarrow = "STREET_TOO_NARROW":
            "an etched street (within the die or across the dicing street) is narrower than sqrt 2 \
             x depth",
        ElectrodeGap = "ELECTRODE_GAP":
            "two electrode islands are closer than drc.min_electrode_gap_um",
        ElectrodeEdge = "ELECTRODE_EDGE":
            "an electrode island is closer to the film edge than the edge margin",
        ElectrodeNearWall = "ELECTRODE_NEAR_WALL":
            "a middle island is not on the etched channel floor, or a support island not under its \
             support's etched footprint, by drc.min_wall_margin_um",
        InvalidPolygon = "INVALID_POLYGON":
            "unclosed, fewer than 3 vertices, self-intersecting, clockwise, with holes, or too many \
             vertices",
    }
}

codes! {
    /// What drawing the masks finds that is not a rule violation.
    LayoutCode {
        LabelOnDeepEtch = "LABEL_ON_DEEP_ETCH":
            "a label on an etched layer is undercut away: it identifies the plate, not the die",
        LabelNoRoom = "LABEL_NO_ROOM": "no free spot for a mask label; none drawn",
        TestDieNoRoom = "TEST_DIE_NO_ROOM":
            "the compensation test die finds no room on the wafer (or no a above the overlap); none drawn",
    }
}

codes! {
    /// How an FE answer should be read.
    SceneCode {
        LinearRange = "LINEAR_RANGE":
            "the deflection is beyond the linear plate's range: membrane stiffening not modelled",
        NotConverged = "NOT_CONVERGED": "the error estimate is above the tolerance",
        NoErrorEstimate = "NO_ERROR_ESTIMATE": "too few mesh levels for a three-mesh estimate",
        OrderUnknown = "ORDER_UNKNOWN":
            "the finest meshes do not converge monotonically; the estimate is the last change",
        ProbeOverhang = "PROBE_OVERHANG":
            "the probe is wider than the die: its force spreads over the part on the die",
        StressSingular = "STRESS_SINGULAR":
            "the peak point stress does not converge; the safety factor uses the averaged stress",
        EdgeStress = "EDGE_STRESS":
            "the solid rung's stress at the critical distance from a sharp re-entrant edge \
             governs the safety factor",
        TouchDown = "TOUCH_DOWN":
            "the plate reaches the channel floor: readings beyond touch-down are not modelled",
        BelowSafetyFactor = "BELOW_SAFETY_FACTOR":
            "the scene's safety factor is under materials.silicon.safety_factor: its load is over \
             the permissible one",
    }
}

/// A finding's code: the domain's enum inside.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Code {
    Etch(EtchCode),
    Drc(DrcCode),
    Layout(LayoutCode),
    Scene(SceneCode),
}

impl Code {
    pub fn as_str(self) -> &'static str {
        match self {
            Code::Etch(c) => c.as_str(),
            Code::Drc(c) => c.as_str(),
            Code::Layout(c) => c.as_str(),
            Code::Scene(c) => c.as_str(),
        }
    }
    pub fn meaning(self) -> &'static str {
        match self {
            Code::Etch(c) => c.meaning(),
            Code::Drc(c) => c.meaning(),
            Code::Layout(c) => c.meaning(),
            Code::Scene(c) => c.meaning(),
        }
    }
    /// Every code of every domain.
    pub fn all() -> impl Iterator<Item = Code> {
        (EtchCode::ALL.iter().map(|&c| Code::Etch(c)))
            .chain(DrcCode::ALL.iter().map(|&c| Code::Drc(c)))
            .chain(LayoutCode::ALL.iter().map(|&c| Code::Layout(c)))
            .chain(SceneCode::ALL.iter().map(|&c| Code::Scene(c)))
    }
    /// The code with this spelling.
    pub fn parse(s: &str) -> Option<Code> {
        Code::all().find(|c| c.as_str() == s)
    }
}

impl From<EtchCode> for Code {
    fn from(c: EtchCode) -> Self {
        Code::Etch(c)
    }
}
impl From<DrcCode> for Code {
    fn from(c: DrcCode) -> Self {
        Code::Drc(c)
    }
}
impl From<LayoutCode> for Code {
    fn from(c: LayoutCode) -> Self {
        Code::Layout(c)
    }
}
impl From<SceneCode> for Code {
    fn from(c: SceneCode) -> Self {
        Code::Scene(c)
    }
}

impl std::fmt::Display for Code {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl Serialize for Code {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.as_str())
    }
}

/// Where a finding is.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum At {
    /// The process as a whole.
    Process,
    /// A point of the layout (um, die coordinates unless the message says wafer), on a layer
    /// (its YAML spelling) when one is concerned.
    Point {
        x_um: f64,
        y_um: f64,
        layer: Option<&'static str>,
    },
    /// A mask of the set, by name.
    Mask(String),
    /// An FE scene, by name.
    Scene(String),
}

impl At {
    fn is_process(&self) -> bool {
        *self == At::Process
    }
}

/// One warning, error or rule violation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Finding {
    pub code: Code,
    pub severity: Severity,
    pub message: String,
    #[serde(skip_serializing_if = "At::is_process")]
    pub at: At,
}

impl Finding {
    pub fn new(severity: Severity, code: impl Into<Code>, message: impl Into<String>) -> Self {
        Finding {
            code: code.into(),
            severity,
            message: message.into(),
            at: At::Process,
        }
    }
    pub fn warning(code: impl Into<Code>, message: impl Into<String>) -> Self {
        Finding {
            code: code.into(),
            severity: Severity::Warning,
            message: message.into(),
            at: At::Process,
        }
    }
    pub fn error(code: impl Into<Code>, message: impl Into<String>) -> Self {
        Finding {
            severity: Severity::Error,
            ..Finding::warning(code, message)
        }
    }
    /// The same finding, placed.
    pub fn at(self, at: At) -> Self {
        Finding { at, ..self }
    }
    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }
}

/// `warning[CODE]: message`, the form every command prints.
impl std::fmt::Display for Finding {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}[{}]: {}",
            self.severity.as_str(),
            self.code,
            self.message
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_code_is_spelled_once_and_parses_back() {
        let all: Vec<Code> = Code::all().collect();
        for (i, a) in all.iter().enumerate() {
            assert_eq!(Code::parse(a.as_str()), Some(*a));
            assert!(!a.meaning().is_empty());
            assert!(
                a.as_str()
                    .chars()
                    .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_'),
                "{a}"
            );
            for b in &all[i + 1..] {
                assert_ne!(a.as_str(), b.as_str(), "two codes spelled alike");
            }
        }
    }

    #[test]
    fn serialises_as_the_old_check_did_when_not_placed() {
        let f = Finding::warning(EtchCode::HillockRisk, "m");
        assert_eq!(
            serde_json::to_string(&f).unwrap(),
            r#"{"code":"HILLOCK_RISK","severity":"warning","message":"m"}"#
        );
        assert_eq!(f.to_string(), "warning[HILLOCK_RISK]: m");
    }
}
