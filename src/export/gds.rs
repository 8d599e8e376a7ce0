//! GDSII through gds21 =3.0.0-pre.2: user unit 1 um, database unit 1 nm; cells sorted by name;
//! closed CCW boundaries; all-zero dates unless a SOURCE_DATE_EPOCH is given; written to memory.

use gds21::{
    GdsArrayRef, GdsBoundary, GdsDateTime, GdsElement, GdsLibrary, GdsPoint, GdsStruct,
    GdsStructRef, GdsTextElem, GdsUnits,
};

use super::{nm, ExportError};
use crate::layout::{LayerKind, MaskSet};

/// GDS output options.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct GdsOptions {
    /// Seconds since 1970 for the library and structure dates (SOURCE_DATE_EPOCH); `None` writes
    /// all-zero dates.
    pub date_epoch_s: Option<i64>,
}

impl MaskSet {
    /// The mask set as GDSII bytes: tooth, die and wafer cells, AREFs for the die rows.
    pub fn to_gds(&self, opts: &GdsOptions) -> Result<Vec<u8>, ExportError> {
        let lib = library(self, opts)?;
        let mut bytes = Vec::new();
        lib.write(&mut bytes)
            .map_err(|e| ExportError::Gds(e.to_string()))?;
        Ok(bytes)
    }
}

fn point(x_um: f64, y_um: f64) -> Result<GdsPoint, ExportError> {
    Ok(GdsPoint::new(nm(x_um)?, nm(y_um)?))
}

/// Civil date from days since 1970-01-01 (Hinnant's algorithm).
fn civil(days: i64) -> (i64, i64, i64) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    (yoe + era * 400 + i64::from(m <= 2), m, d)
}

fn date(epoch: Option<i64>) -> GdsDateTime {
    match epoch {
        None => GdsDateTime {
            year: 0,
            month: 0,
            day: 0,
            hour: 0,
            minute: 0,
            second: 0,
        },
        Some(s) => {
            let (days, secs) = (s.div_euclid(86_400), s.rem_euclid(86_400));
            let (y, m, d) = civil(days);
            GdsDateTime {
                year: (y - 1900) as i16,
                month: m as i16,
                day: d as i16,
                hour: (secs / 3600) as i16,
                minute: (secs % 3600 / 60) as i16,
                second: (secs % 60) as i16,
            }
        }
    }
}

fn library(set: &MaskSet, opts: &GdsOptions) -> Result<GdsLibrary, ExportError> {
    let mut lib = GdsLibrary::new(set.device.to_uppercase().replace('-', "_"));
    lib.units = GdsUnits::new(1e-3, 1e-9);
    // BTreeMap: cells come sorted by name.
    for (name, cell) in &set.cells {
        let mut s = GdsStruct::new(name.clone());
        for layer in LayerKind::ALL {
            let Some(polys) = cell.shapes.get(&layer) else {
                continue;
            };
            let g = layer.gds(&set.layers);
            for p in polys {
                let ring = &p.exterior().0;
                if ring.first() != ring.last() || ring.len() < 4 {
                    return Err(ExportError::Invalid(format!(
                        "cell {name}: an unclosed or degenerate ring on {}",
                        layer.name()
                    )));
                }
                let xy = ring
                    .iter()
                    .map(|c| point(c.x, c.y))
                    .collect::<Result<Vec<_>, _>>()?;
                s.elems.push(GdsElement::GdsBoundary(GdsBoundary {
                    layer: g.layer,
                    datatype: g.datatype,
                    xy,
                    ..Default::default()
                }));
            }
        }
        let a = set.layers.annotation;
        for n in &cell.notes {
            s.elems.push(GdsElement::GdsTextElem(GdsTextElem {
                string: n.text.clone(),
                layer: a.layer,
                texttype: a.datatype,
                xy: point(n.x_um, n.y_um)?,
                ..Default::default()
            }));
        }
        for pl in &cell.placements {
            if pl.is_array() {
                let o = point(pl.x_um, pl.y_um)?;
                let c = point(pl.x_um + f64::from(pl.cols) * pl.pitch_x_um, pl.y_um)?;
                let r = point(pl.x_um, pl.y_um + f64::from(pl.rows) * pl.pitch_y_um)?;
                s.elems.push(GdsElement::GdsArrayRef(GdsArrayRef {
                    name: pl.cell.clone(),
                    xy: [o, c, r],
                    cols: i16::try_from(pl.cols)
                        .map_err(|_| ExportError::Invalid("too many columns".into()))?,
                    rows: i16::try_from(pl.rows)
                        .map_err(|_| ExportError::Invalid("too many rows".into()))?,
                    ..Default::default()
                }));
            } else {
                s.elems.push(GdsElement::GdsStructRef(GdsStructRef {
                    name: pl.cell.clone(),
                    xy: point(pl.x_um, pl.y_um)?,
                    ..Default::default()
                }));
            }
        }
        lib.structs.push(s);
    }
    lib.set_all_dates(date(opts.date_epoch_s));
    Ok(lib)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates() {
        assert_eq!(civil(0), (1970, 1, 1));
        assert_eq!(civil(19_723), (2024, 1, 1));
        let d = date(Some(1_700_000_000));
        assert_eq!(
            (d.year, d.month, d.day, d.hour, d.minute, d.second),
            (123, 11, 14, 22, 13, 20)
        );
    }
}
