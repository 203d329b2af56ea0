//! Number formatting and the [`Table`] type rendered both as a Markdown
//! table (rounded, the way papers print numbers) and as a CSV file (full
//! precision, for further processing).

use crate::files::{csv_bytes, fmt_real};
use crate::markdown::{self, Alignment};

/// A table of the report: Markdown and CSV renderings of the same rows.
#[derive(Clone, Debug, Default)]
pub struct Table {
    /// The file stem under `tables/` (`descriptive` → `tables/descriptive.csv`).
    pub stem: String,
    /// The section title in `report.md`.
    pub title: String,
    /// Paragraphs shown before the table (what it contains, how to read it).
    pub intro: Vec<String>,
    /// Column names of the Markdown table.
    pub md_header: Vec<String>,
    /// Markdown rows (formatted numbers).
    pub md_rows: Vec<Vec<String>>,
    /// Column names of the CSV file.
    pub csv_header: Vec<String>,
    /// CSV rows (full-precision numbers).
    pub csv_rows: Vec<Vec<String>>,
}

impl Table {
    /// The CSV bytes of the table.
    pub fn csv_bytes(&self) -> Vec<u8> {
        csv_bytes(&self.csv_header, &self.csv_rows)
    }

    /// The Markdown table (header, alignment row and rows), ending in a newline.
    pub fn markdown(&self) -> String {
        markdown::table(&self.md_header, &self.md_rows, Alignment::ByContent)
    }
}

/// Scientific notation with `digits` significant digits and a signed
/// two-digit exponent, as results tables print errors: `1.23e-05`; zero is
/// `0`, infinities `inf`/`-inf`, NaN `NaN`.
pub fn sci_digits(x: f64, digits: usize) -> String {
    if x.is_nan() {
        return "NaN".into();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf".into() } else { "-inf".into() };
    }
    if x == 0.0 {
        return "0".into();
    }
    let decimals = digits.saturating_sub(1);
    let s = format!("{x:.decimals$e}");
    // Rust writes `1.23e-5`: pad the exponent to a sign and two digits.
    match s.split_once('e') {
        Some((mantissa, exp)) => {
            let (sign, digits) = match exp.strip_prefix('-') {
                Some(d) => ('-', d),
                None => ('+', exp),
            };
            format!("{mantissa}e{sign}{digits:0>2}")
        }
        None => s,
    }
}

/// An error or other real in three significant digits (see [`sci_digits`]).
pub fn sci(x: f64) -> String {
    sci_digits(x, 3)
}

/// An optional real in three significant digits, `—` when absent.
pub fn sci_opt(x: Option<f64>) -> String {
    x.map_or_else(|| "\u{2014}".to_owned(), sci)
}

/// An effect in a table cell: two decimals from 0.095 up, two significant
/// digits in scientific notation below; `∞` and `−∞` for an unbounded end
/// of an interval, `—` for NaN.
pub fn effect(x: f64) -> String {
    if x.is_nan() {
        "\u{2014}".into()
    } else if x.is_infinite() {
        if x > 0.0 {
            "\u{221e}"
        } else {
            "\u{2212}\u{221e}"
        }
        .into()
    } else if x == 0.0 {
        "0".into()
    } else if (0.095..1e4).contains(&x.abs()) {
        format!("{x:.2}")
    } else {
        sci_digits(x, 2)
    }
}

/// A Hodges–Lehmann estimate with its confidence interval:
/// `-0.30 [-0.57, -0.04]` ([`effect`] for each).
pub fn effect_interval(estimate: f64, low: f64, high: f64) -> String {
    format!("{} [{}, {}]", effect(estimate), effect(low), effect(high))
}

/// Three posterior probabilities (better, within the rope, worse) to two
/// decimals: `0.98/0.02/0.00`; `—` when unknown.
pub fn posterior(better: f64, within: f64, worse: f64) -> String {
    if better.is_nan() || within.is_nan() || worse.is_nan() {
        "\u{2014}".into()
    } else {
        format!("{better:.2}/{within:.2}/{worse:.2}")
    }
}

/// A p-value: three significant digits in scientific notation below 0.001,
/// else three decimals.
pub fn p_value(p: f64) -> String {
    if p.is_finite() && p >= 0.001 {
        format!("{p:.3}")
    } else {
        sci_digits(p, 3)
    }
}

/// A mean number of evaluations: rounded to an integer below one million,
/// scientific notation above; `—` when absent.
pub fn evaluations(x: Option<f64>) -> String {
    match x {
        None => "\u{2014}".into(),
        Some(v) if v.is_finite() && v.abs() < 1e6 => format!("{v:.0}"),
        Some(v) => sci(v),
    }
}

/// A fraction as a percentage without decimals, `60%`.
pub fn percent(x: f64) -> String {
    if x.is_finite() {
        format!("{:.0}%", 100.0 * x)
    } else {
        "\u{2014}".into()
    }
}

/// A real with two decimals (average ranks).
pub fn fixed2(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.2}")
    } else {
        sci(x)
    }
}

/// A real for a CSV file: shortest round-trip text (see [`fmt_real`]).
pub fn csv_real(x: f64) -> String {
    fmt_real(x)
}

/// An optional real for a CSV file: empty when absent.
pub fn csv_opt(x: Option<f64>) -> String {
    x.map_or_else(String::new, fmt_real)
}

/// Unicode superscript form of an integer: `-3` → `⁻³`.
fn superscript(k: i64) -> String {
    k.to_string()
        .chars()
        .map(|c| match c {
            '-' => '\u{207b}',
            '0' => '\u{2070}',
            '1' => '\u{b9}',
            '2' => '\u{b2}',
            '3' => '\u{b3}',
            d => char::from_u32(0x2070 + d.to_digit(10).unwrap_or(0)).unwrap_or(d),
        })
        .collect()
}

/// A tick label for a log10 axis position `x`: `10⁻⁸` on whole decades
/// (`1`, `10` for 10⁰ and 10¹), else two significant digits with the power
/// of ten, `3×10⁻⁸`.
pub fn pow_tick(x: f64) -> String {
    if !x.is_finite() {
        return String::new();
    }
    let k = x.round();
    if (x - k).abs() < 1e-6 {
        return match k as i64 {
            0 => "1".into(),
            1 => "10".into(),
            k => format!("10{}", superscript(k)),
        };
    }
    let e = x.floor();
    let m = 10f64.powf(x - e);
    let m = format!("{m:.1}");
    let m = m.trim_end_matches('0').trim_end_matches('.');
    match e as i64 {
        0 => m.to_owned(),
        e => format!("{m}×10{}", superscript(e)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scientific_notation_as_in_papers() {
        assert_eq!(sci(1.234_567e-5), "1.23e-05");
        assert_eq!(sci(9.999e-6), "1.00e-05");
        assert_eq!(sci(12345.0), "1.23e+04");
        assert_eq!(sci(-0.5), "-5.00e-01");
        assert_eq!(sci(0.0), "0");
        assert_eq!(sci(f64::INFINITY), "inf");
        assert_eq!(sci(f64::NAN), "NaN");
        assert_eq!(sci_digits(3.0e-120, 2), "3.0e-120");
        assert_eq!(sci_opt(None), "\u{2014}");
    }

    #[test]
    fn other_formats() {
        assert_eq!(p_value(0.0312), "0.031");
        assert_eq!(p_value(1.0), "1.000");
        assert_eq!(p_value(1.9e-6), "1.90e-06");
        assert_eq!(evaluations(Some(1234.4)), "1234");
        assert_eq!(evaluations(Some(2.5e7)), "2.50e+07");
        assert_eq!(evaluations(None), "\u{2014}");
        assert_eq!(percent(0.6), "60%");
        assert_eq!(fixed2(2.345), "2.35");
        assert_eq!(pow_tick(-8.0), "10\u{207b}\u{2078}");
        assert_eq!(pow_tick(-10.000000000001), "10\u{207b}\u{b9}\u{2070}");
        assert_eq!(pow_tick(0.0), "1");
        assert_eq!(pow_tick(1.0), "10");
        assert_eq!(pow_tick(23.0), "10\u{b2}\u{b3}");
        assert_eq!(pow_tick(3e-8f64.log10()), "3×10\u{207b}\u{2078}");
        assert_eq!(pow_tick(2500f64.log10()), "2.5×10\u{b3}");
        assert_eq!(pow_tick(5f64.log10()), "5");
        assert_eq!(pow_tick(f64::NEG_INFINITY), "");
    }

    #[test]
    fn csv_quotes_fields() {
        let t = Table {
            csv_header: vec!["algorithm".into(), "params".into()],
            csv_rows: vec![vec!["HS, tuned".into(), "a=1;b=2".into()]],
            ..Table::default()
        };
        let bytes = t.csv_bytes();
        assert_eq!(
            String::from_utf8(bytes).unwrap(),
            "algorithm,params\n\"HS, tuned\",a=1;b=2\n"
        );
    }
}
