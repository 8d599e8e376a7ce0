//! Schematic cross-section of the die after each step, computed from the process, the etch plan
//! and the mask set (not drawn by hand).
//!
//! The cut runs across the die width (y) through the centre of the first tooth column. Silicon is
//! etched from the openings with {111} sidewalls at 54.74 deg (run-out h / tan 54.74 deg, crystal
//! geometry, `etch::geometry`): the surface is the highest of the tooth frustums and the etched
//! floor, so narrow openings self-stop as V-grooves. The back is the same with the supports as
//! mesas. Films (oxide, resist, PVDF, Al) are drawn along the surface with a minimum visible width.

use serde::Serialize;

use crate::etch::geometry::sidewall_run_out_um;
use crate::etch::EtchPlan;
use crate::export::xml::escape;
use crate::layout::MaskSet;
use crate::process::{Process, Side, StepParams, StripTarget, Substrate};

/// A film on one face: thickness (0 = absent) and whether it is patterned to its mask.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct Film {
    pub thickness_um: f64,
    pub patterned: bool,
}

/// The PVDF film on its way: on the glass carrier, resist, Al patterned, attached to the die.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct PvdfState {
    pub on_carrier: bool,
    pub resist: Film,
    pub electrodes_patterned: bool,
    /// Electrode islands the Al etch leaves (from the electrode pattern).
    pub islands: usize,
    pub attached: bool,
}

/// The layer stack after a step.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct Stack {
    pub front_etch_um: f64,
    pub back_etch_um: f64,
    pub oxide_front: Film,
    pub oxide_back: Film,
    pub resist_front: Film,
    pub resist_back: Film,
    pub pvdf: Option<PvdfState>,
}

impl Stack {
    /// One line for the Markdown traveler.
    pub fn describe(&self) -> String {
        let film = |f: &Film| {
            if f.thickness_um <= 0.0 {
                "-".to_string()
            } else {
                format!(
                    "{:.3} um{}",
                    f.thickness_um,
                    if f.patterned { " patterned" } else { "" }
                )
            }
        };
        let mut s = format!(
            "Si front etched {:.1} um, back {:.1} um; oxide front {}, back {}; resist front {}, \
             back {}",
            self.front_etch_um,
            self.back_etch_um,
            film(&self.oxide_front),
            film(&self.oxide_back),
            film(&self.resist_front),
            film(&self.resist_back)
        );
        if let Some(p) = &self.pvdf {
            s.push_str(&format!(
                "; PVDF {}, resist {}, Al {}",
                if p.attached {
                    "attached to the channel and supports"
                } else if p.on_carrier {
                    "on the glass carrier"
                } else {
                    "free"
                },
                film(&p.resist),
                if p.electrodes_patterned {
                    format!("patterned ({} islands)", p.islands)
                } else {
                    "blanket".to_string()
                }
            ));
        }
        s
    }
}

/// The stack after every step of the process, in step order.
pub fn stacks(p: &Process, plan: &EtchPlan) -> Vec<Stack> {
    let mut st = Stack::default();
    let (mut ox, mut rs, mut si) = (
        plan.oxidations.iter(),
        plan.resists.iter(),
        plan.steps.iter(),
    );
    let mut out = Vec::with_capacity(p.steps.len());
    for step in &p.steps {
        let film_phase = st.pvdf.is_some_and(|f| !f.attached);
        match &step.params {
            StepParams::Oxidation(_) => {
                if let Some(o) = ox.next() {
                    st.oxide_front = Film {
                        thickness_um: o.thickness_um,
                        patterned: false,
                    };
                    st.oxide_back = st.oxide_front;
                }
            }
            StepParams::SpinCoat(c) => {
                let t = rs.next().map(|r| r.thickness_um).unwrap_or(0.0);
                match c.substrate {
                    Substrate::Pvdf => {
                        if let Some(f) = st.pvdf.as_mut() {
                            f.resist = Film {
                                thickness_um: t,
                                patterned: false,
                            };
                        }
                    }
                    Substrate::Carrier => {}
                    Substrate::Wafer => {
                        if matches!(c.side, Side::Front | Side::Both) {
                            st.resist_front = Film {
                                thickness_um: t,
                                patterned: false,
                            };
                        }
                        if matches!(c.side, Side::Back | Side::Both) {
                            st.resist_back = Film {
                                thickness_um: t,
                                patterned: false,
                            };
                        }
                    }
                }
            }
            StepParams::Develop(_) => match st.pvdf.as_mut() {
                Some(f) if film_phase => f.resist.patterned = f.resist.thickness_um > 0.0,
                _ => {
                    st.resist_front.patterned = st.resist_front.thickness_um > 0.0;
                    st.resist_back.patterned = st.resist_back.thickness_um > 0.0;
                }
            },
            StepParams::OxideEtch(e) => {
                if matches!(e.side, Side::Front | Side::Both) {
                    st.oxide_front.patterned = true;
                }
                if matches!(e.side, Side::Back | Side::Both) {
                    st.oxide_back.patterned = true;
                }
            }
            StepParams::SiliconEtch(_) => {
                if let Some(e) = si.next() {
                    if matches!(e.side, Side::Front | Side::Both) {
                        st.front_etch_um += e.achieved_depth_um;
                    }
                    if matches!(e.side, Side::Back | Side::Both) {
                        st.back_etch_um += e.achieved_depth_um;
                    }
                    // The whole wafer sits in the bath: both oxide faces erode; resist dissolves
                    // (RESIST_NOT_A_MASK: its developer is TMAH).
                    for o in [&mut st.oxide_front, &mut st.oxide_back] {
                        if o.thickness_um > 0.0 {
                            o.thickness_um = (o.thickness_um - e.mask_consumed_um).max(0.0);
                        }
                    }
                    st.resist_front = Film::default();
                    st.resist_back = Film::default();
                }
            }
            StepParams::Strip(s) => match s.target {
                StripTarget::Resist => match st.pvdf.as_mut() {
                    // The carrier glue is resist too: stripping frees the film.
                    Some(f) if film_phase => {
                        f.resist = Film::default();
                        f.on_carrier = false;
                    }
                    _ => {
                        st.resist_front = Film::default();
                        st.resist_back = Film::default();
                    }
                },
                StripTarget::Oxide => {
                    st.oxide_front = Film::default();
                    st.oxide_back = Film::default();
                }
            },
            StepParams::Mount(_) => {
                st.pvdf = Some(PvdfState {
                    on_carrier: true,
                    ..PvdfState::default()
                })
            }
            StepParams::MetalEtch(_) => {
                if let Some(f) = st.pvdf.as_mut() {
                    f.electrodes_patterned = true;
                    f.islands = p.geometry.electrodes.island_count();
                }
            }
            StepParams::Assemble(_) => {
                if let Some(f) = st.pvdf.as_mut() {
                    f.attached = true;
                    f.on_carrier = false;
                }
            }
            StepParams::Clean(_) | StepParams::Bake(_) | StepParams::Expose(_) => {}
        }
        out.push(st);
    }
    out
}

/// What the cut crosses, in die y (um).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Cut {
    pub x_um: f64,
    pub width_um: f64,
    pub thickness_um: f64,
    /// Tooth tops (front mask) crossed by the cut.
    pub teeth: Vec<(f64, f64)>,
    /// Supports (back mask) crossed by the cut.
    pub supports: Vec<(f64, f64)>,
    /// Electrode islands crossed by the cut, by name.
    pub electrodes: Vec<(String, f64, f64)>,
    pub pvdf_thickness_um: f64,
}

impl Cut {
    /// The cut through the centre of the first tooth column (or the die centre without teeth).
    pub fn new(p: &Process, set: &MaskSet) -> Cut {
        let g = &p.geometry;
        let top = set.tooth_top_um;
        let x = set
            .teeth
            .first()
            .map(|t| t.x_um + top / 2.0)
            .unwrap_or(g.die_length_um / 2.0);
        let mut teeth: Vec<(f64, f64)> = set
            .teeth
            .iter()
            .filter(|t| t.x_um <= x && x <= t.x_um + top)
            .map(|t| (t.y_um, t.y_um + top))
            .collect();
        teeth.sort_by(|a, b| a.0.total_cmp(&b.0));
        let w = g.die_width_um;
        let supports = vec![(0.0, g.support_width_um), (w - g.support_width_um, w)];
        let mut electrodes: Vec<(String, f64, f64)> = set
            .electrodes
            .iter()
            .filter_map(|e| {
                use geo::BoundingRect;
                let r = e.polygon.bounding_rect()?;
                (r.min().x <= x && x <= r.max().x).then(|| (e.name.clone(), r.min().y, r.max().y))
            })
            .collect();
        electrodes.sort_by(|a, b| a.1.total_cmp(&b.1));
        Cut {
            x_um: x,
            width_um: w,
            thickness_um: p.wafer.thickness_um,
            teeth,
            supports,
            electrodes,
            pvdf_thickness_um: p.materials.pvdf.thickness_um,
        }
    }

    /// Front surface height z(y) (z = 0 at the back face) after a front etch of `depth_um`.
    pub fn front_z(&self, y: f64, depth_um: f64) -> f64 {
        self.thickness_um - depth_um + mesa_lift(y, depth_um, &self.teeth)
    }

    /// Back surface height z(y) after a back etch of `depth_um`.
    pub fn back_z(&self, y: f64, depth_um: f64) -> f64 {
        depth_um - mesa_lift(y, depth_um, &self.supports)
    }

    /// Breakpoints of the piecewise-linear profile: edges, sidewall feet, midpoints between mesas.
    fn breaks(&self, mesas: &[(f64, f64)], depth_um: f64) -> Vec<f64> {
        let r = sidewall_run_out_um(depth_um);
        let mut v = vec![0.0, self.width_um];
        for (i, &(a, b)) in mesas.iter().enumerate() {
            v.extend([a, b, a - r, b + r]);
            if let Some(&(c, _)) = mesas.get(i + 1) {
                v.push((b + c) / 2.0);
            }
        }
        v.retain(|y| (0.0..=self.width_um).contains(y));
        v.sort_by(f64::total_cmp);
        v.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
        v
    }

    /// Front profile as (y, z) points from y = 0 to the die width.
    pub fn front_profile(&self, depth_um: f64) -> Vec<(f64, f64)> {
        self.breaks(&self.teeth, depth_um)
            .into_iter()
            .map(|y| (y, self.front_z(y, depth_um)))
            .collect()
    }

    /// Back profile as (y, z) points from y = 0 to the die width.
    pub fn back_profile(&self, depth_um: f64) -> Vec<(f64, f64)> {
        self.breaks(&self.supports, depth_um)
            .into_iter()
            .map(|y| (y, self.back_z(y, depth_um)))
            .collect()
    }
}

/// Height of the mesas above the etched floor: each mesa is a frustum whose sides fall at
/// tan 54.74 deg = sqrt 2 from its masked top; the surface is the highest frustum or the floor.
fn mesa_lift(y: f64, depth_um: f64, mesas: &[(f64, f64)]) -> f64 {
    if depth_um <= 0.0 {
        return 0.0;
    }
    let slope = depth_um / sidewall_run_out_um(depth_um);
    mesas
        .iter()
        .map(|&(a, b)| {
            let d = if y < a {
                a - y
            } else if y > b {
                y - b
            } else {
                0.0
            };
            (depth_um - slope * d).max(0.0)
        })
        .fold(0.0, f64::max)
}

/// The part of a polyline with y in [y0, y1] (linear interpolation at the ends).
fn clip(poly: &[(f64, f64)], y0: f64, y1: f64) -> Vec<(f64, f64)> {
    let at = |y: f64| {
        for w in poly.windows(2) {
            let ((ya, za), (yb, zb)) = (w[0], w[1]);
            if ya <= y && y <= yb {
                return if yb > ya {
                    za + (zb - za) * (y - ya) / (yb - ya)
                } else {
                    za
                };
            }
        }
        poly.last().map(|p| p.1).unwrap_or(0.0)
    };
    let mut out = vec![(y0, at(y0))];
    out.extend(poly.iter().copied().filter(|&(y, _)| y > y0 && y < y1));
    out.push((y1, at(y1)));
    out
}

/// Colours of the section (also the legend).
const SI: &str = "#b8c4d6";
const OXIDE: &str = "#d95f02";
const RESIST: &str = "#e7298a";
const PVDF: &str = "#1b9e77";
const AL: &str = "#444444";
const GLASS: &str = "#dde8ee";

/// Drawing frame: 640 x 200 px, the die width over 600 px, the wafer thickness over 100 px.
const W_PX: f64 = 600.0;
const T_PX: f64 = 100.0;
const X0: f64 = 20.0;
const Z0: f64 = 130.0;

/// The section after a step as an inline SVG (deterministic: fixed decimals, no ids).
pub fn svg(cut: &Cut, st: &Stack, caption: &str) -> String {
    let sx = W_PX / cut.width_um;
    let sz = T_PX / cut.thickness_um;
    let px = |y: f64, z: f64| (X0 + y * sx, Z0 - z * sz);
    let pts = |poly: &[(f64, f64)], dz_px: f64| {
        poly.iter()
            .map(|&(y, z)| {
                let (a, b) = px(y, z);
                format!("{a:.2},{:.2}", b - dz_px)
            })
            .collect::<Vec<_>>()
            .join(" ")
    };
    let front = cut.front_profile(st.front_etch_um);
    let back = cut.back_profile(st.back_etch_um);
    let mut body = String::new();
    let mut outline: Vec<(f64, f64)> = front.clone();
    outline.extend(back.iter().rev().copied());
    body.push_str(&format!(
        "<polygon points=\"{}\" fill=\"{SI}\" stroke=\"#333\" stroke-width=\"0.6\"/>",
        pts(&outline, 0.0)
    ));
    // A film along a polyline: stroke of width w px, shifted off the surface by `off` px (up > 0).
    let stroke = |poly: &[(f64, f64)], colour: &str, w: f64, off: f64| {
        format!(
            "<polyline points=\"{}\" fill=\"none\" stroke=\"{colour}\" stroke-width=\"{w:.2}\"/>",
            pts(poly, off + w / 2.0)
        )
    };
    let film_w = |t: f64| (t * sz).max(2.0);
    let mut layer =
        |surface: &[(f64, f64)], masks: &[(f64, f64)], films: [(&Film, &str); 2], up: bool| {
            let mut off = 0.0;
            for (f, colour) in films {
                if f.thickness_um <= 0.0 {
                    continue;
                }
                let w = film_w(f.thickness_um);
                let shift = if up { off } else { -off - w };
                let parts: Vec<Vec<(f64, f64)>> = if f.patterned {
                    masks.iter().map(|&(a, b)| clip(surface, a, b)).collect()
                } else {
                    vec![surface.to_vec()]
                };
                for part in parts {
                    body.push_str(&stroke(&part, colour, w, shift));
                }
                off += w;
            }
        };
    layer(
        &front,
        &cut.teeth,
        [(&st.oxide_front, OXIDE), (&st.resist_front, RESIST)],
        true,
    );
    layer(
        &back,
        &cut.supports,
        [(&st.oxide_back, OXIDE), (&st.resist_back, RESIST)],
        false,
    );
    if let Some(f) = &st.pvdf {
        let pw = film_w(cut.pvdf_thickness_um);
        let aw = 2.0;
        if f.attached {
            // Glued into the U-channel and onto the supports, electrodes facing the silicon.
            body.push_str(&stroke(&back, PVDF, pw, -pw - aw));
            for (_, a, b) in &cut.electrodes {
                body.push_str(&stroke(&clip(&back, *a, *b), AL, aw, -aw));
            }
        } else {
            // The film below the die on its own: carrier, film, Al, resist.
            let zf = -60.0 / sz;
            let flat = vec![(0.0, zf), (cut.width_um, zf)];
            if f.on_carrier {
                let (a, b) = px(0.0, zf);
                body.push_str(&format!(
                    "<rect x=\"{a:.2}\" y=\"{b:.2}\" width=\"{W_PX:.2}\" height=\"8.00\" \
                     fill=\"{GLASS}\" stroke=\"#888\" stroke-width=\"0.5\"/>"
                ));
            }
            body.push_str(&stroke(&flat, PVDF, pw, 0.0));
            let al: Vec<Vec<(f64, f64)>> = if f.electrodes_patterned {
                cut.electrodes
                    .iter()
                    .map(|(_, a, b)| clip(&flat, *a, *b))
                    .collect()
            } else {
                vec![flat.clone()]
            };
            for part in &al {
                body.push_str(&stroke(part, AL, aw, pw));
            }
            if f.resist.thickness_um > 0.0 {
                let rw = film_w(f.resist.thickness_um);
                let parts: Vec<Vec<(f64, f64)>> = if f.resist.patterned {
                    cut.electrodes
                        .iter()
                        .map(|(_, a, b)| clip(&flat, *a, *b))
                        .collect()
                } else {
                    vec![flat]
                };
                for part in &parts {
                    body.push_str(&stroke(part, RESIST, rw, pw + aw));
                }
            }
        }
    }
    let mut legend = String::new();
    for (i, (c, name)) in [
        (SI, "Si"),
        (OXIDE, "SiO2"),
        (RESIST, "resist"),
        (PVDF, "PVDF"),
        (AL, "Al"),
    ]
    .iter()
    .enumerate()
    {
        let x = X0 + 70.0 * i as f64;
        legend.push_str(&format!(
            "<rect x=\"{x:.2}\" y=\"210\" width=\"10\" height=\"10\" fill=\"{c}\"/><text \
             x=\"{:.2}\" y=\"219\">{name}</text>",
            x + 14.0
        ));
    }
    let exaggeration = sz / sx;
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 640 228\" width=\"640\" \
         height=\"228\" font-family=\"sans-serif\" font-size=\"10\" \
         role=\"img\"><title>{}</title>{body}{legend}<text x=\"{X0}\" y=\"12\">{}</text><text \
         x=\"{X0}\" y=\"24\" fill=\"#555\">cut across y at x = {:.0} um; vertical \
         x{exaggeration:.1}, films not to scale; front (teeth) up</text></svg>",
        escape(caption),
        escape(caption),
        cut.x_um
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cut() -> Cut {
        Cut {
            x_um: 1500.0,
            width_um: 15000.0,
            thickness_um: 500.0,
            teeth: vec![(500.0, 2500.0), (6500.0, 8500.0), (12500.0, 14500.0)],
            supports: vec![(0.0, 2500.0), (12500.0, 15000.0)],
            electrodes: vec![],
            pvdf_thickness_um: 25.0,
        }
    }

    #[test]
    fn sidewalls_fall_at_54_74_degrees() {
        let c = cut();
        let h = 200.0;
        // Tooth top kept, floor at T - h, foot of the sidewall h / tan(54.74 deg) = h / sqrt 2 out.
        assert_eq!(c.front_z(7000.0, h), 500.0);
        assert!((c.front_z(4500.0, h) - 300.0).abs() < 1e-9);
        let run = h / 2f64.sqrt();
        assert!((c.front_z(6500.0 - run, h) - 300.0).abs() < 1e-6);
        let mid = c.front_z(6500.0 - run / 2.0, h);
        assert!(
            (mid - 400.0).abs() < 1e-6,
            "half-way down the sidewall: {mid}"
        );
        let angle = (h / run).atan().to_degrees();
        assert!((angle - 54.7356).abs() < 1e-3);
    }

    #[test]
    fn narrow_opening_self_stops_as_v_groove() {
        let mut c = cut();
        c.teeth = vec![(1000.0, 2000.0), (2200.0, 3200.0)];
        // 200 um opening: V-groove depth gap / sqrt 2 = 141.4 um < 200 um.
        let z = c.front_z(2100.0, 200.0);
        assert!((500.0 - z - 200.0 / 2f64.sqrt()).abs() < 1e-6, "{z}");
    }

    #[test]
    fn back_channel_between_supports_and_plate_thickness() {
        let c = cut();
        let (front, back) = (204.0, 204.0);
        // Channel floor at the back depth; plate under an opening is T - front - back = 92 um.
        assert!((c.back_z(7500.0, back) - back).abs() < 1e-9);
        assert_eq!(c.back_z(1000.0, back), 0.0);
        assert!((c.front_z(4500.0, front) - c.back_z(4500.0, back) - 92.0).abs() < 1e-9);
    }

    #[test]
    fn profile_breakpoints_are_exact_and_ordered() {
        let c = cut();
        let p = c.front_profile(200.0);
        assert!(p.windows(2).all(|w| w[0].0 < w[1].0));
        assert_eq!(p.first().unwrap().0, 0.0);
        assert_eq!(p.last().unwrap().0, 15000.0);
        // Between breakpoints the true profile is linear: midpoints agree with interpolation.
        for w in p.windows(2) {
            let ym = (w[0].0 + w[1].0) / 2.0;
            assert!((c.front_z(ym, 200.0) - (w[0].1 + w[1].1) / 2.0).abs() < 1e-9);
        }
    }

    #[test]
    fn clip_interpolates_ends() {
        let poly = [(0.0, 0.0), (10.0, 10.0), (20.0, 0.0)];
        assert_eq!(
            clip(&poly, 5.0, 15.0),
            vec![(5.0, 5.0), (10.0, 10.0), (15.0, 5.0)]
        );
    }
}
