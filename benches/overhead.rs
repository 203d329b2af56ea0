//! Each optimiser's cost per evaluation against a bare loop of the same
//! objective, in CPU time, timed in the same process (`make overhead`,
//! which runs `cargo bench --locked --bench overhead`).
//!
//! For every optimiser of `Algorithm::names()` (or those given with
//! `--algorithms`), one round times a *bare* sample, `runs × evals`
//! evaluations of Sphere-`D` (or `--function`) cycling through 1,024
//! uniform points, and then the optimiser's sample, `runs` seeded runs of
//! `evals` evaluations each on the same problem (seeds 1..=runs, the same in every round, so every round
//! does the same work). Both are read on the calling thread's CPU clock
//! (`clock_gettime(CLOCK_THREAD_CPUTIME_ID)`, Linux; elsewhere the wall
//! clock, and the table says so) and on the wall clock. The ratio of a round
//! is `optimiser time / bare time` of that adjacent pair; the table gives
//! each optimiser's median ns per evaluation over the rounds, the median
//! ratio, its smallest and largest value (the spread), and the median
//! ratio on the wall clock. `ratio − 1` is the optimiser's own work per
//! evaluation in units of one bare evaluation.
//!
//! CPU time counts only the time this thread ran, so other processes on a
//! shared machine lengthen it much less than the wall clock; the caches and
//! the CPU's clock speed they share still show in the spread.
//!
//! Options (after `--`; `make overhead OVERHEAD_ARGS="..."`): `--function
//! F` (`sphere`; a name of `metabezier list`), `--dim D` (30, at most
//! 1,000), `--evals N` (20,000 a run, as `benches/optimisers.rs`), `--runs
//! K` (10 a sample), `--rounds R` (9), `--algorithms a,b,...` (all), `--long N`
//! (2,000,000). Run without `--bench` (as `cargo test
//! --benches` does), it measures a tiny budget once and checks that its
//! tables are well formed.
//!
//! A second table gives each optimiser's CPU time per evaluation in the
//! first and in the last tenth of one long run (`--long` evaluations, seed
//! 1), read by the evaluator's observer at the checkpoints N/10 and 9N/10:
//! an optimiser whose late evaluations cost more than its early ones
//! (subnormal numbers as its steps shrink, say) shows a ratio above 1.

#[allow(dead_code)]
#[path = "common/mod.rs"]
mod common;

use common::uniform_points;
use std::hint::black_box;
use std::process::ExitCode;
use std::time::Instant;

use metabezier::functions::{Function, TestProblem};
use metabezier::optim::{Algorithm, Evaluator};
use metabezier::problem::Problem;
use metabezier::rng::run_rng;
use metabezier::stats::median;

/// The uniform points the bare loop cycles through.
const POINTS: usize = 1024;

/// What to measure.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// The objective (Sphere by default).
    pub function: Function,
    /// Its dimension.
    pub dim: usize,
    /// Evaluations of one optimiser run.
    pub evals: u64,
    /// Runs (and as many bare loops of `evals`) in one sample.
    pub runs: u64,
    /// Rounds of alternating bare and optimiser samples.
    pub rounds: usize,
    /// The optimisers, by registry name.
    pub algorithms: Vec<String>,
    /// Evaluations of the long run whose first and last tenths are timed.
    pub long: u64,
}

impl Default for Options {
    fn default() -> Options {
        Options {
            function: Function::Sphere,
            dim: 30,
            evals: 20_000,
            runs: 10,
            rounds: 9,
            algorithms: Algorithm::names().into_iter().map(String::from).collect(),
            long: 2_000_000,
        }
    }
}

impl Options {
    /// A budget small enough for a check that the program runs (a fraction
    /// of a second): one round of one run of 2,000 evaluations.
    pub fn tiny() -> Options {
        Options {
            evals: 2_000,
            runs: 1,
            rounds: 1,
            long: 20_000,
            ..Options::default()
        }
    }

    /// Reads the options from the command-line arguments (without the
    /// program's name). `--bench`, which `cargo bench` passes, is skipped;
    /// whether it was there is returned beside the options.
    pub fn parse(args: &[String]) -> Result<(Options, bool), String> {
        let mut o = Options::default();
        let mut bench = false;
        let mut it = args.iter();
        while let Some(arg) = it.next() {
            if arg == "--bench" {
                bench = true;
                continue;
            }
            let mut value = || {
                it.next()
                    .ok_or_else(|| format!("{arg} needs a value"))
                    .cloned()
            };
            match arg.as_str() {
                "--function" => {
                    let name = value()?;
                    o.function = Function::from_name(&name).ok_or_else(|| {
                        let names: Vec<&str> = Function::ALL.iter().map(|f| f.name()).collect();
                        format!(
                            "--function: unknown function {name:?}; the functions are {}",
                            names.join(", ")
                        )
                    })?;
                }
                "--dim" => match positive(arg, &value()?)? {
                    d if d <= MAX_DIM => o.dim = d as usize,
                    d => return Err(format!("--dim: {d} is more than {MAX_DIM}")),
                },
                "--evals" => o.evals = positive(arg, &value()?)?,
                "--runs" => o.runs = positive(arg, &value()?)?,
                "--rounds" => o.rounds = positive(arg, &value()?)? as usize,
                "--long" => o.long = positive(arg, &value()?)?.max(10),
                "--algorithms" => {
                    let names = Algorithm::names();
                    o.algorithms = Vec::new();
                    for name in value()?.split(',').map(str::trim) {
                        if !names.contains(&name) {
                            return Err(format!(
                                "--algorithms: unknown optimiser {name:?}; the optimisers are {}",
                                names.join(", ")
                            ));
                        }
                        o.algorithms.push(name.to_string());
                    }
                }
                _ => {
                    return Err(format!(
                        "unknown argument {arg:?}; the options are --function F, --dim D, \
                         --evals N, --runs K, --rounds R, --algorithms a,b,..., --long N"
                    ))
                }
            }
        }
        if o.evals.checked_mul(o.runs).is_none_or(|n| n > MAX) {
            return Err(format!(
                "--evals {} × --runs {} is more than 2^40 evaluations a sample",
                o.evals, o.runs
            ));
        }
        TestProblem::new(o.function, o.dim)
            .map_err(|e| format!("--function {} --dim {}: {e}", o.function.name(), o.dim))?;
        Ok((o, bench))
    }
}

/// The largest `--dim` (the bare loop holds 1,024 points of `D` values).
const MAX_DIM: u64 = 1000;

/// The largest count an option takes, and the largest `evals × runs`.
const MAX: u64 = 1 << 40;

/// `text` as a whole number of at least 1, or an error naming `option`.
fn positive(option: &str, text: &str) -> Result<u64, String> {
    match text.parse::<u64>() {
        Ok(n) if (1..=MAX).contains(&n) => Ok(n),
        _ => Err(format!(
            "{option}: {text:?} is not a whole number from 1 to 2^40"
        )),
    }
}

/// The calling thread's CPU time in ns (`CLOCK_THREAD_CPUTIME_ID`).
#[cfg(target_os = "linux")]
fn cpu_ns() -> Option<u64> {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec for the call's duration.
    let r = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    (r == 0).then(|| ts.tv_sec as u64 * 1_000_000_000 + ts.tv_nsec as u64)
}

/// No thread CPU clock is read on this system: the wall clock stands in.
#[cfg(not(target_os = "linux"))]
fn cpu_ns() -> Option<u64> {
    None
}

/// One timed sample: (CPU ns, wall ns) of `work`, the CPU time `None` where
/// the thread's CPU clock cannot be read.
fn timed(work: impl FnOnce() -> f64) -> (Option<f64>, f64) {
    let (c0, w0) = (cpu_ns(), Instant::now());
    black_box(work());
    let wall = w0.elapsed().as_nanos() as f64;
    let cpu = match (c0, cpu_ns()) {
        (Some(a), Some(b)) => Some(b.saturating_sub(a) as f64),
        _ => None,
    };
    (cpu, wall)
}

/// One optimiser's row: its name and, per round, the (CPU, wall) ns of its
/// sample and of the bare sample before it.
#[derive(Clone, Debug)]
pub struct Row {
    /// The optimiser's registry name.
    pub name: String,
    /// Per round: (bare, optimiser) on the CPU clock (the wall clock where
    /// there is none).
    pub cpu: Vec<(f64, f64)>,
    /// Per round: (bare, optimiser) on the wall clock.
    pub wall: Vec<(f64, f64)>,
}

/// What [`measure`] found: the rows and whether the CPU clock was read.
#[derive(Clone, Debug)]
pub struct Measurement {
    /// The options measured with.
    pub options: Options,
    /// One row per optimiser, in the order of the options.
    pub rows: Vec<Row>,
    /// Whether the times of `Row::cpu` are CPU times (else wall times).
    pub cpu_clock: bool,
}

/// Runs the rounds of `o`: an untimed warm-up of each optimiser and the
/// bare loop, then per round and per optimiser a bare sample followed by
/// the optimiser's sample.
pub fn measure(o: &Options) -> Measurement {
    let problem = TestProblem::new(o.function, o.dim).expect("checked by Options::parse");
    let points = uniform_points(&problem, POINTS);
    // At most 2^40 (Options::parse); a 32-bit target stops at usize::MAX.
    let total = usize::try_from(o.evals * o.runs).unwrap_or(usize::MAX);
    let bare = || {
        let mut s = 0.0;
        for x in points.iter().cycle().take(total) {
            s += problem.objective(black_box(x));
        }
        s
    };
    let algos: Vec<Algorithm> = o
        .algorithms
        .iter()
        .map(|n| Algorithm::default_for(n).expect("names checked by Options::parse"))
        .collect();
    let run = |algo: &Algorithm| {
        let mut s = 0.0;
        for seed in 1..=o.runs {
            s += algo.run(&problem, o.evals, &mut run_rng(seed)).best_value;
        }
        s
    };
    black_box(bare());
    for algo in &algos {
        black_box(algo.run(&problem, o.evals, &mut run_rng(1)).best_value);
    }
    let mut rows: Vec<Row> = algos
        .iter()
        .map(|a| Row {
            name: a.name().to_string(),
            cpu: Vec::new(),
            wall: Vec::new(),
        })
        .collect();
    let mut cpu_clock = true;
    for _ in 0..o.rounds {
        for (algo, row) in algos.iter().zip(&mut rows) {
            let (bare_cpu, bare_wall) = timed(bare);
            let (run_cpu, run_wall) = timed(|| run(algo));
            cpu_clock &= bare_cpu.is_some() && run_cpu.is_some();
            row.cpu
                .push((bare_cpu.unwrap_or(bare_wall), run_cpu.unwrap_or(run_wall)));
            row.wall.push((bare_wall, run_wall));
        }
    }
    if !cpu_clock {
        for row in &mut rows {
            row.cpu = row.wall.clone();
        }
    }
    Measurement {
        options: o.clone(),
        rows,
        cpu_clock,
    }
}

impl Measurement {
    /// The table: a heading line, then a Markdown table with one row per
    /// optimiser (bare ns and optimiser ns per evaluation, the median ratio,
    /// its range over the rounds, the median wall-clock ratio).
    pub fn table(&self) -> String {
        let o = &self.options;
        let evals = (o.evals * o.runs) as f64;
        let clock = if self.cpu_clock {
            "thread CPU time (CLOCK_THREAD_CPUTIME_ID)"
        } else {
            "wall clock (no thread CPU clock on this system)"
        };
        let mut out = format!(
            "{}, D = {}: {} runs of {} evaluations a sample against as many bare \
             evaluations, {} rounds, {clock}; medians over the rounds\n\n",
            o.function.title(),
            o.dim,
            o.runs,
            o.evals,
            o.rounds
        );
        out.push_str(
            "| optimiser | bare ns/eval | ns/eval | ratio to bare | ratio min–max | wall-clock ratio |\n",
        );
        out.push_str("|---|---:|---:|---:|---:|---:|\n");
        for row in &self.rows {
            let bare: Vec<f64> = row.cpu.iter().map(|p| p.0 / evals).collect();
            let run: Vec<f64> = row.cpu.iter().map(|p| p.1 / evals).collect();
            let ratio: Vec<f64> = row.cpu.iter().map(|p| p.1 / p.0).collect();
            let wall: Vec<f64> = row.wall.iter().map(|p| p.1 / p.0).collect();
            let lo = ratio.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = ratio.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            out.push_str(&format!(
                "| {} | {:.1} | {:.1} | {:.1} | {lo:.1}–{hi:.1} | {:.1} |\n",
                row.name,
                median(&bare),
                median(&run),
                median(&ratio),
                median(&wall)
            ));
        }
        out
    }
}

/// The calling thread's CPU time in ns, or the wall clock's since the
/// first call where there is no CPU clock.
fn now_ns() -> u64 {
    static EPOCH: std::sync::OnceLock<Instant> = std::sync::OnceLock::new();
    cpu_ns().unwrap_or_else(|| EPOCH.get_or_init(Instant::now).elapsed().as_nanos() as u64)
}

/// Per optimiser of `o`: (name, ns per evaluation in the first tenth, in
/// the last tenth) of one run of `o.long` evaluations with seed 1, timed at
/// the checkpoints N/10 and 9N/10 by the evaluator's observer (no cost per
/// evaluation; a generation evaluated as one batch is timed whole).
pub fn tenths(o: &Options) -> Vec<(String, f64, f64)> {
    let problem = TestProblem::new(o.function, o.dim).expect("checked by Options::parse");
    let n = o.long;
    let tenth = n / 10;
    o.algorithms
        .iter()
        .map(|name| {
            let algo = Algorithm::default_for(name).expect("names checked by Options::parse");
            let marks = std::sync::Arc::new(std::sync::Mutex::new(Vec::with_capacity(3)));
            let seen = std::sync::Arc::clone(&marks);
            let mut eval = Evaluator::new(&problem, n)
                .with_checkpoints(vec![tenth, n - tenth, n])
                .with_observer(Box::new(move |_, _, _| {
                    seen.lock().expect("one thread").push(now_ns());
                    true
                }));
            let start = now_ns();
            algo.minimise_benchmark(&mut eval, &mut run_rng(1));
            black_box(eval.finish());
            let m = marks.lock().expect("one thread").clone();
            let per = |a: u64, b: u64| b.saturating_sub(a) as f64 / tenth as f64;
            match m[..] {
                [first, late, last] => (name.clone(), per(start, first), per(late, last)),
                _ => (name.clone(), f64::NAN, f64::NAN),
            }
        })
        .collect()
}

/// The table of [`tenths`]: one row per optimiser with its ns per
/// evaluation in the first and the last tenth of the long run and their
/// ratio.
pub fn tenths_table(o: &Options, rows: &[(String, f64, f64)]) -> String {
    let mut out = format!(
        "\n{}, D = {}: one run of {} evaluations (seed 1), CPU time per evaluation in its \
         first and last tenth\n\n| optimiser | first tenth ns/eval | last tenth ns/eval | last / first |\n\
         |---|---:|---:|---:|\n",
        o.function.title(),
        o.dim,
        o.long
    );
    for (name, first, last) in rows {
        out.push_str(&format!(
            "| {name} | {first:.1} | {last:.1} | {:.2} |\n",
            last / first
        ));
    }
    out
}

/// Checks the shape of a [`Measurement::table`]: a heading, a table head
/// of six columns, and one row per optimiser in `names` whose five figures
/// are positive numbers (the range `lo–hi` with `lo ≤ hi`).
pub fn check_table(table: &str, names: &[String]) -> Result<(), String> {
    let rows: Vec<&str> = table.lines().filter(|l| l.starts_with('|')).collect();
    if rows.len() != names.len() + 2 {
        return Err(format!(
            "{} table lines, expected {} (head, rule and one per optimiser)",
            rows.len(),
            names.len() + 2
        ));
    }
    for (line, name) in rows[2..].iter().zip(names) {
        let cells: Vec<&str> = line.trim_matches('|').split('|').map(str::trim).collect();
        if cells.len() != 6 || cells[0] != name {
            return Err(format!(
                "row {line:?}: expected 6 cells, the first {name:?}"
            ));
        }
        let number = |t: &str| t.parse::<f64>().ok().filter(|v| v.is_finite() && *v > 0.0);
        let range: Vec<Option<f64>> = cells[4].split('–').map(number).collect();
        let ok = [cells[1], cells[2], cells[3], cells[5]]
            .iter()
            .all(|c| number(c).is_some())
            && matches!(range[..], [Some(lo), Some(hi)] if lo <= hi);
        if !ok {
            return Err(format!("row {line:?}: a figure is not a positive number"));
        }
    }
    Ok(())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (options, bench) = match Options::parse(&args) {
        Ok(parsed) => parsed,
        Err(e) => {
            eprintln!("overhead: {e}");
            return ExitCode::from(2);
        }
    };
    if !bench {
        // `cargo test --benches`: a tiny budget, and the table's shape.
        let tiny = Options {
            algorithms: options.algorithms,
            ..Options::tiny()
        };
        let table = measure(&tiny).table();
        print!("{table}");
        let rows = tenths(&tiny);
        print!("{}", tenths_table(&tiny, &rows));
        if let Some((name, ..)) = rows
            .iter()
            .find(|(_, a, b)| !(a.is_finite() && b.is_finite() && *a >= 0.0 && *b >= 0.0))
        {
            eprintln!("overhead: {name}: the long run's tenths were not both timed");
            return ExitCode::FAILURE;
        }
        return match check_table(&table, &tiny.algorithms) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("overhead: malformed table: {e}");
                ExitCode::FAILURE
            }
        };
    }
    print!("{}", measure(&options).table());
    print!("{}", tenths_table(&options, &tenths(&options)));
    ExitCode::SUCCESS
}
