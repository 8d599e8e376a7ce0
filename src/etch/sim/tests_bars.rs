//! The <110> bar simulated (20 um grid, so the debug build stays quick): the cell holds the bar
//! the layout draws, a longer bar leaves more corner and lasts longer, the quarter cell is a
//! true symmetry cell of the bar pattern (which has no diagonal symmetry), runs repeat exactly.

use geo::Polygon;

use super::cell::{rasterise, tooth_cell};
use super::level_set::Grid;
use super::run::{rate_table, simulate};
use super::{RateModel, Stepper, Surface};
use crate::layout::{LayerKind, MaskSet};

const GRID_UM: f64 = 20.0;

fn design(sets: &[String]) -> (crate::process::Process, crate::etch::EtchPlan, MaskSet) {
    let sets: Vec<&str> = sets.iter().map(String::as_str).collect();
    super::tests_tooth::design(&sets)
}

/// Bars of length `l_um` (ratio 200 / L), the default width.
fn bars(l_um: f64) -> Vec<String> {
    vec![
        "steps.tmah-etch.compensation.geometry=bar_110".into(),
        format!("steps.tmah-etch.compensation.ratio={}", 200.0 / l_um),
    ]
}

/// The raster holds the bar along x beyond the corner and nothing beyond the corner on the
/// diagonal or beside the bar.
#[test]
fn cell_holds_the_drawn_bar() {
    let (p, _, masks) = design(&bars(400.0));
    let cell = tooth_cell(&masks, &p.geometry.teeth, GRID_UM).unwrap();
    let g = cell.grid;
    let (cx, cy) = cell.centre_um();
    let at = |x: f64, y: f64| {
        let (i, j) = (
            ((x - cx) / g.dx_um).round() as usize,
            ((y - cy) / g.dy_um).round() as usize,
        );
        cell.drawn[j * g.nx + i]
    };
    // Bar: x 1000..1400, y 950..1000 (b = 50 um) from the tooth centre.
    assert!(at(cx + 1020.0, cy + 1000.0) && at(cx + 1380.0, cy + 960.0));
    assert!(!at(cx + 1420.0, cy + 980.0));
    assert!(!at(cx + 1020.0, cy + 1020.0) && !at(cx + 1020.0, cy + 920.0));
    // Along y the tooth ends at its corner: no bar there.
    assert!(!at(cx + 980.0, cy + 1020.0));
}

/// Corner and consumption time rise with L; no bar is worse than the shortest.
#[test]
fn longer_bar_leaves_more_corner() {
    let run = |sets: &[String]| {
        let (p, plan, masks) = design(sets);
        simulate(&p, &plan, &masks, GRID_UM).unwrap()
    };
    let none = run(&["steps.tmah-etch.compensation=null".into()]);
    let s: Vec<_> = [150.0, 300.0, 450.0]
        .iter()
        .map(|&l| run(&bars(l)))
        .collect();
    let c: Vec<f64> = s.iter().map(|s| s.corner_deviation_um).collect();
    let t: Vec<f64> = s
        .iter()
        .map(|s| s.compensator_consumed_h.unwrap())
        .collect();
    assert!(
        none.corner_deviation_um < c[0],
        "{} {c:?}",
        none.corner_deviation_um
    );
    assert!(c[0] < c[1] && c[1] < c[2], "{c:?}");
    assert!(t[0] < t[1] && t[1] < t[2] && t[2] < s[2].time_h, "{t:?}");
    // The corner starts at the drawn corner (a bar adds nothing on the diagonal).
    assert!(
        s[1].history[0].corner_deviation_um.abs() <= GRID_UM,
        "{:?}",
        s[1].history[0]
    );
    // Deterministic: the same run twice is the same to the bit.
    assert_eq!(run(&bars(300.0)), s[1]);
}

/// The bar pattern is mirror-symmetric about the tooth's centre lines but not its diagonal;
/// the whole neighbourhood (four cells round the tooth centre) etched at once equals the
/// quarter cell mirrored into each quadrant.
#[test]
fn quarter_cell_is_a_symmetry_cell_of_the_bars() {
    let (p, plan, masks) = design(&bars(200.0 / 0.544));
    let cell = tooth_cell(&masks, &p.geometry.teeth, GRID_UM).unwrap();
    let (cx, cy) = cell.centre_um();
    let (px, py) = (p.geometry.teeth.pitch_x_um, p.geometry.teeth.pitch_y_um);
    let wide = Grid::covering(cx - px, cy - py, 2.0 * px, 2.0 * py, GRID_UM).unwrap();
    let shape = masks.flatten(masks.tooth_cell.as_deref().unwrap(), LayerKind::FrontSi);
    let polys: Vec<Polygon> = masks
        .teeth
        .iter()
        .flat_map(|k| crate::layout::boolean::translate(&shape, k.x_um, k.y_um))
        .collect();
    let drawn = rasterise(&wide, &polys);
    let (nx, ny) = (wide.nx, wide.ny);
    let d = |i: usize, j: usize| drawn[j * nx + i];
    let mut off_diagonal = 0;
    for j in 0..ny {
        for i in 0..nx {
            assert_eq!(d(i, j), d(nx - 1 - i, j), "x mirror at ({i}, {j})");
            assert_eq!(d(i, j), d(i, ny - 1 - j), "y mirror at ({i}, {j})");
            off_diagonal += usize::from(d(i, j) != d(j, i));
        }
    }
    assert!(off_diagonal > 0, "the bars break the diagonal symmetry");
    let step = &plan.steps[0];
    let table = rate_table(step, &p.etchants);
    let etch = |g: Grid, m: Vec<bool>| {
        let st = Stepper::new(RateModel::new(table), &g);
        let mut s = Surface::new(g, m);
        st.advance(&mut s, step.time_h).unwrap();
        s
    };
    let q = etch(cell.grid, cell.drawn.clone());
    let w = etch(wide, drawn);
    let (oi, oj) = ((nx - 1) / 2, (ny - 1) / 2);
    assert_eq!((q.grid.nx, q.grid.ny), (oi + 1, oj + 1));
    let mut worst = 0.0f64;
    for j in 0..q.grid.ny {
        for i in 0..q.grid.nx {
            let h = q.h(i, j);
            for (a, b) in [
                (oi + i, oj + j),
                (oi - i, oj + j),
                (oi + i, oj - j),
                (oi - i, oj - j),
            ] {
                worst = worst.max((w.h(a, b) - h).abs());
            }
        }
    }
    assert!(worst < 1e-6, "{worst}");
}
