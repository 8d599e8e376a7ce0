//! The traveler's cross-section of the simulated tooth: the etched surface along the tooth's
//! diagonal (centre to the street and the diagonal neighbour) drawn as an obliquely extruded
//! slab, so the facets read as faces; the drawn mask (tooth plus compensator) above it and the
//! drawn corner marked. Heights exaggerated by [`VERTICAL_EXAGGERATION`] (stated in the SVG).

use std::fmt::Write;

use super::tooth::ToothSimulation;

/// Vertical exaggeration of the section \[choice: 200 um of depth against 2 mm of diagonal\].
pub const VERTICAL_EXAGGERATION: f64 = 3.0;

/// The SVG text, 720 px wide.
pub fn diagonal_section(sim: &ToothSimulation) -> String {
    let prof = &sim.diagonal_profile;
    let len = prof.last().map_or(1.0, |p| p[0]).max(1.0);
    let depth = sim.floor_depth_um.max(1.0);
    let px = 600.0 / len;
    let pz = px * VERTICAL_EXAGGERATION;
    let (ox, oy) = (60.0, -36.0); // the oblique depth of the slab
    let (left, top) = (20.0, 70.0);
    let base = depth * 0.35;
    let height = top + (depth + base) * pz + 70.0;
    let x = |s: f64| left + s * px;
    let y = |z: f64| top - z * pz;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"720\" height=\"{height:.0}\" \
         viewBox=\"0 0 720 {height:.0}\" font-family=\"sans-serif\" font-size=\"12\" \
         role=\"img\"><title>etched tooth along its diagonal</title>"
    );
    let _ = writeln!(
        out,
        "<rect width=\"720\" height=\"{height:.0}\" fill=\"white\"/>"
    );
    // Top faces: one strip per profile segment, shaded by its slope (steeper darker).
    for w in prof.windows(2) {
        let (a, b) = (w[0], w[1]);
        let slope = ((b[1] - a[1]) / (b[0] - a[0]).max(1e-9)).abs();
        let shade = (225.0 - 120.0 * (slope / (1.0 + slope))).round() as u8;
        let _ = writeln!(
            out,
            "<path d=\"M{:.1} {:.1}L{:.1} {:.1}L{:.1} {:.1}L{:.1} {:.1}Z\" fill=\"rgb({shade},{shade},{})\" \
             stroke=\"none\"/>",
            x(a[0]),
            y(a[1]),
            x(b[0]),
            y(b[1]),
            x(b[0]) + ox,
            y(b[1]) + oy,
            x(a[0]) + ox,
            y(a[1]) + oy,
            shade.saturating_add(15)
        );
    }
    // Front face: the section itself.
    let mut d = format!("M{:.1} {:.1}", x(0.0), y(-depth - base));
    for p in prof {
        let _ = write!(d, "L{:.1} {:.1}", x(p[0]), y(p[1]));
    }
    let _ = write!(d, "L{:.1} {:.1}Z", x(len), y(-depth - base));
    let _ = writeln!(
        out,
        "<path d=\"{d}\" fill=\"#9a9a9a\" stroke=\"#333333\" stroke-width=\"1\"/>"
    );
    // Right end face.
    let _ = writeln!(
        out,
        "<path d=\"M{:.1} {:.1}L{:.1} {:.1}L{:.1} {:.1}L{:.1} {:.1}Z\" fill=\"#7a7a7a\" \
         stroke=\"#333333\"/>",
        x(len),
        y(prof.last().map_or(0.0, |p| p[1])),
        x(len) + ox,
        y(prof.last().map_or(0.0, |p| p[1])) + oy,
        x(len) + ox,
        y(-depth - base) + oy,
        x(len),
        y(-depth - base)
    );
    // The drawn mask (oxide) along the diagonal, and the drawn tooth corner.
    let corner = sim.tooth_top_um / 2.0 * 2f64.sqrt();
    let _ = writeln!(
        out,
        "<path d=\"M{:.1} {:.1}L{:.1} {:.1}\" stroke=\"#b2182b\" stroke-width=\"4\"/>",
        x(0.0),
        y(0.0) - 3.0,
        x(sim.drawn_diagonal_um),
        y(0.0) - 3.0
    );
    let _ = writeln!(
        out,
        "<path d=\"M{:.1} {:.1}L{:.1} {:.1}\" stroke=\"#b2182b\" stroke-dasharray=\"4 3\"/>",
        x(corner),
        y(0.0) - 20.0,
        x(corner),
        y(-depth)
    );
    let _ = writeln!(
        out,
        "<text x=\"{:.1}\" y=\"{:.1}\" fill=\"#b2182b\">drawn corner</text>",
        x(corner) + 4.0,
        y(0.0) - 24.0
    );
    let best = sim.corner_error.map_or(sim.corner_deviation_um, |e| {
        e.extrapolated_corner_deviation_um
    });
    let _ = writeln!(
        out,
        "<text x=\"8\" y=\"18\">tooth centre (left) along the diagonal to the street and the \
         neighbour; red: the drawn mask (tooth and compensator)</text>"
    );
    let _ = writeln!(
        out,
        "<text x=\"8\" y=\"{:.0}\">after {:.2} h on a {:.0} um grid: corner {:+.1} um (best \
         estimate {:+.1} um), floor {:.0} um deep; heights x{VERTICAL_EXAGGERATION}</text>",
        height - 14.0,
        sim.time_h,
        sim.grid_um,
        sim.corner_deviation_um,
        best,
        sim.floor_depth_um
    );
    out.push_str("</svg>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn section_draws_the_profile_once_per_segment() {
        let text = std::fs::read_to_string("process/mis-grasper.yaml").unwrap();
        let p = crate::process::load_str(&text, "mis-grasper.yaml", &[])
            .unwrap()
            .process;
        let plan = crate::etch::plan(&p);
        let masks = crate::layout::build(&p, &plan).unwrap();
        let sim = super::super::simulate(&p, &plan, &masks, 40.0).unwrap();
        // The profile starts on the tooth top (unetched) and reaches the floor.
        let prof = &sim.diagonal_profile;
        assert!(prof[0][1].abs() < 1e-9);
        let low = prof.iter().map(|p| p[1]).fold(0.0, f64::min);
        assert!(
            (low + sim.floor_depth_um).abs() < 0.05 * sim.floor_depth_um,
            "{low}"
        );
        // The drawn mask reaches beyond the tooth corner by the compensator's diagonal.
        let corner = 1000.0 * 2f64.sqrt();
        assert!(
            sim.drawn_diagonal_um > corner + 300.0,
            "{}",
            sim.drawn_diagonal_um
        );
        let svg = diagonal_section(&sim);
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
        assert_eq!(svg.matches("<path").count(), prof.len() - 1 + 4);
    }
}
