//! What the plate rungs stand on, as numbers a designer can read: the edge stiffness per unit
//! length of wall that `support_model` gives the plate at its clamp lines, and the along-wall
//! (Pasternak) term of `solid_section`. The fe answers show only the stiffness's effect; these
//! are the stiffness itself, in the plate's signs ([`crate::fe::EdgeSpring`]: w down the plate's
//! normal, theta the slope pointing into the support, u the mid-plane's in-plane displacement
//! towards the span).

use serde::Serialize;

use crate::fe::FeResult;
use crate::process::SupportModel;

use super::footing::SupportFooting;
use super::geometry::SensorGeometry;

/// One edge's stiffness per metre of wall on (w, theta, u). `in_plane_pa` is the stiffness
/// across the wall with w and theta free (the compliance's in-plane entry inverted), and
/// `rotation_n` the stiffness on theta with w held and u free (the 3 x 3's Schur complement):
/// the two a designer compares with the clamp (infinite).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EdgeStiffness {
    pub k_w_w_pa: f64,
    pub k_w_theta_n_per_m: f64,
    pub k_theta_theta_n: f64,
    pub k_u_u_pa: f64,
    pub k_w_u_pa: f64,
    pub k_theta_u_n_per_m: f64,
    pub rotation_n: f64,
    pub in_plane_pa: f64,
}

impl EdgeStiffness {
    /// From the coupled 3 x 3 ([[N/m^2, N/m, N/m^2], [N/m, N, N/m], [N/m^2, N/m, N/m^2]]) and
    /// its in-plane stiffness with w and theta free.
    fn coupled(k: &[[f64; 3]; 3], in_plane_pa: f64) -> Self {
        EdgeStiffness {
            k_w_w_pa: k[0][0],
            k_w_theta_n_per_m: k[0][1],
            k_theta_theta_n: k[1][1],
            k_u_u_pa: k[2][2],
            k_w_u_pa: k[0][2],
            k_theta_u_n_per_m: k[1][2],
            rotation_n: super::support_section::with_in_plane_free(k)[1][1],
            in_plane_pa,
        }
    }

    /// From a (w, theta) block and an uncoupled in-plane spring (the elastic footing's).
    fn uncoupled(k: &[[f64; 2]; 2], in_plane_pa: f64) -> Self {
        Self::coupled(
            &[
                [k[0][0], k[0][1], 0.0],
                [k[1][0], k[1][1], 0.0],
                [0.0, 0.0, in_plane_pa],
            ],
            in_plane_pa,
        )
    }
}

/// The along-wall term 1/2 int q'^T G q' dx per clamp line (plate signs): G on (w', theta', u').
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AlongWall {
    pub g_w_w_n: f64,
    pub g_w_theta_n_m: f64,
    pub g_theta_theta_n_m2: f64,
    pub g_u_u_n: f64,
    pub g_w_u_n: f64,
    pub g_theta_u_n_m: f64,
    /// The half wavelength along the wall it was measured at (the channel floor's width, um).
    pub half_wavelength_um: f64,
}

/// The supports as the plate rungs see them.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SupportStiffness {
    pub support_model: SupportModel,
    /// The stiffness along the bare wall; None for the clamp (w and the slope held).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bare: Option<EdgeStiffness>,
    /// Under a tooth of the row standing on a support (`solid_section` with such a row).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub under_tooth: Option<EdgeStiffness>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub along_wall: Option<AlongWall>,
}

impl SupportStiffness {
    /// The design's supports under its `support_model`; an error only if `solid_section`'s
    /// sections failed to solve (the plate answers fail the same way).
    ///
    /// ```
    /// # use tactfab::sensor::{support_stiffness::SupportStiffness, SensorGeometry};
    /// let text = std::fs::read_to_string("process/mis-grasper.yaml").unwrap();
    /// let loaded = tactfab::process::load_str(&text, "mis-grasper.yaml", &[]).unwrap();
    /// let design = tactfab::design::Design::new(loaded.process).unwrap();
    /// let s = SupportStiffness::of(&SensorGeometry::new(&design)).unwrap();
    /// assert!(s.bare.is_none(), "the bundled file clamps the plate");
    /// ```
    pub fn of(g: &SensorGeometry) -> FeResult<Self> {
        let mut out = SupportStiffness {
            support_model: g.support_model,
            bare: None,
            under_tooth: None,
            along_wall: None,
        };
        match g.support_model {
            SupportModel::Clamped => {}
            SupportModel::ElasticFooting => {
                let ft = SupportFooting::new(g);
                out.bare = Some(EdgeStiffness::uncoupled(
                    &ft.edge_stiffness(),
                    ft.in_plane_pa,
                ));
            }
            SupportModel::SolidSection => {
                let s = g.support_sections()?;
                let edge = |x: &super::support_section::SupportSection| {
                    EdgeStiffness::coupled(&x.stiffness, x.in_plane_pa())
                };
                out.bare = Some(edge(&s.bare));
                out.under_tooth = s.under_tooth.as_ref().map(edge);
                let g_ = &s.along_wall;
                out.along_wall = Some(AlongWall {
                    g_w_w_n: g_[0][0],
                    g_w_theta_n_m: g_[0][1],
                    g_theta_theta_n_m2: g_[1][1],
                    g_u_u_n: g_[2][2],
                    g_w_u_n: g_[0][2],
                    g_theta_u_n_m: g_[1][2],
                    half_wavelength_um: super::support_section::along_wall_half_wavelength_um(g),
                });
            }
        }
        Ok(out)
    }

    /// Lines for the text reports, starting "supports:".
    pub fn text(&self) -> String {
        let model = crate::spelling::yaml(&self.support_model);
        let Some(bare) = &self.bare else {
            // The support islands' readings are the clamp's reaction, not the film under them:
            // said where the user reads them (the solid reads the film; README, "the support
            // islands read").
            return format!(
                "supports: `support_model: {model}`: w and the slope held where the etched walls \
                 meet the plate (an infinitely stiff edge); the support islands read d33 x the \
                 clamp's reaction along them (paper 001 Eq. 6), not the film under them, which \
                 the 3D solid reads (on the bundled design with the opposite sign): \
                 `support_model: solid_section` or --verify-solid for those readings\n"
            );
        };
        let edge = |name: &str, e: &EdgeStiffness| {
            format!(
                "  {name}: per m of wall k_ww {:.4e} N/m^2, k_wtheta {:.4e} N/m, k_thetatheta \
                 {:.4e} N, k_uu {:.4e} N/m^2, k_wu {:.4e} N/m^2, k_thetau {:.4e} N/m; rotation \
                 (w held, u free) {:.4e} N, in-plane (w, theta free) {:.4e} N/m^2\n",
                e.k_w_w_pa,
                e.k_w_theta_n_per_m,
                e.k_theta_theta_n,
                e.k_u_u_pa,
                e.k_w_u_pa,
                e.k_theta_u_n_per_m,
                e.rotation_n,
                e.in_plane_pa
            )
        };
        let mut s = format!(
            "supports: `support_model: {model}`: edge springs on (w, theta, u) at the clamp \
             lines, plate signs\n"
        );
        s.push_str(&edge("bare wall", bare));
        if let Some(t) = &self.under_tooth {
            s.push_str(&edge("under a tooth", t));
        }
        if let Some(a) = &self.along_wall {
            s.push_str(&format!(
                "  along the wall (1/2 int q'^T G q' dx, measured at a half wavelength of {:.0} \
                 um): G_ww {:.4e} N, G_wtheta {:.4e} N m, G_thetatheta {:.4e} N m^2, G_uu {:.4e} \
                 N, G_wu {:.4e} N, G_thetau {:.4e} N m\n",
                a.half_wavelength_um,
                a.g_w_w_n,
                a.g_w_theta_n_m,
                a.g_theta_theta_n_m2,
                a.g_u_u_n,
                a.g_w_u_n,
                a.g_theta_u_n_m
            ));
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor::geometry::bundled as geometry;

    #[test]
    fn the_report_carries_the_springs_the_plate_gets() {
        let g = geometry(&["materials.base.support_model=solid_section"]);
        let r = SupportStiffness::of(&g).unwrap();
        let s = g.support_sections().unwrap();
        let bare = r.bare.unwrap();
        // The same numbers the plate's edge springs take (evaluate::build_problem).
        assert_eq!(bare.k_w_w_pa, s.bare.stiffness[0][0]);
        assert_eq!(bare.k_theta_u_n_per_m, s.bare.stiffness[1][2]);
        assert_eq!(bare.in_plane_pa, s.bare.in_plane_pa());
        assert!(
            (bare.rotation_n - s.bare.bending_stiffness()[1][1]).abs()
                < 1e-12 * bare.rotation_n.abs(),
            "the rotation with w held is the bending block's theta entry: {bare:?}"
        );
        assert_eq!(r.under_tooth.is_some(), s.under_tooth.is_some());
        let a = r.along_wall.unwrap();
        assert_eq!(a.g_u_u_n, s.along_wall[2][2]);
        // The channel floor's width (the span's first mode along the wall).
        assert_eq!(a.half_wavelength_um, g.plate_y1_um - g.plate_y0_um);
        // A stiff edge: positive diagonal, in-plane with w, theta free below k_uu.
        assert!(bare.k_w_w_pa > 0.0 && bare.k_theta_theta_n > 0.0 && bare.k_u_u_pa > 0.0);
        assert!(bare.in_plane_pa > 0.0 && bare.in_plane_pa <= bare.k_u_u_pa * (1.0 + 1e-12));
        let text = r.text();
        assert!(
            text.starts_with("supports: `support_model: solid_section`"),
            "{text}"
        );
        assert!(text.contains("along the wall"), "{text}");
        let json = serde_json::to_value(&r).unwrap();
        assert_eq!(json["support_model"], "solid_section");
        assert!(json["bare"]["k_w_w_pa"].as_f64().unwrap() > 0.0);
    }

    #[test]
    fn the_clamp_and_the_footing_say_what_they_hold() {
        let r = SupportStiffness::of(&geometry(&[])).unwrap();
        assert_eq!(r.bare, None);
        assert!(
            r.text().contains("infinitely stiff")
                && r.text().contains("d33 x the clamp's reaction"),
            "{}",
            r.text()
        );
        let g = geometry(&["materials.base.support_model=elastic_footing"]);
        let r = SupportStiffness::of(&g).unwrap();
        let ft = SupportFooting::new(&g);
        let b = r.bare.unwrap();
        assert_eq!(b.k_theta_theta_n, ft.edge_stiffness()[1][1]);
        assert_eq!(b.k_w_u_pa, 0.0);
        assert_eq!(b.in_plane_pa, ft.in_plane_pa);
        assert!(r.along_wall.is_none() && r.under_tooth.is_none());
    }
}
