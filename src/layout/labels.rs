//! Where a polygon label fits: the first free spot of a coarse scan over the die, clear of every
//! shape of its layer by a margin. No room is a warning value, not a silent omission.

use geo::{BoundingRect, Polygon, Rect};

use super::text::block_size_um;

/// Lower-left corner for a `lines` block of `pixel_um` text inside [0, L] x [0, W], keeping
/// `clearance_um` from the die edge and from the bounding boxes of `obstacles`.
pub fn find_spot(
    lines: &[String],
    pixel_um: f64,
    obstacles: &[Polygon],
    die_length_um: f64,
    die_width_um: f64,
    clearance_um: f64,
) -> Option<(f64, f64)> {
    let (w, h) = block_size_um(lines, pixel_um);
    let boxes: Vec<Rect> = obstacles.iter().filter_map(|p| p.bounding_rect()).collect();
    let step = 50.0;
    let nx = ((die_length_um - w - 2.0 * clearance_um) / step).floor();
    let ny = ((die_width_um - h - 2.0 * clearance_um) / step).floor();
    if nx < 0.0 || ny < 0.0 {
        return None;
    }
    for j in 0..=(ny as i64) {
        for i in 0..=(nx as i64) {
            let (x, y) = (
                clearance_um + i as f64 * step,
                clearance_um + j as f64 * step,
            );
            let (x0, y0, x1, y1) = (
                x - clearance_um,
                y - clearance_um,
                x + w + clearance_um,
                y + h + clearance_um,
            );
            let free = boxes
                .iter()
                .all(|b| b.max().x <= x0 || b.min().x >= x1 || b.max().y <= y0 || b.min().y >= y1);
            if free {
                return Some((x, y));
            }
        }
    }
    None
}
