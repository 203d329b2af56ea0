//! The fitted shape as a DXF drawing that CAD tools read exactly: every
//! segment one `SPLINE` entity of its own degree, with its control points
//! and, for a rational segment, its weights, so that nothing is
//! approximated (SVG, which has no rational curves, cannot do this).
//!
//! A Bézier segment of degree `m` is the B-spline of order `m + 1` on the
//! clamped knot vector `[0^(m+1), 1^(m+1)]` (Piegl & Tiller, *The NURBS
//! Book*, §2.2), and a rational one the NURBS with the same weights, which
//! is DXF's `SPLINE` with flag 4 (rational) and group 41 (weights)
//! (Autodesk, *DXF Reference*, "SPLINE"). The file is DXF R2000 (`AC1015`)
//! with the tables, block records, blocks and root dictionary that a
//! drawing of that version holds, every object with a unique handle and
//! its owner; the outline frame (y up) is the drawing's x–y plane.
//! Coordinates are written with Rust's shortest round-trip formatting, so
//! they read back bit for bit.

use std::fmt::Write as _;

use super::ShapeFit;
use crate::fit::Segment;
use crate::geometry::Curve;

/// Writes group code and value pairs with consecutive handles.
struct Dxf {
    text: String,
    next_handle: u64,
}

impl Dxf {
    fn pair(&mut self, code: u32, value: impl std::fmt::Display) {
        let _ = write!(self.text, "{code}\n{value}\n");
    }

    /// A new handle (hexadecimal, as DXF writes them).
    fn handle(&mut self) -> String {
        let h = format!("{:X}", self.next_handle);
        self.next_handle += 1;
        h
    }

    /// `0 TABLE` … with a record per name in `entries`, each with a new
    /// handle and its body written by `entry`.
    fn table(&mut self, name: &str, entries: &[&str], entry: impl Fn(&mut Dxf, &str)) {
        let table = self.handle();
        let records: Vec<(&str, String)> = entries.iter().map(|&e| (e, self.handle())).collect();
        self.table_of(name, &table, &records, entry);
    }

    /// `0 TABLE` with handle `table` and the given `(name, handle)`
    /// records (each owned by the table), their bodies written by `entry`.
    fn table_of(
        &mut self,
        name: &str,
        table: &str,
        records: &[(&str, String)],
        entry: impl Fn(&mut Dxf, &str),
    ) {
        self.pair(0, "TABLE");
        self.pair(2, name);
        self.pair(5, table);
        self.pair(330, 0);
        self.pair(100, "AcDbSymbolTable");
        self.pair(70, records.len());
        for (e, h) in records {
            self.pair(0, name);
            self.pair(5, h);
            self.pair(330, table);
            self.pair(100, "AcDbSymbolTableRecord");
            entry(self, e);
        }
        self.pair(0, "ENDTAB");
    }

    /// A `DICTIONARY` object with its handle, owner and `(name, handle)`
    /// entries.
    fn dictionary(&mut self, handle: &str, owner: &str, entries: &[(&str, &str)]) {
        self.pair(0, "DICTIONARY");
        self.pair(5, handle);
        self.pair(330, owner);
        self.pair(100, "AcDbDictionary");
        self.pair(281, 1);
        for (name, h) in entries {
            self.pair(3, name);
            self.pair(350, h);
        }
    }
}

impl Dxf {
    /// The TABLES section: the symbol tables a DXF reader expects, and the
    /// block records with the fixed handles `model` and `paper`.
    fn tables(&mut self, model: &str, paper: &str) {
        self.pair(0, "SECTION");
        self.pair(2, "TABLES");
        self.symbol_tables();
        // BLOCK_RECORD with the two fixed handles.
        let records = self.handle();
        self.table_of(
            "BLOCK_RECORD",
            &records,
            &[
                ("*Model_Space", model.to_owned()),
                ("*Paper_Space", paper.to_owned()),
            ],
            |d, name| {
                d.pair(100, "AcDbBlockTableRecord");
                d.pair(2, name);
            },
        );
        self.pair(0, "ENDSEC");
    }

    /// The symbol tables before the block records: a viewport, the line
    /// types, layer `0`, the standard text style, the application id and
    /// dimension style, no views and no UCS.
    fn symbol_tables(&mut self) {
        self.table("VPORT", &["*Active"], |d, name| {
            d.pair(100, "AcDbViewportTableRecord");
            d.pair(2, name);
            d.pair(70, 0);
        });
        self.table("LTYPE", &["ByBlock", "ByLayer", "Continuous"], |d, name| {
            d.pair(100, "AcDbLinetypeTableRecord");
            d.pair(2, name);
            d.pair(70, 0);
            d.pair(
                3,
                if name == "Continuous" {
                    "Solid line"
                } else {
                    ""
                },
            );
            d.pair(72, 65);
            d.pair(73, 0);
            d.pair(40, 0.0);
        });
        self.table("LAYER", &["0"], |d, name| {
            d.pair(100, "AcDbLayerTableRecord");
            d.pair(2, name);
            d.pair(70, 0);
            d.pair(62, 7);
            d.pair(6, "Continuous");
        });
        self.table("STYLE", &["Standard"], |d, name| {
            d.pair(100, "AcDbTextStyleTableRecord");
            d.pair(2, name);
            d.pair(70, 0);
            d.pair(40, 0.0);
            d.pair(41, 1.0);
            d.pair(50, 0.0);
            d.pair(71, 0);
            d.pair(42, 2.5);
            d.pair(3, "txt");
            d.pair(4, "");
        });
        self.table("VIEW", &[], |_, _| {});
        self.table("UCS", &[], |_, _| {});
        self.table("APPID", &["ACAD"], |d, name| {
            d.pair(100, "AcDbRegAppTableRecord");
            d.pair(2, name);
            d.pair(70, 0);
        });
        self.table("DIMSTYLE", &["Standard"], |d, name| {
            d.pair(100, "AcDbDimStyleTableRecord");
            d.pair(2, name);
            d.pair(70, 0);
        });
    }

    /// The BLOCKS section: the two layout blocks, owned by the block
    /// records `model` and `paper`, empty.
    fn blocks(&mut self, model: &str, paper: &str) {
        // BLOCKS: the two layout blocks, empty (model space's entities are in
        // ENTITIES).
        self.pair(0, "SECTION");
        self.pair(2, "BLOCKS");
        for (name, owner) in [("*Model_Space", model), ("*Paper_Space", paper)] {
            let (block, end) = (self.handle(), self.handle());
            self.pair(0, "BLOCK");
            self.pair(5, &block);
            self.pair(330, owner);
            self.pair(100, "AcDbEntity");
            self.pair(8, "0");
            self.pair(100, "AcDbBlockBegin");
            self.pair(2, name);
            self.pair(70, 0);
            for code in [10, 20, 30] {
                self.pair(code, 0.0);
            }
            self.pair(3, name);
            self.pair(1, "");
            self.pair(0, "ENDBLK");
            self.pair(5, &end);
            self.pair(330, owner);
            self.pair(100, "AcDbEntity");
            self.pair(8, "0");
            self.pair(100, "AcDbBlockEnd");
        }
        self.pair(0, "ENDSEC");
    }

    /// The HEADER and CLASSES sections, with the handle seed `handseed`.
    fn header(&mut self, handseed: u64) {
        self.pair(
            999,
            "metabezier fit: every segment one SPLINE, exact (control points and weights)",
        );
        self.pair(0, "SECTION");
        self.pair(2, "HEADER");
        self.pair(9, "$ACADVER");
        self.pair(1, "AC1015");
        self.pair(9, "$HANDSEED");
        self.pair(5, format!("{:X}", handseed));
        self.pair(9, "$INSUNITS");
        self.pair(70, 0);
        self.pair(0, "ENDSEC");
        self.pair(0, "SECTION");
        self.pair(2, "CLASSES");
        self.pair(0, "ENDSEC");
    }
}

/// The DXF R2000 document of `fit`: one `SPLINE` per segment on layer `0`
/// of model space, in contour order.
pub fn shape_dxf(fit: &ShapeFit) -> String {
    let mut d = Dxf {
        text: String::new(),
        next_handle: 0,
    };
    // Handles fixed in advance: the block records, which entities and
    // blocks point to.
    let (model_record, paper_record) = ("1F".to_owned(), "1E".to_owned());
    let mut body = Dxf {
        text: String::new(),
        next_handle: 0x100,
    };
    body.tables(&model_record, &paper_record);
    body.blocks(&model_record, &paper_record);
    // ENTITIES: one SPLINE per segment.
    body.pair(0, "SECTION");
    body.pair(2, "ENTITIES");
    for c in &fit.contours {
        for s in &c.fit.segments {
            spline(&mut body, &s.segment, &model_record);
        }
    }
    body.pair(0, "ENDSEC");
    // OBJECTS: the root dictionary and its ACAD_GROUP dictionary.
    let (root, groups) = (body.handle(), body.handle());
    body.pair(0, "SECTION");
    body.pair(2, "OBJECTS");
    body.dictionary(&root, "0", &[("ACAD_GROUP", &groups)]);
    body.dictionary(&groups, &root, &[]);
    body.pair(0, "ENDSEC");
    body.pair(0, "EOF");
    // HEADER last, once the handle seed is known.
    d.header(body.next_handle);
    d.text.push_str(&body.text);
    d.text
}

/// One segment as a `SPLINE`: degree `m`, the clamped knots
/// `[0^(m+1), 1^(m+1)]`, the `m + 1` control points, and the weights when
/// the segment is rational (flags: 8 planar, 4 rational).
fn spline(d: &mut Dxf, segment: &Segment, owner: &str) {
    let points = segment.control_points();
    let weights = segment.weights();
    let rational = segment.function().is_rational();
    let m = points.len() - 1;
    let h = d.handle();
    d.pair(0, "SPLINE");
    d.pair(5, &h);
    d.pair(330, owner);
    d.pair(100, "AcDbEntity");
    d.pair(8, "0");
    d.pair(100, "AcDbSpline");
    for (code, v) in [(210, 0.0), (220, 0.0), (230, 1.0)] {
        d.pair(code, v);
    }
    d.pair(70, if rational { 8 + 4 } else { 8 });
    d.pair(71, m);
    d.pair(72, 2 * (m + 1));
    d.pair(73, m + 1);
    d.pair(74, 0);
    for k in 0..2 * (m + 1) {
        d.pair(40, if k <= m { 0.0 } else { 1.0 });
    }
    if rational {
        for w in &weights {
            d.pair(41, w);
        }
    }
    for p in &points {
        d.pair(10, p.x);
        d.pair(20, p.y);
        d.pair(30, 0.0);
    }
    debug_assert_eq!(points[0], segment.start());
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The `(code, value)` pairs of a DXF text.
    fn pairs(text: &str) -> Vec<(u32, &str)> {
        let lines: Vec<&str> = text.lines().collect();
        lines
            .chunks_exact(2)
            .map(|c| (c[0].trim().parse().expect("a group code"), c[1]))
            .collect()
    }

    #[test]
    fn every_segment_is_a_spline_with_its_exact_control_points_and_weights() {
        use crate::fit::{FitOptions, FunctionType};
        use crate::geometry::{Continuity, Point, RationalQuadBez};
        use crate::reconstruction::{Method, Reconstruction, Segmentation, Source};
        let mut pts = Vec::new();
        for k in 0..4 {
            let arc = RationalQuadBez::circular_arc(
                Point::new(3.0, 4.0),
                2.5,
                k as f64 * std::f64::consts::FRAC_PI_2,
                std::f64::consts::FRAC_PI_2,
            )
            .unwrap();
            pts.extend((0..25).map(|j| arc.eval(j as f64 / 25.0)));
        }
        let outline =
            crate::outline::outline_from_points(pts, Some(true), 4, std::path::Path::new("circle"))
                .unwrap();
        let source = Source::from_outline("circle", outline);
        let r = Reconstruction {
            source: &source,
            segmentation: Segmentation::Count(4),
            corners: None,
            options: FitOptions::new(FunctionType::RationalCubic, Continuity::G1),
        };
        let fit = r.fit(&Method::Exact, 1).unwrap();
        let text = shape_dxf(&fit);
        let p = pairs(&text);
        assert_eq!(p.last(), Some(&(0, "EOF")));
        let splines: Vec<usize> = (0..p.len()).filter(|&i| p[i] == (0, "SPLINE")).collect();
        assert_eq!(splines.len(), 4);
        // The first spline's groups read back to the segment exactly.
        let seg = &fit.contours[0].fit.segments[0].segment;
        let body = &p[splines[0]..splines.get(1).copied().unwrap_or(p.len())];
        let values = |code: u32| -> Vec<f64> {
            body.iter()
                .filter(|(c, _)| *c == code)
                .map(|(_, v)| v.parse().unwrap())
                .collect()
        };
        let xs: Vec<f64> = seg.control_points().iter().map(|q| q.x).collect();
        let ys: Vec<f64> = seg.control_points().iter().map(|q| q.y).collect();
        assert_eq!(values(10), xs);
        assert_eq!(values(20), ys);
        assert_eq!(values(41), seg.weights());
        assert_eq!(values(40), [0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0]);
        assert_eq!(values(70), [12.0]);
        // Handles are unique.
        let mut handles: Vec<&str> = p.iter().filter(|(c, _)| *c == 5).map(|(_, v)| *v).collect();
        let n = handles.len();
        handles.sort();
        handles.dedup();
        assert_eq!(handles.len(), n);
    }
}
