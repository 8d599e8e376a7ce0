//! Time of the 3-D tissue slab (`softness::slab3d`): `cargo run --release --example
//! slab3d_bench [runs=5] [near_mm] [far_mm] [y_mm]`; wall-clock medians (2 cores shared).
//!
//! One P(x, y) / P0(x, y) face field: paper 002's slab (30 mm along the jaw x 15 mm across x
//! 10 mm, 20 kPa, nu 0.49, squeezed 10 %) with the 2 mm lump 4 mm up at the jaw's middle
//! (quarter block) or at `y_mm` across (half block); two solves (with and without the lump).
//! Prints the peak P / P0, the mesh and the profile along the jaw through the lump.

use tactfab::softness::inclusion::{Feature, Slab};
use tactfab::softness::slab3d::{face_field, Mesh3d, Slab3d};

mod support;
use support::time;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let arg = |k: usize, d: f64| args.get(k).and_then(|a| a.parse().ok()).unwrap_or(d);
    let runs = arg(1, 5.0) as usize;
    let mesh = Mesh3d {
        near_m: arg(2, Mesh3d::DEFAULT.near_m * 1e3) * 1e-3,
        far_m: arg(3, Mesh3d::DEFAULT.far_m * 1e3) * 1e-3,
    };
    let y = arg(4, 7.5) * 1e-3;
    let lump = Feature::Lump {
        e_pa: 200e3,
        nu: 0.4,
    };
    let s = Slab3d::from_slab(&Slab::paper_002(lump), 15e-3, y);
    let (t_ms, f) = time(runs, || face_field(&s, &mesh).expect("3-D slab"));
    println!(
        "3-D slab, lump at y = {:.2} mm, near {:.3} mm, far {:.3} mm: {:?} bricks (mirrored {:?}), \
         {} unknowns; peak P / P0 {:.4} at {:?} mm, min {:.4}; median {:.0} ms over {runs} runs",
        y * 1e3,
        mesh.near_m * 1e3,
        mesh.far_m * 1e3,
        f.elements,
        f.mirrored,
        f.unknowns,
        f.peak_ratio,
        f.peak_at_m.map(|v| v * 1e3),
        f.min_ratio,
        t_ms
    );
    let yl = f.y_m.iter().position(|&v| (v - y).abs() < 1e-9);
    if let Some(j) = yl {
        let nx = f.x_m.len();
        let prof: Vec<String> = (0..nx)
            .filter(|&i| (f.x_m[i] - 15e-3).abs() < 4.1e-3)
            .map(|i| {
                format!(
                    "{:.2}:{:.4}",
                    f.x_m[i] * 1e3,
                    f.p_pa[j * nx + i] / f.p0_pa[j * nx + i]
                )
            })
            .collect();
        println!(
            "P / P0 along the jaw through the lump (x mm: ratio): {}",
            prof.join(" ")
        );
    }
}
