//! Convex-corner compensators for anisotropic etching: squares at the corner and <110> bars.

use serde::Serialize;

use crate::process::{CompensationGeometry, Geometry, TeethPattern};

/// The default bar width in side undercuts R111 t / sin 54.74 deg \[choice: both sides' undercut
/// (2 of them) cuts a bar through; three times that covers R111 up to 3x the table's, beyond
/// the 2.4x of the R100/R111 = 12.5-50 range about 30 in process-physics.md\].
pub const BAR_WIDTH_UNDERCUTS: f64 = 6.0;

/// A length along die x and along die y (both <110>).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Reach {
    pub x_um: f64,
    pub y_um: f64,
}

impl Reach {
    /// Both components times `k`.
    pub fn scaled(self, k: f64) -> Reach {
        Reach {
            x_um: k * self.x_um,
            y_um: k * self.y_um,
        }
    }
}

/// The compensation design for one etch depth.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CompensationDesign {
    /// `corner_attached`, `centred` or `bar_110`.
    pub kind: CompensationGeometry,
    /// Side of the square drawn on the mask, or the bar's length L.
    pub side_um: f64,
    /// The ratio in a = h / ratio.
    pub ratio: f64,
    /// Width b of a `bar_110` beam; none for the squares.
    pub bar_width_um: Option<f64>,
    /// Smallest street between two facing compensated corners along x and along y before the
    /// compensators touch (2 reach).
    pub min_gap: Reach,
    /// How far the compensator reaches beyond the corner along x and along y.
    pub reach: Reach,
}

/// a = h / ratio (paper 002 sec. VI.A, after the KOH work of its ref. \[33\]); a square centred on
/// the corner needs side sqrt 2 a to reach as far along the diagonal (process-physics.md); a
/// <110> bar (Bao 1993) is L = a long and `bar_width_um` wide.
///
/// Facing corners across a street of width g: corner-attached squares reach a into the street
/// from each side, so they meet at g = 2a; centred squares of side s reach s/2 each, meeting at
/// g = s = sqrt 2 a. (process-physics.md lists `>= a` for the centred case; the geometry of a
/// square centred on the corner gives sqrt 2 a, which we use as the stricter value.) A bar
/// reaches L along x and nothing along y (it lies in the tooth's row): facing bars meet at
/// g = 2L along x only.
///
/// Panics (misuse) when a bar comes without a positive width or a square with one.
#[track_caller]
pub fn design(
    depth_um: f64,
    ratio: f64,
    kind: CompensationGeometry,
    bar_width_um: Option<f64>,
) -> CompensationDesign {
    assert_eq!(
        kind == CompensationGeometry::Bar110,
        bar_width_um.is_some_and(|b| b > 0.0),
        "a bar_110 compensator needs a positive width, a square none"
    );
    let a = depth_um / ratio;
    let side_um = match kind {
        CompensationGeometry::Centred => 2f64.sqrt() * a,
        _ => a,
    };
    let reach = reach_per_a(kind).scaled(a);
    CompensationDesign {
        kind,
        side_um,
        ratio,
        bar_width_um,
        min_gap: reach.scaled(2.0),
        reach,
    }
}

/// The default width of a <110> bar: [`BAR_WIDTH_UNDERCUTS`] side undercuts
/// (R111 t / sin 54.74 deg, process-physics.md), at least `min_width_um` (the DRC's) and at most
/// the tooth top.
pub fn default_bar_width_um(undercut_um: f64, min_width_um: f64, top_um: f64) -> f64 {
    (BAR_WIDTH_UNDERCUTS * undercut_um)
        .max(min_width_um)
        .min(top_um)
}

/// How far a compensator of size a (a = h / ratio) reaches beyond its corner along x and y, per
/// um of a: a both ways corner-attached, sqrt 2 a / 2 centred, a along x and 0 along y for a
/// bar ([`design`]).
pub fn reach_per_a(kind: CompensationGeometry) -> Reach {
    let (x_um, y_um) = match kind {
        CompensationGeometry::CornerAttached => (1.0, 1.0),
        CompensationGeometry::Centred => (
            std::f64::consts::FRAC_1_SQRT_2,
            std::f64::consts::FRAC_1_SQRT_2,
        ),
        CompensationGeometry::Bar110 => (1.0, 0.0),
    };
    Reach { x_um, y_um }
}

/// The largest a with `a * r <= limit` for every axis whose reach per a is positive.
fn per_axis(limits: [(f64, f64); 2]) -> f64 {
    limits
        .iter()
        .filter(|(r, _)| *r > 0.0)
        .map(|(r, l)| l / r)
        .fold(f64::INFINITY, f64::min)
}

/// The largest compensator a of `kind` the teeth of `g` can carry, and what limits it: facing
/// compensators must stay `min_space_um` apart (the DRC's COMPENSATORS_COLLIDE: across the
/// street for a matrix; for a checkered pattern, whose orthogonal neighbour cells are empty,
/// corner to corner diagonally, and along x or y to the tooth two pitches away, which is what
/// limits a bar) and the outer teeth's must stay on the die (COMPENSATOR_OUTSIDE_DIE). Matches
/// the plan's checks: a compensator of this a passes both.
pub fn largest_a_um(
    g: &Geometry,
    kind: CompensationGeometry,
    min_space_um: f64,
) -> (f64, &'static str) {
    let t = &g.teeth;
    let r = reach_per_a(kind);
    let (gx, gy) = (t.pitch_x_um - t.top_um, t.pitch_y_um - t.top_um);
    // Largest a between facing compensators.
    let street = match t.pattern {
        TeethPattern::Matrix => per_axis([
            (r.x_um, 0.5 * (gx - min_space_um)),
            (r.y_um, 0.5 * (gy - min_space_um)),
        ]),
        _ => {
            // Along a row or column: the tooth two pitches away.
            let two = per_axis([
                (r.x_um, 0.5 * (gx + t.pitch_x_um - min_space_um)),
                (r.y_um, 0.5 * (gy + t.pitch_y_um - min_space_um)),
            ]);
            // Diagonal neighbours: the compensators' facing corners are
            // (gx - 2 a rx, gy - 2 a ry) apart; the distance falls monotonically in a, so
            // bisect for min_space.
            let dist = |a: f64| {
                (gx - 2.0 * a * r.x_um)
                    .max(0.0)
                    .hypot((gy - 2.0 * a * r.y_um).max(0.0))
            };
            let (mut lo, mut hi) = (0.0, two.max(0.0));
            if dist(lo) < min_space_um {
                hi = 0.0;
            }
            if dist(hi) >= min_space_um {
                lo = hi;
            }
            for _ in 0..100 {
                let mid = 0.5 * (lo + hi);
                if dist(mid) >= min_space_um {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            lo.min(two)
        }
    };
    // Outer teeth: reach within the die on every side.
    let inset_x = t.origin_x_um + (t.pitch_x_um - t.top_um) / 2.0;
    let inset_y = t.origin_y_um + (t.pitch_y_um - t.top_um) / 2.0;
    let end_x = g.die_length_um
        - (t.origin_x_um + f64::from(t.count_x) * t.pitch_x_um - (t.pitch_x_um - t.top_um) / 2.0);
    let end_y = g.die_width_um
        - (t.origin_y_um + f64::from(t.count_y) * t.pitch_y_um - (t.pitch_y_um - t.top_um) / 2.0);
    let die = per_axis([(r.x_um, inset_x.min(end_x)), (r.y_um, inset_y.min(end_y))]);
    let (a, why) = if street <= die {
        (street, "facing compensators min_space apart")
    } else {
        (die, "outer teeth's compensators on the die")
    };
    (a.max(0.0), why)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_values() {
        let c = design(200.0, 0.544, CompensationGeometry::CornerAttached, None);
        assert!((c.side_um - 367.647).abs() < 1e-3);
        assert!((c.min_gap.x_um - 735.294).abs() < 1e-3);
        let z = design(200.0, 0.544, CompensationGeometry::Centred, None);
        assert!((z.side_um - 519.93).abs() < 0.01);
        assert!((z.min_gap.y_um - z.side_um).abs() < 1e-9);
    }

    #[test]
    fn largest_a_fits_the_street_and_no_more() {
        let text = std::fs::read_to_string("process/mis-grasper.yaml").unwrap();
        let mut g = crate::process::load_str(&text, "mis-grasper.yaml", &[])
            .unwrap()
            .process
            .geometry;
        let t = &mut g.teeth;
        (t.top_um, t.pitch_x_um, t.pitch_y_um) = (2000.0, 3000.0, 3000.0);
        (t.origin_x_um, t.origin_y_um) = (0.0, 0.0);
        (g.die_length_um, g.die_width_um) = (1e5, 1e5);
        g.teeth.pattern = TeethPattern::Checkered;
        // Diagonal corners sqrt 2 (1000 - 2a) apart = 10 um.
        let (a, why) = largest_a_um(&g, CompensationGeometry::CornerAttached, 10.0);
        assert!(
            (a - (1000.0 - 10.0 / 2f64.sqrt()) / 2.0).abs() < 1e-9,
            "{a} {why}"
        );
        let (c, _) = largest_a_um(&g, CompensationGeometry::Centred, 10.0);
        assert!((c - 2f64.sqrt() * a).abs() < 1e-9);
        // The plan's collision rule passes at the limit (min gap 2 reach <= street).
        let d = design(200.0, 200.0 / a, CompensationGeometry::CornerAttached, None);
        assert!(d.min_gap.x_um <= 1000.0);
        g.teeth.pattern = TeethPattern::Matrix;
        let (m, _) = largest_a_um(&g, CompensationGeometry::CornerAttached, 10.0);
        assert!((m - 495.0).abs() < 1e-9);
        // A die edge 300 um beyond the outer tooth tops limits the reach to 300.
        (g.die_length_um, g.die_width_um) = (10.0 * 3000.0 - 200.0, 1e5);
        g.teeth.count_x = 10;
        let (e, why) = largest_a_um(&g, CompensationGeometry::CornerAttached, 10.0);
        assert!((e - 300.0).abs() < 1e-9 && why.contains("die"), "{e} {why}");
    }

    /// Bars reach along x only: checkered, the facing bar is two pitches away (the orthogonal
    /// neighbour cell is empty) and the diagonal neighbour's bars never come nearer than the
    /// y street; matrix, across the x street; the die's x ends limit, its y ends do not.
    #[test]
    fn largest_bar_by_hand() {
        let text = std::fs::read_to_string("process/mis-grasper.yaml").unwrap();
        let mut g = crate::process::load_str(&text, "mis-grasper.yaml", &[])
            .unwrap()
            .process
            .geometry;
        let bar = CompensationGeometry::Bar110;
        let t = &mut g.teeth;
        (t.top_um, t.pitch_x_um, t.pitch_y_um) = (2000.0, 3000.0, 3000.0);
        (t.origin_x_um, t.origin_y_um) = (5000.0, 0.0);
        (t.count_x, t.count_y) = (10, 5);
        (g.die_length_um, g.die_width_um) = (1e5, 1e5);
        g.teeth.pattern = TeethPattern::Checkered;
        // 2 pitches - top - 2 L = 10 um.
        let (l, why) = largest_a_um(&g, bar, 10.0);
        assert!(
            (l - (6000.0 - 2000.0 - 10.0) / 2.0).abs() < 1e-9,
            "{l} {why}"
        );
        assert!(why.contains("facing"));
        // A 100 um y street does not limit the bar (it limits the squares).
        g.teeth.pitch_y_um = 2100.0;
        let (l2, _) = largest_a_um(&g, bar, 10.0);
        assert!((l2 - l).abs() < 1e-9, "{l2}");
        g.teeth.pattern = TeethPattern::Matrix;
        let (m, _) = largest_a_um(&g, bar, 10.0);
        assert!((m - 495.0).abs() < 1e-9, "{m}");
        let (sq, _) = largest_a_um(&g, CompensationGeometry::CornerAttached, 10.0);
        assert!((sq - 45.0).abs() < 1e-9, "{sq}");
        // The die's x end: the outer teeth start 500 um in.
        g.teeth.pattern = TeethPattern::Checkered;
        g.teeth.origin_x_um = 0.0;
        let (e, why) = largest_a_um(&g, bar, 10.0);
        assert!((e - 500.0).abs() < 1e-9 && why.contains("die"), "{e} {why}");
        let d = design(200.0, 200.0 / e, bar, Some(50.0));
        assert_eq!((d.reach.x_um, d.reach.y_um), (e, 0.0));
        assert_eq!(d.min_gap.y_um, 0.0);
    }

    #[test]
    fn default_bar_width() {
        // 6 undercuts of 8.33 um (bundled TMAH): 50 um; floored at the DRC width, capped at the top.
        assert!((default_bar_width_um(8.3283, 10.0, 2000.0) - 49.97).abs() < 0.01);
        assert_eq!(default_bar_width_um(0.1, 10.0, 2000.0), 10.0);
        assert_eq!(default_bar_width_um(1000.0, 10.0, 2000.0), 2000.0);
    }
}
