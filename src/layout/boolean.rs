//! The one boolean adapter of the crate, on geo 0.33 `BooleanOps` (i_overlay).
//!
//! Every ring is oriented counter-clockwise before `unary_union` (geo picks its fill rule from the
//! first ring's winding; mixed windings turn overlaps into holes), and every result is snapped to
//! the 1 nm database grid so that output does not depend on float noise or shape order.
//! geo-booleanop is not used: it returns wrong areas on rectangle unions
//! (reference/layout-conventions.md; see the regression test below).

use geo::orient::Direction;
use geo::{Area, BooleanOps, BoundingRect, Coord, LineString, MultiPolygon, Orient, Polygon, Rect};

/// Database grid in um (1 nm).
pub const GRID_UM: f64 = 1e-3;

/// Axis-aligned rectangle as a CCW polygon, corners snapped to the grid.
pub fn rect(x0_um: f64, y0_um: f64, x1_um: f64, y1_um: f64) -> Polygon {
    let (xa, xb) = (snap(x0_um.min(x1_um)), snap(x0_um.max(x1_um)));
    let (ya, yb) = (snap(y0_um.min(y1_um)), snap(y0_um.max(y1_um)));
    Polygon::new(
        LineString::from(vec![(xa, ya), (xb, ya), (xb, yb), (xa, yb), (xa, ya)]),
        vec![],
    )
}

/// Rounds a coordinate to the 1 nm grid.
pub fn snap(v_um: f64) -> f64 {
    let r = (v_um / GRID_UM).round() * GRID_UM;
    // Normalise -0.0 so that equal inputs give equal bytes.
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

/// Union of any polygons (any winding, overlapping or not): disjoint, CCW, hole-free polygons on
/// the grid, sorted by their lowest-leftmost vertex. Holes are opened by cutting (GDS has none).
pub fn union(polys: &[Polygon]) -> Vec<Polygon> {
    let oriented: Vec<Polygon> = polys.iter().map(|p| p.orient(Direction::Default)).collect();
    if oriented.is_empty() {
        return Vec::new();
    }
    let merged = geo::unary_union(oriented.iter());
    finish(merged)
}

/// `a` minus `b`, each taken as the union of its polygons.
pub fn difference(a: &[Polygon], b: &[Polygon]) -> Vec<Polygon> {
    let (ma, mb) = (as_multi(a), as_multi(b));
    finish(ma.difference(&mb))
}

/// `a` and `b`, each taken as the union of its polygons.
pub fn intersection(a: &[Polygon], b: &[Polygon]) -> Vec<Polygon> {
    let (ma, mb) = (as_multi(a), as_multi(b));
    finish(ma.intersection(&mb))
}

/// Area of the symmetric difference: zero (to the grid) when two shape sets cover the same region.
/// Shape equality is tested this way, never by comparing vertex lists.
pub fn xor_area_um2(a: &[Polygon], b: &[Polygon]) -> f64 {
    let (ma, mb) = (as_multi(a), as_multi(b));
    ma.xor(&mb).unsigned_area()
}

/// Total area of the union.
pub fn area_um2(polys: &[Polygon]) -> f64 {
    as_multi(polys).unsigned_area()
}

/// Mirrors about the vertical line x = axis (x -> 2 axis - x), keeping rings CCW.
pub fn mirror_x(polys: &[Polygon], axis_um: f64) -> Vec<Polygon> {
    polys
        .iter()
        .map(|p| {
            let ring: Vec<Coord> = p
                .exterior()
                .0
                .iter()
                .rev()
                .map(|c| Coord {
                    x: snap(2.0 * axis_um - c.x),
                    y: c.y,
                })
                .collect();
            Polygon::new(LineString::new(ring), vec![])
        })
        .collect()
}

/// Moves polygons by (dx, dy).
pub fn translate(polys: &[Polygon], dx_um: f64, dy_um: f64) -> Vec<Polygon> {
    polys
        .iter()
        .map(|p| {
            let ring: Vec<Coord> = p
                .exterior()
                .0
                .iter()
                .map(|c| Coord {
                    x: snap(c.x + dx_um),
                    y: snap(c.y + dy_um),
                })
                .collect();
            Polygon::new(LineString::new(ring), vec![])
        })
        .collect()
}

/// Bounding box of a set of polygons.
pub fn bbox(polys: &[Polygon]) -> Option<Rect> {
    as_multi_raw(polys).bounding_rect()
}

fn as_multi(polys: &[Polygon]) -> MultiPolygon {
    // Union first: BooleanOps on a MultiPolygon requires non-overlapping members.
    let oriented: Vec<Polygon> = polys.iter().map(|p| p.orient(Direction::Default)).collect();
    if oriented.is_empty() {
        return MultiPolygon::new(vec![]);
    }
    geo::unary_union(oriented.iter())
}

fn as_multi_raw(polys: &[Polygon]) -> MultiPolygon {
    MultiPolygon::new(polys.to_vec())
}

/// Snaps, cleans, opens holes, orients and sorts a boolean result.
fn finish(m: MultiPolygon) -> Vec<Polygon> {
    let mut out = Vec::new();
    for p in m.0 {
        let Some(ext) = clean_ring(p.exterior()) else {
            continue;
        };
        let holes: Vec<LineString> = p.interiors().iter().filter_map(clean_ring).collect();
        let p = Polygon::new(ext, holes).orient(Direction::Default);
        for q in open_holes(p) {
            out.push(q);
        }
    }
    out.sort_by(|a, b| key(a).partial_cmp(&key(b)).expect("finite coordinates"));
    out
}

fn key(p: &Polygon) -> (f64, f64, f64) {
    let c = p.exterior().0[0];
    (c.y, c.x, -p.unsigned_area())
}

/// Grid-snapped ring with repeated and collinear vertices removed, starting at its lowest-leftmost
/// vertex, closed; `None` when fewer than 3 vertices remain.
pub fn clean_ring(ring: &LineString) -> Option<LineString> {
    let mut pts: Vec<Coord> = ring
        .0
        .iter()
        .map(|c| Coord {
            x: snap(c.x),
            y: snap(c.y),
        })
        .collect();
    if pts.len() > 1 && pts.first() == pts.last() {
        pts.pop();
    }
    pts.dedup();
    while pts.len() > 1 && pts.first() == pts.last() {
        pts.pop();
    }
    // Drop collinear vertices until none is left.
    loop {
        let n = pts.len();
        if n < 3 {
            return None;
        }
        let mut removed = false;
        let mut keep = Vec::with_capacity(n);
        for i in 0..n {
            let (a, b, c) = (pts[(i + n - 1) % n], pts[i], pts[(i + 1) % n]);
            let cross = (b.x - a.x) * (c.y - b.y) - (b.y - a.y) * (c.x - b.x);
            if cross.abs() < 1e-9 && !removed {
                removed = true;
                continue;
            }
            keep.push(b);
        }
        pts = keep;
        if !removed {
            break;
        }
    }
    let start = (0..pts.len())
        .min_by(|&i, &j| {
            (pts[i].y, pts[i].x)
                .partial_cmp(&(pts[j].y, pts[j].x))
                .expect("finite")
        })
        .expect("non-empty");
    pts.rotate_left(start);
    pts.push(pts[0]);
    Some(LineString::new(pts))
}

/// Splits a polygon with holes by vertical cuts through the holes until none is left: GDS
/// boundaries have no holes. The pieces touch along the cuts; their union is the input.
fn open_holes(p: Polygon) -> Vec<Polygon> {
    if p.interiors().is_empty() {
        return vec![p];
    }
    let hole = &p.interiors()[0];
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for c in &hole.0 {
        lo = lo.min(c.x);
        hi = hi.max(c.x);
    }
    let cut = snap((lo + hi) / 2.0);
    let r = p.bounding_rect().expect("non-empty polygon");
    let margin = 1.0;
    let left = rect(
        r.min().x - margin,
        r.min().y - margin,
        cut,
        r.max().y + margin,
    );
    let right = rect(
        cut,
        r.min().y - margin,
        r.max().x + margin,
        r.max().y + margin,
    );
    let mut out = Vec::new();
    for half in [left, right] {
        let piece = p.intersection(&half);
        for q in piece.0 {
            let Some(ext) = clean_ring(q.exterior()) else {
                continue;
            };
            let holes: Vec<LineString> = q.interiors().iter().filter_map(clean_ring).collect();
            out.extend(open_holes(
                Polygon::new(ext, holes).orient(Direction::Default),
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The geo-booleanop counter-example (layout-conventions.md): geo-booleanop 0.3.2 returns 11.
    #[test]
    fn rectangle_union_counter_example_has_area_21() {
        let rs = [
            rect(3.0, 10.0, 4.0, 15.0),
            rect(3.0, 6.0, 9.0, 7.0),
            rect(2.0, 3.0, 5.0, 7.0),
        ];
        let u = union(&rs);
        let a: f64 = u.iter().map(|p| p.unsigned_area()).sum();
        assert!((a - 21.0).abs() < 1e-9, "area {a}");
        assert_eq!(u.len(), 2);
        // Clockwise input must give the same result.
        let cw: Vec<Polygon> = rs.iter().map(|p| p.orient(Direction::Reversed)).collect();
        assert!(xor_area_um2(&union(&cw), &u) < 1e-9);
    }

    #[test]
    fn holes_are_opened_into_touching_pieces() {
        let frame = [
            rect(0.0, 0.0, 10.0, 2.0),
            rect(0.0, 8.0, 10.0, 10.0),
            rect(0.0, 0.0, 2.0, 10.0),
            rect(8.0, 0.0, 10.0, 10.0),
        ];
        let u = union(&frame);
        assert!(u.iter().all(|p| p.interiors().is_empty()));
        assert!(u.len() >= 2);
        let a: f64 = u.iter().map(|p| p.unsigned_area()).sum();
        assert!((a - 64.0).abs() < 1e-9);
    }

    #[test]
    fn outputs_are_ccw_and_closed() {
        let u = union(&[rect(0.0, 0.0, 1.0, 1.0).orient(Direction::Reversed)]);
        assert!(u[0].exterior().is_closed());
        assert!(u[0].signed_area() > 0.0);
    }
}
