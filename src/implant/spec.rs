//! The chapter-6 experiment spec (`metabezier implant SPEC.toml`).
//!
//! ```toml
//! [implant]
//! volume = "../data/ct0051/ct0051_z040-100.inv3"  # .inv3 file or DICOM directory, relative to this file
//! first_z = 40              # original number of the volume's slice 0
//! threshold = 300           # bone threshold, HU
//! midline = "auto"          # or M_x in mm
//! midline_slices = [88, 90] # slices (range) for "auto"; default: the defect slices
//! function = "rational-cubic"  # quadratic, cubic, rational-quadratic, rational-cubic
//! continuity = "g1"         # c0, c1, g1
//! method = "mhs"            # any metaheuristic, "lm", or "<name>+lm"
//! budget = 10000            # evaluations per slice
//! seed = 2026
//!
//! [defect]                  # the real defect (optional)
//! slices = [56, 84]         # first and last slice (original numbering)
//! ends = "auto"             # default for slices without an [[defect.end]]
//! overlays = [64, 72, 80]   # slices rendered as overlay PNGs
//! ring_points = 160
//!
//! [[defect.end]]            # A and B as (row, col) pixels, per slice
//! z = 64
//! a = [196, 111]
//! b = [188, 86]
//!
//! [validation]              # artificial defects (optional)
//! slices = [88, 89, 90]
//! positions = [200, 240, 300, 340]   # polar angles (degrees) of the defect centres
//! widths = [20, 30, 40]              # mm
//! methods = ["mhs", "lm"]            # default: [implant.method]
//! runs = 30                          # per stochastic method
//! margin_mm = 10                     # boundary Dice band
//! ```
//!
//! Errors name the file, line, column and field, say what was expected and
//! list the valid choices ([`crate::experiment::SpecError`]).

use std::path::{Path, PathBuf};

use toml::de::{DeTable, DeValue};

use super::pipeline::{DefectConfig, Ends, MidlineSpec, SliceSpec};
use super::wall::WallOptions;
use crate::experiment::spec::{type_name, Parser, SpecError, Table, Value};
use crate::fit::FunctionType;
use crate::geometry::Continuity;
use crate::reconstruction::Method;

/// The artificial-defect validation part.
#[derive(Clone, Debug)]
pub struct ValidationSpec {
    /// Slices (original numbering).
    pub slices: Vec<usize>,
    /// Polar angles of the defect centres (degrees).
    pub positions: Vec<f64>,
    /// Widths (mm).
    pub widths: Vec<f64>,
    /// Curve-fit methods.
    pub methods: Vec<Method>,
    /// Runs per stochastic method.
    pub runs: usize,
    /// Boundary-Dice band (mm).
    pub margin_mm: f64,
}

/// A loaded chapter-6 spec.
#[derive(Clone, Debug)]
pub struct ImplantSpec {
    /// The spec file.
    pub path: PathBuf,
    /// The volume, resolved against the spec's directory.
    pub volume: PathBuf,
    /// The volume path as written in the spec.
    pub volume_label: String,
    /// The method of the real defect.
    pub method: Method,
    /// The master seed.
    pub seed: u64,
    /// Whether a `[defect]` section is present.
    pub run_defect: bool,
    /// Slices rendered as overlays.
    pub overlays: Vec<usize>,
    /// Pipeline configuration (slices empty without `[defect]`).
    pub defect_config: DefectConfig,
    /// The validation part.
    pub validation: Option<ValidationSpec>,
}

const IMPLANT_KEYS: [&str; 10] = [
    "volume",
    "first_z",
    "threshold",
    "midline",
    "midline_slices",
    "function",
    "continuity",
    "method",
    "budget",
    "seed",
];
const DEFECT_KEYS: [&str; 5] = ["slices", "ends", "overlays", "ring_points", "end"];
const END_KEYS: [&str; 3] = ["z", "a", "b"];
const VALIDATION_KEYS: [&str; 6] = [
    "slices",
    "positions",
    "widths",
    "methods",
    "runs",
    "margin_mm",
];

fn quoted(names: &[&str]) -> String {
    names
        .iter()
        .map(|n| format!("\"{n}\""))
        .collect::<Vec<_>>()
        .join(", ")
}

impl Parser<'_> {
    fn int(&self, v: &Value<'_>, field: &str, min: i64, max: i64) -> Result<i64, SpecError> {
        let n = match v.get_ref() {
            DeValue::Integer(i) => i64::from_str_radix(i.as_str(), i.radix()).ok(),
            _ => None,
        };
        match n {
            Some(n) if (min..=max).contains(&n) => Ok(n),
            _ => Err(self.error(
                v.span(),
                field,
                format!(
                    "expected an integer in {min}..={max}, found {}",
                    self.show(v)
                ),
            )),
        }
    }

    /// A finite real number (an integer is accepted).
    fn finite_real(&self, v: &Value<'_>, field: &str) -> Result<f64, SpecError> {
        let x = match v.get_ref() {
            DeValue::Integer(i) => i64::from_str_radix(i.as_str(), i.radix())
                .ok()
                .map(|n| n as f64),
            DeValue::Float(x) => x.as_str().parse::<f64>().ok(),
            _ => None,
        };
        x.filter(|x| x.is_finite()).ok_or_else(|| {
            self.error(
                v.span(),
                field,
                format!("expected a real number, found {}", self.show(v)),
            )
        })
    }

    fn show(&self, v: &Value<'_>) -> String {
        let s = &self.text[v.span().start.min(self.text.len())..v.span().end.min(self.text.len())];
        if s.is_empty() {
            format!("a {}", type_name(v.get_ref()))
        } else {
            s.to_string()
        }
    }

    fn array<'t, 'i>(
        &self,
        v: &'t Value<'i>,
        field: &str,
    ) -> Result<Vec<&'t Value<'i>>, SpecError> {
        match v.get_ref() {
            DeValue::Array(a) if !a.is_empty() => Ok(a.iter().collect()),
            o => Err(self.error(
                v.span(),
                field,
                format!(
                    "expected a non-empty list, found {}",
                    if matches!(o, DeValue::Array(_)) {
                        "an empty list".into()
                    } else {
                        format!("a {}", type_name(o))
                    }
                ),
            )),
        }
    }

    fn pixel(&self, v: &Value<'_>, field: &str) -> Result<(f64, f64), SpecError> {
        let a = self.array(v, field)?;
        if a.len() != 2 {
            return Err(self.error(v.span(), field, "expected [row, col] (two numbers)".into()));
        }
        Ok((
            self.finite_real(a[0], field)?,
            self.finite_real(a[1], field)?,
        ))
    }

    fn method(&self, v: &Value<'_>, field: &str) -> Result<Method, SpecError> {
        let name = self.string(v, field)?;
        let bad = || {
            let names = Method::names();
            let names: Vec<&str> = names.iter().map(String::as_str).collect();
            self.error(
                v.span(),
                field,
                format!(
                    "unknown method \"{name}\"; valid choices: {}",
                    quoted(&names)
                ),
            )
        };
        Method::from_name(&name).ok_or_else(bad)
    }

    fn range(&self, v: &Value<'_>, field: &str) -> Result<(usize, usize), SpecError> {
        let a = self.array(v, field)?;
        if a.len() != 2 {
            return Err(self.error(
                v.span(),
                field,
                "expected [first, last] (two slice numbers)".into(),
            ));
        }
        let (z0, z1) = (
            self.int(a[0], field, 0, 1 << 20)? as usize,
            self.int(a[1], field, 0, 1 << 20)? as usize,
        );
        if z1 <= z0 {
            return Err(self.error(
                v.span(),
                field,
                format!("expected first < last, found [{z0}, {z1}]"),
            ));
        }
        Ok((z0, z1))
    }

    fn implant_spec(&self) -> Result<ImplantSpec, SpecError> {
        let doc = DeTable::parse(self.text).map_err(|e| {
            let msg = e.message().trim().to_string();
            self.error(e.span().unwrap_or(0..0), "", format!("invalid TOML: {msg}"))
        })?;
        let root = doc.get_ref();
        self.check_keys(root, "", &["implant", "defect", "validation"])?;
        let imp = self
            .get(root, "implant")
            .ok_or_else(|| self.error(0..0, "implant", "missing section [implant]".into()))?;
        let mut implant = self.implant_section(self.table(imp, "implant")?)?;
        let defect = match self.get(root, "defect") {
            Some(d) => Some(self.defect_section(d, &mut implant.config)?),
            None => None,
        };
        let validation = match self.get(root, "validation") {
            Some(v) => Some(self.validation_section(v, &implant.method)?),
            None => None,
        };
        if defect.is_none() && validation.is_none() {
            return Err(self.error(
                0..0,
                "",
                "nothing to run: add a [defect] or a [validation] section".into(),
            ));
        }
        Ok(ImplantSpec {
            path: self.path.to_owned(),
            volume: implant.volume,
            volume_label: implant.volume_label,
            method: implant.method,
            seed: implant.seed,
            run_defect: defect.is_some(),
            overlays: defect.unwrap_or_default(),
            defect_config: implant.config,
            validation,
        })
    }

    /// The `[implant]` section: the volume, the method and seed, and the
    /// pipeline configuration without slices.
    fn implant_section(&self, imp: &Table<'_>) -> Result<ImplantSection, SpecError> {
        self.check_keys(imp, "implant", &IMPLANT_KEYS)?;
        let vol = self.get(imp, "volume").ok_or_else(|| {
            self.error(
                0..0,
                "implant.volume",
                "missing field: the CT volume (.inv3 file or DICOM directory)".into(),
            )
        })?;
        let volume_label = self.string(vol, "implant.volume")?;
        let base = self.path.parent().unwrap_or(Path::new("."));
        let volume = base.join(&volume_label);
        let int_or = |k: &str, d: i64, min: i64, max: i64| -> Result<i64, SpecError> {
            self.get(imp, k)
                .map_or(Ok(d), |v| self.int(v, &format!("implant.{k}"), min, max))
        };
        let first_z = int_or("first_z", 0, 0, 1 << 20)? as usize;
        let threshold = int_or("threshold", 300, i16::MIN as i64, i16::MAX as i64)? as i16;
        let budget = int_or("budget", 10_000, 1, i64::MAX)? as u64;
        let seed = int_or("seed", 0, 0, i64::MAX)? as u64;
        let wall = self.wall_options(imp, budget)?;
        let method = match self.get(imp, "method") {
            Some(v) => self.method(v, "implant.method")?,
            None => Method::from_name("mhs").expect("mhs exists"),
        };
        let midline = self.midline(imp)?;
        Ok(ImplantSection {
            volume,
            volume_label,
            method,
            seed,
            config: DefectConfig {
                first_z,
                slices: Vec::new(),
                midline,
                threshold,
                wall,
                ring_points: 160,
            },
        })
    }

    /// `implant.function` and `implant.continuity` on the default wall
    /// options with `budget`.
    fn wall_options(&self, imp: &Table<'_>, budget: u64) -> Result<WallOptions, SpecError> {
        let mut wall = WallOptions {
            budget,
            ..WallOptions::default()
        };
        if let Some(v) = self.get(imp, "function") {
            let s = self.string(v, "implant.function")?;
            let names = ["quadratic", "cubic", "rational-quadratic", "rational-cubic"];
            wall.function = FunctionType::from_name(&s).ok_or_else(|| {
                self.error(
                    v.span(),
                    "implant.function",
                    format!(
                        "unknown function \"{s}\"; valid choices: {}",
                        quoted(&names)
                    ),
                )
            })?;
        }
        if let Some(v) = self.get(imp, "continuity") {
            let s = self.string(v, "implant.continuity")?;
            wall.continuity = Continuity::from_name(&s).ok_or_else(|| {
                self.error(
                    v.span(),
                    "implant.continuity",
                    format!(
                        "unknown continuity \"{s}\"; valid choices: {}",
                        quoted(&["c0", "c1", "g1"])
                    ),
                )
            })?;
        }
        Ok(wall)
    }

    /// `implant.midline` (`"auto"` or M_x in mm) and `implant.midline_slices`.
    fn midline(&self, imp: &Table<'_>) -> Result<MidlineSpec, SpecError> {
        let midline_slices = match self.get(imp, "midline_slices") {
            Some(v) => {
                let (a, b) = self.range(v, "implant.midline_slices")?;
                (a..=b).collect()
            }
            None => Vec::new(),
        };
        Ok(match self.get(imp, "midline") {
            None => MidlineSpec::Auto(midline_slices),
            Some(v) => match v.get_ref() {
                DeValue::String(s) if s.as_ref() == "auto" => MidlineSpec::Auto(midline_slices),
                DeValue::Integer(_) | DeValue::Float(_) => {
                    MidlineSpec::Given(self.finite_real(v, "implant.midline")?)
                }
                _ => {
                    return Err(self.error(
                        v.span(),
                        "implant.midline",
                        format!("expected \"auto\" or M_x in mm, found {}", self.show(v)),
                    ))
                }
            },
        })
    }

    /// The `[defect]` section: fills `cfg`'s slices (and ring points) and
    /// returns the overlay slices.
    fn defect_section(
        &self,
        d: &Value<'_>,
        cfg: &mut DefectConfig,
    ) -> Result<Vec<usize>, SpecError> {
        let d = self.table(d, "defect")?;
        self.check_keys(d, "defect", &DEFECT_KEYS)?;
        let sv = self.get(d, "slices").ok_or_else(|| {
            self.error(
                0..0,
                "defect.slices",
                "missing field: [first, last] slice of the defect".into(),
            )
        })?;
        let (z0, z1) = self.range(sv, "defect.slices")?;
        if let Some(v) = self.get(d, "ends") {
            let s = self.string(v, "defect.ends")?;
            if s != "auto" {
                return Err(self.error(v.span(), "defect.ends", format!("unknown value \"{s}\"; valid choices: \"auto\" (give per-slice ends in [[defect.end]])")));
            }
        }
        if let Some(v) = self.get(d, "ring_points") {
            cfg.ring_points = self.int(v, "defect.ring_points", 8, 100_000)? as usize;
        }
        let mut overlays = Vec::new();
        if let Some(v) = self.get(d, "overlays") {
            for (i, x) in self.array(v, "defect.overlays")?.iter().enumerate() {
                overlays.push(
                    self.int(x, &format!("defect.overlays[{i}]"), z0 as i64, z1 as i64)? as usize,
                );
            }
        }
        cfg.slices = (z0..=z1)
            .map(|z| SliceSpec {
                z,
                ends: Ends::Auto,
            })
            .collect();
        if let Some(v) = self.get(d, "end") {
            self.defect_ends(v, (z0, z1), &mut cfg.slices)?;
        }
        Ok(overlays)
    }

    /// The `[[defect.end]]` tables: A and B as pixels on the slices they
    /// name (`slices` holds `z0..=z1`).
    fn defect_ends(
        &self,
        v: &Value<'_>,
        (z0, z1): (usize, usize),
        slices: &mut [SliceSpec],
    ) -> Result<(), SpecError> {
        let items = match v.get_ref() {
            DeValue::Array(a) => a.iter().collect::<Vec<_>>(),
            o => {
                return Err(self.error(
                    v.span(),
                    "defect.end",
                    format!("expected [[defect.end]] tables, found a {}", type_name(o)),
                ))
            }
        };
        for (i, e) in items.iter().enumerate() {
            let f = format!("defect.end[{i}]");
            let t = self.table(e, &f)?;
            self.check_keys(t, &f, &END_KEYS)?;
            let need = |k: &str| {
                self.get(t, k).ok_or_else(|| {
                    self.error(
                        e.span(),
                        &format!("{f}.{k}"),
                        format!("missing field `{k}`"),
                    )
                })
            };
            let zv = need("z")?;
            let z = self.int(zv, &format!("{f}.z"), z0 as i64, z1 as i64)? as usize;
            let a = self.pixel(need("a")?, &format!("{f}.a"))?;
            let b = self.pixel(need("b")?, &format!("{f}.b"))?;
            slices[z - z0].ends = Ends::Pixels { a, b };
        }
        Ok(())
    }

    /// The `[validation]` section; its methods default to `[method]`.
    fn validation_section(
        &self,
        v: &Value<'_>,
        method: &Method,
    ) -> Result<ValidationSpec, SpecError> {
        let t = self.table(v, "validation")?;
        self.check_keys(t, "validation", &VALIDATION_KEYS)?;
        let need = |k: &str| {
            self.get(t, k).ok_or_else(|| {
                self.error(
                    v.span(),
                    &format!("validation.{k}"),
                    format!("missing field `{k}`"),
                )
            })
        };
        let list_real = |k: &str| -> Result<Vec<f64>, SpecError> {
            let a = need(k)?;
            self.array(a, &format!("validation.{k}"))?
                .iter()
                .enumerate()
                .map(|(i, x)| self.finite_real(x, &format!("validation.{k}[{i}]")))
                .collect()
        };
        let slices = self
            .array(need("slices")?, "validation.slices")?
            .iter()
            .enumerate()
            .map(|(i, x)| {
                self.int(x, &format!("validation.slices[{i}]"), 0, 1 << 20)
                    .map(|n| n as usize)
            })
            .collect::<Result<Vec<_>, _>>()?;
        let positions = list_real("positions")?;
        let widths = list_real("widths")?;
        if let Some((i, _)) = widths.iter().enumerate().find(|(_, w)| **w <= 0.0) {
            let a = self.array(need("widths")?, "validation.widths")?;
            return Err(self.error(
                a[i].span(),
                &format!("validation.widths[{i}]"),
                "expected a width > 0 mm".into(),
            ));
        }
        let methods = match self.get(t, "methods") {
            None => vec![method.clone()],
            Some(m) => self
                .array(m, "validation.methods")?
                .iter()
                .enumerate()
                .map(|(i, x)| self.method(x, &format!("validation.methods[{i}]")))
                .collect::<Result<Vec<_>, _>>()?,
        };
        let runs = match self.get(t, "runs") {
            None => 30,
            Some(x) => self.int(x, "validation.runs", 1, 100_000)? as usize,
        };
        let margin_mm = match self.get(t, "margin_mm") {
            None => 10.0,
            Some(x) => self.finite_real(x, "validation.margin_mm")?,
        };
        Ok(ValidationSpec {
            slices,
            positions,
            widths,
            methods,
            runs,
            margin_mm,
        })
    }
}

/// What the `[implant]` section gives.
struct ImplantSection {
    /// The volume, resolved against the spec's directory.
    volume: PathBuf,
    /// The volume path as written.
    volume_label: String,
    /// The method of the real defect (and the validation's default).
    method: Method,
    /// The master seed.
    seed: u64,
    /// The pipeline configuration, without slices.
    config: DefectConfig,
}

impl ImplantSpec {
    /// Parses `text` as the spec at `path` (relative paths resolve against
    /// its directory).
    pub fn parse(path: &Path, text: &str) -> Result<ImplantSpec, SpecError> {
        Parser { path, text }.implant_spec()
    }

    /// Reads and parses the spec file.
    pub fn load(path: &Path) -> Result<ImplantSpec, SpecError> {
        let text = std::fs::read_to_string(path).map_err(|e| SpecError::unreadable(path, &e))?;
        Self::parse(path, &text)
    }
}
