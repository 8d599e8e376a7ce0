//! Local refinement: merged bricks and the hanging nodes on their faces. The patch test stays
//! exact across every kind of hanging node (2:1 and 4:1 faces, edges, chains, nodes on the
//! boundary), a grid merged everywhere is the coarse grid, the spaces nest (coarse, partly
//! merged, fine), loads on hanging nodes balance, and the nonlinear model agrees.

use std::sync::Arc;

use super::dofs::active_nodes;
use super::hanging::Hanging;
use super::tests::{linear_field_m, prescribe_linear_on_box, voigt_strain};
use crate::fe::error::FeError;
use crate::fe::solid::*;

/// [0, 2000]^2 x [0, 1000] um in 250 um cells with bricks of 4 x 4 x 2, 2 x 2 x 2 and 2 x 1 x 1
/// cells beside single cells: hanging nodes on 2:1 and 4:1 faces, on edges, in chains (a cell's
/// node on a 2-brick's node that hangs on the 4-brick) and on the outer faces.
fn refined_block() -> HexGrid {
    let xy = uniform_lines(0.0, 2000.0, 8);
    let mut g = HexGrid::new(&xy, &xy, &uniform_lines(0.0, 1000.0, 4)).unwrap();
    g.merge([0, 0, 0], [4, 4, 2]).unwrap();
    g.merge([4, 0, 0], [6, 2, 2]).unwrap();
    g.merge([4, 2, 0], [6, 4, 2]).unwrap();
    g.merge([0, 4, 0], [2, 6, 2]).unwrap();
    g.merge([2, 4, 2], [4, 5, 3]).unwrap();
    g
}

#[test]
fn merge_checks_its_box() {
    let g = refined_block();
    let e = g.element([0, 0, 0]);
    assert_eq!(g.element_size_um(e), [1000.0, 1000.0, 500.0]);
    assert_eq!(g.element_centre_um(e), [500.0, 500.0, 250.0]);
    let nodes = g.element_nodes(e);
    assert_eq!(g.lattice_position_um(nodes[26]), [1000.0, 1000.0, 500.0]);
    assert_eq!(g.lattice_position_um(nodes[13]), [500.0, 500.0, 250.0]);
    for n in nodes {
        assert!(g.node_elements(n).any(|x| x == e), "node {n}");
    }
    let inside = g.element([3, 2, 1]);
    assert_eq!((g.material(inside), g.owner(inside)), (None, e));
    let fails = |g: &mut HexGrid, lo, hi| {
        let err = g.merge(lo, hi).unwrap_err();
        assert!(matches!(err, FeError::SolidInput { .. }), "{err}");
    };
    let mut g2 = g.clone();
    fails(&mut g2, [3, 3, 0], [5, 5, 1]); // overlaps a brick
    fails(&mut g2, [6, 6, 0], [7, 7, 1]); // one cell
    fails(&mut g2, [6, 6, 3], [8, 8, 5]); // leaves the grid
    fails(&mut g2, [6, 6, 2], [7, 7, 2]); // empty
    let mut voided = g.clone();
    voided.set_material([7, 7, 3], None);
    fails(&mut voided, [6, 6, 2], [8, 8, 4]);
    // No line halves [0, 100, 300].
    let mut uneven = HexGrid::new(&[0.0, 100.0, 300.0], &[0.0, 1.0], &[0.0, 1.0]).unwrap();
    fails(&mut uneven, [0, 0, 0], [2, 1, 1]);
    // A refused merge changes nothing.
    assert_eq!(g2.materials(), g.materials());
    assert_eq!(g2.merged_bricks(), g.merged_bricks());
}

/// Patch test (Irons; Hughes sec. 4.6) across hanging nodes: a linear field on the boundary is
/// reproduced exactly at every node, hanging ones included, with the exact constant stress in
/// merged and fine bricks, on an anisotropic material and with either transverse shear.
#[test]
fn patch_test_holds_across_hanging_nodes() {
    let grid = refined_block();
    let pos: Vec<[f64; 3]> = (0..grid.node_count())
        .map(|n| grid.node_position_um(n))
        .collect();
    let active = active_nodes(&grid).unwrap();
    let hanging = Hanging::find(&grid, &pos, &active).unwrap();
    // Chains resolved: no master hangs.
    assert!(hanging.nodes.len() > 100, "{} hanging", hanging.nodes.len());
    for (_, ms) in &hanging.nodes {
        assert!(ms.iter().all(|(m, _)| hanging.masters(*m).is_none()));
        let sum: f64 = ms.iter().map(|(_, w)| w).sum();
        assert!((sum - 1.0).abs() < 1e-12, "{sum}");
    }
    for shear in [TransverseShear::Displacement, TransverseShear::Tied] {
        let c = Elasticity::cubic(165.7e9, 63.9e9, 79.6e9).rotated_about_z(30.0);
        let mut p = SolidProblem::new(grid.clone(), vec![c]);
        p.shear = shear;
        let gradient = [
            [1.0e-4, 2.0e-5, -3.0e-5],
            [5.0e-5, -2.0e-4, 1.0e-5],
            [-4.0e-5, 6.0e-5, 1.5e-4],
        ];
        let u0_m = [1e-7, -2e-7, 3e-7];
        // Every face of the 2000 x 2000 x 1000 block held to the field.
        prescribe_linear_on_box(&mut p, [0.0; 3], [2000.0, 2000.0, 1000.0], u0_m, gradient);
        p.load_cases.push(vec![]);
        let s = &p.solve().unwrap()[0];
        let exact = linear_field_m(u0_m, gradient);
        let scale = 2000e-6 * 2e-4;
        let mut worst: f64 = 0.0;
        for (n, x) in s.node_positions_um().iter().enumerate() {
            if !active[n] {
                continue;
            }
            let (u, e) = (s.node_displacement_m(n), exact(*x));
            for d in 0..3 {
                worst = worst.max((u[d] - e[d]).abs() / scale);
            }
        }
        assert!(worst < 1e-10, "{shear:?}: displacement error {worst:e}");
        let sigma = c.stress_pa(&voigt_strain(&gradient));
        let s_scale = sigma.iter().map(|v| v.abs()).fold(0.0, f64::max);
        let mut worst_s: f64 = 0.0;
        // The 4-brick, a 2-brick, the flat brick and fine cells beside them.
        for at in [
            [300.0, 700.0, 100.0],
            [1100.0, 900.0, 400.0],
            [700.0, 1100.0, 600.0],
            [1300.0, 300.0, 700.0],
            [1900.0, 1900.0, 900.0],
            [600.0, 1200.0, 300.0],
        ] {
            let (e, xi) = s.locate(at).unwrap();
            let st = s.stress_at(e, xi).unwrap();
            for d in 0..6 {
                worst_s = worst_s.max((st[d] - sigma[d]).abs() / s_scale);
            }
            let u = s.displacement_m(at).unwrap();
            let ex = exact(at);
            assert!(
                (0..3).all(|d| (u[d] - ex[d]).abs() < 1e-10 * scale),
                "{at:?}"
            );
        }
        assert!(worst_s < 1e-10, "{shear:?}: stress error {worst_s:e}");
        let r = s.reaction_n("boundary").unwrap();
        let big = s
            .nodal_reactions("boundary")
            .iter()
            .map(|(_, f)| f.iter().fold(0.0f64, |a, v| a.max(v.abs())))
            .fold(0.0, f64::max);
        assert!(r.iter().all(|v| v.abs() < 1e-9 * big), "{r:?} vs {big}");
    }
}

/// A cantilever 4000 x 500 x 500 um, clamped at x = 0, 1e-4 N down at the tip's centre line.
fn cantilever(merge: impl Fn(&mut HexGrid)) -> SolidProblem {
    let mut grid = HexGrid::new(
        &uniform_lines(0.0, 4000.0, 8),
        &uniform_lines(0.0, 500.0, 2),
        &uniform_lines(0.0, 500.0, 2),
    )
    .unwrap();
    merge(&mut grid);
    let mut p = SolidProblem::new(grid, vec![Elasticity::isotropic(169e9, 0.28)]);
    p.constraints.push(Constraint::clamp(
        "root",
        NodeSet::Plane {
            axis: Axis3::X,
            at_um: 0.0,
        },
    ));
    p.load_cases.push(vec![SolidLoad::Point {
        at_um: [4000.0, 250.0, 250.0],
        force_n: [0.0, 0.0, -1e-4],
        snap: Snap::Exact,
    }]);
    p
}

fn merge_pairs(g: &mut HexGrid, from_cell: usize) {
    for i in (from_cell..8).step_by(2) {
        g.merge([i, 0, 0], [i + 2, 2, 2]).unwrap();
    }
}

/// Merged everywhere into 2 x 2 x 2 boxes, the grid is the coarse grid of 4 x 1 x 1 cells: the
/// same field to round-off. Partly merged, it lies between the two: the spaces nest, so the
/// tip's compliance rises from coarse to partly merged to fine, and the clamp holds the load.
#[test]
fn merged_spaces_nest_between_the_coarse_and_the_fine_grid() {
    let tip = [4000.0, 250.0, 250.0];
    let solve = |p: SolidProblem| p.solve().unwrap().remove(0);
    let fine = solve(cantilever(|_| {}));
    let partly = solve(cantilever(|g| merge_pairs(g, 4)));
    let merged = solve(cantilever(|g| merge_pairs(g, 0)));
    let coarse = {
        let grid =
            HexGrid::new(&uniform_lines(0.0, 4000.0, 4), &[0.0, 500.0], &[0.0, 500.0]).unwrap();
        let mut p = cantilever(|_| {});
        p.grid = grid;
        solve(p)
    };
    let w = |s: &SolidSolution| -s.displacement_m(tip).unwrap()[2];
    for x in [500.0, 1700.0, 3300.0] {
        for at in [[x, 0.0, 0.0], [x, 250.0, 500.0], [x, 125.0, 375.0]] {
            let (a, b) = (
                merged.displacement_m(at).unwrap(),
                coarse.displacement_m(at).unwrap(),
            );
            assert!(
                (0..3).all(|d| (a[d] - b[d]).abs() <= 1e-9 * w(&coarse)),
                "{at:?}: {a:?} {b:?}"
            );
        }
    }
    let (wc, wp, wf) = (w(&merged), w(&partly), w(&fine));
    assert!(wc < wp && wp < wf, "{wc:e} {wp:e} {wf:e}");
    // The merged far half costs little: the partly merged tip is within 1 % of the fine one.
    assert!((wf - wp) / wf < 0.01, "{wp:e} {wf:e}");
    let r = partly.reaction_n("root").unwrap();
    assert!((r[2] - 1e-4).abs() < 1e-12 && r[0].abs() < 1e-12, "{r:?}");
    assert!(partly.grid().has_merged());
}

/// A point force on a hanging node acts through its masters: the clamp balances it, and it
/// does the same work as the force split over the masters by hand.
#[test]
fn a_force_on_a_hanging_node_acts_on_its_masters() {
    // (3000, 125, 375) hangs: a fine cell's mid-edge node on the merged brick's x = 3000 face.
    let at = [3000.0, 125.0, 375.0];
    let mut p = cantilever(|g| {
        g.merge([6, 0, 0], [8, 2, 2]).unwrap();
    });
    p.load_cases[0] = vec![SolidLoad::Point {
        at_um: at,
        force_n: [0.0, 1e-4, -2e-4],
        snap: Snap::Exact,
    }];
    let s = p.solve().unwrap().remove(0);
    let r = s.reaction_n("root").unwrap();
    assert!(
        (r[1] + 1e-4).abs() < 1e-12 && (r[2] - 2e-4).abs() < 1e-12,
        "{r:?}"
    );
    // By hand: the trace's weights of the brick's face nodes (biquadratic in y, z).
    let q = |t: f64| [t * (t - 1.0) / 2.0, 1.0 - t * t, t * (t + 1.0) / 2.0];
    let (wy, wz) = (q(-0.5), q(0.5));
    let mut by_hand = vec![];
    for (j, y) in [0.0, 250.0, 500.0].iter().enumerate() {
        for (k, z) in [0.0, 250.0, 500.0].iter().enumerate() {
            let w = wy[j] * wz[k];
            if w.abs() > 1e-14 {
                by_hand.push(SolidLoad::Point {
                    at_um: [3000.0, *y, *z],
                    force_n: [0.0, 1e-4 * w, -2e-4 * w],
                    snap: Snap::Exact,
                });
            }
        }
    }
    p.load_cases[0] = by_hand;
    let h = p.solve().unwrap().remove(0);
    let (a, b) = (s.displacement_m(at).unwrap(), h.displacement_m(at).unwrap());
    assert!(
        (0..3).all(|d| (a[d] - b[d]).abs() < 1e-12 * a[2].abs()),
        "{a:?} {b:?}"
    );
}

/// At a small load the nonlinear model on a grid with hanging nodes gives the linear field
/// (to the load's geometric order), and its reactions balance.
#[test]
fn the_nonlinear_model_takes_hanging_nodes() {
    let p = cantilever(|g| merge_pairs(g, 4));
    let lin = p.solve().unwrap().remove(0);
    let nl = p.solve_nonlinear(TlOptions::default()).unwrap().remove(0);
    let tip = [4000.0, 250.0, 250.0];
    let (a, b) = (
        lin.displacement_m(tip).unwrap()[2],
        nl.displacement_m(tip).unwrap()[2],
    );
    assert!(((a - b) / a).abs() < 1e-5, "{a:e} {b:e}");
    let r = nl.reaction_n("root").unwrap();
    assert!((r[2] - 1e-4).abs() < 1e-10, "{r:?}");
}

/// Under a node map a merge is taken where the brick's quadratic trace puts every node of the
/// box where the map does (a bilinear taper, as of a tooth's sidewall) and refused where the map
/// bends the box; the patch test holds on the tapered, merged grid.
#[test]
fn merges_follow_the_node_map_or_are_refused() {
    let l = uniform_lines(0.0, 1000.0, 4);
    // x narrows with z: bilinear in (x, z), which quadratic bricks carry exactly.
    let taper = |p: [f64; 3]| [p[0] * (1.0 - 0.2 * p[2] / 1000.0), p[1], p[2]];
    let mut g = HexGrid::new(&l, &l, &l).unwrap().with_map(Arc::new(taper));
    g.merge([0, 0, 0], [2, 2, 1]).unwrap();
    g.merge([2, 2, 2], [4, 4, 4]).unwrap();
    let mut bent = HexGrid::new(&l, &l, &l)
        .unwrap()
        .with_map(Arc::new(|p: [f64; 3]| {
            [p[0] + 20.0 * (p[1] / 300.0).sin(), p[1], p[2]]
        }));
    let err = bent.merge([0, 0, 0], [2, 2, 1]).unwrap_err();
    assert!(err.to_string().contains("bends"), "{err}");
    assert!(!bent.has_merged());
    let c = Elasticity::isotropic(169e9, 0.28);
    let mut p = SolidProblem::new(g, vec![c]);
    let gradient = [[1e-4, 0.0, 2e-5], [0.0, -5e-5, 0.0], [3e-5, 0.0, 1e-4]];
    let u0_m = [0.0; 3];
    for (axis, lo, hi) in [(Axis3::Y, 0.0, 1000.0), (Axis3::Z, 0.0, 1000.0)] {
        for at_um in [lo, hi] {
            p.constraints.push(Constraint {
                group: "boundary".into(),
                nodes: NodeSet::Plane { axis, at_um },
                fixed: [true; 3],
                value: Prescribed::Linear { u0_m, gradient },
            });
        }
    }
    // The tapered x faces: x = 0, and x = 1000 (1 - 0.2 z / 1000) after the map (not a plane:
    // held by a box, which takes a few inner nodes too).
    p.constraints.push(Constraint {
        group: "boundary".into(),
        nodes: NodeSet::Plane {
            axis: Axis3::X,
            at_um: 0.0,
        },
        fixed: [true; 3],
        value: Prescribed::Linear { u0_m, gradient },
    });
    p.constraints.push(Constraint {
        group: "boundary".into(),
        nodes: NodeSet::Box {
            min_um: [790.0, -1.0, -1.0],
            max_um: [1001.0, 1001.0, 1001.0],
        },
        fixed: [true; 3],
        value: Prescribed::Linear { u0_m, gradient },
    });
    p.load_cases.push(vec![]);
    let s = p.solve().unwrap().remove(0);
    let exact = linear_field_m(u0_m, gradient);
    for at in [
        [300.0, 400.0, 200.0],
        [500.0, 700.0, 800.0],
        [100.0, 900.0, 500.0],
    ] {
        let (u, e) = (s.displacement_m(at).unwrap(), exact(at));
        assert!(
            (0..3).all(|d| (u[d] - e[d]).abs() < 1e-9 * 1e-7),
            "{at:?}: {u:?} {e:?}"
        );
    }
}

/// Bricks offset by a cell share nodes without hanging and their traces differ: refused when
/// the dofs are numbered, naming both.
#[test]
fn offset_bricks_are_refused() {
    let l = uniform_lines(0.0, 400.0, 4);
    let mut g = HexGrid::new(&l, &l, &[0.0, 100.0]).unwrap();
    g.merge([0, 0, 0], [2, 2, 1]).unwrap();
    g.merge([2, 1, 0], [4, 3, 1]).unwrap();
    let mut p = SolidProblem::new(g, vec![Elasticity::isotropic(169e9, 0.3)]);
    p.constraints.push(Constraint::clamp(
        "root",
        NodeSet::Plane {
            axis: Axis3::X,
            at_um: 0.0,
        },
    ));
    p.load_cases.push(vec![]);
    let err = p.solve().unwrap_err();
    assert!(err.to_string().contains("share part of a face"), "{err}");
}

/// The elimination order never cuts through a merged brick: every plane it separates on is one
/// no brick spans, and it still numbers every node once.
#[test]
fn the_order_cuts_between_merged_bricks() {
    let g = refined_block();
    let crossed = super::ordering::crossed_planes(&g);
    // The 4-brick spans lattice planes 1-7 along x and y and 1-3 along z.
    assert!((1..8).all(|m| crossed[0][m] && crossed[1][m]) && !crossed[0][8]);
    assert!((1..4).all(|m| crossed[2][m]) && !crossed[2][4]);
    let order = super::ordering::nested_dissection_between(g.lattice(), &crossed);
    let mut sorted = order.clone();
    sorted.sort_unstable();
    assert!(sorted.iter().enumerate().all(|(k, &n)| k == n));
    // The last block eliminated is the top separator: a plane no brick spans.
    let lat = g.lattice();
    let total: usize = lat.iter().product();
    let axis = (0..3)
        .find(|&d| {
            let last = &order[order.len() - total / lat[d]..];
            let m = g.node_ijk(last[0])[d];
            last.iter().all(|&n| g.node_ijk(n)[d] == m)
        })
        .expect("a separator plane");
    let m = g.node_ijk(order[order.len() - 1])[axis];
    assert!(!crossed[axis][m], "cut at a crossed plane {m} along {axis}");
}
