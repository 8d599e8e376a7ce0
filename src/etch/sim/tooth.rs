//! One tooth's symmetry cell etched for the recipe's time, and what the designer asks of it:
//! is the etched tooth top square, rounded, or carrying a spike of leftover compensator?

use serde::Serialize;

use super::cell::ToothCell;
use super::level_set::{Stepper, Surface};
use super::rate_table::{RateModel, RateTable};
use super::readout::{contour, crossing_on_ray, nearest_family, sample};
use super::richardson::CornerError;
use super::SimError;

/// How often the corner is read during the etch (for the time the compensator is consumed).
pub const HISTORY_POINTS: usize = 40;
/// A floor node this far above the deepest one is compensator residue \[choice: 1 um, what a
/// profilometer sees on a 200 um etch\].
pub const RESIDUE_UM: f64 = 1.0;
/// Facets are named when the normal lies within this angle of the family \[choice\].
pub const FACET_TOLERANCE_DEG: f64 = 3.0;

/// The corner's shape against the tolerance.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CornerShape {
    /// Within the tolerance of the drawn corner.
    Square,
    /// The corner receded (undercut by the fast planes).
    Rounded,
    /// Leftover compensator stands beyond the drawn corner.
    OverCompensated,
}

impl CornerShape {
    /// The shape of a corner `deviation_um` from the drawn one (> 0 outwards).
    pub fn of(deviation_um: f64, tolerance_um: f64) -> CornerShape {
        if deviation_um.abs() <= tolerance_um {
            CornerShape::Square
        } else if deviation_um < 0.0 {
            CornerShape::Rounded
        } else {
            CornerShape::OverCompensated
        }
    }
}

/// One facet family seen on the sidewalls.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Facet {
    /// Sorted |Miller indices|, e.g. `111`.
    pub family: String,
    /// Share of the sidewall area (true area, not projected).
    pub area_share: f64,
    /// Mean angle between the surface normals and the family's (deg).
    pub mean_deviation_deg: f64,
}

/// The corner deviation at one time of the etch.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CornerAt {
    pub time_h: f64,
    pub corner_deviation_um: f64,
}

/// Top-edge contours at one time: segments (x0, y0, x1, y1) in die um.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    pub time_h: f64,
    pub segments: Vec<[f64; 4]>,
}

/// The etched tooth cell. Sign convention: `corner_deviation_um` is measured along the tooth's
/// diagonal from the drawn tooth-top corner to the etched top edge, > 0 outwards (silicon left
/// beyond the drawn corner: over-compensated), < 0 inwards (the corner receded: rounded). A top
/// that reaches the middle of the street (bridged to the diagonal neighbour) is reported as
/// that far out.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ToothSimulation {
    pub time_h: f64,
    pub grid_um: f64,
    pub nodes: usize,
    pub time_steps: usize,
    pub rates: RateTable,
    /// Tooth (column, row) whose cell was simulated, and the cell (die um: x0, y0, x1, y1).
    pub tooth: [u32; 2],
    pub cell_um: [f64; 4],
    pub tooth_top_um: f64,
    pub corner_deviation_um: f64,
    /// The corner against the square whose edges moved by the measured edge undercut:
    /// corner_deviation + sqrt 2 edge_undercut.
    pub corner_vs_undercut_square_um: f64,
    /// Judged on the best estimate: the extrapolated corner when [`Self::corner_error`] is
    /// known, else this grid's.
    pub corner_shape: CornerShape,
    pub tolerance_um: f64,
    /// The top is unbroken to the middle of the street (bridged to the diagonal neighbour);
    /// the corner is then the cap, not a converging number.
    pub corner_bridged: bool,
    /// The corner's discretisation error from this grid and its double (Richardson); none for
    /// a single-grid run or a bridged corner.
    pub corner_error: Option<CornerError>,
    /// Mid-edge: drawn edge to etched top edge, > 0 inwards.
    pub edge_undercut_um: f64,
    /// When the compensator is used up: for squares, when the etched top edge on the diagonal
    /// first reaches the drawn corner; for a <110> bar, when the top along the bar's centre
    /// line (from the tooth centre along x) first ends at the drawn tooth edge. None when the
    /// mask draws nothing beyond the corner or the compensator outlasts the etch.
    pub compensator_consumed_h: Option<f64>,
    /// Deepest floor in the cell (the (100) etch depth).
    pub floor_depth_um: f64,
    /// Highest floor point away from the teeth's ideal bases ({111} frusta of the drawn tops),
    /// above the deepest floor.
    pub floor_residue_height_um: f64,
    /// Floor area in the cell standing more than [`RESIDUE_UM`] above the deepest floor.
    pub floor_residue_area_um2: f64,
    pub facets: Vec<Facet>,
    pub history: Vec<CornerAt>,
    #[serde(skip)]
    pub frames: Vec<Frame>,
    /// The final base contour (95 % of the floor depth), die um segments.
    #[serde(skip)]
    pub base: Vec<[f64; 4]>,
    #[serde(skip)]
    pub drawn: Vec<geo::Polygon>,
    /// The final surface along the tooth's diagonal from its centre to the cell's far corner:
    /// (distance, height) in um, every half cell (the traveler's cross-section).
    #[serde(skip)]
    pub diagonal_profile: Vec<[f64; 2]>,
    /// Where the drawn mask ends along that diagonal (tooth corner plus compensator), um.
    #[serde(skip)]
    pub drawn_diagonal_um: f64,
}

/// Etches `cell` with `table` for `time_h` and reads the tooth off it; `frames` plan-view
/// contours are kept at equal times. `bar_width_um`: the drawn compensator is a <110> bar of
/// that width (its consumption is read along its centre line), none for squares or nothing.
pub fn simulate_cell(
    table: RateTable,
    cell: &ToothCell,
    time_h: f64,
    tolerance_um: f64,
    frames: usize,
    bar_width_um: Option<f64>,
) -> Result<ToothSimulation, SimError> {
    let g = cell.grid;
    let stepper = Stepper::new(RateModel::new(table), &g);
    let mut s = Surface::new(g, cell.drawn.clone());
    let (cx, cy) = cell.centre_um();
    let half = cell.top_um / 2.0;
    let diag = std::f64::consts::FRAC_1_SQRT_2;
    let reach = g.nx as f64 * g.dx_um + g.ny as f64 * g.dy_um;
    // Along the diagonal only up to the middle of the street (beyond is the neighbour's half):
    // a top still unbroken there bridges to the neighbour, reported as that far out.
    let street_mid = 0.5 * (g.x_um(g.nx - 1) - cx).min(g.y_um(g.ny - 1) - cy) * 2f64.sqrt();
    let corner = |s: &Surface| {
        let f = stepper.top_field(s);
        crossing_on_ray(&f, &g, (cx, cy), (diag, diag), 0.0, street_mid).unwrap_or(street_mid)
            - half * 2f64.sqrt()
    };
    // A bar's top along its centre line y = s/2 - b/2, beyond the drawn tooth edge x = s/2
    // (> 0: bar left; the bar lies in the cell's tooth row, so the ray stays in the cell).
    let bar = |s: &Surface, b: f64| {
        let f = stepper.top_field(s);
        crossing_on_ray(&f, &g, (cx, cy + half - b / 2.0), (1.0, 0.0), 0.0, reach).unwrap_or(0.0)
            - half
    };
    let mut history = vec![CornerAt {
        time_h: 0.0,
        corner_deviation_um: corner(&s),
    }];
    let mut bar_history: Vec<CornerAt> = bar_width_um
        .map(|b| CornerAt {
            time_h: 0.0,
            corner_deviation_um: bar(&s, b),
        })
        .into_iter()
        .collect();
    let mut kept = Vec::new();
    let every = (HISTORY_POINTS / frames.max(1)).max(1);
    for k in 1..=HISTORY_POINTS {
        let t = time_h * k as f64 / HISTORY_POINTS as f64;
        stepper.advance(&mut s, t)?;
        history.push(CornerAt {
            time_h: t,
            corner_deviation_um: corner(&s),
        });
        if let Some(b) = bar_width_um {
            bar_history.push(CornerAt {
                time_h: t,
                corner_deviation_um: bar(&s, b),
            });
        }
        if k % every == 0 || k == HISTORY_POINTS {
            kept.push(Frame {
                time_h: t,
                segments: contour(&stepper.top_field(&s), &g, 0.0),
            });
        }
    }
    let time_steps = (time_h / stepper.dt_max_h()).ceil() as usize;
    let field = stepper.top_field(&s);
    let edge = crossing_on_ray(&field, &g, (cx, cy), (1.0, 0.0), 0.0, reach).unwrap_or(0.0);
    let edge_undercut_um = half - edge;
    let corner_deviation_um = history.last().map_or(0.0, |c| c.corner_deviation_um);
    let corner_shape = CornerShape::of(corner_deviation_um, tolerance_um);
    let corner_bridged =
        crossing_on_ray(&field, &g, (cx, cy), (diag, diag), 0.0, street_mid).is_none();
    let floor_depth_um = -s.h_um.iter().copied().fold(0.0, f64::min);
    let diag_len = (g.x_um(g.nx - 1) - cx).hypot(g.y_um(g.ny - 1) - cy);
    let n_prof = (2.0 * diag_len / g.dx_um).ceil() as usize;
    let diagonal_profile = (0..=n_prof)
        .map(|k| {
            let d = diag_len * k as f64 / n_prof as f64;
            [d, sample(&s.h_um, &g, cx + d * diag, cy + d * diag)]
        })
        .collect();
    let mask_field: Vec<f64> = cell
        .drawn
        .iter()
        .map(|&m| if m { 1.0 } else { -1.0 })
        .collect();
    let drawn_diagonal_um =
        crossing_on_ray(&mask_field, &g, (cx, cy), (diag, diag), 0.0, diag_len).unwrap_or(diag_len);
    let (floor_residue_height_um, floor_residue_area_um2) = residue(&s, cell, floor_depth_um);
    Ok(ToothSimulation {
        time_h,
        grid_um: g.dx_um,
        nodes: g.len(),
        time_steps,
        rates: table,
        tooth: [cell.tooth.i, cell.tooth.j],
        cell_um: [g.x0_um, g.y0_um, g.x_um(g.nx - 1), g.y_um(g.ny - 1)],
        tooth_top_um: cell.top_um,
        corner_deviation_um,
        corner_vs_undercut_square_um: corner_deviation_um + 2f64.sqrt() * edge_undercut_um,
        corner_shape,
        tolerance_um,
        corner_bridged,
        corner_error: None,
        edge_undercut_um,
        compensator_consumed_h: consumed(
            if bar_width_um.is_some() {
                &bar_history
            } else {
                &history
            },
            0.5 * g.dx_um,
        ),
        floor_depth_um,
        floor_residue_height_um,
        floor_residue_area_um2,
        facets: facets(&s, floor_depth_um),
        history,
        frames: kept,
        base: contour(&s.h_um, &g, -0.95 * floor_depth_um),
        drawn: cell.polygons.clone(),
        diagonal_profile,
        drawn_diagonal_um,
    })
}

/// The first time the corner deviation (or a bar's length) falls to 0 (linear between the
/// readings), when it started more than `drawn_um` (half a cell: a compensator is drawn) above
/// 0.
fn consumed(history: &[CornerAt], drawn_um: f64) -> Option<f64> {
    if history.first()?.corner_deviation_um <= drawn_um {
        return None;
    }
    history.windows(2).find_map(|w| {
        let (a, b) = (w[0], w[1]);
        (a.corner_deviation_um > 0.0 && b.corner_deviation_um <= 0.0).then(|| {
            a.time_h
                + (b.time_h - a.time_h) * a.corner_deviation_um
                    / (a.corner_deviation_um - b.corner_deviation_um)
        })
    })
}

/// Height and area of the floor that stands above the deepest floor away from every tooth's
/// ideal base: the drawn top grown by the {111} run-out of the depth and two cells.
fn residue(s: &Surface, cell: &ToothCell, depth_um: f64) -> (f64, f64) {
    let g = s.grid;
    let reach =
        cell.top_um / 2.0 + crate::etch::geometry::sidewall_run_out_um(depth_um) + 2.0 * g.dx_um;
    let (mut height, mut area) = (0.0f64, 0.0);
    for j in 0..g.ny {
        for i in 0..g.nx {
            let (x, y) = (g.x_um(i), g.y_um(j));
            let near_tooth = cell
                .tooth_centres_um
                .iter()
                .any(|&(tx, ty)| (x - tx).abs().max((y - ty).abs()) < reach);
            if near_tooth {
                continue;
            }
            let above = s.h(i, j) + depth_um;
            height = height.max(above);
            if above > RESIDUE_UM {
                // Nodes on the cell's mirror sides carry half (a quarter at corners) of a cell.
                let wx = if i == 0 || i == g.nx - 1 { 0.5 } else { 1.0 };
                let wy = if j == 0 || j == g.ny - 1 { 0.5 } else { 1.0 };
                area += wx * wy * g.dx_um * g.dy_um;
            }
        }
    }
    (height, area)
}

/// The sidewall facets: every exposed node between 3 % and 97 % of the depth with all four
/// neighbours exposed, its central-difference normal named after the nearest family within
/// [`FACET_TOLERANCE_DEG`] (else `other`), weighted by true area.
fn facets(s: &Surface, depth_um: f64) -> Vec<Facet> {
    let g = s.grid;
    let mut acc: std::collections::BTreeMap<&str, (f64, f64)> = Default::default();
    let mut total = 0.0;
    for j in 1..g.ny - 1 {
        for i in 1..g.nx - 1 {
            let k = j * g.nx + i;
            let h = s.h_um[k];
            if h > -0.03 * depth_um || h < -0.97 * depth_um {
                continue;
            }
            let nb = [k - 1, k + 1, k - g.nx, k + g.nx];
            if nb.iter().any(|&n| s.covered[n]) || s.covered[k] {
                continue;
            }
            let p = (s.h_um[k + 1] - s.h_um[k - 1]) / (2.0 * g.dx_um);
            let q = (s.h_um[k + g.nx] - s.h_um[k - g.nx]) / (2.0 * g.dy_um);
            let w = (1.0 + p * p + q * q).sqrt();
            // Wafer (x [110], y [-110], z [001]) to crystal axes.
            let r = std::f64::consts::FRAC_1_SQRT_2;
            let n = [r * (-p + q), r * (-p - q), 1.0];
            let (fam, ang) = nearest_family(n);
            let name = if ang <= FACET_TOLERANCE_DEG {
                fam
            } else {
                "other"
            };
            let e = acc.entry(name).or_insert((0.0, 0.0));
            e.0 += w;
            e.1 += w * ang;
            total += w;
        }
    }
    let mut out: Vec<Facet> = acc
        .into_iter()
        .filter(|(_, (a, _))| total > 0.0 && *a / total >= 0.01)
        .map(|(f, (a, sa))| Facet {
            family: f.to_string(),
            area_share: a / total,
            mean_deviation_deg: sa / a,
        })
        .collect();
    out.sort_by(|a, b| b.area_share.total_cmp(&a.area_share));
    out
}
