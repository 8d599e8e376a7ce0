//! The supports' elastic footing for the plate rungs (`materials.base.support_model:
//! elastic_footing`): each support, a strip of silicon of the support height plus the plate
//! thickness from its etched footprint edge to the die edge, is a beam on the PVDF film and the
//! base as a Winkler foundation ([`crate::fe::footing::FootingBeam`], Hetenyi 1946). Its end
//! stiffness, carried to the clamp line, holds the plate there instead of the clamp; the support
//! electrodes read the film bonded under it: the foundation pressure through it and the beam's
//! bottom strain across the wall in it (`readout::footing_charge_pc`).

use crate::fe::footing::{FootingBeam, FootingShape};

use super::geometry::{Base, SensorGeometry};

/// One support's footing, the same for both supports (they mirror).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SupportFooting {
    pub beam: FootingBeam,
    /// Distance from the clamp line (where the etched wall meets the plate) out to the footing's
    /// edge on the film (um): the {111} wall's run-out, taken as a rigid link \[choice\].
    pub offset_um: f64,
    /// The beam's height, support plus plate (um): its bottom fibre, which the film under it
    /// follows, lies half of it under the neutral axis.
    pub height_um: f64,
    /// The film's and the base's foundation moduli (N/m^3) in series make `beam.k_pa_per_m`.
    pub film_k_pa_per_m: f64,
    pub base_k_pa_per_m: f64,
    /// The support's in-plane give across the wall, per unit length along it (N/m^2): the
    /// film's shear lag and the base's shear in series ([`in_plane_stiffness_pa`]).
    pub in_plane_pa: f64,
}

/// In-plane stiffness across the wall, per unit length along it (N/m^2), of a support pulled
/// towards the span at its edge (the plate's membrane force), in series:
///
/// - the film's shear lag (Volkersen 1938, "Die Nietkraftverteilung in zugbeanspruchten
///   Nietverbindungen mit konstanten Laschenquerschnitten", Luftfahrtforschung 15, 41-47: the
///   shear-lag model of a bonded lap): the support strip (in-plane stiffness `ea_n_per_m`,
///   length `length_m` from the pulled edge to its free end at the die edge) on a film of shear
///   stiffness G_f / t_f per area over a rigid substrate, EA u'' = (G_f / t_f) u with
///   EA u'(0) = -F and u'(L) = 0, gives F / u(0) = EA beta tanh(beta L),
///   beta = sqrt(G_f / (t_f EA));
/// - the base (a layer of thickness H held on its bottom face) in simple shear under the
///   support's footprint, which the support (far stiffer in-plane than the layer) drags as a
///   whole, the loaded width taken as the footprint plus H / 2 on the channel side (a 45 degree
///   spread of half the layer; the die edge bounds the other side), G_b (L + H / 2) / H
///   \[choice\]: not checked against the layer's elastic solution. A rigid base adds nothing.
pub fn in_plane_stiffness_pa(
    ea_n_per_m: f64,
    length_m: f64,
    film_g_pa: f64,
    film_thickness_m: f64,
    base: Base,
) -> f64 {
    let beta = (film_g_pa / (film_thickness_m * ea_n_per_m)).sqrt();
    let film = ea_n_per_m * beta * (beta * length_m).tanh();
    match base {
        Base::Rigid => film,
        Base::Elastic {
            thickness_um,
            e_pa,
            nu,
        } => {
            let h = thickness_um * 1e-6;
            let base = e_pa / (2.0 * (1.0 + nu)) * (length_m + 0.5 * h) / h;
            1.0 / (1.0 / film + 1.0 / base)
        }
    }
}

/// Constrained (oedometric) modulus E (1 - nu) / ((1 + nu)(1 - 2 nu)): a layer thin against the
/// load's length scale, bonded on both faces, compressed without lateral strain.
fn constrained_modulus_pa(e_pa: f64, nu: f64) -> f64 {
    e_pa * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu))
}

impl SupportFooting {
    /// The footing of the design's supports.
    ///
    /// - Beam: D = Q22 h^3 / 12 per unit length along the wall (cylindrical bending across the
    ///   support, silicon's reduced stiffness in the die's y direction), h = support height +
    ///   plate thickness; length from the footprint edge to the die edge, free there.
    /// - Film: k_f = E_oed / t_f (the film is 25 um against a foundation length of tenths of a
    ///   mm).
    /// - Base (2 mm Plexiglas, held at its bottom), \[choice\]: Vesic's half-space modulus for a
    ///   beam of width b (A. B. Vesic, "Beams on elastic subgrade and the Winkler's hypothesis",
    ///   Proc. 5th ICSMFE, Paris 1961, vol. 1, 845-850): k = 0.65 (E_s b^4 / (E I))^(1/12)
    ///   E_s / ((1 - nu_s^2) b) with b = 1 / lambda, the width over which the footing pressure
    ///   acts (E I = D b), plus the layer's own Winkler stiffness E_oed / H so that the
    ///   thinness of the layer (2 mm against a pressure wave 2 pi / lambda long) stiffens it;
    ///   the sum bridges the half-space (short waves) and the thin layer (long waves). lambda
    ///   and k are iterated to a fixed point. A rigid base adds nothing.
    pub fn new(g: &SensorGeometry) -> Self {
        let h_m = (g.etched.support_height_um + g.plate_thickness_um) * 1e-6;
        let d_nm = g.material.bending_stiffness(h_m).d22_nm;
        let film_k = constrained_modulus_pa(g.pvdf_e_pa, g.pvdf_nu) / (g.film_thickness_um * 1e-6);
        let length_m = g.etched.support_edge_y_um.max(1.0) * 1e-6;
        let offset_um = (g.plate_y0_um - g.etched.support_edge_y_um).max(0.0);
        let base_k = |lambda: f64| match g.base {
            Base::Rigid => f64::INFINITY,
            Base::Elastic {
                thickness_um,
                e_pa,
                nu,
            } => {
                let b = 1.0 / lambda;
                let half_space = 0.65 * (e_pa * b.powi(3) / d_nm).powf(1.0 / 12.0) * e_pa
                    / ((1.0 - nu * nu) * b);
                half_space + constrained_modulus_pa(e_pa, nu) / (thickness_um * 1e-6)
            }
        };
        let series = |kb: f64| 1.0 / (1.0 / film_k + 1.0 / kb);
        // Fixed point on lambda: k grows with lambda as lambda^(3/4) at most, lambda with k^(1/4),
        // so the map contracts (factor <= 3/16).
        let mut k = film_k;
        for _ in 0..60 {
            let lambda = (k / (4.0 * d_nm)).powf(0.25);
            let next = series(base_k(lambda));
            let done = (next - k).abs() <= 1e-13 * k;
            k = next;
            if done {
                break;
            }
        }
        let lambda = (k / (4.0 * d_nm)).powf(0.25);
        SupportFooting {
            beam: FootingBeam {
                d_nm,
                k_pa_per_m: k,
                length_m,
            },
            offset_um,
            height_um: h_m * 1e6,
            film_k_pa_per_m: film_k,
            base_k_pa_per_m: base_k(lambda),
            in_plane_pa: in_plane_stiffness_pa(
                g.material.q22_pa * h_m,
                length_m,
                g.pvdf_e_pa / (2.0 * (1.0 + g.pvdf_nu)),
                g.film_thickness_um * 1e-6,
                g.base,
            ),
        }
    }

    /// Characteristic length 1 / lambda (um).
    pub fn length_scale_um(&self) -> f64 {
        1e6 / self.beam.lambda_per_m()
    }

    /// The beam's end state from the plate's (w, theta) at the clamp line, theta pointing into
    /// the support: the rigid wall link moves the end by the offset (w0 = w + theta d).
    fn beam_end(&self, w_m: f64, theta: f64) -> (f64, f64) {
        (w_m + theta * self.offset_um * 1e-6, theta)
    }

    /// Stiffness per unit length on the plate's (w, theta) at the clamp line: T^T K T with K the
    /// footing beam's end stiffness and T the rigid link [[1, d], [0, 1]].
    pub fn edge_stiffness(&self) -> [[f64; 2]; 2] {
        let k = self.beam.end_stiffness();
        let d = self.offset_um * 1e-6;
        [
            [k[0][0], k[0][1] + d * k[0][0]],
            [
                k[0][1] + d * k[0][0],
                k[1][1] + 2.0 * d * k[0][1] + d * d * k[0][0],
            ],
        ]
    }

    /// Footing shape under the plate's edge state (w, theta at the clamp line).
    pub fn shape(&self, w_m: f64, theta: f64) -> FootingShape {
        let (w0, t0) = self.beam_end(w_m, theta);
        self.beam.shape(w0, t0)
    }

    /// Foundation force per unit length along the wall (N/m, positive in compression) between
    /// the distances s0 and s1 (um) from the footing's edge, for the plate's edge state.
    pub fn force_per_length(&self, w_m: f64, theta: f64, s0_um: f64, s1_um: f64) -> f64 {
        self.beam.k_pa_per_m
            * self
                .shape(w_m, theta)
                .deflection_integral_m2(s0_um * 1e-6, s1_um * 1e-6)
    }

    /// Integral over [s0, s1] (um from the footing's edge, clipped to the beam) of the
    /// support's strain across the wall at its bottom face, where the film is bonded (m):
    /// Euler-Bernoulli, eps = -(h / 2) w'' at h / 2 under the neutral axis (w downward), so the
    /// integral is -(h / 2) (w'(s1) - w'(s0)).
    pub fn bottom_strain_integral_m(&self, w_m: f64, theta: f64, s0_um: f64, s1_um: f64) -> f64 {
        let (a, b) = (
            (s0_um * 1e-6).max(0.0),
            (s1_um * 1e-6).min(self.beam.length_m),
        );
        if b <= a {
            return 0.0;
        }
        let shape = self.shape(w_m, theta);
        -0.5 * self.height_um * 1e-6 * (shape.derivative(1, b) - shape.derivative(1, a))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::{Load, PlateSolution};
    use crate::sensor::evaluate::build_problem;
    use crate::sensor::geometry::{ElectrodeArea, ElectrodeSide};
    use crate::sensor::mesh_lines::{base_lines, MeshOptions};
    use crate::sensor::readout::footing_island;
    use crate::sensor::symmetry::Symmetry;

    /// The bundled design on the elastic footing, with `sets`.
    fn geometry(sets: &[&str]) -> SensorGeometry {
        let mut all = vec!["materials.base.support_model=elastic_footing"];
        all.extend_from_slice(sets);
        crate::sensor::geometry::bundled(&all)
    }

    /// The whole plate at level 1 under a point load at (x, y) um.
    fn solve(g: &SensorGeometry, x_um: f64, y_um: f64, force_n: f64) -> PlateSolution {
        let sym = Symmetry::none(g);
        let base = base_lines(g, &[], &sym, &MeshOptions::FEATURE_LINES);
        let mut p = build_problem(g, &base, 1, &sym).unwrap();
        assert_eq!(p.edge_springs.len(), 2, "the footing replaces the clamps");
        assert!(p.supports.is_empty());
        p.load_cases.push(vec![Load::Point {
            x_um,
            y_um,
            force_n,
            radius_um: 0.0,
        }]);
        p.solve().unwrap().remove(0)
    }

    fn whole_footing(g: &SensorGeometry, side: ElectrodeSide) -> ElectrodeArea {
        let (y0, y1) = match side {
            ElectrodeSide::Support1 => (0.0, g.etched.support_edge_y_um),
            _ => (g.width_um - g.etched.support_edge_y_um, g.width_um),
        };
        ElectrodeArea {
            name: "all".into(),
            side,
            x0_um: 0.0,
            y0_um: y0,
            x1_um: g.length_um,
            y1_um: y1,
            area_um2: 1.0,
        }
    }

    #[test]
    fn the_footing_pressure_carries_each_supports_reaction() {
        for sets in [&[][..], &["materials.base.kind=rigid"][..]] {
            let g = geometry(sets);
            let s = solve(&g, 11_000.0, 6_000.0, 0.3);
            for side in [ElectrodeSide::Support1, ElectrodeSide::Support2] {
                let ft = SupportFooting::new(&g);
                let f = footing_island(&g, &ft, &s, side, &whole_footing(&g, side)).force_n;
                let r = s
                    .reaction_n(crate::sensor::readout::group_for(side))
                    .unwrap();
                assert!((f - r).abs() < 1e-9 * 0.3, "{sets:?} {side:?}: {f} vs {r}");
            }
            let total = s.reaction_n("support1").unwrap() + s.reaction_n("support2").unwrap();
            assert!((total - 0.3).abs() < 1e-9 * 0.3, "{total}");
        }
    }

    #[test]
    fn mirrored_load_mirrors_the_island_forces_and_doubles_linearly() {
        // No teeth: the plate is mirror-symmetric about the die's centre line y = W / 2.
        let g = geometry(&["geometry.teeth.pattern=none"]);
        let w = g.width_um;
        let ft = SupportFooting::new(&g);
        let a = solve(&g, 11_000.0, 6_000.0, 0.2);
        let b = solve(&g, 11_000.0, w - 6_000.0, 0.2);
        let c = solve(&g, 11_000.0, 6_000.0, 0.4);
        // Islands from the footing's edge outwards, mirrored: the one near the edge is in
        // compression, the far one in tension (the footing lifts off there).
        let edge = g.etched.support_edge_y_um;
        let mut sign = Vec::new();
        for (s0, s1) in [(50.0, 900.0), (1200.0, 2400.0)] {
            let island = |side, y0, y1| ElectrodeArea {
                name: "i".into(),
                side,
                x0_um: 8_000.0,
                y0_um: y0,
                x1_um: 15_000.0,
                y1_um: y1,
                area_um2: 1.0,
            };
            let i1 = island(ElectrodeSide::Support1, edge - s1, edge - s0);
            let i2 = island(ElectrodeSide::Support2, w - edge + s0, w - edge + s1);
            let fa = footing_island(&g, &ft, &a, ElectrodeSide::Support1, &i1).force_n;
            let fb = footing_island(&g, &ft, &b, ElectrodeSide::Support2, &i2).force_n;
            let fc = footing_island(&g, &ft, &c, ElectrodeSide::Support1, &i1).force_n;
            assert!((fa - fb).abs() < 1e-9 * fa.abs(), "{fa} vs {fb}");
            assert!((fc - 2.0 * fa).abs() < 1e-9 * fa.abs(), "{fc} vs 2 x {fa}");
            sign.push(fa.signum());
        }
        assert_eq!(sign, [1.0, -1.0], "compression at the edge, tension beyond");
    }

    /// The film's shear lag against a finite-difference solution of EA u'' = (G / t) u on the
    /// strip (u'(L) = 0, EA u'(0) = -F), and the base in series, the rigid base its limit.
    #[test]
    fn in_plane_stiffness_is_the_shear_lag_in_series_with_the_base() {
        let (ea, l, g, t) = (5e7, 2.5e-3, 1.1e9, 25e-6);
        let k = in_plane_stiffness_pa(ea, l, g, t, Base::Rigid);
        let n = 4000;
        let h = l / n as f64;
        let c = g / t * h * h / ea;
        // Rows i = 0..=n of -u_{i-1} + (2 + c) u_i - u_{i+1} = 0 with mirrored ghosts:
        // u_{-1} = u_1 + 2 h F / EA (F = 1) and u_{n+1} = u_{n-1}; halves at the ends so the
        // matrix is symmetric; Thomas algorithm.
        let mut diag = vec![2.0 + c; n + 1];
        let (lo, mut rhs) = (vec![-1.0; n + 1], vec![0.0; n + 1]);
        diag[0] = 1.0 + 0.5 * c;
        diag[n] = 1.0 + 0.5 * c;
        rhs[0] = h / ea;
        for i in 1..=n {
            let f = lo[i] / diag[i - 1];
            diag[i] -= f * lo[i];
            rhs[i] -= f * rhs[i - 1];
        }
        let mut u = vec![0.0; n + 1];
        u[n] = rhs[n] / diag[n];
        for i in (0..n).rev() {
            u[i] = (rhs[i] - lo[i + 1] * u[i + 1]) / diag[i];
        }
        let k_fd = 1.0 / u[0];
        assert!(
            (k - k_fd).abs() < 1e-4 * k,
            "{k} vs finite differences {k_fd}"
        );
        // A long strip: sqrt(EA G / t).
        let long = in_plane_stiffness_pa(ea, 1.0, g, t, Base::Rigid);
        assert!((long - (ea * g / t).sqrt()).abs() < 1e-12 * long);
        let base = |e_pa: f64| Base::Elastic {
            thickness_um: 2000.0,
            e_pa,
            nu: 0.37,
        };
        let kb = 3e9 / 2.74 * (l + 1e-3) / 2e-3;
        let series = in_plane_stiffness_pa(ea, l, g, t, base(3e9));
        assert!((1.0 / series - 1.0 / k - 1.0 / kb).abs() < 1e-12 / series);
        let stiff = in_plane_stiffness_pa(ea, l, g, t, base(3e19));
        assert!((stiff - k).abs() < 1e-8 * k, "{stiff} vs rigid {k}");
    }

    /// The island's strain integral is -(h / 2) times the integral of w'' over its extent,
    /// checked against composite Gauss on the beam's second derivative, clipped at the beam's
    /// ends, and linear in the end state.
    #[test]
    fn the_bottom_strain_integral_is_the_bottom_fibres_strain_integrated() {
        let g = geometry(&[]);
        let ft = SupportFooting::new(&g);
        let (w, t) = (2.0e-7, -4.0e-4);
        let shape = ft.shape(w, t);
        let len_um = ft.beam.length_m * 1e6;
        let h = ft.height_um * 1e-6;
        assert!((ft.height_um - 292.0).abs() < 1.0, "{}", ft.height_um);
        let gauss = |a_um: f64, b_um: f64| -> f64 {
            let n = 400;
            let d = (b_um - a_um) / n as f64;
            (0..n)
                .flat_map(|i| {
                    let x0 = a_um + d * i as f64;
                    crate::fe::bfs::gauss4_on(x0, x0 + d)
                })
                .map(|(s, wq)| -0.5 * h * shape.derivative(2, s * 1e-6) * wq * 1e-6)
                .sum()
        };
        for (s0, s1) in [
            (0.0, 300.0),
            (180.0, 2300.0),
            (-100.0, 500.0),
            (2000.0, 9e9),
        ] {
            let got = ft.bottom_strain_integral_m(w, t, s0, s1);
            let want = gauss(f64::max(s0, 0.0), f64::min(s1, len_um));
            assert!(
                (got - want).abs() < 1e-9 * want.abs().max(1e-12),
                "[{s0}, {s1}]: {got} vs {want}"
            );
        }
        let a = ft.bottom_strain_integral_m(w, t, 100.0, 900.0);
        let b = ft.bottom_strain_integral_m(3.0 * w, 3.0 * t, 100.0, 900.0);
        assert!((b - 3.0 * a).abs() < 1e-12 * a.abs(), "{b} vs 3 x {a}");
        assert_eq!(ft.bottom_strain_integral_m(w, t, 900.0, 100.0), 0.0);
    }

    #[test]
    fn a_stiff_foundation_approaches_the_clamp() {
        let mut g = geometry(&["materials.base.kind=rigid"]);
        let soft = SupportFooting::new(&g);
        g.pvdf_e_pa *= 1e6;
        let stiff = SupportFooting::new(&g);
        assert!(stiff.length_scale_um() < 0.05 * soft.length_scale_um());
        let wc = {
            let mut gc = g.clone();
            gc.support_model = crate::process::SupportModel::Clamped;
            let sym = Symmetry::none(&gc);
            let base = base_lines(&gc, &[], &sym, &MeshOptions::FEATURE_LINES);
            let mut p = build_problem(&gc, &base, 1, &sym).unwrap();
            p.load_cases.push(vec![Load::Point {
                x_um: 15_000.0,
                y_um: 7_500.0,
                force_n: 0.1,
                radius_um: 0.0,
            }]);
            p.solve().unwrap()[0].deflection_m(15_000.0, 7_500.0)
        };
        let ws = solve(&g, 15_000.0, 7_500.0, 0.1).deflection_m(15_000.0, 7_500.0);
        assert!((ws - wc).abs() < 2e-3 * wc, "{ws} vs clamped {wc}");
    }
}
