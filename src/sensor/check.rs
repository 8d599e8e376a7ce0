//! Whether a scene can be answered: every number finite, sizes positive, and the whole loaded
//! area (contact patch, probe footprint, pressure region, line) on the die. File scenes and
//! ad-hoc loads (`fe --point`, `--pressure`) pass this one check before anything is solved, so
//! a load that reaches off the die is refused instead of losing part of its force.

use crate::fe::clip::{clip_polygon, polygon_area};
use crate::fe::loads::probe_polygon;
use crate::fe::FeError;
use crate::finding::{At, Finding, SceneCode};
use crate::process::{Scene, SceneLoad};

use super::geometry::SensorGeometry;

/// Why a scene was not solved.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SensorError {
    #[error("scene `{scene}`: {problem}\n  hint: {hint}")]
    Scene {
        scene: String,
        problem: String,
        hint: &'static str,
    },
    #[error(
        "{loads} loads on a mesh of {dofs} dofs (level {level}) would hold {} solution values, \
         above the limit of {MAX_SOLUTION_VALUES}\n  hint: solve fewer loads at once (coarser \
         grid steps), or fewer mesh levels (--max-levels, a looser --tol)",
        loads * dofs
    )]
    TooLarge {
        loads: usize,
        dofs: usize,
        level: usize,
    },
    #[error("finite-element solve failed: {0}")]
    Fe(#[from] FeError),
}

/// Most solution values (loads x dofs) one mesh level may hold: 1e8 doubles, 0.8 GB, refused
/// before anything is allocated.
pub const MAX_SOLUTION_VALUES: usize = 100_000_000;

/// Slack on the die edges (um): a patch drawn exactly to the edge is on the die.
const EDGE_SLACK_UM: f64 = 1e-6;

/// The footprint of a load: the polygon whose force the sensor must receive in full.
pub(super) fn footprint(load: &SceneLoad, g: &SensorGeometry) -> Vec<(f64, f64)> {
    match *load {
        SceneLoad::Point {
            x_um,
            y_um,
            radius_um,
            ..
        } => {
            // The square patch of equal area the split and the FE use.
            let h = 0.5 * std::f64::consts::PI.sqrt() * radius_um;
            vec![
                (x_um - h, y_um - h),
                (x_um + h, y_um - h),
                (x_um + h, y_um + h),
                (x_um - h, y_um + h),
            ]
        }
        SceneLoad::Pressure { region, .. } => match region {
            Some(r) => vec![(r.x0_um, r.y0_um), (r.x1_um, r.y1_um)],
            None => vec![(0.0, g.plate_y0_um), (g.length_um, g.plate_y1_um)],
        },
        SceneLoad::Probe {
            x_um,
            y_um,
            width_um,
            height_um,
            angle_deg,
            ..
        } => probe_polygon(x_um, y_um, width_um, height_um, angle_deg).to_vec(),
        SceneLoad::Line { y_um, .. } => vec![(0.0, y_um), (g.length_um, y_um)],
        // Every corner: each patch must lie on the die.
        SceneLoad::Patches { ref patches } => patches
            .iter()
            .flat_map(|p| {
                [
                    (p.region.x0_um, p.region.y0_um),
                    (p.region.x1_um, p.region.y1_um),
                ]
            })
            .collect(),
    }
}

/// Named values of a load.
type Named = Vec<(&'static str, f64)>;

/// Every number of the load that must be finite, and the sizes that must be positive.
fn numbers(load: &SceneLoad) -> (Named, Named) {
    match *load {
        SceneLoad::Point {
            x_um,
            y_um,
            force_n,
            radius_um,
        } => (
            vec![("x_um", x_um), ("y_um", y_um), ("force_n", force_n)],
            vec![("radius_um", radius_um)],
        ),
        SceneLoad::Pressure { force_n, region } => {
            let mut v = vec![("force_n", force_n)];
            if let Some(r) = region {
                v.extend([
                    ("region.x0_um", r.x0_um),
                    ("region.y0_um", r.y0_um),
                    ("region.x1_um", r.x1_um),
                    ("region.y1_um", r.y1_um),
                ]);
            }
            let sizes = region
                .map(|r| {
                    vec![
                        ("region width (x1_um - x0_um)", r.x1_um - r.x0_um),
                        ("region height (y1_um - y0_um)", r.y1_um - r.y0_um),
                    ]
                })
                .unwrap_or_default();
            (v, sizes)
        }
        SceneLoad::Probe {
            x_um,
            y_um,
            width_um,
            height_um,
            angle_deg,
            force_n,
        } => (
            vec![
                ("x_um", x_um),
                ("y_um", y_um),
                ("angle_deg", angle_deg),
                ("force_n", force_n),
            ],
            vec![("width_um", width_um), ("height_um", height_um)],
        ),
        SceneLoad::Line { y_um, force_n } => (vec![("y_um", y_um), ("force_n", force_n)], vec![]),
        SceneLoad::Patches { ref patches } => {
            let mut v = Vec::with_capacity(5 * patches.len());
            let mut sizes = Vec::with_capacity(2 * patches.len());
            for p in patches {
                let r = p.region;
                v.extend([
                    ("patches[].force_n", p.force_n),
                    ("patches[].region.x0_um", r.x0_um),
                    ("patches[].region.y0_um", r.y0_um),
                    ("patches[].region.x1_um", r.x1_um),
                    ("patches[].region.y1_um", r.y1_um),
                ]);
                sizes.extend([
                    ("patches[] region width (x1_um - x0_um)", r.x1_um - r.x0_um),
                    ("patches[] region height (y1_um - y0_um)", r.y1_um - r.y0_um),
                ]);
            }
            (v, sizes)
        }
    }
}

/// Most rectangles of a [`SceneLoad::Patches`] load \[choice\]: the tissue study's 5,000 cells.
pub const MAX_PATCHES: usize = 5_000;

/// PROBE_OVERHANG when a probe reaches beyond the die (its force then spreads over the rest).
pub fn overhang(scene: &Scene, g: &SensorGeometry) -> Option<Finding> {
    let SceneLoad::Probe { .. } = scene.load else {
        return None;
    };
    let poly = footprint(&scene.load, g);
    let whole = polygon_area(&poly);
    let on_die = polygon_area(&clip_polygon(&poly, 0.0, 0.0, g.length_um, g.width_um));
    (on_die < whole * (1.0 - 1e-9)).then(|| {
        Finding::warning(
            SceneCode::ProbeOverhang,
            format!(
                "{:.1} % of the probe's footprint is off the die; its force is spread over the \
                 part on the die",
                100.0 * (1.0 - on_die / whole)
            ),
        )
        .at(At::Scene(scene.name.clone()))
    })
}

/// Checks that `scene` can be answered on `g`.
pub fn check_scene(scene: &Scene, g: &SensorGeometry) -> Result<(), SensorError> {
    let err = |problem: String, hint| SensorError::Scene {
        scene: scene.name.clone(),
        problem,
        hint,
    };
    if g.plate_thickness_um.is_nan() || g.plate_thickness_um <= 0.0 {
        return Err(err(
            format!(
                "the recipe leaves a {:.1} um plate: it etches through the wafer",
                g.plate_thickness_um
            ),
            "fix the etch depths or times (`tactfab check` lists DEPTH_EXCEEDS_WAFER)",
        ));
    }
    if let SceneLoad::Patches { ref patches } = scene.load {
        if patches.is_empty() || patches.len() > MAX_PATCHES {
            return Err(err(
                format!("{} pressure patches", patches.len()),
                "between 1 and 5,000 patches",
            ));
        }
    }
    let (finite, sizes) = numbers(&scene.load);
    for (name, v) in finite.iter().chain(&sizes) {
        if !v.is_finite() {
            return Err(err(
                format!("{name} = {v} is not a finite number"),
                "give a number",
            ));
        }
    }
    for (name, v) in sizes {
        if v <= 0.0 {
            return Err(err(
                format!("{name} = {v} um must be positive"),
                "a contact, probe or region needs an area",
            ));
        }
    }
    let (l, w) = (g.length_um, g.width_um);
    let poly = footprint(&scene.load, g);
    if let SceneLoad::Probe { .. } = scene.load {
        // A rigid probe wider than the die touches the die only: its force spreads over the
        // part on the die (reported as PROBE_OVERHANG), but some part must be there.
        let on_die = clip_polygon(&poly, 0.0, 0.0, l, w);
        if on_die.len() < 3 || polygon_area(&on_die) <= 0.0 {
            return Err(err(
                format!("the probe does not touch the {l} x {w} um die"),
                "move the probe onto the die; coordinates are um from the die corner",
            ));
        }
        return Ok(());
    }
    let off = poly.into_iter().find(|&(x, y)| {
        x < -EDGE_SLACK_UM || x > l + EDGE_SLACK_UM || y < -EDGE_SLACK_UM || y > w + EDGE_SLACK_UM
    });
    if let Some((x, y)) = off {
        return Err(err(
            format!(
                "the loaded area reaches ({x:.1}, {y:.1}) um, off the {l} x {w} um die: part of \
                 the force would go nowhere"
            ),
            "move the load (or shrink its contact) so that all of it is on the die; \
             coordinates are um from the die corner (mm in `--point`)",
        ));
    }
    Ok(())
}
