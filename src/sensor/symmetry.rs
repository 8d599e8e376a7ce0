//! Mirror symmetry of the sensor and its scenes: which half (or quarter) of the plate to solve.
//!
//! The plate is clamped along both etched channel walls and free at its ends, so its outline and
//! supports are symmetric about y = (y0 + y1) / 2 and about x = length / 2; the material is
//! orthotropic in die axes (no Q16, Q26), so it is too. What can break a mirror is the thickness
//! map (teeth) and the loads. When every scene is symmetric, the solution is (uniqueness of the
//! linear problem), and one half with a symmetry line gives it at about a third of the cost
//! (Cholesky flops grow as n^1.5 on a 2-D mesh). Readouts are taken on the mirrored whole-plate
//! field, so electrodes need not be symmetric.

use crate::fe::clip::{clip_polygon, polygon_area};
use crate::fe::loads::probe_polygon;
use crate::fe::problem::Axis as FeAxis;
use crate::fe::{Load, PlateSolution, RectUm, ThicknessRegion};

use super::geometry::SensorGeometry;

/// Coordinates closer than this (um) are the same: a nanometre, the mask grid.
const TOL_UM: f64 = 1e-3;

/// A mirror line of the problem: along x at y = `at_um`, or along y at x = `at_um`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mirror {
    pub along: FeAxis,
    pub at_um: f64,
}

/// True unless the supports' sections ([`super::support_section::SupportSections`]) break the
/// mirror: across the span both supports must carry their teeth at the same x, along it each
/// support's teeth must mirror about the die's middle.
fn supports_symmetric(g: &SensorGeometry, m: Mirror) -> bool {
    let Some(Ok(s)) = &g.support_section else {
        return true;
    };
    let same = |a: &[[f64; 2]], b: &[[f64; 2]]| {
        a.len() == b.len()
            && a.iter()
                .zip(b)
                .all(|(p, q)| (p[0] - q[0]).abs() < TOL_UM && (p[1] - q[1]).abs() < TOL_UM)
    };
    let [one, two] = &s.teeth_x_um;
    match m.along {
        FeAxis::X => same(one, two),
        FeAxis::Y => [one, two].iter().all(|v| {
            let mut mirrored: Vec<[f64; 2]> = v
                .iter()
                .map(|i| [2.0 * m.at_um - i[1], 2.0 * m.at_um - i[0]])
                .collect();
            mirrored.sort_by(|a, b| a[0].total_cmp(&b[0]));
            same(v, &mirrored)
        }),
    }
}

impl Mirror {
    fn image(&self, (x, y): (f64, f64)) -> (f64, f64) {
        match self.along {
            FeAxis::X => (x, 2.0 * self.at_um - y),
            FeAxis::Y => (2.0 * self.at_um - x, y),
        }
    }

    /// Distance of a point from the line.
    fn off(&self, (x, y): (f64, f64)) -> f64 {
        match self.along {
            FeAxis::X => (y - self.at_um).abs(),
            FeAxis::Y => (x - self.at_um).abs(),
        }
    }

    fn symmetric_points(&self, pts: &[(f64, f64)]) -> bool {
        self.maps_onto(pts, pts)
    }

    /// Every point of `from` has its image among `to`.
    fn maps_onto(&self, from: &[(f64, f64)], to: &[(f64, f64)]) -> bool {
        let near = |a: (f64, f64), b: (f64, f64)| {
            (a.0 - b.0).abs() <= TOL_UM && (a.1 - b.1).abs() <= TOL_UM
        };
        from.iter()
            .all(|&p| to.iter().any(|&q| near(self.image(p), q)))
    }

    fn symmetric_region(&self, r: &ThicknessRegion, all: &[ThicknessRegion]) -> bool {
        let corners = |r: &ThicknessRegion| [(r.x0_um, r.y0_um), (r.x1_um, r.y1_um)];
        let [a, b] = corners(r);
        let (a, b) = (self.image(a), self.image(b));
        let (lo, hi) = ((a.0.min(b.0), a.1.min(b.1)), (a.0.max(b.0), a.1.max(b.1)));
        all.iter().any(|s| {
            let [p, q] = corners(s);
            (p.0 - lo.0).abs() <= TOL_UM
                && (p.1 - lo.1).abs() <= TOL_UM
                && (q.0 - hi.0).abs() <= TOL_UM
                && (q.1 - hi.1).abs() <= TOL_UM
                && (s.thickness_um - r.thickness_um).abs() <= 1e-9 * r.thickness_um
        })
    }

    /// Whether another load of the same case is `load`'s mirror image with the same force (the
    /// sidewall corrections of a pair of mirrored teeth, [`super::scene`]): polygons and lines.
    fn has_image(&self, load: &Load, case: &[Load]) -> bool {
        let shape = |l: &Load| -> Option<(Vec<(f64, f64)>, f64)> {
            match l {
                Load::Polygon {
                    points_um,
                    total_force_n,
                } => Some((points_um.clone(), *total_force_n)),
                Load::Line {
                    x0_um,
                    y0_um,
                    x1_um,
                    y1_um,
                    total_force_n,
                } => Some((vec![(*x0_um, *y0_um), (*x1_um, *y1_um)], *total_force_n)),
                _ => None,
            }
        };
        let Some((pts, f)) = shape(load) else {
            return false;
        };
        case.iter().filter_map(shape).any(|(q, g)| {
            (g - f).abs() <= 1e-9 * f.abs() && q.len() == pts.len() && self.maps_onto(&pts, &q)
        })
    }

    /// Whether a plate load is its own mirror image.
    fn symmetric_load(&self, load: &Load) -> bool {
        match *load {
            Load::Point { x_um, y_um, .. } => self.off((x_um, y_um)) <= TOL_UM,
            Load::Pressure { region: None, .. } => true,
            Load::Pressure {
                region: Some(r), ..
            } => self.symmetric_points(&rect_points(&r)),
            Load::Line {
                x0_um,
                y0_um,
                x1_um,
                y1_um,
                ..
            } => self.symmetric_points(&[(x0_um, y0_um), (x1_um, y1_um)]),
            Load::Probe {
                x_um,
                y_um,
                width_um,
                height_um,
                angle_deg,
                ..
            } => self.symmetric_points(&probe_polygon(x_um, y_um, width_um, height_um, angle_deg)),
            Load::Polygon { ref points_um, .. } => self.symmetric_points(points_um),
        }
    }
}

fn rect_points(r: &RectUm) -> [(f64, f64); 4] {
    [
        (r.x0_um, r.y0_um),
        (r.x1_um, r.y0_um),
        (r.x1_um, r.y1_um),
        (r.x0_um, r.y1_um),
    ]
}

/// The part of the plate solved and the mirror lines that bound it (none, one or two).
#[derive(Debug, Clone, PartialEq)]
pub struct Symmetry {
    pub mirrors: Vec<Mirror>,
    /// (x0, x1, y0, y1) of the part meshed.
    pub domain_um: (f64, f64, f64, f64),
    /// (x0, x1, y0, y1) of the whole plate.
    pub plate_um: (f64, f64, f64, f64),
}

impl Symmetry {
    /// The whole plate, no mirror.
    pub fn none(g: &SensorGeometry) -> Self {
        let plate = (0.0, g.length_um, g.plate_y0_um, g.plate_y1_um);
        Symmetry {
            mirrors: Vec::new(),
            domain_um: plate,
            plate_um: plate,
        }
    }

    /// Every mirror line under which the teeth and every plate load of every case are symmetric;
    /// the part solved is the lower (and left) part.
    pub fn detect(g: &SensorGeometry, cases: &[Vec<Load>]) -> Self {
        let mut s = Symmetry::none(g);
        let candidates = [
            Mirror {
                along: FeAxis::X,
                at_um: 0.5 * (g.plate_y0_um + g.plate_y1_um),
            },
            Mirror {
                along: FeAxis::Y,
                at_um: 0.5 * g.length_um,
            },
        ];
        for m in candidates {
            let teeth = g.teeth.iter().all(|t| m.symmetric_region(t, &g.teeth));
            let loads = cases.iter().all(|case| {
                case.iter()
                    .all(|l| m.symmetric_load(l) || m.has_image(l, case))
            });
            if teeth && loads && supports_symmetric(g, m) {
                match m.along {
                    FeAxis::X => s.domain_um.3 = m.at_um,
                    FeAxis::Y => s.domain_um.1 = m.at_um,
                }
                s.mirrors.push(m);
            }
        }
        s
    }

    /// "half, mirror y = 7.5 mm" or similar; None for the whole plate.
    pub fn describe(&self) -> Option<String> {
        let lines: Vec<String> = self
            .mirrors
            .iter()
            .map(|m| match m.along {
                FeAxis::X => format!("y = {:.3} mm", m.at_um * 1e-3),
                FeAxis::Y => format!("x = {:.3} mm", m.at_um * 1e-3),
            })
            .collect();
        match lines.len() {
            0 => None,
            1 => Some(format!("half, mirror {}", lines[0])),
            _ => Some(format!("quarter, mirrors {}", lines.join(" and "))),
        }
    }

    /// A line coordinate list of one axis folded into the part solved: lines beyond a mirror are
    /// replaced by their images, and the mirror line itself is added, so the mirrored mesh keeps
    /// every feature line of both halves.
    /// `x_lines`: the list holds x coordinates (lines along y).
    pub fn fold(&self, x_lines: bool, lines: Vec<f64>) -> Vec<f64> {
        let axis = if x_lines { FeAxis::Y } else { FeAxis::X };
        let Some(m) = self.mirrors.iter().find(|m| m.along == axis) else {
            return lines;
        };
        let mut out: Vec<f64> = lines
            .into_iter()
            .map(|v| if v > m.at_um { 2.0 * m.at_um - v } else { v })
            .collect();
        out.push(m.at_um);
        out
    }

    /// One load case restricted to the part solved: each load clipped to it, carrying the force
    /// of the part it keeps (a half, or a quarter, of a symmetric load).
    pub fn restrict(&self, loads: &[Load]) -> Vec<Load> {
        if self.mirrors.is_empty() {
            return loads.to_vec();
        }
        let (x0, x1, y0, y1) = self.domain_um;
        let share = |p: &[(f64, f64)], f: f64| {
            let c = clip_polygon(p, x0, y0, x1, y1);
            let a = polygon_area(p).abs();
            Load::Polygon {
                total_force_n: f * polygon_area(&c).abs() / a,
                points_um: c,
            }
        };
        loads
            .iter()
            .map(|l| match *l {
                Load::Point {
                    x_um,
                    y_um,
                    force_n,
                    radius_um,
                } if radius_um == 0.0 => {
                    // On every mirror line (it is symmetric): each halving keeps half of it.
                    Load::Point {
                        x_um,
                        y_um,
                        force_n: force_n / f64::powi(2.0, self.mirrors.len() as i32),
                        radius_um,
                    }
                }
                Load::Point {
                    x_um,
                    y_um,
                    force_n,
                    radius_um,
                } => {
                    let h = 0.5 * std::f64::consts::PI.sqrt() * radius_um;
                    share(
                        &[
                            (x_um - h, y_um - h),
                            (x_um + h, y_um - h),
                            (x_um + h, y_um + h),
                            (x_um - h, y_um + h),
                        ],
                        force_n,
                    )
                }
                Load::Pressure {
                    region,
                    total_force_n,
                } => {
                    let (px0, px1, py0, py1) = self.plate_um;
                    let r = region
                        .unwrap_or(RectUm {
                            x0_um: px0,
                            y0_um: py0,
                            x1_um: px1,
                            y1_um: py1,
                        })
                        .normalised();
                    share(&rect_points(&r), total_force_n)
                }
                Load::Probe {
                    x_um,
                    y_um,
                    width_um,
                    height_um,
                    angle_deg,
                    total_force_n,
                } => share(
                    &probe_polygon(x_um, y_um, width_um, height_um, angle_deg),
                    total_force_n,
                ),
                Load::Polygon {
                    ref points_um,
                    total_force_n,
                } => share(points_um, total_force_n),
                Load::Line {
                    x0_um: a0,
                    y0_um: b0,
                    x1_um: a1,
                    y1_um: b1,
                    total_force_n,
                } => {
                    // Clip the segment (Liang-Barsky on the box); a segment lying on a mirror line
                    // keeps its length but carries half: it is shared by both halves.
                    let (t0, t1) = clip_segment((a0, b0), (a1, b1), (x0, x1, y0, y1));
                    let on_lines = self
                        .mirrors
                        .iter()
                        .filter(|m| m.off((a0, b0)) <= TOL_UM && m.off((a1, b1)) <= TOL_UM)
                        .count();
                    let f = total_force_n * (t1 - t0) / f64::powi(2.0, on_lines as i32);
                    let at = |t: f64| (a0 + t * (a1 - a0), b0 + t * (b1 - b0));
                    let ((p0x, p0y), (p1x, p1y)) = (at(t0), at(t1));
                    Load::Line {
                        x0_um: p0x,
                        y0_um: p0y,
                        x1_um: p1x,
                        y1_um: p1y,
                        total_force_n: f,
                    }
                }
            })
            // A load of a mirrored pair may lie wholly in the other part: its image is here.
            .filter(|l| match l {
                Load::Polygon { points_um, .. } => {
                    points_um.len() >= 3 && polygon_area(points_um) != 0.0
                }
                Load::Line {
                    x0_um,
                    y0_um,
                    x1_um,
                    y1_um,
                    ..
                } => x0_um != x1_um || y0_um != y1_um,
                _ => true,
            })
            .collect()
    }

    /// The whole-plate solution from the solution of the part: mirrored about each line, the
    /// image of a support's reactions going to the support it faces.
    pub fn expand(&self, s: PlateSolution) -> PlateSolution {
        self.mirrors.iter().rev().fold(s, |s, m| {
            s.mirrored(m.along, m.at_um, |g| match (m.along, g) {
                (FeAxis::X, "support1") => "support2".to_string(),
                (FeAxis::X, "support2") => "support1".to_string(),
                _ => g.to_string(),
            })
        })
    }
}

/// Parameter range [t0, t1] of the segment p + t (q - p) inside the box (Liang & Barsky 1984).
fn clip_segment(
    p: (f64, f64),
    q: (f64, f64),
    (x0, x1, y0, y1): (f64, f64, f64, f64),
) -> (f64, f64) {
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    let (dx, dy) = (q.0 - p.0, q.1 - p.1);
    for (d, lo, hi, s) in [(dx, x0, x1, p.0), (dy, y0, y1, p.1)] {
        if d.abs() < 1e-300 {
            continue;
        }
        let (a, b) = ((lo - s) / d, (hi - s) / d);
        t0 = t0.max(a.min(b));
        t1 = t1.min(a.max(b));
    }
    (t0, t1.max(t0))
}
