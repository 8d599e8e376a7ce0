//! Putting several charts on one SVG page.

/// Charts (each a complete `<svg>` from [`super::xy_svg`]) placed left to right in one SVG.
/// Nested `<svg>` elements keep each chart's own coordinates and ids.
pub fn side_by_side(charts: &[String]) -> String {
    let size = |s: &str, attr: &str| -> u32 {
        let key = format!("{attr}=\"");
        s.find(&key)
            .and_then(|i| {
                s[i + key.len()..]
                    .split('"')
                    .next()
                    .and_then(|v| v.parse().ok())
            })
            .unwrap_or(0)
    };
    let width: u32 = charts.iter().map(|c| size(c, "width")).sum();
    let height = charts.iter().map(|c| size(c, "height")).max().unwrap_or(0);
    let mut out = format!("<svg width=\"{width}\" height=\"{height}\" viewBox=\"0 0 {width} {height}\" xmlns=\"http://www.w3.org/2000/svg\">\n");
    let mut x = 0;
    for c in charts {
        out.push_str(&c.replacen("<svg ", &format!("<svg x=\"{x}\" y=\"0\" "), 1));
        out.push('\n');
        x += size(c, "width");
    }
    out.push_str("</svg>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn widths_add_and_each_chart_is_offset() {
        let a = "<svg width=\"100\" height=\"50\" xmlns=\"http://www.w3.org/2000/svg\"></svg>"
            .to_string();
        let b = "<svg width=\"30\" height=\"70\" xmlns=\"http://www.w3.org/2000/svg\"></svg>"
            .to_string();
        let s = side_by_side(&[a, b]);
        assert!(s.starts_with("<svg width=\"130\" height=\"70\""));
        assert!(
            s.contains("<svg x=\"0\" y=\"0\" width=\"100\"")
                && s.contains("<svg x=\"100\" y=\"0\" width=\"30\"")
        );
        assert_eq!(s.matches("</svg>").count(), 3);
    }
}
