//! Minimum width and space on Manhattan geometry by facing-edge pairs (Euclidean for corners).
//!
//! Rings are CCW, so the interior lies left of every edge. Two parallel axis-aligned edges whose
//! projections overlap face each other across interior (a width) or exterior (a space). Corners of
//! different polygons are also checked point to point. Touching pieces (distance 0, e.g. the two
//! halves of a cut glyph) are one shape on the mask and are not a space. Non-axis-aligned edges
//! are not measured (no printing layer has any).

use geo::{Coord, Polygon};

use super::violation;
use crate::finding::{DrcCode, Finding};
use crate::layout::LayerKind;

#[derive(Clone, Copy)]
struct Edge {
    /// Position across (y of a horizontal edge, x of a vertical one).
    at: f64,
    lo: f64,
    hi: f64,
    /// Interior on the + side (above / right).
    interior_plus: bool,
}

/// Width and space violations of one layer.
pub fn check(
    polys: &[Polygon],
    layer: LayerKind,
    min_width_um: f64,
    min_space_um: f64,
) -> Vec<Finding> {
    let mut hor = Vec::new();
    let mut ver = Vec::new();
    for p in polys {
        for w in p.exterior().0.windows(2) {
            let (a, b) = (w[0], w[1]);
            if a.y == b.y && a.x != b.x {
                hor.push(Edge {
                    at: a.y,
                    lo: a.x.min(b.x),
                    hi: a.x.max(b.x),
                    interior_plus: b.x > a.x,
                });
            } else if a.x == b.x && a.y != b.y {
                ver.push(Edge {
                    at: a.x,
                    lo: a.y.min(b.y),
                    hi: a.y.max(b.y),
                    interior_plus: b.y < a.y,
                });
            }
        }
    }
    let mut out = Vec::new();
    let limit = min_width_um.max(min_space_um);
    for (edges, horizontal) in [(&mut hor, true), (&mut ver, false)] {
        edges.sort_by(|a, b| a.at.partial_cmp(&b.at).expect("finite"));
        for i in 0..edges.len() {
            let e1 = edges[i];
            for e2 in edges[i + 1..].iter() {
                let d = e2.at - e1.at;
                if d >= limit {
                    break;
                }
                let (lo, hi) = (e1.lo.max(e2.lo), e1.hi.min(e2.hi));
                if hi - lo <= 1e-9 || d <= 1e-9 {
                    continue;
                }
                let mid = (lo + hi) / 2.0;
                let at = |c: f64| if horizontal { (mid, c) } else { (c, mid) };
                if e1.interior_plus && !e2.interior_plus && d < min_width_um {
                    out.push(violation(
                        DrcCode::MinWidth,
                        Some(layer),
                        at(e1.at + d / 2.0),
                        format!("width {d:.3} um < {min_width_um} um"),
                    ));
                } else if !e1.interior_plus && e2.interior_plus && d < min_space_um {
                    out.push(violation(
                        DrcCode::MinSpace,
                        Some(layer),
                        at(e1.at + d / 2.0),
                        format!("space {d:.3} um < {min_space_um} um"),
                    ));
                }
            }
        }
    }
    out.extend(point_contacts(polys, layer));
    // Corner to corner between different polygons.
    let mut pts: Vec<(Coord, usize)> = Vec::new();
    for (k, p) in polys.iter().enumerate() {
        pts.extend(p.exterior().0.iter().skip(1).map(|c| (*c, k)));
    }
    pts.sort_by(|a, b| a.0.x.partial_cmp(&b.0.x).expect("finite"));
    for i in 0..pts.len() {
        for j in i + 1..pts.len() {
            let (a, b) = (pts[i], pts[j]);
            if b.0.x - a.0.x >= min_space_um {
                break;
            }
            if a.1 == b.1 {
                continue;
            }
            let (dx, dy) = (b.0.x - a.0.x, b.0.y - a.0.y);
            let d = (dx * dx + dy * dy).sqrt();
            // Only diagonal neighbours: aligned corners are covered by the edge pairs.
            if d > 1e-9
                && d < min_space_um
                && dx.abs() > 1e-9
                && dy.abs() > 1e-9
                && !inside_any(polys, a.0, b.0)
            {
                out.push(violation(
                    DrcCode::MinSpace,
                    Some(layer),
                    ((a.0.x + b.0.x) / 2.0, (a.0.y + b.0.y) / 2.0),
                    format!("corner-to-corner space {d:.3} um < {min_space_um} um"),
                ));
            }
        }
    }
    out
}

/// Shapes of one layer that meet only at a vertex: on the mask a zero-width neck (pieces that
/// share an edge, such as the halves of a cut glyph, are fine).
fn point_contacts(polys: &[Polygon], layer: LayerKind) -> Vec<Finding> {
    let mut at: std::collections::BTreeMap<(i64, i64), Vec<(usize, usize)>> =
        std::collections::BTreeMap::new();
    for (k, p) in polys.iter().enumerate() {
        let ring = &p.exterior().0;
        for (i, c) in ring.iter().enumerate().take(ring.len().saturating_sub(1)) {
            at.entry(((c.x * 1000.0).round() as i64, (c.y * 1000.0).round() as i64))
                .or_default()
                .push((k, i));
        }
    }
    let dirs = |k: usize, i: usize| -> [(f64, f64); 2] {
        let ring = &polys[k].exterior().0;
        let n = ring.len() - 1;
        let c = ring[i];
        let (a, b) = (ring[(i + n - 1) % n], ring[(i + 1) % n]);
        let unit = |d: (f64, f64)| {
            let l = (d.0 * d.0 + d.1 * d.1).sqrt();
            (d.0 / l, d.1 / l)
        };
        [unit((a.x - c.x, a.y - c.y)), unit((b.x - c.x, b.y - c.y))]
    };
    let mut out = Vec::new();
    for ((x, y), users) in &at {
        for i in 0..users.len() {
            for j in i + 1..users.len() {
                let (u, v) = (users[i], users[j]);
                let shared = dirs(u.0, u.1).iter().any(|a| {
                    dirs(v.0, v.1).iter().any(|b| {
                        (a.0 * b.1 - a.1 * b.0).abs() < 1e-9 && a.0 * b.0 + a.1 * b.1 > 0.0
                    })
                });
                if !shared {
                    out.push(violation(
                        DrcCode::MinWidth,
                        Some(layer),
                        (*x as f64 / 1000.0, *y as f64 / 1000.0),
                        "shapes touch at a single point: a zero-width neck",
                    ));
                }
            }
        }
    }
    out
}

/// Whether the midpoint of two corners lies inside some polygon (then it is not a gap).
fn inside_any(polys: &[Polygon], a: Coord, b: Coord) -> bool {
    use geo::Contains;
    let m = geo::Point::new((a.x + b.x) / 2.0, (a.y + b.y) / 2.0);
    polys.iter().any(|p| p.contains(&m))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::boolean::rect;

    #[test]
    fn finds_narrow_and_close() {
        let v = check(
            &[rect(0.0, 0.0, 100.0, 5.0), rect(0.0, 8.0, 100.0, 50.0)],
            LayerKind::FrontSi,
            10.0,
            10.0,
        );
        assert!(v.iter().any(|x| x.code == DrcCode::MinWidth.into()));
        assert!(v.iter().any(|x| x.code == DrcCode::MinSpace.into()));
        let ok = check(
            &[rect(0.0, 0.0, 100.0, 20.0), rect(0.0, 40.0, 100.0, 80.0)],
            LayerKind::FrontSi,
            10.0,
            10.0,
        );
        assert!(ok.is_empty());
        let diag = check(
            &[rect(0.0, 0.0, 10.0, 10.0), rect(13.0, 13.0, 30.0, 30.0)],
            LayerKind::FrontSi,
            10.0,
            10.0,
        );
        assert_eq!(diag.len(), 1);
        // Corner contact is a zero-width neck.
        let v = check(
            &[rect(0.0, 0.0, 10.0, 10.0), rect(10.0, 10.0, 30.0, 30.0)],
            LayerKind::FrontSi,
            10.0,
            10.0,
        );
        assert!(
            v.iter().any(|x| x.message.contains("single point")),
            "{v:?}"
        );
        // Touching halves are one shape.
        assert!(check(
            &[rect(0.0, 0.0, 10.0, 20.0), rect(10.0, 0.0, 20.0, 20.0)],
            LayerKind::FrontSi,
            10.0,
            10.0
        )
        .is_empty());
    }
}
