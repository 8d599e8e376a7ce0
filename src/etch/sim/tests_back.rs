//! The back mask's corner cell of the bundled process: taken from the drawn supports, its wall
//! and floor against the etch plan's closed forms, its convex corners against the {110}-facet
//! closed form, and symmetric about the street corner's diagonal.

use super::back_cell::{back_cell, reach_um};
use super::run::simulate_back;
use super::tests_tooth::design;

/// The cell starts on the streets' middle lines, holds support 1's two corners at the die
/// origin (both convex, bisectors out of the island) and is masked exactly on the support.
#[test]
fn back_cell_is_the_drawn_support_corner() {
    let (p, _, masks) = design(&[]);
    let cell = back_cell(&masks, 300.0, 2500.0, 1300.0, 20.0).unwrap();
    let g = cell.grid;
    assert_eq!((g.x0_um, g.y0_um), (-150.0, -150.0));
    assert_eq!((g.dx_um, g.dy_um), (20.0, 20.0));
    assert_eq!(p.geometry.dicing_street_um, 300.0);
    let r = std::f64::consts::FRAC_1_SQRT_2;
    let got: Vec<_> = cell
        .corners
        .iter()
        .map(|c| (c.at_um, c.convex, c.outward))
        .collect();
    let want = [([0.0, 0.0], true, [-r, -r]), ([0.0, 2500.0], true, [-r, r])];
    assert_eq!(got.len(), 2, "{got:?}");
    for (a, b) in got.iter().zip(want) {
        assert_eq!((a.0, a.1), (b.0, b.1));
        assert!((a.2[0] - b.2[0]).abs() < 1e-12 && (a.2[1] - b.2[1]).abs() < 1e-12);
    }
    for j in 0..g.ny {
        for i in 0..g.nx {
            let (x, y) = (g.x_um(i), g.y_um(j));
            let on_support = x >= 0.0 && (0.0..=2500.0).contains(&y);
            assert_eq!(cell.drawn[j * g.nx + i], on_support, "({x}, {y})");
        }
    }
}

/// The bundled back etch (TMAH 8.5 h, 204 um) on 10 um and 20 um: the floor at R100 t, the
/// wall's run-out h / tan 54.74 deg within half a cell, the top edge at R111 t / sin 54.74 deg within a
/// cell (the corner's fan has not reached the cut), the floor edge and width as the etch plan
/// has them, the convex corners' recession against sqrt 2 R110 t.
#[test]
fn back_wall_floor_and_corners_against_closed_forms() {
    let (p, plan, masks) = design(&[]);
    let b = simulate_back(&p, &plan, &masks, 10.0).unwrap().unwrap();
    eprintln!(
        "back: floor {:.3} um, run-out {:.3} (closed {:.3}), undercut {:.3} (closed {:.3}), \
         floor edge {:.2} (plan {:.2}, error {:?}), width {:.2} (plan {:.2})",
        b.floor_depth_um,
        b.run_out_um,
        b.closed_form_run_out_um,
        b.edge_undercut_um,
        b.closed_form_undercut_um,
        b.floor_edge_y_um,
        b.plan_floor_edge_y_um,
        b.floor_edge_error,
        b.floor_width_um,
        b.plan_floor_width_um
    );
    assert!(
        (b.floor_depth_um - 204.0).abs() < 1e-6,
        "{}",
        b.floor_depth_um
    );
    assert!((b.floor_depth_um - plan.back_depth_um).abs() < 1e-6);
    // Run-out within half a cell (measured 2.3 um on 10 um; 0.55 % on 1 um in
    // tests_closed_form.rs).
    let ro = b.closed_form_run_out_um;
    assert!(
        (b.run_out_um - ro).abs() < 0.5 * b.grid_um,
        "{} vs {ro}",
        b.run_out_um
    );
    assert!(
        (b.edge_undercut_um - b.closed_form_undercut_um).abs() < b.grid_um,
        "{} vs {}",
        b.edge_undercut_um,
        b.closed_form_undercut_um
    );
    // Floor edge: within two cells of the plan (the wall's start-up lag is part of a cell).
    assert!(
        (b.floor_edge_y_um - b.plan_floor_edge_y_um).abs() < 2.0 * b.grid_um,
        "{} vs {}",
        b.floor_edge_y_um,
        b.plan_floor_edge_y_um
    );
    assert!((b.floor_width_um - b.plan_floor_width_um).abs() < 4.0 * b.grid_um);
    assert_eq!(b.corners.len(), 2);
    for c in &b.corners {
        let e = c.error.expect("both grids read the corner");
        eprintln!(
            "corner {:?} {}: {:?} um on 10 um, {:.1} on 20 um, extrapolated {:.1}, closed form \
             {:.1}",
            c.at_um, c.kind, c.deviation_um, e.coarse_um, e.extrapolated_um, c.closed_form_um
        );
        assert_eq!(c.kind, "convex");
        let want = c.closed_form_um;
        assert!(want < -400.0);
        // Held to 15 % (the free mesa's corner is 8 % low extrapolated; this one on 10/20 um).
        assert!(
            (e.extrapolated_um - want).abs() < 0.15 * want.abs(),
            "{} vs {want}",
            e.extrapolated_um
        );
    }
    // Deterministic: the same run gives the same numbers.
    let again = simulate_back(&p, &plan, &masks, 10.0).unwrap().unwrap();
    assert_eq!(b, again);
}

/// The street corner at the die origin sees streets of the same width both ways, so within the
/// corner's reach the etched surface is symmetric about its diagonal (node for node: the grid
/// has dx = dy and its origin on the diagonal).
#[test]
fn back_corner_is_symmetric_about_its_diagonal() {
    let (p, plan, masks) = design(&[]);
    let steps = super::run::back_steps(&plan, &p.etchants);
    let r110_t: f64 = steps.iter().map(|s| s.rates.r110_um_per_h * s.time_h).sum();
    let cell = back_cell(
        &masks,
        300.0,
        2500.0,
        reach_um(r110_t, plan.back_depth_um),
        20.0,
    )
    .unwrap();
    let g = cell.grid;
    let mut s = super::Surface::new(g, cell.drawn.clone());
    let st = super::Stepper::new(super::RateModel::new(steps[0].rates), &g);
    st.advance(&mut s, steps[0].time_h).unwrap();
    // Within 900 um of the street middle's corner (the corner recedes ~505 um into the island).
    let n = (900.0 / g.dx_um) as usize;
    let mut worst = 0.0f64;
    for j in 0..n {
        for i in 0..j {
            worst = worst.max((s.h(i, j) - s.h(j, i)).abs());
        }
    }
    eprintln!("diagonal asymmetry {worst:.3e} um");
    assert!(worst < 1e-6, "{worst}");
}
