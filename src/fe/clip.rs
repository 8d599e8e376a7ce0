//! Polygon clipping against element rectangles and polygon geometry.

/// Sutherland-Hodgman clipping of a polygon against an axis-aligned box (Sutherland & Hodgman, CACM
/// 1974).
pub fn clip_polygon(poly: &[(f64, f64)], x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<(f64, f64)> {
    let mut out = poly.to_vec();
    // (axis, bound, keep >= bound?)
    for (axis, bound, keep_ge) in [(0, x0, true), (0, x1, false), (1, y0, true), (1, y1, false)] {
        if out.is_empty() {
            break;
        }
        let input = std::mem::take(&mut out);
        let coord = |p: &(f64, f64)| if axis == 0 { p.0 } else { p.1 };
        let inside = |p: &(f64, f64)| {
            if keep_ge {
                coord(p) >= bound
            } else {
                coord(p) <= bound
            }
        };
        for k in 0..input.len() {
            let cur = input[k];
            let prev = input[(k + input.len() - 1) % input.len()];
            let intersect = || {
                let t = (bound - coord(&prev)) / (coord(&cur) - coord(&prev));
                let p = (prev.0 + t * (cur.0 - prev.0), prev.1 + t * (cur.1 - prev.1));
                if axis == 0 {
                    (bound, p.1)
                } else {
                    (p.0, bound)
                }
            };
            match (inside(&cur), inside(&prev)) {
                (true, true) => out.push(cur),
                (true, false) => {
                    out.push(intersect());
                    out.push(cur);
                }
                (false, true) => out.push(intersect()),
                (false, false) => {}
            }
        }
    }
    out
}

/// Shoelace area of a polygon.
pub fn polygon_area(poly: &[(f64, f64)]) -> f64 {
    let n = poly.len();
    0.5 * (0..n)
        .map(|k| poly[k].0 * poly[(k + 1) % n].1 - poly[(k + 1) % n].0 * poly[k].1)
        .sum::<f64>()
}
