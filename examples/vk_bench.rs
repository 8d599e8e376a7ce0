//! The large-deflection rung against its closed form, error and time: `cargo run --release
//! --example vk_bench [runs]`.
//!
//! (a) A 100 um silicon strip over 2 mm, clamped and held in-plane along both edges, in
//!     cylindrical bending (mirror lines at its ends) under the pressure that would deflect the
//!     linear plate by 1.6 thicknesses: centre deflection of [`VonKarman`] on 16-128 elements
//!     across against [`clamped_strip_reference`] (Timoshenko & Woinowsky-Krieger sec. 3), with
//!     the Newton iterations and the median wall time of `runs` full solves (set-up, Newton,
//!     read-out), beside the linear plate's time and error on the same mesh.
//! (b) The bundled sensor, 1 N and 4 N at the die centre: `--model auto` (what `fe` runs),
//!     `--model plate` and `--model large-deflection` at `--tol 0.01` (levels, dofs, median
//!     time; faer sequential as in the CLI).
//! (c) The peer: a clamped, in-plane immovable 10 mm square (isotropic 169 GPa, nu 0.3, 100 um)
//!     under uniform pressure and a centre point load at linear deflections of 0.25-4
//!     thicknesses, tactfab's quarter plate (24 x 24 BFS, graded to the centre) against
//!     scikit-fem (`benches/skfem_vk.py`: Argyris w, P2 u and v, whole plate, Newton) run here
//!     with `python3` (skipped with a note when it or scikit-fem is missing); the deflections,
//!     their relative difference, and each code's time per load (tactfab: set-up and Newton from
//!     zero per load; scikit-fem: its Newton iterations for that load step from the previous
//!     one, set-up excluded).

use std::time::Instant;

use tactfab::design::Design;
use tactfab::fe::vonkarman::clamped_strip_reference;
use tactfab::fe::*;
use tactfab::process::{load_str, Limits, Scene, SceneLoad};
use tactfab::sensor::{evaluate, Accuracy, ModelChoice, SensorGeometry};

mod support;
use support::median;

const SPAN_UM: f64 = 2000.0;
const SQUARE_UM: f64 = 10_000.0;
const WIDTH_UM: f64 = 500.0;
const T_UM: f64 = 100.0;
const PROCESS: &str = include_str!("../process/mis-grasper.yaml");

fn strip(n: usize, pressure_pa: f64) -> PlateProblem {
    let mesh = RectMesh {
        x_um: vec![0.0, 0.5 * WIDTH_UM, WIDTH_UM],
        y_um: (0..=n).map(|k| SPAN_UM * k as f64 / n as f64).collect(),
    };
    let mut p = PlateProblem::new(mesh, T_UM, PlateMaterial::silicon(DieEdge::Along110));
    for (g, at) in [("y0", 0.0), ("y1", SPAN_UM)] {
        p.supports.push(LineSupport {
            group: g.into(),
            kind: SupportKind::Clamped,
            along: Axis::X,
            at_um: at,
            from_um: 0.0,
            to_um: WIDTH_UM,
        });
    }
    for at in [0.0, WIDTH_UM] {
        p.supports.push(LineSupport {
            group: "mirror".into(),
            kind: SupportKind::Symmetry,
            along: Axis::Y,
            at_um: at,
            from_um: 0.0,
            to_um: SPAN_UM,
        });
    }
    p.load_cases.push(vec![Load::Pressure {
        region: None,
        total_force_n: pressure_pa * SPAN_UM * WIDTH_UM * 1e-12,
    }]);
    p
}

fn main() {
    let runs: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(5)
        .max(1);
    // As the CLI runs: faer sequential, the ladder's own threads for levels and scenes.
    faer::set_global_parallelism(faer::Par::Seq);
    let mat = PlateMaterial::silicon(DieEdge::Along110);
    let t = T_UM * 1e-6;
    let (d, a) = (mat.q22_pa * t.powi(3) / 12.0, mat.q22_pa * t);
    let l = SPAN_UM * 1e-6;
    let q = 1.6 * t * 384.0 * d / l.powi(4);
    let (w_ref, n_ref) = clamped_strip_reference(q, l, d, a);
    let w_lin_exact = q * l.powi(4) / (384.0 * d);
    println!(
        "(a) strip, w/t = {:.2} (linear {:.2}), membrane force {:.0} N/m; {runs} runs, medians",
        w_ref / t,
        w_lin_exact / t,
        n_ref
    );
    println!("  elements  dofs  newton  vk_ms  vk_error  linear_ms  linear_error");
    for n in [16, 32, 64, 128] {
        let p = strip(n, q);
        let centre = |s: &PlateSolution| s.deflection_m(0.5 * WIDTH_UM, 0.5 * SPAN_UM);
        let (mut vk_ms, mut lin_ms) = (Vec::new(), Vec::new());
        let (mut w, mut w_lin, mut its, mut dofs) = (0.0, 0.0, 0, 0);
        for _ in 0..runs {
            let t0 = Instant::now();
            let vk = VonKarman::new(&p, NonlinearOptions::default()).expect("strip");
            let (s, st) = vk.solve(&p.load_cases[0]).expect("converges");
            vk_ms.push(t0.elapsed().as_secs_f64() * 1e3);
            (w, its, dofs) = (centre(&s), st.iterations, vk.n_free_dofs());
            let t0 = Instant::now();
            let s = p.solve().expect("linear").remove(0);
            lin_ms.push(t0.elapsed().as_secs_f64() * 1e3);
            w_lin = centre(&s);
        }
        println!(
            "  {:>8}  {:>4}  {:>6}  {:>5.2}  {:>8.2e}  {:>9.3}  {:>12.2e}",
            2 * n,
            dofs,
            its,
            median(vk_ms),
            (w - w_ref).abs() / w_ref,
            median(lin_ms),
            (w_lin - w_ref).abs() / w_ref
        );
    }

    let p = load_str(PROCESS, "mis-grasper.yaml", &[])
        .expect("valid process")
        .process;
    let g = SensorGeometry::new(&Design::new(p).expect("design"));
    for force_n in [1.0, 4.0] {
        let scene = Scene {
            name: format!("centre-{force_n}n"),
            load: SceneLoad::Point {
                x_um: g.length_um / 2.0,
                y_um: g.width_um / 2.0,
                force_n,
                radius_um: 500.0,
            },
            limits: Limits::default(),
        };
        println!("(b) sensor, {force_n} N at the centre, tol 1 %; {runs} runs, medians");
        for model in [
            ModelChoice::Auto,
            ModelChoice::Plate,
            ModelChoice::LargeDeflection,
        ] {
            let mut ms = Vec::new();
            let mut last = None;
            for _ in 0..runs {
                let t0 = Instant::now();
                let r =
                    evaluate(&g, &scene, Accuracy::new(0.01, 8).with_model(model)).expect("solves");
                ms.push(t0.elapsed().as_secs_f64() * 1e3);
                last = Some(r);
            }
            let r = last.expect("one run");
            let part =
                |v: Option<f64>| v.map_or_else(|| "not estimated".into(), |e| format!("{e:.1e}"));
            println!(
                "  {:<16} {} levels, {} dofs, {} Newton iterations, {:.0} ms, deflection {:.2} \
                 um, M2 {:.1} pC, error: discretisation {} + model {}",
                model.as_str(),
                r.model.levels,
                r.model.dofs,
                r.model.newton_iterations.unwrap_or(0),
                median(ms),
                r.deflection_at_load_um,
                r.electrodes[4].charge_pc,
                part(r.error.discretisation),
                part(r.error.model)
            );
        }
    }
    peer(runs);
}

/// (c): scikit-fem's RESULT lines against tactfab's quarter plate, load by load.
fn peer(runs: usize) {
    let max_refinement = std::env::var("SKFEM_VK_REFINEMENT").unwrap_or_else(|_| "4".into());
    println!(
        "(c) clamped immovable square against scikit-fem (benches/skfem_vk.py {max_refinement}); \
         {runs} runs of tactfab, medians"
    );
    let out = match std::process::Command::new("python3")
        .arg(concat!(env!("CARGO_MANIFEST_DIR"), "/benches/skfem_vk.py"))
        .arg(&max_refinement)
        .output()
    {
        Ok(o) if o.status.success() => String::from_utf8_lossy(&o.stdout).into_owned(),
        Ok(o) => {
            println!(
                "  scikit-fem did not run (pip install -r benches/requirements.txt):\n{}",
                String::from_utf8_lossy(&o.stderr)
            );
            return;
        }
        Err(e) => {
            println!("  python3 did not start: {e}");
            return;
        }
    };
    let (t, a) = (T_UM * 1e-6, SQUARE_UM * 1e-6);
    let d = 169e9 * t.powi(3) / (12.0 * (1.0 - 0.09));
    let p = quarter_square(SQUARE_UM, T_UM, PlateMaterial::isotropic(169e9, 0.3), 24);
    println!(
        "  case      wlin/t  tactfab_w/t  skfem_w/t  rel_diff  tactfab_ms  skfem_ms  skfem_dofs"
    );
    for line in out.lines().filter_map(|l| l.strip_prefix("RESULT ")) {
        let field = |k: &str| -> String {
            line.split_whitespace()
                .find_map(|kv| kv.strip_prefix(&format!("{k}=")))
                .unwrap_or("")
                .to_string()
        };
        let num = |k: &str| field(k).parse::<f64>().unwrap_or(f64::NAN);
        let (pressure, wlin) = (field("case") == "pressure", num("wlin_over_t"));
        let load = if pressure {
            Load::Pressure {
                region: None,
                total_force_n: wlin * t * d / (0.00126532 * a.powi(4)) * a * a / 4.0,
            }
        } else {
            Load::Point {
                x_um: SQUARE_UM / 2.0,
                y_um: SQUARE_UM / 2.0,
                force_n: wlin * t * d / (0.0056120 * a * a) / 4.0,
                radius_um: 0.0,
            }
        };
        let mut ms = Vec::new();
        let mut w = 0.0;
        for _ in 0..runs {
            let t0 = Instant::now();
            let vk = VonKarman::new(&p, NonlinearOptions::default()).expect("quarter");
            let (s, _) = vk.solve(std::slice::from_ref(&load)).expect("converges");
            ms.push(t0.elapsed().as_secs_f64() * 1e3);
            w = s.deflection_m(SQUARE_UM / 2.0, SQUARE_UM / 2.0) / t;
        }
        let peer_w = num("w_over_t");
        println!(
            "  {:<8} {:>7} {:>12.6} {:>10.6} {:>9.1e} {:>11.1} {:>9.0} {:>11}",
            field("case"),
            wlin,
            w,
            peer_w,
            (w - peer_w) / peer_w,
            median(ms),
            num("seconds") * 1e3,
            field("dofs")
        );
    }
}
