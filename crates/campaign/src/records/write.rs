//! The writers of the result files.

use std::io::{self, Write};
use std::path::Path;

use super::schema::*;
use super::*;
use crate::files::{fmt_real, write_atomic_with, IoError};
use crate::segments::{FIT_SEGMENT_HEADER, SEGMENT_HEADER};
use crate::spec::Spec;

/// The bytes of `hits.csv`: one row per run and target reached, with the
/// first evaluation at which it was reached.
pub fn hits_csv(records: &[RunRecord]) -> Vec<u8> {
    in_memory(|w| write_hits(w, Schema::of(records), records))
}

/// Streams `hits.csv` of `records` under `schema` into `w`.
pub fn write_hits(w: impl Write, schema: Schema, records: &[RunRecord]) -> io::Result<()> {
    let rows = records.iter().flat_map(|r| {
        let key = schema.key_fields(r);
        r.hits.iter().map(move |h| {
            let mut row = key.clone();
            row.extend([fmt_real(h.precision), h.evaluations.to_string()]);
            row
        })
    });
    write_csv(w, &schema.keyed_header(&HITS_FIELDS), rows)
}

/// The columns of `hits.csv` after the run key.
pub(crate) const HITS_FIELDS: [&str; 2] = ["target", "evaluations"];

/// The bytes of `fits.csv`: one row per fitting run with its RMS, maximum
/// orthogonal distance and closing-joint mismatch (`E` and evaluations are
/// in `runs.csv`).
pub fn fits_csv(records: &[RunRecord]) -> Vec<u8> {
    in_memory(|w| write_fits(w, Schema::of(records), records))
}

/// Streams `fits.csv` of `records` under `schema` into `w`.
pub fn write_fits(w: impl Write, schema: Schema, records: &[RunRecord]) -> io::Result<()> {
    let rest: &[&'static str] = if current_fit_records(records) {
        &FIT_FIELDS_CURRENT
    } else {
        &FIT_FIELDS
    };
    let rows = records.iter().filter_map(|r| {
        r.fit.as_ref().map(|f| {
            let mut row = schema.key_fields(r);
            row.extend(f.fields());
            row
        })
    });
    write_csv(w, &schema.keyed_header(rest), rows)
}

/// The bytes of `segments.csv`: one row per segment of every fitting run,
/// with its control points, weights and metrics (and its contour and
/// orthogonal RMS with the current fitting records).
pub fn segments_csv(records: &[RunRecord]) -> Vec<u8> {
    in_memory(|w| write_segments(w, Schema::of(records), records))
}

/// Streams `segments.csv` of `records` under `schema` into `w`.
pub fn write_segments(w: impl Write, schema: Schema, records: &[RunRecord]) -> io::Result<()> {
    let rest: &[&'static str] = if current_fit_records(records) {
        &FIT_SEGMENT_HEADER
    } else {
        &SEGMENT_HEADER
    };
    let rows = records.iter().flat_map(|r| {
        let key = schema.key_fields(r);
        r.fit.iter().flat_map(move |f| {
            let key = key.clone();
            f.segments.iter().map(move |seg| {
                let mut row = key.clone();
                row.extend(seg.iter().cloned());
                row
            })
        })
    });
    write_csv(w, &schema.keyed_header(rest), rows)
}

/// The bytes of `runs.csv` for records in their final order.
pub fn runs_csv(records: &[RunRecord]) -> Vec<u8> {
    in_memory(|w| write_runs(w, Schema::of(records), records))
}

/// Streams `runs.csv` of `records` (in their final order) under `schema`
/// into `w`.
pub fn write_runs(w: impl Write, schema: Schema, records: &[RunRecord]) -> io::Result<()> {
    write_csv(
        w,
        &schema.runs_header(),
        records.iter().map(|r| runs_row(schema, r)),
    )
}

/// The bytes of `convergence.csv` for records in their final order;
/// `optimum` gives `f*` of a record so the error column can be filled.
pub fn convergence_csv(records: &[RunRecord], optimum: impl Fn(&RunRecord) -> f64) -> Vec<u8> {
    in_memory(|w| write_convergence(w, Schema::of(records), records, &optimum))
}

/// Streams `convergence.csv` of `records` under `schema` into `w`;
/// `optimum` gives `f*` of a record.
pub fn write_convergence(
    w: impl Write,
    schema: Schema,
    records: &[RunRecord],
    optimum: impl Fn(&RunRecord) -> f64,
) -> io::Result<()> {
    let rows = records.iter().flat_map(|r| {
        let f_star = optimum(r);
        let key = schema.key_fields(r);
        r.trace.iter().map(move |p| {
            let mut row = key.clone();
            row.extend([
                p.evaluations.to_string(),
                fmt_real(p.best),
                fmt_real(p.best - f_star),
            ]);
            row
        })
    });
    write_csv(w, &schema.keyed_header(&CONVERGENCE_FIELDS), rows)
}

/// The bytes of `timing.csv`.
pub fn timing_csv(records: &[RunRecord]) -> Vec<u8> {
    in_memory(|w| write_timing(w, Schema::of(records), records))
}

/// Streams `timing.csv` of `records` under `schema` into `w`.
pub fn write_timing(w: impl Write, schema: Schema, records: &[RunRecord]) -> io::Result<()> {
    let rows = records.iter().map(|r| {
        let mut row = schema.key_fields(r);
        row.push(fmt_real(r.wall_seconds));
        row
    });
    write_csv(w, &schema.keyed_header(&TIMING_FIELDS), rows)
}

/// Streams a CSV file, a header then rows, into `w` exactly as
/// [`crate::files::csv_bytes`] writes it to memory.
pub(crate) fn write_csv<W, H, R, I>(w: W, header: &[H], rows: I) -> io::Result<()>
where
    W: Write,
    H: AsRef<[u8]>,
    R: IntoIterator,
    R::Item: AsRef<[u8]>,
    I: IntoIterator<Item = R>,
{
    let mut w = csv::WriterBuilder::new().flexible(true).from_writer(w);
    w.write_record(header)?;
    for row in rows {
        w.write_record(row)?;
    }
    w.flush()
}

/// The bytes that `write` streams, in memory.
pub(crate) fn in_memory(write: impl FnOnce(&mut Vec<u8>) -> io::Result<()>) -> Vec<u8> {
    let mut bytes = Vec::new();
    write(&mut bytes).expect("writing to memory cannot fail");
    bytes
}

/// Writes the result files of `records`, complete and in their final order,
/// into `out`: `runs.csv`, `convergence.csv`, `timing.csv`, `hits.csv` when
/// `hits` (the campaign has benchmark problems) and, when some run is a fit,
/// `fits.csv` and `segments.csv`. Each file is streamed to its temporary
/// file and renamed into place, so no file's text is ever held in memory
/// whole; `optimum` gives `f*` of a record.
pub(crate) fn write_files(
    spec: &Spec,
    out: &Path,
    records: &[RunRecord],
    optimum: impl Fn(&RunRecord) -> f64,
    hits: bool,
) -> Result<(), IoError> {
    let schema = Schema::of_spec(spec);
    debug_assert_eq!(schema, Schema::of(records));
    let stream = |name: &str, write: &dyn Fn(&mut std::fs::File) -> io::Result<()>| {
        write_atomic_with(&out.join(name), |f| write(f))
    };
    stream("runs.csv", &|f| write_runs(f, schema, records))?;
    stream("convergence.csv", &|f| {
        write_convergence(f, schema, records, &optimum)
    })?;
    stream("timing.csv", &|f| write_timing(f, schema, records))?;
    if hits {
        stream("hits.csv", &|f| write_hits(f, schema, records))?;
    }
    if records.iter().any(|r| r.fit.is_some()) {
        stream("fits.csv", &|f| write_fits(f, schema, records))?;
        stream("segments.csv", &|f| write_segments(f, schema, records))?;
    }
    Ok(())
}
