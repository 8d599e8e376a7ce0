//! Benchmark (not a timed test): build the full wafer and write it as GDS, hierarchical and
//! flattened; then time gdstk writing the same flattened polygons (benches/gdstk_write.py, via
//! a JSON export) and print medians and ratios.
//!
//! cargo run --release --example wafer_bench -- [RUNS] [--set path=value ...]

use tactfab::export::gds::GdsOptions;

mod support;
use support::time;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let runs: usize = args.first().and_then(|a| a.parse().ok()).unwrap_or(11);
    let sets: Vec<String> = args
        .windows(2)
        .filter(|w| w[0] == "--set")
        .map(|w| w[1].clone())
        .collect();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let loaded = tactfab::process::load(&root.join("process/mis-grasper.yaml"), &sets)?;
    let p = &loaded.process;
    let plan = tactfab::etch::plan(p);

    let (t_build, set) = time(runs, || tactfab::layout::build(p, &plan).expect("layout"));
    let opts = GdsOptions::default();
    let (t_hier, hier) = time(runs, || set.to_gds(&opts).expect("gds"));
    let (t_flatten, flat) = time(runs, || set.flattened());
    let (t_flat, flat_bytes) = time(runs, || flat.to_gds(&opts).expect("gds"));
    let dir = tempfile_dir()?;
    let (t_write, _) = time(runs, || {
        tactfab::export::write_atomic(&dir.join("flat.gds"), &flat_bytes).expect("write")
    });

    // The same flattened polygons for gdstk, in integer nm.
    let mut polys = Vec::new();
    let cell = &flat.cells[&flat.wafer_cell];
    for (layer, ps) in &cell.shapes {
        let g = layer.gds(&flat.layers);
        for q in ps {
            let pts: Vec<[i64; 2]> = q
                .exterior()
                .0
                .iter()
                .map(|c| [(c.x * 1000.0).round() as i64, (c.y * 1000.0).round() as i64])
                .collect();
            polys.push(serde_json::json!({"layer": g.layer, "datatype": g.datatype, "xy": pts}));
        }
    }
    let n_polys = polys.len();
    let n_vertices: usize = cell
        .shapes
        .values()
        .flatten()
        .map(|q| q.exterior().0.len())
        .sum();
    let json_path = dir.join("flat.json");
    std::fs::write(&json_path, serde_json::to_vec(&polys)?)?;
    let out = std::process::Command::new("python3")
        .arg(root.join("benches/gdstk_write.py"))
        .arg(&json_path)
        .arg(dir.join("gdstk.gds"))
        .arg(runs.to_string())
        .output()?;
    let gdstk_ms: Option<f64> = String::from_utf8_lossy(&out.stdout).lines().find_map(|l| {
        l.strip_prefix("gdstk_write_median_ms ")
            .and_then(|v| v.trim().parse().ok())
    });

    println!(
        "wafer: {} dies, {} flattened polygons ({} vertices), {} runs each",
        set.die_origins.len(),
        n_polys,
        n_vertices,
        runs
    );
    println!("layout::build                      {t_build:9.3} ms (median)");
    println!(
        "to_gds hierarchical ({:>8} B)   {t_hier:9.3} ms",
        hier.len()
    );
    println!("flatten                            {t_flatten:9.3} ms");
    println!(
        "to_gds flattened    ({:>8} B)   {t_flat:9.3} ms",
        flat_bytes.len()
    );
    println!("write_atomic flattened             {t_write:9.3} ms");
    match gdstk_ms {
        Some(g) => {
            println!("gdstk write_gds flattened          {g:9.3} ms (build from JSON excluded)");
            println!(
                "ratio tactfab(to_gds + write) / gdstk = {:.2}",
                (t_flat + t_write) / g
            );
        }
        None => println!(
            "gdstk: not measured ({}); pip install gdstk",
            String::from_utf8_lossy(&out.stderr)
                .lines()
                .last()
                .unwrap_or("")
        ),
    }
    let _ = std::fs::remove_dir_all(&dir);
    Ok(())
}

fn tempfile_dir() -> anyhow::Result<std::path::PathBuf> {
    let d = std::env::temp_dir().join(format!("tactfab-bench-{}", std::process::id()));
    std::fs::create_dir_all(&d)?;
    Ok(d)
}
