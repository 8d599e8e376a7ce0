//! Error against time for the clamped square plate with a centre point load (reference
//! alpha_P = 0.0056120, fe-validation.md). Run: `cargo run --release --example plate_bench [runs]`.
//! Times are wall-clock medians of full runs: mesh + assembly + symbolic + numeric factorisation +
//! solve + evaluation of w at the centre. faer runs sequentially (`Par::Seq`).

use std::time::Instant;
use tactfab::fe::*;

const ALPHA_P: f64 = 0.0056120;
const B_UM: f64 = 10_000.0;

fn solve_once(mesh: RectMesh) -> (f64, usize, usize) {
    let m = PlateMaterial::isotropic(169e9, 0.3);
    let d = m.bending_stiffness(100e-6).d11_nm;
    let n_el = mesh.n_elements();
    let mut p = PlateProblem::new(mesh, 100.0, m);
    p.support_all_edges(SupportKind::Clamped);
    p.load_cases.push(vec![Load::Point {
        x_um: 5000.0,
        y_um: 5000.0,
        force_n: 1.0,
        radius_um: 0.0,
    }]);
    let f = Factorised::new(&p).expect("factorise");
    let s = f.solve(&p.load_cases).expect("solve");
    let w = s[0].deflection_m(5000.0, 5000.0);
    (w * d / (B_UM * 1e-6f64).powi(2), n_el, f.n_free_dofs())
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v[v.len() / 2]
}

fn main() {
    let runs: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(21);
    if std::env::var("FE_PAR").is_err() {
        faer::set_global_parallelism(faer::Par::Seq);
    }
    let mut cases: Vec<(String, Box<dyn Fn() -> RectMesh>)> = Vec::new();
    for n in [2usize, 4, 6, 8, 10, 12, 16, 20, 24, 32, 48, 64] {
        cases.push((
            format!("uniform {n}x{n}"),
            Box::new(move || RectMesh::uniform(B_UM, B_UM, n, n)),
        ));
    }
    for (max_el, h_min) in [
        (2500.0, 1250.0),
        (2500.0, 500.0),
        (2000.0, 250.0),
        (1250.0, 125.0),
        (1000.0, 60.0),
        (700.0, 30.0),
    ] {
        cases.push((
            format!("graded max {max_el} min {h_min}"),
            Box::new(move || {
                RectMesh::build(
                    &[0.0, 5000.0, B_UM],
                    &[0.0, 5000.0, B_UM],
                    max_el,
                    &[RefinePoint {
                        x_um: 5000.0,
                        y_um: 5000.0,
                        h_min_um: h_min,
                    }],
                )
            }),
        ));
    }
    println!();
    println!("phase split (median ms): Factorised::new = dofs + pattern + symbolic + values + numeric; solve = rhs + solve + reactions");
    for n in [8usize, 16, 32, 64] {
        let (mut tf, mut ts) = (Vec::new(), Vec::new());
        for _ in 0..runs {
            let m = PlateMaterial::isotropic(169e9, 0.3);
            let mut p = PlateProblem::new(RectMesh::uniform(B_UM, B_UM, n, n), 100.0, m);
            p.support_all_edges(SupportKind::Clamped);
            p.load_cases.push(vec![Load::Point {
                x_um: 5000.0,
                y_um: 5000.0,
                force_n: 1.0,
                radius_um: 0.0,
            }]);
            let t0 = Instant::now();
            let f = Factorised::new(&p).expect("factorise");
            let t1 = Instant::now();
            let s = f.solve(&p.load_cases).expect("solve");
            std::hint::black_box(s[0].deflection_m(5000.0, 5000.0));
            tf.push((t1 - t0).as_secs_f64() * 1e3);
            ts.push(t1.elapsed().as_secs_f64() * 1e3);
        }
        println!(
            "uniform {n}x{n}: factorise {:.3} ms, solve {:.3} ms",
            median(tf),
            median(ts)
        );
    }
    // Many load cases as one multi-column solve vs one at a time.
    {
        let m = PlateMaterial::isotropic(169e9, 0.3);
        let mut p = PlateProblem::new(RectMesh::uniform(B_UM, B_UM, 32, 32), 100.0, m);
        p.support_all_edges(SupportKind::Clamped);
        let cases: Vec<Vec<Load>> = (0..64)
            .map(|k| {
                vec![Load::Point {
                    x_um: 1000.0 + 125.0 * k as f64,
                    y_um: 5000.0,
                    force_n: 1.0,
                    radius_um: 0.0,
                }]
            })
            .collect();
        let f = Factorised::new(&p).expect("factorise");
        let t0 = Instant::now();
        std::hint::black_box(f.solve(&cases).expect("solve"));
        let multi = t0.elapsed().as_secs_f64() * 1e3;
        let t0 = Instant::now();
        for c in &cases {
            std::hint::black_box(f.solve(std::slice::from_ref(c)).expect("solve"));
        }
        let single = t0.elapsed().as_secs_f64() * 1e3;
        println!("32x32, 64 load cases: one multi-column solve {multi:.2} ms, 64 single solves {single:.2} ms");
    }
    println!();
    println!("clamped square, centre point load, median of {runs} runs (alpha_ref = {ALPHA_P})");
    println!(
        "{:<28} {:>8} {:>8} {:>11} {:>12} {:>10}",
        "mesh", "elements", "dofs", "time_ms", "alpha", "rel_err"
    );
    for (name, mk) in &cases {
        let mut times = Vec::with_capacity(runs);
        let mut out = (0.0, 0, 0);
        for _ in 0..runs {
            let t0 = Instant::now();
            out = solve_once(mk());
            times.push(t0.elapsed().as_secs_f64() * 1e3);
        }
        let (alpha, el, dofs) = out;
        println!(
            "{:<28} {:>8} {:>8} {:>11.3} {:>12.8} {:>10.2e}",
            name,
            el,
            dofs,
            median(times),
            alpha,
            (alpha - ALPHA_P).abs() / ALPHA_P
        );
    }
}
