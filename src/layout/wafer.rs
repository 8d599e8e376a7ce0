//! Stepping dies over the wafer: only whole dies inside the wafer less its edge exclusion, on a
//! grid symmetric about the wafer centre (so a per-die mirror is a wafer mirror), with room on
//! the horizontal axis for the two alignment-mark sites. Rows become array references.

use geo::Coord;

use super::maskset::Placement;

/// Die grid result: die origins (lower-left, wafer centre at 0, 0) and the two mark sites.
#[derive(Debug, Clone, PartialEq)]
pub struct Stepping {
    pub origins: Vec<Coord>,
    pub mark_sites: [Coord; 2],
}

/// Dies of `length x width` at pitch (length + street, width + street) whose four corners lie
/// within the usable radius, keeping two square keep-outs of half-side `keepout_um` on the x axis
/// free.
pub fn step(
    length_um: f64,
    width_um: f64,
    street_um: f64,
    usable_radius_um: f64,
    keepout_um: f64,
) -> Stepping {
    let (px, py) = (length_um + street_um, width_um + street_um);
    let inside = |x: f64, y: f64| x * x + y * y <= usable_radius_um * usable_radius_um;
    let grid = |ox: f64, oy: f64| -> Vec<Coord> {
        let nx = (usable_radius_um / px).ceil() as i64 + 1;
        let ny = (usable_radius_um / py).ceil() as i64 + 1;
        let mut v = Vec::new();
        for j in -ny..=ny {
            for i in -nx..=nx {
                let (x0, y0) = (ox + i as f64 * px, oy + j as f64 * py);
                let (x1, y1) = (x0 + length_um, y0 + width_um);
                if inside(x0, y0) && inside(x1, y0) && inside(x0, y1) && inside(x1, y1) {
                    v.push(Coord { x: x0, y: y0 });
                }
            }
        }
        v
    };
    // Symmetric grids: a die centred on the axis, or a street centred on it.
    let xs = [-length_um / 2.0, street_um / 2.0];
    let ys = [-width_um / 2.0, street_um / 2.0];
    let mut best: Option<Vec<Coord>> = None;
    for ox in xs {
        for oy in ys {
            let g = grid(ox, oy);
            if best.as_ref().is_none_or(|b| g.len() > b.len()) {
                best = Some(g);
            }
        }
    }
    let mut origins = best.unwrap_or_default();
    // Mark sites: as far out on the x axis as the usable circle allows; dies in the way give way.
    let k = keepout_um;
    let xm = ((usable_radius_um - k) * (usable_radius_um - k) - k * k)
        .max(0.0)
        .sqrt()
        - k;
    let xm = xm.max(0.0);
    let hits = |o: &Coord| -> bool {
        [xm, -xm]
            .iter()
            .any(|&c| o.x < c + k && o.x + length_um > c - k && o.y < k && o.y + width_um > -k)
    };
    origins.retain(|o| !hits(o));
    origins.sort_by(|a, b| (a.y, a.x).partial_cmp(&(b.y, b.x)).expect("finite"));
    Stepping {
        origins,
        mark_sites: [Coord { x: -xm, y: 0.0 }, Coord { x: xm, y: 0.0 }],
    }
}

/// Contiguous runs of dies in each row as single-row array references.
pub fn arrays(cell: &str, origins: &[Coord], pitch_x_um: f64, pitch_y_um: f64) -> Vec<Placement> {
    let mut out: Vec<Placement> = Vec::new();
    for o in origins {
        if let Some(last) = out.last_mut() {
            let next_x = last.x_um + f64::from(last.cols) * pitch_x_um;
            if (last.y_um - o.y).abs() < 1e-6
                && (next_x - o.x).abs() < 1e-6
                && last.cols < i16::MAX as u16
            {
                last.cols += 1;
                continue;
            }
        }
        out.push(Placement {
            cell: cell.to_string(),
            x_um: o.x,
            y_um: o.y,
            cols: 1,
            rows: 1,
            pitch_x_um,
            pitch_y_um,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dies_inside_and_clear_of_marks() {
        let s = step(30000.0, 15000.0, 300.0, 47000.0, 1000.0);
        assert!(!s.origins.is_empty());
        for o in &s.origins {
            for (x, y) in [
                (o.x, o.y),
                (o.x + 30000.0, o.y + 15000.0),
                (o.x, o.y + 15000.0),
                (o.x + 30000.0, o.y),
            ] {
                assert!(x * x + y * y <= 47000.0f64.powi(2) + 1e-6);
            }
        }
        let a = arrays("D", &s.origins, 30300.0, 15300.0);
        let n: u32 = a.iter().map(|p| u32::from(p.cols)).sum();
        assert_eq!(n as usize, s.origins.len());
    }
}
