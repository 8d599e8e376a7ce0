//! Consistent load vectors of point, patch, pressure, line and rotated-probe loads.

use crate::fe::bfs;
use crate::fe::clip::{clip_polygon, polygon_area};
use crate::fe::dofs::element_dofs;
use crate::fe::error::{FeError, FeResult};
use crate::fe::mesh::RectMesh;
use crate::fe::problem::{Load, RectUm};

fn scatter(f: &mut [f64], mesh: &RectMesh, e: usize, fe: &[f64; 16]) {
    for (d, v) in element_dofs(mesh, e).iter().zip(fe) {
        f[*d] += v;
    }
}

/// Uniform pressure over a rectangle (um), clipped per element; returns the force actually applied
/// (N).
fn add_rect(
    f: &mut [f64],
    mesh: &RectMesh,
    x0: f64,
    y0: f64,
    x1: f64,
    y1: f64,
    pressure_pa: f64,
) -> f64 {
    let mut applied = 0.0;
    for i in RectMesh::axis_range(&mesh.x_um, x0, x1) {
        let (ex0, ex1) = (mesh.x_um[i], mesh.x_um[i + 1]);
        let (cx0, cx1) = (x0.max(ex0), x1.min(ex1));
        if cx1 <= cx0 {
            continue;
        }
        for j in RectMesh::axis_range(&mesh.y_um, y0, y1) {
            let (ey0, ey1) = (mesh.y_um[j], mesh.y_um[j + 1]);
            let (cy0, cy1) = (y0.max(ey0), y1.min(ey1));
            if cy1 <= cy0 {
                continue;
            }
            let (a, b) = ((ex1 - ex0) * 1e-6, (ey1 - ey0) * 1e-6);
            let fe = bfs::rect_load(
                (cx0 - ex0) * 1e-6,
                (cx1 - ex0) * 1e-6,
                (cy0 - ey0) * 1e-6,
                (cy1 - ey0) * 1e-6,
                a,
                b,
                pressure_pa,
            );
            applied += pressure_pa * (cx1 - cx0) * (cy1 - cy0) * 1e-12;
            scatter(f, mesh, mesh.element(i, j), &fe);
        }
    }
    applied
}

/// Corners (um) of a rotated rectangle, counter-clockwise.
pub fn probe_polygon(
    x_um: f64,
    y_um: f64,
    width_um: f64,
    height_um: f64,
    angle_deg: f64,
) -> [(f64, f64); 4] {
    let (s, c) = angle_deg.to_radians().sin_cos();
    let (hw, hh) = (0.5 * width_um, 0.5 * height_um);
    [(-hw, -hh), (hw, -hh), (hw, hh), (-hw, hh)]
        .map(|(u, v)| (x_um + c * u - s * v, y_um + s * u + c * v))
}

/// Consistent global load vector (all dofs) of one load case. Forces are positive in +w.
pub fn load_vector(mesh: &RectMesh, loads: &[Load], case: usize) -> FeResult<Vec<f64>> {
    let mut f = vec![0.0; 4 * mesh.n_nodes()];
    for (index, load) in loads.iter().enumerate() {
        add_load(&mut f, mesh, load).ok_or(FeError::LoadOutsidePlate {
            case,
            index,
            hint: "loads must lie inside the plate outline and have positive size",
        })?;
    }
    Ok(f)
}

/// Adds one load's consistent nodal forces to `f`; `None` when it lies outside the plate or has
/// no positive size.
fn add_load(f: &mut [f64], mesh: &RectMesh, load: &Load) -> Option<()> {
    match *load {
        Load::Point {
            x_um,
            y_um,
            force_n,
            radius_um,
        } => add_point(f, mesh, (x_um, y_um), force_n, radius_um),
        Load::Pressure {
            region,
            total_force_n,
        } => add_pressure(f, mesh, region, total_force_n),
        Load::Line {
            x0_um,
            y0_um,
            x1_um,
            y1_um,
            total_force_n,
        } => add_line(f, mesh, (x0_um, y0_um), (x1_um, y1_um), total_force_n),
        Load::Probe {
            x_um,
            y_um,
            width_um,
            height_um,
            angle_deg,
            total_force_n,
        } => {
            if !(width_um > 0.0 && height_um > 0.0) {
                return None;
            }
            let poly = probe_polygon(x_um, y_um, width_um, height_um, angle_deg);
            add_polygon(f, mesh, &poly, total_force_n)
        }
        Load::Polygon {
            ref points_um,
            total_force_n,
        } => {
            if points_um.len() < 3 || polygon_area(points_um).abs() <= 0.0 {
                return None;
            }
            add_polygon(f, mesh, points_um, total_force_n)
        }
    }
}

/// Both corners of a rectangle (um) lie on the mesh.
fn inside_rect(mesh: &RectMesh, x0: f64, y0: f64, x1: f64, y1: f64) -> bool {
    mesh.contains_um(x0, y0) && mesh.contains_um(x1, y1)
}

/// A point force: exact at a point (radius 0), else spread uniformly over the square of the same
/// area as the contact disc (side sqrt(pi) r).
fn add_point(
    f: &mut [f64],
    mesh: &RectMesh,
    (x_um, y_um): (f64, f64),
    force_n: f64,
    radius_um: f64,
) -> Option<()> {
    if !(radius_um >= 0.0 && x_um.is_finite() && y_um.is_finite()) {
        return None;
    }
    if radius_um == 0.0 {
        let (e, lx, ly) = mesh.locate(x_um, y_um)?;
        let (x0, y0, x1, y1) = mesh.element_bounds_um(e);
        scatter(
            f,
            mesh,
            e,
            &bfs::point_load(lx, ly, (x1 - x0) * 1e-6, (y1 - y0) * 1e-6, force_n),
        );
    } else {
        let h = 0.5 * std::f64::consts::PI.sqrt() * radius_um;
        if !inside_rect(mesh, x_um - h, y_um - h, x_um + h, y_um + h) {
            return None;
        }
        add_rect(
            f,
            mesh,
            x_um - h,
            y_um - h,
            x_um + h,
            y_um + h,
            force_n / (4.0 * h * h * 1e-12),
        );
    }
    Some(())
}

/// Uniform pressure total / area over a region, or the whole plate when none is given.
fn add_pressure(
    f: &mut [f64],
    mesh: &RectMesh,
    region: Option<RectUm>,
    total_force_n: f64,
) -> Option<()> {
    let (px0, py0, px1, py1) = mesh.bounds_um();
    let r = region.map(|r| r.normalised()).unwrap_or(RectUm {
        x0_um: px0,
        y0_um: py0,
        x1_um: px1,
        y1_um: py1,
    });
    if r.area_m2().is_nan()
        || r.area_m2() <= 0.0
        || !inside_rect(mesh, r.x0_um, r.y0_um, r.x1_um, r.y1_um)
    {
        return None;
    }
    add_rect(
        f,
        mesh,
        r.x0_um,
        r.y0_um,
        r.x1_um,
        r.y1_um,
        total_force_n / r.area_m2(),
    );
    Some(())
}

/// A uniform line load q = total / length, split at every mesh line crossed; each piece goes to
/// the element containing its midpoint.
fn add_line(
    f: &mut [f64],
    mesh: &RectMesh,
    (x0_um, y0_um): (f64, f64),
    (x1_um, y1_um): (f64, f64),
    total_force_n: f64,
) -> Option<()> {
    let rel = 1e-9;
    let len_um = ((x1_um - x0_um).powi(2) + (y1_um - y0_um).powi(2)).sqrt();
    if len_um.is_nan() || len_um <= 0.0 || !inside_rect(mesh, x0_um, y0_um, x1_um, y1_um) {
        return None;
    }
    let q = total_force_n / (len_um * 1e-6);
    // Split at every mesh line crossed; each piece goes to the element containing its
    // midpoint.
    let mut ts = vec![0.0, 1.0];
    for (axis, s0, s1) in [(&mesh.x_um, x0_um, x1_um), (&mesh.y_um, y0_um, y1_um)] {
        if (s1 - s0).abs() > 0.0 {
            ts.extend(
                axis.iter()
                    .map(|&c| (c - s0) / (s1 - s0))
                    .filter(|t| *t > 0.0 && *t < 1.0),
            );
        }
    }
    ts.sort_by(|a, b| a.partial_cmp(b).unwrap());
    for w in ts.windows(2) {
        if w[1] - w[0] <= rel {
            continue;
        }
        let at = |t: f64| (x0_um + t * (x1_um - x0_um), y0_um + t * (y1_um - y0_um));
        let mid = at(0.5 * (w[0] + w[1]));
        let (e, _, _) = mesh.locate(mid.0, mid.1)?;
        let (ex0, ey0, ex1, ey1) = mesh.element_bounds_um(e);
        let loc = |p: (f64, f64)| ((p.0 - ex0) * 1e-6, (p.1 - ey0) * 1e-6);
        let fe = bfs::line_load(
            loc(at(w[0])),
            loc(at(w[1])),
            (ex1 - ex0) * 1e-6,
            (ey1 - ey0) * 1e-6,
            q,
        );
        scatter(f, mesh, e, &fe);
    }
    Some(())
}

/// Uniform pressure over a polygon, clipped exactly against every element it overlaps; `None` when
/// part of the polygon lies outside the mesh.
fn add_polygon(
    f: &mut [f64],
    mesh: &RectMesh,
    poly: &[(f64, f64)],
    total_force_n: f64,
) -> Option<()> {
    // The element rule integrates over a counter-clockwise polygon.
    let ccw: Vec<(f64, f64)> = if polygon_area(poly) < 0.0 {
        poly.iter().rev().copied().collect()
    } else {
        poly.to_vec()
    };
    let poly = &ccw[..];
    let area_um2 = polygon_area(poly).abs();
    let p = total_force_n / (area_um2 * 1e-12);
    let (bx0, bx1) = poly
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), q| (a.min(q.0), b.max(q.0)));
    let (by0, by1) = poly
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), q| (a.min(q.1), b.max(q.1)));
    let mut clipped_area = 0.0;
    for i in RectMesh::axis_range(&mesh.x_um, bx0, bx1) {
        for j in RectMesh::axis_range(&mesh.y_um, by0, by1) {
            let e = mesh.element(i, j);
            let (ex0, ey0, ex1, ey1) = mesh.element_bounds_um(e);
            let c = clip_polygon(poly, ex0, ey0, ex1, ey1);
            if c.len() < 3 {
                continue;
            }
            let area = polygon_area(&c).abs();
            if area <= 1e-14 * area_um2 {
                continue;
            }
            clipped_area += area;
            let local: Vec<(f64, f64)> = c
                .iter()
                .map(|q| ((q.0 - ex0) * 1e-6, (q.1 - ey0) * 1e-6))
                .collect();
            let fe = bfs::polygon_load(&local, (ex1 - ex0) * 1e-6, (ey1 - ey0) * 1e-6, p);
            scatter(f, mesh, e, &fe);
        }
    }
    ((clipped_area - area_um2).abs() <= 1e-6 * area_um2).then_some(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clipping_square_by_box() {
        let sq = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
        let c = clip_polygon(&sq, 0.0, 0.0, 5.0, 5.0);
        assert!((polygon_area(&c) - 1.0).abs() < 1e-14);
        let diamond = probe_polygon(0.0, 0.0, 2.0, 2.0, 45.0);
        let c = clip_polygon(&diamond, 0.0, 0.0, 5.0, 5.0);
        assert!(
            (polygon_area(&c) - 1.0).abs() < 1e-12,
            "{}",
            polygon_area(&c)
        );
    }

    #[test]
    fn load_totals_equal_force() {
        let mesh = RectMesh::uniform(1000.0, 800.0, 7, 5);
        let loads = [
            Load::Point {
                x_um: 333.0,
                y_um: 111.0,
                force_n: 1.5,
                radius_um: 0.0,
            },
            Load::Point {
                x_um: 500.0,
                y_um: 400.0,
                force_n: 0.5,
                radius_um: 60.0,
            },
            Load::Probe {
                x_um: 500.0,
                y_um: 400.0,
                width_um: 300.0,
                height_um: 100.0,
                angle_deg: 30.0,
                total_force_n: 2.0,
            },
            Load::Line {
                x0_um: 0.0,
                y0_um: 320.0,
                x1_um: 1000.0,
                y1_um: 320.0,
                total_force_n: 0.25,
            },
            Load::Pressure {
                region: None,
                total_force_n: 0.75,
            },
        ];
        for (k, l) in loads.iter().enumerate() {
            let f = load_vector(&mesh, std::slice::from_ref(l), 0).unwrap();
            let total: f64 = f.iter().step_by(4).sum();
            let expect = [1.5, 0.5, 2.0, 0.25, 0.75][k];
            assert!((total - expect).abs() < 1e-12, "load {k}: {total}");
        }
        let bad = Load::Point {
            x_um: 1500.0,
            y_um: 0.0,
            force_n: 1.0,
            radius_um: 0.0,
        };
        assert!(matches!(
            load_vector(&mesh, &[bad], 0),
            Err(FeError::LoadOutsidePlate { .. })
        ));
    }
}
