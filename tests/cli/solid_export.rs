//! The solid model export for the independent code (`examples/solid_export.rs`,
//! `benches/solid_peer.py`): it is the model `fe --model solid` solves (the same readings), and
//! it is whole (loads, constraints, volumes and electrodes consistent among themselves).

use tactfab::process::{Limits, Scene, SceneLoad};
use tactfab::sensor::solid::{evaluate_solid, SolidRun};
use tactfab::sensor::solid_export::{export_scene, ExportOptions};
use tactfab::sensor::solid_mesh::Base;

use super::sensor::geometry;

#[test]
fn the_export_is_the_solid_rungs_model_and_is_complete() {
    // A 12 mm die with four columns of teeth, a centre load: half the die is solved.
    let g = geometry(&[
        "geometry.die_length_um=12000",
        "geometry.teeth.count_x=4",
        "checks.scenes[0].load.point.x_um=6000",
        "checks.scenes[1].load.point.x_um=6000",
    ]);
    let scene = Scene {
        name: "c".into(),
        load: SceneLoad::Point {
            x_um: 6000.0,
            y_um: 7500.0,
            force_n: 1.0,
            radius_um: 500.0,
        },
        limits: Limits::default(),
    };
    let run = SolidRun {
        base: Base::Rigid,
        levels: 1,
        tol: 0.01,
        symmetry: true,
        nonlinear: false,
        graded: false,
        tied_shear: true,
        grading: tactfab::sensor::solid::SolidGrading::Lines,
    };
    let rung = evaluate_solid(&g, &scene, run, &[], &[]).unwrap();
    let r = &rung.levels[0].readout;
    let ex = export_scene(
        &g,
        &scene,
        Base::Rigid,
        ExportOptions {
            level: 0,
            symmetry: true,
            runs: 1,
            tied_shear: true,
        },
        &[],
    )
    .unwrap();
    let res = &ex.results;
    // The same model: bit-for-bit the same readings and dofs as the rung's level 0.
    assert_eq!(res.charge_pc, r.charge_pc);
    assert_eq!(res.deflection_at_load_um, r.deflection_at_load_um);
    assert_eq!(
        (res.support1_n, res.support2_n),
        (r.support1_n, r.support2_n)
    );
    assert_eq!(res.free_dofs, rung.levels[0].dofs);
    // The cell sizes it says are the level's, across the span too.
    let level = &rung.levels[0];
    assert_eq!(
        (ex.element_um, ex.span_element_um),
        (level.element_um, level.span_element_um)
    );
    assert!(ex.span_element_um < ex.element_um);
    assert!(ex.mirror_y_um.is_some() && ex.mirror_x_um.is_none());

    // Connectivity: 27 distinct nodes per element, every node used, positive volumes.
    let mut used = vec![false; ex.nodes_um.len()];
    for el in &ex.elements {
        let mut s = el.clone();
        s.sort_unstable();
        s.dedup();
        assert_eq!(s.len(), 27);
        for &n in el {
            used[n] = true;
        }
    }
    assert!(used.iter().all(|&u| u));
    assert!(ex.element_volume_um3.iter().all(|&v| v > 0.0));
    // Node order: tactfab's local node a + 3 b + 9 c is the point (a, b, c) / 2 of the element:
    // nodes 2, 6 and 18 lie from node 0 along +x, +y and +z (the map is monotone along each
    // grid line).
    for el in &ex.elements {
        let p = |k: usize| ex.nodes_um[el[k]];
        for (k, d) in [(2, 0), (6, 1), (18, 2)] {
            assert!(p(k)[d] > p(0)[d], "{:?} {:?}", p(0), p(k));
        }
    }

    // The load: the half model carries half the force, straight down, all of it on pressure
    // faces pointing up; the reactions balance it.
    let sum = |c: usize| -> f64 {
        res.load_vector_n
            .iter()
            .filter(|e| e.1 == c)
            .map(|e| e.2)
            .sum()
    };
    assert!((sum(2) + 0.5).abs() < 1e-12, "{}", sum(2));
    assert!(sum(0).abs() < 1e-12 && sum(1).abs() < 1e-12);
    assert!(!ex.pressures.is_empty() && ex.points.is_empty());
    assert!(ex.pressures.iter().all(|p| p.face == "+z"));
    for c in 0..3 {
        let total: f64 = res.reactions_n.iter().map(|(_, f)| f[c]).sum::<f64>() + sum(c);
        assert!(total.abs() < 1e-9, "component {c}: {total}");
    }

    // Constraints: the base's bottom (z = 0, the rigid base) clamped, the mirror's normal
    // component, nothing else.
    assert_eq!(ex.groups, ["base", "mirror_y"]);
    let m = ex.mirror_y_um.unwrap();
    for &(n, c, grp) in &ex.constrained {
        let p = ex.nodes_um[n];
        match grp {
            0 => assert!(p[2].abs() < 1e-6),
            _ => assert!((p[1] - m).abs() < 1e-6 && c == 1, "{p:?} {c}"),
        }
    }

    // Electrodes: each reads film elements, each of those inside the film's layer.
    assert_eq!(ex.electrodes.len(), g.electrodes.len());
    for e in &ex.electrodes {
        assert!(!e.elements.is_empty(), "{}", e.name);
        // The electrode edges are grid lines: no film element is cut.
        assert!(
            e.cut_elements.is_empty(),
            "{}: {:?}",
            e.name,
            e.cut_elements
        );
        for &[el, k] in &e.elements {
            assert_eq!(ex.material[el], 1, "{} reads a non-PVDF element", e.name);
            assert!(k >= 1);
        }
    }
    // The silicon's C in die axes: the <110> rotation of a cubic crystal, C11' = (C11 + C12) / 2
    // + C44 with C11 = C33', C12 = C13', C44 = C44' (Nye ch. VIII).
    let c = &ex.materials[0].c_pa;
    assert_eq!(ex.materials[0].name, "silicon");
    let c11 = 0.5 * (c[2][2] + c[0][2]) + c[3][3];
    assert!((c[0][0] - c11).abs() < 1e-6 * c11, "{c:?}");
}
