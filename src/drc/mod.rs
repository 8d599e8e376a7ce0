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
use crate::finding::{At, Code, DrcCode, Finding, Severity};
use crate::layout::{LayerKind, MaskSet};
use crate::process::Process;

/// A rule violation: an error finding of a [`DrcCode`], placed at a point of a layer. The
/// process file can waive its code: it is then a warning, still reported.
pub fn violation(
    code: DrcCode,
    layer: Option<LayerKind>,
    at: (f64, f64),
    message: impl Into<String>,
) -> Finding {
    Finding::error(code, message).at(At::Point {
        x_um: at.0,
        y_um: at.1,
        layer: layer.map(LayerKind::name),
    })
}

/// Waived: reported, does not fail.
pub fn is_waived(v: &Finding) -> bool {
    !v.is_error()
}

/// `CODE (waived) [layer] at (x, y) um: message`, one line of the report.
pub fn line(v: &Finding) -> String {
    let w = if is_waived(v) { " (waived)" } else { "" };
    match &v.at {
        At::Point { x_um, y_um, layer } => format!(
            "{}{w} [{}] at ({x_um:.3}, {y_um:.3}) um: {}",
            v.code,
            layer.unwrap_or("-"),
            v.message
        ),
        _ => format!("{}{w}: {}", v.code, v.message),
    }
}

/// The DRC result.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DrcReport {
    pub violations: Vec<Finding>,
    pub min_width_um: f64,
    pub min_space_um: f64,
}

impl DrcReport {
    /// True when nothing unwaived is left.
    pub fn passed(&self) -> bool {
        self.violations.iter().all(is_waived)
    }
    pub fn failing(&self) -> usize {
        self.violations.iter().filter(|v| v.is_error()).count()
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
        for &code in DrcCode::ALL {
            let meaning = code.meaning();
            let vs: Vec<&Finding> = self
                .violations
                .iter()
                .filter(|v| v.code == Code::Drc(code))
                .collect();
            if vs.is_empty() {
                continue;
            }
            out.push_str(&format!("  {code}: {} ({meaning})\n", vs.len()));
            for v in vs.iter().take(per_code) {
                out.push_str(&format!("    {}\n", line(v)));
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
        .filter(|w| !DrcCode::ALL.iter().any(|c| c.as_str() == w.as_str()))
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
        // The test die's shapes, where it sits on the wafer.
        if let Some(t) = &set.test_die {
            polys.extend(crate::layout::boolean::translate(
                &set.flatten(&t.cell, layer),
                t.origin_um[0],
                t.origin_um[1],
            ));
        }
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
    v.extend(rules::electrodes_on_etched(set, p, plan));
    for x in &mut v {
        if d.waive.iter().any(|w| w == x.code.as_str()) {
            x.severity = Severity::Warning;
        }
    }
    DrcReport {
        violations: v,
        min_width_um: d.min_width_um,
        min_space_um: d.min_space_um,
    }
}
