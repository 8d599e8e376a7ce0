//! Plan-view SVG of the simulated tooth: the drawn mask, the etched top edge at several times
//! and the base at the end, mirrored from the symmetry cell about the tooth's centre lines.

use std::fmt::Write;

use super::tooth::ToothSimulation;

/// Colours of the frames, earliest first (then repeated).
const FRAME_COLOURS: [&str; 4] = ["#9ecae1", "#4292c6", "#2171b5", "#08306b"];

/// The SVG text: 800 px wide, the cell and its mirror images around the tooth centre.
pub fn plan_view(sim: &ToothSimulation) -> String {
    let [x0, y0, x1, y1] = sim.cell_um;
    let (w, h) = (x1 - x0, y1 - y0);
    let px = 800.0 / (2.0 * w);
    let hpx = 2.0 * h * px;
    // Die um to px: the tooth centre (x0, y0) at the middle; y up.
    let tx = |x: f64| (x - x0 + w) * px;
    let ty = |y: f64| hpx - (y - y0 + h) * px;
    let mirror = |x: f64, y: f64, q: usize| {
        let (sx, sy) = [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)][q];
        (x0 + sx * (x - x0), y0 + sy * (y - y0))
    };
    let mut out = String::new();
    let _ = writeln!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"800\" height=\"{:.0}\" \
         viewBox=\"0 0 800 {:.0}\" font-family=\"sans-serif\" font-size=\"12\">",
        hpx + 74.0,
        hpx + 74.0
    );
    let _ = writeln!(
        out,
        "<rect width=\"800\" height=\"{:.0}\" fill=\"white\"/>",
        hpx + 74.0
    );
    let seg_path = |segs: &[[f64; 4]], out: &mut String, colour: &str, width: f64| {
        let mut d = String::new();
        for q in 0..4 {
            for s in segs {
                let (a, b) = (mirror(s[0], s[1], q), mirror(s[2], s[3], q));
                let _ = write!(
                    d,
                    "M{:.1} {:.1}L{:.1} {:.1}",
                    tx(a.0),
                    ty(a.1),
                    tx(b.0),
                    ty(b.1)
                );
            }
        }
        let _ = writeln!(
            out,
            "<path d=\"{d}\" stroke=\"{colour}\" stroke-width=\"{width}\" fill=\"none\"/>"
        );
    };
    // Everything drawn is clipped to the mirrored cell (the drawn mask reaches beyond it and
    // would run into the legend below).
    let _ = writeln!(
        out,
        "<clipPath id=\"tooth-cell\"><rect width=\"800\" height=\"{hpx:.1}\"/></clipPath>\n\
         <g clip-path=\"url(#tooth-cell)\">"
    );
    for q in 0..4 {
        for p in &sim.drawn {
            let mut d = String::new();
            for (k, c) in p.exterior().coords().enumerate() {
                let (x, y) = mirror(c.x, c.y, q);
                let _ = write!(
                    d,
                    "{}{:.1} {:.1}",
                    if k == 0 { "M" } else { "L" },
                    tx(x),
                    ty(y)
                );
            }
            let _ = writeln!(
                out,
                "<path d=\"{d}Z\" fill=\"#eeeeee\" stroke=\"#888888\" stroke-dasharray=\"4 3\"/>"
            );
        }
    }
    seg_path(&sim.base, &mut out, "#d95f02", 1.0);
    for (k, f) in sim.frames.iter().enumerate() {
        seg_path(&f.segments, &mut out, FRAME_COLOURS[k % 4], 1.5);
    }
    out.push_str("</g>\n");
    let legend = format!(
        "Plan view: top edge at {} h (light to dark); orange: base at 95 % depth.",
        sim.frames
            .iter()
            .map(|f| format!("{:.2}", f.time_h))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let corner = format!(
        "Dashed: drawn mask. Corner {:+.1} um along the diagonal ({}), edge undercut {:.1} um.",
        sim.corner_deviation_um,
        crate::spelling::yaml(&sim.corner_shape),
        sim.edge_undercut_um
    );
    let place = format!(
        "Tooth ({}, {}) of the die, {:.0} x {:.0} um around its centre, grid {:.2} um.",
        sim.tooth[0],
        sim.tooth[1],
        2.0 * w,
        2.0 * h,
        sim.grid_um
    );
    for (k, line) in [legend, corner, place].iter().enumerate() {
        let _ = writeln!(
            out,
            "<text x=\"8\" y=\"{:.0}\" font-size=\"12\">{}</text>",
            hpx + 20.0 + 18.0 * k as f64,
            line.replace('&', "&amp;").replace('<', "&lt;")
        );
    }
    out.push_str("</svg>\n");
    out
}

/// Plan-view SVG of the simulated back corner cell: the drawn back mask (supports), the etched
/// top edge at several times and the channel floor's edge (95 % depth) at the end, in drawn die
/// coordinates (the mask as designed, not mirrored for the back exposure), fitted into 800 x
/// 640 px.
pub fn back_plan_view(sim: &super::back::BackSimulation) -> String {
    let [x0, y0, x1, y1] = sim.cell_um;
    let (w, h) = (x1 - x0, y1 - y0);
    let px = (760.0 / w).min(640.0 / h);
    let (wpx, hpx) = (w * px, h * px);
    let left = 0.5 * (800.0 - wpx);
    let top = 10.0;
    let tx = |x: f64| left + (x - x0) * px;
    let ty = |y: f64| top + hpx - (y - y0) * px;
    let height = top + hpx + 100.0;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"800\" height=\"{height:.0}\" \
         viewBox=\"0 0 800 {height:.0}\" font-family=\"sans-serif\" font-size=\"12\">"
    );
    let _ = writeln!(
        out,
        "<rect width=\"800\" height=\"{height:.0}\" fill=\"white\"/>"
    );
    let _ = writeln!(
        out,
        "<clipPath id=\"back-cell\"><rect x=\"{:.1}\" y=\"{top:.1}\" width=\"{wpx:.1}\" \
         height=\"{hpx:.1}\"/></clipPath>",
        left
    );
    let _ = writeln!(
        out,
        "<rect x=\"{left:.1}\" y=\"{top:.1}\" width=\"{wpx:.1}\" height=\"{hpx:.1}\" \
         fill=\"none\" stroke=\"#cccccc\"/>"
    );
    out.push_str("<g clip-path=\"url(#back-cell)\">\n");
    for p in &sim.drawn {
        let mut d = String::new();
        for (k, c) in p.exterior().coords().enumerate() {
            let _ = write!(
                d,
                "{}{:.1} {:.1}",
                if k == 0 { "M" } else { "L" },
                tx(c.x),
                ty(c.y)
            );
        }
        let _ = writeln!(
            out,
            "<path d=\"{d}Z\" fill=\"#eeeeee\" stroke=\"#888888\" stroke-dasharray=\"4 3\"/>"
        );
    }
    let path = |segs: &[[f64; 4]], out: &mut String, colour: &str, width: f64| {
        let mut d = String::new();
        for s in segs {
            let _ = write!(
                d,
                "M{:.1} {:.1}L{:.1} {:.1}",
                tx(s[0]),
                ty(s[1]),
                tx(s[2]),
                ty(s[3])
            );
        }
        let _ = writeln!(
            out,
            "<path d=\"{d}\" stroke=\"{colour}\" stroke-width=\"{width}\" fill=\"none\"/>"
        );
    };
    path(&sim.base, &mut out, "#d95f02", 1.0);
    for (k, f) in sim.frames.iter().enumerate() {
        path(&f.segments, &mut out, FRAME_COLOURS[k % 4], 1.5);
    }
    out.push_str("</g>\n");
    let lines = [
        format!(
            "Back mask: support corner at the die origin, {:.0} x {:.0} um, drawn die \
             coordinates, grid {:.2} um.",
            w, h, sim.grid_um
        ),
        format!(
            "Plan view: top edge at {} h (light to dark); dashed: drawn supports.",
            sim.frames
                .iter()
                .map(|f| format!("{:.2}", f.time_h))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        format!(
            "Orange: channel floor at 95 % depth; its edge y = {:.1} um (etch plan {:.1} um).",
            sim.floor_edge_y_um, sim.plan_floor_edge_y_um
        ),
        format!(
            "Support corner {}.",
            sim.corners
                .first()
                .and_then(|c| c.deviation_um)
                .map_or("not read".to_string(), |d| format!(
                    "{d:+.1} um along its bisector (< 0: receded into the support)"
                ))
        ),
    ];
    for (k, l) in lines.iter().enumerate() {
        let _ = writeln!(
            out,
            "<text x=\"8\" y=\"{:.0}\" font-size=\"12\">{}</text>",
            top + hpx + 22.0 + 18.0 * k as f64,
            l.replace('&', "&amp;").replace('<', "&lt;")
        );
    }
    out.push_str("</svg>\n");
    out
}
