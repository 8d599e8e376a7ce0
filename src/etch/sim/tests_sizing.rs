//! Compensation sizing on the bundled tooth cell (20 um grid, so the debug build stays quick):
//! the bracket holds the corner's zero from both sides, the limit is respected, the a = 0 end
//! is the uncompensated corner's closed form, and each probe is what the layout's own drawing
//! of that compensator simulates to.

use crate::etch::sim::simulate;
use crate::etch::sim::sizing::{size, RuleVerdict, GEOMETRIES, MAX_BISECTION_STEPS};
use crate::finding::{Code, DrcCode};
use crate::process::{Compensation, CompensationGeometry, Process, StepParams};

/// The bundled process with `--set` overrides (the etch simulation tests' one loader).
pub(super) fn load(sets: &[&str]) -> Process {
    let text = std::fs::read_to_string("process/mis-grasper.yaml").unwrap();
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    crate::process::load_str(&text, "mis-grasper.yaml", &sets)
        .unwrap()
        .process
}

/// The process with its front etch's compensation set to ratio (none: no compensator).
fn with_ratio(p: &Process, ratio: Option<f64>, geometry: CompensationGeometry) -> Process {
    let mut q = p.clone();
    for s in &mut q.steps {
        if let StepParams::SiliconEtch(e) = &mut s.params {
            if e.compensation.is_some() {
                e.compensation = ratio.map(|ratio| Compensation {
                    ratio,
                    geometry,
                    bar_width_um: None,
                });
            }
        }
    }
    q
}

#[test]
fn sized_a_brackets_the_corner_and_matches_the_drawn_mask() {
    let grid = 20.0;
    let p = load(&[]);
    let plan = crate::etch::plan(&p);
    let masks = crate::layout::build(&p, &plan).unwrap();
    let z = size(&p, &plan, &masks, grid).unwrap();
    assert_eq!(z.geometries.len(), GEOMETRIES.len());
    assert_eq!(z.coarse_grid_um, 2.0 * grid);
    let step = crate::etch::sim::run::front_step(&plan).unwrap();
    for g in &z.geometries {
        // Bounded: two ends, the bisection, the rule.
        assert!(g.probes.len() <= 2 + MAX_BISECTION_STEPS + 1, "{g:?}");
        assert!(g.probes.iter().all(|q| q.a_um <= g.largest_a_um + 1e-9));
        // The a = 0 end is the uncompensated convex corner: sqrt 2 R110 t inwards (the {110}
        // facet through the corner), within 15 % (the tests of the closed form hold 10 % at
        // 1-2 um).
        let zero = g.probes.iter().find(|q| q.a_um == 0.0).unwrap();
        let closed = -(2f64.sqrt()) * step.rate_110_um_per_h * step.time_h;
        assert!(
            (zero.best_um() - closed).abs() < 0.15 * closed.abs(),
            "{} vs {closed}",
            zero.best_um()
        );
        if let (Some([lo, hi]), Some([clo, chi])) = (g.bracket_a_um, g.bracket_corner_um) {
            // The zero is held from both sides, and the bracket was halved to the grid or to the
            // cap of steps.
            assert!(lo < hi && clo < 0.0 && chi > 0.0, "{g:?}");
            assert!(
                hi - lo <= grid || g.probes.len() >= 2 + MAX_BISECTION_STEPS,
                "{g:?}"
            );
        }
        if g.within_tolerance {
            assert!(g.sized_corner_deviation_um.abs() <= z.tolerance_um);
        } else {
            // Best achievable: no probe is nearer.
            assert!(g
                .probes
                .iter()
                .all(|q| q.best_um().abs() >= g.sized_corner_deviation_um.abs()));
            assert_ne!(g.rule, RuleVerdict::Confirmed);
        }
        // The sized compensator drawn by the layout itself simulates to the same corner, and the
        // plan finds no collision at the largest a.
        let q = with_ratio(&p, g.sized_ratio, g.geometry);
        let qplan = crate::etch::plan(&q);
        let qmasks = crate::layout::build(&q, &qplan).unwrap();
        let s = simulate(&q, &qplan, &qmasks, grid).unwrap();
        let again = s.corner_error.map_or(s.corner_deviation_um, |e| {
            e.extrapolated_corner_deviation_um
        });
        assert!(
            (again - g.sized_corner_deviation_um).abs() < 1e-9,
            "{again} vs {}",
            g.sized_corner_deviation_um
        );
        let at_limit = with_ratio(&p, Some(step.depth_um / g.largest_a_um), g.geometry);
        let lplan = crate::etch::plan(&at_limit);
        assert!(
            !lplan
                .warnings
                .iter()
                .any(|w| w.code == Code::Drc(DrcCode::CompensatorsCollide)),
            "{:?}",
            lplan.warnings
        );
    }
}

#[test]
fn a_huge_tolerance_confirms_the_rule() {
    let p = load(&["etchants.etched_corner_tolerance_um=2000"]);
    let plan = crate::etch::plan(&p);
    let masks = crate::layout::build(&p, &plan).unwrap();
    let z = size(&p, &plan, &masks, 30.0).unwrap();
    for g in &z.geometries {
        assert_eq!(g.rule, RuleVerdict::Confirmed, "{g:?}");
        assert!(g.within_tolerance);
        assert_eq!(g.tolerance_band_a_um.unwrap()[0], 0.0);
    }
}
