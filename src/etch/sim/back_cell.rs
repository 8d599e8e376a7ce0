//! The back mask's simulated cell: the corner of a support where the U-channel opening meets
//! the dicing streets, rasterised from the generated [`MaskSet`]'s back layer (the die's
//! polygons and its eight neighbours' at the die pitch), so what is simulated is what is drawn.
//!
//! The drawn supports are strips along the die's long edges and the back opening is everything
//! else (channel and streets), so each support is an island with four convex corners. The
//! middle lines of the dicing streets are mirror planes of the pattern (x = -street / 2 and
//! y = -street / 2 at the die origin), so the cell starts there; it ends where the support's
//! edge is straight again (x) and on the flat channel floor (y), each at [`reach_um`] from the
//! corner or at the die's own mirror line (x = L / 2, y = W / 2) when that is nearer. A mirror
//! plane across a straight edge or a flat floor changes nothing there, so the cut is exact as
//! long as the corner's disturbance ends before it (the tests check the edge at the cut is at
//! its closed-form undercut).

use geo::{Area, BoundingRect, Coord, Intersects, Polygon};
use serde::Serialize;

use crate::etch::geometry::sidewall_run_out_um;
use crate::layout::{LayerKind, MaskSet};

use super::cell::rasterise;
use super::level_set::Grid;
use super::SimError;

/// How far the cell reaches past the corner: twice the corner's closed-form recession
/// sqrt 2 R110 t plus the wall's run-out h / tan 54.74 deg \[choice: the corner's fan ends
/// within one recession of it along the edge; the factor 2 is margin, checked by the tests\].
pub fn reach_um(r110_times_t_um: f64, depth_um: f64) -> f64 {
    2.0 * (std::f64::consts::SQRT_2 * r110_times_t_um + sidewall_run_out_um(depth_um.max(0.0)))
}

/// A drawn mask corner inside the cell.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DrawnCorner {
    /// The vertex (die um, as drawn).
    pub at_um: [f64; 2],
    /// Unit bisector pointing out of the mask into the opening.
    pub outward: [f64; 2],
    /// Convex for the mask (an island's corner: undercut by the fast planes); concave ones are
    /// bounded by two {111} walls and stay sharp.
    pub convex: bool,
}

/// The rasterised corner cell of the back mask.
#[derive(Debug, Clone)]
pub struct BackCell {
    pub grid: Grid,
    /// Node under the drawn back mask.
    pub drawn: Vec<bool>,
    /// The drawn polygons reaching into the cell (die um).
    pub polygons: Vec<Polygon>,
    /// The drawn corners strictly inside the cell.
    pub corners: Vec<DrawnCorner>,
    /// The support's inner (channel-side) edge as drawn: y = support width.
    pub support_edge_y_um: f64,
    /// The straight part of that edge where the wall is read: the cell's far x side.
    pub wall_x_um: f64,
    /// The die width (the channel is mirror-symmetric about its middle, y = W / 2).
    pub die_width_um: f64,
}

/// The corner cell of support 1 at the die origin on a grid of about `step_um`; `reach_um` as
/// [`reach_um`]. The lengths are rounded up to whole steps (so dx = dy) unless the die's own
/// mirror line is nearer.
pub fn back_cell(
    masks: &MaskSet,
    street_um: f64,
    support_width_um: f64,
    reach_um: f64,
    step_um: f64,
) -> Result<BackCell, SimError> {
    let (l, w) = (masks.die_length_um, masks.die_width_um);
    let (x0, y0) = (-street_um / 2.0, -street_um / 2.0);
    let whole = |from: f64, to: f64, mirror: f64| {
        let n = ((to - from) / step_um).ceil().max(2.0);
        (from + n * step_um).min(mirror)
    };
    let x1 = whole(x0, reach_um, l / 2.0);
    let y1 = whole(y0, support_width_um + reach_um, w / 2.0);
    let grid = Grid::covering(x0, y0, x1 - x0, y1 - y0, step_um)?;
    // Label strokes are not simulated (as on the front): only shapes at least reach^2 in area.
    let die: Vec<Polygon> = masks
        .die_layer(LayerKind::BackSi)
        .into_iter()
        .filter(|p| p.unsigned_area() >= reach_um * reach_um)
        .collect();
    let mut polygons = Vec::new();
    for oy in [-1.0, 0.0, 1.0] {
        for ox in [-1.0, 0.0, 1.0] {
            let moved = crate::layout::boolean::translate(
                &die,
                ox * masks.pitch_x_um,
                oy * masks.pitch_y_um,
            );
            for p in moved {
                let Some(r) = p.bounding_rect() else { continue };
                if r.max().x >= x0 && r.min().x <= x1 && r.max().y >= y0 && r.min().y <= y1 {
                    polygons.push(p);
                }
            }
        }
    }
    let drawn = rasterise(&grid, &polygons);
    let inside =
        |c: Coord| c.x > x0 + 1e-6 && c.x < x1 - 1e-6 && c.y > y0 + 1e-6 && c.y < y1 - 1e-6;
    let mut corners: Vec<DrawnCorner> = polygons
        .iter()
        .flat_map(|p| vertex_corners(p, &polygons))
        .filter(|c| {
            inside(Coord {
                x: c.at_um[0],
                y: c.at_um[1],
            })
        })
        .collect();
    corners.sort_by(|a, b| {
        (a.at_um[1], a.at_um[0])
            .partial_cmp(&(b.at_um[1], b.at_um[0]))
            .expect("finite")
    });
    Ok(BackCell {
        grid,
        drawn,
        polygons,
        corners,
        support_edge_y_um: support_width_um,
        wall_x_um: x1,
        die_width_um: w,
    })
}

/// The corners of `p`'s outline with their outward bisectors; a vertex where the union of
/// `all` continues (shapes that touch) is not a corner of the mask.
fn vertex_corners(p: &Polygon, all: &[Polygon]) -> Vec<DrawnCorner> {
    let ring: Vec<Coord> = p.exterior().coords().copied().collect();
    // Closed ring: the last coordinate repeats the first.
    let n = ring.len().saturating_sub(1);
    if n < 3 {
        return Vec::new();
    }
    let ccw = p.signed_area() > 0.0;
    let unit = |a: Coord, b: Coord| {
        let (dx, dy) = (b.x - a.x, b.y - a.y);
        let l = dx.hypot(dy);
        (dx / l, dy / l)
    };
    let covered = |c: Coord| all.iter().any(|q| q.intersects(&c));
    let mut out = Vec::new();
    for k in 0..n {
        let v = ring[k];
        let prev = ring[(k + n - 1) % n];
        let next = ring[(k + 1) % n];
        let (a, b) = (unit(v, prev), unit(v, next));
        let cross = (next.x - v.x) * (prev.y - v.y) - (next.y - v.y) * (prev.x - v.x);
        // Straight-through vertices are not corners.
        if cross.abs() < 1e-9 * (1.0 + v.x.abs() + v.y.abs()) {
            continue;
        }
        let convex = (cross > 0.0) == ccw;
        let (sx, sy) = (a.0 + b.0, a.1 + b.1);
        let l = sx.hypot(sy);
        let sign = if convex { -1.0 } else { 1.0 };
        let out_dir = [sign * sx / l, sign * sy / l];
        let probe = |d: f64| Coord {
            x: v.x + d * out_dir[0],
            y: v.y + d * out_dir[1],
        };
        // A real corner of the union: mask just inside, opening just outside.
        if covered(probe(-1e-3)) && !covered(probe(1e-3)) {
            out.push(DrawnCorner {
                at_um: [v.x, v.y],
                outward: out_dir,
                convex,
            });
        }
    }
    out
}
