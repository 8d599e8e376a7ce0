//! The tooth cell of the bundled process: taken from the drawn mask, symmetric, and the corner
//! responding to the compensator as it must.

use super::cell::tooth_cell;
use super::run::simulate;

/// The bundled design with `--set` overrides: process, etch plan and masks.
pub(super) fn design(
    sets: &[&str],
) -> (
    crate::process::Process,
    crate::etch::EtchPlan,
    crate::layout::MaskSet,
) {
    let p = super::tests_sizing::load(sets);
    let plan = crate::etch::plan(&p);
    let masks = crate::layout::build(&p, &plan).unwrap();
    (p, plan, masks)
}

/// The cell holds a quarter of the drawn tooth with its compensator: the node at the tooth
/// centre is masked, the drawn corner and the compensator's far corner are, just beyond is not,
/// and the raster is symmetric about the diagonal.
#[test]
fn cell_is_the_drawn_tooth_quarter() {
    let (p, plan, masks) = design(&[]);
    let cell = tooth_cell(&masks, &p.geometry.teeth, 10.0).unwrap();
    let g = cell.grid;
    assert_eq!((g.nx, g.ny), (301, 301));
    let at = |x: f64, y: f64| {
        let (i, j) = (
            ((x - g.x0_um) / g.dx_um).round() as usize,
            ((y - g.y0_um) / g.dy_um).round() as usize,
        );
        cell.drawn[j * g.nx + i]
    };
    let a = plan.steps[0].compensation.unwrap().side_um; // 367.6 um
    let (cx, cy) = cell.centre_um();
    assert!(at(cx, cy) && at(cx + 1000.0, cy + 1000.0));
    // The compensator reaches a - overlap (10 um) beyond the corner along each axis.
    let reach = 1000.0 + a - 10.0;
    assert!(at(cx + reach - 10.0, cy + reach - 10.0));
    assert!(!at(cx + reach + 10.0, cy + reach + 10.0));
    assert!(!at(cx + 1500.0, cy));
    for j in 0..g.ny {
        for i in 0..j {
            assert_eq!(
                cell.drawn[j * g.nx + i],
                cell.drawn[i * g.nx + j],
                "({i}, {j})"
            );
        }
    }
}

/// The etched cell is symmetric about the tooth's diagonal; a larger compensator leaves more
/// silicon at the corner (monotone), and without one the corner is rounded at once.
#[test]
fn corner_is_symmetric_and_monotone_in_the_compensator() {
    let grid = 20.0;
    let run = |sets: &[&str]| {
        let (p, plan, masks) = design(sets);
        simulate(&p, &plan, &masks, grid).unwrap()
    };
    let base = run(&[]);
    let bigger = run(&["steps.tmah-etch.compensation.ratio=0.4"]);
    assert!(
        bigger.corner_deviation_um > base.corner_deviation_um + 20.0,
        "{} vs {}",
        bigger.corner_deviation_um,
        base.corner_deviation_um
    );
    let none = run(&["steps.tmah-etch.compensation=null"]);
    assert!(none.corner_deviation_um < base.corner_deviation_um);
    assert_eq!(none.compensator_consumed_h, None);
    let t = base.compensator_consumed_h.unwrap();
    assert!(t > 0.0 && t < base.time_h, "{t}");
    assert!((base.floor_depth_um - 204.0).abs() < 1e-6);
    assert!(base.facets.iter().take(2).any(|f| f.family == "111"));
    // Symmetry of the etched field itself.
    let (p, plan, masks) = design(&[]);
    let cell = tooth_cell(&masks, &p.geometry.teeth, grid).unwrap();
    let step = &plan.steps[0];
    let mut s = super::Surface::new(cell.grid, cell.drawn.clone());
    let st = super::Stepper::new(
        super::RateModel::new(super::run::rate_table(step, &p.etchants)),
        &cell.grid,
    );
    st.advance(&mut s, step.time_h).unwrap();
    let g = s.grid;
    let mut worst = (0.0f64, 0, 0);
    for j in 0..g.ny {
        for i in 0..j {
            let d = (s.h(i, j) - s.h(j, i)).abs();
            if d > worst.0 {
                worst = (d, i, j);
            }
        }
    }
    // Round-off only (the x and y terms are summed in another order): 3e-9 um measured.
    assert!(worst.0 < 1e-6, "{worst:?}");
}
