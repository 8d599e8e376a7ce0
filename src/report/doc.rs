//! A small document model: sections of paragraphs, tables, lists and figures. The traveler is
//! built once as a [`Doc`] ([`super::sheet`]) and rendered by [`super::markdown`] and
//! [`super::html`], so every heading, column and sentence is written once.

/// A run of inline text.
#[derive(Debug, Clone, PartialEq)]
pub enum Span {
    Text(String),
    /// A file name, code or command: `x` / `<code>`.
    Code(String),
    /// A digest: `x` / a monospace span that may break anywhere.
    Hash(String),
    /// A value the reader looks for: plain in Markdown, bold in HTML.
    Value(String),
    /// Provenance or basis: plain in Markdown, grey in HTML.
    Note(String),
    Pass(String),
    /// A failure: bold in both.
    Fail(String),
    /// A line break inside a cell or item.
    Break,
}

/// Inline text: spans in order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Rich(pub Vec<Span>);

impl Rich {
    pub fn text(s: impl Into<String>) -> Self {
        Rich(vec![Span::Text(s.into())])
    }
    pub fn code(s: impl Into<String>) -> Self {
        Rich(vec![Span::Code(s.into())])
    }
    pub fn value(s: impl Into<String>) -> Self {
        Rich(vec![Span::Value(s.into())])
    }
    /// Appends a span.
    pub fn and(mut self, s: Span) -> Self {
        self.0.push(s);
        self
    }
    pub fn plain(self, s: impl Into<String>) -> Self {
        self.and(Span::Text(s.into()))
    }
}

impl From<&str> for Rich {
    fn from(s: &str) -> Self {
        Rich::text(s)
    }
}
impl From<String> for Rich {
    fn from(s: String) -> Self {
        Rich::text(s)
    }
}

/// A table. A run sheet has fixed column widths (so it prints on A4) and blank columns the
/// operator fills in, after the cells of each row.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Table {
    pub head: Vec<String>,
    pub rows: Vec<Vec<Rich>>,
    /// Column widths in % of the page: a run sheet.
    pub widths_pct: Option<Vec<u32>>,
    /// Blank columns at the end of every row (their headings are the last of `head`).
    pub blanks: usize,
}

impl Table {
    pub fn new<S: AsRef<str>>(head: &[S]) -> Self {
        Table {
            head: head.iter().map(|h| h.as_ref().to_string()).collect(),
            ..Table::default()
        }
    }
    /// A run sheet: widths in % and the number of blank columns at the end.
    pub fn sheet<S: AsRef<str>>(head: &[S], widths_pct: &[u32], blanks: usize) -> Self {
        Table {
            widths_pct: Some(widths_pct.to_vec()),
            blanks,
            ..Table::new(head)
        }
    }
    pub fn row(&mut self, cells: Vec<Rich>) {
        self.rows.push(cells);
    }
}

/// A figure: inline SVG and its caption. Markdown has no figures; it says where to find them.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    pub svg: String,
    pub caption: String,
}

/// Which renderer a block is for, when the formats differ in what they can show.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    Markdown,
    Html,
}

/// A block of a section.
#[derive(Debug, Clone, PartialEq)]
pub enum Block {
    Para(Rich),
    Subheading(String),
    /// Labels with a value, or a blank when `None`.
    Form(Vec<(String, Option<String>)>),
    Table(Table),
    /// Items; an item marked `true` is an error.
    List(Vec<(Rich, bool)>),
    /// Preformatted text (ends with a newline).
    Pre(String),
    /// Figures, side by side in a grid when `grid`, at most `max_width_mm` wide.
    Figures {
        figures: Vec<Figure>,
        grid: bool,
        max_width_mm: Option<u32>,
    },
    /// A block for one format only.
    Only(Format, Box<Block>),
}

/// A section with its heading; `page_break` starts it on a new printed page.
#[derive(Debug, Clone, PartialEq)]
pub struct Section {
    pub id: &'static str,
    pub title: &'static str,
    pub page_break: bool,
    pub blocks: Vec<Block>,
}

impl Section {
    pub fn new(id: &'static str, title: &'static str) -> Self {
        Section {
            id,
            title,
            page_break: false,
            blocks: Vec::new(),
        }
    }
    pub fn push(&mut self, b: Block) {
        self.blocks.push(b);
    }
}

/// A whole document.
#[derive(Debug, Clone, PartialEq)]
pub struct Doc {
    /// The page title (HTML `<title>`).
    pub title: String,
    pub heading: String,
    pub intro: Rich,
    /// When the document records a failed build: why, one line each (shown first, as a banner).
    pub verdict: Option<Vec<String>>,
    pub sections: Vec<Section>,
}

/// Unit typography for people: the ASCII `um` (a whole word, so `depth_um` and `medium` stay)
/// becomes `µm`, `um2`/`um3` become `µm²`/`µm³`, and `+/-` becomes `±`. Code and digests are
/// never typeset: they are what the user types.
///
/// ```
/// use tactfab::report::doc::typeset;
/// assert_eq!(typeset("200 um +/- 1 % at 0.5 um/h; B = 0.53 um2/h"), "200 µm ± 1 % at 0.5 µm/h; B = 0.53 µm²/h");
/// assert_eq!(typeset("depth_um in a medium"), "depth_um in a medium");
/// ```
pub fn typeset(s: &str) -> String {
    let s = s.replace("+/-", "±");
    let mut out = String::with_capacity(s.len());
    let mut word = String::new();
    let flush = |word: &mut String, out: &mut String| {
        out.push_str(match word.as_str() {
            "um" => "µm",
            "um2" => "µm²",
            "um3" => "µm³",
            w => w,
        });
        word.clear();
    };
    for c in s.chars() {
        if c.is_alphanumeric() || c == '_' {
            word.push(c);
        } else {
            flush(&mut word, &mut out);
            out.push(c);
        }
    }
    flush(&mut word, &mut out);
    out
}
