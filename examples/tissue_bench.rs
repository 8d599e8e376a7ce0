//! Time of issue 17's tissue pieces: `cargo run --release --example tissue_bench [runs=5]`;
//! wall-clock medians on the bundled design (2 cores shared).
//!
//! (a) One P / P0 profile (`tactfab tissue` defaults: 30 x 10 mm slab, 2 mm lump 4 mm up,
//!     120 x 40 Q2/P1 elements; two solves: with and without the lump).
//! (b) The die's unit responses: 30 x 15 cells of 1 mm on the linear plate (tol 0.05, 3 levels).
//! (c) The inverse on one record (two references, candidate grid 0.5 mm + compass search).
//! (e) A pulsating vessel (2 mm void 4 mm up, a cylinder across the jaw) from nothing: the
//!     slab's background, the void's grasp and its wall's unit pressure (slab solves), the grasp
//!     and the unit pressure as two patches scenes of one linear-plate batch, 20 instants of a
//!     1.2 Hz cycle, the plate's first modes (for the quasi-static check) and 5 cycles at 1 ms
//!     through the charge amplifiers: no unit responses.
//! (d) The detectability map of `tissue --detectability` (8 radii x 8 heights x 2 stiffness
//!     ratios, those that fit), on (b)'s unit responses; and (b) + (d), the whole map.
//! (f) The sphere's P / P0 from the axisymmetric scene (the fitted mesh of 60 x 40's element
//!     size, two solves), and (f') with its two coarser meshes and the Richardson estimate.
//! (g) The background and the lump's grasp as two full scenes on `--model auto` (the
//!     large-deflection plate at 3.2 N).
//! (h) The traveler's tissue section (`hidden::summary`): three slab solves and three scenes.
//!
//! `tissue_bench RUNS sphere` times (f) alone, `tissue_bench RUNS vessel` (f) and (e); `tissue_bench RUNS summary` times (h) alone (run it in the dev profile for the traveler's
//! share of the debug-mode tests).

use tactfab::design::Design;
use tactfab::hidden::cells::{unit_responses, CellGrid};
use tactfab::hidden::detect::{detectability, MapSpec};
use tactfab::hidden::field::{Background, Disturbance, Shape};
use tactfab::hidden::locate::{locate, Search, SNR_THRESHOLD};
use tactfab::hidden::scenes::cells_answers;
use tactfab::hidden::scenes::full_scenes;
use tactfab::hidden::summary::tissue_summary;
use tactfab::hidden::vessel::{vessel, vessel_fields, Pulse};
use tactfab::process::load_str;
use tactfab::sensor::{Accuracy, SensorGeometry};
use tactfab::softness::axislab::{sphere_convergence, sphere_profile};
use tactfab::softness::inclusion::{pressure_profile, Feature, Slab};

mod support;
use support::time;

const PROCESS: &str = include_str!("../process/mis-grasper.yaml");

fn main() {
    let runs: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(5)
        .max(1);
    let loaded = load_str(PROCESS, "mis-grasper.yaml", &[]).expect("bundled process");
    let design = Design::new(loaded.process).expect("design");
    let g = SensorGeometry::new(&design);
    let lump = Feature::Lump {
        e_pa: 200e3,
        nu: 0.4,
    };
    let slab = Slab {
        width_m: 30e-3,
        thickness_m: 10e-3,
        tissue_e_pa: 20e3,
        tissue_nu: 0.49,
        compression: 0.1,
        feature: lump,
        centre_x_m: 15e-3,
        centre_height_m: 4e-3,
        radius_m: 2e-3,
    };
    if std::env::args().nth(2).as_deref() == Some("summary") {
        let (ms, t) = time(runs, || {
            tissue_summary(&g, Accuracy::new(0.05, 3)).expect("summary")
        });
        println!("(h) the traveler's tissue section: {ms:.0} ms, median of {runs}: {t:?}");
        return;
    }
    let (ms, p) = time(runs, || sphere_profile(&slab, 60, 40).expect("sphere"));
    println!(
        "(f) sphere P/P0 (axisymmetric, fitted mesh of 60 x 40's size): {ms:.0} ms (peak {:.4}, \
         {} elements), median of {runs}",
        p.peak_ratio, p.elements
    );
    let (ms, c) = time(runs, || sphere_convergence(&slab, 60, 40).expect("sphere"));
    println!(
        "(f') its three meshes and Richardson: {ms:.0} ms (peaks {:?}, estimate {:?}), median of \
         {runs}",
        c.extreme, c.estimate
    );
    if std::env::args().nth(2).as_deref() == Some("sphere") {
        return;
    }
    let grid = CellGrid::new(&g, 1000.0).expect("grid");
    let acc = Accuracy::new(0.05, 3);
    let centre = (0.5 * g.length_um, 0.5 * g.width_um);
    // (e) from nothing: the slab's background and vessel, the wall's unit pressure, the two
    // plate scenes, the modes and the chain.
    let electronics = tactfab::process::ReadoutElectronics::default();
    let (ms, v) = time(runs, || {
        let bg = Background::new(&slab, 120, 40, g.length_um).expect("background");
        let cyl =
            Disturbance::new(&bg, Feature::Void, 2e-3, 4e-3, Shape::Cylinder).expect("vessel");
        vessel(
            &g,
            &grid,
            &bg,
            &cyl,
            centre,
            Pulse::default_pulse(),
            &electronics,
            acc,
        )
        .expect("vessel")
    });
    println!(
        "(e) vessel cycle from nothing: {ms:.0} ms, median of {runs} ({} instants, {} samples x {} \
         channels, plate {} levels {} dofs, f1 {:.0} Hz)",
        v.instants.len(),
        v.t_s.len(),
        v.channels.len(),
        v.grasp.levels,
        v.grasp.dofs,
        v.f1_hz
    );
    if std::env::args().nth(2).as_deref() == Some("vessel") {
        // Its pieces, one run each.
        let t = std::time::Instant::now();
        let bg = Background::new(&slab, 120, 40, g.length_um).expect("background");
        let t1 = t.elapsed().as_secs_f64() * 1e3;
        let cyl =
            Disturbance::new(&bg, Feature::Void, 2e-3, 4e-3, Shape::Cylinder).expect("vessel");
        let t2 = t.elapsed().as_secs_f64() * 1e3;
        let (grasp, unit) = vessel_fields(&bg, &cyl, &grid, centre).expect("fields");
        let t3 = t.elapsed().as_secs_f64() * 1e3;
        let plate = acc.with_model(tactfab::sensor::ModelChoice::Plate);
        let fields = [("grasp", &grasp[..]), ("unit", &unit[..])];
        let opts = tactfab::sensor::MeshOptions::default();
        cells_answers(&g, &grid, &fields, plate, opts).expect("plate");
        let t4 = t.elapsed().as_secs_f64() * 1e3;
        tactfab::sensor::plate_modes(&g, 4, 3).expect("modes");
        let t5 = t.elapsed().as_secs_f64() * 1e3;
        println!(
            "    background {t1:.0} ms, void grasp {:.0} ms, wall {:.0} ms, plate batch {:.0} ms, \
             modes {:.0} ms",
            t2 - t1,
            t3 - t2,
            t4 - t3,
            t5 - t4
        );
        return;
    }
    let (ms, p) = time(runs, || pressure_profile(&slab, 120, 40).expect("profile"));
    println!(
        "(a) P/P0 profile, 120 x 40: {ms:.0} ms (peak {:.3}), median of {runs}",
        p.peak_ratio
    );
    let (ms_ur, ur) = time(runs.min(3), || {
        unit_responses(&g, grid, acc).expect("units")
    });
    println!(
        "(b) unit responses, {} cells: {ms_ur:.0} ms ({} levels, {} dofs), median of {}",
        grid.len(),
        ur.levels,
        ur.dofs,
        runs.min(3)
    );
    let bg = Background::new(&slab, 120, 40, g.length_um).expect("background");
    let reference = Disturbance::new(&bg, lump, 2e-3, 4e-3, Shape::Sphere).expect("lump");
    let void = Disturbance::new(&bg, Feature::Void, 2e-3, 4e-3, Shape::Sphere).expect("void");
    let dv = ur.voltages_mv(&reference.cells(&bg, &grid, (12_300.0, 6_100.0)));
    let search = Search {
        step_um: 500.0,
        noise_mv: 1.0,
        threshold_snr: SNR_THRESHOLD,
    };
    let (ms, r) = time(runs, || {
        locate(&ur, &bg, &[&reference, &void], &dv, search).expect("locate")
    });
    println!(
        "(c) inverse, one record: {ms:.0} ms ({} template evaluations)",
        r.evaluations
    );
    let p0 = bg.cells(&grid);
    let dp = reference.cells(&bg, &grid, centre);
    let (b, w) = (ur.voltages_mv(&p0), {
        let d = ur.voltages_mv(&dp);
        ur.voltages_mv(&p0)
            .iter()
            .zip(&d)
            .map(|(a, b)| a + b)
            .collect::<Vec<_>>()
    });
    let (ms, f) = time(runs, || {
        full_scenes(&g, &grid, &p0, &dp, (&b, &w), acc).expect("full scenes")
    });
    println!(
        "(g) two full scenes on auto: {ms:.0} ms ({}, {} dofs)",
        f.background.rung, f.background.dofs
    );
    let (ms, _) = time(runs, || tissue_summary(&g, acc).expect("summary"));
    println!("(h) the traveler's tissue section: {ms:.0} ms");
    let spec = MapSpec {
        radii_m: [0.5, 0.75, 1.0, 1.25, 1.5, 2.0, 2.5, 3.0]
            .iter()
            .map(|r| r * 1e-3)
            .collect(),
        heights_m: [1.5, 2.5, 3.5, 4.5, 5.5, 6.5, 7.5, 8.5]
            .iter()
            .map(|h| h * 1e-3)
            .collect(),
        stiffness_ratios: vec![3.0, 10.0],
        lump_nu: 0.4,
        shape: Shape::Sphere,
        centre_um: (0.5 * g.length_um, 0.5 * g.width_um),
        noise_mv: 1.0,
        threshold_snr: SNR_THRESHOLD,
    };
    let (ms_map, m) = time(runs.min(3), || detectability(&ur, &bg, &spec).expect("map"));
    println!(
        "(d) detectability map, {} lumps ({} skipped): {ms_map:.0} ms; with (b): {:.1} s",
        m.rows.len(),
        m.skipped,
        (ms_map + ms_ur) * 1e-3
    );
}
