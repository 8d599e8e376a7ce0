//! Cost of the solid rung, one command: `cargo run --release --example solid_bench [runs] [max_level]`.
//!
//! The plain plate of the solid tests, solved whole: Si (die edges along <110>), 10 x 10 mm x
//! 100 um, the edges x = 0 and x = 10 mm clamped on their faces, y edges free, 1 N uniform over
//! the centre 1 x 1 mm square on the top face. Per mesh: free dofs, entries of the assembled lower
//! triangle and of the factor (f64s, nested dissection and AMD), and the median over `runs` (5) of
//! setup (positions, checks, dofs, element matrices, pattern), assembly, symbolic analysis,
//! numeric factorisation and the solve of 4 load cases; the centre deflection beside the
//! Kirchhoff value for orientation. faer uses its default parallelism (all cores) unless
//! SOLID_SEQ is set.

use std::time::Instant;

use tactfab::fe::material::DieEdge;
use tactfab::fe::solid::*;

mod support;
use support::median;

const SPAN_UM: f64 = 10_000.0;
const T_UM: f64 = 100.0;

fn plate(h_um: f64, nz: usize) -> SolidProblem {
    let n = (SPAN_UM / h_um).round() as usize;
    let l = uniform_lines(0.0, SPAN_UM, n);
    let grid = HexGrid::new(&l, &l, &uniform_lines(0.0, T_UM, nz)).expect("grid");
    let mut p = SolidProblem::new(grid, vec![Elasticity::silicon(DieEdge::Along110)]);
    for (g, at) in [("x0", 0.0), ("x1", SPAN_UM)] {
        p.constraints.push(Constraint::clamp(
            g,
            NodeSet::Plane {
                axis: Axis3::X,
                at_um: at,
            },
        ));
    }
    let patch = |f: f64| SolidLoad::Pressure {
        face: FaceRect {
            axis: Axis3::Z,
            at_um: T_UM,
            outward: Outward::Plus,
            from_um: [4500.0, 4500.0],
            to_um: [5500.0, 5500.0],
        },
        pressure_pa: f / 1e-6,
    };
    // Four load cases on one factorisation.
    p.load_cases = (1..=4).map(|k| vec![patch(k as f64)]).collect();
    p
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let runs: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(5);
    let max_level: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(4);
    if std::env::var("SOLID_SEQ").is_ok() {
        faer::set_global_parallelism(faer::Par::Seq);
    }
    println!(
        "threads: rayon {}, faer {:?}",
        rayon::current_num_threads(),
        faer::get_global_parallelism()
    );
    println!(
        "{:>7} {:>3} {:>8} {:>10} {:>11} {:>11} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>12}",
        "h_um",
        "nz",
        "dofs",
        "nnz(K)",
        "L (ND)",
        "L (AMD)",
        "setup_s",
        "asm_s",
        "symb_s",
        "num_s",
        "solve_s",
        "AMD_s",
        "w_centre_um"
    );
    let meshes = [(500.0, 1), (250.0, 1), (250.0, 2), (125.0, 1), (125.0, 2)];
    for &(h, nz) in meshes.iter().take(max_level.min(meshes.len())) {
        let p = plate(h, nz);
        let mut t = [vec![], vec![], vec![], vec![], vec![]];
        let mut last = None;
        for _ in 0..runs {
            let m = SolidModel::new(&p).expect("model");
            let t0 = Instant::now();
            let s = m.solve(&p.load_cases).expect("solve");
            let solve = t0.elapsed().as_secs_f64();
            let b = m.timings();
            for (v, x) in t.iter_mut().zip([
                b.setup.as_secs_f64(),
                b.assembly.as_secs_f64(),
                b.symbolic.as_secs_f64(),
                b.numeric.as_secs_f64(),
                solve,
            ]) {
                v.push(x);
            }
            last = Some((m, s));
        }
        let (m, s) = last.expect("runs >= 1");
        let w = -s[0].displacement_m([5000.0, 5000.0, 50.0]).expect("centre")[2];
        let t0 = Instant::now();
        let amd = SolidModel::with_ordering(&p, Ordering::Amd).expect("amd");
        let amd_s = t0.elapsed().as_secs_f64();
        println!(
            "{:>7} {:>3} {:>8} {:>10} {:>11} {:>11} {:>8.3} {:>8.3} {:>8.3} {:>8.3} {:>8.3} {:>8.2} {:>12.5}",
            h,
            nz,
            m.n_free_dofs(),
            m.matrix_nnz(),
            m.factor_len(),
            amd.factor_len(),
            median(t[0].clone()),
            median(t[1].clone()),
            median(t[2].clone()),
            median(t[3].clone()),
            median(t[4].clone()),
            amd_s,
            w * 1e6
        );
        println!(
            "        AMD build: symbolic {:.3} s, numeric {:.3} s; element matrices computed: {}",
            amd.timings().symbolic.as_secs_f64(),
            amd.timings().numeric.as_secs_f64(),
            m.distinct_element_matrices()
        );
    }
}
