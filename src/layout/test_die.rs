//! The compensation test die (issue 19, item 4): one row of teeth like the device's on the front
//! mask, their compensators stepping through a = centre - span .. centre + span, each labelled
//! with its a, placed on the wafer where no device die or alignment mark is, so it etches with
//! the wafer and the fab can measure which a leaves a square corner.
//!
//! The labels are drawn on the front layer (they print in the oxide and can be read before the
//! etch) and as annotation text; their 25 um strokes are undercut away in a 200 um etch, so the
//! ladder is also ordered: a rises from left to right.

use geo::{Coord, Polygon};
use serde::Serialize;

use crate::etch::compensation::{default_bar_width_um, design, reach_per_a};
use crate::etch::EtchPlan;
use crate::process::{CompensationGeometry, Process, Side, StepParams};

use super::boolean::{rect, translate};
use super::maskset::{Cell, LayerKind};
use super::{teeth, text};

/// Most teeth on the ladder.
pub const MAX_TEETH: usize = 15;
/// Clear border inside the test die's outline \[choice: as wide as a compensator\].
pub const MARGIN_UM: f64 = 500.0;
/// Between a label and the compensators above it \[choice\].
pub const LABEL_GAP_UM: f64 = 200.0;

/// What the mask set says about its test die.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TestDieInfo {
    /// GDS structure name.
    pub cell: String,
    /// Lower-left corner on the wafer (wafer centre at 0, 0), um.
    pub origin_um: [f64; 2],
    pub size_um: [f64; 2],
    pub geometry: CompensationGeometry,
    pub centre_a_um: f64,
    /// Where the centre came from.
    pub centre_from: String,
    /// The a of each tooth, left to right.
    pub a_um: Vec<f64>,
    /// Tooth top lower-left corners in the test die, um.
    pub teeth_um: Vec<[f64; 2]>,
}

/// The first front-side silicon etch's compensator a = h / ratio; without a compensation
/// section the paper's rule a = h / 0.544; none without a front etch.
pub fn front_rule_a_um(p: &Process) -> Option<f64> {
    front_compensation(p).map(|(h, r, _, _)| h / r).or_else(|| {
        p.steps.iter().find_map(|s| match &s.params {
            StepParams::SiliconEtch(e) if matches!(e.side, Side::Front | Side::Both) => {
                Some(e.depth_um / crate::etch::sim::sizing::RULE_RATIO)
            }
            _ => None,
        })
    })
}

/// Depth, ratio, geometry and stated bar width of the first front-side etch's compensation.
fn front_compensation(p: &Process) -> Option<(f64, f64, CompensationGeometry, Option<f64>)> {
    p.steps.iter().find_map(|s| match &s.params {
        StepParams::SiliconEtch(e) if matches!(e.side, Side::Front | Side::Both) => e
            .compensation
            .as_ref()
            .map(|c| (e.depth_um, c.ratio, c.geometry, c.bar_width_um)),
        _ => None,
    })
}

/// The ladder's a values: centre + k step for |k step| <= span, ascending.
#[track_caller]
pub fn ladder_a_um(centre_um: f64, span_um: f64, step_um: f64) -> Vec<f64> {
    assert!(
        step_um > 0.0 && span_um >= 0.0,
        "a ladder needs a positive step"
    );
    let n = (span_um / step_um + 1e-9).floor() as i64;
    (-n..=n).map(|k| centre_um + k as f64 * step_um).collect()
}

/// The test die cell and what it holds, or none when the file does not ask for one. The
/// process has been validated (a centre exists, every a exceeds the overlap).
pub fn build(p: &Process, plan: &EtchPlan, cell: &str) -> Option<(Cell, TestDieInfo)> {
    let t = &p.layout.test_die;
    if !t.enabled {
        return None;
    }
    let front = plan
        .steps
        .iter()
        .find(|s| matches!(s.side, Side::Front | Side::Both))?;
    let h = front.depth_um;
    let kind = front_compensation(p).map_or(CompensationGeometry::CornerAttached, |c| c.2);
    // The file's bar width, else the plan's default (computed here too: the plan draws no
    // compensation when the die has no teeth).
    let bar_width_um = (kind == CompensationGeometry::Bar110).then(|| {
        front_compensation(p).and_then(|c| c.3).unwrap_or_else(|| {
            default_bar_width_um(
                front.undercut_um,
                p.drc.min_width_um,
                p.geometry.teeth.top_um,
            )
        })
    });
    let (centre, centre_from) = match (t.centre_a_um, front_rule_a_um(p)) {
        (Some(c), _) => (c, "layout.test_die.centre_a_um".to_string()),
        (None, Some(r)) => (
            r,
            if front_compensation(p).is_some() {
                "the front etch's a = h / ratio"
            } else {
                "the rule a = h / 0.544 (the front etch draws no compensation)"
            }
            .to_string(),
        ),
        (None, None) => return None,
    };
    // A derived centre on a shallow what-if etch may put the low end at or below the overlap:
    // those rungs are dropped (validation refuses them only for a stated centre).
    let overlap = p.layout.compensation_overlap_um;
    let a_um: Vec<f64> = ladder_a_um(centre, t.span_um, t.step_um)
        .into_iter()
        .filter(|&a| a > overlap)
        .collect();
    if a_um.is_empty() {
        return None;
    }
    let top = p.geometry.teeth.top_um;
    let reach = reach_per_a(kind).scaled(a_um.iter().copied().fold(0.0, f64::max));
    let street = front.min_street_um + p.drc.min_space_um;
    let pitch = top + 2.0 * reach.x_um + street;
    let pixel = p.layout.label_pixel_um;
    let label = |a: f64| vec![format!("A {a:.0}")];
    let label_h = text::block_size_um(&label(0.0), pixel).1;
    let n = a_um.len() as f64;
    let w = 2.0 * MARGIN_UM + n * pitch - street;
    let hgt = 2.0 * MARGIN_UM + label_h + LABEL_GAP_UM + 2.0 * reach.y_um + top;
    let y_tooth = MARGIN_UM + label_h + LABEL_GAP_UM + reach.y_um;
    let mut c = Cell::default();
    let mut front_polys: Vec<Polygon> = Vec::new();
    let mut teeth_um = Vec::new();
    for (k, &a) in a_um.iter().enumerate() {
        let x = MARGIN_UM + reach.x_um + k as f64 * pitch;
        let d = design(h, h / a, kind, bar_width_um);
        front_polys.extend(translate(
            &teeth::tooth_cell(top, Some(&d), overlap),
            x,
            y_tooth,
        ));
        let lines = label(a);
        let lw = text::block_size_um(&lines, pixel).0;
        front_polys.extend(text::text_polygons(
            &lines,
            x + (top - lw) / 2.0,
            MARGIN_UM,
            pixel,
        ));
        c.note(format!("A={a:.1} UM"), x + top / 2.0, MARGIN_UM);
        teeth_um.push([x, y_tooth]);
    }
    c.add(LayerKind::FrontSi, front_polys);
    c.add(LayerKind::Outline, [rect(0.0, 0.0, w, hgt)]);
    c.note(
        format!(
            "TEST DIE: {} COMPENSATION LADDER A = {:.0}..{:.0} UM (STEP {}), H = {} UM; A RISES \
             LEFT TO RIGHT",
            crate::spelling::yaml(&kind).to_uppercase(),
            a_um[0],
            a_um[a_um.len() - 1],
            t.step_um,
            h
        ),
        MARGIN_UM,
        hgt - MARGIN_UM / 2.0,
    );
    Some((
        c,
        TestDieInfo {
            cell: cell.to_string(),
            origin_um: [0.0, 0.0],
            size_um: [w, hgt],
            geometry: kind,
            centre_a_um: centre,
            centre_from,
            a_um,
            teeth_um,
        },
    ))
}

/// Where a `w` x `h` test die goes on the wafer: whole inside the usable circle, a dicing street
/// clear of every device die (lower-left `dies`, `die_w` x `die_h`) and of the mark keep-outs;
/// the first spot scanning rows from the bottom of the wafer up and, in each row, from the
/// vertical axis outwards (deterministic). None when no spot fits.
#[allow(clippy::too_many_arguments)]
pub fn place(
    w: f64,
    h: f64,
    dies: &[Coord],
    die_w: f64,
    die_h: f64,
    street_um: f64,
    usable_radius_um: f64,
    marks: &[Coord],
    keepout_um: f64,
) -> Option<Coord> {
    const STEP_UM: f64 = 250.0;
    let r2 = usable_radius_um * usable_radius_um;
    let inside = |x: f64, y: f64| x * x + y * y <= r2;
    let overlaps = |x0: f64, y0: f64, x1: f64, y1: f64, bx0: f64, by0: f64, bx1: f64, by1: f64| {
        x0 < bx1 && x1 > bx0 && y0 < by1 && y1 > by0
    };
    let clear = |x: f64, y: f64| {
        let (x1, y1) = (x + w, y + h);
        inside(x, y)
            && inside(x1, y)
            && inside(x, y1)
            && inside(x1, y1)
            && !dies.iter().any(|d| {
                overlaps(
                    x,
                    y,
                    x1,
                    y1,
                    d.x - street_um,
                    d.y - street_um,
                    d.x + die_w + street_um,
                    d.y + die_h + street_um,
                )
            })
            && !marks.iter().any(|m| {
                overlaps(
                    x,
                    y,
                    x1,
                    y1,
                    m.x - keepout_um,
                    m.y - keepout_um,
                    m.x + keepout_um,
                    m.y + keepout_um,
                )
            })
    };
    let rows = (2.0 * usable_radius_um / STEP_UM).ceil() as i64;
    let cols = (usable_radius_um / STEP_UM).ceil() as i64;
    for j in 0..=rows {
        let y = -usable_radius_um + j as f64 * STEP_UM;
        for k in 0..=cols {
            for x in [-w / 2.0 + k as f64 * STEP_UM, -w / 2.0 - k as f64 * STEP_UM] {
                if clear(x, y) {
                    return Some(Coord { x, y });
                }
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ladder_is_symmetric_about_the_centre() {
        let a = ladder_a_um(367.6, 150.0, 50.0);
        assert_eq!(a.len(), 7);
        assert!((a[0] - 217.6).abs() < 1e-9 && (a[6] - 517.6).abs() < 1e-9);
        assert_eq!(ladder_a_um(300.0, 0.0, 50.0), vec![300.0]);
        assert_eq!(ladder_a_um(300.0, 149.0, 50.0).len(), 5);
    }

    #[test]
    fn placement_avoids_dies_and_marks() {
        // One die at the centre; the test die goes below it, clear by the street.
        let dies = [Coord {
            x: -5000.0,
            y: -5000.0,
        }];
        let c = place(
            8000.0,
            2000.0,
            &dies,
            10000.0,
            10000.0,
            300.0,
            20000.0,
            &[],
            1000.0,
        )
        .unwrap();
        assert!(c.y + 2000.0 <= -5300.0 || c.y >= 5300.0, "{c:?}");
        assert!((c.x + 8000.0).hypot(c.y) <= 20000.0 && c.x.hypot(c.y) <= 20000.0);
        // Nothing fits inside a circle smaller than the die.
        assert!(place(8000.0, 2000.0, &[], 1.0, 1.0, 0.0, 3000.0, &[], 0.0).is_none());
    }
}
