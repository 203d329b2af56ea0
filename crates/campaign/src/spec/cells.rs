//! The `[[algorithm]]` sections: each a method, a label and its listed
//! parameter values, expanded into the grid of its algorithm cells.

use std::ops::Range;

use super::reader::Parser;
use super::{choices_hint, raw, Cell, SpecError, Table, WithSpan, MAX_CELLS};
use crate::optim::{quoted_list, OptimiserDef, ParamDef, ParamSet, Setting};
use crate::reconstruction::Method;

impl Parser<'_> {
    /// The algorithm cells of the spec: each `[[algorithm]]` expanded into
    /// the grid of its listed parameter values. With `benchmarks`, only
    /// metaheuristics are allowed.
    pub(super) fn cells(
        &self,
        root: &Table<'_>,
        span: Range<usize>,
        benchmarks: bool,
        (problems, runs): (usize, u32),
    ) -> Result<Vec<Cell>, SpecError> {
        let mut out: Vec<Cell> = Vec::new();
        let mut seen = std::collections::HashSet::new();
        for (i, entry) in self
            .array_of_tables(root, "algorithm", span)?
            .into_iter()
            .enumerate()
        {
            let section = format!("algorithm[{}]", i + 1);
            let table = self.table(entry, &section)?;
            let algorithm = self.algorithm_entry(table, section, entry.span(), benchmarks)?;
            self.check_grid_size(&algorithm, out.len(), problems, runs)?;
            for combo in grid(&algorithm.axes) {
                let cell = self.grid_cell(&algorithm, &combo)?;
                if !seen.insert(cell.key()) {
                    return Err(self.error(
                        algorithm.span.clone(),
                        &algorithm.section,
                        format!(
                            "algorithm cell {} [{}] appears twice; give the entries different labels or parameters",
                            cell.label,
                            cell.params.canonical()
                        ),
                    ));
                }
                out.push(cell);
            }
        }
        Ok(out)
    }

    /// Refuses, before it is expanded, a grid that takes the spec past
    /// [`MAX_CELLS`] cells, or the campaign past `limits.max_runs` runs
    /// (problems × cells × runs, counted with the `have` cells before it).
    fn check_grid_size(
        &self,
        entry: &AlgorithmEntry,
        have: usize,
        problems: usize,
        runs: u32,
    ) -> Result<(), SpecError> {
        let sizes: Vec<usize> = entry.axes.iter().map(|a| a.len().max(1)).collect();
        let grid = sizes
            .iter()
            .fold(1u128, |n, &k| n.saturating_mul(k as u128));
        let shape = if sizes.iter().any(|&k| k > 1) {
            let listed: Vec<String> = sizes
                .iter()
                .filter(|&&k| k > 1)
                .map(usize::to_string)
                .collect();
            format!("its grid of {} = {grid} cells", listed.join(" × "))
        } else {
            "its cell".to_owned()
        };
        let cells = have as u128 + grid;
        if cells > MAX_CELLS as u128 {
            return Err(self.error(
                entry.span.clone(),
                &entry.section,
                format!(
                    "{shape}{} pass the limit of {MAX_CELLS} algorithm cells of a spec; list fewer values, or split the spec",
                    if have > 0 {
                        format!(" after {have} cells before it")
                    } else {
                        String::new()
                    }
                ),
            ));
        }
        let total = (problems as u128)
            .saturating_mul(cells)
            .saturating_mul(u128::from(runs));
        if total > self.limits.max_runs {
            return Err(self.error(
                entry.span.clone(),
                &entry.section,
                format!(
                    "with {shape} the campaign has {problems} problems × {cells} cells × {runs} runs = {total} runs, over the limit of {} runs; split the spec, or pass --allow-large",
                    self.limits.max_runs
                ),
            ));
        }
        Ok(())
    }

    /// Reads one `[[algorithm]]` table: its method, label and parameter
    /// axes, in that order.
    fn algorithm_entry(
        &self,
        table: &Table<'_>,
        section: String,
        span: Range<usize>,
        benchmarks: bool,
    ) -> Result<AlgorithmEntry, SpecError> {
        let (name, def, polish) = self.method_name(table, &section, span.clone(), benchmarks)?;
        let base = def.map(|d| d.name.clone());
        let defs: &'static [ParamDef] = def.map_or(&[], |d| d.params);
        let label = self.cell_label(table, &section, &name)?;
        self.check_params(table, &section, &name, defs)?;
        let axes = self.param_axes(table, &section, defs)?;
        Ok(AlgorithmEntry {
            section,
            span,
            base,
            polish,
            label,
            defs,
            axes,
        })
    }

    /// The required `name` of an `[[algorithm]]`, resolved to a method;
    /// Levenberg–Marquardt is refused when the spec has `benchmarks`.
    fn method_name(
        &self,
        table: &Table<'_>,
        section: &str,
        span: Range<usize>,
        benchmarks: bool,
    ) -> Result<(String, Option<&OptimiserDef>, bool), SpecError> {
        let nv = self.required(table, section, "name", span)?;
        let field = format!("{section}.name");
        let name = self.string(nv, &field)?;
        let optimisers = &self.registry.optimisers;
        let (base, polish) = Method::parse_name_in(&name, optimisers).ok_or_else(|| {
            // Only the methods that can solve this spec's problems.
            let names = if benchmarks {
                optimisers.names().iter().map(|s| s.to_string()).collect()
            } else {
                Method::names_in(optimisers)
            };
            let names: Vec<&str> = names.iter().map(String::as_str).collect();
            self.error(
                nv.span(),
                &field,
                format!(
                    "unknown algorithm \"{name}\"; {}",
                    choices_hint(&name, &names)
                ),
            )
        })?;
        if benchmarks && (base.is_none() || polish) {
            return Err(self.error(
                nv.span(),
                &field,
                format!(
                    "\"{name}\" uses Levenberg–Marquardt, which solves least-squares fitting problems only, but this spec has [[problem]] benchmark functions; use it with [[fit]] problems, or choose one of {}",
                    quoted_list(&optimisers.names())
                ),
            ));
        }
        let def = base.and_then(|b| optimisers.get(b));
        Ok((name, def, polish))
    }

    /// The cell label: `label` if given, else the method name.
    fn cell_label(
        &self,
        table: &Table<'_>,
        section: &str,
        name: &str,
    ) -> Result<String, SpecError> {
        let Some(v) = self.get(table, "label") else {
            return Ok(name.to_owned());
        };
        let l = self.string(v, &format!("{section}.label"))?;
        if l.is_empty() || l.contains(['\n', '\r', '"']) {
            return Err(self.error(
                v.span(),
                &format!("{section}.label"),
                "expected a non-empty label without quotes or line breaks".into(),
            ));
        }
        Ok(l)
    }

    /// Checks that every key of an `[[algorithm]]` besides `name` and
    /// `label` is a parameter of method `name` (whose parameters are `defs`).
    fn check_params(
        &self,
        table: &Table<'_>,
        section: &str,
        name: &str,
        defs: &[ParamDef],
    ) -> Result<(), SpecError> {
        let param_names: Vec<&str> = defs.iter().map(|d| d.name).collect();
        for (k, _) in table.iter() {
            let key: &str = k.get_ref();
            if key == "name" || key == "label" || param_names.contains(&key) {
                continue;
            }
            let mut valid = vec!["name", "label"];
            valid.extend(&param_names);
            return Err(self.error(
                k.span(),
                &format!("{section}.{key}"),
                format!(
                    "unknown parameter for {name}{}; {}",
                    if defs.is_empty() {
                        " (it has none)"
                    } else {
                        ""
                    },
                    choices_hint(key, &valid)
                ),
            ));
        }
        Ok(())
    }

    /// Each parameter's listed values with their spans, in declaration
    /// order; empty for a parameter left at its default.
    fn param_axes(
        &self,
        table: &Table<'_>,
        section: &str,
        defs: &[ParamDef],
    ) -> Result<Vec<Axis>, SpecError> {
        let mut axes: Vec<Axis> = Vec::new();
        for def in defs {
            let Some(v) = self.get(table, def.name) else {
                axes.push(Vec::new());
                continue;
            };
            let field = format!("{section}.{}", def.name);
            let mut values = Vec::new();
            for item in self.one_or_many(v, &field)? {
                let setting = def
                    .check(&raw(item.get_ref()))
                    .map_err(|e| self.error(item.span(), &field, e.to_string()))?;
                values.push((setting, item.span()));
            }
            axes.push(values);
        }
        Ok(axes)
    }

    /// The cell of one grid point `combo` (an index into each axis): the
    /// defaults with the chosen values, and the method configured with them.
    fn grid_cell(&self, entry: &AlgorithmEntry, combo: &[usize]) -> Result<Cell, SpecError> {
        let mut params = ParamSet::defaults(entry.defs);
        let mut spans = Vec::new();
        for ((def, axis), k) in entry.defs.iter().zip(&entry.axes).zip(combo) {
            if let Some((setting, sp)) = axis.get(*k) {
                params.put(def.name, setting.clone());
                spans.push((def.name, sp.clone()));
            }
        }
        let algorithm = match &entry.base {
            None => None,
            Some(b) => Some(self.registry.optimisers.build(b, &params).map_err(|e| {
                let sp = spans
                    .iter()
                    .find(|(n, _)| *n == e.param)
                    .map_or(entry.span.clone(), |(_, s)| s.clone());
                self.error(
                    sp,
                    &format!("{}.{}", entry.section, e.param),
                    e.message.clone(),
                )
            })?),
        };
        Ok(Cell {
            label: entry.label.clone(),
            method: Method::build(algorithm, entry.polish),
            params,
        })
    }
}

/// One `[[algorithm]]` entry, read: its method, label and parameter axes.
struct AlgorithmEntry {
    /// `algorithm[i]`, for errors.
    section: String,
    /// The entry's span, for errors about the whole entry.
    span: Range<usize>,
    /// The metaheuristic whose parameters it takes (`None` for `lm`).
    base: Option<String>,
    /// Whether the metaheuristic is polished by LM.
    polish: bool,
    /// The label of its cells.
    label: String,
    /// The parameters of the metaheuristic.
    defs: &'static [ParamDef],
    /// The listed values of each parameter, in `defs` order.
    axes: Vec<Axis>,
}

/// The values listed for one parameter, each with its span; empty when the
/// parameter keeps its default.
type Axis = Vec<WithSpan<Setting>>;

/// The cartesian product of the axes as index vectors, first axis slowest;
/// an empty axis counts as one value (the default).
fn grid(axes: &[Axis]) -> Vec<Vec<usize>> {
    let mut combos: Vec<Vec<usize>> = vec![Vec::new()];
    for axis in axes {
        let n = axis.len().max(1);
        combos = combos
            .into_iter()
            .flat_map(|c| {
                (0..n).map(move |k| {
                    let mut c = c.clone();
                    c.push(k);
                    c
                })
            })
            .collect();
    }
    combos
}
