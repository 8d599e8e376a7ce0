//! A [`Doc`] as one self-contained HTML page (inline CSS, figures as inline SVG, no scripts and no
//! external resources; laid out for A4 print), and the traveler in it.

use super::doc::{typeset, Block, Doc, Figure, Format, Rich, Span, Table};
use super::sheet::document;
pub use super::sheet::Figures;
use super::traveler::Traveler;
use crate::export::xml::escape;

const CSS: &str = "body { font-family: sans-serif; font-size: 9pt; margin: 0 auto; color: #111; }
@media screen { body { max-width: 186mm; } }
h1 { font-size: 15pt; margin: 0 0 4pt; } h2 { font-size: 12pt; border-bottom: 1px solid #999; \
                   margin-top: 14pt; }
h2 { break-after: avoid; } table { border-collapse: collapse; width: 100%; margin: 4pt 0; }
th, td { border: 1px solid #999; padding: 2pt 3pt; vertical-align: top; text-align: left; }
th { background: #eee; } td, th { overflow-wrap: break-word; hyphens: auto; }
table.steps { table-layout: fixed; } tr { break-inside: avoid; } .blank { min-width: 18mm; height: \
                   12pt; }
code, .hash { font-family: monospace; font-size: 7.5pt; word-break: break-all; }
.prov { color: #555; font-size: 7.5pt; }
figure { margin: 4pt 0; break-inside: avoid; } figure svg { width: 100%; height: auto; }
.masks { display: grid; grid-template-columns: 1fr 1fr; gap: 6pt; }
.pass { color: #1a7f37; font-weight: bold; } .fail { color: #b00020; font-weight: bold; }
.error { color: #b00020; } .banner { border: 2pt solid #b00020; color: #b00020; padding: 4pt; \
                   margin: 6pt 0; font-size: 11pt; } pre { font-size: 7.5pt; white-space: pre-wrap; }
@media print { .section-steps { break-before: page; page: wide; } }";

/// The traveler as an HTML page.
pub fn html(t: &Traveler, fig: &Figures) -> String {
    render(&document(t, fig))
}

/// A document as an HTML page.
pub fn render(d: &Doc) -> String {
    let mut b = format!(
        "<h1>{}</h1>\n<p>{}</p>\n",
        esc(&d.heading),
        inline(&d.intro)
    );
    if let Some(why) = &d.verdict {
        let items: String = why.iter().map(|w| format!("<li>{}</li>", esc(w))).collect();
        b.push_str(&format!(
            "<div class=\"banner\"><b>BUILD FAILED: do not process wafers with this \
             traveler</b><ul>{items}</ul></div>\n"
        ));
    }
    for sec in &d.sections {
        let class = if sec.page_break {
            format!(" class=\"section-{}\"", sec.id)
        } else {
            String::new()
        };
        b.push_str(&format!(
            "<section id=\"{}\"{class}><h2>{}</h2>\n",
            sec.id,
            esc(sec.title)
        ));
        for x in &sec.blocks {
            block(&mut b, x);
        }
        b.push_str("</section>\n");
    }
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</\
         title>\n<style>\n{}\n{CSS}\n</style>\n</head>\n<body>\n{b}</body>\n</html>\n",
        esc(&d.title),
        page_css(&d.title)
    )
}

/// The printed page: A4 (the run sheet's steps on landscape pages, nine columns wide), and on
/// every page the document, the lot and wafer to fill in, and "page x of y" (CSS paged-media
/// margin boxes).
fn page_css(title: &str) -> String {
    // A CSS string: quotes and backslashes escaped, and `<` so the text cannot close the style.
    let quoted: String = title
        .chars()
        .map(|c| match c {
            '"' | '\\' | '<' => format!("\\{:x} ", c as u32),
            c => c.to_string(),
        })
        .collect();
    let font = "font: 8pt sans-serif; color: #333;";
    format!(
        "@page {{ size: A4; margin: 16mm 12mm 14mm;\n  @top-left {{ content: \"{quoted}\"; {font} \
         }}\n  @top-right {{ content: \"Lot ________   Wafer ________\"; {font} }}\n  \
         @bottom-right {{ content: \"page \" counter(page) \" of \" counter(pages); {font} }} }}\n\
         @page wide {{ size: A4 landscape; }}"
    )
}

/// Text for people: units typeset, then escaped.
fn esc(s: &str) -> String {
    escape(&typeset(s))
}

const BLANK_CELL: &str = "<td class=\"blank\"></td>";

fn block(b: &mut String, x: &Block) {
    match x {
        Block::Para(r) => b.push_str(&format!("<p>{}</p>\n", inline(r))),
        Block::Subheading(h) => b.push_str(&format!("<h3>{}</h3>\n", esc(h))),
        Block::Form(rows) => {
            b.push_str("<table><tbody>");
            for (k, v) in rows {
                let value = match v {
                    Some(v) => format!("<td>{}</td>", esc(v)),
                    None => BLANK_CELL.into(),
                };
                b.push_str(&format!("<tr><th>{}</th>{value}</tr>", esc(k)));
            }
            b.push_str("</tbody></table>\n");
        }
        Block::Table(t) => table(b, t),
        Block::List(items) => {
            if items.is_empty() {
                return;
            }
            b.push_str("<ul>");
            for (r, error) in items {
                let class = if *error { " class=\"error\"" } else { "" };
                b.push_str(&format!("<li{class}>{}</li>", inline(r)));
            }
            b.push_str("</ul>\n");
        }
        Block::Pre(text) => b.push_str(&format!("<pre>{}</pre>\n", esc(text))),
        Block::Figures {
            figures,
            grid,
            max_width_mm,
        } => {
            let style = max_width_mm
                .map(|w| format!(" style=\"max-width: {w}mm\""))
                .unwrap_or_default();
            let figs: String = figures.iter().map(|f| figure(f, &style)).collect();
            if *grid && !figures.is_empty() {
                b.push_str(&format!("<div class=\"masks\">{figs}</div>\n"));
            } else {
                b.push_str(&figs);
            }
        }
        Block::Only(Format::Html, x) => block(b, x),
        Block::Only(Format::Markdown, _) => {}
    }
}

fn figure(f: &Figure, style: &str) -> String {
    // An SVG file's XML declaration cannot sit inside a page.
    let svg = f.svg.find("<svg").map_or(f.svg.as_str(), |i| &f.svg[i..]);
    format!(
        "<figure{style}>{svg}<figcaption>{}</figcaption></figure>\n",
        esc(&f.caption)
    )
}

/// A table; a run sheet gets fixed column widths (%, so it prints on A4) and blank cells.
fn table(b: &mut String, t: &Table) {
    match &t.widths_pct {
        Some(w) => {
            let cols: String = w
                .iter()
                .map(|w| format!("<col style=\"width: {w}%\">"))
                .collect();
            b.push_str(&format!(
                "<table class=\"steps\"><colgroup>{cols}</colgroup>"
            ));
        }
        None => b.push_str("<table>"),
    }
    b.push_str("<thead><tr>");
    for h in &t.head {
        b.push_str(&format!("<th>{}</th>", esc(h)));
    }
    b.push_str("</tr></thead><tbody>");
    for r in &t.rows {
        b.push_str("<tr>");
        for c in r {
            b.push_str(&format!("<td>{}</td>", inline(c)));
        }
        b.push_str(&BLANK_CELL.repeat(t.blanks));
        b.push_str("</tr>");
    }
    b.push_str("</tbody></table>\n");
}

/// Text that may quote code in Markdown backticks (messages are written once, for both
/// formats): the quoted parts as `<code>`, never literal backticks.
fn text(s: &str) -> String {
    if !s.matches('`').count().is_multiple_of(2) {
        return esc(s);
    }
    s.split('`')
        .enumerate()
        .map(|(i, part)| {
            if i % 2 == 1 {
                format!("<code>{}</code>", escape(part))
            } else {
                esc(part)
            }
        })
        .collect()
}

fn inline(r: &Rich) -> String {
    r.0.iter()
        .map(|sp| match sp {
            Span::Text(x) => text(x),
            Span::Code(x) => format!("<code>{}</code>", escape(x)),
            Span::Hash(x) => format!("<span class=\"hash\">{}</span>", escape(x)),
            Span::Value(x) => format!("<b>{}</b>", text(x)),
            Span::Note(x) => format!("<span class=\"prov\">{}</span>", text(x)),
            Span::Pass(x) => format!("<span class=\"pass\">{}</span>", esc(x)),
            Span::Fail(x) => format!("<span class=\"fail\">{}</span>", esc(x)),
            Span::Break => "<br>".into(),
        })
        .collect()
}
