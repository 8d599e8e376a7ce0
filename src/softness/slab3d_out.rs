//! Outputs of the 3-D slab ([`super::slab3d`]): `tissue-3d.csv` (the face nodes' P0, P and
//! P / P0 with unit headers) and `tissue-3d.svg` (a plan-view heat map of P / P0).

use std::fmt::Write as _;

use super::slab3d::FaceField;

impl FaceField {
    /// One row per face node: x along the jaw, y across (mm), P0 and P (kPa), P / P0.
    pub fn csv(&self) -> String {
        let mut s = String::from("x_mm,y_mm,p0_kpa,p_kpa,p_over_p0\n");
        let nx = self.x_m.len();
        for (j, y) in self.y_m.iter().enumerate() {
            for (i, x) in self.x_m.iter().enumerate() {
                let (p0, p) = (self.p0_pa[j * nx + i], self.p_pa[j * nx + i]);
                let _ = writeln!(
                    s,
                    "{:.4},{:.4},{:.6e},{:.6e},{:.6}",
                    x * 1e3,
                    y * 1e3,
                    p0 * 1e-3,
                    p * 1e-3,
                    p / p0
                );
            }
        }
        s
    }

    /// Plan view of P / P0 over the face (x along the jaw to the right, y across upward): one
    /// rectangle per node's tributary area, blue below 1, white at 1, red above, symmetric
    /// about 1 to the largest |P / P0 - 1|; a colour bar and the extreme values as text.
    pub fn svg(&self, title: &str) -> String {
        let (nx, ny) = (self.x_m.len(), self.y_m.len());
        let (lx, ly) = (
            self.x_m[nx - 1] - self.x_m[0],
            self.y_m[ny - 1] - self.y_m[0],
        );
        let (w_px, left, top) = (640.0, 70.0, 60.0);
        let scale = w_px / lx;
        let h_px = ly * scale;
        let ratio = self.ratio();
        let span = ratio.iter().map(|r| (r - 1.0).abs()).fold(1e-12, f64::max);
        let colour = |r: f64| -> String {
            let t = ((r - 1.0) / span).clamp(-1.0, 1.0);
            let fade = |t: f64| (255.0 * (1.0 - t.abs())).round() as u8;
            if t >= 0.0 {
                format!("#ff{:02x}{:02x}", fade(t), fade(t))
            } else {
                format!("#{:02x}{:02x}ff", fade(t), fade(t))
            }
        };
        // Tributary edges: midpoints between node lines.
        let edges = |ls: &[f64]| -> Vec<f64> {
            let mut e = vec![ls[0]];
            e.extend(ls.windows(2).map(|w| 0.5 * (w[0] + w[1])));
            e.push(ls[ls.len() - 1]);
            e
        };
        let (ex, ey) = (edges(&self.x_m), edges(&self.y_m));
        let width = left + w_px + 170.0;
        let height = top + h_px + 70.0;
        let mut s = format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width:.0}\" height=\"{height:.0}\" \
             viewBox=\"0 0 {width:.0} {height:.0}\" font-family=\"sans-serif\" font-size=\"12\">\n\
             <rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n\
             <text x=\"{left:.0}\" y=\"24\" font-size=\"14\">{title}</text>\n"
        );
        let px = |x: f64| left + (x - self.x_m[0]) * scale;
        let py = |y: f64| top + h_px - (y - self.y_m[0]) * scale;
        for j in 0..ny {
            for i in 0..nx {
                let (x0, x1, y0, y1) = (px(ex[i]), px(ex[i + 1]), py(ey[j + 1]), py(ey[j]));
                let _ = writeln!(
                    s,
                    "<rect x=\"{x0:.2}\" y=\"{y0:.2}\" width=\"{:.2}\" height=\"{:.2}\" \
                     fill=\"{}\"/>",
                    x1 - x0,
                    y1 - y0,
                    colour(ratio[j * nx + i])
                );
            }
        }
        let _ = writeln!(
            s,
            "<rect x=\"{left:.0}\" y=\"{top:.0}\" width=\"{w_px:.2}\" height=\"{h_px:.2}\" \
             fill=\"none\" stroke=\"black\"/>\n\
             <text x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"middle\">x along the jaw (mm), {:.1} \
             to {:.1}</text>\n\
             <text x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"middle\" transform=\"rotate(270 \
             {:.2} {:.2})\">y across (mm), {:.1} to {:.1}</text>",
            left + 0.5 * w_px,
            top + h_px + 30.0,
            self.x_m[0] * 1e3,
            self.x_m[nx - 1] * 1e3,
            left - 20.0,
            top + 0.5 * h_px,
            left - 20.0,
            top + 0.5 * h_px,
            self.y_m[0] * 1e3,
            self.y_m[ny - 1] * 1e3
        );
        // Colour bar.
        let bx = left + w_px + 30.0;
        for k in 0..20 {
            let r = 1.0 + span * (1.0 - 2.0 * (k as f64 + 0.5) / 20.0);
            let _ = writeln!(
                s,
                "<rect x=\"{bx:.2}\" y=\"{:.2}\" width=\"16\" height=\"{:.2}\" fill=\"{}\"/>",
                top + k as f64 * h_px / 20.0,
                h_px / 20.0,
                colour(r)
            );
        }
        let _ = writeln!(
            s,
            "<text x=\"{:.2}\" y=\"{:.2}\">P/P0 {:.3}</text>\n\
             <text x=\"{:.2}\" y=\"{:.2}\">1</text>\n\
             <text x=\"{:.2}\" y=\"{:.2}\">{:.3}</text>\n\
             <text x=\"{left:.0}\" y=\"{:.2}\">peak {:.3} at ({:.2}, {:.2}) mm; min {:.3} at \
             ({:.2}, {:.2}) mm</text>\n</svg>",
            bx + 20.0,
            top + 10.0,
            1.0 + span,
            bx + 20.0,
            top + 0.5 * h_px + 4.0,
            bx + 20.0,
            top + h_px,
            1.0 - span,
            top + h_px + 55.0,
            self.peak_ratio,
            self.peak_at_m[0] * 1e3,
            self.peak_at_m[1] * 1e3,
            self.min_ratio,
            self.min_at_m[0] * 1e3,
            self.min_at_m[1] * 1e3
        );
        s
    }
}
