//! A scene's load split into what the plate carries and what goes straight into a support.
//!
//! Load over a support is carried by the 300 um thick support into its PVDF film, not by the
//! plate: it reaches the support electrodes directly (thickness mode), whatever the mesh.

use serde::Serialize;

use crate::fe::clip::{clip_polygon, polygon_area};
use crate::fe::loads::probe_polygon;
use crate::fe::{Load, RectUm};
use crate::process::{PressurePatch, SceneLoad};

use super::geometry::{ElectrodeSide, SensorGeometry};

/// Force delivered straight to a support over an x-range (uniformly along it).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DirectLoad {
    pub side: ElectrodeSide,
    pub x0_um: f64,
    pub x1_um: f64,
    pub force_n: f64,
}

/// The split load of one scene.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SceneLoads {
    pub plate: Vec<Load>,
    pub direct: Vec<DirectLoad>,
    pub total_force_n: f64,
    /// Where deflection "at the load" is read, and the contact patch the stress is reported for.
    pub at_um: (f64, f64),
    pub patch: RectUm,
}

impl SceneLoads {
    /// Every plate load's edges run along the mesh axes (points, rectangles, lines, probes at a
    /// multiple of 90 deg): its patch lines are worth keeping as mesh lines. A rotated probe's
    /// edges cross the elements whatever the lines, and the bounding boxes of a batch of them at
    /// nearby angles would leave sliver elements.
    pub fn axis_aligned(&self) -> bool {
        let square = |a: f64| (a / 90.0 - (a / 90.0).round()).abs() < 1e-9;
        self.plate.iter().all(|l| match l {
            Load::Probe { angle_deg, .. } => square(*angle_deg),
            Load::Polygon { points_um, .. } => points_um
                .iter()
                .zip(points_um.iter().cycle().skip(1))
                .all(|(a, b)| (a.0 - b.0).abs() < 1e-9 || (a.1 - b.1).abs() < 1e-9),
            _ => true,
        })
    }
}

/// Splits `load` between the plate and the supports by area.
pub fn split(load: &SceneLoad, g: &SensorGeometry) -> SceneLoads {
    match *load {
        SceneLoad::Point {
            x_um,
            y_um,
            force_n,
            radius_um,
        } => split_point(g, (x_um, y_um), force_n, radius_um),
        SceneLoad::Pressure { force_n, region } => {
            let r = region
                .map(|r| (r.x0_um, r.y0_um, r.x1_um, r.y1_um))
                .unwrap_or((0.0, g.plate_y0_um, g.length_um, g.plate_y1_um));
            split_pressure(g, r, force_n)
        }
        SceneLoad::Probe {
            x_um,
            y_um,
            width_um,
            height_um,
            angle_deg,
            force_n,
        } => split_probe(g, (x_um, y_um), (width_um, height_um), angle_deg, force_n),
        SceneLoad::Line { y_um, force_n } => split_line(g, y_um, force_n),
        SceneLoad::Patches { ref patches } => split_patches(g, patches),
    }
}

/// The bounding box (x0, y0, x1, y1) of the patches, forceless ones included; `None` when there
/// are none.
pub(crate) fn patches_extent_um(patches: &[PressurePatch]) -> Option<(f64, f64, f64, f64)> {
    patches.iter().map(|p| p.region).fold(None, |acc, r| {
        let (x0, y0, x1, y1) = acc.unwrap_or((f64::MAX, f64::MAX, f64::MIN, f64::MIN));
        Some((
            x0.min(r.x0_um),
            y0.min(r.y0_um),
            x1.max(r.x1_um),
            y1.max(r.y1_um),
        ))
    })
}

/// Piecewise-uniform pressure: each rectangle split as a uniform pressure of its own force
/// (patches without force are left out); read at the bounding box's centre.
fn split_patches(g: &SensorGeometry, patches: &[PressurePatch]) -> SceneLoads {
    let (py0, py1) = (g.plate_y0_um, g.plate_y1_um);
    let mut s = SceneLoads {
        plate: Vec::with_capacity(patches.len()),
        direct: Vec::new(),
        total_force_n: 0.0,
        at_um: (0.0, 0.0),
        patch: RectUm {
            x0_um: 0.0,
            y0_um: 0.0,
            x1_um: 0.0,
            y1_um: 0.0,
        },
    };
    for p in patches {
        let r = p.region;
        if p.force_n == 0.0 {
            continue;
        }
        let poly = [
            (r.x0_um, r.y0_um),
            (r.x1_um, r.y0_um),
            (r.x1_um, r.y1_um),
            (r.x0_um, r.y1_um),
        ];
        let one = polygon_split(&poly, p.force_n, g);
        s.plate.extend(one.plate);
        s.direct.extend(one.direct);
        s.total_force_n += p.force_n;
    }
    let (x0, y0, x1, y1) = patches_extent_um(patches).unwrap_or((0.0, py0, g.length_um, py1));
    s.at_um = ((x0 + x1) / 2.0, ((y0 + y1) / 2.0).clamp(py0, py1));
    s.patch = RectUm {
        x0_um: x0,
        y0_um: y0.max(py0),
        x1_um: x1,
        y1_um: y1.min(py1),
    };
    s
}

/// A point load with a contact radius: the square patch of equal area (side sqrt(pi) r, as the FE
/// point load with a radius uses), kept as a point load when the patch lies on the plate.
fn split_point(
    g: &SensorGeometry,
    (x_um, y_um): (f64, f64),
    force_n: f64,
    radius_um: f64,
) -> SceneLoads {
    let (py0, py1, l) = (g.plate_y0_um, g.plate_y1_um, g.length_um);
    // Square patch of equal area, as the FE point load with a radius uses.
    let h = 0.5 * std::f64::consts::PI.sqrt() * radius_um;
    let poly = [
        (x_um - h, y_um - h),
        (x_um + h, y_um - h),
        (x_um + h, y_um + h),
        (x_um - h, y_um + h),
    ];
    let mut s = polygon_split(&poly, force_n, g);
    let inside = y_um - h >= py0 && y_um + h <= py1 && x_um - h >= 0.0 && x_um + h <= l;
    if inside {
        s.plate = vec![Load::Point {
            x_um,
            y_um,
            force_n,
            radius_um,
        }];
    }
    // The centre may lie over a support while the patch reaches the plate: read there.
    s.at_um = (x_um.clamp(0.0, l), y_um.clamp(py0, py1));
    s.patch = RectUm {
        x0_um: x_um - h,
        y0_um: y_um - h,
        x1_um: x_um + h,
        y1_um: y_um + h,
    };
    s
}

/// A uniform pressure over the rectangle `r` = (x0, y0, x1, y1); read at its centre.
fn split_pressure(g: &SensorGeometry, r: (f64, f64, f64, f64), force_n: f64) -> SceneLoads {
    let (py0, py1) = (g.plate_y0_um, g.plate_y1_um);
    let poly = [(r.0, r.1), (r.2, r.1), (r.2, r.3), (r.0, r.3)];
    let mut s = polygon_split(&poly, force_n, g);
    s.at_um = ((r.0 + r.2) / 2.0, ((r.1 + r.3) / 2.0).clamp(py0, py1));
    s.patch = RectUm {
        x0_um: r.0,
        y0_um: r.1.max(py0),
        x1_um: r.2,
        y1_um: r.3.min(py1),
    };
    s
}

/// A rotated rectangular probe, kept whole when every corner lies on the plate; the patch is its
/// bounding box clipped to the plate.
fn split_probe(
    g: &SensorGeometry,
    (x_um, y_um): (f64, f64),
    (width_um, height_um): (f64, f64),
    angle_deg: f64,
    force_n: f64,
) -> SceneLoads {
    let (py0, py1, l) = (g.plate_y0_um, g.plate_y1_um, g.length_um);
    let poly = probe_polygon(x_um, y_um, width_um, height_um, angle_deg);
    let mut s = polygon_split(&poly, force_n, g);
    let inside = poly
        .iter()
        .all(|&(x, y)| x >= 0.0 && x <= l && y >= py0 && y <= py1);
    if inside {
        s.plate = vec![Load::Probe {
            x_um,
            y_um,
            width_um,
            height_um,
            angle_deg,
            total_force_n: force_n,
        }];
    }
    let (bx0, bx1) = poly
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), q| (a.min(q.0), b.max(q.0)));
    let (by0, by1) = poly
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), q| (a.min(q.1), b.max(q.1)));
    s.at_um = (x_um, y_um.clamp(py0, py1));
    s.patch = RectUm {
        x0_um: bx0.max(0.0),
        y0_um: by0.max(py0),
        x1_um: bx1.min(l),
        y1_um: by1.min(py1),
    };
    s
}

/// A line load across the whole length at `y_um`: on the plate when strictly between the
/// supports, else straight into the support it lies over.
fn split_line(g: &SensorGeometry, y_um: f64, force_n: f64) -> SceneLoads {
    let (py0, py1, l) = (g.plate_y0_um, g.plate_y1_um, g.length_um);
    let (plate, direct) = if y_um > py0 && y_um < py1 {
        (
            vec![Load::Line {
                x0_um: 0.0,
                y0_um: y_um,
                x1_um: l,
                y1_um: y_um,
                total_force_n: force_n,
            }],
            vec![],
        )
    } else {
        let side = if y_um <= py0 {
            ElectrodeSide::Support1
        } else {
            ElectrodeSide::Support2
        };
        (
            vec![],
            vec![DirectLoad {
                side,
                x0_um: 0.0,
                x1_um: l,
                force_n,
            }],
        )
    };
    SceneLoads {
        plate,
        direct,
        total_force_n: force_n,
        at_um: (l / 2.0, y_um.clamp(py0, py1)),
        patch: RectUm {
            x0_um: 0.0,
            y0_um: (y_um - 50.0).max(py0),
            x1_um: l,
            y1_um: (y_um + 50.0).min(py1),
        },
    }
}

/// Clips a loaded polygon (uniform pressure) against the plate and both supports. The force is
/// spread over the part on the die (a probe wider than the die touches only there), so the die
/// receives all of it; [`super::check_scene`] refuses loads with no part on the die.
fn polygon_split(poly: &[(f64, f64)], force_n: f64, g: &SensorGeometry) -> SceneLoads {
    let (py0, py1, l, w) = (g.plate_y0_um, g.plate_y1_um, g.length_um, g.width_um);
    let area = polygon_area(&clip_polygon(poly, 0.0, 0.0, l, w));
    let mut plate = Vec::new();
    let mut direct = Vec::new();
    for (side, y0, y1) in [
        (ElectrodeSide::Support1, 0.0, py0),
        (ElectrodeSide::Middle, py0, py1),
        (ElectrodeSide::Support2, py1, w),
    ] {
        let c = clip_polygon(poly, 0.0, y0, l, y1);
        if c.len() < 3 {
            continue;
        }
        let a = polygon_area(&c);
        if a <= 1e-12 * area {
            continue;
        }
        let f = force_n * a / area;
        if side == ElectrodeSide::Middle {
            plate.push(Load::Polygon {
                points_um: c,
                total_force_n: f,
            });
        } else {
            let (x0, x1) = c
                .iter()
                .fold((f64::MAX, f64::MIN), |(a, b), q| (a.min(q.0), b.max(q.0)));
            direct.push(DirectLoad {
                side,
                x0_um: x0,
                x1_um: x1,
                force_n: f,
            });
        }
    }
    SceneLoads {
        plate,
        direct,
        total_force_n: force_n,
        at_um: (0.0, 0.0),
        patch: RectUm {
            x0_um: 0.0,
            y0_um: 0.0,
            x1_um: 0.0,
            y1_um: 0.0,
        },
    }
}
