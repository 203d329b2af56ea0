//! The verdict map: where each verdict against the reference holds. Rows
//! are the design points (every combination of the factors that vary other
//! than the algorithm, the function and the run) under the verdict over all
//! problems; columns are the algorithms; a cell is coloured by the verdict
//! of the comparison across the units there (better, worse, equivalent,
//! undecided) and carries its units (functions, outlines or segments)
//! better/equal/worse.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::super::format::Table;
use super::super::render::{font, text_width, Draw, DrawResult};
use super::super::style::{base_colour, SeriesStyle};
use super::layout::{frame, frame_height, AXIS_FONT, TICK_FONT};
use super::{Figure, Page, Plot};

/// One verdict of the map: its colour class and unit counts.
#[derive(Clone, Debug, PartialEq)]
struct Mark {
    verdict: String,
    counts: String,
}

/// The verdict-map figure.
pub(crate) struct VerdictMap {
    title: String,
    /// Design points (rows), `all problems` first.
    points: Vec<String>,
    /// Algorithms (columns).
    algorithms: Vec<String>,
    /// `marks[row][column]`.
    marks: Vec<Vec<Option<Mark>>>,
}

/// Height of a row of cells.
const ROW_H: u32 = 30;
/// Colour of "better".
fn better() -> RGBColor {
    base_colour("ga")
}
/// Colour of "worse".
fn worse() -> RGBColor {
    base_colour("mhs")
}
/// Colour of "undecided" (the test did not reject; no equivalence either).
const TIE: RGBColor = RGBColor(228, 228, 228);
/// Colour of "equivalent" (Okabe & Ito's sky blue, lightened).
const EQUIVALENT: RGBColor = RGBColor(170, 215, 242);

impl VerdictMap {
    fn label_width(&self) -> u32 {
        self.points
            .iter()
            .map(|p| text_width(p, TICK_FONT))
            .max()
            .unwrap_or(40)
            + 24
    }

    fn column_width(&self) -> u32 {
        self.algorithms
            .iter()
            .map(|a| text_width(a, TICK_FONT))
            .max()
            .unwrap_or(40)
            .max(text_width("10/10/10", TICK_FONT))
            + 16
    }

    fn legend(&self) -> Vec<(String, SeriesStyle)> {
        vec![
            (
                "better than the reference".into(),
                SeriesStyle::solid(better()),
            ),
            ("equivalent".into(), SeriesStyle::solid(EQUIVALENT)),
            ("undecided".into(), SeriesStyle::solid(TIE)),
            ("worse".into(), SeriesStyle::solid(worse())),
        ]
    }
}

impl Draw for VerdictMap {
    fn size(&self) -> (u32, u32) {
        let w =
            (self.label_width() + self.column_width() * self.algorithms.len() as u32 + 20).max(600);
        let h = frame_height(w, &self.legend()) + 40 + ROW_H * self.points.len() as u32 + 30;
        (w, h)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        let area = frame(root, &self.title, &self.legend())?;
        let (x0, cw) = (self.label_width() as i32, self.column_width() as i32);
        let head = 40i32;
        let centre = |s| font(TICK_FONT).pos(Pos::new(HPos::Center, s));
        for (j, a) in self.algorithms.iter().enumerate() {
            let x = x0 + cw * j as i32 + cw / 2;
            area.draw_text(a, &centre(VPos::Bottom), (x, head - 8))?;
        }
        let left = font(TICK_FONT).pos(Pos::new(HPos::Right, VPos::Center));
        for (i, (point, row)) in self.points.iter().zip(&self.marks).enumerate() {
            let y = head + ROW_H as i32 * i as i32;
            area.draw_text(point, &left, (x0 - 10, y + ROW_H as i32 / 2))?;
            for (j, mark) in row.iter().enumerate() {
                let x = x0 + cw * j as i32;
                let cell = [(x + 1, y + 1), (x + cw - 1, y + ROW_H as i32 - 1)];
                let Some(m) = mark else {
                    area.draw(&Rectangle::new(
                        cell,
                        RGBColor(200, 200, 200).stroke_width(1),
                    ))?;
                    continue;
                };
                let (fill, ink) = match m.verdict.as_str() {
                    "better" => (better(), WHITE),
                    "worse" => (worse(), WHITE),
                    "equivalent" => (EQUIVALENT, BLACK),
                    _ => (TIE, BLACK),
                };
                area.draw(&Rectangle::new(cell, fill.filled()))?;
                area.draw_text(
                    &m.counts,
                    &centre(VPos::Center).color(&ink),
                    (x + cw / 2, y + ROW_H as i32 / 2),
                )?;
            }
            if i == 0 && self.points.len() > 1 {
                let y = y + ROW_H as i32;
                let x1 = x0 + cw * self.algorithms.len() as i32;
                area.draw(&PathElement::new(
                    vec![(x0, y), (x1, y)],
                    BLACK.stroke_width(2),
                ))?;
            }
        }
        let note = font(AXIS_FONT - 2).pos(Pos::new(HPos::Left, VPos::Top));
        let y = head + ROW_H as i32 * self.points.len() as i32 + 8;
        area.draw_text(
            "cells: units (functions, outlines or segments) better/equal/worse than the \
             reference at that design point",
            &note,
            (10, y),
        )?;
        Ok(())
    }
}

/// The verdict map of `measure` against the reference, from the verdict
/// table's CSV rows (`table`, `measure`, `algorithm`, `scope`, `better`,
/// `equal`, `worse`, `verdict`) of the reference and state-of-the-art
/// families, the first test of each scope (the signed-rank test across the
/// functions; the Friedman post-hoc rows are left to the table), or `None`
/// when the results have no design point beyond "all". Only the algorithms
/// named in `shown` (those the other figures draw: of a tuning grid its
/// best and default settings) get a column.
pub(super) fn verdict_map(t: &Table, measure: &str, shown: &[&str]) -> Option<Plot> {
    let col = |name: &str| t.csv_header.iter().position(|h| h == name);
    let (table, meas, alg, scope) = (
        col("table")?,
        col("measure")?,
        col("algorithm")?,
        col("scope")?,
    );
    let (b, e, w, v) = (
        col("better")?,
        col("equal")?,
        col("worse")?,
        col("verdict")?,
    );
    let reference = col("reference")?;
    let rows: Vec<&Vec<String>> = t
        .csv_rows
        .iter()
        .filter(|r| {
            (r[table] == "reference" || r[table] == "state-of-the-art")
                && r[meas] == measure
                && shown.contains(&r[alg].as_str())
        })
        .collect();
    let parts = |r: &Vec<String>| {
        if r[scope] == "all" {
            0
        } else {
            r[scope].split(';').count()
        }
    };
    let most = rows.iter().map(|r| parts(r)).max()?;
    if most == 0 {
        return None;
    }
    let mut points: Vec<String> = vec!["all".into()];
    let mut algorithms: Vec<String> = Vec::new();
    for r in &rows {
        if parts(r) == most && !points.contains(&r[scope]) {
            points.push(r[scope].clone());
        }
        if !algorithms.contains(&r[alg]) {
            algorithms.push(r[alg].clone());
        }
    }
    let mut marks = vec![vec![None; algorithms.len()]; points.len()];
    for r in rows
        .iter()
        .filter(|r| parts(r) == most || r[scope] == "all")
    {
        let (Some(i), Some(j)) = (
            points.iter().position(|p| *p == r[scope]),
            algorithms.iter().position(|a| *a == r[alg]),
        ) else {
            continue;
        };
        // The first test of a scope is the one across the functions (the
        // post-hoc rows after it are another family).
        marks[i][j].get_or_insert_with(|| Mark {
            verdict: r[v].clone(),
            counts: format!("{}/{}/{}", r[b], r[e], r[w]),
        });
    }
    let reference = rows
        .first()
        .map_or_else(String::new, |r| r[reference].clone());
    let shown: Vec<String> = points
        .iter()
        .map(|p| {
            if p == "all" {
                "all design points".to_owned()
            } else {
                p.replace(';', ", ").replace('=', " = ")
            }
        })
        .collect();
    Some(Plot {
        stem: format!("verdicts_{}", measure.replace('-', "_")),
        title: format!("Verdicts per design point against {reference} ({measure})"),
        caption: format!(
            "Where each verdict against {reference} holds, measure {measure}: one row per \
             design point (the combination of the factors other than the algorithm, the \
             function and the run) under the verdict over all of them, one column per \
             algorithm. A cell is green where the Holm-corrected test across the units \
             at that design point finds the algorithm better than the reference, vermillion \
             where worse, light blue where the Bayesian signed-rank test finds them \
             equivalent (P(rope) ≥ 0.95), grey where undecided; it reads the \
             units (functions, outlines or segments) better/equal/worse. The same verdicts, with p-values and effect \
             sizes, are in tables/verdicts.csv."
        ),
        figure: Figure::Verdicts(VerdictMap {
            title: format!("Verdict against {reference}, {measure}, per design point"),
            points: shown,
            algorithms,
            marks,
        }),
        page: Page::SINGLE,
    })
}
