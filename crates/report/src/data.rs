//! The report's view of a results directory: the runs grouped by cell
//! (algorithm label, kind, parameters) and problem (function, dimension),
//! plus the provenance read from `spec.toml` and `meta.toml`.

use std::collections::BTreeMap;
use std::path::Path;

use super::ReportError;
use crate::experiment::records::{read_results, read_runs, RunRecord, Schema};
use crate::experiment::spec::factor_suffix;
use crate::experiment::{DataError, DataProblem};
use crate::files::{read_text_limited, MAX_TEXT_BYTES};
use crate::functions::Transform;

/// One run, reduced to what the report uses.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Run {
    /// The run number, from 0 (for pooled bbob instances, see
    /// [`BBOB_RUN_STRIDE`]).
    pub run: u32,
    /// The run's derived seed: two runs share their random numbers (and so
    /// are paired) only when their seeds are equal.
    pub seed: u64,
    /// The run's evaluation budget.
    pub budget: u64,
    /// Final error `f − f*`.
    pub error: f64,
    /// Evaluations used.
    pub evaluations: u64,
    /// First evaluation count at which the threshold was reached.
    pub evaluations_to_target: Option<u64>,
    /// Whether the threshold was reached.
    pub success: bool,
    /// Best-so-far error `f − f*` at the convergence checkpoints.
    pub trace: Vec<(u64, f64)>,
    /// (target precision Δf, first evaluation with `f − f* ≤ Δf`) of every
    /// target reached (`hits.csv`).
    pub hits: Vec<(f64, u64)>,
    /// Wall time of the run, when `timing.csv` was read.
    pub wall_seconds: Option<f64>,
}

/// An algorithm cell: a label with one parameter setting.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Cell {
    /// The `algorithm` column.
    pub label: String,
    /// The optimiser (`kind` column).
    pub kind: String,
    /// The canonical parameter text.
    pub params: String,
    /// The name shown in tables and plots: the label, followed by the
    /// parameters that distinguish it when several cells share the label.
    pub name: String,
    /// Whether the cell comes from the external `runs.csv`.
    pub external: bool,
}

/// A problem: a benchmark function at a dimension (with its transform and
/// instance, and its budget when the results hold several budgets of one
/// problem), or a fitting case.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) struct Problem {
    /// The function's name (for a fitting case `source/function/continuity`,
    /// with `/bounding-box` for the naive search space).
    pub function: String,
    /// The dimension D (for a fitting case its number of segments).
    pub dim: usize,
    /// The budget, when it is a design factor of the results.
    pub budget: Option<u64>,
    /// The benchmark transform (`none` when untransformed).
    pub transform: Transform,
    /// The benchmark instance (1 when untransformed).
    pub instance: u32,
}

impl Problem {
    /// `sphere, D = 10`; for a fitting problem (`source/function/continuity`)
    /// `horse/cubic/g1, 30 segments`; a transformed instance adds
    /// `, shift-rotate #2` and a budget grid `, budget 1000`.
    pub fn title(&self) -> String {
        let mut t = if self.is_fit() {
            format!("{}, {} segments", self.function, self.dim)
        } else {
            format!("{}, D = {}", self.function, self.dim)
        };
        t.push_str(&self.short()[self.function.len()..]);
        t
    }

    /// The problem's name in CSV tables: the function (or fitting case),
    /// followed by `|budget=`, `|transform=` and `|instance=` parts for the
    /// factors that are not at their default, as in the spec's problem keys.
    pub fn label(&self) -> String {
        let mut s = self.function.clone();
        if let Some(b) = self.budget {
            s.push_str(&format!("|budget={b}"));
        }
        s.push_str(&factor_suffix(self.transform, self.instance, true, true));
        s
    }

    /// The problem's name in Markdown tables: the function (or fitting
    /// case), then `, shift-rotate #2` and `, budget 1000` when those
    /// factors are not at their default.
    pub fn short(&self) -> String {
        let mut s = self.function.clone();
        if self.transform != Transform::None {
            s.push_str(&format!(", {} #{}", self.transform, self.instance));
        }
        if let Some(b) = self.budget {
            s.push_str(&format!(", budget {b}"));
        }
        s
    }

    /// [`Problem::short`] without the dimension a COCO bbob id carries
    /// (`bbob_f008_d05` → `bbob_f008`), so that one function's dimensions
    /// group together (scalability).
    pub fn across_dimensions(&self) -> String {
        let short = self.short();
        let Some(rest) = self.function.strip_prefix("bbob_f") else {
            return short;
        };
        match rest.rsplit_once("_d") {
            Some((f, d)) if !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()) => {
                short.replacen(&self.function, &format!("bbob_f{f}"), 1)
            }
            _ => short,
        }
    }

    /// Whether this is a fitting case (its name has `/` parts).
    pub fn is_fit(&self) -> bool {
        self.function.contains('/')
    }
}

/// Run numbers of pooled bbob instances: instance k's run r is
/// `(k − 1)·BBOB_RUN_STRIDE + r`, the same for every algorithm, so paired
/// tests pair the same instance and run.
pub(crate) const BBOB_RUN_STRIDE: u32 = 100_000;

/// The pooled name of a COCO bbob id: `bbob_f008_i02_d05` → `bbob_f008_d05`.
fn bbob_pooled(id: &str) -> Option<String> {
    let rest = id.strip_prefix("bbob_f")?;
    let (f, rest) = rest.split_once("_i")?;
    let (_, d) = rest.split_once("_d")?;
    Some(format!("bbob_f{f}_d{d}"))
}

/// All runs of a report, indexed by problem and cell.
#[derive(Clone, Debug)]
pub(crate) struct Dataset {
    /// Cells in order of first appearance (results first, external after).
    pub cells: Vec<Cell>,
    /// Problems in order of first appearance.
    pub problems: Vec<Problem>,
    /// `runs[problem][cell]`, sorted by run number (empty when the cell did
    /// not run the problem).
    runs: Vec<Vec<Vec<Run>>>,
    /// Whether `convergence.csv` was read (some run has a trace).
    pub has_convergence: bool,
    /// Whether `timing.csv` was read.
    pub has_timing: bool,
    /// Whether `hits.csv` was read, so that the runs of the results (not
    /// the external ones) carry every target they reached.
    pub has_hits: bool,
    /// Whether the external runs came with their results directory's
    /// convergence and hits, so that they carry every target they reached.
    pub external_anytime: bool,
    /// Number of runs read.
    pub total_runs: usize,
    /// Remarks about the input, shown in the report.
    pub notes: Vec<String>,
    /// The comparison families of the cells' optimisers
    /// ([`crate::ReportOptions::families`]).
    pub families: crate::families::Families,
}

impl Dataset {
    /// Whether every problem is a curve fit (a `[[fit]]` case): its error
    /// is the fitting error E and its dimension the number of segments.
    pub fn fitting_only(&self) -> bool {
        !self.problems.is_empty() && self.problems.iter().all(Problem::is_fit)
    }

    /// The name of the final error in the reader's vocabulary: `E` (the
    /// fitting error Σ|R_i − P_i|²) for a fitting campaign, `f − f*`
    /// otherwise.
    pub fn error_symbol(&self) -> &'static str {
        if self.fitting_only() {
            "E"
        } else {
            "f − f*"
        }
    }
}

impl Dataset {
    /// The runs of `cell` on `problem`, sorted by run number.
    pub fn runs(&self, problem: usize, cell: usize) -> &[Run] {
        self.runs
            .get(problem)
            .and_then(|p| p.get(cell))
            .map_or(&[], |v| v.as_slice())
    }

    /// The final errors of `cell` on `problem`, in run order.
    pub fn errors(&self, problem: usize, cell: usize) -> Vec<f64> {
        self.runs(problem, cell).iter().map(|r| r.error).collect()
    }

    /// Builds a dataset from records; `external` marks records from the
    /// external file (their labels are already disambiguated).
    pub fn from_records(records: Vec<(RunRecord, bool)>) -> Dataset {
        let mut cell_index: BTreeMap<(String, String, String), usize> = BTreeMap::new();
        let mut cells: Vec<Cell> = Vec::new();
        let mut problem_index: BTreeMap<Problem, usize> = BTreeMap::new();
        let mut problems: Vec<Problem> = Vec::new();
        let mut grouped: BTreeMap<(usize, usize), BTreeMap<u32, Run>> = BTreeMap::new();
        let mut duplicates = 0usize;
        let mut has_convergence = false;
        let total_runs = records.len();
        let budget_factor = Schema::of(records.iter().map(|(r, _)| r)).keyed_budget;
        for (r, external) in records {
            let key = (r.algorithm.clone(), r.kind.clone(), r.params.clone());
            let c = *cell_index.entry(key).or_insert_with(|| {
                cells.push(Cell {
                    label: r.algorithm.clone(),
                    kind: r.kind.clone(),
                    params: r.params.clone(),
                    name: String::new(),
                    external,
                });
                cells.len() - 1
            });
            // A bbob problem pools its instances, as COCO does: the
            // instances of bbob_f008_iKK_d05 are runs of bbob_f008_d05.
            let (function, instance, run_number) = match bbob_pooled(&r.problem) {
                Some(f) => (f, 1, (r.instance - 1) * BBOB_RUN_STRIDE + r.run),
                None => (r.problem.clone(), r.instance, r.run),
            };
            let problem = Problem {
                function,
                dim: r.dim,
                budget: budget_factor.then_some(r.budget),
                transform: r.transform,
                instance,
            };
            let p = *problem_index.entry(problem.clone()).or_insert_with(|| {
                problems.push(problem);
                problems.len() - 1
            });
            let f_star = r.best - r.error;
            let trace: Vec<(u64, f64)> = r
                .trace
                .iter()
                .map(|t| (t.evaluations, t.best - f_star))
                .collect();
            has_convergence |= !trace.is_empty();
            let run = Run {
                run: run_number,
                seed: r.seed,
                budget: r.budget,
                error: r.error,
                evaluations: r.evaluations,
                evaluations_to_target: r.evaluations_to_target,
                success: r.success,
                trace,
                hits: r
                    .hits
                    .iter()
                    .map(|h| (h.precision, h.evaluations))
                    .collect(),
                wall_seconds: Some(r.wall_seconds),
            };
            match grouped.entry((p, c)).or_default().entry(run_number) {
                std::collections::btree_map::Entry::Occupied(_) => duplicates += 1,
                std::collections::btree_map::Entry::Vacant(slot) => {
                    slot.insert(run);
                }
            }
        }
        let mut runs = vec![vec![Vec::new(); cells.len()]; problems.len()];
        for ((p, c), slot) in grouped {
            runs[p][c] = slot.into_values().collect();
        }
        name_cells(&mut cells);
        let mut notes = Vec::new();
        if duplicates > 0 {
            notes.push(format!(
                "{duplicates} row(s) repeat the run number of an earlier row of the same \
                 algorithm and problem; only the first of each was used."
            ));
        }
        Dataset {
            families: crate::families::Families::default(),
            cells,
            problems,
            runs,
            has_convergence,
            has_timing: false,
            has_hits: false,
            external_anytime: false,
            total_runs,
            notes,
        }
    }

    /// A dataset of `cells` over `problems` with the runs
    /// `runs[problem][cell]` (each sorted by run number), taking its flags
    /// (convergence, timing, hits) and families from `like`: the view of
    /// chosen cells of several campaigns side by side (`compare`).
    pub fn from_parts(
        cells: Vec<Cell>,
        problems: Vec<Problem>,
        runs: Vec<Vec<Vec<Run>>>,
        like: &Dataset,
    ) -> Dataset {
        let total_runs = runs.iter().flatten().map(Vec::len).sum();
        Dataset {
            cells,
            problems,
            runs,
            has_convergence: like.has_convergence,
            has_timing: like.has_timing,
            has_hits: like.has_hits,
            external_anytime: false,
            total_runs,
            notes: Vec::new(),
            families: like.families.clone(),
        }
    }

    /// Forgets the wall times (when `timing.csv` was not read, the records
    /// carry a placeholder 0).
    fn clear_timing(&mut self) {
        for p in &mut self.runs {
            for c in p {
                for r in c {
                    r.wall_seconds = None;
                }
            }
        }
    }

    /// Forgets the wall times of external cells.
    fn clear_external_timing(&mut self) {
        for p in &mut self.runs {
            for (c, runs) in p.iter_mut().enumerate() {
                if self.cells.get(c).is_some_and(|cell| cell.external) {
                    for r in runs {
                        r.wall_seconds = None;
                    }
                }
            }
        }
    }
}

/// Splits the canonical parameter text `a=1;b=2` into (name, value) pairs.
pub(crate) fn parse_params(params: &str) -> Vec<(String, String)> {
    params
        .split(';')
        .filter(|s| !s.is_empty())
        .map(|s| match s.split_once('=') {
            Some((k, v)) => (k.trim().to_owned(), v.trim().to_owned()),
            None => (s.trim().to_owned(), String::new()),
        })
        .collect()
}

/// The parameter names whose values differ among `cells` (in order of first
/// appearance).
pub(crate) fn varying_params(cells: &[&Cell]) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    let mut values: BTreeMap<String, Vec<Option<String>>> = BTreeMap::new();
    for (i, cell) in cells.iter().enumerate() {
        for (k, v) in parse_params(&cell.params) {
            if !values.contains_key(&k) {
                names.push(k.clone());
            }
            let entry = values.entry(k).or_insert_with(|| vec![None; cells.len()]);
            if let Some(slot) = entry.get_mut(i) {
                *slot = Some(v);
            }
        }
    }
    names
        .into_iter()
        .filter(|k| {
            values.get(k).is_some_and(|vs| {
                let first = &vs[0];
                vs.iter().any(|v| v != first)
            })
        })
        .collect()
}

/// The value of parameter `name` in a cell, if set.
pub(crate) fn param_value(cell: &Cell, name: &str) -> Option<String> {
    parse_params(&cell.params)
        .into_iter()
        .find(|(k, _)| k == name)
        .map(|(_, v)| v)
}

/// Gives every cell a unique display name: the label alone when it is the
/// only cell with that label, else the label with the varying parameters.
fn name_cells(cells: &mut [Cell]) {
    let mut by_label: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    for (i, c) in cells.iter().enumerate() {
        by_label.entry(c.label.clone()).or_default().push(i);
    }
    let mut names = vec![String::new(); cells.len()];
    for idx in by_label.values() {
        if idx.len() == 1 {
            names[idx[0]] = cells[idx[0]].label.clone();
            continue;
        }
        let group: Vec<&Cell> = idx.iter().map(|&i| &cells[i]).collect();
        let varying = varying_params(&group);
        for &i in idx {
            let c = &cells[i];
            let shown: Vec<String> = varying
                .iter()
                .map(|k| format!("{k}={}", param_value(c, k).unwrap_or_else(|| "-".into())))
                .collect();
            names[i] = if shown.is_empty() {
                format!("{} [{}]", c.label, c.kind)
            } else {
                format!("{} ({})", c.label, shown.join(", "))
            };
        }
    }
    // Any remaining clash (a label that looks like another's full name).
    let mut seen: BTreeMap<String, usize> = BTreeMap::new();
    for (i, name) in names.iter_mut().enumerate() {
        let n = seen.entry(name.clone()).or_insert(0);
        *n += 1;
        if *n > 1 {
            *name = format!("{name} #{}", *n);
        }
        cells[i].name = name.clone();
    }
}

/// Reads the runs of a results directory and of an optional external
/// `runs.csv`.
pub(crate) fn load(dir: &Path, external: Option<&Path>) -> Result<Dataset, ReportError> {
    let runs_path = dir.join("runs.csv");
    let campaign = is_campaign(dir);
    if campaign {
        require(dir, &["runs.csv", "convergence.csv", "timing.csv"])?;
    }
    let conv = dir.join("convergence.csv").is_file();
    let timing = dir.join("timing.csv").is_file();
    let mut notes = Vec::new();
    let records = if conv && timing {
        read_results(dir)?
    } else {
        let missing: Vec<&str> = [(conv, "convergence.csv"), (timing, "timing.csv")]
            .iter()
            .filter(|(present, _)| !present)
            .map(|(_, f)| *f)
            .collect();
        notes.push(format!(
            "{} not found in the results directory: only runs.csv was read, so the plots \
             that need it are skipped.",
            missing.join(" and ")
        ));
        read_runs(&runs_path)?
    };
    if records.is_empty() {
        return Err(DataError::new(&runs_path, 0, DataProblem::NoRuns).into());
    }
    if campaign {
        // What a finished campaign writes beside runs.csv for its kinds of
        // problem (fitting cases are named source/function/continuity).
        if records.iter().any(|r| !r.problem.contains('/')) {
            require(dir, &["hits.csv"])?;
        }
        if records.iter().any(|r| r.problem.contains('/')) {
            require(dir, &["fits.csv", "segments.csv", "outlines.csv"])?;
        }
    }
    notes.extend(super::integrity::check_rows(dir, &records)?);
    let internal_labels: std::collections::BTreeSet<String> =
        records.iter().map(|r| r.algorithm.clone()).collect();
    let mut all: Vec<(RunRecord, bool)> = records.into_iter().map(|r| (r, false)).collect();
    let mut external_anytime = false;
    if let Some(ext) = external {
        // A runs.csv inside another campaign's results directory brings its
        // convergence and target hits, so that its runs enter every plot.
        let ext_dir = ext
            .parent()
            .filter(|_| ext.file_name().is_some_and(|n| n == "runs.csv"))
            .filter(|d| {
                ["convergence.csv", "timing.csv", "hits.csv"]
                    .iter()
                    .all(|f| d.join(f).is_file())
            });
        external_anytime = ext_dir.is_some();
        let ext_records = match ext_dir {
            Some(d) => read_results(d)?,
            None => {
                notes.push(format!(
                    "The external runs ({}) come without convergence.csv, timing.csv and \
                     hits.csv beside them: they are in the tables, the final-error box plots \
                     and the runtime ECDF to the success threshold, but not in the convergence \
                     plot or the ECDFs over 51 targets, which need those files. Pass the runs.csv \
                     of a complete results directory to draw them everywhere.",
                    ext.display()
                ));
                read_runs(ext)?
            }
        };
        super::external::check_external(dir, ext, all.iter().map(|(r, _)| r), &ext_records)?;
        let mut renamed: std::collections::BTreeSet<String> = Default::default();
        for mut r in ext_records {
            if internal_labels.contains(&r.algorithm) {
                renamed.insert(r.algorithm.clone());
                r.algorithm = format!("{} (external)", r.algorithm);
            }
            all.push((r, true));
        }
        if !renamed.is_empty() {
            let list: Vec<String> = renamed.into_iter().collect();
            notes.push(format!(
                "The external file uses the label(s) {} of the results directory; its \
                 runs are shown as \"<label> (external)\".",
                list.join(", ")
            ));
        }
    }
    let mut ds = Dataset::from_records(all);
    ds.has_timing = timing && conv;
    ds.has_hits = ds.has_timing && dir.join("hits.csv").is_file();
    ds.external_anytime = external_anytime;
    if !ds.has_timing {
        ds.clear_timing();
    }
    ds.clear_external_timing();
    notes.append(&mut ds.notes);
    ds.notes = notes;
    Ok(ds)
}

/// Whether `dir` is the directory of a campaign of this tool (`run` and
/// `merge` write its `meta.toml`), which must then hold every result file
/// of its campaign; a directory with a `runs.csv` alone (another tool's,
/// or made by hand) is reported from what it has.
pub(crate) fn is_campaign(dir: &Path) -> bool {
    dir.join("meta.toml").is_file()
}

/// Refuses a campaign directory without one of `files`.
fn require(dir: &Path, files: &[&str]) -> Result<(), ReportError> {
    for f in files {
        let path = dir.join(f);
        if !path.is_file() {
            return Err(DataError::new(
                &path,
                0,
                DataProblem::Missing(
                    "the directory holds a campaign (it has meta.toml), whose finished runs always write it; was it deleted, or the directory copied in part?",
                ),
            )
            .into());
        }
    }
    Ok(())
}

/// What the report says about where the results come from.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Provenance {
    /// The experiment name.
    pub name: Option<String>,
    /// The spec's description.
    pub description: Option<String>,
    /// Master seed.
    pub seed: Option<String>,
    /// Runs per (cell, problem).
    pub runs: Option<String>,
    /// The spec's budget text (`budget` or `budget_per_dim`).
    pub budget: Option<String>,
    /// Success threshold on `f − f*`.
    pub threshold: Option<f64>,
    /// `experiment.stop` when the spec sets it (`"budget"` or `"target"`).
    pub stop: Option<String>,
    /// `tool version` from meta.toml.
    pub tool: Option<String>,
    /// Hash of the spec text from meta.toml.
    pub spec_hash: Option<String>,
    /// The factors the campaign paired its seeds on (meta.toml `paired`).
    pub paired: Vec<String>,
    /// Whether `spec.toml` was found and parsed.
    pub spec_found: bool,
    /// Whether `meta.toml` was found and parsed.
    pub meta_found: bool,
    /// The keys of the spec's `[report]` section with their values (NaN
    /// where a value is not a number), for [`crate::effective_ropes`].
    pub report_keys: Vec<(String, f64)>,
    /// The sessions of `provenance.toml` (version, commit, date, threads,
    /// SIMD level, CPU), oldest first; empty when it is missing.
    pub sessions: Vec<crate::experiment::provenance::Session>,
    /// Problems reading the two files.
    pub notes: Vec<String>,
}

fn value_text(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

fn read_toml(path: &Path, notes: &mut Vec<String>) -> Option<toml::Table> {
    let text = match read_text_limited(path, MAX_TEXT_BYTES, "a TOML file of a results directory") {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            notes.push(format!("{} not found.", file_name(path)));
            return None;
        }
        Err(e) => {
            notes.push(format!("{} cannot be read: {e}.", file_name(path)));
            return None;
        }
    };
    match toml::from_str::<toml::Table>(&text) {
        Ok(t) => Some(t),
        Err(e) => {
            let msg = e.message().to_owned();
            notes.push(format!("{} is not valid TOML: {msg}.", file_name(path)));
            None
        }
    }
}

fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// Reads `spec.toml` and `meta.toml` of `dir`; missing or malformed files
/// leave fields empty and add a note.
pub(crate) fn provenance(dir: &Path) -> Provenance {
    let mut p = Provenance::default();
    let mut notes = Vec::new();
    if let Some(spec) = read_toml(&dir.join("spec.toml"), &mut notes) {
        p.spec_found = true;
        if let Some(exp) = spec.get("experiment").and_then(|v| v.as_table()) {
            p.name = exp.get("name").map(value_text);
            p.description = exp.get("description").map(value_text);
            p.seed = exp.get("seed").map(value_text);
            p.runs = exp.get("runs").map(value_text);
            p.budget = match (exp.get("budget"), exp.get("budget_per_dim")) {
                (Some(b), _) => Some(value_text(b)),
                (None, Some(b)) => Some(format!("{} × D", value_text(b))),
                (None, None) => None,
            };
            p.threshold = exp.get("threshold").and_then(|v| match v {
                toml::Value::Float(f) => Some(*f),
                toml::Value::Integer(i) => Some(*i as f64),
                _ => None,
            });
            p.stop = exp.get("stop").map(value_text);
        }
        if let Some(report) = spec.get("report").and_then(|v| v.as_table()) {
            p.report_keys = report
                .iter()
                .map(|(k, v)| {
                    let x = match v {
                        toml::Value::Float(f) => *f,
                        toml::Value::Integer(i) => *i as f64,
                        _ => f64::NAN,
                    };
                    (k.clone(), x)
                })
                .collect();
        }
    }
    p.sessions = crate::experiment::provenance::read(dir);
    if let Some(meta) = read_toml(&dir.join("meta.toml"), &mut notes) {
        p.meta_found = true;
        let tool = meta.get("tool").map(value_text);
        let version = meta.get("version").map(value_text);
        p.tool = match (tool, version) {
            (Some(t), Some(v)) => Some(format!("{t} {v}")),
            (None, Some(v)) => Some(v),
            (Some(t), None) => Some(t),
            (None, None) => None,
        };
        p.spec_hash = meta.get("spec_fnv1a64").map(value_text);
        p.paired = meta
            .get("paired")
            .and_then(|v| v.as_array())
            .map(|a| a.iter().map(value_text).collect())
            .unwrap_or_default();
        if p.name.is_none() {
            p.name = meta.get("experiment").map(value_text);
        }
        if p.seed.is_none() {
            p.seed = meta.get("master_seed").map(value_text);
        }
    }
    p.notes = notes;
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cell(label: &str, params: &str) -> Cell {
        Cell {
            label: label.into(),
            kind: "mhs".into(),
            params: params.into(),
            name: String::new(),
            external: false,
        }
    }

    #[test]
    fn a_bbob_function_is_one_function_across_its_dimensions() {
        let p = |function: &str, dim: usize| Problem {
            function: function.into(),
            dim,
            budget: None,
            transform: Transform::None,
            instance: 1,
        };
        assert_eq!(p("bbob_f008_d05", 5).across_dimensions(), "bbob_f008");
        assert_eq!(
            p("bbob_f008_d05", 5).across_dimensions(),
            p("bbob_f008_d10", 10).across_dimensions()
        );
        assert_eq!(p("sphere", 30).across_dimensions(), "sphere");
        assert_eq!(p("bbob_f008_dx", 5).across_dimensions(), "bbob_f008_dx");
    }

    #[test]
    fn names_show_the_varying_parameters() {
        let mut cells = vec![
            cell("HS", "hms=5;hmcr=0.9"),
            cell("MHS", "hms=5;hmcr=0.7;bw=0.01"),
            cell("MHS", "hms=5;hmcr=0.9;bw=0.01"),
            cell("MHS", "hms=5;hmcr=0.9;bw=0.1"),
        ];
        name_cells(&mut cells);
        let names: Vec<&str> = cells.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "HS",
                "MHS (hmcr=0.7, bw=0.01)",
                "MHS (hmcr=0.9, bw=0.01)",
                "MHS (hmcr=0.9, bw=0.1)"
            ]
        );
    }

    #[test]
    fn same_label_and_params_but_other_kind() {
        let mut cells = vec![cell("X", "a=1"), cell("X", "a=1")];
        cells[1].kind = "hs".into();
        name_cells(&mut cells);
        assert_eq!(cells[0].name, "X [mhs]");
        assert_eq!(cells[1].name, "X [hs]");
    }

    #[test]
    fn params_parse_leniently() {
        assert_eq!(
            parse_params("a=1;b;c=x=y;"),
            vec![
                ("a".to_owned(), "1".to_owned()),
                ("b".to_owned(), String::new()),
                ("c".to_owned(), "x=y".to_owned())
            ]
        );
        assert!(parse_params("").is_empty());
    }
}
