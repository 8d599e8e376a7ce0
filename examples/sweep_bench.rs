//! Design-sweep benchmark: `cargo run --release --example sweep_bench [threads] [--direct]`.
//!
//! Runs the paper 001 sweep (15,000 designs, 4 N centre load, orthotropic <110> Si) with the
//! standard sweep mesh through `tactfab::sweep::run_range` (rayon, one symbolic factorisation per
//! worker; by default one solve per (length, width) scaled by t^3, with `--direct` also one numeric
//! refactorisation per design), and prints: the total wall-clock time, the median
//! time per design (a sequential pass over 300 designs spread over the grid), the family size, and
//! the estimated discretisation error of the sweep mesh (three nested meshes, Richardson) at the
//! eight grid corners and the prototype. Wall-clock times on a shared machine: quote medians.

use std::time::Instant;

use tactfab::fe::{DieEdge, PlateMaterial};
use tactfab::sweep::run::corner_designs;
use tactfab::sweep::*;

fn main() {
    if let Some(t) = std::env::args()
        .nth(1)
        .and_then(|s| s.parse::<usize>().ok())
    {
        rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build_global()
            .unwrap();
    }
    let grid = Grid::paper();
    let model = DesignModel {
        material: PlateMaterial::silicon(DieEdge::Along110),
        force_n: 4.0,
        contact_radius_um: 250.0,
        mesh: MeshSpec::standard(),
    };
    let proto = Design {
        index: usize::MAX,
        length_um: 30_000.0,
        width_um: 15_000.0,
        thickness_um: 100.0,
    };
    let matching = Matching::new(proto, &model, 0.01, 4000.0 / 3.0).unwrap();
    let mesh = model.mesh.mesh(30_000.0, 15_000.0);
    println!(
        "threads {}, mesh {} x {} elements, {} designs",
        rayon::current_num_threads(),
        mesh.nx(),
        mesh.ny(),
        grid.len()
    );

    let mut solver = DesignSolver::new(model);
    let mut per = Vec::new();
    for k in 0..300 {
        let d = grid.design(k * 50);
        let t = Instant::now();
        solver.solve(&d).unwrap();
        per.push(t.elapsed().as_secs_f64() * 1e3);
    }
    per.sort_by(f64::total_cmp);
    println!(
        "per design (sequential, 300 designs): median {:.2} ms, p90 {:.2} ms",
        per[150], per[270]
    );

    let direct = std::env::args().any(|a| a == "--direct");
    for mode in if direct {
        vec![Mode::ScaledThickness, Mode::Direct]
    } else {
        vec![Mode::ScaledThickness]
    } {
        let t = Instant::now();
        let rows = run_range(&grid, &model, &matching, 0..grid.len(), mode, &|_| {}).unwrap();
        let total = t.elapsed().as_secs_f64();
        let family = rows.iter().filter(|r| r.matches).count();
        println!(
            "sweep {mode:?}: {} designs in {:.2} s ({:.3} ms/design wall), family {} within 1 % \
             of the prototype's elongation {:.3} um",
            rows.len(),
            total,
            1e3 * total / rows.len() as f64,
            family,
            matching.prototype_response.elongation_um
        );
    }

    let mut sample = corner_designs(&grid);
    sample.push(proto);
    let t = Instant::now();
    let errs = estimate_error(&model, &sample).unwrap();
    println!(
        "error of the sweep mesh (3 nested meshes, {:.1} s):",
        t.elapsed().as_secs_f64()
    );
    println!(
        "{:>9} {:>9} {:>7} {:>12} {:>12} {:>12}",
        "length_um", "width_um", "t_um", "deflection", "elongation", "max_stress"
    );
    for e in &errs {
        println!(
            "{:>9.0} {:>9.0} {:>7.1} {:>11.3}% {:>11.3}% {:>11.3}%",
            e.design.length_um,
            e.design.width_um,
            e.design.thickness_um,
            100.0 * e.deflection_rel,
            100.0 * e.elongation_rel,
            100.0 * e.max_stress_rel
        );
    }
    let worst = |f: fn(&DesignError) -> f64| errs.iter().map(f).fold(0.0, f64::max);
    println!(
        "worst: deflection {:.3} %, elongation {:.3} %, max stress {:.3} %",
        100.0 * worst(|e| e.deflection_rel),
        100.0 * worst(|e| e.elongation_rel),
        100.0 * worst(|e| e.max_stress_rel)
    );
}
