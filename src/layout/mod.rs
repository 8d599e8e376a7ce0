//! Mask layout: [`Process`] + [`EtchPlan`] -> [`MaskSet`] (polygons per layer in f64 um, geo
//! types).
//!
//! One file per idea: the boolean adapter ([`boolean`], the only place booleans happen), the
//! front teeth with corner compensation ([`teeth`]), the back supports ([`supports`]), the PVDF
//! electrodes ([`electrodes`]), alignment marks ([`marks`]), polygon text ([`font`], [`text`],
//! [`labels`]), wafer stepping ([`wafer`]) and the data model ([`maskset`]). Coordinates are die
//! coordinates (origin at the die's lower-left corner, x along the length) in um, snapped to the
//! 1 nm database grid; the export module alone turns them into integers.

pub mod boolean;
pub mod electrodes;
pub mod font;
pub mod labels;
pub mod marks;
pub mod maskset;
mod props;
pub mod supports;
pub mod teeth;
pub mod text;
pub mod wafer;

use std::f64::consts::PI;

use geo::{Coord, LineString, Polygon};

pub use maskset::{
    Cell, Electrode, ElectrodeSide, LayerKind, MaskEntry, MaskSet, Note, Placement, Tooth,
};

use crate::etch::{CompensationDesign, EtchPlan};
use crate::finding::{At, Finding, LayoutCode};
use crate::process::{CompensationGeometry, MaskPurpose, Process, Side, TeethPattern, Tone};
use crate::spelling::yaml;

use boolean::{rect, snap, translate};
use marks::{mark, MarkKind, MARK_KEEPOUT_HALF_UM};

/// Why no mask set could be made from a (validated) process.
#[derive(Debug, thiserror::Error)]
pub enum LayoutError {
    #[error("the electrodes do not fit: {0}")]
    Electrodes(String),
    #[error("no die fits on the {diameter_mm} mm wafer with a {exclusion_mm} mm edge exclusion")]
    NoDie { diameter_mm: f64, exclusion_mm: f64 },
    /// A corner-attached square pulled in by its whole side lies inside the tooth: no
    /// compensation.
    #[error(
        "layout.compensation_overlap_um = {overlap_um} um is not smaller than the {side_um:.1} um \
         compensator: the square would lie inside the tooth\n  hint: keep the overlap a few um \
         (default 10)"
    )]
    CompensationOverlap { overlap_um: f64, side_um: f64 },
}

/// The layer a mask of this purpose is made from.
pub fn layer_of(purpose: MaskPurpose) -> LayerKind {
    match purpose {
        MaskPurpose::FrontSi => LayerKind::FrontSi,
        MaskPurpose::BackSi => LayerKind::BackSi,
        MaskPurpose::Pvdf => LayerKind::Pvdf,
    }
}

/// The first front-side compensation design of the plan.
pub fn front_compensation(plan: &EtchPlan) -> Option<CompensationDesign> {
    plan.steps
        .iter()
        .filter(|s| matches!(s.side, Side::Front | Side::Both))
        .find_map(|s| s.compensation)
}

/// GDS structure name: upper case, `-` to `_`.
fn cell_name(device: &str, what: &str) -> String {
    format!("{}_{what}", device.to_uppercase().replace('-', "_"))
}

/// Builds the mask set.
pub fn build(p: &Process, plan: &EtchPlan) -> Result<MaskSet, LayoutError> {
    let g = &p.geometry;
    let lay = &p.layout;
    let (l, w) = (g.die_length_um, g.die_width_um);
    let mut warnings = Vec::new();
    let mut cells = std::collections::BTreeMap::new();

    // Front: tooth cell and its instances.
    let comp = front_compensation(plan);
    if let Some(c) = comp
        .as_ref()
        .filter(|c| c.kind == CompensationGeometry::CornerAttached)
    {
        if lay.compensation_overlap_um >= c.side_um {
            return Err(LayoutError::CompensationOverlap {
                overlap_um: lay.compensation_overlap_um,
                side_um: c.side_um,
            });
        }
    }
    let teeth = teeth::teeth(&g.teeth);
    let tooth_name = cell_name(&p.device.name, "TOOTH");
    let die_name = cell_name(&p.device.name, "DIE");
    let wafer_name = cell_name(&p.device.name, "WAFER");
    let mut die = Cell::default();
    let tooth_cell = if g.teeth.pattern != TeethPattern::None && !teeth.is_empty() {
        let mut c = Cell::default();
        c.add(
            LayerKind::FrontSi,
            teeth::tooth_cell(g.teeth.top_um, comp.as_ref(), lay.compensation_overlap_um),
        );
        cells.insert(tooth_name.clone(), c);
        for t in &teeth {
            die.placements
                .push(Placement::single(&tooth_name, t.x_um, t.y_um));
        }
        Some(tooth_name.clone())
    } else {
        None
    };
    if let Some(c) = &comp {
        die.note(
            format!(
                "TEETH {} {} X {} UM, {} COMPENSATION {:.1} UM",
                yaml(&g.teeth.pattern),
                g.teeth.top_um,
                g.teeth.top_um,
                yaml(&c.kind),
                c.side_um
            )
            .to_uppercase(),
            l / 2.0,
            w / 2.0,
        );
    }

    // Back: supports; the U-channel is what is not drawn.
    die.add(
        LayerKind::BackSi,
        supports::supports(l, w, g.support_width_um),
    );
    die.note("U-CHANNEL (BACK, ETCHED)", l / 2.0, w / 2.0 - 500.0);

    // PVDF electrodes.
    let e = &g.electrodes;
    let unit_w = (l - 2.0 * e.edge_margin_um - f64::from(e.units.saturating_sub(1)) * e.gap_um)
        / f64::from(e.units.max(1));
    if unit_w < e.wire_pad_um
        || g.support_width_um - e.gap_um / 2.0 - e.edge_margin_um < e.wire_pad_um
    {
        return Err(LayoutError::Electrodes(format!(
            "islands of {unit_w:.0} um along x and {:.0} um across the supports cannot hold a {} \
             um wire pad",
            g.support_width_um - e.gap_um / 2.0 - e.edge_margin_um,
            e.wire_pad_um
        )));
    }
    let electrodes = electrodes::islands(e, l, w, g.support_width_um);
    for el in &electrodes {
        die.add(LayerKind::Pvdf, [el.polygon.clone()]);
        let r = geo::BoundingRect::bounding_rect(&el.polygon).expect("island");
        die.note(
            el.name.clone(),
            (r.min().x + r.max().x) / 2.0,
            (r.min().y + r.max().y) / 2.0,
        );
        die.note(
            format!("{} WIRE PAD", el.name),
            el.pad[0] + el.pad[2] / 2.0,
            el.pad[1] + el.pad[2] / 2.0,
        );
    }
    die.note(
        "COMMON BACK ELECTRODE: UNPATTERNED AL ON THE FILM BACK (10TH WIRE)",
        l / 2.0,
        w / 2.0 + 500.0,
    );

    // Die outline.
    die.add(LayerKind::Outline, [rect(0.0, 0.0, l, w)]);

    // Labels on every printing layer.
    let masks: Vec<MaskEntry> = p
        .masks
        .iter()
        .map(|m| MaskEntry {
            name: m.name.clone(),
            purpose: m.purpose,
            side: m.side,
            tone: m.tone,
            layer: layer_of(m.purpose),
            gds: layer_of(m.purpose).gds(&lay.layers),
            mirrored: m.mirrored,
            chrome: match m.tone {
                Tone::LightField => "chrome = drawn shape (light field)".into(),
                Tone::DarkField => "chrome = outside the drawn shape (dark field)".into(),
            },
        })
        .collect();
    let pixel = lay.label_pixel_um;
    let clearance = (p.drc.min_space_um * 2.0).max(150.0);
    let mut front_obstacles = Vec::new();
    if let Some(t) = &tooth_cell {
        let tc = cells
            .get(t)
            .expect("tooth cell")
            .shapes
            .get(&LayerKind::FrontSi)
            .cloned()
            .unwrap_or_default();
        for tooth in &teeth {
            front_obstacles.extend(translate(&tc, tooth.x_um, tooth.y_um));
        }
    }
    for m in &masks {
        let layer = m.layer;
        let obstacles = match layer {
            LayerKind::FrontSi => front_obstacles.clone(),
            _ => die.shapes.get(&layer).cloned().unwrap_or_default(),
        };
        let device = text::printable(&p.device.name);
        let name = text::printable(&m.name);
        let rev = format!("REV {}", text::printable(&p.device.revision));
        let choices = [
            vec![device.clone(), name.clone(), rev.clone()],
            vec![format!("{device} {name} {rev}")],
        ];
        let spot = choices.iter().find_map(|lines| {
            labels::find_spot(lines, pixel, &obstacles, l, w, clearance).map(|s| (lines, s))
        });
        match spot {
            Some((lines, (x, y))) => {
                die.add(layer, text::text_polygons(lines, x, y, pixel));
                if matches!(layer, LayerKind::FrontSi | LayerKind::BackSi) {
                    let depth = plan.steps.iter().map(|s| s.depth_um).fold(0.0, f64::max);
                    if pixel < 2.0 * depth {
                        warnings.push(
                            Finding::warning(
                                LayoutCode::LabelOnDeepEtch,
                                format!(
                                "mask `{}`: label strokes of {pixel} um are undercut away by the \
                                 {depth} um etch: the label identifies the mask plate, not the \
                                 etched die",
                                m.name
                            ),
                            )
                            .at(At::Mask(m.name.clone())),
                        );
                    }
                }
            }
            None => warnings.push(
                Finding::warning(
                    LayoutCode::LabelNoRoom,
                    format!(
                    "mask `{}`: no free spot on layer {} for a {pixel} um-pixel label; none drawn",
                    m.name,
                    layer.name()
                ),
                )
                .at(At::Mask(m.name.clone())),
            ),
        }
    }
    cells.insert(die_name.clone(), die);

    // Wafer: stepped dies, alignment marks on the x axis, wafer and usable edge outlines.
    let r_usable = p.wafer.diameter_mm * 500.0 - lay.edge_exclusion_mm * 1000.0;
    let stepping = wafer::step(l, w, g.dicing_street_um, r_usable, MARK_KEEPOUT_HALF_UM);
    if stepping.origins.is_empty() {
        return Err(LayoutError::NoDie {
            diameter_mm: p.wafer.diameter_mm,
            exclusion_mm: lay.edge_exclusion_mm,
        });
    }
    let origins: Vec<Coord> = stepping
        .origins
        .iter()
        .map(|c| Coord {
            x: snap(c.x),
            y: snap(c.y),
        })
        .collect();
    let (px, py) = (l + g.dicing_street_um, w + g.dicing_street_um);
    let mut wafer_cell = Cell {
        placements: wafer::arrays(&die_name, &origins, px, py),
        ..Cell::default()
    };
    for site in stepping.mark_sites {
        let (x, y) = (snap(site.x), snap(site.y));
        let front = mark(MarkKind::Front, x, y);
        let back = mark(MarkKind::Back, x, y);
        for m in &masks {
            let kind = if m.side == Side::Back { &back } else { &front };
            wafer_cell.add(m.layer, kind.iter().cloned());
        }
        // Overlaid but not merged: front and back ticks meet at single points.
        wafer_cell.add(
            LayerKind::Marks,
            front.iter().cloned().chain(back.iter().cloned()),
        );
        wafer_cell.note(
            "ALIGNMENT MARK: FRONT CROSS 50 UM VERNIER, BACK CROSS 52 UM VERNIER",
            x,
            y + MARK_KEEPOUT_HALF_UM,
        );
    }
    wafer_cell.add(
        LayerKind::Outline,
        [circle(p.wafer.diameter_mm * 500.0), circle(r_usable)],
    );
    wafer_cell.note(
        format!(
            "{} REV {} WAFER {} MM",
            p.device.name.to_uppercase(),
            p.device.revision,
            p.wafer.diameter_mm
        ),
        0.0,
        -r_usable,
    );
    cells.insert(wafer_name.clone(), wafer_cell);

    Ok(MaskSet {
        device: p.device.name.clone(),
        revision: p.device.revision.clone(),
        layers: lay.layers.clone(),
        cells,
        tooth_cell,
        die_cell: die_name,
        wafer_cell: wafer_name,
        die_length_um: l,
        die_width_um: w,
        pitch_x_um: px,
        pitch_y_um: py,
        wafer_diameter_um: p.wafer.diameter_mm * 1000.0,
        edge_exclusion_um: lay.edge_exclusion_mm * 1000.0,
        die_origins: origins,
        teeth,
        tooth_top_um: g.teeth.top_um,
        electrodes,
        masks,
        warnings,
    })
}

/// A 720-gon circle centred on the origin (non-printing outline).
fn circle(radius_um: f64) -> Polygon {
    let n = 720;
    let ring: Vec<Coord> = (0..=n)
        .map(|k| {
            let a = 2.0 * PI * f64::from(k % n) / f64::from(n);
            Coord {
                x: snap(radius_um * a.cos()),
                y: snap(radius_um * a.sin()),
            }
        })
        .collect();
    Polygon::new(LineString::new(ring), vec![])
}
