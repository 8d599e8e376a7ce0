//! The mask set as data: cells of polygons per layer (f64 um, geo types), references, the mask
//! inventory and the layout's own warnings. Export (GDS, SVG, lyp) reads this and nothing else.

use std::collections::BTreeMap;

use geo::{Coord, Polygon};
use serde::Serialize;

use crate::finding::Finding;
use crate::process::{GdsLayer, LayerMap, MaskPurpose, Side, Tone};

use super::boolean::translate;

/// What a layer holds. The drawn shape is what remains on the wafer (or film).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LayerKind {
    FrontSi,
    BackSi,
    Pvdf,
    Marks,
    Annotation,
    /// The die outline (its YAML and lyp name is `die_outline`).
    Outline,
    /// The wafer edge and usable-area circles, in the wafer cell.
    WaferOutline,
}

impl LayerKind {
    pub const ALL: [LayerKind; 7] = [
        LayerKind::FrontSi,
        LayerKind::BackSi,
        LayerKind::Pvdf,
        LayerKind::Marks,
        LayerKind::Annotation,
        LayerKind::Outline,
        LayerKind::WaferOutline,
    ];

    /// Logical layer name (lyp, SVG group id, reports).
    pub fn name(self) -> &'static str {
        match self {
            LayerKind::FrontSi => "front_si",
            LayerKind::BackSi => "back_si",
            LayerKind::Pvdf => "pvdf",
            LayerKind::Marks => "marks",
            LayerKind::Annotation => "annotation",
            LayerKind::Outline => "die_outline",
            LayerKind::WaferOutline => "wafer_outline",
        }
    }

    /// What the drawn shapes mean.
    pub fn meaning(self) -> &'static str {
        match self {
            LayerKind::FrontSi => {
                "front Si kept (teeth tops + compensation), label, front alignment marks"
            }
            LayerKind::BackSi => {
                "back Si kept (supports; the U-channel between them is etched), label, back \
                 alignment marks"
            }
            LayerKind::Pvdf => {
                "Al kept on the PVDF film (electrode islands with wire pads), label, marks"
            }
            LayerKind::Marks => {
                "reference copy of all alignment marks (front and back overlaid); does not print \
                 by itself"
            }
            LayerKind::Annotation => "non-printing notes (GDS TEXT)",
            LayerKind::Outline => {
                "die outline; dicing streets lie between outlines; does not print"
            }
            LayerKind::WaferOutline => {
                "wafer edge and the usable area inside the edge exclusion; does not print"
            }
        }
    }

    /// Whether a mask is made from this layer.
    pub fn printing(self) -> bool {
        matches!(
            self,
            LayerKind::FrontSi | LayerKind::BackSi | LayerKind::Pvdf
        )
    }

    /// The GDS layer/datatype from the process file's layer map.
    pub fn gds(self, map: &LayerMap) -> GdsLayer {
        match self {
            LayerKind::FrontSi => map.front_si,
            LayerKind::BackSi => map.back_si,
            LayerKind::Pvdf => map.pvdf,
            LayerKind::Marks => map.marks,
            LayerKind::Annotation => map.annotation,
            LayerKind::Outline => map.outline,
            LayerKind::WaferOutline => map.wafer_outline,
        }
    }

    /// Display colour (lyp, SVG).
    pub fn colour(self) -> &'static str {
        match self {
            LayerKind::FrontSi => "#1f77b4",
            LayerKind::BackSi => "#2ca02c",
            LayerKind::Pvdf => "#d62728",
            LayerKind::Marks => "#ff7f0e",
            LayerKind::Annotation => "#bcbd22",
            LayerKind::Outline => "#808080",
            LayerKind::WaferOutline => "#404040",
        }
    }
}

/// A non-printing note: GDS TEXT on the annotation layer.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Note {
    pub text: String,
    pub x_um: f64,
    pub y_um: f64,
}

/// A placement of another cell, optionally as an n x m array.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Placement {
    pub cell: String,
    pub x_um: f64,
    pub y_um: f64,
    pub cols: u16,
    pub rows: u16,
    pub pitch_x_um: f64,
    pub pitch_y_um: f64,
}

impl Placement {
    pub fn single(cell: &str, x_um: f64, y_um: f64) -> Self {
        Placement {
            cell: cell.to_string(),
            x_um,
            y_um,
            cols: 1,
            rows: 1,
            pitch_x_um: 0.0,
            pitch_y_um: 0.0,
        }
    }
    /// Origins of every instance.
    pub fn origins(&self) -> Vec<Coord> {
        let mut out = Vec::new();
        for r in 0..self.rows {
            for c in 0..self.cols {
                out.push(Coord {
                    x: self.x_um + f64::from(c) * self.pitch_x_um,
                    y: self.y_um + f64::from(r) * self.pitch_y_um,
                });
            }
        }
        out
    }
    /// True when this is an array (exported as AREF) rather than a single reference.
    pub fn is_array(&self) -> bool {
        self.cols > 1 || self.rows > 1
    }
}

/// One cell: polygons per layer, notes, placements of other cells.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Cell {
    pub shapes: BTreeMap<LayerKind, Vec<Polygon>>,
    pub notes: Vec<Note>,
    pub placements: Vec<Placement>,
}

impl Cell {
    pub fn add(&mut self, layer: LayerKind, polys: impl IntoIterator<Item = Polygon>) {
        self.shapes.entry(layer).or_default().extend(polys);
    }
    pub fn note(&mut self, text: impl Into<String>, x_um: f64, y_um: f64) {
        self.notes.push(Note {
            text: text.into(),
            x_um,
            y_um,
        });
    }
}

/// One mask of the inventory.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MaskEntry {
    pub name: String,
    pub purpose: MaskPurpose,
    pub side: Side,
    pub tone: Tone,
    pub layer: LayerKind,
    pub gds: GdsLayer,
    /// The shop receives this mask mirrored (x -> die_length - x per die).
    pub mirrored: bool,
    /// Chrome where the drawn shape is (light field) or where it is not (dark field).
    pub chrome: String,
}

/// Where an electrode island sits across the die: what it reads depends on it (thickness mode
/// under a support, extension mode over the plate).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ElectrodeSide {
    /// Over support 1 (y = 0 .. support width).
    Support1,
    /// Over the plate spanning the U-channel.
    Middle,
    /// Over support 2 (y = width - support width .. width).
    Support2,
}

/// One electrode island of the PVDF mask.
#[derive(Debug, Clone, PartialEq)]
pub struct Electrode {
    /// S11..S13, M1..M3, S21..S23.
    pub name: String,
    pub side: ElectrodeSide,
    pub polygon: Polygon,
    /// The wire pad square (part of the island), lower-left and side.
    pub pad: [f64; 3],
}

/// One tooth instance: its cell placement and top square (for DRC).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Tooth {
    pub i: u32,
    pub j: u32,
    /// Lower-left corner of the tooth top.
    pub x_um: f64,
    pub y_um: f64,
}

/// The whole mask set.
#[derive(Debug, Clone, PartialEq)]
pub struct MaskSet {
    pub device: String,
    pub revision: String,
    pub layers: LayerMap,
    /// Cells by name; names are GDS structure names.
    pub cells: BTreeMap<String, Cell>,
    pub tooth_cell: Option<String>,
    pub die_cell: String,
    pub wafer_cell: String,
    pub die_length_um: f64,
    pub die_width_um: f64,
    /// Die pitch on the wafer (die + dicing street).
    pub pitch_x_um: f64,
    pub pitch_y_um: f64,
    pub wafer_diameter_um: f64,
    pub edge_exclusion_um: f64,
    /// Lower-left corners of the dies on the wafer (wafer centre at 0, 0).
    pub die_origins: Vec<Coord>,
    pub teeth: Vec<Tooth>,
    pub tooth_top_um: f64,
    pub electrodes: Vec<Electrode>,
    pub masks: Vec<MaskEntry>,
    pub warnings: Vec<Finding>,
    /// The compensation test die, when the process asks for one (its cell is in `cells` and
    /// placed once in the wafer cell).
    pub test_die: Option<super::test_die::TestDieInfo>,
}

impl MaskSet {
    /// Every polygon of `layer` in `cell` and below it, in the cell's coordinates.
    #[track_caller]
    pub fn flatten(&self, cell: &str, layer: LayerKind) -> Vec<Polygon> {
        let c = self
            .cells
            .get(cell)
            .unwrap_or_else(|| panic!("no cell `{cell}` in the mask set"));
        let mut out = c.shapes.get(&layer).cloned().unwrap_or_default();
        for p in &c.placements {
            let inner = self.flatten(&p.cell, layer);
            for o in p.origins() {
                out.extend(translate(&inner, o.x, o.y));
            }
        }
        out
    }

    /// The die's polygons on one layer, drawn (unmirrored) die coordinates.
    pub fn die_layer(&self, layer: LayerKind) -> Vec<Polygon> {
        self.flatten(&self.die_cell, layer)
    }

    /// The die's polygons on one mask as the shop receives them: mirrored about x = L/2 when the
    /// mask says `mirrored: true`.
    pub fn die_mask(&self, mask: &MaskEntry) -> Vec<Polygon> {
        let drawn = self.die_layer(mask.layer);
        if mask.mirrored {
            super::boolean::mirror_x(&drawn, self.die_length_um / 2.0)
        } else {
            drawn
        }
    }

    /// Human-readable inventory: layers, masks with tone and mirroring, what goes where.
    pub fn inventory(&self) -> String {
        let mut out = String::new();
        out.push_str(&format!("mask set {} rev {}\n", self.device, self.revision));
        out.push_str("layers (the drawn shape is what remains on the wafer or film):\n");
        for k in LayerKind::ALL {
            let g = k.gds(&self.layers);
            out.push_str(&format!(
                "  {:>2}/{:<2} {:<12} {}\n",
                g.layer,
                g.datatype,
                k.name(),
                k.meaning()
            ));
        }
        out.push_str("masks:\n");
        for m in &self.masks {
            out.push_str(&format!(
                "  {:<10} layer {}/{} ({}), {} side, {}: {}\n",
                m.name,
                m.gds.layer,
                m.gds.datatype,
                m.layer.name(),
                crate::spelling::yaml(&m.side),
                match m.tone {
                    Tone::LightField => "light field",
                    Tone::DarkField => "dark field",
                },
                m.chrome
            ));
            if m.mirrored {
                out.push_str(&format!(
                    "             MIRRORED for the shop (x -> {} - x per die): `{}-{}.svg` is \
                     mirrored; GDS layer {}/{} is drawn unmirrored in die coordinates, the shop \
                     must mirror it\n",
                    self.die_length_um, self.device, m.name, m.gds.layer, m.gds.datatype
                ));
            } else {
                out.push_str(&format!(
                    "             not mirrored: `{}-{}.svg` and GDS layer {}/{} read as drawn\n",
                    self.device, m.name, m.gds.layer, m.gds.datatype
                ));
            }
        }
        out.push_str(&format!(
            "cells: {} (tooth), {} (die {} x {} mm), {} (wafer {} mm, {} dies at pitch {} x {} \
             um, edge exclusion {} mm)\n",
            self.tooth_cell.as_deref().unwrap_or("-"),
            self.die_cell,
            self.die_length_um / 1000.0,
            self.die_width_um / 1000.0,
            self.wafer_cell,
            self.wafer_diameter_um / 1000.0,
            self.die_origins.len(),
            self.pitch_x_um,
            self.pitch_y_um,
            self.edge_exclusion_um / 1000.0
        ));
        if let Some(t) = &self.test_die {
            out.push_str(&format!(
                "test die: {} at ({}, {}) um on the wafer, {:.1} x {:.1} um, front mask only: {} teeth \
                 with {} compensators a = {} um (left to right; centre from {})\n",
                t.cell,
                t.origin_um[0],
                t.origin_um[1],
                t.size_um[0],
                t.size_um[1],
                t.a_um.len(),
                crate::spelling::yaml(&t.geometry),
                t.a_um
                    .iter()
                    .map(|a| format!("{a:.1}"))
                    .collect::<Vec<_>>()
                    .join(", "),
                t.centre_from
            ));
        }
        out
    }
}

impl MaskSet {
    /// The wafer with every reference expanded: one cell, all polygons (for flat export and the
    /// benchmark against other writers).
    pub fn flattened(&self) -> MaskSet {
        let mut cell = Cell::default();
        for layer in LayerKind::ALL {
            let polys = self.flatten(&self.wafer_cell, layer);
            if !polys.is_empty() {
                cell.add(layer, polys);
            }
        }
        let name = format!("{}_FLAT", self.wafer_cell);
        let mut cells = BTreeMap::new();
        cells.insert(name.clone(), cell);
        MaskSet {
            cells,
            tooth_cell: None,
            test_die: None,
            die_cell: name.clone(),
            wafer_cell: name,
            ..self.clone()
        }
    }
}
