//! Writes the solid rung's model of one scene at one mesh level, with tactfab's answer, for the
//! independent scikit-fem code `benches/solid_peer.py` (issue 16):
//!
//! ```sh
//! cargo run --release --example solid_export -- PROCESS SCENE LEVEL OUT.json [runs=3] [--no-symmetry] [--plain-shear]
//! cargo run --release --example solid_export -- process/mis-grasper.yaml centre-1n 0 /tmp/c0.json
//! python3 benches/solid_peer.py /tmp/c0.json
//! ```
//!
//! The model is built exactly as `tactfab fe PROCESS --scene SCENE --model solid` builds that
//! level (the same `sensor::solid_mesh::build`, the same mirrors and base, graded at the teeth
//! the plate answer finds hottest), then solved `runs`
//! times (median wall time of build + factorisation + solve + read-out) with faer on all cores.
//! The peak resident memory of this process after the runs (`VmHWM`, before the export is
//! assembled) is printed and stored as `results.peak_rss_mb`.
//!
//! # Format (one JSON object, `tactfab::sensor::solid_export::SolidExport`)
//! - `nodes_um`: node positions after the node map (the {111} faces), um, nodes of active
//!   elements only; `elements`: 27 node indices per element in tactfab's order, node
//!   `a + 3 b + 9 c` at reference point (a - 1, b - 1, c - 1) in [-1, 1]^3, the reference axes
//!   along the die's x, y, z; `material`: 0 silicon, 1 PVDF, 2 base, and `materials[m].c_pa`
//!   the 6 x 6 stiffness in die axes, Voigt order xx, yy, zz, yz, xz, xy, engineering shears;
//!   `element_volume_um3`: tactfab's volume of each element (to check a reader's node order).
//! - `shear`: "tied" (the rung's default) or, with `--plain-shear`, "displacement" (the plain
//!   brick: strains from the displacement gradient). Tied: on each parallelepiped brick gamma_xz
//!   at a point is the linear interpolation in xi of its values on the lines xi = -1/sqrt 3 and
//!   +1/sqrt 3 (at the point's eta, zeta), gamma_yz likewise in eta; other bricks plain
//!   (`fe::solid::shear_tying`).
//! - `constrained`: (node, component, group) of every dof held at zero: the base's bottom face
//!   clamped, `mirror_x`/`mirror_y` planes (normal component), group names in `groups`.
//! - `pressures`: (element, face "+z" etc., pressure_pa) uniform pressures, positive pushing
//!   into the material; `points`: (node, force_n) forces.
//! - `film`: thickness, d31/d32/d33 (pC/N), the drawn axis (the film's axis 1), the layer
//!   heights. `electrodes`: name, side, area, the rectangle and its mirror images in the part
//!   solved, the polarity sign and tactfab's film elements with their image counts. Each
//!   charge is Q = sign (1/t) integral over the film under the electrode of D3 = d31 s1 + d32 s2
//!   + d33 s3 (pC), s in the film's axes.
//! - `deflection_point_um`: where -u_z is read (the load's point on the plate's mid-plane).
//! - `results`: tactfab's free dofs, factor entries, deflection (um), nine charges (pC), support
//!   forces (N, compressive, the whole die), reactions per group (K u - f, N, the part solved),
//!   peak principal stress (MPa), every node's displacement (m), the assembled load vector's
//!   nonzeros (node, component, N), median seconds and runs, peak memory (MB).

use std::path::PathBuf;

use tactfab::design::Design;
use tactfab::sensor::solid::MAX_SOLID_LEVELS;
use tactfab::sensor::solid_export::{export_scene, ExportOptions};
use tactfab::sensor::{evaluate, Accuracy, SensorGeometry};

/// The process's peak resident set (`VmHWM` of /proc/self/status), MB; NaN where unreadable.
fn peak_rss_mb() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|kb| kb.parse::<f64>().ok())
        })
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let symmetry = !args.iter().any(|a| a == "--no-symmetry");
    let tied_shear = !args.iter().any(|a| a == "--plain-shear");
    let pos: Vec<&String> = args.iter().filter(|a| !a.starts_with("--")).collect();
    if pos.len() < 4 {
        return Err(
            "usage: solid_export PROCESS SCENE LEVEL OUT.json [runs=3] [--no-symmetry] \
             [--plain-shear]"
                .into(),
        );
    }
    let level: usize = pos[2].parse()?;
    if level >= MAX_SOLID_LEVELS {
        return Err(format!(
            "level {level}: the solid rung has levels 0 to {}",
            MAX_SOLID_LEVELS - 1
        )
        .into());
    }
    let out = PathBuf::from(pos[3]);
    let runs: usize = pos.get(4).map_or(Ok(3), |s| s.parse())?;
    let (_, design) = Design::load(&PathBuf::from(pos[0]), &[])?;
    let scene = design
        .process
        .checks
        .scenes
        .iter()
        .find(|s| &s.name == pos[1])
        .ok_or_else(|| format!("no scene `{}` in {}", pos[1], pos[0]))?
        .clone();
    let g = SensorGeometry::new(&design);
    // Graded where `fe --model solid` grades: the teeth the plate answer finds hottest.
    let plate = evaluate(&g, &scene, Accuracy::new(0.01, 8))?;
    let opts = ExportOptions {
        level,
        symmetry,
        runs,
        tied_shear,
    };
    let mut e = export_scene(&g, &scene, g.base, opts, &plate.hot_teeth)?;
    let rss = peak_rss_mb();
    e.results.peak_rss_mb = rss;
    std::fs::write(&out, serde_json::to_vec(&e)?)?;
    let r = &e.results;
    println!(
        "{} level {} (h {:.0} um): {} elements, {} nodes, {} free dofs, {:.0} MB of factor; \
         median {:.3} s of {} runs, peak RSS {:.0} MB; deflection {:.4} um, charges {:?} pC; \
         wrote {}",
        e.scene,
        e.level,
        e.element_um,
        e.elements.len(),
        e.nodes_um.len(),
        r.free_dofs,
        r.factor_entries as f64 * 8e-6,
        r.seconds,
        r.runs,
        rss,
        r.deflection_at_load_um,
        r.charge_pc
            .iter()
            .map(|q| (q * 1e3).round() / 1e3)
            .collect::<Vec<_>>(),
        out.display()
    );
    Ok(())
}
