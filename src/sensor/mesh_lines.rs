//! The mesh sequence of the sensor plate: lines of the coarsest mesh (every feature line, and with
//! [`MeshOptions::graded`] geometric grading towards the loads and tooth corners), and their
//! uniform subdivision per level.

use crate::fe::RectMesh;

use super::edge_section::station_lines_um;
use super::geometry::SensorGeometry;
use super::scene::SceneLoads;
use super::symmetry::Symmetry;

/// Largest element of the coarsest mesh; level k splits every interval of it into
/// [`SUBDIVISIONS`]`[k]` parts. Feature lines, not this size, set
/// most of the coarsest mesh: 2 mm gives about 430 elements on the bundled design.
pub(super) const COARSE_ELEMENT_UM: f64 = 2000.0;
/// Subdivisions of the coarsest mesh per level: ratios 2, 1.5, 4/3, 1.5, 4/3, ... The third mesh
/// has 9x, not 16x, the coarsest's elements, so the three-mesh estimate costs about half as
/// much as with halving: centre load on the bundled design (half model), deflection estimated at
/// 0.73 % (0.60 % true; 0.83 % worst over the charges) on 8,800 dofs, against 0.57 % (0.43 % true)
/// on 15,400 dofs with subdivisions 1, 2, 4. "True" is against the Richardson extrapolation of
/// subdivisions 6-8-12 (35.983 um, benches/README.md).
pub const SUBDIVISIONS: [usize; 10] = [1, 2, 3, 4, 6, 8, 12, 16, 24, 32];
/// Feature lines closer than this are merged (the tooth edge moves to the electrode edge).
const MIN_LINE_GAP_UM: f64 = 250.0;
/// A rotated probe's bounding-box line closer than this to a kept line is dropped: a batch of
/// probes at nearly the same angle (the orientation study's inverse re-runs) would otherwise leave
/// elements a few um wide whose conditioning stalls Newton and breaks the Cholesky factorisation.
const ROTATED_LINE_GAP_UM: f64 = 50.0;
/// A tooth-base station's line closer than this to a kept line is dropped: the station is then
/// on that line, near enough, and a sliver element would cost conditioning for nothing.
const STATION_LINE_GAP_UM: f64 = 10.0;
/// Graded meshes: spacing ratio of successive grading lines (first spacing, then x2, x4, ... until
/// the coarse element size).
const GRADING_GROWTH: f64 = 2.0;
/// Graded meshes: first spacing next to a tooth edge. Of 250 and 500 um, 500 um gave the lower
/// error for the same solve time on the bundled design.
const TOOTH_FIRST_SPACING_UM: f64 = 500.0;
/// Graded meshes: first spacing next to a load-patch edge, as a fraction of the patch side.
const LOAD_FIRST_SPACING: f64 = 0.5;

/// How the plate's mesh sequence is built.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MeshOptions {
    /// Solve half or a quarter of the plate when the teeth and every load are mirror-symmetric.
    pub symmetry: bool,
    /// Grade the coarsest mesh geometrically towards the load-patch and tooth edges (on a
    /// rectilinear mesh grading towards a corner means towards both of its edge lines).
    pub graded: bool,
    /// Put mesh lines through the teeth's base-edge stations ([`station_lines_um`]), so the
    /// tooth-base stress converges as the safety factor needs: on the bundled design
    /// `centre-1n` in 6 levels (303k dofs) instead of 9 (804k), but every level about 3x the
    /// elements, which a study answering only readings does not need ([`MeshOptions::READINGS`]).
    pub stations: bool,
}

impl MeshOptions {
    /// For studies that answer readings only (calibration, orientation, the tissue's cells):
    /// no station lines, so each level is about a third the size; their tooth-base stress is
    /// read off the lines, with the optimistic estimate that goes with it.
    pub const READINGS: MeshOptions = MeshOptions::FEATURE_LINES;

    /// The feature lines alone, ungraded and without station lines: the meshes that read no
    /// tooth-base stress (the natural frequencies, the footing's fit).
    pub const FEATURE_LINES: MeshOptions = MeshOptions {
        symmetry: true,
        graded: false,
        stations: false,
    };
}

impl Default for MeshOptions {
    /// Symmetry on; no grading. With 25 teeth the 100 tooth corners, whose singular moments hold
    /// the observed order near 1, are all over the plate, so on a rectilinear mesh grading
    /// towards them refines almost everywhere: on the bundled design (`fe_bench`) the graded
    /// sequence took 80 ms for the centre load where the ungraded one took 30 ms for the
    /// default 1 %, but reached an estimated 0.44 % in those 80 ms where the ungraded needed
    /// 192 ms for 0.31 % (true errors of the deflection 0.30 % and 0.27 %); off-centre the
    /// ungraded sequence stayed cheaper at 0.5 %.
    fn default() -> Self {
        MeshOptions {
            symmetry: true,
            graded: false,
            stations: true,
        }
    }
}

/// Lines of the coarsest mesh: every feature line (electrode, tooth, support and load-patch
/// edges) and, when graded, the grading lines; intervals no longer than [`COARSE_ELEMENT_UM`].
/// Exact lines (plate, electrode, axis-aligned load patch) always stay; a tooth line or grading
/// line closer than [`MIN_LINE_GAP_UM`] to a kept line is dropped, tooth lines taking precedence
/// over grading, and so is a rotated probe's bounding-box line within [`ROTATED_LINE_GAP_UM`].
/// Last come, with `stations`, the lines through the tooth-base stations ([`station_lines_um`]),
/// dropped only within [`STATION_LINE_GAP_UM`] of a kept line.
///
/// On a symmetric problem the lines are folded into the part solved ([`Symmetry::fold`]).
/// `opts` says whether to grade and to put in the station lines (its `symmetry` is `sym`'s).
pub(super) fn base_lines(
    g: &SensorGeometry,
    loads: &[SceneLoads],
    sym: &Symmetry,
    opts: &MeshOptions,
) -> (Vec<f64>, Vec<f64>) {
    let (mut xs, mut ys) = g.exact_lines();
    // Rotated patches' bounding boxes only where they keep clear of the other lines.
    let (mut rx, mut ry) = (Vec::new(), Vec::new());
    for l in loads {
        let p = &l.patch;
        if p.x1_um > p.x0_um && p.y1_um > p.y0_um {
            let (x, y) = if l.axis_aligned() {
                (&mut xs, &mut ys)
            } else {
                (&mut rx, &mut ry)
            };
            x.extend([p.x0_um, p.x1_um]);
            y.extend([p.y0_um, p.y1_um]);
        }
    }
    let (tx, ty) = g.tooth_lines();
    let (x0, x1, y0, y1) = sym.domain_um;
    let mut xs = merge_lines(sym.fold(true, xs), sym.fold(true, tx.clone()), x0, x1);
    let mut ys = merge_lines(sym.fold(false, ys), sym.fold(false, ty.clone()), y0, y1);
    xs = merge_lines_within(xs, sym.fold(true, rx), x0, x1, ROTATED_LINE_GAP_UM);
    ys = merge_lines_within(ys, sym.fold(false, ry), y0, y1, ROTATED_LINE_GAP_UM);
    if opts.graded {
        let (mut gx, mut gy) = (Vec::new(), Vec::new());
        for l in loads {
            let p = &l.patch;
            let first = LOAD_FIRST_SPACING * (p.x1_um - p.x0_um).max(p.y1_um - p.y0_um);
            if first > 0.0 {
                gx.extend(
                    [p.x0_um, p.x1_um]
                        .iter()
                        .flat_map(|&c| grading_lines(c, first)),
                );
                gy.extend(
                    [p.y0_um, p.y1_um]
                        .iter()
                        .flat_map(|&c| grading_lines(c, first)),
                );
            }
        }
        gx.extend(
            tx.iter()
                .flat_map(|&c| grading_lines(c, TOOTH_FIRST_SPACING_UM)),
        );
        gy.extend(
            ty.iter()
                .flat_map(|&c| grading_lines(c, TOOTH_FIRST_SPACING_UM)),
        );
        xs = merge_lines(xs, sym.fold(true, gx), x0, x1);
        ys = merge_lines(ys, sym.fold(false, gy), y0, y1);
    }
    // The tooth-base stations' lines go in last, closer than MIN_LINE_GAP_UM where need be (a
    // base edge is a half run-out from the plate's step line): what they buy is a station that
    // keeps its place in its element from level to level.
    if opts.stations {
        let (sx, sy) = station_lines_um(g);
        xs = merge_lines_within(xs, sym.fold(true, sx), x0, x1, STATION_LINE_GAP_UM);
        ys = merge_lines_within(ys, sym.fold(false, sy), y0, y1, STATION_LINE_GAP_UM);
    }
    let mesh = RectMesh::ungraded(&xs, &ys, COARSE_ELEMENT_UM);
    (mesh.x_um, mesh.y_um)
}

/// What [`base_lines`] grades towards, for the report.
pub(super) fn grading_description(loads: &[SceneLoads]) -> String {
    let patches = loads
        .iter()
        .filter(|l| l.patch.x1_um > l.patch.x0_um && l.patch.y1_um > l.patch.y0_um)
        .count();
    format!(
        "geometric (growth {GRADING_GROWTH}) towards {patches} load patch(es) (first spacing \
         {LOAD_FIRST_SPACING} x the patch side) and the tooth edges (first spacing \
         {TOOTH_FIRST_SPACING_UM} um)"
    )
}

/// Lines on both sides of `c_um` at spacings first, 2 first, 4 first, ... (geometric grading,
/// growth [`GRADING_GROWTH`]) while the spacing is below [`COARSE_ELEMENT_UM`].
fn grading_lines(c_um: f64, first_um: f64) -> Vec<f64> {
    let mut out = Vec::new();
    let (mut offset, mut step) = (first_um, first_um);
    while step < COARSE_ELEMENT_UM {
        out.extend([c_um - offset, c_um + offset]);
        step *= GRADING_GROWTH;
        offset += step;
    }
    out
}

/// `kept` lines first, then `extra` ones that are at least [`MIN_LINE_GAP_UM`] from every kept
/// line: slivers between nearly coincident lines would force tiny, badly graded elements.
fn merge_lines(kept: Vec<f64>, extra: Vec<f64>, lo: f64, hi: f64) -> Vec<f64> {
    merge_lines_within(kept, extra, lo, hi, MIN_LINE_GAP_UM)
}

/// [`merge_lines`] with its own gap.
fn merge_lines_within(kept: Vec<f64>, extra: Vec<f64>, lo: f64, hi: f64, gap_um: f64) -> Vec<f64> {
    let mut kept: Vec<f64> = kept.into_iter().filter(|x| *x >= lo && *x <= hi).collect();
    kept.extend([lo, hi]);
    kept.sort_by(f64::total_cmp);
    kept.dedup_by(|a, b| (*a - *b).abs() < 1e-6);
    let mut extra: Vec<f64> = extra.into_iter().filter(|x| *x > lo && *x < hi).collect();
    extra.sort_by(f64::total_cmp);
    for x in extra {
        if kept.iter().all(|k| (k - x).abs() >= gap_um) {
            let i = kept.partition_point(|k| *k < x);
            kept.insert(i, x);
        }
    }
    kept
}

/// Every interval split into [`SUBDIVISIONS`]`[level]` equal parts.
pub(super) fn subdivide(lines: &[f64], level: usize) -> Vec<f64> {
    let n = SUBDIVISIONS[level];
    let mut out = Vec::with_capacity((lines.len() - 1) * n + 1);
    for w in lines.windows(2) {
        for k in 0..n {
            out.push(w[0] + (w[1] - w[0]) * k as f64 / n as f64);
        }
    }
    out.push(*lines.last().expect("a mesh has lines"));
    out
}

/// Refinement ratios (h3/h2, h2/h1) of the three levels ending at `level`.
pub fn level_ratios(level: usize) -> (f64, f64) {
    assert!(level >= 2, "three levels");
    let n = |k: usize| SUBDIVISIONS[k] as f64;
    (n(level - 1) / n(level - 2), n(level) / n(level - 1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grading_lines_double_their_spacing_up_to_the_coarse_size() {
        assert_eq!(
            grading_lines(0.0, 500.0),
            vec![-500.0, 500.0, -1500.0, 1500.0]
        );
        assert_eq!(
            grading_lines(10.0, 250.0),
            vec![-240.0, 260.0, -740.0, 760.0, -1740.0, 1760.0]
        );
        assert!(grading_lines(0.0, COARSE_ELEMENT_UM).is_empty());
    }

    #[test]
    fn every_tooth_base_station_stands_on_coarse_lines() {
        let g = crate::sensor::geometry::bundled(&[]);
        let (sx, sy) = station_lines_um(&g);
        // Two base edges and two end stations per direction for each tooth (25).
        let n = 4 * g.etched.tooth_tops_um.len();
        assert_eq!((n, sx.len(), sy.len()), (100, n, n));
        let (xs, ys) = base_lines(&g, &[], &Symmetry::none(&g), &MeshOptions::default());
        // Each station line inside the plate is a line (the first and last rows' teeth stand
        // on the supports, so some of theirs are outside it, and one base edge 8 um inside its
        // edge, which the gap drops).
        let on = |lines: &[f64], v: f64| {
            let (lo, hi) = (lines[0], lines[lines.len() - 1]);
            v <= lo + STATION_LINE_GAP_UM
                || v >= hi - STATION_LINE_GAP_UM
                || lines.iter().any(|l| (l - v).abs() < 1e-6)
        };
        assert!(sx.iter().all(|&x| on(&xs, x)) && sy.iter().all(|&y| on(&ys, y)));
        // The base edges a half run-out from the plate's step lines, which the feature lines'
        // gap alone would drop.
        let (tx, _) = g.tooth_lines();
        let ro = g.etched.tooth_run_out_um;
        let gap = tx
            .iter()
            .map(|t| (sx[0] - t).abs())
            .fold(f64::INFINITY, f64::min);
        assert!(
            gap < MIN_LINE_GAP_UM && (gap - 0.5 * ro).abs() < 1.0,
            "{gap} um"
        );
    }

    #[test]
    fn merged_lines_keep_the_kept_and_drop_extras_too_close() {
        let m = merge_lines(
            vec![0.0, 1000.0, 5000.0],
            vec![100.0, 1300.0, 1400.0, 4900.0, 6000.0],
            0.0,
            5000.0,
        );
        assert_eq!(m, vec![0.0, 1000.0, 1300.0, 5000.0]);
    }
}
