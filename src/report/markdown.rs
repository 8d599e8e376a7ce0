//! A [`Doc`] as Markdown (GitHub tables; `<br>` inside cells), and the traveler in it.
//! Deterministic: fixed decimals, the model's order, no dates or timings.

use super::doc::{typeset as ts, Block, Doc, Format, Rich, Span, Table};
use super::sheet::{document, Figures};
use super::traveler::Traveler;

/// Blank for the operator to fill in.
pub const BLANK: &str = "________";

/// The traveler as Markdown text.
pub fn markdown(t: &Traveler) -> String {
    render(&document(t, &Figures::default()))
}

/// A document as Markdown.
pub fn render(d: &Doc) -> String {
    let mut s = format!("# {}\n\n{}\n\n", ts(&d.heading), inline(&d.intro));
    if let Some(why) = &d.verdict {
        s.push_str("> **BUILD FAILED: do not process wafers with this traveler**\n>\n");
        for w in why {
            s.push_str(&format!("> - {}\n", ts(w)));
        }
        s.push('\n');
    }
    for sec in &d.sections {
        s.push_str(&format!("## {}\n\n", ts(sec.title)));
        for b in &sec.blocks {
            block(&mut s, b);
        }
    }
    // One newline at the end, whatever the last block left.
    let end = s.trim_end_matches('\n').len();
    s.truncate(end);
    s.push('\n');
    s
}

fn block(s: &mut String, b: &Block) {
    match b {
        Block::Para(r) => s.push_str(&format!("{}\n\n", inline(r))),
        Block::Subheading(h) => s.push_str(&format!("### {}\n\n", ts(h))),
        Block::Form(rows) => {
            s.push_str(&head(&["field", "value"]));
            for (k, v) in rows {
                s.push_str(&row(&[
                    ts(k),
                    v.as_deref().map_or_else(|| BLANK.into(), ts),
                ]));
            }
            s.push('\n');
        }
        Block::Table(t) => table(s, t),
        Block::List(items) => {
            for (r, _) in items {
                s.push_str(&format!("- {}\n", inline(r)));
            }
            if !items.is_empty() {
                s.push('\n');
            }
        }
        Block::Pre(text) => s.push_str(&format!("```text\n{}```\n\n", ts(text))),
        Block::Figures { .. } => {}
        Block::Only(Format::Markdown, b) => block(s, b),
        Block::Only(Format::Html, _) => {}
    }
}

fn table(s: &mut String, t: &Table) {
    s.push_str(&head(&t.head));
    for r in &t.rows {
        let mut cells: Vec<String> = r.iter().map(inline).collect();
        cells.extend(std::iter::repeat_n(BLANK.to_string(), t.blanks));
        s.push_str(&row(&cells));
    }
    s.push('\n');
}

/// Inline Markdown: code and digests in backticks, failures in bold, breaks as newlines (cells
/// turn them into `<br>`).
fn inline(r: &Rich) -> String {
    r.0.iter()
        .map(|sp| match sp {
            Span::Text(x) | Span::Value(x) | Span::Note(x) | Span::Pass(x) => ts(x),
            Span::Code(x) | Span::Hash(x) => format!("`{x}`"),
            Span::Fail(x) => format!("**{}**", ts(x)),
            Span::Break => "\n".into(),
        })
        .collect()
}

/// A table cell: pipes escaped, newlines as `<br>`.
fn cell(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', "<br>")
}

fn row(cells: &[String]) -> String {
    format!(
        "| {} |\n",
        cells
            .iter()
            .map(|c| cell(c))
            .collect::<Vec<_>>()
            .join(" | ")
    )
}

fn head<S: AsRef<str>>(cols: &[S]) -> String {
    let cols: Vec<String> = cols.iter().map(|c| ts(c.as_ref())).collect();
    format!(
        "| {} |\n|{}\n",
        cols.join(" | "),
        " --- |".repeat(cols.len())
    )
}
