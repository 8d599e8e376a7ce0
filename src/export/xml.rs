//! The one XML/HTML text escaper (.lyp, SVG cross-sections, the HTML traveler).

/// `&`, `<`, `>` and `"` as entities: safe in text and in double-quoted attributes.
///
/// ```
/// assert_eq!(tactfab::export::xml::escape("a < b & \"c\""), "a &lt; b &amp; &quot;c&quot;");
/// ```
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}
