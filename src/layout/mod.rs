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
pub mod test_die;
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
    let mut cells = std::collections::BTreeMap::new();

    let comp = front_compensation(plan);
    check_compensation_overlap(lay.compensation_overlap_um, comp.as_ref())?;
    let teeth = teeth::teeth(&g.teeth);
    let tooth_name = cell_name(&p.device.name, "TOOTH");
    let die_name = cell_name(&p.device.name, "DIE");
    let wafer_name = cell_name(&p.device.name, "WAFER");
    let mut die = Cell::default();
    let tooth_cell = tooth_cell(p, comp.as_ref(), &teeth).map(|c| {
        cells.insert(tooth_name.clone(), c);
        place_teeth(&mut die, &tooth_name, &teeth);
        tooth_name.clone()
    });
    // The die carries short labels only (its electrodes' names): it is repeated over the wafer,
    // where KLayout draws every text at screen size, so longer notes there overlap into clutter.
    // The die's description goes once into the wafer cell's legend.
    let mut legend = Vec::new();
    if let Some(c) = &comp {
        legend.push(teeth_note(p, c));
    }
    add_supports(&mut die, p);
    legend.push("U-CHANNEL ON THE BACK (ETCHED)".to_string());
    let electrodes = add_electrodes(&mut die, p, plan)?;
    legend.push(format!(
        "COMMON BACK ELECTRODE: UNPATTERNED AL ON THE FILM BACK ({}TH WIRE)",
        electrodes.len() + 1
    ));
    die.add(LayerKind::Outline, [rect(0.0, 0.0, l, w)]);

    let masks = mask_entries(p);
    let front_obstacles = front_obstacles(&cells, tooth_cell.as_deref(), &teeth);
    let warnings = add_labels(&mut die, p, plan, &masks, &front_obstacles);
    cells.insert(die_name.clone(), die);

    let (px, py) = (l + g.dicing_street_um, w + g.dicing_street_um);
    let test_die = test_die::build(p, plan, &cell_name(&p.device.name, "TEST_DIE"));
    let wants_test_die = p.layout.test_die.enabled;
    let built_test_die = test_die.is_some();
    let (wafer_cell, origins, test_die, no_room) =
        wafer_cell(p, &masks, &die_name, &legend, test_die)?;
    let mut warnings = warnings;
    if let Some((tw, th)) = no_room {
        warnings.push(Finding::warning(
            LayoutCode::TestDieNoRoom,
            format!(
                "the {:.1} x {:.1} mm test die finds no room on the wafer clear of the dies and \
                 marks; none drawn (a smaller layout.test_die.span_um or a larger step_um)",
                tw / 1000.0,
                th / 1000.0
            ),
        ));
    } else if wants_test_die && !built_test_die {
        warnings.push(Finding::warning(
            LayoutCode::TestDieNoRoom,
            "no ladder a is larger than layout.compensation_overlap_um (the front etch is too \
             shallow for layout.test_die.span_um); no test die drawn",
        ));
    }
    cells.insert(wafer_name.clone(), wafer_cell);
    let test_die = test_die.map(|(c, info)| {
        cells.insert(info.cell.clone(), c);
        info
    });

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
        test_die,
    })
}

/// A corner-attached square pulled in by its whole side lies inside the tooth: refuse it.
fn check_compensation_overlap(
    overlap_um: f64,
    comp: Option<&CompensationDesign>,
) -> Result<(), LayoutError> {
    match comp.filter(|c| c.kind == CompensationGeometry::CornerAttached) {
        Some(c) if overlap_um >= c.side_um => Err(LayoutError::CompensationOverlap {
            overlap_um,
            side_um: c.side_um,
        }),
        _ => Ok(()),
    }
}

/// The tooth cell (top square plus compensators on the front Si layer), when there are teeth.
fn tooth_cell(p: &Process, comp: Option<&CompensationDesign>, teeth: &[Tooth]) -> Option<Cell> {
    let g = &p.geometry;
    if g.teeth.pattern == TeethPattern::None || teeth.is_empty() {
        return None;
    }
    let mut c = Cell::default();
    c.add(
        LayerKind::FrontSi,
        teeth::tooth_cell(g.teeth.top_um, comp, p.layout.compensation_overlap_um),
    );
    Some(c)
}

/// One placement of the tooth cell per tooth.
fn place_teeth(die: &mut Cell, tooth_name: &str, teeth: &[Tooth]) {
    for t in teeth {
        die.placements
            .push(Placement::single(tooth_name, t.x_um, t.y_um));
    }
}

/// The legend line naming the tooth pattern, size and compensation.
fn teeth_note(p: &Process, c: &CompensationDesign) -> String {
    let g = &p.geometry;
    let width = c
        .bar_width_um
        .map_or(String::new(), |b| format!(" X {b:.1} UM"));
    format!(
        "DIE TEETH {} {} X {} UM, {} COMPENSATION {:.1} UM{width}",
        yaml(&g.teeth.pattern),
        g.teeth.top_um,
        g.teeth.top_um,
        yaml(&c.kind),
        c.side_um
    )
    .to_uppercase()
}

/// Back: the supports; the U-channel is what is not drawn.
fn add_supports(die: &mut Cell, p: &Process) {
    let g = &p.geometry;
    let (l, w) = (g.die_length_um, g.die_width_um);
    die.add(
        LayerKind::BackSi,
        supports::supports(l, w, g.support_width_um),
    );
}

/// The PVDF electrode islands with their names and wire pads, after checking a pad fits on each.
fn add_electrodes(
    die: &mut Cell,
    p: &Process,
    plan: &EtchPlan,
) -> Result<Vec<Electrode>, LayoutError> {
    let g = &p.geometry;
    let (l, w) = (g.die_length_um, g.die_width_um);
    let e = &g.electrodes;
    let wall = electrodes::Wall {
        support_edge_um: plan.channel_wall_y_um[0],
        floor_edge_um: plan.channel_wall_y_um[1],
    };
    let unit_w = (l - 2.0 * e.edge_margin_um - f64::from(e.units.saturating_sub(1)) * e.gap_um)
        / f64::from(e.units.max(1));
    let across = wall.middle_um() - e.gap_um / 2.0 - e.edge_margin_um;
    if unit_w < e.wire_pad_um || across < e.wire_pad_um {
        return Err(LayoutError::Electrodes(format!(
            "islands of {unit_w:.0} um along x and {across:.0} um across the supports cannot hold \
             a {} um wire pad",
            e.wire_pad_um
        )));
    }
    let electrodes = electrodes::islands(e, l, w, wall);
    for el in &electrodes {
        die.add(LayerKind::Pvdf, [el.polygon.clone()]);
        let r = geo::BoundingRect::bounding_rect(&el.polygon).expect("island");
        die.note(
            el.name.clone(),
            (r.min().x + r.max().x) / 2.0,
            (r.min().y + r.max().y) / 2.0,
        );
    }
    Ok(electrodes)
}

/// The mask inventory of the process: layer, GDS layer/datatype and chrome tone per mask.
fn mask_entries(p: &Process) -> Vec<MaskEntry> {
    p.masks
        .iter()
        .map(|m| MaskEntry {
            name: m.name.clone(),
            purpose: m.purpose,
            side: m.side,
            tone: m.tone,
            layer: layer_of(m.purpose),
            gds: layer_of(m.purpose).gds(&p.layout.layers),
            mirrored: m.mirrored,
            chrome: match m.tone {
                Tone::LightField => "chrome = drawn shape (light field)".into(),
                Tone::DarkField => "chrome = outside the drawn shape (dark field)".into(),
            },
        })
        .collect()
}

/// Every tooth's front Si shapes in die coordinates: what a front label must avoid.
fn front_obstacles(
    cells: &std::collections::BTreeMap<String, Cell>,
    tooth_cell: Option<&str>,
    teeth: &[Tooth],
) -> Vec<Polygon> {
    let mut front_obstacles = Vec::new();
    if let Some(t) = tooth_cell {
        let tc = cells
            .get(t)
            .expect("tooth cell")
            .shapes
            .get(&LayerKind::FrontSi)
            .cloned()
            .unwrap_or_default();
        for tooth in teeth {
            front_obstacles.extend(translate(&tc, tooth.x_um, tooth.y_um));
        }
    }
    front_obstacles
}

/// A label (device, mask name, revision) on every printing layer where it finds room; returns
/// the warnings for labels not drawn or undercut away by the etch.
fn add_labels(
    die: &mut Cell,
    p: &Process,
    plan: &EtchPlan,
    masks: &[MaskEntry],
    front_obstacles: &[Polygon],
) -> Vec<Finding> {
    let g = &p.geometry;
    let (l, w) = (g.die_length_um, g.die_width_um);
    let pixel = p.layout.label_pixel_um;
    let mut warnings = Vec::new();
    for m in masks {
        let layer = m.layer;
        // A label obeys the rules of the layer it is drawn on: on the PVDF mask it keeps the
        // electrode gap from the islands (it is metal like them).
        let clearance = match layer {
            LayerKind::Pvdf => p.drc.min_electrode_gap_um,
            _ => 0.0,
        }
        .max((p.drc.min_space_um * 2.0).max(150.0));
        let obstacles = match layer {
            LayerKind::FrontSi => front_obstacles.to_vec(),
            _ => die.shapes.get(&layer).cloned().unwrap_or_default(),
        };
        let device = text::printable(&p.device.name);
        let name = text::printable(&m.name);
        let rev = format!("REV {}", text::printable(&p.device.revision));
        let choices = [
            vec![device.clone(), name.clone(), rev.clone()],
            vec![format!("{device} {name} {rev}")],
        ];
        // The configured pixel first, then smaller ones down to twice the minimum width (the
        // strokes must still print), before giving up on a label.
        let pixels = [1.0, 0.8, 0.6]
            .map(|f| f * pixel)
            .into_iter()
            .filter(|&px| px == pixel || px >= 2.0 * p.drc.min_width_um);
        let spot = pixels.into_iter().find_map(|px| {
            choices.iter().find_map(|lines| {
                labels::find_spot(lines, px, &obstacles, l, w, clearance).map(|s| (lines, s, px))
            })
        });
        match spot {
            Some((lines, (x, y), px)) => {
                die.add(layer, text::text_polygons(lines, x, y, px));
                warnings.extend(label_undercut(plan, m, px));
            }
            None => warnings.push(
                Finding::warning(
                    LayoutCode::LabelNoRoom,
                    format!(
                        "mask `{}`: no free spot on layer {} for a label ({pixel} um pixels or \
                     smaller, {clearance} um from every shape); none drawn",
                        m.name,
                        layer.name()
                    ),
                )
                .at(At::Mask(m.name.clone())),
            ),
        }
    }
    warnings
}

/// A silicon mask's label strokes narrower than twice the deepest etch are undercut away.
fn label_undercut(plan: &EtchPlan, m: &MaskEntry, pixel: f64) -> Option<Finding> {
    if !matches!(m.layer, LayerKind::FrontSi | LayerKind::BackSi) {
        return None;
    }
    let depth = plan.steps.iter().map(|s| s.depth_um).fold(0.0, f64::max);
    (pixel < 2.0 * depth).then(|| {
        Finding::warning(
            LayoutCode::LabelOnDeepEtch,
            format!(
                "mask `{}`: label strokes of {pixel} um are undercut away by the {depth} um etch: \
                 the label identifies the mask plate, not the etched die",
                m.name
            ),
        )
        .at(At::Mask(m.name.clone()))
    })
}

/// The wafer cell: stepped dies, alignment marks on an axis, wafer and usable edge outlines;
/// also returns the snapped die origins.
fn wafer_cell(
    p: &Process,
    masks: &[MaskEntry],
    die_name: &str,
    legend: &[String],
    test_die: Option<(Cell, test_die::TestDieInfo)>,
) -> Result<WaferCell, LayoutError> {
    let g = &p.geometry;
    let lay = &p.layout;
    let (l, w) = (g.die_length_um, g.die_width_um);
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
        placements: wafer::arrays(die_name, &origins, px, py),
        ..Cell::default()
    };
    for site in stepping.mark_sites {
        add_alignment_marks(&mut wafer_cell, masks, snap(site.x), snap(site.y));
    }
    let mut no_room = None;
    let test_die = match test_die {
        None => None,
        Some((cell, mut info)) => {
            let [tw, th] = info.size_um;
            let at = test_die::place(
                tw,
                th,
                &origins,
                l,
                w,
                g.dicing_street_um,
                r_usable,
                &stepping.mark_sites,
                MARK_KEEPOUT_HALF_UM,
            )
            .map(|at| {
                let (x, y) = (snap(at.x), snap(at.y));
                wafer_cell
                    .placements
                    .push(Placement::single(&info.cell, x, y));
                info.origin_um = [x, y];
                (cell, info)
            });
            if at.is_none() {
                no_room = Some((tw, th));
            }
            at
        }
    };
    let r_wafer = p.wafer.diameter_mm * 500.0;
    wafer_cell.add(LayerKind::WaferOutline, [circle(r_wafer), circle(r_usable)]);
    wafer_cell.note(
        format!(
            "{} REV {} WAFER {} MM",
            p.device.name.to_uppercase(),
            p.device.revision,
            p.wafer.diameter_mm
        ),
        -r_wafer,
        -r_wafer - 2000.0,
    );
    // The die's description once, under the title, a line every 2 mm (clear of the dies and the
    // marks on the wafer's axes).
    for (k, line) in legend.iter().enumerate() {
        wafer_cell.note(line.clone(), -r_wafer, -r_wafer - 2000.0 * (k as f64 + 2.0));
    }
    Ok((wafer_cell, origins, test_die, no_room))
}

/// The wafer cell, the die origins and the placed test die.
/// (the wafer cell, die origins, the placed test die, the size of a test die that found no room).
type WaferCell = (
    Cell,
    Vec<Coord>,
    Option<(Cell, test_die::TestDieInfo)>,
    Option<(f64, f64)>,
);

/// Front and back alignment marks at one site: on each mask's layer by its side, and overlaid on
/// the reference marks layer.
fn add_alignment_marks(wafer_cell: &mut Cell, masks: &[MaskEntry], x: f64, y: f64) {
    let front = mark(MarkKind::Front, x, y);
    let back = mark(MarkKind::Back, x, y);
    for m in masks {
        let kind = if m.side == Side::Back { &back } else { &front };
        wafer_cell.add(m.layer, kind.iter().cloned());
    }
    // Overlaid but not merged: front and back ticks meet at single points.
    wafer_cell.add(
        LayerKind::Marks,
        front.iter().cloned().chain(back.iter().cloned()),
    );
    wafer_cell.note(
        "ALIGN: FRONT 50 UM, BACK 52 UM VERNIER",
        x,
        y + MARK_KEEPOUT_HALF_UM,
    );
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
