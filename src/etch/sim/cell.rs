//! The simulated cell: one tooth's symmetry cell, rasterised from the drawn front mask of the
//! generated [`MaskSet`] (the tooth cell's polygons at every tooth placement), so what is
//! simulated is what is drawn.
//!
//! Checkered and matrix teeth are mirror-symmetric about every tooth's centre lines and every
//! cell's centre lines, so the rectangle from a tooth's centre to the centre of the next cell
//! diagonally up (one pitch each way) is a symmetry cell: a quarter of the tooth with its
//! compensator, the street, and a quarter of whatever the diagonal cell holds (the next tooth
//! in a checkered pattern). Its sides are mirror planes of the level set. The tooth is taken
//! from the die's interior, so that the mirror images are real neighbours.

use geo::{BoundingRect, Coord, Intersects, Polygon};

use crate::layout::{LayerKind, MaskSet, Tooth};
use crate::process::Teeth;

use super::level_set::Grid;
use super::SimError;

/// The rasterised symmetry cell of one tooth.
#[derive(Debug, Clone)]
pub struct ToothCell {
    pub grid: Grid,
    /// Node under the drawn front mask.
    pub drawn: Vec<bool>,
    /// The tooth whose cell this is.
    pub tooth: Tooth,
    /// The drawn mask polygons that reach into the cell (die coordinates, um).
    pub polygons: Vec<Polygon>,
    /// Centres of the tooth tops whose quarter lies in the cell (die coordinates, um).
    pub tooth_centres_um: Vec<(f64, f64)>,
    /// Side of the drawn tooth top.
    pub top_um: f64,
}

impl ToothCell {
    /// The tooth centre: the cell's lower-left node.
    pub fn centre_um(&self) -> (f64, f64) {
        (self.grid.x0_um, self.grid.y0_um)
    }
}

/// The interior tooth nearest the die centre whose cell's mirror images are teeth of the die:
/// column i in 1..=count_x - 3, row j likewise.
fn interior_tooth(masks: &MaskSet, t: &Teeth) -> Option<Tooth> {
    let (cx, cy) = (masks.die_length_um / 2.0, masks.die_width_um / 2.0);
    let dist = |k: &Tooth| {
        let (x, y) = (k.x_um + t.top_um / 2.0, k.y_um + t.top_um / 2.0);
        (x - cx).hypot(y - cy)
    };
    masks
        .teeth
        .iter()
        .filter(|k| k.i >= 1 && k.j >= 1 && k.i + 3 <= t.count_x && k.j + 3 <= t.count_y)
        .min_by(|a, b| dist(a).total_cmp(&dist(b)))
        .cloned()
}

/// The symmetry cell of the interior tooth nearest the die centre, on a grid of about
/// `step_um`.
pub fn tooth_cell(masks: &MaskSet, teeth: &Teeth, step_um: f64) -> Result<ToothCell, SimError> {
    let name = masks.tooth_cell.as_deref().ok_or(SimError::NoTeeth)?;
    let tooth = interior_tooth(masks, teeth).ok_or(SimError::NoInteriorTooth {
        count_x: teeth.count_x,
        count_y: teeth.count_y,
    })?;
    let half = teeth.top_um / 2.0;
    let (x0, y0) = (tooth.x_um + half, tooth.y_um + half);
    let (lx, ly) = (teeth.pitch_x_um, teeth.pitch_y_um);
    let grid = Grid::covering(x0, y0, lx, ly, step_um)?;
    let shape = masks.flatten(name, LayerKind::FrontSi);
    let (wx1, wy1) = (x0 + lx, y0 + ly);
    let mut polygons = Vec::new();
    let mut tooth_centres_um = Vec::new();
    for k in &masks.teeth {
        let c = (k.x_um + half, k.y_um + half);
        if c.0 >= x0 - 1e-6 && c.0 <= wx1 + 1e-6 && c.1 >= y0 - 1e-6 && c.1 <= wy1 + 1e-6 {
            tooth_centres_um.push(c);
        }
        for p in crate::layout::boolean::translate(&shape, k.x_um, k.y_um) {
            let Some(r) = p.bounding_rect() else { continue };
            if r.max().x >= x0 && r.min().x <= wx1 && r.max().y >= y0 && r.min().y <= wy1 {
                polygons.push(p);
            }
        }
    }
    let drawn = rasterise(&grid, &polygons);
    Ok(ToothCell {
        grid,
        drawn,
        tooth,
        polygons,
        tooth_centres_um,
        top_um: teeth.top_um,
    })
}

/// The closed raster of `polygons` on `grid`: a node on a drawn edge is under the mask.
pub fn rasterise(grid: &Grid, polygons: &[Polygon]) -> Vec<bool> {
    let boxes: Vec<_> = polygons.iter().filter_map(|p| p.bounding_rect()).collect();
    let mut drawn = Vec::with_capacity(grid.len());
    for j in 0..grid.ny {
        for i in 0..grid.nx {
            let c = Coord {
                x: grid.x_um(i),
                y: grid.y_um(j),
            };
            drawn.push(polygons.iter().zip(&boxes).any(|(p, b)| {
                c.x >= b.min().x
                    && c.x <= b.max().x
                    && c.y >= b.min().y
                    && c.y <= b.max().y
                    && p.intersects(&c)
            }));
        }
    }
    drawn
}
