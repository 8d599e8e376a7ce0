//! Benchmark (not a timed test): one tooth cell of the bundled process etched for the recipe's
//! time (8.5 h of TMAH) on a 5 um grid, median wall time of RUNS runs; prints the tooth's
//! numbers. With `--viennaps DIR` it also reads what `benches/viennaps_wet.py` wrote into DIR
//! (same mask and rates; its top-edge contour and time) and prints the comparison.
//!
//! cargo run --release --example etch_sim_bench -- [RUNS] [--grid-um 5] [--set path=value ...]
//!     [--export DIR] [--viennaps DIR]

use std::time::Instant;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

fn flag<'a>(args: &'a [String], name: &str) -> Vec<&'a String> {
    args.windows(2)
        .filter(|w| w[0] == name)
        .map(|w| &w[1])
        .collect()
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let runs: usize = args.first().and_then(|a| a.parse().ok()).unwrap_or(3);
    let sets: Vec<String> = flag(&args, "--set").into_iter().cloned().collect();
    let grid_um: f64 = flag(&args, "--grid-um")
        .first()
        .map(|g| g.parse())
        .transpose()?
        .unwrap_or(5.0);
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let loaded = tactfab::process::load(&root.join("process/mis-grasper.yaml"), &sets)?;
    let p = &loaded.process;
    let plan = tactfab::etch::plan(p);
    let masks = tactfab::layout::build(p, &plan)?;
    let mut ts = Vec::new();
    let mut sim = None;
    for _ in 0..runs {
        let t = Instant::now();
        sim = Some(tactfab::etch::sim::simulate(p, &plan, &masks, grid_um)?);
        ts.push(t.elapsed().as_secs_f64());
    }
    let sim = sim.expect("runs > 0");
    println!(
        "tooth cell {} nodes, {} steps, {:.2} h, grid {:.3} um: median {:.3} s over {runs} runs \
         (min {:.3}, max {:.3})",
        sim.nodes,
        sim.time_steps,
        sim.time_h,
        sim.grid_um,
        median(ts.clone()),
        ts.iter().copied().fold(f64::INFINITY, f64::min),
        ts.iter().copied().fold(0.0, f64::max)
    );
    println!(
        "corner deviation {:.1} um ({:?}), edge undercut {:.1} um, vs undercut square {:.1} um, \
         compensator consumed at {:?} h, floor {:.1} um, residue {:.2} um over {:.0} um2",
        sim.corner_deviation_um,
        sim.corner_shape,
        sim.edge_undercut_um,
        sim.corner_vs_undercut_square_um,
        sim.compensator_consumed_h,
        sim.floor_depth_um,
        sim.floor_residue_height_um,
        sim.floor_residue_area_um2
    );
    for f in &sim.facets {
        println!(
            "  facet {{{}}} {:.1} % (mean {:.2} deg off)",
            f.family,
            100.0 * f.area_share,
            f.mean_deviation_deg
        );
    }
    Ok(())
}
