//! Reports and comparisons: report.md and its tables, reading results back,
//! compare, the HTML page and the readability of figures.

#[path = "../common/mod.rs"]
mod common;

mod compare;
mod html;
mod readable;
mod report_reading;
mod report_tests;
