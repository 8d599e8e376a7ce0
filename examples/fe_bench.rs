//! Error against time, one command: `cargo run --release --example fe_bench [plate_runs]
//! [sensor_runs]`.
//!
//! (a) tactfab on the plain plate: clamped 10 x 10 mm square, isotropic E = 169 GPa, nu = 0.3,
//!     t = 100 um, 1 N at the centre, error against alpha_P = 0.0056120 (fe-validation.md).
//! (b) the full sensor (process/mis-grasper.yaml: nine electrodes, checkered teeth, orthotropic
//! Si),     1 N point load of radius 0.5 mm at the die centre (half the plate solved, and the whole
//! plate     for comparison) and off the centre, the three-mesh error estimate per tolerance.
//! (c) `python3 benches/skfem_plate.py` (scikit-fem, Morley) on the same plate as (a), and the time
//! ratio.
//!
//! Times are wall-clock medians of full runs (mesh + assembly + factorisation + solve + read-out);
//! faer runs sequentially (`Par::Seq`) unless FE_PAR is set.

use std::process::Command;
use std::time::Instant;

use tactfab::design::Design;
use tactfab::fe::*;
use tactfab::process::{load_str, Limits, Scene, SceneLoad};
use tactfab::sensor::{evaluate_many_with, Accuracy, MeshOptions, SensorGeometry};

mod support;
use support::median;

const ALPHA_P: f64 = 0.0056120;
const SIDE_UM: f64 = 10_000.0;
const E_PA: f64 = 169e9;
const NU: f64 = 0.3;
const THICKNESS_UM: f64 = 100.0;
const FORCE_N: f64 = 1.0;
const PROCESS: &str = include_str!("../process/mis-grasper.yaml");
const SENSOR_TOLS: [f64; 4] = [0.05, 0.02, 0.01, 0.005];
/// Levels 0..=7 split the 2 mm coarse mesh up to 16 times (125 um); enough for the tolerances
/// above.
const SENSOR_MAX_LEVELS: usize = 8;

/// One plain-plate solve; returns (alpha, elements, free dofs).
fn plate_once(mesh: RectMesh) -> (f64, usize, usize) {
    let m = PlateMaterial::isotropic(E_PA, NU);
    let d_nm = m.bending_stiffness(THICKNESS_UM * 1e-6).d11_nm;
    let n_el = mesh.n_elements();
    let mut p = PlateProblem::new(mesh, THICKNESS_UM, m);
    p.support_all_edges(SupportKind::Clamped);
    let c = SIDE_UM / 2.0;
    p.load_cases.push(vec![Load::Point {
        x_um: c,
        y_um: c,
        force_n: FORCE_N,
        radius_um: 0.0,
    }]);
    let f = Factorised::new(&p).expect("factorise");
    let s = f.solve(&p.load_cases).expect("solve");
    let w_m = s[0].deflection_m(c, c);
    (
        w_m * d_nm / (FORCE_N * (SIDE_UM * 1e-6).powi(2)),
        n_el,
        f.n_free_dofs(),
    )
}

type MeshCase = (String, Box<dyn Fn() -> RectMesh>);

fn plate_cases() -> Vec<MeshCase> {
    let mut cases: Vec<MeshCase> = Vec::new();
    for n in [4usize, 8, 12, 16, 24, 32, 48, 64] {
        cases.push((
            format!("uniform {n}x{n}"),
            Box::new(move || RectMesh::uniform(SIDE_UM, SIDE_UM, n, n)),
        ));
    }
    // Graded towards the load: the point-load error lives near the centre.
    for (max_el_um, h_min_um) in [
        (2500.0, 1250.0),
        (2500.0, 500.0),
        (2000.0, 250.0),
        (1250.0, 125.0),
        (1000.0, 60.0),
        (700.0, 30.0),
    ] {
        cases.push((
            format!("graded max {max_el_um} min {h_min_um}"),
            Box::new(move || {
                let c = SIDE_UM / 2.0;
                RectMesh::build(
                    &[0.0, c, SIDE_UM],
                    &[0.0, c, SIDE_UM],
                    max_el_um,
                    &[RefinePoint {
                        x_um: c,
                        y_um: c,
                        h_min_um,
                    }],
                )
            }),
        ));
    }
    cases
}

/// (a): prints the table; returns (time_ms, rel_err) per mesh.
fn bench_plate(runs: usize) -> Vec<(f64, f64)> {
    let m = PlateMaterial::isotropic(E_PA, NU);
    println!("== (a) tactfab, plain plate (BFS bicubic rectangles), median of {runs} runs");
    println!(
        "clamped square {} mm, isotropic E = {E_PA:.4e} Pa, nu = {NU}, t = {THICKNESS_UM} um, D = \
         {:.6e} N m, P = {FORCE_N} N at the centre, alpha_ref = {ALPHA_P}",
        SIDE_UM / 1e3,
        m.bending_stiffness(THICKNESS_UM * 1e-6).d11_nm
    );
    println!(
        "{:<28} {:>8} {:>8} {:>11} {:>12} {:>10}",
        "mesh", "elements", "dofs", "time_ms", "alpha", "rel_err"
    );
    let mut out = Vec::new();
    for (name, mk) in plate_cases() {
        let mut times_ms = Vec::with_capacity(runs);
        let mut last = (0.0, 0, 0);
        for _ in 0..runs {
            let t0 = Instant::now();
            last = plate_once(mk());
            times_ms.push(t0.elapsed().as_secs_f64() * 1e3);
        }
        let (alpha, el, dofs) = last;
        let (t_ms, err) = (median(times_ms), (alpha - ALPHA_P).abs() / ALPHA_P);
        println!("{name:<28} {el:>8} {dofs:>8} {t_ms:>11.3} {alpha:>12.8} {err:>10.2e}");
        out.push((t_ms, err));
    }
    out
}

/// Smallest median time of a mesh whose error is at most `target`.
fn time_to(rows: &[(f64, f64)], target: f64) -> Option<f64> {
    rows.iter()
        .filter(|r| r.1 <= target)
        .map(|r| r.0)
        .min_by(f64::total_cmp)
}

/// (b): the full sensor, per tolerance: the centre load (mirror-symmetric: half the plate is
/// solved), the same with symmetry off, and an off-centre load (no symmetry); both loads also on
/// graded meshes.
fn bench_sensor(runs: usize) {
    let p = load_str(PROCESS, "mis-grasper.yaml", &[])
        .expect("valid process")
        .process;
    let g = SensorGeometry::new(&Design::new(p).expect("design"));
    let (xc, yc) = (g.length_um / 2.0, (g.plate_y0_um + g.plate_y1_um) / 2.0);
    println!();
    println!(
        "== (b) tactfab, full sensor (process/mis-grasper.yaml: {} electrodes, {} teeth, plate \
         {:.0} um), {FORCE_N} N point load r = 0.5 mm, median of {runs} runs",
        g.electrodes.len(),
        g.teeth.len(),
        g.plate_thickness_um,
    );
    println!(
        "error = the three-mesh estimate of evaluate() (worst of deflection and the nine \
         charges); solve_ms = evaluate()'s own sum of level times; wall_ms includes the rest of \
         evaluate()"
    );
    let mesh_with = |symmetry: bool, graded: bool| MeshOptions {
        symmetry,
        graded,
        stations: true,
    };
    for (label, (x_um, y_um), mesh) in [
        ("centre", (xc, yc), MeshOptions::default()),
        ("centre, --graded", (xc, yc), mesh_with(true, true)),
        ("centre, --no-symmetry", (xc, yc), mesh_with(false, false)),
        ("off-centre", (10_000.0, 5_000.0), MeshOptions::default()),
        (
            "off-centre, --graded",
            (10_000.0, 5_000.0),
            mesh_with(true, true),
        ),
    ] {
        let scene = Scene {
            name: label.into(),
            load: SceneLoad::Point {
                x_um,
                y_um,
                force_n: FORCE_N,
                radius_um: 500.0,
            },
            limits: Limits::default(),
        };
        println!();
        println!(
            "-- {label}: load at ({:.1}, {:.1}) mm",
            x_um / 1e3,
            y_um / 1e3
        );
        println!(
            "{:>6} {:>7} {:>9} {:>9} {:>9} {:>10} {:>9}  model",
            "tol", "levels", "elements", "dofs", "solve_ms", "wall_ms", "est_err"
        );
        let mut finest = None;
        for tol in SENSOR_TOLS {
            let (mut solve_ms, mut wall_ms) = (Vec::new(), Vec::new());
            let mut last = None;
            for _ in 0..runs {
                let t0 = Instant::now();
                let r = evaluate_many_with(
                    &g,
                    std::slice::from_ref(&scene),
                    Accuracy::new(tol, SENSOR_MAX_LEVELS),
                    mesh,
                )
                .expect("sensor solves")
                .remove(0);
                wall_ms.push(t0.elapsed().as_secs_f64() * 1e3);
                solve_ms.push(r.solve_ms);
                last = Some(r);
            }
            let r = last.expect("at least one run");
            let est = r
                .error_estimate
                .map_or("-".to_string(), |e| format!("{e:.2e}"));
            let mark = if r.converged { "" } else { "  NOT CONVERGED" };
            println!(
                "{tol:>6} {:>7} {:>9} {:>9} {:>9.1} {:>10.1} {est:>9}  {}{mark}",
                r.model.levels,
                r.model.elements,
                r.model.dofs,
                median(solve_ms),
                median(wall_ms),
                r.model.symmetry.as_deref().unwrap_or("whole plate"),
            );
            finest = Some(r);
        }
        if let Some(r) = finest {
            println!(
                "per level, last run at tol = {}:",
                SENSOR_TOLS[SENSOR_TOLS.len() - 1]
            );
            println!(
                "{:>6} {:>10} {:>9} {:>9} {:>10} {:>9} {:>6}",
                "level", "h_um", "elements", "dofs", "time_ms", "est_err", "order"
            );
            for (i, l) in r.convergence.iter().enumerate() {
                let est = l
                    .error_estimate
                    .map_or("-".to_string(), |e| format!("{e:.2e}"));
                let order = l
                    .observed_order
                    .map_or("-".to_string(), |p| format!("{p:.2}"));
                println!(
                    "{i:>6} {:>10.1} {:>9} {:>9} {:>10.1} {est:>9} {order:>6}",
                    l.max_element_um, l.elements, l.dofs, l.time_ms
                );
            }
        }
    }
}

/// (c): runs the scikit-fem script; returns its (total_ms, asm_solve_ms) at 1 % and 0.1 %.
fn bench_skfem(repeats: usize) -> Option<[Option<(f64, f64)>; 2]> {
    println!();
    println!("== (c) scikit-fem on the same plate (benches/skfem_plate.py {repeats})");
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/benches/skfem_plate.py");
    let out = match Command::new("python3")
        .arg(script)
        .arg(repeats.to_string())
        .output()
    {
        Ok(o) => o,
        Err(e) => {
            println!("NOTE: could not run python3 ({e}); skipping the scikit-fem comparison");
            return None;
        }
    };
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        println!(
            "NOTE: benches/skfem_plate.py failed (is scikit-fem installed? pip install -r \
             benches/requirements.txt); skipping:\n{}",
            err.trim_end()
        );
        return None;
    }
    let text = String::from_utf8_lossy(&out.stdout);
    let mut res = [None, None];
    for line in text.lines() {
        if let Some(rest) = line.strip_prefix("RESULT ") {
            let field = |k: &str| {
                rest.split_whitespace()
                    .find_map(|f| f.strip_prefix(k))
                    .and_then(|v| v.parse::<f64>().ok())
            };
            let slot = if field("target=") == Some(0.01) { 0 } else { 1 };
            res[slot] = field("total_ms=").zip(field("asm_solve_ms="));
        } else {
            println!("{line}");
        }
    }
    Some(res)
}

fn main() {
    let mut args = std::env::args().skip(1).map(|s| s.parse::<usize>().ok());
    let plate_runs = args.next().flatten().unwrap_or(21);
    let sensor_runs = args.next().flatten().unwrap_or(3);
    if std::env::var("FE_PAR").is_err() {
        faer::set_global_parallelism(faer::Par::Seq);
    }
    let rows = bench_plate(plate_runs);
    let ours = [time_to(&rows, 0.01), time_to(&rows, 0.001)];
    for (target, t) in [0.01, 0.001].iter().zip(ours) {
        match t {
            Some(t) => println!(
                "tactfab smallest time to {:.1} %: {t:.3} ms",
                target * 100.0
            ),
            None => println!("tactfab: {:.1} % not reached", target * 100.0),
        }
    }
    bench_sensor(sensor_runs);
    let Some(sk) = bench_skfem(5) else { return };
    println!();
    println!(
        "== time ratio tactfab / scikit-fem: same plate, same D, same 1 N centre load, same \
         alpha_ref (medians; a mesh slower than 10 s in Python is a single run)"
    );
    for (i, target) in [0.01, 0.001].iter().enumerate() {
        match (ours[i], sk[i]) {
            (Some(t), Some((total, asm))) => println!(
                "{:>4.1} %: tactfab {t:.3} ms, scikit-fem {total:.1} ms total ({asm:.1} ms \
                 assemble+solve): ratio {:.2e} (vs assemble+solve {:.2e}; scikit-fem/tactfab = \
                 {:.0}x)",
                target * 100.0,
                t / total,
                t / asm,
                total / t
            ),
            _ => println!("{:>4.1} %: not reached by one of the codes", target * 100.0),
        }
    }
}
