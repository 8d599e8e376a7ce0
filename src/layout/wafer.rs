//! Stepping dies over the wafer: only whole dies inside the wafer less its edge exclusion, in rows
//! symmetric about the wafer centre (so a per-die mirror is a wafer mirror), each row centred on
//! a die or a street, whichever holds more, with room on the horizontal axis for the two
//! alignment-mark sites (on the x axis, or the y axis if that fits more dies). Rows become array
//! references.

use geo::Coord;

use super::maskset::Placement;

/// Die grid result: die origins (lower-left, wafer centre at 0, 0) and the two mark sites.
#[derive(Debug, Clone, PartialEq)]
pub struct Stepping {
    pub origins: Vec<Coord>,
    pub mark_sites: [Coord; 2],
}

/// Dies of `length x width` at pitch (length + street, width + street) whose four corners lie
/// within the usable radius, keeping two square keep-outs of half-side `keepout_um` free for the
/// alignment marks, on the x axis or, where that leaves room for more dies, on the y axis.
pub fn step(
    length_um: f64,
    width_um: f64,
    street_um: f64,
    usable_radius_um: f64,
    keepout_um: f64,
) -> Stepping {
    let (px, py) = (length_um + street_um, width_um + street_um);
    let inside = |x: f64, y: f64| x * x + y * y <= usable_radius_um * usable_radius_um;
    // Mark sites: as far out on an axis as the usable circle allows; dies in the way give way.
    // The x axis unless the y axis leaves room for more dies.
    let k = keepout_um;
    let m = (((usable_radius_um - k) * (usable_radius_um - k) - k * k)
        .max(0.0)
        .sqrt()
        - k)
        .max(0.0);
    let arrange = |sites: [Coord; 2]| -> Vec<Coord> {
        let hits = |o: &Coord| -> bool {
            sites.iter().any(|c| {
                o.x < c.x + k
                    && o.x + length_um > c.x - k
                    && o.y < c.y + k
                    && o.y + width_um > c.y - k
            })
        };
        // One row at y0: whole dies inside the usable circle and clear of the mark sites, on a
        // grid centred on the vertical axis (a die or a street on it, whichever fits more: each
        // row chooses, so every row stays mirror-symmetric and the wafer with it).
        let nx = (usable_radius_um / px).ceil() as i64 + 1;
        let row = |y0: f64| -> Vec<Coord> {
            [-length_um / 2.0, street_um / 2.0]
                .iter()
                .map(|&ox| {
                    (-nx..=nx)
                        .map(|i| Coord {
                            x: ox + i as f64 * px,
                            y: y0,
                        })
                        .filter(|o| {
                            let (x1, y1) = (o.x + length_um, o.y + width_um);
                            inside(o.x, o.y)
                                && inside(x1, o.y)
                                && inside(o.x, y1)
                                && inside(x1, y1)
                                && !hits(o)
                        })
                        .collect::<Vec<_>>()
                })
                .max_by_key(|v| v.len())
                .unwrap_or_default()
        };
        // Rows symmetric about the horizontal axis: a die row or a street centred on it.
        let ny = (usable_radius_um / py).ceil() as i64 + 1;
        [-width_um / 2.0, street_um / 2.0]
            .iter()
            .map(|&oy| {
                (-ny..=ny)
                    .flat_map(|j| row(oy + j as f64 * py))
                    .collect::<Vec<_>>()
            })
            .max_by_key(|v| v.len())
            .unwrap_or_default()
    };
    let on_x = [Coord { x: -m, y: 0.0 }, Coord { x: m, y: 0.0 }];
    let on_y = [Coord { x: 0.0, y: -m }, Coord { x: 0.0, y: m }];
    let (dies_x, dies_y) = (arrange(on_x), arrange(on_y));
    let (mut origins, mark_sites) = if dies_y.len() > dies_x.len() {
        (dies_y, on_y)
    } else {
        (dies_x, on_x)
    };
    origins.sort_by(|a, b| (a.y, a.x).partial_cmp(&(b.y, b.x)).expect("finite"));
    Stepping {
        origins,
        mark_sites,
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
        // By hand (usable radius 47 mm, pitch 30.3 x 15.3 mm): die-centred rows hold 3 (y = 0,
        // half-width 46.4 mm), 2 + 2 (|y| <= 23.25 mm, street-centred) and 1 + 1 (|y| <= 38.85
        // mm); marks on the x axis (at 45.0 mm) would cost the outer dies of the middle row (8),
        // on the y axis they cost none.
        assert_eq!(s.origins.len(), 9);
        assert!(s
            .mark_sites
            .iter()
            .all(|c| c.x == 0.0 && c.y.abs() > 44_000.0));
        for o in &s.origins {
            for c in &s.mark_sites {
                let clear = o.x >= c.x + 1000.0
                    || o.x + 30000.0 <= c.x - 1000.0
                    || o.y >= c.y + 1000.0
                    || o.y + 15000.0 <= c.y - 1000.0;
                assert!(clear, "die at {o:?} on the mark at {c:?}");
            }
            // Mirror-symmetric about the vertical axis.
            assert!(s
                .origins
                .iter()
                .any(|m| (m.x + o.x + 30000.0).abs() < 1e-6 && (m.y - o.y).abs() < 1e-6));
        }
    }
}
