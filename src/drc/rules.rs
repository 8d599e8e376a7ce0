//! Process-aware rules: compensators, tooth bases, etched streets, electrodes.

use geo::{BoundingRect, Distance, Euclidean, Polygon, Rect};

use super::violation;
use crate::etch::EtchPlan;
use crate::finding::{DrcCode, Finding};
use crate::layout::boolean::{rect, translate};
use crate::layout::{front_compensation, LayerKind, MaskSet};
use crate::process::{Process, Side};

fn centre(r: &Rect) -> (f64, f64) {
    ((r.min().x + r.max().x) / 2.0, (r.min().y + r.max().y) / 2.0)
}

fn gap(a: &Polygon, b: &Polygon) -> f64 {
    Euclidean.distance(a, b)
}

/// Bounding boxes closer than `d` (cheap pre-filter).
fn near(a: &Rect, b: &Rect, d: f64) -> bool {
    a.min().x - d < b.max().x
        && b.min().x - d < a.max().x
        && a.min().y - d < b.max().y
        && b.min().y - d < a.max().y
}

/// Compensators colliding or crossing the die edge; tooth bases merging.
pub fn teeth(set: &MaskSet, p: &Process, plan: &EtchPlan) -> Vec<Finding> {
    let mut out = Vec::new();
    let Some(cell) = &set.tooth_cell else {
        return out;
    };
    let tc = set.cells[cell]
        .shapes
        .get(&LayerKind::FrontSi)
        .cloned()
        .unwrap_or_default();
    let inst: Vec<(String, Vec<Polygon>, Rect)> = set
        .teeth
        .iter()
        .map(|t| {
            let ps = translate(&tc, t.x_um, t.y_um);
            let r = crate::layout::boolean::bbox(&ps).expect("tooth");
            (format!("tooth ({}, {})", t.i, t.j), ps, r)
        })
        .collect();
    let (l, w) = (set.die_length_um, set.die_width_um);
    let comp = front_compensation(plan).is_some();
    for (name, _, r) in &inst {
        if r.min().x < 0.0 || r.min().y < 0.0 || r.max().x > l || r.max().y > w {
            let what = if comp {
                "its compensators reach"
            } else {
                "it reaches"
            };
            out.push(violation(
                DrcCode::CompensatorOutsideDie,
                Some(LayerKind::FrontSi),
                centre(r),
                format!(
                    "{name}: {what} x {:.1}..{:.1}, y {:.1}..{:.1} um, beyond the {l} x {w} um die",
                    r.min().x,
                    r.max().x,
                    r.min().y,
                    r.max().y
                ),
            ));
        }
    }
    let min_space = p.drc.min_space_um;
    for i in 0..inst.len() {
        for j in i + 1..inst.len() {
            let (a, b) = (&inst[i], &inst[j]);
            if !near(&a.2, &b.2, min_space) {
                continue;
            }
            let d =
                a.1.iter()
                    .flat_map(|x| b.1.iter().map(move |y| gap(x, y)))
                    .fold(f64::INFINITY, f64::min);
            if d < min_space {
                let (ca, cb) = (centre(&a.2), centre(&b.2));
                out.push(violation(
                    DrcCode::CompensatorsCollide,
                    Some(LayerKind::FrontSi),
                    ((ca.0 + cb.0) / 2.0, (ca.1 + cb.1) / 2.0),
                    format!(
                        "{} and {} are {d:.1} um apart (< {min_space} um): the compensators merge \
                         into a bridge",
                        a.0, b.0
                    ),
                ));
            }
        }
    }
    // Etched bases: top grown by the sidewall run-out of the front etch on each side.
    let Some(step) = plan
        .steps
        .iter()
        .find(|s| matches!(s.side, Side::Front | Side::Both))
    else {
        return out;
    };
    let ro = step.sidewall_run_out_um;
    let top = set.tooth_top_um;
    let bases: Vec<Rect> = set
        .teeth
        .iter()
        .map(|t| {
            Rect::new(
                (t.x_um - ro, t.y_um - ro),
                (t.x_um + top + ro, t.y_um + top + ro),
            )
        })
        .collect();
    for i in 0..bases.len() {
        for j in i + 1..bases.len() {
            let (a, b) = (&bases[i], &bases[j]);
            if near(a, b, 0.0) {
                let (ti, tj) = (&set.teeth[i], &set.teeth[j]);
                let (ca, cb) = (centre(a), centre(b));
                out.push(violation(
                    DrcCode::TeethBasesMerge,
                    Some(LayerKind::FrontSi),
                    ((ca.0 + cb.0) / 2.0, (ca.1 + cb.1) / 2.0),
                    format!(
                        "bases of tooth ({}, {}) and ({}, {}) ({top} um top + 2 x {ro:.1} um \
                         run-out) overlap",
                        ti.i, ti.j, tj.i, tj.j
                    ),
                ));
            }
        }
    }
    out
}

/// Etched streets on each silicon side, within the die and across the dicing street to the
/// neighbouring dies: narrower than sqrt 2 h they self-stop as V-grooves.
pub fn streets(set: &MaskSet, p: &Process, plan: &EtchPlan) -> Vec<Finding> {
    let mut out = Vec::new();
    let (px, py) = (set.pitch_x_um, set.pitch_y_um);
    for (layer, side) in [
        (LayerKind::FrontSi, Side::Front),
        (LayerKind::BackSi, Side::Back),
    ] {
        let Some(step) = plan
            .steps
            .iter()
            .find(|s| s.side == side || s.side == Side::Both)
        else {
            continue;
        };
        let need = step.min_street_um;
        // Device shapes only: labels and marks are not devices (and do not survive the etch).
        let own: Vec<Polygon> = match layer {
            LayerKind::FrontSi => match &set.tooth_cell {
                Some(c) => {
                    let tc = set.cells[c]
                        .shapes
                        .get(&LayerKind::FrontSi)
                        .cloned()
                        .unwrap_or_default();
                    set.teeth
                        .iter()
                        .flat_map(|t| translate(&tc, t.x_um, t.y_um))
                        .collect()
                }
                None => Vec::new(),
            },
            _ => crate::layout::supports::supports(
                set.die_length_um,
                set.die_width_um,
                p.geometry.support_width_um,
            ),
        };
        let boxes: Vec<Rect> = own.iter().filter_map(|q| q.bounding_rect()).collect();
        let mut pairs =
            |a: &[Polygon], ab: &[Rect], b: &[Polygon], bb: &[Rect], same: bool, where_: &str| {
                for i in 0..a.len() {
                    let j0 = if same { i + 1 } else { 0 };
                    for j in j0..b.len() {
                        if !near(&ab[i], &bb[j], need) {
                            continue;
                        }
                        let d = gap(&a[i], &b[j]);
                        if d > 1e-9 && d < need {
                            let (ca, cb) = (centre(&ab[i]), centre(&bb[j]));
                            out.push(violation(
                                DrcCode::StreetTooNarrow,
                                Some(layer),
                                ((ca.0 + cb.0) / 2.0, (ca.1 + cb.1) / 2.0),
                                format!(
                                    "{where_}: a {d:.1} um street self-stops as a V-groove {:.1} \
                                     um deep; the {:.0} um etch needs {need:.1} um",
                                    crate::etch::geometry::v_groove_depth_um(d),
                                    step.depth_um
                                ),
                            ));
                        }
                    }
                }
            };
        pairs(&own, &boxes, &own, &boxes, true, "within the die");
        for (dx, dy) in [(px, 0.0), (0.0, py), (px, py), (px, -py)] {
            let other = translate(&own, dx, dy);
            let ob: Vec<Rect> = other.iter().filter_map(|q| q.bounding_rect()).collect();
            pairs(&own, &boxes, &other, &ob, false, "across the dicing street");
        }
    }
    out
}

/// Electrode islands closer than the minimum gap or than the edge margin to the film edge.
pub fn electrodes(set: &MaskSet, p: &Process) -> Vec<Finding> {
    let mut out = Vec::new();
    let min = p.drc.min_electrode_gap_um;
    let es = &set.electrodes;
    for i in 0..es.len() {
        for j in i + 1..es.len() {
            let d = gap(&es[i].polygon, &es[j].polygon);
            if d < min {
                let r = es[i].polygon.bounding_rect().expect("island");
                out.push(violation(
                    DrcCode::ElectrodeGap,
                    Some(LayerKind::Pvdf),
                    centre(&r),
                    format!(
                        "{} and {} are {d:.1} um apart (< {min} um)",
                        es[i].name, es[j].name
                    ),
                ));
            }
        }
    }
    // Everything else drawn on the PVDF mask (label pixels, marks) is metal too: it keeps the
    // electrode gap from every island, as the islands do from each other.
    let boxes: Vec<Rect> = es
        .iter()
        .map(|e| e.polygon.bounding_rect().expect("island"))
        .collect();
    for shape in set.die_layer(LayerKind::Pvdf) {
        let Some(sb) = shape.bounding_rect() else {
            continue;
        };
        let near_ones: Vec<usize> = (0..es.len())
            .filter(|&k| near(&sb, &boxes[k], min))
            .collect();
        // Part of an island (its own polygon or a pad touching it): not another shape.
        if near_ones
            .iter()
            .any(|&k| gap(&shape, &es[k].polygon) <= 1e-9)
        {
            continue;
        }
        if let Some((k, d)) = near_ones
            .iter()
            .map(|&k| (k, gap(&shape, &es[k].polygon)))
            .filter(|&(_, d)| d < min)
            .min_by(|a, b| a.1.total_cmp(&b.1))
        {
            out.push(violation(
                DrcCode::ElectrodeGap,
                Some(LayerKind::Pvdf),
                centre(&sb),
                format!(
                    "a PVDF shape that is not an electrode (label or mark) is {d:.1} um from {} \
                     (< {min} um)",
                    es[k].name
                ),
            ));
        }
    }
    let m = p.geometry.electrodes.edge_margin_um;
    let film = rect(m, m, set.die_length_um - m, set.die_width_um - m);
    let fr = film.bounding_rect().expect("film");
    for e in es {
        let r = e.polygon.bounding_rect().expect("island");
        if r.min().x < fr.min().x - 1e-6
            || r.min().y < fr.min().y - 1e-6
            || r.max().x > fr.max().x + 1e-6
            || r.max().y > fr.max().y + 1e-6
        {
            out.push(violation(
                DrcCode::ElectrodeEdge,
                Some(LayerKind::Pvdf),
                centre(&r),
                format!("{} is closer than {m} um to the film edge", e.name),
            ));
        }
    }
    out
}

/// Islands against the etched back: a middle island must lie on the channel floor (between the
/// U-channel's {111} walls as etched, [`EtchPlan::channel_floor_y_um`]) and a support island under
/// its support's etched footprint, each by `drc.min_wall_margin_um`. The film is flat: an island
/// that reaches the wall is bent over its foot or left unbonded.
pub fn electrodes_on_etched(set: &MaskSet, p: &Process, plan: &EtchPlan) -> Vec<Finding> {
    use crate::layout::ElectrodeSide;
    let m = p.drc.min_wall_margin_um;
    let w = set.die_width_um;
    let [f0, f1] = plan.channel_floor_y_um;
    let support = plan.channel_wall_y_um[0];
    let mut out = Vec::new();
    // Islands are reported once per name (an island and its pad are separate polygons).
    let mut seen = std::collections::BTreeSet::new();
    for e in &set.electrodes {
        let Some(r) = e.polygon.bounding_rect() else {
            continue;
        };
        let (lo, hi) = (r.min().y, r.max().y);
        let (clearance, what) = match e.side {
            ElectrodeSide::Middle => (
                (lo - f0).min(f1 - hi),
                format!("the channel floor between the etched walls (y {f0:.1}-{f1:.1} um)"),
            ),
            ElectrodeSide::Support1 => (
                support - hi,
                format!("support 1's etched footprint (y < {support:.1} um)"),
            ),
            ElectrodeSide::Support2 => (
                lo - (w - support),
                format!("support 2's etched footprint (y > {:.1} um)", w - support),
            ),
        };
        if clearance < m - 1e-6 && seen.insert(e.name.clone()) {
            let reach = if clearance < 0.0 {
                format!("crosses the edge of {what} by {:.1} um", -clearance)
            } else {
                format!("keeps only {clearance:.1} um inside {what}")
            };
            out.push(violation(
                DrcCode::ElectrodeNearWall,
                Some(LayerKind::Pvdf),
                centre(&r),
                format!("{} {reach}; drc.min_wall_margin_um is {m} um", e.name),
            ));
        }
    }
    out
}
