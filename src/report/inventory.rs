//! The mask inventory the traveler and the build summary print: one row per mask with the file
//! the shop receives and its SHA-256, plus the GDS holding every layer.

use serde::Serialize;

use crate::layout::MaskSet;
use crate::process::{Side, Tone};

pub use crate::digest::sha256_hex;

/// One mask as the shop and the operator need it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MaskRow {
    pub name: String,
    /// GDS layer/datatype, e.g. `1/0`.
    pub gds_layer: String,
    pub side: Side,
    /// `light field` or `dark field`.
    pub tone: String,
    pub mirrored: bool,
    /// `<device>-<mask>.svg` as written by `tactfab masks` / `tactfab build`.
    pub svg_file: String,
    pub svg_sha256: String,
}

/// The GDS file and every mask of the set.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Inventory {
    pub gds_file: String,
    pub gds_sha256: String,
    pub lyp_file: String,
    pub masks: Vec<MaskRow>,
    /// The compensation test die on the front mask, when the process asks for one.
    pub test_die: Option<crate::layout::test_die::TestDieInfo>,
}

/// The inventory from the set and the bytes actually written (GDS, and each mask's SVG in mask
/// order).
#[track_caller]
pub fn inventory(set: &MaskSet, gds: &[u8], svgs: &[String]) -> Inventory {
    assert_eq!(svgs.len(), set.masks.len(), "one SVG per mask");
    let masks = set
        .masks
        .iter()
        .zip(svgs)
        .map(|(m, svg)| MaskRow {
            name: m.name.clone(),
            gds_layer: format!("{}/{}", m.gds.layer, m.gds.datatype),
            side: m.side,
            tone: match m.tone {
                Tone::LightField => "light field".into(),
                Tone::DarkField => "dark field".into(),
            },
            mirrored: m.mirrored,
            svg_file: format!("{}-{}.svg", set.device, m.name),
            svg_sha256: sha256_hex(svg.as_bytes()),
        })
        .collect();
    Inventory {
        gds_file: format!("{}.gds", set.device),
        gds_sha256: sha256_hex(gds),
        lyp_file: format!("{}.lyp", set.device),
        masks,
        test_die: set.test_die.clone(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sha256_matches_published_vectors() {
        // FIPS 180-2 appendix B.1 and the empty message.
        assert_eq!(
            sha256_hex(b"abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
        assert_eq!(
            sha256_hex(b""),
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"
        );
    }
}
