//! Benchmark (not a timed test): one tooth cell of the bundled process etched for the recipe's
//! time (8.5 h of TMAH) on a 5 um grid, median wall time of RUNS runs; prints the tooth's
//! numbers; then the back mask's support corner likewise. With `--viennaps DIR` it also reads what `benches/viennaps_wet.py` wrote into DIR
//! (same mask and rates; its top-edge contour and time) and prints the comparison.
//!
//! cargo run --release --example etch_sim_bench -- [RUNS] [--grid-um 5] [--set path=value ...]
//!     [--export DIR] [--viennaps DIR] [--size]
//!
//! `--size` also times one compensation sizing (every geometry) on the same grid, once: it is
//! about twenty simulations.
//!
//! The peer: `--export DIR` writes DIR/cell.json (the cell's drawn polygons and the rates);
//! `python3 benches/viennaps_wet.py DIR` etches it with ViennaPS's WetEtching model and writes
//! DIR/viennaps.json; `--viennaps DIR` prints both side by side.

use std::time::Instant;

use tactfab::spelling::yaml;

mod support;
use support::median;

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
    // The back mask's support corner (the U-channel), on the grid and its double likewise.
    let mut tb = Vec::new();
    let mut back = None;
    for _ in 0..runs {
        let t = Instant::now();
        back = tactfab::etch::sim::simulate_back(p, &plan, &masks, grid_um)?;
        tb.push(t.elapsed().as_secs_f64());
    }
    if let Some(b) = &back {
        println!(
            "back corner cell {} nodes, {} steps, grid {:.3} um: median {:.3} s over {runs} runs \
             (min {:.3}, max {:.3}); floor edge {:.1} um (plan {:.1}), run-out {:.1} um (closed \
             form {:.1}), corners {}",
            b.nodes,
            b.time_steps,
            b.grid_um,
            median(tb.clone()),
            tb.iter().copied().fold(f64::INFINITY, f64::min),
            tb.iter().copied().fold(0.0, f64::max),
            b.floor_edge_y_um,
            b.plan_floor_edge_y_um,
            b.run_out_um,
            b.closed_form_run_out_um,
            b.corners
                .iter()
                .map(|c| format!(
                    "({:.1}, {:.1}) {:.1} um (extrapolated {:.1}, closed form {:.1})",
                    c.at_um[0],
                    c.at_um[1],
                    c.deviation_um.unwrap_or(f64::NAN),
                    c.error.map_or(f64::NAN, |e| e.extrapolated_um),
                    c.closed_form_um
                ))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
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
        "corner deviation {:.1} um ({}), edge undercut {:.1} um, vs undercut square {:.1} um, \
         compensator consumed at {} h, floor {:.1} um, residue {:.2} um over {:.0} um2",
        sim.corner_deviation_um,
        yaml(&sim.corner_shape),
        sim.edge_undercut_um,
        sim.corner_vs_undercut_square_um,
        sim.compensator_consumed_h
            .map_or("-".into(), |h| format!("{h:.2}")),
        sim.floor_depth_um,
        sim.floor_residue_height_um,
        sim.floor_residue_area_um2
    );
    if let Some(e) = &sim.corner_error {
        println!(
            "corner on {:.2} um {:.1} um: error {:.1} um, extrapolated {:.1} um ({}; the \
             timing includes this coarser run)",
            e.coarse_grid_um,
            e.coarse_corner_deviation_um,
            e.error_um,
            e.extrapolated_corner_deviation_um,
            yaml(&e.decision)
        );
    }
    if let Some(dir) = flag(&args, "--export").first() {
        export(dir, &sim, &masks, p, grid_um)?;
    }
    if let Some(dir) = flag(&args, "--viennaps").first() {
        compare(dir, &sim)?;
    }
    if args.iter().any(|a| a == "--size") {
        let t = Instant::now();
        let z = tactfab::etch::sim::sizing::size(p, &plan, &masks, grid_um)?;
        println!(
            "sizing: {} simulations on {:.2} um and {:.2} um in {:.2} s",
            z.evaluations,
            z.grid_um,
            z.coarse_grid_um,
            t.elapsed().as_secs_f64()
        );
        for g in &z.geometries {
            println!(
                "  {}: a {:.1} um (ratio {}), corner {:.1} um, within {}; rule {}",
                yaml(&g.geometry),
                g.sized_a_um,
                g.sized_ratio.map_or("-".into(), |r| format!("{r:.3}")),
                g.sized_corner_deviation_um,
                g.within_tolerance,
                yaml(&g.rule)
            );
        }
    }
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

/// The same mask (the cell's drawn polygons clipped to it) and rates for benches/viennaps_wet.py.
fn export(
    dir: &str,
    sim: &tactfab::etch::sim::ToothSimulation,
    masks: &tactfab::layout::MaskSet,
    p: &tactfab::process::Process,
    grid_um: f64,
) -> anyhow::Result<()> {
    use tactfab::layout::boolean::{intersection, rect};
    let cell = tactfab::etch::sim::cell::tooth_cell(masks, &p.geometry.teeth, grid_um)?;
    let [x0, y0, x1, y1] = sim.cell_um;
    let clipped = intersection(&cell.polygons, &[rect(x0, y0, x1, y1)]);
    let polys: Vec<Vec<[f64; 2]>> = clipped
        .iter()
        .map(|q| {
            q.exterior()
                .coords()
                .map(|c| [c.x - x0, c.y - y0])
                .collect()
        })
        .collect();
    let r = &sim.rates;
    let v = serde_json::json!({
        "cell_um": [x1 - x0, y1 - y0],
        "grid_um": grid_um,
        "time_h": sim.time_h,
        "tooth_top_um": sim.tooth_top_um,
        "rates_um_per_h": {
            "r100": r.r100_um_per_h, "r110": r.r110_um_per_h, "r111": r.r111_um_per_h,
            "r311": r.r311_um_per_h.unwrap_or(f64::NAN),
        },
        "polygons": polys,
        "tactfab": {
            "corner_deviation_um": sim.corner_deviation_um,
            "edge_undercut_um": sim.edge_undercut_um,
        },
    });
    std::fs::create_dir_all(dir)?;
    std::fs::write(
        std::path::Path::new(dir).join("cell.json"),
        serde_json::to_string_pretty(&v)?,
    )?;
    println!("wrote {dir}/cell.json (run benches/viennaps_wet.py {dir})");
    Ok(())
}

/// Prints ViennaPS's corner and edge beside ours, and its time.
fn compare(dir: &str, sim: &tactfab::etch::sim::ToothSimulation) -> anyhow::Result<()> {
    let text = std::fs::read_to_string(std::path::Path::new(dir).join("viennaps.json"))?;
    let v: serde_json::Value = serde_json::from_str(&text)?;
    let num = |k: &str| v[k].as_f64().unwrap_or(f64::NAN);
    println!(
        "ViennaPS {} (grid {} um): corner {:.1} um vs tactfab {:.1} um (difference {:.1}); edge \
         undercut {:.1} vs {:.1} um; wall time {:.1} s",
        v["version"].as_str().unwrap_or("?"),
        num("grid_um"),
        num("corner_deviation_um"),
        sim.corner_deviation_um,
        sim.corner_deviation_um - num("corner_deviation_um"),
        num("edge_undercut_um"),
        sim.edge_undercut_um,
        num("seconds")
    );
    Ok(())
}
