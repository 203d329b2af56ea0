//! One colour per algorithm across every report. The built-in optimisers
//! have fixed colours from the colour-blind-safe palette of Okabe & Ito
//! ("Color Universal Design", 2008), with two of Tol's muted colours
//! (Tol, "Colour Schemes", SRON/EPS/TN/09-002, 2021) for the tenth and
//! eleventh; any other optimiser gets a colour computed from its name, so
//! it too keeps its colour from report to report. A variant of an
//! optimiser (a label other than its own name: `HS-tuned`, `MHS+LM`,
//! `MHS-pervar`) has the optimiser's hue and a dashed line, and several
//! configurations of one label are lighter shades of it. Curve labels
//! that name no method (`C1`, `G1`) get Tol's muted colours in order.

use plotters::style::RGBColor;

use crate::rng::fnv1a64;

/// How a series is drawn: its colour, and whether its line is dashed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SeriesStyle {
    /// The line and fill colour.
    pub colour: RGBColor,
    /// Whether the line is dashed (a variant of an optimiser).
    pub dashed: bool,
}

impl SeriesStyle {
    /// A solid line of `colour` (the data of an overlay, a reference line).
    pub fn solid(colour: RGBColor) -> Self {
        SeriesStyle {
            colour,
            dashed: false,
        }
    }
}

/// A legend entry: the series' name and style.
pub type LegendEntry = (String, SeriesStyle);

/// The fixed colours of the built-in optimisers and of LM, by the key of
/// their algorithm name (lower case, letters and digits only).
const BUILT_IN: [(&str, (u8, u8, u8)); 10] = [
    ("mhs", (0xd5, 0x5e, 0x00)),    // Okabe–Ito vermillion
    ("hs", (0x00, 0x72, 0xb2)),     // Okabe–Ito blue
    ("ghs", (0x56, 0xb4, 0xe9)),    // Okabe–Ito sky blue
    ("ga", (0x00, 0x9e, 0x73)),     // Okabe–Ito bluish green
    ("pso", (0xe6, 0x9f, 0x00)),    // Okabe–Ito orange
    ("cmaes", (0xcc, 0x79, 0xa7)),  // Okabe–Ito reddish purple
    ("lshade", (0x00, 0x00, 0x00)), // Okabe–Ito black
    ("lm", (0x33, 0x22, 0x88)),     // Tol indigo
    ("random", (0x99, 0x99, 0x33)), // Tol olive
    ("best2009", (0x88, 0x88, 0x88)),
];

/// `name` in lower case with letters and digits only: `CMA-ES` → `cmaes`.
fn key(name: &str) -> String {
    name.chars()
        .filter(char::is_ascii_alphanumeric)
        .map(|c| c.to_ascii_lowercase())
        .collect()
}

/// The colour of an optimiser: fixed for the built-ins, else a hue from the
/// FNV-1a hash of its key at fixed saturation 0.65 and lightness 0.40
/// (dark enough on white), the same in every report.
pub fn base_colour(kind: &str) -> RGBColor {
    let k = key(kind);
    if let Some((_, (r, g, b))) = BUILT_IN.iter().find(|(n, _)| *n == k) {
        return RGBColor(*r, *g, *b);
    }
    hsl((fnv1a64(&k) % 360) as f64, 0.65, 0.40)
}

/// HSL to RGB (Foley et al., "Computer Graphics", 2nd ed., §13.3.5).
fn hsl(h: f64, s: f64, l: f64) -> RGBColor {
    let c = (1.0 - (2.0 * l - 1.0).abs()) * s;
    let hp = h / 60.0;
    let x = c * (1.0 - (hp % 2.0 - 1.0).abs());
    let (r, g, b) = match hp as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let m = l - c / 2.0;
    let to = |v: f64| ((v + m) * 255.0).round().clamp(0.0, 255.0) as u8;
    RGBColor(to(r), to(g), to(b))
}

/// `c` mixed with white: `t` = 0 keeps it, 1 gives white.
fn lighten(c: RGBColor, t: f64) -> RGBColor {
    let to = |v: u8| (f64::from(v) + (255.0 - f64::from(v)) * t).round() as u8;
    RGBColor(to(c.0), to(c.1), to(c.2))
}

/// The optimiser part of an algorithm name: `mhs+lm` → `mhs`.
fn optimiser(kind: &str) -> &str {
    kind.split('+').next().unwrap_or(kind)
}

/// The style of every cell, given as its `(label, kind)` (the kind is the
/// algorithm name, empty when unknown), in the order of `cells`: the optimiser's
/// colour, dashed when the label is not the optimiser's own name (or the
/// algorithm is a hybrid such as `mhs+lm`), and the k-th of n
/// configurations sharing a label lightened by 0.5·k/(n − 1).
pub fn cell_styles(cells: &[(&str, &str)]) -> Vec<SeriesStyle> {
    cells
        .iter()
        .enumerate()
        .map(|(i, &(label, kind))| {
            let kind = if kind.is_empty() { label } else { kind };
            let base = base_colour(optimiser(kind));
            let dashed = key(label) != key(kind) || kind.contains('+');
            let same = |o: &&(&str, &str)| o.0 == label;
            let k = cells[..i].iter().filter(same).count();
            let n = k + cells[i..].iter().filter(same).count();
            let shade = if n > 1 {
                0.5 * k as f64 / (n - 1) as f64
            } else {
                0.0
            };
            SeriesStyle {
                colour: lighten(base, shade),
                dashed,
            }
        })
        .collect()
}

/// Categorical colours for curve labels that name no method (`C1`, `G1`,
/// a function): Tol's muted scheme (Tol 2021), in order.
const OTHERS: [(u8, u8, u8); 7] = [
    (0xcc, 0x66, 0x77), // rose
    (0x11, 0x77, 0x33), // green
    (0x88, 0x22, 0x55), // wine
    (0x44, 0xaa, 0x99), // teal
    (0xaa, 0x44, 0x99), // purple
    (0xdd, 0xcc, 0x77), // sand
    (0x88, 0xcc, 0xee), // cyan
];

/// The colours of curve labels, distinct among `labels`: a label that
/// names a method (`LM`, `MHS`, `CMA-ES+LM`: the label or its first part
/// before `+`, `-`, `/` or a space is a built-in) gets the optimiser's
/// colour, unless an earlier label has it; the others, in order, Tol's
/// muted colours, then colours from their names.
pub fn label_colours(labels: &[&str]) -> Vec<RGBColor> {
    let built_in = |n: &str| BUILT_IN.iter().any(|(b, _)| *b == key(n));
    let mut out: Vec<RGBColor> = Vec::with_capacity(labels.len());
    let mut others = OTHERS.iter().map(|&(r, g, b)| RGBColor(r, g, b));
    for label in labels {
        let head = label.split(['+', '-', '/', ' ']).next().unwrap_or(label);
        let method = if built_in(label) {
            Some(base_colour(label))
        } else if built_in(head) {
            Some(base_colour(head))
        } else {
            None
        };
        let c = match method.filter(|c| !out.contains(c)) {
            Some(c) => c,
            None => others
                .by_ref()
                .find(|c| !out.contains(c))
                .unwrap_or_else(|| base_colour(&format!("{label}#"))),
        };
        out.push(c);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cell as `cell_styles` sees it; its parameters do not enter.
    fn cell<'a>(label: &'a str, kind: &'a str, _params: &str) -> (&'a str, &'a str) {
        (label, kind)
    }

    #[test]
    fn built_ins_keep_their_colour_whatever_their_position() {
        let a = cell_styles(&[cell("HS", "hs", ""), cell("PSO", "pso", "")]);
        let b = cell_styles(&[
            cell("PSO", "pso", ""),
            cell("GA", "ga", ""),
            cell("HS", "hs", ""),
        ]);
        assert_eq!(a[0], b[2]);
        assert_eq!(a[1], b[0]);
        assert_eq!(a[1].colour, RGBColor(0xe6, 0x9f, 0x00));
        assert!(!a[0].dashed);
        let names = [
            "hs", "ghs", "ga", "pso", "mhs", "cmaes", "lshade", "lm", "random",
        ];
        let colours: std::collections::BTreeSet<(u8, u8, u8)> = names
            .iter()
            .map(|n| {
                let c = base_colour(n);
                (c.0, c.1, c.2)
            })
            .collect();
        assert_eq!(colours.len(), names.len(), "the built-ins share a colour");
    }

    #[test]
    fn variants_share_the_hue_and_are_dashed() {
        let s = cell_styles(&[
            cell("HS", "hs", ""),
            cell("HS-tuned", "hs", ""),
            cell("MHS+LM", "mhs+lm", ""),
            cell("CMA-ES", "cmaes", ""),
        ]);
        assert_eq!(s[0].colour, s[1].colour);
        assert!(!s[0].dashed && s[1].dashed);
        assert_eq!(s[2].colour, base_colour("mhs"));
        assert!(s[2].dashed);
        assert!(!s[3].dashed, "CMA-ES is cmaes's own name");
    }

    #[test]
    fn curve_labels_get_their_method_colour_and_stay_distinct() {
        let c = label_colours(&["LM", "MHS", "MHS+LM", "quadratic"]);
        assert_eq!(c[0], base_colour("lm"));
        assert_eq!(c[1], base_colour("mhs"));
        assert_ne!(c[2], c[1], "MHS+LM is told apart from MHS");
        assert_eq!(c[3], RGBColor(0x11, 0x77, 0x33));
        // Labels that name no method get distinct categorical colours.
        let c = label_colours(&["C1", "G1"]);
        assert_eq!(c, [RGBColor(0xcc, 0x66, 0x77), RGBColor(0x11, 0x77, 0x33)]);
    }

    #[test]
    fn other_optimisers_get_a_colour_from_their_name() {
        let a = base_colour("my-optimiser");
        assert_eq!(a, base_colour("MyOptimiser"));
        assert_ne!(a, base_colour("another"));
        let s = cell_styles(&[cell("Mine", "", ""), cell("Mine", "", "x=1")]);
        assert_eq!(s[0].colour, base_colour("Mine"));
        assert_ne!(s[0].colour, s[1].colour, "configurations are shaded");
        assert!(!s[0].dashed);
    }
}
