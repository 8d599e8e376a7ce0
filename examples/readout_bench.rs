//! Time of the two pieces of issue 17 items 4-5: `cargo run --release --example readout_bench
//! [runs=11]`; wall-clock medians, faer sequential as in the CLI.
//!
//! (a) The sensor plate's natural frequencies ([`plate_modes`]): the bundled design, 4 modes on
//!     1-4 mesh levels (`fe` and the traveler use 3), with the first frequency and its estimated
//!     error.
//! (b) The modal solve alone on the plain simply supported plate of the tests (40 x 24 BFS
//!     elements) against Navier: error and time.
//! (c) The read-out chain ([`study`]): sensitivities at the die centre (linear plate, tol 0.01)
//!     plus nine channels over 5 s at 1 ms, and the filter alone on 1e6 samples.

use std::f64::consts::PI;

use tactfab::design::Design;
use tactfab::fe::*;
use tactfab::process::load_str;
use tactfab::readout_chain::{high_pass, study, HistoryKind, ReadoutSpec};
use tactfab::sensor::{plate_modes, Accuracy, SensorGeometry};

mod support;
use support::time;

const PROCESS: &str = include_str!("../process/mis-grasper.yaml");

fn main() {
    faer::set_global_parallelism(faer::Par::Seq);
    let runs: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(11)
        .max(1);
    let loaded = load_str(PROCESS, "mis-grasper.yaml", &[]).expect("bundled process");
    let design = Design::new(loaded.process.clone()).expect("design");
    let g = SensorGeometry::new(&design);

    println!("(a) sensor plate, 4 modes, median of {runs}");
    for levels in 1..=4 {
        let (ms, m) = time(runs, || plate_modes(&g, 4, levels).expect("modes"));
        println!(
            "  {levels} levels: {ms:8.1} ms, {:6} dofs, f1 {:.1} Hz, est. error {}",
            m.dofs,
            m.modes[0].freq_hz,
            m.modes[0]
                .error_rel
                .map_or_else(|| "n/a".into(), |e| format!("{e:.1e}"))
        );
    }

    println!("(b) simply supported 10 x 6 mm, 100 um, 40 x 24 elements, 6 modes");
    let mut p = PlateProblem::new(
        RectMesh::uniform(10_000.0, 6_000.0, 40, 24),
        100.0,
        PlateMaterial::isotropic(169e9, 0.25),
    );
    p.support_all_edges(SupportKind::SimplySupported);
    let opts = ModalOptions {
        modes: 6,
        ..Default::default()
    };
    let (ms, m) = time(runs, || {
        natural_frequencies(&p, MassModel::plate(2329.0), opts).expect("modes")
    });
    let t: f64 = 100e-6;
    let c = (169e9 * t * t * t / (12.0 * (1.0 - 0.0625)) / (2329.0 * t)).sqrt();
    let f11 = PI * PI * (1.0 / 1e-4 + 1.0 / 36e-6) * c / (2.0 * PI);
    println!(
        "  {ms:.1} ms ({} free dofs, {} iterations, subspace {}); f11 {:.3} Hz, Navier {f11:.3} \
         Hz, error {:.1e}",
        m.free_dofs,
        m.iterations,
        m.subspace,
        m.modes[0].freq_hz,
        m.modes[0].freq_hz / f11 - 1.0
    );

    println!("(c) read-out chain");
    let spec = ReadoutSpec {
        x_um: 15_000.0,
        y_um: 7_500.0,
        contact_radius_um: 250.0,
        history: HistoryKind::HalfSine,
        force_n: 1.0,
        duration_s: None,
        dt_s: 1e-3,
        accuracy: Accuracy::new(0.01, 8),
    };
    let (ms, s) = time(runs, || {
        study(&g, &loaded.process.readout, &spec).expect("study")
    });
    println!(
        "  study (sensitivities + 9 x {} samples): {ms:.1} ms",
        s.t_s.len()
    );
    let n = 1_000_000;
    let tt: Vec<f64> = (0..n).map(|k| k as f64 * 1e-5).collect();
    let x: Vec<f64> = tt.iter().map(|t| (2.0 * PI * 5.0 * t).sin()).collect();
    let (ms, y) = time(runs, || high_pass(&tt, &x, 0.1));
    println!(
        "  high-pass alone, {n} samples: {ms:.2} ms ({:.1} ns per sample; last {:.3})",
        ms * 1e6 / n as f64,
        y[n - 1]
    );
}
