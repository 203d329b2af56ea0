//! `report.html`: the self-contained page written beside every `report.md`
//! (a campaign's and the implant's). It refers to nothing outside itself,
//! inlines one SVG per figure, attaches the linked CSV tables, gives a
//! crowded section its figure menu, keeps hostile text inert and comes out
//! byte-identical when regenerated. `make test-browser` opens the same
//! pages in headless Chromium.

use std::path::{Path, PathBuf};
use std::process::Command;

use metabezier::experiment::{run_campaign, RunOptions, Spec};
use metabezier::report::{write_html, write_report, ReportOptions};

/// 2 functions × 2 dimensions × 2 algorithms × 3 runs: nine figures (the
/// verdict maps of the final error and the anytime measure, convergence,
/// box plots, the ECDF to the threshold and over all targets at each of
/// the two dimensions, scalability), and a description and a label that
/// try to inject a script.
const SPEC: &str = r#"
[experiment]
name = "html_test"
description = "Hostile <script>alert(1)</script> & \"quotes\" *stars* | pipes"
seed = 11
runs = 3
budget = 1000
threshold = 1e-3

[[problem]]
function = ["sphere", "rastrigin"]
dim = [2, 4]

[[algorithm]]
name = "hs"
label = "HS<script>alert(2)</script>"

[[algorithm]]
name = "pso"
label = "PSO"
swarm = 10
"#;

/// Runs [`SPEC`] into `tmp/results` and writes its report.
fn reported(tmp: &Path) -> (PathBuf, metabezier::report::ReportSummary) {
    let path = tmp.join("spec.toml");
    std::fs::write(&path, SPEC).unwrap();
    let spec = Spec::parse(&path, SPEC).unwrap();
    let out = tmp.join("results");
    let opts = RunOptions {
        out: Some(out.clone()),
        threads: Some(2),
        ..RunOptions::default()
    };
    assert!(run_campaign(&spec, &opts).unwrap().complete);
    let summary = write_report(&out, &ReportOptions::default()).unwrap();
    (out, summary)
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Every `http://` or `https://` of `html` that is not the value of an
/// `xmlns` or `xmlns:NAME` attribute.
fn external_urls(html: &str) -> Vec<String> {
    let mut found = Vec::new();
    for scheme in ["http://", "https://"] {
        for (at, _) in html.match_indices(scheme) {
            let before = &html[..at];
            let namespace = before.strip_suffix('"').is_some_and(|b| {
                let attr = b.strip_suffix('=').unwrap_or("");
                let name = attr.rsplit([' ', '\n', '<']).next().unwrap_or("");
                name == "xmlns" || name.starts_with("xmlns:")
            });
            if !namespace {
                let end = html[at..]
                    .find(['"', '\'', ' ', '<', ')'])
                    .map_or(html.len(), |e| at + e);
                found.push(html[at..end].to_owned());
            }
        }
    }
    found
}

/// The values of every `attr="…"` of `html`.
fn attribute_values<'h>(html: &'h str, attr: &str) -> Vec<&'h str> {
    let key = format!(" {attr}=\"");
    html.match_indices(&key)
        .map(|(at, _)| {
            let v = &html[at + key.len()..];
            &v[..v.find('"').unwrap()]
        })
        .collect()
}

/// The `tables/X.csv` files linked from `md`, each once, in order.
fn linked_csvs(md: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for (at, _) in md.match_indices("](tables/") {
        let rest = &md[at + 2..];
        let link = &rest[..rest.find(')').unwrap()];
        if link.ends_with(".csv") && !out.iter().any(|l| l == link) {
            out.push(link.to_owned());
        }
    }
    out
}

#[test]
fn report_html_is_self_contained_escaped_and_reproducible() {
    let tmp = tempfile::tempdir().unwrap();
    let (dir, summary) = reported(tmp.path());
    assert_eq!(summary.html, dir.join("report.html"));
    let html = read(&summary.html);
    let md = read(&dir.join("report.md"));

    // Nothing outside the page: no address but the SVG namespaces, no
    // source but data: URIs, no link but anchors and relative files.
    assert_eq!(external_urls(&html), Vec::<String>::new());
    assert!(attribute_values(&html, "src")
        .iter()
        .all(|s| s.starts_with("data:image/")));
    for href in attribute_values(&html, "href") {
        assert!(
            href.starts_with('#') || (!href.contains(':') && !href.starts_with('/')),
            "{href}"
        );
    }

    // One inline SVG per figure of report.md, with its prolog dropped.
    let figures = md.matches("![").count();
    assert_eq!(figures, 9, "{md}");
    assert_eq!(html.matches("<svg").count(), figures);
    assert_eq!(html.matches("<span class=\"mb-svg\"").count(), figures);
    assert!(!html.contains("<?xml") && !html.contains("data:image/png"));

    // Each linked CSV once, as a collapsed table with all its rows.
    let csvs = linked_csvs(&md);
    assert!(csvs.len() >= 8, "{csvs:?}");
    assert_eq!(
        html.matches("<details class=\"mb-csv\"").count(),
        csvs.len()
    );
    for csv in &csvs {
        let rows = read(&dir.join(csv)).lines().count() - 1;
        assert!(
            html.contains(&format!(
                "Table <code>{csv}</code>: {rows} row{}",
                if rows == 1 { "" } else { "s" }
            )),
            "{csv}"
        );
    }
    let problems = read(&dir.join("tables/problems.csv"));
    let row = problems.lines().nth(1).unwrap();
    let cells: Vec<String> = row
        .split(',')
        .map(|c| {
            let class = if c.parse::<f64>().is_ok() {
                " class=\"r\""
            } else {
                ""
            };
            format!("<td{class}>{c}</td>")
        })
        .collect();
    assert!(html.contains(&cells.concat()), "{row}");

    // More than six figures in a section: a menu with one option each, and
    // every figure still in the page.
    assert_eq!(html.matches("<select").count(), 1);
    assert_eq!(html.matches("<div class=\"mb-unit\"").count(), figures);
    assert_eq!(html.matches("<option value=").count(), figures + 1);
    assert!(html.contains("<option value=\"2\">3. Convergence</option>"));

    // A table of contents of the ## headings, sortable tables, the script
    // that sets the ready flag.
    let sections: Vec<&str> = md.lines().filter_map(|l| l.strip_prefix("## ")).collect();
    let toc = &html[html.find("<nav class=\"mb-toc\"").unwrap()..html.find("</nav>").unwrap()];
    assert_eq!(toc.matches("<li>").count(), sections.len());
    for s in sections {
        assert!(toc.contains(&format!(">{s}</a></li>")), "{s}");
    }
    assert!(html.contains("<table class=\"mb-sortable\">"));
    assert!(html.contains("document.body.dataset.ready = \"1\";"));

    // The hostile description and label stay text: the page's one script
    // is its own.
    assert_eq!(html.matches("<script").count(), 1);
    assert!(html.contains("Hostile &lt;script&gt;alert(1)&lt;/script&gt; &amp; &quot;quotes&quot;"));
    assert!(html.contains("HS&lt;script&gt;alert(2)&lt;/script&gt;"));
    assert!(!html.contains("<script>alert"));

    // Byte-identical when written again, alone or with the whole report.
    write_html(&dir).unwrap();
    assert_eq!(read(&dir.join("report.html")), html);
    write_report(&dir, &ReportOptions::default()).unwrap();
    assert_eq!(read(&dir.join("report.html")), html);
}

#[test]
fn missing_figures_and_long_tables() {
    let tmp = tempfile::tempdir().unwrap();
    let (dir, _) = reported(tmp.path());
    // Without its SVG a figure is its PNG; without both, a note.
    std::fs::remove_file(dir.join("plots/convergence.svg")).unwrap();
    std::fs::remove_file(dir.join("plots/boxplots.svg")).unwrap();
    std::fs::remove_file(dir.join("plots/boxplots.png")).unwrap();
    // A table longer than 2,000 rows shows its first 2,000.
    let mut big = String::from("name,value\n");
    for i in 0..2500 {
        big.push_str(&format!("r{i},{i}\n"));
    }
    std::fs::write(dir.join("tables/big.csv"), big).unwrap();
    let mut md = read(&dir.join("report.md"));
    md.push_str("\nCSV: [`tables/big.csv`](tables/big.csv)\n");
    std::fs::write(dir.join("report.md"), md).unwrap();

    let html = read(&write_html(&dir).unwrap());
    assert_eq!(html.matches("<svg").count(), 7);
    assert_eq!(
        html.matches("<img id=\"fig-convergence\" alt=\"Convergence\" src=\"data:image/png;base64,iVBORw0KGgo")
            .count(),
        1
    );
    assert!(html.contains("figure missing: neither plots/boxplots.svg nor plots/boxplots.png"));
    assert!(html.contains("Table <code>tables/big.csv</code>: 2,500 rows, 2 columns"));
    assert!(html.contains("first 2,000 of 2,500 rows; the full table is tables/big.csv"));
    assert!(html.contains("<td>r1999</td>") && !html.contains("<td>r2000</td>"));

    // No report.md: an error naming it.
    std::fs::remove_file(dir.join("report.md")).unwrap();
    let e = write_html(&dir).unwrap_err().to_string();
    assert!(e.contains("report.md") && e.contains("cannot read"), "{e}");
}

#[test]
fn the_implant_writes_report_html_with_its_report() {
    let tmp = tempfile::tempdir().unwrap();
    let volume = Path::new(env!("CARGO_MANIFEST_DIR")).join(metabezier::ct::CT0051_PATH);
    let spec = tmp.path().join("spec.toml");
    std::fs::write(
        &spec,
        format!(
            "[implant]\nvolume = \"{}\"\nfirst_z = 40\nmidline_slices = [86, 92]\nmethod = \"mhs\"\n\
             budget = 2000\nseed = 7\n\n[defect]\nslices = [70, 72]\noverlays = [72]\n",
            volume.display()
        ),
    )
    .unwrap();
    let out = tmp.path().join("out");
    let run = || {
        let o = Command::new(env!("CARGO_BIN_EXE_metabezier"))
            .arg("implant")
            .arg(&spec)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    let said = run();
    assert!(said.contains("8 files written"), "{said}");
    let html = read(&out.join("report.html"));
    assert!(html.contains("<h1 id=\"chapter-6-cranial-implant\">Chapter 6: cranial implant</h1>"));
    assert!(html.contains("<th>width mm</th>") && html.contains("<table class=\"mb-sortable\">"));
    assert_eq!(external_urls(&html), Vec::<String>::new());
    run();
    assert_eq!(read(&out.join("report.html")), html);
}
