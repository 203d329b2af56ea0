//! The readers of the result files, checked line by line.

use std::collections::HashMap;
use std::path::Path;

use super::*;
use super::{data::*, schema::*, write::*};
use crate::functions::Transform;
use crate::reading::{open_csv, CsvFile, RESULT_LIMITS, RUNS_LIMITS};
use crate::segments::{FIT_SEGMENT_HEADER, SEGMENT_HEADER};

/// Parses a transform name.
pub(crate) fn parse_transform(path: &Path, line: u64, text: &str) -> Result<Transform, ReadError> {
    Transform::from_name(text).ok_or_else(|| {
        data(
            path,
            line,
            DataProblem::Cell {
                column: "transform".to_owned(),
                text: text.to_owned(),
            },
        )
    })
}

/// A record from the fields of a `runs.csv` row in the layout of
/// [`run_fields`] (no transform and instance columns).
pub(crate) fn record_from_fields(
    path: &Path,
    line: u64,
    f: &csv::StringRecord,
) -> Result<RunRecord, ReadError> {
    let fields: Vec<&str> = f.iter().collect();
    record_from(path, line, &fields)
}

pub(crate) fn record_from(path: &Path, line: u64, f: &[&str]) -> Result<RunRecord, ReadError> {
    if f.len() < RUNS_HEADER.len() {
        return Err(data(
            path,
            line,
            DataProblem::TooFewColumns {
                expected: RUNS_HEADER.len(),
                found: f.len(),
            },
        ));
    }
    let get = |i: usize| f.get(i).copied().unwrap_or("");
    let success = match get(12) {
        "true" => true,
        "false" => false,
        other => return Err(data(path, line, DataProblem::Success(other.to_owned()))),
    };
    Ok(RunRecord {
        algorithm: get(0).to_owned(),
        kind: get(1).to_owned(),
        params: get(2).to_owned(),
        problem: get(3).to_owned(),
        dim: parse(path, line, "dim", get(4))?,
        budget: parse(path, line, "budget", get(5))?,
        transform: Transform::None,
        instance: 1,
        run: parse(path, line, "run", get(6))?,
        seed: parse(path, line, "seed", get(7))?,
        best: parse(path, line, "best", get(8))?,
        error: parse(path, line, "error", get(9))?,
        evaluations: parse(path, line, "evaluations", get(10))?,
        evaluations_to_target: match get(11) {
            "" => None,
            t => Some(parse(path, line, "evaluations_to_target", t)?),
        },
        success,
        trace: Vec::new(),
        hits: Vec::new(),
        fit: None,
        wall_seconds: 0.0,
    })
}

/// The header of `reader`, checked by `schema_of` (which gives the schema
/// the header belongs to); `expected` names the legacy layout in the error,
/// which says how many columns the first line has but never quotes it.
pub(crate) fn read_header(
    path: &Path,
    reader: &mut CsvFile,
    expected: &[&str],
    schema_of: impl Fn(&[&str]) -> Option<Schema>,
) -> Result<Schema, ReadError> {
    let header = reader
        .headers()
        .map_err(|e| data(path, 1, DataProblem::Csv(e)))?;
    let found: Vec<&str> = header.iter().collect();
    schema_of(&found).ok_or_else(|| {
        data(
            path,
            1,
            DataProblem::Header {
                expected: expected.iter().map(|c| c.to_string()).collect(),
                found: found.len(),
            },
        )
    })
}

/// Whether the header line of the CSV file at `path` has the column `name`.
pub(crate) fn header_has(path: &Path, name: &str) -> Result<bool, ReadError> {
    let mut reader = open_csv(path, RESULT_LIMITS, true)?;
    let header = reader
        .headers()
        .map_err(|e| data(path, 1, DataProblem::Csv(e)))?;
    Ok(header.iter().any(|h| h == name))
}

/// Reads `runs.csv` alone (traces empty, wall time 0): the input of reports,
/// which may also come from outside this tool.
pub fn read_runs(path: &Path) -> Result<Vec<RunRecord>, ReadError> {
    read_runs_with(path, false)
}

/// Reads `runs.csv`; `strict` (the file of a campaign of this tool, which
/// never writes a NaN objective) refuses a NaN `best` or `error`.
pub(crate) fn read_runs_with(path: &Path, strict: bool) -> Result<Vec<RunRecord>, ReadError> {
    let mut reader = open_csv(path, RUNS_LIMITS, true)?;
    let schema = read_header(path, &mut reader, &RUNS_HEADER, Schema::from_runs_header)?;
    let mut out = Vec::new();
    let mut row = csv::StringRecord::new();
    loop {
        let line = reader.position().line();
        match reader.read_record(&mut row) {
            Ok(true) => {}
            Ok(false) => break,
            Err(e) => return Err(data(path, line, DataProblem::Csv(e))),
        }
        let line = row.position().map_or(line, |p| p.line());
        let mut fields: Vec<&str> = row.iter().collect();
        let factors = if schema.instances && fields.len() >= RUNS_HEADER.len() + 2 {
            let f: Vec<&str> = fields.drain(6..8).collect();
            Some((f[0], f[1]))
        } else {
            None
        };
        let mut rec = record_from(path, line, &fields)?;
        if strict {
            parse_real(path, line, "best", fields[8], Real::NotNan)?;
            parse_real(path, line, "error", fields[9], Real::NotNan)?;
        }
        if let Some((t, k)) = factors {
            rec.transform = parse_transform(path, line, t)?;
            rec.instance = parse(path, line, "instance", k)?;
        }
        out.push(rec);
    }
    Ok(out)
}

/// The run keys of a keyed file under `schema`, mapped to their records.
struct KeyIndex {
    schema: Schema,
    index: HashMap<(String, String, Option<u64>, u32), usize>,
}

impl KeyIndex {
    fn new(schema: Schema, records: &[RunRecord]) -> KeyIndex {
        let index = records
            .iter()
            .enumerate()
            .map(|(i, r)| {
                let budget = schema.keyed_budget.then_some(r.budget);
                ((r.cell_key(), r.match_key(), budget, r.run), i)
            })
            .collect();
        KeyIndex { schema, index }
    }

    /// The record a keyed row belongs to.
    fn lookup(&self, path: &Path, line: u64, row: &csv::StringRecord) -> Result<usize, ReadError> {
        let mut col = 5;
        let budget = if self.schema.keyed_budget {
            col += 1;
            Some(parse(path, line, "budget", &row[5])?)
        } else {
            None
        };
        let (transform, instance) = if self.schema.instances {
            col += 2;
            (
                parse_transform(path, line, &row[col - 2])?,
                parse(path, line, "instance", &row[col - 1])?,
            )
        } else {
            (Transform::None, 1)
        };
        let run: u32 = parse(path, line, "run", &row[col])?;
        let key = (
            format!("{}:{}[{}]", &row[0], &row[1], &row[2]),
            format!(
                "{}-{}{}",
                &row[3],
                &row[4],
                factor_suffix(transform, instance, true, true)
            ),
            budget,
            run,
        );
        self.index
            .get(&key)
            .copied()
            .ok_or_else(|| data(path, line, DataProblem::UnknownRun))
    }
}

/// Reads the rows of a keyed CSV file whose columns after the run key are
/// `rest`, checking the header and every row's column count, and hands each
/// record index, its fields after the key and its line number to `row`.
pub(crate) fn read_keyed(
    path: &Path,
    rest: &[&'static str],
    records: &[RunRecord],
    mut row: impl FnMut(usize, &[&str], u64) -> Result<(), ReadError>,
) -> Result<(), ReadError> {
    let mut reader = open_csv(path, RESULT_LIMITS, true)?;
    let legacy = Schema::default().keyed_header(rest);
    let schema = read_header(path, &mut reader, &legacy, |h| {
        Schema::from_keyed_header(h, rest)
    })?;
    let index = KeyIndex::new(schema, records);
    let width = schema.key_len() + rest.len();
    let mut r = csv::StringRecord::new();
    loop {
        let line = reader.position().line();
        match reader.read_record(&mut r) {
            Ok(true) => {}
            Ok(false) => break,
            Err(e) => return Err(data(path, line, DataProblem::Csv(e))),
        }
        let line = r.position().map_or(line, |p| p.line());
        if r.len() != width {
            return Err(data(path, line, DataProblem::WrongColumnCount));
        }
        let k = index.lookup(path, line, &r)?;
        let fields: Vec<&str> = r.iter().skip(schema.key_len()).collect();
        row(k, &fields, line)?;
    }
    Ok(())
}

/// Reads a finished campaign directory's `runs.csv`, `convergence.csv`,
/// `timing.csv` and, when present, `hits.csv`, `fits.csv` and
/// `segments.csv` back into complete records.
pub fn read_results(dir: &Path) -> Result<Vec<RunRecord>, ReadError> {
    let mut records = read_runs_with(&dir.join("runs.csv"), true)?;
    let mut traces: Vec<Vec<TracePoint>> = vec![Vec::new(); records.len()];
    let path = dir.join("convergence.csv");
    read_keyed(&path, &CONVERGENCE_FIELDS, &records, |k, f, line| {
        let point = TracePoint {
            evaluations: parse(&path, line, "evaluations", f[0])?,
            best: parse_real(&path, line, "best", f[1], Real::NotNan)?,
        };
        parse_real(&path, line, "error", f[2], Real::NotNan)?;
        // Each run's checkpoints rise strictly: a row repeated or out of
        // order is not a trace this tool wrote.
        if traces[k]
            .last()
            .is_some_and(|p| p.evaluations >= point.evaluations)
        {
            return Err(data(&path, line, DataProblem::Order("evaluations", "rise")));
        }
        traces[k].push(point);
        Ok(())
    })?;
    let mut walls: Vec<Option<f64>> = vec![None; records.len()];
    let path = dir.join("timing.csv");
    read_keyed(&path, &TIMING_FIELDS, &records, |k, f, line| {
        let wall = parse_real(&path, line, "wall_seconds", f[0], Real::NonNegative)?;
        if walls[k].replace(wall).is_some() {
            return Err(data(&path, line, DataProblem::RepeatedRun));
        }
        Ok(())
    })?;
    if let Some(k) = walls.iter().position(Option::is_none) {
        return Err(data(&path, 0, DataProblem::NoRowFor(records[k].describe())));
    }
    let walls = walls.into_iter().map(|w| w.unwrap_or(0.0));
    let mut hits: Vec<Vec<TargetHit>> = vec![Vec::new(); records.len()];
    let path = dir.join("hits.csv");
    if path.exists() {
        read_keyed(&path, &HITS_FIELDS, &records, |k, f, line| {
            let hit = TargetHit {
                precision: parse_real(&path, line, "target", f[0], Real::Positive)?,
                evaluations: parse(&path, line, "evaluations", f[1])?,
            };
            // Each run reaches its targets from the largest down.
            if hits[k].last().is_some_and(|h| h.precision <= hit.precision) {
                return Err(data(&path, line, DataProblem::Order("target", "fall")));
            }
            hits[k].push(hit);
            Ok(())
        })?;
    }
    let mut fits: Vec<Option<FitDetail>> = vec![None; records.len()];
    if dir.join("fits.csv").exists() {
        let path = dir.join("fits.csv");
        let current = header_has(&path, "rms_distance")?;
        let two_sided = header_has(&path, "hausdorff")?;
        let (fit_rest, segment_rest): (&[&'static str], &[&'static str]) =
            match (current, two_sided) {
                (true, true) => (&FIT_FIELDS_CURRENT, &FIT_SEGMENT_HEADER),
                (true, false) => (&FIT_FIELDS_RMS, &FIT_SEGMENT_HEADER),
                _ => (&FIT_FIELDS, &SEGMENT_HEADER),
            };
        read_keyed(&path, fit_rest, &records, |k, f, line| {
            if fits[k]
                .replace(FitDetail::from_fields(&path, line, f)?)
                .is_some()
            {
                return Err(data(&path, line, DataProblem::RepeatedRun));
            }
            Ok(())
        })?;
        // Every fitting run (its problem is source/function/continuity)
        // has its row.
        if let Some(k) =
            (0..records.len()).find(|&k| fits[k].is_none() && records[k].problem.contains('/'))
        {
            return Err(data(&path, 0, DataProblem::NoRowFor(records[k].describe())));
        }
        let path = dir.join("segments.csv");
        read_keyed(&path, segment_rest, &records, |k, f, line| {
            let fit = fits[k]
                .as_mut()
                .ok_or_else(|| data(&path, line, DataProblem::NoFitRow))?;
            fit.segments.push(f.iter().map(|c| c.to_string()).collect());
            Ok(())
        })?;
    }
    for ((((r, t), w), h), f) in records
        .iter_mut()
        .zip(traces)
        .zip(walls)
        .zip(hits)
        .zip(fits)
    {
        r.trace = t;
        r.wall_seconds = w;
        r.hits = h;
        r.fit = f;
    }
    Ok(records)
}
