//! Design-rule checks of a generated [`MaskSet`]: results are values (code, layer, location,
//! message), never prints. A violation fails `tactfab masks` (exit 1) unless the process file
//! waives its code in `drc.waive`; waived violations are still reported.
//!
//! Rules: minimum width and space per printing layer ([`widthspace`]), colliding compensators,
//! compensators across the die edge, merging tooth bases, streets too narrow for the full etch
//! depth, electrodes too close ([`rules`]), invalid polygons ([`validity`]).

pub mod rules;
pub mod validity;
pub mod widthspace;

use serde::Serialize;

use crate::etch::EtchPlan;
use crate::layout::{LayerKind, MaskSet};
use crate::process::Process;

/// One rule violation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Violation {
    pub code: &'static str,
    pub layer: Option<LayerKind>,
    /// Where (um, die coordinates unless the message says wafer).
    pub x_um: f64,
    pub y_um: f64,
    pub message: String,
    /// Waived by the process file: reported, does not fail.
    pub waived: bool,
}

impl Violation {
    pub fn new(
        code: &'static str,
        layer: Option<LayerKind>,
        at: (f64, f64),
        message: impl Into<String>,
    ) -> Self {
        Violation {
            code,
            layer,
            x_um: at.0,
            y_um: at.1,
            message: message.into(),
            waived: false,
        }
    }
}

impl std::fmt::Display for Violation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let layer = self.layer.map(|l| l.name()).unwrap_or("-");
        let w = if self.waived { " (waived)" } else { "" };
        write!(
            f,
            "{}{w} [{layer}] at ({:.3}, {:.3}) um: {}",
            self.code, self.x_um, self.y_um, self.message
        )
    }
}

/// Every rule code with what it means.
pub const CODES: &[(&str, &str)] = &[
    ("MIN_WIDTH", "a shape is narrower than drc.min_width_um"),
    ("MIN_SPACE", "two shapes are closer than drc.min_space_um"),
    (
        "COMPENSATORS_COLLIDE",
        "compensated teeth touch or come closer than drc.min_space_um: a bridge",
    ),
    (
        "COMPENSATOR_OUTSIDE_DIE",
        "a tooth's compensators cross the die edge",
    ),
    (
        "TEETH_BASES_MERGE",
        "etched tooth bases (top + 2 sidewall run-outs) overlap",
    ),
    (
        "STREET_TOO_NARROW",
        "an etched street (within the die or across the dicing street) is narrower than sqrt 2 x \
         depth",
    ),
    (
        "ELECTRODE_GAP",
        "two electrode islands are closer than drc.min_electrode_gap_um",
    ),
    (
        "ELECTRODE_EDGE",
        "an electrode island is closer to the film edge than the edge margin",
    ),
    (
        "INVALID_POLYGON",
        "unclosed, fewer than 3 vertices, self-intersecting, clockwise, with holes, or too many \
         vertices",
    ),
];

/// The DRC result.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DrcReport {
    pub violations: Vec<Violation>,
    pub min_width_um: f64,
    pub min_space_um: f64,
}

impl DrcReport {
    /// True when nothing unwaived is left.
    pub fn passed(&self) -> bool {
        self.violations.iter().all(|v| v.waived)
    }
    pub fn failing(&self) -> usize {
        self.violations.iter().filter(|v| !v.waived).count()
    }
    /// A readable report: one line per violation, at most `per_code` per code.
    pub fn summary(&self, per_code: usize) -> String {
        let mut out = String::new();
        let waived = self.violations.len() - self.failing();
        out.push_str(&format!(
            "DRC: {} violations ({} failing, {waived} waived); min width {} um, min space {} um\n",
            self.violations.len(),
            self.failing(),
            self.min_width_um,
            self.min_space_um
        ));
        for (code, meaning) in CODES {
            let vs: Vec<&Violation> = self.violations.iter().filter(|v| v.code == *code).collect();
            if vs.is_empty() {
                continue;
            }
            out.push_str(&format!("  {code}: {} ({meaning})\n", vs.len()));
            for v in vs.iter().take(per_code) {
                out.push_str(&format!("    {v}\n"));
            }
            if vs.len() > per_code {
                out.push_str(&format!("    ... and {} more\n", vs.len() - per_code));
            }
        }
        out
    }
}

/// Waived codes that are not rule codes (a typo would silently waive nothing): an input error.
pub fn unknown_waivers(p: &Process) -> Vec<String> {
    p.drc
        .waive
        .iter()
        .filter(|w| !CODES.iter().any(|(c, _)| c == w))
        .cloned()
        .collect()
}

/// Runs every rule on the mask set.
pub fn check(set: &MaskSet, p: &Process, plan: &EtchPlan) -> DrcReport {
    let d = &p.drc;
    let mut v = Vec::new();
    v.extend(validity::check(set, d.max_vertices));
    for layer in [LayerKind::FrontSi, LayerKind::BackSi, LayerKind::Pvdf] {
        let mut polys = set.die_layer(layer);
        polys.extend(
            set.cells[&set.wafer_cell]
                .shapes
                .get(&layer)
                .cloned()
                .unwrap_or_default(),
        );
        v.extend(widthspace::check(
            &polys,
            layer,
            d.min_width_um,
            d.min_space_um,
        ));
    }
    v.extend(rules::teeth(set, p, plan));
    v.extend(rules::streets(set, p, plan));
    v.extend(rules::electrodes(set, p));
    for x in &mut v {
        x.waived = d.waive.iter().any(|w| w == x.code);
    }
    DrcReport {
        violations: v,
        min_width_um: d.min_width_um,
        min_space_um: d.min_space_um,
    }
}
