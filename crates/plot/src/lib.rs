//! metabezier-plot: what the report and the implant draw and write as
//! documents. Figures as SVG and PNG through plotters ([`render`], with the
//! shared [`layout`] of axes and legends and the [`factor_lines`] figure),
//! one colour per algorithm ([`style`]), text in the one embedded font
//! ([`font`], DejaVu Sans), PNG encoding ([`png`]), number formats and
//! tables ([`format`](mod@format)), and Markdown tables and `report.html` pages
//! ([`markdown`]).
//!
//! | # | room | what lives there |
//! |---|---|---|
//! | 0 | [`font`], [`png`], [`markdown`] | leaves: the embedded font; PNG bytes; Markdown tables and report.html pages |
//! | 1 | [`format`](mod@format), [`style`] | numbers as the reports print them; series colours |
//! | 2 | [`render`] | drawing primitives, legends, figures in memory |
//! | 3 | [`layout`] | frames, ticks and panels shared by every figure |
//! | 4 | [`factor_lines`] | lines over a design factor (chapters 5 and 6) |
#![warn(missing_docs)]

use metabezier_core::rng;
use metabezier_files as files;

pub mod font;
pub mod markdown;
pub mod png;

pub mod format;
pub mod style;

pub mod render;

pub mod layout;

pub mod factor_lines;
