//! Markdown to one self-contained HTML page, for every report the crate
//! writes (`report.md` of a campaign and of the chapter-6 implant).
//!
//! The subset converted is the one the reports write: headings `#` to
//! `######`, paragraphs, `-` lists, pipe tables with their separator row,
//! fenced code blocks, code spans, `**bold**`, `*italic*`, `[text](link)`
//! and `![alt](image)`. On top of the plain conversion the page
//!
//! - inlines every figure: `plots/X.png` becomes the contents of
//!   `plots/X.svg` (its prolog dropped), or, when the SVG is missing or
//!   holds anything active (scripts, event handlers, external references),
//!   the PNG as a `data:` URI; a figure with neither says so;
//! - follows each link to a `tables/X.csv` with a collapsed `<details>`
//!   holding the CSV as a table (at most [`MAX_CSV_ROWS`] rows);
//! - makes every table sortable by a click on a header, numbers by value;
//! - opens with a table of contents of the `##` headings;
//! - gives a section of more than [`MAX_OPEN_FIGURES`] figures a menu that
//!   shows one figure at a time (the others stay in the page, hidden by the
//!   `mb-hidden` class);
//! - sets `data-ready="1"` on `<body>` once its script has run.
//!
//! All text is escaped, so no text of a spec can become markup, and the
//! page refers to nothing outside itself but the relative links it was
//! given (the inline SVGs keep their `xmlns`). The same Markdown and files
//! give the same bytes.
//!
//! Part of the [`crate::markdown`] leaf: it imports nothing of the crate.

mod files;
mod parse;

use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::path::Path;

use super::thousands;

pub use self::files::base64;
use self::files::{inline_svg, read_csv, read_limited, CsvHead};
use self::parse::{images, parse_blocks, parse_inline, plain, Align, Block, Tok};

/// The most rows of a CSV file shown in the page; the rest are counted and
/// left to the file.
pub const MAX_CSV_ROWS: usize = 2000;

/// A `##` section with more figures than this shows one at a time, chosen
/// from a menu.
pub const MAX_OPEN_FIGURES: usize = 6;

/// The page's style sheet.
const STYLE: &str = include_str!("html/report.css");

/// The page's script: sortable tables, the figure menus, `data-ready`.
const SCRIPT: &str = include_str!("html/report.js");

/// The HTML page of `markdown`, whose relative links and images are files
/// under `dir` (read for the figures and the CSV tables; a file that is
/// missing or unreadable is named in the page, never an error).
pub fn markdown_to_html(markdown: &str, dir: &Path) -> String {
    let blocks = parse_blocks(markdown);
    let mut ctx = Context::new(dir, &blocks);
    let items: Vec<Item> = blocks.iter().map(|b| ctx.block(b)).collect();
    let title = items
        .iter()
        .find_map(|i| i.heading.as_ref().filter(|h| h.level == 1))
        .map_or_else(|| "Report".to_owned(), |h| h.text.clone());
    let mut out = String::with_capacity(markdown.len() * 2 + STYLE.len() + SCRIPT.len());
    out.push_str("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n");
    out.push_str("<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n");
    out.push_str(
        "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; \
         img-src data:; style-src 'unsafe-inline'; script-src 'unsafe-inline'\">\n",
    );
    out.push_str("<meta name=\"generator\" content=\"metabezier report\">\n");
    out.push_str(&format!("<title>{}</title>\n", escape(&title)));
    out.push_str("<style>\n");
    out.push_str(STYLE);
    out.push_str("</style>\n</head>\n<body>\n<main>\n");
    assemble(&items, &mut out);
    out.push_str("</main>\n<script>\n");
    out.push_str(SCRIPT);
    out.push_str("</script>\n</body>\n</html>\n");
    out
}

/// Escapes text for HTML content and attribute values.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for ch in text.chars() {
        match ch {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

// ---------------------------------------------------------------------------
// Rendering.

/// A heading as the table of contents and the sections see it.
struct Heading {
    level: usize,
    id: String,
    text: String,
}

/// A rendered block: its HTML and what the page's layout needs of it.
struct Item {
    html: String,
    heading: Option<Heading>,
    /// The alternative text, when the block is a figure.
    figure: Option<String>,
}

/// What rendering needs across blocks.
struct Context<'d> {
    dir: &'d Path,
    /// The ids of the headings, in order.
    heading_ids: VecDeque<String>,
    /// The ids of the images, in order.
    image_ids: VecDeque<String>,
    /// The id of the first figure of each image source.
    figure_of: BTreeMap<String, String>,
    /// The CSV files already shown.
    csv_shown: BTreeSet<String>,
    /// The CSV files linked from the block being rendered.
    csv_pending: Vec<String>,
    /// Ids taken.
    ids: BTreeSet<String>,
    /// The next suffix to try for each base of an id.
    suffixes: BTreeMap<String, usize>,
}

impl<'d> Context<'d> {
    /// Gives every heading and image of `blocks` its id.
    fn new(dir: &'d Path, blocks: &[Block]) -> Self {
        let mut ctx = Context {
            dir,
            heading_ids: VecDeque::new(),
            image_ids: VecDeque::new(),
            figure_of: BTreeMap::new(),
            csv_shown: BTreeSet::new(),
            csv_pending: Vec::new(),
            ids: BTreeSet::new(),
            suffixes: BTreeMap::new(),
        };
        ctx.ids.insert("mb-toc".to_owned());
        for b in blocks {
            let texts: Vec<&str> = match b {
                Block::Heading(_, t) | Block::Paragraph(t) => vec![t],
                Block::List(items) => items.iter().map(String::as_str).collect(),
                Block::Table(header, _, rows) => header
                    .iter()
                    .chain(rows.iter().flatten())
                    .map(String::as_str)
                    .collect(),
                Block::Code(_) => Vec::new(),
            };
            if let Block::Heading(_, t) = b {
                let id = ctx.unique_id(&slug(&plain(&parse_inline(t))));
                ctx.heading_ids.push_back(id);
            }
            for t in texts {
                let toks = parse_inline(t);
                let mut srcs = Vec::new();
                images(&toks, &mut srcs);
                for src in srcs {
                    let stem = Path::new(src)
                        .file_stem()
                        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
                    let id = ctx.unique_id(&format!("fig-{}", slug(&stem)));
                    ctx.figure_of
                        .entry(src.to_owned())
                        .or_insert_with(|| id.clone());
                    ctx.image_ids.push_back(id);
                }
            }
        }
        ctx
    }

    /// `base`, or `base-2`, `base-3`, … if taken.
    fn unique_id(&mut self, base: &str) -> String {
        let mut id = base.to_owned();
        let k = self.suffixes.entry(base.to_owned()).or_insert(2);
        while self.ids.contains(&id) {
            id = format!("{base}-{k}");
            *k += 1;
        }
        self.ids.insert(id.clone());
        id
    }

    /// The HTML of one block.
    fn block(&mut self, b: &Block) -> Item {
        let mut item = Item {
            html: String::new(),
            heading: None,
            figure: None,
        };
        let h = &mut item.html;
        match b {
            Block::Heading(level, text) => {
                let toks = parse_inline(text);
                let id = self.heading_ids.pop_front().unwrap_or_default();
                h.push_str(&format!("<h{level} id=\"{}\">", escape(&id)));
                self.inline(&toks, false, h);
                h.push_str(&format!("</h{level}>\n"));
                item.heading = Some(Heading {
                    level: *level,
                    id,
                    text: plain(&toks),
                });
            }
            Block::Paragraph(text) => {
                let toks = parse_inline(text);
                if let Some((Tok::Image(alt, src), rest)) = toks.split_first() {
                    h.push_str("<figure class=\"mb-fig\">");
                    let id = self.image_ids.pop_front().unwrap_or_default();
                    h.push_str(&self.image(alt, src, &id));
                    let mut caption = String::new();
                    self.inline(rest, false, &mut caption);
                    let caption = caption.trim();
                    if !caption.is_empty() {
                        h.push_str("\n<figcaption>");
                        h.push_str(caption);
                        h.push_str("</figcaption>");
                    }
                    h.push_str("</figure>\n");
                    item.figure = Some(alt.clone());
                } else {
                    h.push_str("<p>");
                    self.inline(&toks, false, h);
                    h.push_str("</p>\n");
                }
            }
            Block::List(items) => {
                h.push_str("<ul>\n");
                for it in items {
                    h.push_str("<li>");
                    self.inline(&parse_inline(it), false, h);
                    let csv = self.csv_blocks();
                    h.push_str(&csv);
                    h.push_str("</li>\n");
                }
                h.push_str("</ul>\n");
            }
            Block::Table(header, align, rows) => {
                h.push_str("<div class=\"mb-table\"><table class=\"mb-sortable\">\n<thead><tr>");
                for (cell, a) in header.iter().zip(align) {
                    h.push_str(&format!("<th{}>", align_class(*a)));
                    self.inline(&parse_inline(cell), false, h);
                    h.push_str("</th>");
                }
                h.push_str("</tr></thead>\n<tbody>\n");
                for row in rows {
                    h.push_str("<tr>");
                    for (cell, a) in row.iter().zip(align) {
                        h.push_str(&format!("<td{}>", align_class(*a)));
                        self.inline(&parse_inline(cell), false, h);
                        h.push_str("</td>");
                    }
                    h.push_str("</tr>\n");
                }
                h.push_str("</tbody>\n</table></div>\n");
            }
            Block::Code(text) => {
                h.push_str("<pre><code>");
                h.push_str(&escape(text));
                h.push_str("</code></pre>\n");
            }
        }
        let csv = self.csv_blocks();
        item.html.push_str(&csv);
        item
    }

    /// The HTML of inline content (`in_link`: inside a link, whose links
    /// are text).
    fn inline(&mut self, toks: &[Tok], in_link: bool, out: &mut String) {
        for t in toks {
            match t {
                Tok::Text(s) => out.push_str(&escape(s)),
                Tok::Entity(e) => out.push_str(e),
                Tok::Code(s) => {
                    out.push_str("<code>");
                    out.push_str(&escape(s));
                    out.push_str("</code>");
                }
                Tok::Strong(inner) => {
                    out.push_str("<strong>");
                    self.inline(inner, in_link, out);
                    out.push_str("</strong>");
                }
                Tok::Em(inner) => {
                    out.push_str("<em>");
                    self.inline(inner, in_link, out);
                    out.push_str("</em>");
                }
                Tok::Link(inner, _) if in_link => self.inline(inner, true, out),
                Tok::Link(inner, dest) => self.link(inner, dest, out),
                Tok::Image(alt, src) => {
                    let id = self.image_ids.pop_front().unwrap_or_default();
                    out.push_str(&self.image(alt, src, &id));
                }
            }
        }
    }

    /// A link: to a figure of the page, its anchor; to a CSV table, the
    /// file, with the table shown after the block; to another file or an
    /// anchor, as it is; to anything else (another site), its text and the
    /// address as text, not followed.
    fn link(&mut self, inner: &[Tok], dest: &str, out: &mut String) {
        let mut text = String::new();
        self.inline(inner, true, &mut text);
        if let Some(id) = self.figure_of.get(dest).filter(|_| dest.ends_with(".png")) {
            out.push_str(&format!("<a href=\"#{}\">{text}</a>", escape(id)));
        } else if dest.starts_with('#') || relative_file(dest) {
            out.push_str(&format!("<a href=\"{}\">{text}</a>", escape(dest)));
            if csv_table(dest) && !self.csv_pending.iter().any(|d| d == dest) {
                self.csv_pending.push(dest.to_owned());
            }
        } else {
            out.push_str(&format!(
                "{text} (<span class=\"mb-ext\">{}</span>)",
                escape(dest)
            ));
        }
    }

    /// The collapsed tables of the CSV files linked since the last call,
    /// each shown once in the page.
    fn csv_blocks(&mut self) -> String {
        let mut out = String::new();
        for dest in std::mem::take(&mut self.csv_pending) {
            if self.csv_shown.insert(dest.clone()) {
                let id = self.unique_id(&format!("csv-{}", slug(&dest)));
                out.push_str(&csv_details(self.dir, &dest, &id));
            }
        }
        out
    }

    /// An image as inline HTML: its SVG, else its PNG as a data URI, else a
    /// note that it is missing.
    fn image(&self, alt: &str, src: &str, id: &str) -> String {
        let missing = |why: &str| {
            format!(
                "<span class=\"mb-missing\" id=\"{}\" role=\"img\" aria-label=\"{}\">figure missing: {}</span>",
                escape(id),
                escape(alt),
                escape(why)
            )
        };
        if !relative_file(src) {
            return missing(&format!("{src} is not a file beside the report"));
        }
        let path = self.dir.join(src);
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        let svg_path = path.with_extension("svg");
        let vector = matches!(ext.as_deref(), Some("png" | "svg"));
        // Whether an SVG was there but not inlined.
        let mut svg_refused = false;
        if vector {
            if let Ok(bytes) = read_limited(&svg_path) {
                match String::from_utf8(bytes).ok().and_then(|t| inline_svg(&t)) {
                    Some(svg) => {
                        return format!(
                            "<span class=\"mb-svg\" id=\"{}\" role=\"img\" aria-label=\"{}\">{svg}</span>",
                            escape(id),
                            escape(alt)
                        )
                    }
                    None => svg_refused = true,
                }
            }
        }
        let (raster, mime) = match ext.as_deref() {
            Some("png" | "svg") => (path.with_extension("png"), "image/png"),
            Some("jpg" | "jpeg") => (path.clone(), "image/jpeg"),
            Some("gif") => (path.clone(), "image/gif"),
            Some("webp") => (path.clone(), "image/webp"),
            _ => return missing(&format!("{src} is not an image the report can show")),
        };
        let name = |ext: &str| Path::new(src).with_extension(ext).display().to_string();
        match read_limited(&raster) {
            Ok(bytes) if mime != "image/png" || bytes.starts_with(b"\x89PNG\r\n\x1a\n") => format!(
                "<img id=\"{}\" alt=\"{}\" src=\"data:{mime};base64,{}\">",
                escape(id),
                escape(alt),
                base64(&bytes)
            ),
            Ok(_) => missing(&format!("{} is not a PNG file", name("png"))),
            Err(_) if svg_refused => missing(&format!(
                "{} is not plain drawing and {} cannot be read",
                name("svg"),
                name("png")
            )),
            Err(_) if vector => missing(&format!("neither {} nor {}", name("svg"), name("png"))),
            Err(_) => missing(&format!("{src} cannot be read")),
        }
    }
}

/// The class attribute of an aligned cell.
fn align_class(a: Align) -> &'static str {
    match a {
        Align::None => "",
        Align::Left => " class=\"l\"",
        Align::Right => " class=\"r\"",
        Align::Center => " class=\"c\"",
    }
}

/// Whether `dest` names a file below the report's directory: relative, no
/// scheme, no `..`, no backslash.
fn relative_file(dest: &str) -> bool {
    let first = dest.split('/').next().unwrap_or("");
    !dest.is_empty()
        && !dest.starts_with('/')
        && !first.contains(':')
        && !dest.contains('\\')
        && !dest.chars().any(char::is_control)
        && dest.split('/').all(|c| !c.is_empty() && c != "..")
}

/// Whether `dest` is one of the report's CSV tables, `tables/X.csv`.
fn csv_table(dest: &str) -> bool {
    dest.strip_prefix("tables/")
        .and_then(|r| r.strip_suffix(".csv"))
        .is_some_and(|stem| !stem.is_empty() && !stem.contains('/'))
}

/// An anchor name for `text`: lower-case letters and digits, the rest
/// dashes.
fn slug(text: &str) -> String {
    let mut out = String::new();
    for c in text.chars().flat_map(char::to_lowercase) {
        if c.is_alphanumeric() {
            out.push(c);
        } else if !out.ends_with('-') && !out.is_empty() {
            out.push('-');
        }
    }
    let out = out.trim_end_matches('-');
    if out.is_empty() {
        "section".to_owned()
    } else {
        out.to_owned()
    }
}

/// A collapsed `<details>` with the CSV file `dest` as a sortable table.
fn csv_details(dir: &Path, dest: &str, id: &str) -> String {
    let mut out = format!("<details class=\"mb-csv\" id=\"{}\"><summary>", escape(id));
    match read_csv(&dir.join(dest)) {
        Ok(CsvHead {
            header,
            rows,
            total,
        }) => {
            out.push_str(&format!(
                "Table <code>{}</code>: {} row{}, {} column{}</summary>\n",
                escape(dest),
                thousands(total as u128),
                if total == 1 { "" } else { "s" },
                header.len(),
                if header.len() == 1 { "" } else { "s" }
            ));
            out.push_str("<div class=\"mb-table\"><table class=\"mb-sortable\">\n<thead><tr>");
            for h in &header {
                out.push_str(&format!("<th>{}</th>", escape(h)));
            }
            out.push_str("</tr></thead>\n<tbody>\n");
            for row in &rows {
                out.push_str("<tr>");
                for k in 0..header.len().max(row.len()) {
                    let cell = row.get(k).map_or("", String::as_str);
                    let class = if looks_numeric(cell) {
                        " class=\"r\""
                    } else {
                        ""
                    };
                    out.push_str(&format!("<td{class}>{}</td>", escape(cell)));
                }
                out.push_str("</tr>\n");
            }
            out.push_str("</tbody>\n</table></div>\n");
            if total > rows.len() {
                out.push_str(&format!(
                    "<p class=\"mb-note\">first {} of {} rows; the full table is {}</p>\n",
                    thousands(rows.len() as u128),
                    thousands(total as u128),
                    escape(dest)
                ));
            }
        }
        Err(why) => out.push_str(&format!(
            "Table <code>{0}</code></summary>\n<p class=\"mb-missing\">cannot show {0}: {1}</p>\n",
            escape(dest),
            escape(&why)
        )),
    }
    out.push_str("</details>\n");
    out
}

/// Whether a CSV cell reads as a number (right-aligned).
fn looks_numeric(cell: &str) -> bool {
    !cell.is_empty() && (cell.parse::<f64>().is_ok())
}

/// Writes the page body: the blocks, the table of contents after the
/// title, and the figure menus of the crowded sections.
fn assemble(items: &[Item], out: &mut String) {
    let toc = toc(items);
    let mut k = 0;
    let mut toc_written = false;
    let mut groups = 0;
    if items.first().is_none_or(|i| heading_level(i) != Some(1)) {
        out.push_str(&toc);
        toc_written = true;
    }
    while k < items.len() {
        let item = &items[k];
        if heading_level(item) == Some(2) {
            let end = (k + 1..items.len())
                .find(|&j| heading_level(&items[j]).is_some_and(|l| l <= 2))
                .unwrap_or(items.len());
            out.push_str(&item.html);
            let section = &items[k + 1..end];
            if section.iter().filter(|i| i.figure.is_some()).count() > MAX_OPEN_FIGURES {
                groups += 1;
                figure_menu(section, groups, out);
            } else {
                section.iter().for_each(|i| out.push_str(&i.html));
            }
            k = end;
            continue;
        }
        out.push_str(&item.html);
        if !toc_written {
            out.push_str(&toc);
            toc_written = true;
        }
        k += 1;
    }
}

/// The level of an item's heading.
fn heading_level(item: &Item) -> Option<usize> {
    item.heading.as_ref().map(|h| h.level)
}

/// The table of contents: a link to each `##` heading (nothing without
/// one).
fn toc(items: &[Item]) -> String {
    let entries: Vec<String> = items
        .iter()
        .filter_map(|i| i.heading.as_ref())
        .filter(|h| h.level == 2)
        .map(|h| {
            format!(
                "<li><a href=\"#{}\">{}</a></li>\n",
                escape(&h.id),
                escape(&h.text)
            )
        })
        .collect();
    if entries.is_empty() {
        return String::new();
    }
    format!(
        "<nav class=\"mb-toc\" id=\"mb-toc\" aria-label=\"Contents\"><p class=\"mb-toc-title\">Contents</p>\n<ul>\n{}</ul></nav>\n",
        entries.concat()
    )
}

/// A section's blocks with a menu showing one figure at a time: each
/// `###` subsection with a single figure is one unit (heading, figure,
/// caption and all), every other figure a unit by itself.
fn figure_menu(section: &[Item], group: usize, out: &mut String) {
    // The units as (first item, end, alternative text).
    let mut units: Vec<(usize, usize, String)> = Vec::new();
    let mut k = 0;
    while k < section.len() {
        let sub_end = if heading_level(&section[k]) == Some(3) {
            (k + 1..section.len())
                .find(|&j| heading_level(&section[j]).is_some_and(|l| l <= 3))
                .unwrap_or(section.len())
        } else {
            k + 1
        };
        let figures: Vec<usize> = (k..sub_end)
            .filter(|&j| section[j].figure.is_some())
            .collect();
        match figures.as_slice() {
            [only] if sub_end > k + 1 => {
                units.push((
                    k,
                    sub_end,
                    section[*only].figure.clone().unwrap_or_default(),
                ));
            }
            many => units.extend(
                many.iter()
                    .map(|&j| (j, j + 1, section[j].figure.clone().unwrap_or_default())),
            ),
        }
        k = sub_end;
    }
    let mut next = 0;
    for (k, item) in section.iter().enumerate() {
        if let Some((index, (_, _, _))) = units.iter().enumerate().find(|(_, u)| u.0 == k) {
            if index == 0 {
                out.push_str(&format!(
                    "<p class=\"mb-figsel\"><label>Figure <select class=\"mb-select\" data-group=\"{group}\">\n"
                ));
                for (n, (_, _, alt)) in units.iter().enumerate() {
                    out.push_str(&format!(
                        "<option value=\"{n}\">{}. {}</option>\n",
                        n + 1,
                        escape(alt)
                    ));
                }
                out.push_str(&format!(
                    "<option value=\"all\">all {} figures</option>\n</select></label> \
                     <span class=\"mb-note\">{} figures in this section, one shown at a time</span></p>\n",
                    units.len(),
                    units.len()
                ));
            }
            out.push_str(&format!(
                "<div class=\"mb-unit\" data-group=\"{group}\" data-index=\"{index}\">\n"
            ));
            next = units[index].1;
        }
        out.push_str(&item.html);
        if next == k + 1 {
            out.push_str("</div>\n");
            next = 0;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn body(md: &str) -> String {
        let dir = std::env::temp_dir().join("metabezier-html-unit-missing");
        let html = markdown_to_html(md, &dir);
        let start = html.find("<main>").unwrap() + "<main>\n".len();
        let end = html.find("</main>").unwrap();
        html[start..end].to_owned()
    }

    #[test]
    fn escapes_text_and_keeps_references() {
        let b = body("A <script>alert(1)</script> & \"q\" &lt;b&gt; \\* x\n");
        assert_eq!(
            b,
            "<p>A &lt;script&gt;alert(1)&lt;/script&gt; &amp; &quot;q&quot; &lt;b&gt; * x</p>\n"
        );
        assert!(!body("&#x3C;script> `<b>` **<i>**").contains("<i>"));
    }

    #[test]
    fn headings_toc_and_ids() {
        let b = body("# Report: x\n\n## Summary\n\ntext\n\n## Summary\n\n### Sub *part*\n");
        assert!(
            b.starts_with("<h1 id=\"report-x\">Report: x</h1>\n<nav class=\"mb-toc\""),
            "{b}"
        );
        assert!(
            b.contains("<li><a href=\"#summary\">Summary</a></li>\n<li><a href=\"#summary-2\">")
        );
        assert!(
            b.contains("<h3 id=\"sub-part\">Sub <em>part</em></h3>"),
            "{b}"
        );
    }

    #[test]
    fn tables_with_alignment_and_escaped_pipes() {
        let b = body("| Name | n |\n| :-- | --: |\n| a\\|b | `x\\|y` |\n| c |\n");
        assert!(
            b.contains("<th class=\"l\">Name</th><th class=\"r\">n</th>"),
            "{b}"
        );
        assert!(
            b.contains("<td class=\"l\">a|b</td><td class=\"r\"><code>x|y</code></td>"),
            "{b}"
        );
        assert!(
            b.contains("<td class=\"l\">c</td><td class=\"r\"></td>"),
            "{b}"
        );
        assert!(b.contains("<table class=\"mb-sortable\">"));
        // Without a separator row, pipes are text.
        assert_eq!(body("a | b\nc\n"), "<p>a | b\nc</p>\n");
    }

    #[test]
    fn lists_paragraphs_and_emphasis() {
        let b =
            body("- **Spec:** `spec.toml`\n- two\n  more\n\nPara *it* and **bo *x***.\nline 2\n");
        assert_eq!(
            b,
            "<ul>\n<li><strong>Spec:</strong> <code>spec.toml</code></li>\n<li>two\nmore</li>\n</ul>\n\
             <p>Para <em>it</em> and <strong>bo <em>x</em></strong>.\nline 2</p>\n"
        );
        assert_eq!(body("2 * 3 * 4 and **\n"), "<p>2 * 3 * 4 and **</p>\n");
        assert_eq!(body("f − f\\* ≤ 1\n"), "<p>f − f* ≤ 1</p>\n");
    }

    #[test]
    fn code_blocks_and_spans() {
        let b = body("```toml\n[a]\nx = \"<b>\"\n```\n\nuse `` a`b `` here\n");
        assert_eq!(
            b,
            "<pre><code>[a]\nx = &quot;&lt;b&gt;&quot;</code></pre>\n<p>use <code>a`b</code> here</p>\n"
        );
        // An unclosed fence runs to the end.
        assert_eq!(
            body("~~~\n# not a heading\n"),
            "<pre><code># not a heading</code></pre>\n"
        );
    }

    #[test]
    fn links_relative_and_external() {
        let b =
            body("[t](tables/x.csv) [e](https://example.org/a) [j](javascript:alert(1)) [a](#s)\n");
        assert!(b.contains("<a href=\"tables/x.csv\">t</a>"), "{b}");
        assert!(
            !b.contains("href=\"https") && !b.contains("href=\"javascript"),
            "{b}"
        );
        assert!(
            b.contains("e (<span class=\"mb-ext\">https://example.org/a</span>)"),
            "{b}"
        );
        assert!(b.contains("<a href=\"#s\">a</a>"));
        // The CSV is missing here: the block says so.
        assert!(
            b.contains("cannot show tables/x.csv: the file is missing"),
            "{b}"
        );
        // ../ never leaves the directory.
        assert!(body("![x](../secret.png)\n").contains("figure missing"));
    }

    #[test]
    fn csv_tables_and_figures_from_files() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir_all(dir.path().join("tables")).unwrap();
        std::fs::create_dir_all(dir.path().join("plots")).unwrap();
        let mut csv = String::from("name,value\n");
        for i in 0..2003 {
            csv.push_str(&format!("r{i},{i}\n"));
        }
        std::fs::write(dir.path().join("tables/t.csv"), csv).unwrap();
        std::fs::write(
            dir.path().join("plots/a.svg"),
            "<?xml version=\"1.0\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\"><text>&lt;x</text></svg>\n",
        )
        .unwrap();
        std::fs::write(
            dir.path().join("plots/b.svg"),
            "<svg onload=\"alert(1)\"></svg>",
        )
        .unwrap();
        std::fs::write(dir.path().join("plots/b.png"), b"\x89PNG\r\n\x1a\nabc").unwrap();
        let md = "[Fig A](plots/a.png) CSV: [`tables/t.csv`](tables/t.csv)\n\n\
                  ![A <1>](plots/a.png)\nCaption.\n\n![B](plots/b.png)\n\n![C](plots/c.png)\n";
        let html = markdown_to_html(md, dir.path());
        assert!(html.contains("<a href=\"#fig-a\">Fig A</a>"), "{html}");
        assert!(html.contains("first 2,000 of 2,003 rows; the full table is tables/t.csv"));
        assert_eq!(html.matches("<tr>").count(), 2001);
        assert!(html.contains(
            "<figure class=\"mb-fig\"><span class=\"mb-svg\" id=\"fig-a\" role=\"img\" \
             aria-label=\"A &lt;1&gt;\"><svg xmlns=\"http://www.w3.org/2000/svg\"><text>&lt;x</text></svg></span>\n\
             <figcaption>Caption.</figcaption></figure>"
        ), "{html}");
        assert!(!html.contains("<?xml") && !html.contains("onload"));
        assert!(html.contains(
            "<img id=\"fig-b\" alt=\"B\" src=\"data:image/png;base64,iVBORw0KGgphYmM=\">"
        ));
        assert!(
            html.contains("figure missing: neither plots/c.svg nor plots/c.png"),
            "{html}"
        );
        assert_eq!(html, markdown_to_html(md, dir.path()));
    }

    #[test]
    fn crowded_sections_get_a_menu() {
        let mut md = String::from("# T\n\n## Plots\n\n");
        for i in 0..7 {
            md.push_str(&format!(
                "### P{i}\n\n![Plot {i}](plots/p{i}.png)\nCap {i}.\n\n"
            ));
        }
        md.push_str("## Other\n\n![Q](plots/q.png)\n");
        let b = body(&md);
        assert_eq!(b.matches("<select").count(), 1);
        assert_eq!(b.matches("<div class=\"mb-unit\"").count(), 7);
        assert!(b.contains("<option value=\"0\">1. Plot 0</option>"));
        assert!(b.contains("<div class=\"mb-unit\" data-group=\"1\" data-index=\"6\">\n<h3 id=\"p6\">P6</h3>\n<figure"), "{b}");
        let other = &b[b.find("<h2 id=\"other\"").unwrap()..];
        assert!(!other.contains("mb-unit"));
        assert!(!body(&md.replace("### P6\n\n![Plot 6](plots/p6.png)\n", "")).contains("<select"));
    }

    #[test]
    fn hostile_input_never_panics() {
        for s in [
            "[",
            "![",
            "[a](",
            "[a](<",
            "`",
            "**",
            "*",
            "&",
            "&#",
            "&#x;",
            "|",
            "|\n|",
            "| a |\n|---|\n|",
            "[a](b \"c",
            "\\",
            "é*é*",
            "***x***",
            "- ",
            "```",
            "#",
            "######## x",
            "[]()",
            "![](/)",
        ] {
            let _ = body(s);
        }
        let long = "[*`".repeat(20_000);
        let _ = body(&long);
        // Seeded random strings over the characters that matter, with
        // multi-byte ones between them: no panic, and no tag but the
        // converter's own.
        let alphabet = [
            "[",
            "]",
            "(",
            ")",
            "!",
            "*",
            "`",
            "\\",
            "&",
            "#",
            ";",
            "|",
            "-",
            ":",
            "<",
            ">",
            "\"",
            " ",
            "\n",
            "é",
            "−",
            "x",
            "1",
            "plots/a.png",
            "tables/t.csv",
            "https://e/",
        ];
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        for _ in 0..3000 {
            let mut s = String::new();
            for _ in 0..40 {
                state = state
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                s.push_str(alphabet[(state >> 33) as usize % alphabet.len()]);
            }
            let html = body(&s);
            assert!(
                !html.contains("<script") && !html.contains("href=\"https"),
                "{s:?}"
            );
        }
    }
}
