//! DRC results as a KLayout report database (`.lyrdb`): each violation a marker box at its place
//! in the die cell, filed under its code (with the code's meaning), carrying its message, so the
//! marker browser (Tools > Marker Browser, or `klayout f.gds -m f.lyrdb`) walks through them.

use super::xml::escape;
use crate::drc::{is_waived, DrcReport};
use crate::finding::At;
use crate::layout::MaskSet;

/// Half side (um) of the box drawn around a violation's point.
pub const MARKER_HALF_UM: f64 = 25.0;

/// A text value: single-quoted, with `\` and `'` escaped as KLayout reads them.
fn quoted(s: &str) -> String {
    let inner = s.replace('\\', "\\\\").replace('\'', "\\'");
    escape(&format!("text: '{inner}'"))
}

/// The report database of `drc` for the mask set `set` (coordinates in um, die cell).
pub fn to_lyrdb(drc: &DrcReport, set: &MaskSet) -> String {
    let cell = escape(&set.die_cell);
    let mut codes: Vec<_> = drc.violations.iter().map(|v| v.code).collect();
    codes.sort_by_key(|c| c.as_str());
    codes.dedup();
    let mut s = String::from("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<report-database>\n");
    s.push_str(&format!(
        " <description>DRC of {} rev {}: {} violations, {} failing (tactfab)</description>\n \
         <original-file/>\n <generator>tactfab {}</generator>\n <top-cell>{cell}</top-cell>\n \
         <tags>\n  <tag>\n   <name>waived</name>\n   <description>waived by drc.waive in the \
         process file</description>\n  </tag>\n </tags>\n <categories>\n",
        escape(&set.device),
        escape(&set.revision),
        drc.violations.len(),
        drc.failing(),
        env!("CARGO_PKG_VERSION"),
    ));
    for c in &codes {
        s.push_str(&format!(
            "  <category>\n   <name>{}</name>\n   <description>{}</description>\n   \
             <categories>\n   </categories>\n  </category>\n",
            c.as_str(),
            escape(c.meaning())
        ));
    }
    s.push_str(&format!(
        " </categories>\n <cells>\n  <cell>\n   <name>{cell}</name>\n   <variant/>\n   \
         <layout-name/>\n   <references>\n   </references>\n  </cell>\n </cells>\n <items>\n"
    ));
    for v in &drc.violations {
        let (x, y, layer) = match &v.at {
            At::Point { x_um, y_um, layer } => (*x_um, *y_um, *layer),
            _ => (0.0, 0.0, None),
        };
        let h = MARKER_HALF_UM;
        let tags = if is_waived(v) { "waived" } else { "" };
        let mut values = format!(
            "    <value>box: ({},{};{},{})</value>\n    <value>{}</value>\n",
            x - h,
            y - h,
            x + h,
            y + h,
            quoted(&v.message)
        );
        if let Some(l) = layer {
            values.push_str(&format!(
                "    <value>{}</value>\n",
                quoted(&format!("layer {l}"))
            ));
        }
        s.push_str(&format!(
            "  <item>\n   <tags>{tags}</tags>\n   <category>{}</category>\n   <cell>{cell}</cell>\n   \
             <visited>false</visited>\n   <multiplicity>1</multiplicity>\n   <comment/>\n   \
             <image/>\n   <values>\n{values}   </values>\n  </item>\n",
            v.code.as_str()
        ));
    }
    s.push_str(" </items>\n</report-database>\n");
    s
}
