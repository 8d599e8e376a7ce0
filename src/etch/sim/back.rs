//! The back etch of one support corner ([`super::back_cell`]) for the recipe's back-side
//! steps, and what the designer asks of it: where the U-channel's floor ends (the plate is
//! clamped there), how far the {111} wall runs out, and how far the supports' corners recede.
//! Each is set against its closed form from process-physics.md.

use serde::Serialize;

use crate::etch::geometry::{sidewall_run_out_um, undercut_um};

use super::back_cell::BackCell;
use super::level_set::{Stepper, Surface};
use super::rate_table::{RateModel, RateTable};
use super::readout::{contour, crossing_on_ray, sample};
use super::richardson::{extrapolate, CORNER_ORDER};
use super::tooth::Frame;
use super::SimError;

/// One back-side silicon etch of the recipe, run in order.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BackStep {
    pub name: String,
    pub time_h: f64,
    pub rates: RateTable,
}

/// A quantity on the grid and its double: the Richardson estimate (order
/// [`CORNER_ORDER`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Extrapolated {
    pub coarse_grid_um: f64,
    pub coarse_um: f64,
    /// Estimated error of the fine value (fine + error = extrapolated).
    pub error_um: f64,
    pub extrapolated_um: f64,
}

impl Extrapolated {
    /// From the fine value on `h_um` and the coarse one on `coarse_h_um`.
    pub fn of(fine_um: f64, h_um: f64, coarse_um: f64, coarse_h_um: f64) -> Extrapolated {
        let (ext, err) = extrapolate(fine_um, h_um, coarse_um, coarse_h_um, CORNER_ORDER);
        Extrapolated {
            coarse_grid_um: coarse_h_um,
            coarse_um,
            error_um: err,
            extrapolated_um: ext,
        }
    }
}

/// A drawn corner of the back mask after the etch.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BackCorner {
    /// The drawn vertex (die um).
    pub at_um: [f64; 2],
    /// `convex` (an island's corner: the support's) or `concave`.
    pub kind: &'static str,
    /// Along the bisector from the drawn vertex to the etched top edge, > 0 out into the
    /// opening, < 0 into the mask (the corner receded); none when the top edge left the
    /// cell's reach.
    pub deviation_um: Option<f64>,
    /// Convex: -sqrt 2 R110 t (the {110} facet through the corner, as for the tooth);
    /// concave: +sqrt 2 R111 t / sin 54.74 deg (two {111} walls, each undercut).
    pub closed_form_um: f64,
    /// The Richardson estimate from the doubled grid (none for one grid).
    pub error: Option<Extrapolated>,
}

/// The etched back corner cell. y is across the support's channel-side edge (drawn at
/// `support_edge_y_um`), read on the straight part of the edge at `wall_x_um`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BackSimulation {
    pub steps: Vec<BackStep>,
    pub time_h: f64,
    pub grid_um: f64,
    pub nodes: usize,
    pub time_steps: usize,
    /// The cell (die um: x0, y0, x1, y1).
    pub cell_um: [f64; 4],
    /// Channel floor depth at the cell's far corner (on the channel floor).
    pub floor_depth_um: f64,
    pub support_edge_y_um: f64,
    pub wall_x_um: f64,
    /// Drawn edge to the etched top edge, > 0 into the support.
    pub edge_undercut_um: f64,
    /// Sum over the steps of R111 t / sin 54.74 deg.
    pub closed_form_undercut_um: f64,
    /// Horizontal run of the wall from a straight line through its 20 % and 80 % depth points.
    pub run_out_um: f64,
    /// h / tan 54.74 deg of the simulated floor depth.
    pub closed_form_run_out_um: f64,
    /// Where that line meets the floor: the channel floor's edge (y, die um).
    pub floor_edge_y_um: f64,
    /// The etch plan's floor edge: support width - undercut + run-out (`channel_floor_y_um`).
    pub plan_floor_edge_y_um: f64,
    /// The channel floor across the die (mirror-symmetric about W / 2): W - 2 floor edge.
    pub floor_width_um: f64,
    pub plan_floor_width_um: f64,
    /// The floor edge's Richardson estimate from the doubled grid.
    pub floor_edge_error: Option<Extrapolated>,
    pub corners: Vec<BackCorner>,
    #[serde(skip)]
    pub frames: Vec<Frame>,
    /// The final floor contour (95 % of the depth), die um segments.
    #[serde(skip)]
    pub base: Vec<[f64; 4]>,
    #[serde(skip)]
    pub drawn: Vec<geo::Polygon>,
}

/// Etches `cell` through `steps` in order, keeping `frames` plan-view contours at equal times;
/// `plan_floor_edge_y_um` is the etch plan's channel floor edge to compare with.
#[track_caller]
pub fn simulate_back_cell(
    cell: &BackCell,
    steps: &[BackStep],
    plan_floor_edge_y_um: f64,
    frames: usize,
) -> Result<BackSimulation, SimError> {
    assert!(
        !steps.is_empty(),
        "a back simulation needs a back-side step"
    );
    let g = cell.grid;
    let mut s = Surface::new(g, cell.drawn.clone());
    let total: f64 = steps.iter().map(|st| st.time_h).sum();
    let frame_t: Vec<f64> = (1..=frames)
        .map(|k| total * k as f64 / frames as f64)
        .collect();
    let (mut t0, mut fi, mut time_steps) = (0.0, 0, 0);
    let mut kept = Vec::new();
    let mut last = None;
    for st in steps {
        let stepper = Stepper::new(RateModel::new(st.rates), &g);
        let t1 = t0 + st.time_h;
        time_steps += (st.time_h / stepper.dt_max_h()).ceil() as usize;
        while fi < frame_t.len() && frame_t[fi] <= t1 + 1e-9 {
            stepper.advance(&mut s, frame_t[fi].min(t1))?;
            kept.push(Frame {
                time_h: frame_t[fi],
                segments: contour(&stepper.top_field(&s), &g, 0.0),
            });
            fi += 1;
        }
        stepper.advance(&mut s, t1)?;
        t0 = t1;
        last = Some(stepper);
    }
    let stepper = last.expect("at least one step");
    let field = stepper.top_field(&s);
    let (x1, y1) = (g.x_um(g.nx - 1), g.y_um(g.ny - 1));
    let depth = -sample(&s.h_um, &g, x1, y1);
    // The wall: up y from inside the support, across its drawn edge, on the straight part.
    let edge = cell.support_edge_y_um;
    let into = (0.5 * edge).min(edge - g.y0_um - g.dy_um);
    let from = (cell.wall_x_um, edge - into);
    let span = y1 - from.1;
    let cross = |f: &[f64], level: f64| {
        crossing_on_ray(f, &g, from, (0.0, 1.0), level, span).map_or(f64::NAN, |d| from.1 + d)
    };
    let top = cross(&field, 0.0);
    let (y20, y80) = (cross(&s.h_um, -0.2 * depth), cross(&s.h_um, -0.8 * depth));
    let run_out_um = (y80 - y20) / 0.6;
    let floor_edge_y_um = y20 + 0.8 * run_out_um;
    let r110_t: f64 = steps
        .iter()
        .map(|st| st.rates.r110_um_per_h * st.time_h)
        .sum();
    let undercut: f64 = steps
        .iter()
        .map(|st| undercut_um(st.rates.r111_um_per_h, st.time_h))
        .sum();
    let corners = cell
        .corners
        .iter()
        .map(|c| {
            // From inside the mask out along the bisector, starting as deep in as the cell
            // allows (up to twice the closed-form recession).
            let reach = 2.0 * std::f64::consts::SQRT_2 * r110_t + 4.0 * g.dx_um.max(g.dy_um);
            let room = room_inside(&g, c.at_um, [-c.outward[0], -c.outward[1]]);
            let d_in = reach.min(room);
            let start = (
                c.at_um[0] - d_in * c.outward[0],
                c.at_um[1] - d_in * c.outward[1],
            );
            let out_room = room_inside(&g, c.at_um, c.outward);
            let deviation_um = (sample(&field, &g, start.0, start.1) > 0.0)
                .then(|| {
                    crossing_on_ray(
                        &field,
                        &g,
                        start,
                        (c.outward[0], c.outward[1]),
                        0.0,
                        d_in + out_room,
                    )
                })
                .flatten()
                .map(|d| d - d_in);
            BackCorner {
                at_um: c.at_um,
                kind: if c.convex { "convex" } else { "concave" },
                deviation_um,
                closed_form_um: if c.convex {
                    -std::f64::consts::SQRT_2 * r110_t
                } else {
                    std::f64::consts::SQRT_2 * undercut
                },
                error: None,
            }
        })
        .collect();
    let plan_floor_width_um = cell.die_width_um - 2.0 * plan_floor_edge_y_um;
    Ok(BackSimulation {
        steps: steps.to_vec(),
        time_h: total,
        grid_um: g.dx_um,
        nodes: g.len(),
        time_steps,
        cell_um: [g.x0_um, g.y0_um, x1, y1],
        floor_depth_um: depth,
        support_edge_y_um: edge,
        wall_x_um: cell.wall_x_um,
        edge_undercut_um: edge - top,
        closed_form_undercut_um: undercut,
        run_out_um,
        closed_form_run_out_um: sidewall_run_out_um(depth),
        floor_edge_y_um,
        plan_floor_edge_y_um,
        floor_width_um: cell.die_width_um - 2.0 * floor_edge_y_um,
        plan_floor_width_um,
        floor_edge_error: None,
        corners,
        frames: kept,
        base: contour(&s.h_um, &g, -0.95 * depth),
        drawn: cell.polygons.clone(),
    })
}

/// How far from `at` along the unit `dir` the grid extends.
fn room_inside(g: &super::level_set::Grid, at: [f64; 2], dir: [f64; 2]) -> f64 {
    let (x1, y1) = (g.x_um(g.nx - 1), g.y_um(g.ny - 1));
    let lim = |p: f64, d: f64, lo: f64, hi: f64| {
        if d > 1e-12 {
            (hi - p) / d
        } else if d < -1e-12 {
            (lo - p) / d
        } else {
            f64::INFINITY
        }
    };
    lim(at[0], dir[0], g.x0_um, x1)
        .min(lim(at[1], dir[1], g.y0_um, y1))
        .max(0.0)
}

/// The fine run with the Richardson estimates of its floor edge and corners from the `coarse`
/// run of the same cell (corners matched by their drawn vertex); none when the coarse grid is
/// not coarser (a cell too small to double its step).
pub fn with_errors(mut fine: BackSimulation, coarse: &BackSimulation) -> BackSimulation {
    let (h, h2) = (fine.grid_um, coarse.grid_um);
    if h2 <= h {
        return fine;
    }
    fine.floor_edge_error = Some(Extrapolated::of(
        fine.floor_edge_y_um,
        h,
        coarse.floor_edge_y_um,
        h2,
    ));
    for f in fine.corners.iter_mut() {
        let c = coarse.corners.iter().find(|c| c.at_um == f.at_um);
        f.error = match (f.deviation_um, c.and_then(|c| c.deviation_um)) {
            (Some(a), Some(b)) => Some(Extrapolated::of(a, h, b, h2)),
            _ => None,
        };
    }
    fine
}
