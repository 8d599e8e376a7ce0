//! A scene's load split into what the plate carries and what goes straight into a support.
//!
//! Load over a support is carried by the 300 um thick support into its PVDF film, not by the
//! plate: it reaches the support electrodes directly (thickness mode), whatever the mesh.
//!
//! A load presses the upward faces only, the tooth tops and the plate's top between the teeth's
//! bases, as the solid rung's loads do: the part of a load over a tooth's {111} sidewall carries
//! nothing and its force is spread over the rest of that load ([`sidewalls`]). So every rung
//! answers the same scene, and the plate's model error measured against the solid is the
//! model's, not the load's (0.7 % on the bundled centre load's deflection, whose contact patch
//! reaches 84 um onto a sidewall).

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

/// The teeth's {111} sidewalls in plan, each as (base, top) rectangles [x0, y0, x1, y1]: the ring
/// between them slopes, so a contact does not press it (the module's doc).
fn sidewalls(g: &SensorGeometry) -> Vec<([f64; 4], [f64; 4])> {
    let ro = g.etched.tooth_run_out_um;
    g.etched
        .tooth_tops_um
        .iter()
        .map(|t| ([t[0] - ro, t[1] - ro, t[2] + ro, t[3] + ro], *t))
        .collect()
}

/// The parts of polygon `c` over sidewalls: per sidewall that `c` reaches (its signed area over
/// the ring above `1e-9 tol_um2`), the clip to the base and its signed area, and the clip to the
/// top and its signed area (same orientation as `c`).
type WallClip = (Vec<(f64, f64)>, f64, Vec<(f64, f64)>, f64);
fn on_sidewalls(c: &[(f64, f64)], walls: &[([f64; 4], [f64; 4])], tol_um2: f64) -> Vec<WallClip> {
    walls
        .iter()
        .filter_map(|(b, t)| {
            let cb = clip_polygon(c, b[0], b[1], b[2], b[3]);
            let ab = if cb.len() < 3 { 0.0 } else { polygon_area(&cb) };
            let ct = clip_polygon(c, t[0], t[1], t[2], t[3]);
            let at = if ct.len() < 3 { 0.0 } else { polygon_area(&ct) };
            ((ab - at).abs() > 1e-9 * tol_um2).then_some((cb, ab, ct, at))
        })
        .collect()
}

/// No part of `poly` lies over a sidewall: a point or probe load may stay whole.
fn clear_of_sidewalls(poly: &[(f64, f64)], g: &SensorGeometry) -> bool {
    on_sidewalls(poly, &sidewalls(g), polygon_area(poly).abs()).is_empty()
}

/// Signed area of the sidewall parts [`on_sidewalls`] found.
fn sidewall_area(parts: &[WallClip]) -> f64 {
    parts.iter().map(|p| p.1 - p.3).sum()
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
    if inside && clear_of_sidewalls(&poly, g) {
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
    if inside && clear_of_sidewalls(&poly, g) {
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
        let pieces = line_off_sidewalls(g, y_um);
        let length: f64 = pieces.iter().map(|p| p.1 - p.0).sum();
        (
            pieces
                .iter()
                .map(|&(x0, x1)| Load::Line {
                    x0_um: x0,
                    y0_um: y_um,
                    x1_um: x1,
                    y1_um: y_um,
                    total_force_n: if pieces.len() == 1 {
                        force_n
                    } else {
                        force_n * (x1 - x0) / length
                    },
                })
                .collect(),
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

/// The pieces of the line across the die at `y_um` that do not run over a sidewall (the whole
/// line when it crosses none, or when nothing would be left).
fn line_off_sidewalls(g: &SensorGeometry, y_um: f64) -> Vec<(f64, f64)> {
    let l = g.length_um;
    let mut cuts: Vec<(f64, f64)> = Vec::new();
    for (b, t) in sidewalls(g) {
        if y_um <= b[1] || y_um >= b[3] {
            continue;
        }
        if y_um > t[1] && y_um < t[3] {
            cuts.extend([(b[0], t[0]), (t[2], b[2])]);
        } else {
            cuts.push((b[0], b[2]));
        }
    }
    let mut cuts: Vec<(f64, f64)> = cuts
        .into_iter()
        .map(|(a, c)| (a.max(0.0), c.min(l)))
        .filter(|(a, c)| c > a)
        .collect();
    cuts.sort_by(|p, q| p.0.total_cmp(&q.0));
    let mut pieces = Vec::new();
    let mut at = 0.0;
    for (a, c) in cuts {
        if a > at {
            pieces.push((at, a));
        }
        at = at.max(c);
    }
    if at < l {
        pieces.push((at, l));
    }
    if pieces.is_empty() {
        vec![(0.0, l)]
    } else {
        pieces
    }
}

/// Clips a loaded polygon (uniform pressure) against the plate and both supports. The force is
/// spread over the part on the die (a probe wider than the die touches only there), so the die
/// receives all of it; [`super::check_scene`] refuses loads with no part on the die.
fn polygon_split(poly: &[(f64, f64)], force_n: f64, g: &SensorGeometry) -> SceneLoads {
    let (py0, py1, l, w) = (g.plate_y0_um, g.plate_y1_um, g.length_um, g.width_um);
    let area = polygon_area(&clip_polygon(poly, 0.0, 0.0, l, w));
    let walls = sidewalls(g);
    let strips: Vec<_> = [
        (ElectrodeSide::Support1, 0.0, py0),
        (ElectrodeSide::Middle, py0, py1),
        (ElectrodeSide::Support2, py1, w),
    ]
    .into_iter()
    .filter_map(|(side, y0, y1)| {
        let c = clip_polygon(poly, 0.0, y0, l, y1);
        if c.len() < 3 {
            return None;
        }
        let a = polygon_area(&c);
        if a <= 1e-12 * area {
            return None;
        }
        let on_walls = on_sidewalls(&c, &walls, area.abs());
        Some((side, c, a, on_walls))
    })
    .collect();
    // The force per unit of the area pressed (the upward faces'), unless the load lies on
    // sidewalls alone (then over its whole area, as without teeth).
    let pressed: f64 = strips.iter().map(|s| s.2 - sidewall_area(&s.3)).sum();
    let by_walls = strips.iter().any(|s| !s.3.is_empty()) && pressed / area > 1e-9;
    let mut plate = Vec::new();
    let mut direct = Vec::new();
    for (side, c, a, on_walls) in strips {
        let f = if by_walls {
            force_n * (a - sidewall_area(&on_walls)) / pressed
        } else {
            force_n * a / area
        };
        if side == ElectrodeSide::Middle {
            if by_walls && !on_walls.is_empty() {
                // The whole polygon at the pressed areas' pressure, less each sidewall ring (its
                // base clip taken away, its top clip given back): the forces sum to f.
                let p = force_n / pressed;
                plate.push(Load::Polygon {
                    points_um: c,
                    total_force_n: p * a,
                });
                for (cb, ab, ct, at) in on_walls {
                    plate.push(Load::Polygon {
                        points_um: cb,
                        total_force_n: -p * ab,
                    });
                    if at.abs() > 1e-12 * area {
                        plate.push(Load::Polygon {
                            points_um: ct,
                            total_force_n: p * at,
                        });
                    }
                }
            } else {
                plate.push(Load::Polygon {
                    points_um: c,
                    total_force_n: f,
                });
            }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor::geometry::bundled as geometry;

    /// The pressure (N/um^2) the plate loads put at (x, y): each polygon's force over its area
    /// where the point lies inside it (the clipped polygons are convex).
    fn pressure_at(loads: &[Load], (x, y): (f64, f64)) -> f64 {
        let inside = |p: &[(f64, f64)]| {
            let s = polygon_area(p).signum();
            p.iter()
                .zip(p.iter().cycle().skip(1))
                .all(|(a, b)| s * ((b.0 - a.0) * (y - a.1) - (b.1 - a.1) * (x - a.0)) >= 0.0)
        };
        loads
            .iter()
            .map(|l| match l {
                Load::Polygon {
                    points_um,
                    total_force_n,
                } if inside(points_um) => total_force_n / polygon_area(points_um).abs(),
                _ => 0.0,
            })
            .sum()
    }

    /// The bundled centre load's patch (x 14.557-15.443 mm) reaches 84 um onto the sidewall of
    /// the tooth whose top ends at x = 14.5 mm: nothing presses the sidewall, the rest carries
    /// the whole force at one pressure, and the loads still sum to it.
    #[test]
    fn a_contact_presses_the_upward_faces_only() {
        let g = geometry(&[]);
        let (ro, tops) = (g.etched.tooth_run_out_um, &g.etched.tooth_tops_um);
        let top = tops
            .iter()
            .find(|t| t[0] < 15_000.0 && t[2] > 14_000.0 && t[1] < 7_500.0 && t[3] > 7_500.0)
            .expect("the tooth left of the centre");
        assert!((top[2] - 14_500.0).abs() < 1.0 && ro > 100.0);
        let s = split_point(&g, (15_000.0, 7_500.0), 1.0, 500.0);
        let total: f64 = s
            .plate
            .iter()
            .map(|l| match l {
                Load::Polygon { total_force_n, .. } => *total_force_n,
                _ => panic!("the patch over a sidewall becomes polygons: {l:?}"),
            })
            .sum();
        assert!((total - 1.0).abs() < 1e-12, "{total}");
        let h = 0.5 * std::f64::consts::PI.sqrt() * 500.0;
        let pressed = (15_000.0 + h - (top[2] + ro)) * 2.0 * h;
        let on_wall = pressure_at(&s.plate, (top[2] + 0.5 * ro, 7_500.0));
        let on_street = pressure_at(&s.plate, (15_200.0, 7_300.0));
        assert!(on_wall.abs() < 1e-15, "{on_wall}");
        assert!(((on_street - 1.0 / pressed) * pressed).abs() < 1e-12);
        // Read where the scene says, whatever carries it.
        assert_eq!(s.at_um, (15_000.0, 7_500.0));
        // Clear of the teeth (a 0.53 mm patch in the 0.71 mm street) the contact stays one point
        // load, as before.
        let clear = split_point(&g, (15_000.0, 6_000.0), 1.0, 300.0);
        assert_eq!(
            clear.plate,
            vec![Load::Point {
                x_um: 15_000.0,
                y_um: 6_000.0,
                force_n: 1.0,
                radius_um: 300.0
            }]
        );
    }

    /// A line across the die skips the sidewalls it crosses (the bundled `line-y5mm` runs over
    /// five tooth tops: ten sidewall crossings of one run-out each) and keeps its force.
    #[test]
    fn a_line_load_skips_the_sidewalls_it_crosses() {
        let g = geometry(&[]);
        let ro = g.etched.tooth_run_out_um;
        let s = split_line(&g, 5_000.0, 1.0);
        let mut length = 0.0;
        let mut force = 0.0;
        for l in &s.plate {
            let Load::Line {
                x0_um,
                x1_um,
                total_force_n,
                ..
            } = *l
            else {
                panic!("{l:?}")
            };
            length += x1_um - x0_um;
            force += total_force_n;
            assert!((total_force_n / (x1_um - x0_um) - 1.0 / (30_000.0 - 10.0 * ro)).abs() < 1e-15);
        }
        assert_eq!(s.plate.len(), 11);
        assert!((length - (30_000.0 - 10.0 * ro)).abs() < 1e-6, "{length}");
        assert!((force - 1.0).abs() < 1e-12);
    }

    /// A pressure over the whole plate takes each tooth's sidewall ring out; the corrections of
    /// mirrored teeth are each other's images, so the half model still serves.
    #[test]
    fn a_pressure_skips_every_sidewall_and_stays_symmetric() {
        let g = geometry(&[]);
        let s = split(
            &SceneLoad::Pressure {
                force_n: 2.0,
                region: None,
            },
            &g,
        );
        let total: f64 = s
            .plate
            .iter()
            .map(|l| match l {
                Load::Polygon { total_force_n, .. } => *total_force_n,
                _ => 0.0,
            })
            .sum();
        let direct: f64 = s.direct.iter().map(|d| d.force_n).sum();
        assert!((total + direct - 2.0).abs() < 1e-12);
        let tops = &g.etched.tooth_tops_um;
        let ro = g.etched.tooth_run_out_um;
        let t = tops
            .iter()
            .find(|t| t[1] > 3_000.0 && t[3] < 6_000.0)
            .expect("a tooth of the second row");
        let p_wall = pressure_at(&s.plate, (t[0] - 0.5 * ro, 0.5 * (t[1] + t[3])));
        let p_top = pressure_at(&s.plate, (0.5 * (t[0] + t[2]), 0.5 * (t[1] + t[3])));
        let p_street = pressure_at(&s.plate, (t[0] - 2.0 * ro, 0.5 * (t[1] + t[3])));
        assert!(p_top > 0.0 && ((p_top - p_street) / p_top).abs() < 1e-9);
        assert!(p_wall.abs() < 1e-9 * p_top, "{p_wall}");
        let sym = crate::sensor::symmetry::Symmetry::detect(&g, std::slice::from_ref(&s.plate));
        assert_eq!(sym.mirrors.len(), 1, "{:?}", sym.mirrors);
    }
}
