//! What a reader would see wrong in a chart: text running off its canvas. A geometric check of
//! the SVG as written (text boxes estimated from the font size), run on every chart in the tests.

/// Average advance of a sans-serif character, in ems (DejaVu Sans digits and lower case: ~0.6).
const EM_PER_CHAR: f64 = 0.6;

/// Every `<text>` whose estimated box leaves the canvas it is drawn on (the root `<svg>` or a
/// nested one placed by [`super::side_by_side`]), as "text (x0..x1, y0..y1) outside W x H".
///
/// ```
/// let svg = r#"<svg width="100" height="50"><text x="90" y="20" text-anchor="start" font-size="10">far too long</text></svg>"#;
/// assert_eq!(tactfab::plot::text_outside_canvas(svg).len(), 1);
/// ```
pub fn text_outside_canvas(svg: &str) -> Vec<String> {
    let attr = |tag: &str, name: &str| -> Option<String> {
        let key = format!(" {name}=\"");
        let i = tag.find(&key)? + key.len();
        Some(tag[i..].split('"').next()?.to_string())
    };
    let num = |tag: &str, name: &str| attr(tag, name).and_then(|v| v.parse::<f64>().ok());
    // Canvas stack: (width, height) of each open <svg>; a nested one has its own coordinates.
    let mut canvases: Vec<(f64, f64)> = Vec::new();
    let mut out = Vec::new();
    let mut rest = svg;
    while let Some(i) = rest.find('<') {
        rest = &rest[i..];
        let end = rest.find('>').map_or(rest.len(), |e| e + 1);
        let tag = &rest[..end];
        if tag.starts_with("<svg") {
            canvases.push((
                num(tag, "width").unwrap_or(f64::INFINITY),
                num(tag, "height").unwrap_or(f64::INFINITY),
            ));
        } else if tag.starts_with("</svg") {
            canvases.pop();
        } else if tag.starts_with("<text") {
            let body_end = rest[end..].find("</text>").map_or(0, |b| b);
            let text = rest[end..end + body_end].trim();
            let (Some(&(w, h)), Some(x), Some(y)) = (canvases.last(), num(tag, "x"), num(tag, "y"))
            else {
                rest = &rest[end..];
                continue;
            };
            let size = num(tag, "font-size").unwrap_or(16.0);
            let len = EM_PER_CHAR * size * text.chars().count() as f64;
            let start = match attr(tag, "text-anchor").as_deref() {
                Some("middle") => -0.5 * len,
                Some("end") => -len,
                _ => 0.0,
            };
            // Along the baseline from the anchor; a quarter turn puts the baseline along y.
            let rotated = attr(tag, "transform")
                .is_some_and(|t| t.contains("rotate(270") || t.contains("rotate(90"));
            let (x0, x1, y0, y1) = if rotated {
                (x - size, x + size, y - start - len, y - start)
            } else {
                (x + start, x + start + len, y - size, y + size)
            };
            if x0 < -0.5 || x1 > w + 0.5 || y0 < -size || y1 > h + size {
                out.push(format!(
                    "{text:?} ({x0:.0}..{x1:.0}, {y0:.0}..{y1:.0}) outside {w} x {h}"
                ));
            }
        }
        rest = &rest[end..];
    }
    out
}
