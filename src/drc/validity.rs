//! Polygon validity: closed, >= 3 distinct vertices, CCW, no holes, not self-intersecting,
//! at most `max_vertices` (reference/layout-conventions.md).

use geo::{Area, Polygon, Validation};

use super::violation;
use crate::finding::{DrcCode, Finding};
use crate::layout::{LayerKind, MaskSet};

/// Problems of one polygon, as messages.
pub fn problems(p: &Polygon, max_vertices: usize) -> Vec<String> {
    let mut out = Vec::new();
    let ring = &p.exterior().0;
    if ring.len() < 2 || ring.first() != ring.last() {
        out.push("ring is not closed".to_string());
    }
    let n = ring.len().saturating_sub(1);
    if n < 3 {
        out.push(format!("{n} vertices"));
    }
    if n > max_vertices {
        out.push(format!("{n} vertices > {max_vertices}"));
    }
    let mut seen = std::collections::BTreeSet::new();
    for c in ring.iter().take(n) {
        if !seen.insert(((c.x * 1000.0).round() as i64, (c.y * 1000.0).round() as i64)) {
            out.push(format!("ring touches itself at ({:.3}, {:.3})", c.x, c.y));
        }
    }
    if !p.interiors().is_empty() {
        out.push("has holes (GDS boundaries cannot)".into());
    }
    if p.signed_area() <= 0.0 {
        out.push("not counter-clockwise".into());
    }
    for e in p.validation_errors() {
        out.push(e.to_string());
    }
    out
}

/// Checks every polygon of every cell and layer.
pub fn check(set: &MaskSet, max_vertices: usize) -> Vec<Finding> {
    let mut out = Vec::new();
    for (name, cell) in &set.cells {
        for (layer, polys) in &cell.shapes {
            for p in polys {
                let probs = problems(p, max_vertices);
                if !probs.is_empty() {
                    let c = p.exterior().0.first().copied().unwrap_or_default();
                    out.push(violation(
                        DrcCode::InvalidPolygon,
                        Some(*layer),
                        (c.x, c.y),
                        format!("cell {name}: {}", probs.join("; ")),
                    ));
                }
            }
        }
    }
    let _ = LayerKind::ALL;
    out
}
