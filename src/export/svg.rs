//! One SVG per mask with the svg crate: width/height in mm, viewBox in um, one `<g>` per layer,
//! y flipped numerically (a transform would mirror text and hide layers from Inkscape), path data
//! written from integer nm with fixed decimals (svg's own path data stores f32).

use geo::Polygon;
use svg::node::element::{Circle, Group, Path, Rectangle, Text};
use svg::Document;

use super::{mm_text, nm, um_text, ExportError};
use crate::layout::{LayerKind, MaskEntry, MaskSet};

/// Path data for polygons in a frame of height `height_nm` (y flipped): `M x y L ... Z` per ring.
pub fn path_data(polys: &[Polygon], height_nm: i64) -> Result<String, ExportError> {
    let mut d = String::new();
    for p in polys {
        let ring = &p.exterior().0;
        let n = ring.len().saturating_sub(1);
        for (k, c) in ring.iter().take(n).enumerate() {
            let (x, y) = (i64::from(nm(c.x)?), height_nm - i64::from(nm(c.y)?));
            if !d.is_empty() {
                d.push(' ');
            }
            d.push_str(if k == 0 { "M" } else { "L" });
            d.push(' ');
            d.push_str(&um_text(x));
            d.push(' ');
            d.push_str(&um_text(y));
        }
        if n > 0 {
            d.push_str(" Z");
        }
    }
    Ok(d)
}

/// Room below the die for the scale bar, um.
const SCALE_MARGIN_UM: f64 = 2000.0;

/// A scale bar under a drawing `length_um` long: 1, 2 or 5 x 10^k um, about a fifth of the
/// length, with its length as text.
fn scale_bar(length_um: f64, top_um: f64) -> Result<Group, ExportError> {
    let target = length_um / 5.0;
    let decade = 10f64.powf(target.log10().floor());
    let bar = [5.0, 2.0, 1.0]
        .iter()
        .map(|m| m * decade)
        .find(|b| *b <= target)
        .unwrap_or(decade);
    let label = if bar >= 1000.0 {
        format!("{} mm", bar / 1000.0)
    } else {
        format!("{bar} um")
    };
    let y = top_um + 500.0;
    Ok(Group::new()
        .set("id", "scale")
        .add(
            Rectangle::new()
                .set("x", um_text(i64::from(nm(500.0)?)))
                .set("y", um_text(i64::from(nm(y)?)))
                .set("width", um_text(i64::from(nm(bar)?)))
                .set("height", "200.000")
                .set("fill", "#000000"),
        )
        .add(
            Text::new(label)
                .set("x", um_text(i64::from(nm(700.0 + bar)?)))
                .set("y", um_text(i64::from(nm(y + 200.0)?)))
                .set("font-family", "sans-serif")
                .set("font-size", "600.000")
                .set("fill", "#000000"),
        ))
}

/// Non-printing notes on the electrode mask: each island's name and its wire pad's outline (the
/// pad is part of the island, so the chrome alone does not show it).
fn electrode_notes(set: &MaskSet, height_um: f64) -> Result<Group, ExportError> {
    let mut g = Group::new()
        .set("id", "notes")
        .set("data-printing", "no")
        .set("fill", "none")
        .set("stroke", "#000000");
    for e in &set.electrodes {
        let [x, y, side] = e.pad;
        g = g.add(
            Rectangle::new()
                .set("x", um_text(i64::from(nm(x)?)))
                .set("y", um_text(i64::from(nm(height_um - y - side)?)))
                .set("width", um_text(i64::from(nm(side)?)))
                .set("height", um_text(i64::from(nm(side)?)))
                .set("stroke-width", "40.000")
                .set("stroke-dasharray", "120 80"),
        );
        let r = geo::BoundingRect::bounding_rect(&e.polygon);
        if let Some(r) = r {
            let c = r.center();
            g = g.add(
                Text::new(e.name.clone())
                    .set("x", um_text(i64::from(nm(c.x)?)))
                    .set("y", um_text(i64::from(nm(height_um - c.y)?)))
                    .set("text-anchor", "middle")
                    .set("dominant-baseline", "middle")
                    .set("font-family", "sans-serif")
                    .set("font-size", "700.000")
                    .set("fill", "#000000")
                    .set("stroke", "none"),
            );
        }
    }
    Ok(g)
}

impl MaskSet {
    /// The wafer map: the wafer and its usable circle, every die numbered in stepping order, and
    /// the alignment-mark sites ringed (the marks themselves, 50 um crosses, drawn to scale
    /// inside the rings), as SVG text in mm with a viewBox in um centred on the wafer.
    pub fn wafer_map_svg(&self) -> Result<String, ExportError> {
        let r = self.wafer_diameter_um / 2.0;
        let r_usable = r - self.edge_exclusion_um;
        let t = |v: f64| -> Result<String, ExportError> { Ok(um_text(i64::from(nm(v)?))) };
        // SVG y runs down: (x, y) on the wafer is (x + r, r - y) here.
        let (sx, sy) = (|x: f64| x + r, |y: f64| r - y);
        let size = 2.0 * r;
        // 5 mm under the wafer for the caption.
        let height = size + 5000.0;
        let mut doc = Document::new()
            .set("width", format!("{}mm", mm_text(i64::from(nm(size)?))))
            .set("height", format!("{}mm", mm_text(i64::from(nm(height)?))))
            .set("viewBox", format!("0 0 {} {}", t(size)?, t(height)?))
            .set("data-device", self.device.clone())
            .set("data-revision", self.revision.clone())
            .set("data-dies", self.die_origins.len().to_string());
        doc = doc.add(
            Group::new()
                .set("id", "wafer")
                .set("fill", "none")
                .set("stroke", "#444444")
                .add(
                    Circle::new()
                        .set("cx", t(r)?)
                        .set("cy", t(r)?)
                        .set("r", t(r)?)
                        .set("stroke-width", "150.000"),
                )
                .add(
                    Circle::new()
                        .set("cx", t(r)?)
                        .set("cy", t(r)?)
                        .set("r", t(r_usable)?)
                        .set("stroke-width", "80.000")
                        .set("stroke-dasharray", "800 500"),
                ),
        );
        let mut dies = Group::new()
            .set("id", "dies")
            .set("fill", "#dbe9f6")
            .set("stroke", "#0072b2")
            .set("stroke-width", "100.000");
        for (k, o) in self.die_origins.iter().enumerate() {
            dies = dies
                .add(
                    Rectangle::new()
                        .set("x", t(sx(o.x))?)
                        .set("y", t(sy(o.y + self.die_width_um))?)
                        .set("width", t(self.die_length_um)?)
                        .set("height", t(self.die_width_um)?),
                )
                .add(
                    Text::new((k + 1).to_string())
                        .set("x", t(sx(o.x + self.die_length_um / 2.0))?)
                        .set("y", t(sy(o.y + self.die_width_um / 2.0))?)
                        .set("text-anchor", "middle")
                        .set("dominant-baseline", "middle")
                        .set("font-family", "sans-serif")
                        .set("font-size", "4000.000")
                        .set("fill", "#0072b2")
                        .set("stroke", "none"),
                );
        }
        doc = doc.add(dies);
        if let Some(td) = &self.test_die {
            let ([x, y], [w, h]) = (td.origin_um, td.size_um);
            doc = doc.add(
                Group::new()
                    .set("id", "test-die")
                    .set(
                        "data-a-um",
                        td.a_um
                            .iter()
                            .map(|a| format!("{a:.1}"))
                            .collect::<Vec<_>>()
                            .join(","),
                    )
                    .set("fill", "#fde0c5")
                    .set("stroke", "#d55e00")
                    .set("stroke-width", "100.000")
                    .add(
                        Rectangle::new()
                            .set("x", t(sx(x))?)
                            .set("y", t(sy(y + h))?)
                            .set("width", t(w)?)
                            .set("height", t(h)?),
                    )
                    .add(
                        Text::new(format!(
                            "TEST DIE a {:.0}-{:.0} um",
                            td.a_um[0],
                            td.a_um[td.a_um.len() - 1]
                        ))
                        .set("x", t(sx(x + w / 2.0))?)
                        .set("y", t(sy(y + h / 2.0))?)
                        .set("text-anchor", "middle")
                        .set("dominant-baseline", "middle")
                        .set("font-family", "sans-serif")
                        .set("font-size", "1500.000")
                        .set("fill", "#d55e00")
                        .set("stroke", "none"),
                    ),
            );
        }
        // Mark sites: the marks' polygons clustered within 2 mm.
        let marks = self.flatten(&self.wafer_cell, LayerKind::Marks);
        let mut sites: Vec<(f64, f64, usize)> = Vec::new();
        for p in &marks {
            if let Some(c) = geo::Centroid::centroid(p) {
                match sites
                    .iter_mut()
                    .find(|s| (s.0 / s.2 as f64 - c.x()).hypot(s.1 / s.2 as f64 - c.y()) < 2000.0)
                {
                    Some(s) => *s = (s.0 + c.x(), s.1 + c.y(), s.2 + 1),
                    None => sites.push((c.x(), c.y(), 1)),
                }
            }
        }
        let mut g = Group::new()
            .set("id", "marks")
            .set("fill", "none")
            .set("stroke", "#d55e00")
            .set("stroke-width", "250.000");
        for (x, y, n) in &sites {
            let (x, y) = (x / *n as f64, y / *n as f64);
            g = g.add(
                Circle::new()
                    .set("cx", t(sx(x))?)
                    .set("cy", t(sy(y))?)
                    .set("r", "1500.000"),
            );
        }
        let flipped: Vec<Polygon> = marks
            .iter()
            .map(|p| {
                geo::MapCoords::map_coords(p, |c| geo::Coord {
                    x: c.x + r,
                    y: c.y + r,
                })
            })
            .collect();
        g = g.add(
            Path::new()
                .set("d", path_data(&flipped, i64::from(nm(size)?))?)
                .set("fill", "#d55e00")
                .set("stroke", "none"),
        );
        doc = doc.add(g).add(
            Text::new(format!(
                "{} rev {}: {} dies, alignment marks ringed",
                self.device,
                self.revision,
                self.die_origins.len()
            ))
            .set("x", t(r)?)
            .set("y", t(size + 3500.0)?)
            .set("text-anchor", "middle")
            .set("font-family", "sans-serif")
            .set("font-size", "3000.000")
            .set("fill", "#000000"),
        );
        Ok(format!("{doc}\n"))
    }

    /// The die as the shop receives `mask` (mirrored when it says so), as SVG text.
    pub fn to_svg(&self, mask: &MaskEntry) -> Result<String, ExportError> {
        let (l, w) = (self.die_length_um, self.die_width_um);
        let h_nm = i64::from(nm(w)?);
        let polys = self.die_mask(mask);
        let layer = mask.layer;
        let mut doc = Document::new()
            .set("width", format!("{}mm", mm_text(i64::from(nm(l)?))))
            .set(
                "height",
                format!("{}mm", mm_text(i64::from(nm(w + SCALE_MARGIN_UM)?))),
            )
            .set(
                "viewBox",
                format!(
                    "0 0 {} {}",
                    um_text(i64::from(nm(l)?)),
                    um_text(i64::from(nm(w + SCALE_MARGIN_UM)?))
                ),
            )
            .set("data-device", self.device.clone())
            .set("data-revision", self.revision.clone())
            .set("data-mask", mask.name.clone())
            .set(
                "data-mirrored",
                if mask.mirrored {
                    "x -> die_length - x"
                } else {
                    "no"
                },
            );
        let g = Group::new()
            .set("id", layer.name())
            .set(
                "data-gds-layer",
                format!("{}/{}", mask.gds.layer, mask.gds.datatype),
            )
            .set("fill", layer.colour())
            .set("fill-rule", "nonzero")
            .set("stroke", "none")
            .add(Path::new().set("d", path_data(&polys, h_nm)?));
        doc = doc.add(g);
        let o = LayerKind::Outline;
        let outline = Group::new()
            .set("id", o.name())
            .set(
                "data-gds-layer",
                format!(
                    "{}/{}",
                    o.gds(&self.layers).layer,
                    o.gds(&self.layers).datatype
                ),
            )
            .set("fill", "none")
            .set("stroke", o.colour())
            .set("stroke-width", "20.000")
            .add(
                Rectangle::new()
                    .set("x", "0.000")
                    .set("y", "0.000")
                    .set("width", um_text(i64::from(nm(l)?)))
                    .set("height", um_text(h_nm)),
            );
        doc = doc.add(outline).add(scale_bar(l, w)?);
        if layer == LayerKind::Pvdf {
            doc = doc.add(electrode_notes(self, w)?);
        }
        Ok(format!("{doc}\n"))
    }
}
