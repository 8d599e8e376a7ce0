//! Cost of the geometrically nonlinear solid, one command:
//! `cargo run --release --example solid_tl_bench [runs]`.
//!
//! Two scenes, each the median over `runs` (3) of the whole solve (analysis once, then Newton
//! with load stepping from the undeformed state), with the Newton statistics and the time per
//! iteration (one tangent assembly, one numeric factorisation or a few conjugate-gradient steps
//! on the last factor, one force evaluation), full Newton (a factorisation every iteration)
//! against lagged-tangent corrections (`TlOptions::krylov_iterations` = 40; by default only
//! where the factor is large, as on the sensor):
//! - the cantilever of the elastica test, 100 x 100 um x 10 mm, 50 x 1 x 1 bricks, end load
//!   P L^2 / EI = 5 (tip rotation ~ 70 deg);
//! - a quarter of the clamped Si plate of the solid tests (10 x 10 mm x 100 um, x edges clamped,
//!   y edges free; symmetry planes at x, y = 5 mm), `n x n x 1` bricks, uniform pressure on the
//!   whole top face of 200 kPa (centre deflection ~ 1.5 t) and its linear deflection beside.

use std::time::Instant;

use tactfab::fe::material::DieEdge;
use tactfab::fe::solid::*;

mod support;
use support::median;

fn plane(axis: Axis3, at_um: f64) -> NodeSet {
    NodeSet::Plane { axis, at_um }
}

fn cantilever() -> SolidProblem {
    let (h, l) = (100.0, 10_000.0);
    let grid = HexGrid::new(&uniform_lines(0.0, l, 50), &[0.0, h], &[0.0, h]).expect("grid");
    let mut p = SolidProblem::new(grid, vec![Elasticity::isotropic(169e9, 0.3)]);
    p.constraints
        .push(Constraint::clamp("root", plane(Axis3::X, 0.0)));
    let ei = 169e9 * (h * 1e-6f64).powi(4) / 12.0;
    let force = 5.0 * ei / (l * 1e-6f64).powi(2);
    // The end face's consistent nodal weights of a uniform traction: (1, 4, 1) / 6 per direction.
    let w = [(0.0, 1.0 / 6.0), (0.5 * h, 4.0 / 6.0), (h, 1.0 / 6.0)];
    let mut loads = Vec::new();
    for (y, wy) in w {
        for (z, wz) in w {
            loads.push(SolidLoad::Point {
                at_um: [l, y, z],
                force_n: [0.0, 0.0, -force * wy * wz],
                snap: Snap::Exact,
            });
        }
    }
    p.load_cases.push(loads);
    p
}

fn quarter_plate(n: usize) -> SolidProblem {
    let half = 5000.0;
    let l = uniform_lines(0.0, half, n);
    let grid = HexGrid::new(&l, &l, &[0.0, 100.0]).expect("grid");
    let mut p = SolidProblem::new(grid, vec![Elasticity::silicon(DieEdge::Along110)]);
    p.constraints
        .push(Constraint::clamp("x0", plane(Axis3::X, 0.0)));
    p.constraints
        .push(Constraint::symmetry("sym-x", Axis3::X, half));
    p.constraints
        .push(Constraint::symmetry("sym-y", Axis3::Y, half));
    p.load_cases.push(vec![SolidLoad::Pressure {
        face: FaceRect {
            axis: Axis3::Z,
            at_um: 100.0,
            outward: Outward::Plus,
            from_um: [0.0, 0.0],
            to_um: [half, half],
        },
        pressure_pa: 2e5,
    }]);
    p
}

fn run(name: &str, p: &SolidProblem, probe_um: [f64; 3], runs: usize) {
    for krylov in [0, 40] {
        let opts = TlOptions {
            krylov_iterations: Some(krylov),
            ..TlOptions::default()
        };
        let mode = if krylov > 0 { "lagged" } else { "full Newton" };
        run_with(&format!("{name}, {mode}"), p, opts, probe_um, runs);
    }
}

fn run_with(name: &str, p: &SolidProblem, opts: TlOptions, probe_um: [f64; 3], runs: usize) {
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..runs {
        let t = Instant::now();
        let model = TlSolid::new(p, opts).expect("model");
        let s = model.solve(&p.load_cases[0]).expect("solve");
        times.push(t.elapsed().as_secs_f64());
        last = Some(((model.n_free_dofs(), model.factor_len()), s));
    }
    let ((dofs, factor), s) = last.expect("at least one run");
    let st = s.stats();
    let w = -s.displacement_m(probe_um).expect("probe")[2];
    let lin = -p.solve().expect("linear")[0]
        .displacement_m(probe_um)
        .expect("probe")[2];
    let total = median(times);
    println!(
        "{name}: {dofs} free dofs, {factor} factor entries, {} steps, {} iterations, {} factorisations; median {total:.3} s \
         ({:.1} ms per iteration); w = {:.3} um (linear {:.3} um)",
        st.load_steps,
        st.iterations,
        st.factorisations,
        1e3 * total / st.iterations as f64,
        w * 1e6,
        lin * 1e6
    );
}

fn main() {
    let runs: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(3);
    run(
        "cantilever 50x1x1, PL^2/EI = 5",
        &cantilever(),
        [10_000.0, 50.0, 50.0],
        runs,
    );
    for n in [10, 20] {
        run(
            &format!("quarter plate {n}x{n}x1, 200 kPa"),
            &quarter_plate(n),
            [5000.0, 5000.0, 50.0],
            runs,
        );
    }
}
