//! Back silicon: the two support strips along x at both y edges; the U-channel between them is
//! the etched (undrawn) region.

use geo::Polygon;

use super::boolean::rect;

/// Support 1 (y in [0, w]) and support 2 (y in [W - w, W]), full die length.
pub fn supports(die_length_um: f64, die_width_um: f64, support_width_um: f64) -> Vec<Polygon> {
    vec![
        rect(0.0, 0.0, die_length_um, support_width_um),
        rect(
            0.0,
            die_width_um - support_width_um,
            die_length_um,
            die_width_um,
        ),
    ]
}
