//! Rectilinear (tensor-product) mesh built from required lines with graded refinement.

use serde::Serialize;

/// Largest size ratio aimed for between neighbouring elements.
pub const MAX_NEIGHBOUR_RATIO: f64 = 1.5;
/// Growth rate g of the size field h(d) = h0 + g d; g = 0.35 keeps neighbour ratios below 1.5 after
/// rounding.
const GROWTH: f64 = 0.35;
/// Coordinates closer than this (um) are merged.
const MERGE_TOL_UM: f64 = 1e-9;

/// A point towards which the mesh is graded (both its x and y lines are refined).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RefinePoint {
    pub x_um: f64,
    pub y_um: f64,
    pub h_min_um: f64,
}

/// Rectilinear mesh: node lines `x_um` and `y_um` (strictly increasing); element (i, j) spans
/// [x_i, x_{i+1}] x [y_j, y_{j+1}]. Node (i, j) has index j (nx + 1) + i.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RectMesh {
    pub x_um: Vec<f64>,
    pub y_um: Vec<f64>,
}

/// A size source on one axis: size h0_um at coordinate c_um.
#[derive(Debug, Clone, Copy)]
struct SizeSource {
    c_um: f64,
    h0_um: f64,
}

fn size_at(s: f64, max_um: f64, sources: &[SizeSource]) -> f64 {
    sources.iter().fold(max_um, |h, src| {
        h.min(src.h0_um + GROWTH * (s - src.c_um).abs())
    })
}

/// Subdivide [p, q] by equidistributing int ds / h(s) (composite midpoint rule, >= 16 cells per
/// smallest size).
fn subdivide(p: f64, q: f64, max_um: f64, sources: &[SizeSource], out: &mut Vec<f64>) {
    let len = q - p;
    let h_min = sources.iter().fold(max_um, |h, s| h.min(s.h0_um));
    let n_cells = ((16.0 * len / h_min).ceil() as usize).clamp(400, 4_000_000);
    let mut cum = Vec::with_capacity(n_cells + 1);
    cum.push(0.0);
    for k in 0..n_cells {
        let s = p + (k as f64 + 0.5) / n_cells as f64 * len;
        let last = *cum.last().unwrap();
        cum.push(last + len / n_cells as f64 / size_at(s, max_um, sources));
    }
    let total = cum[n_cells];
    let n = ((total - 1e-9).ceil() as usize).max(1);
    let mut cell = 0;
    for e in 1..n {
        let target = total * e as f64 / n as f64;
        while cum[cell + 1] < target {
            cell += 1;
        }
        let frac = (target - cum[cell]) / (cum[cell + 1] - cum[cell]);
        out.push(p + (cell as f64 + frac) / n_cells as f64 * len);
    }
    out.push(q);
}

/// Build one axis: required lines kept exactly, gaps subdivided to <= max_um, graded to refine
/// coordinates.
fn build_axis(lines_um: &[f64], max_um: f64, refine: &[(f64, f64)]) -> Vec<f64> {
    let mut lines: Vec<f64> = lines_um.to_vec();
    assert!(
        lines.iter().all(|v| v.is_finite()),
        "mesh lines must be finite"
    );
    lines.sort_by(|a, b| a.partial_cmp(b).unwrap());
    lines.dedup_by(|a, b| (*a - *b).abs() <= MERGE_TOL_UM);
    assert!(
        lines.len() >= 2,
        "a mesh axis needs at least two distinct lines"
    );
    let mut sources: Vec<SizeSource> = refine
        .iter()
        .filter(|(c, _)| *c >= lines[0] && *c <= *lines.last().unwrap())
        .map(|&(c, h)| SizeSource {
            c_um: c,
            h0_um: h.min(max_um),
        })
        .collect();
    // Short gaps between required lines act as size sources so that sizes grade away from them.
    for w in lines.windows(2) {
        let gap = w[1] - w[0];
        if gap < max_um {
            sources.push(SizeSource {
                c_um: w[0],
                h0_um: gap,
            });
            sources.push(SizeSource {
                c_um: w[1],
                h0_um: gap,
            });
        }
    }
    // Rounding the element count per gap can still leave a jump at a required line: add the smaller
    // neighbouring size there as a new source and rebuild (sizes only decrease, so this
    // terminates).
    for _ in 0..32 {
        let mut out = vec![lines[0]];
        for w in lines.windows(2) {
            subdivide(w[0], w[1], max_um, &sources, &mut out);
        }
        let mut added = false;
        for &line in &lines[1..lines.len() - 1] {
            let k = out
                .iter()
                .position(|&v| v == line)
                .expect("required line kept");
            let (left, right) = (out[k] - out[k - 1], out[k + 1] - out[k]);
            if left.max(right) > MAX_NEIGHBOUR_RATIO * left.min(right) {
                sources.push(SizeSource {
                    c_um: line,
                    h0_um: left.min(right),
                });
                added = true;
            }
        }
        if !added {
            return out;
        }
    }
    let mut out = vec![lines[0]];
    for w in lines.windows(2) {
        subdivide(w[0], w[1], max_um, &sources, &mut out);
    }
    out
}

impl RectMesh {
    /// Build from required lines (um): the outer lines are the plate edges; all lines are kept
    /// exactly, every gap is subdivided to elements <= `max_element_um`, with geometric grading
    /// (growth 0.35 per element length, neighbour ratio <= 1.5 where the required lines allow
    /// it) towards the refine points.
    #[track_caller]
    pub fn build(
        x_lines_um: &[f64],
        y_lines_um: &[f64],
        max_element_um: f64,
        refine: &[RefinePoint],
    ) -> Self {
        assert!(
            max_element_um > 0.0 && max_element_um.is_finite(),
            "max_element_um must be positive"
        );
        assert!(
            refine.iter().all(|r| r.h_min_um > 0.0),
            "refine h_min_um must be positive"
        );
        let rx: Vec<(f64, f64)> = refine.iter().map(|r| (r.x_um, r.h_min_um)).collect();
        let ry: Vec<(f64, f64)> = refine.iter().map(|r| (r.y_um, r.h_min_um)).collect();
        RectMesh {
            x_um: build_axis(x_lines_um, max_element_um, &rx),
            y_um: build_axis(y_lines_um, max_element_um, &ry),
        }
    }

    /// Required lines kept exactly and every gap split into equal parts no longer than
    /// `max_element_um`; no grading. Nested refinement of such a mesh keeps every line, so a
    /// sequence of them is the cheapest honest input to a three-mesh error estimate.
    #[track_caller]
    pub fn ungraded(x_lines_um: &[f64], y_lines_um: &[f64], max_element_um: f64) -> Self {
        assert!(
            max_element_um > 0.0 && max_element_um.is_finite(),
            "max_element_um must be positive"
        );
        let axis = |lines: &[f64]| {
            let mut l = lines.to_vec();
            assert!(l.iter().all(|v| v.is_finite()), "mesh lines must be finite");
            l.sort_by(f64::total_cmp);
            l.dedup_by(|a, b| (*a - *b).abs() <= MERGE_TOL_UM);
            assert!(
                l.len() >= 2,
                "a mesh axis needs at least two distinct lines"
            );
            let mut out = vec![l[0]];
            for w in l.windows(2) {
                let n = ((w[1] - w[0]) / max_element_um - 1e-9).ceil().max(1.0) as usize;
                out.extend((1..n).map(|k| w[0] + (w[1] - w[0]) * k as f64 / n as f64));
                out.push(w[1]);
            }
            out
        };
        RectMesh {
            x_um: axis(x_lines_um),
            y_um: axis(y_lines_um),
        }
    }

    /// Uniform nx x ny mesh of a lx_um x ly_um plate with its corner at the origin.
    #[track_caller]
    pub fn uniform(lx_um: f64, ly_um: f64, nx: usize, ny: usize) -> Self {
        assert!(
            nx > 0 && ny > 0 && lx_um > 0.0 && ly_um > 0.0,
            "uniform mesh needs positive size and counts"
        );
        RectMesh {
            x_um: (0..=nx).map(|i| lx_um * i as f64 / nx as f64).collect(),
            y_um: (0..=ny).map(|j| ly_um * j as f64 / ny as f64).collect(),
        }
    }

    /// Panics (at the caller) unless both axes have >= 2 finite, strictly increasing lines.
    #[track_caller]
    pub fn validate(&self) {
        for (name, ax) in [("x", &self.x_um), ("y", &self.y_um)] {
            assert!(
                ax.len() >= 2,
                "empty mesh: the {name} axis needs at least two lines"
            );
            assert!(
                ax.iter().all(|v| v.is_finite()),
                "non-finite {name} mesh line"
            );
            assert!(
                ax.windows(2).all(|w| w[1] > w[0]),
                "{name} mesh lines must be strictly increasing"
            );
        }
    }

    /// Number of elements in x.
    pub fn nx(&self) -> usize {
        self.x_um.len() - 1
    }
    /// Number of elements in y.
    pub fn ny(&self) -> usize {
        self.y_um.len() - 1
    }
    /// Total number of elements.
    pub fn n_elements(&self) -> usize {
        self.nx() * self.ny()
    }
    /// Total number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.x_um.len() * self.y_um.len()
    }
    /// Node index of node (i, j).
    pub fn node(&self, i: usize, j: usize) -> usize {
        j * self.x_um.len() + i
    }
    /// Element index of element (i, j).
    pub fn element(&self, i: usize, j: usize) -> usize {
        j * self.nx() + i
    }
    /// (i, j) of an element index.
    pub fn element_ij(&self, e: usize) -> (usize, usize) {
        (e % self.nx(), e / self.nx())
    }
    /// Global node indices of the element's corners in BFS order (0,0), (1,0), (1,1), (0,1).
    pub fn element_nodes(&self, e: usize) -> [usize; 4] {
        let (i, j) = self.element_ij(e);
        [
            self.node(i, j),
            self.node(i + 1, j),
            self.node(i + 1, j + 1),
            self.node(i, j + 1),
        ]
    }
    /// Element bounds in um: (x0, y0, x1, y1).
    pub fn element_bounds_um(&self, e: usize) -> (f64, f64, f64, f64) {
        let (i, j) = self.element_ij(e);
        (
            self.x_um[i],
            self.y_um[j],
            self.x_um[i + 1],
            self.y_um[j + 1],
        )
    }
    /// Plate bounds in um: (x0, y0, x1, y1).
    pub fn bounds_um(&self) -> (f64, f64, f64, f64) {
        (
            self.x_um[0],
            self.y_um[0],
            *self.x_um.last().unwrap(),
            *self.y_um.last().unwrap(),
        )
    }
    /// Is (x, y) inside the plate (closed, with a 1e-9 relative tolerance)?
    pub fn contains_um(&self, x_um: f64, y_um: f64) -> bool {
        let (x0, y0, x1, y1) = self.bounds_um();
        let tol = 1e-9 * (x1 - x0).max(y1 - y0);
        x_um >= x0 - tol && x_um <= x1 + tol && y_um >= y0 - tol && y_um <= y1 + tol
    }

    /// Element interval index containing s on a sorted axis (points on an interior line go to the
    /// upper interval, points on the last line to the last interval); None outside.
    pub(crate) fn locate_axis(axis: &[f64], s: f64) -> Option<usize> {
        let (lo, hi) = (axis[0], *axis.last().unwrap());
        let tol = 1e-9 * (hi - lo);
        if s < lo - tol || s > hi + tol {
            return None;
        }
        let k = axis.partition_point(|&v| v <= s);
        Some(k.saturating_sub(1).min(axis.len() - 2))
    }

    /// Element containing (x, y) in um, with its local coordinates in metres; None outside the
    /// plate.
    pub fn locate(&self, x_um: f64, y_um: f64) -> Option<(usize, f64, f64)> {
        let i = Self::locate_axis(&self.x_um, x_um)?;
        let j = Self::locate_axis(&self.y_um, y_um)?;
        let lx = (x_um.clamp(self.x_um[i], self.x_um[i + 1]) - self.x_um[i]) * 1e-6;
        let ly = (y_um.clamp(self.y_um[j], self.y_um[j + 1]) - self.y_um[j]) * 1e-6;
        Some((self.element(i, j), lx, ly))
    }

    /// Index range of elements along an axis overlapping [lo, hi] (closed).
    pub(crate) fn axis_range(axis: &[f64], lo: f64, hi: f64) -> std::ops::Range<usize> {
        let start = axis.partition_point(|&v| v <= lo).saturating_sub(1);
        let end = axis.partition_point(|&v| v < hi).min(axis.len() - 1);
        start..end.max(start)
    }

    /// Largest ratio of neighbouring element sizes along either axis.
    pub fn max_neighbour_ratio(&self) -> f64 {
        [&self.x_um, &self.y_um]
            .iter()
            .flat_map(|ax| {
                ax.windows(3).map(|w| {
                    let (h0, h1) = (w[1] - w[0], w[2] - w[1]);
                    h0.max(h1) / h0.min(h1)
                })
            })
            .fold(1.0, f64::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn required_lines_kept_and_sizes_bounded() {
        let xs = [0.0, 1000.0, 1250.0, 3000.0, 10000.0];
        let m = RectMesh::build(
            &xs,
            &[0.0, 5000.0],
            700.0,
            &[RefinePoint {
                x_um: 5000.0,
                y_um: 2500.0,
                h_min_um: 20.0,
            }],
        );
        for x in xs {
            assert!(m.x_um.contains(&x), "line {x} lost");
        }
        for w in m.x_um.windows(2) {
            assert!(w[1] - w[0] <= 700.0 + 1e-9 && w[1] > w[0]);
        }
        let near: f64 = m
            .x_um
            .windows(2)
            .filter(|w| w[0] <= 5000.0 && w[1] >= 5000.0)
            .map(|w| w[1] - w[0])
            .fold(f64::MAX, f64::min);
        assert!(near <= 25.0, "refinement not reached: {near}");
        assert!(
            m.max_neighbour_ratio() <= MAX_NEIGHBOUR_RATIO,
            "ratio {}",
            m.max_neighbour_ratio()
        );
        assert_eq!(
            m,
            RectMesh::build(
                &xs,
                &[0.0, 5000.0],
                700.0,
                &[RefinePoint {
                    x_um: 5000.0,
                    y_um: 2500.0,
                    h_min_um: 20.0
                }]
            )
        );
    }

    proptest! {
        #[test]
        fn lines_kept_sizes_bounded_grading(
            mut cuts in proptest::collection::vec(1.0f64..9999.0, 0..6),
            max_el in 100.0f64..3000.0,
            rx in 0.0f64..10000.0,
            hmin in 5.0f64..200.0,
        ) {
            cuts.push(0.0);
            cuts.push(10000.0);
            let m = RectMesh::build(&cuts, &[0.0, 1000.0], max_el, &[RefinePoint { x_um: rx, y_um: 500.0, h_min_um: hmin }]);
            for c in &cuts {
                prop_assert!(m.x_um.iter().any(|x| (x - c).abs() <= 1e-9));
            }
            for w in m.x_um.windows(2) {
                prop_assert!(w[1] > w[0] && w[1] - w[0] <= max_el * (1.0 + 1e-12));
            }
            // Grading holds wherever required lines are not themselves closer than the size field allows.
            let min_gap = { let mut c = cuts.clone(); c.sort_by(|a, b| a.partial_cmp(b).unwrap()); c.windows(2).map(|w| w[1]-w[0]).filter(|g| *g > 1e-9).fold(f64::MAX, f64::min) };
            if min_gap >= hmin.min(max_el) {
                prop_assert!(m.max_neighbour_ratio() <= MAX_NEIGHBOUR_RATIO, "ratio {}", m.max_neighbour_ratio());
            }
        }
    }
}
