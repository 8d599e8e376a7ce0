//! Alignment marks: a cross with two vernier scales. The front mark's scales have a 50 um pitch,
//! the back mark's 52 um and sit beside them when overlaid, so the double-sided aligner reads the
//! front-to-back offset to 2 um.

use geo::Polygon;

use super::boolean::{rect, union};

/// Which side a mark is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MarkKind {
    Front,
    Back,
}

/// Half the side of the square a mark needs (its keep-out), in um.
pub const MARK_KEEPOUT_HALF_UM: f64 = 1000.0;

/// A mark centred on (x, y): arms 1200 x 60 um, 11 vernier ticks along x (below) and y (left).
pub fn mark(kind: MarkKind, x_um: f64, y_um: f64) -> Vec<Polygon> {
    let arm = 600.0;
    let bar = 30.0;
    let mut s = vec![
        rect(x_um - arm, y_um - bar, x_um + arm, y_um + bar),
        rect(x_um - bar, y_um - arm, x_um + bar, y_um + arm),
    ];
    let (pitch, band) = match kind {
        MarkKind::Front => (50.0, (-800.0, -700.0)),
        MarkKind::Back => (52.0, (-700.0, -600.0)),
    };
    let tick = 10.0;
    for k in -5i32..=5 {
        let off = f64::from(k) * pitch;
        let ext = if k == 0 { 40.0 } else { 0.0 };
        // Horizontal scale below the cross, ticks vertical.
        let (lo, hi) = if kind == MarkKind::Front {
            (band.0 - ext, band.1)
        } else {
            (band.0, band.1 + ext)
        };
        s.push(rect(
            x_um + off - tick / 2.0,
            y_um + lo,
            x_um + off + tick / 2.0,
            y_um + hi,
        ));
        // Vertical scale left of the cross, ticks horizontal.
        s.push(rect(
            x_um + lo,
            y_um + off - tick / 2.0,
            x_um + hi,
            y_um + off + tick / 2.0,
        ));
    }
    union(&s)
}
