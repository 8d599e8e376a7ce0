//! KLayout layer properties (.lyp): the logical layer names live outside GDS.

use crate::layout::{LayerKind, MaskSet};

use super::xml::escape;

impl MaskSet {
    /// The .lyp XML: one entry per layer with its name, colour and source `L/D@1`.
    pub fn to_lyp(&self) -> String {
        let mut out =
            String::from("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<layer-properties>\n");
        for k in LayerKind::ALL {
            let g = k.gds(&self.layers);
            let fill = if matches!(
                k,
                LayerKind::Outline | LayerKind::WaferOutline | LayerKind::Annotation
            ) {
                "I1"
            } else {
                "I5"
            };
            out.push_str(" <properties>\n");
            out.push_str(&format!(
                "  <frame-color>{}</frame-color>\n  <fill-color>{}</fill-color>\n",
                k.colour(),
                k.colour()
            ));
            out.push_str(
                "  <frame-brightness>0</frame-brightness>\n  \
                 <fill-brightness>0</fill-brightness>\n",
            );
            out.push_str(&format!("  <dither-pattern>{fill}</dither-pattern>\n"));
            out.push_str(
                "  <line-style/>\n  <valid>true</valid>\n  <visible>true</visible>\n  \
                 <transparent>false</transparent>\n",
            );
            out.push_str(
                "  <width>1</width>\n  <marked>false</marked>\n  <xfill>false</xfill>\n  \
                 <animation>0</animation>\n",
            );
            out.push_str(&format!(
                "  <name>{} {}/{}</name>\n",
                escape(k.name()),
                g.layer,
                g.datatype
            ));
            out.push_str(&format!(
                "  <source>{}/{}@1</source>\n",
                g.layer, g.datatype
            ));
            out.push_str(" </properties>\n");
        }
        out.push_str(" <name/>\n</layer-properties>\n");
        out
    }
}
