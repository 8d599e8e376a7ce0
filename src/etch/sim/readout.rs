//! What is read off an etched surface: where the top edge lies along a ray of nodes, the
//! contour of a level in plan view, the floor and the facets.

use super::level_set::Grid;

/// Distance (um) from node `from` along the node ray `step` (e.g. (1, 1): the diagonal) to the
/// first place where `field` falls from > `level` to <= `level`, linear between nodes; `None`
/// when it does not within the grid.
#[track_caller]
pub fn crossing_along(
    field: &[f64],
    g: &Grid,
    from: (usize, usize),
    step: (isize, isize),
    level: f64,
) -> Option<f64> {
    assert_eq!(field.len(), g.len(), "field does not fit the grid");
    let at = |k: isize| {
        let (i, j) = (from.0 as isize + k * step.0, from.1 as isize + k * step.1);
        (i >= 0 && j >= 0 && (i as usize) < g.nx && (j as usize) < g.ny)
            .then(|| field[j as usize * g.nx + i as usize])
    };
    let unit = ((step.0 as f64 * g.dx_um).powi(2) + (step.1 as f64 * g.dy_um).powi(2)).sqrt();
    let mut k = 0;
    let mut a = at(0)?;
    while let Some(b) = at(k + 1) {
        if a > level && b <= level {
            return Some(unit * (k as f64 + (a - level) / (a - b)));
        }
        a = b;
        k += 1;
    }
    None
}

/// Line segments (x0, y0, x1, y1 in um) of the `level` contour of a node field by marching
/// squares (each cell's crossings joined; the saddle case joined one way, which only matters
/// within a cell).
#[track_caller]
pub fn contour(field: &[f64], g: &Grid, level: f64) -> Vec<[f64; 4]> {
    assert_eq!(field.len(), g.len(), "field does not fit the grid");
    let v = |i: usize, j: usize| field[j * g.nx + i] - level;
    let mut out = Vec::new();
    for j in 0..g.ny.saturating_sub(1) {
        for i in 0..g.nx.saturating_sub(1) {
            // Corners counter-clockwise from (i, j).
            let c = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
            let mut pts = Vec::with_capacity(4);
            for e in 0..4 {
                let (p, q) = (c[e], c[(e + 1) % 4]);
                let (a, b) = (v(p.0, p.1), v(q.0, q.1));
                if (a > 0.0) != (b > 0.0) {
                    let t = a / (a - b);
                    let x = g.x_um(p.0) + t * (g.x_um(q.0) - g.x_um(p.0));
                    let y = g.y_um(p.1) + t * (g.y_um(q.1) - g.y_um(p.1));
                    pts.push((x, y));
                }
            }
            for pair in pts.chunks_exact(2) {
                out.push([pair[0].0, pair[0].1, pair[1].0, pair[1].1]);
            }
        }
    }
    out
}

/// Bilinear value of a node field at (x, y) (clamped into the grid).
pub fn sample(field: &[f64], g: &Grid, x_um: f64, y_um: f64) -> f64 {
    let fx = ((x_um - g.x0_um) / g.dx_um).clamp(0.0, (g.nx - 1) as f64);
    let fy = ((y_um - g.y0_um) / g.dy_um).clamp(0.0, (g.ny - 1) as f64);
    let (i, j) = ((fx as usize).min(g.nx - 2), (fy as usize).min(g.ny - 2));
    let (tx, ty) = (fx - i as f64, fy - j as f64);
    let v = |a: usize, b: usize| field[b * g.nx + a];
    (1.0 - ty) * ((1.0 - tx) * v(i, j) + tx * v(i + 1, j))
        + ty * ((1.0 - tx) * v(i, j + 1) + tx * v(i + 1, j + 1))
}

/// Distance from (x, y) along the unit direction `dir` to the first place where the bilinear
/// field falls from > `level` to <= `level` (sampled at a quarter cell, then linear), within
/// `max_um`.
pub fn crossing_on_ray(
    field: &[f64],
    g: &Grid,
    from_um: (f64, f64),
    dir: (f64, f64),
    level: f64,
    max_um: f64,
) -> Option<f64> {
    let ds = 0.25 * g.dx_um.min(g.dy_um);
    let at = |s: f64| sample(field, g, from_um.0 + s * dir.0, from_um.1 + s * dir.1);
    let n = (max_um / ds).floor() as usize;
    let mut a = at(0.0);
    for k in 1..=n {
        let b = at(k as f64 * ds);
        if a > level && b <= level {
            return Some(ds * ((k - 1) as f64 + (a - level) / (a - b)));
        }
        a = b;
    }
    None
}

/// The crystal plane families a facet is named after, as sorted |Miller indices|.
pub const FAMILIES: [(&str, [f64; 3]); 8] = [
    ("100", [1.0, 0.0, 0.0]),
    ("110", [1.0, 1.0, 0.0]),
    ("111", [1.0, 1.0, 1.0]),
    ("211", [2.0, 1.0, 1.0]),
    ("311", [3.0, 1.0, 1.0]),
    ("411", [4.0, 1.0, 1.0]),
    ("221", [2.0, 2.0, 1.0]),
    ("331", [3.0, 3.0, 1.0]),
];

/// The family nearest a crystal-axis normal and the angle to it (deg): by the rearrangement
/// inequality the closest member of a family is the one sorted like the normal.
pub fn nearest_family(n: [f64; 3]) -> (&'static str, f64) {
    let mut a = [n[0].abs(), n[1].abs(), n[2].abs()];
    a.sort_by(|x, y| y.total_cmp(x));
    let la = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    let mut best = ("", f64::INFINITY);
    for (name, f) in FAMILIES {
        let lf = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
        let c = ((a[0] * f[0] + a[1] * f[1] + a[2] * f[2]) / (la * lf)).clamp(-1.0, 1.0);
        let ang = c.acos().to_degrees();
        if ang < best.1 {
            best = (name, ang);
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossing_and_contour_of_a_plane() {
        let g = Grid::covering(0.0, 0.0, 10.0, 10.0, 1.0).unwrap();
        // f = 5.5 - x: zero at x = 5.5 on every row.
        let f: Vec<f64> = (0..g.len()).map(|k| 5.5 - g.x_um(k % g.nx)).collect();
        let d = crossing_along(&f, &g, (0, 3), (1, 0), 0.0).unwrap();
        assert!((d - 5.5).abs() < 1e-12);
        // Along the diagonal the plane is met at x = 5.5 too: distance 5.5 sqrt 2.
        let d = crossing_along(&f, &g, (0, 0), (1, 1), 0.0).unwrap();
        assert!((d - 5.5 * 2f64.sqrt()).abs() < 1e-12);
        assert!(crossing_along(&f, &g, (0, 0), (0, 1), 0.0).is_none());
        let c = contour(&f, &g, 0.0);
        assert_eq!(c.len(), 10);
        assert!(c
            .iter()
            .all(|s| (s[0] - 5.5).abs() < 1e-12 && (s[2] - 5.5).abs() < 1e-12));
    }
}
