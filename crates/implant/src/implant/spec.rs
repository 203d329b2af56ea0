//! The chapter-6 experiment spec (`metabezier implant SPEC.toml`).
//!
//! ```toml
//! [implant]
//! volume = "../data/ct0051/ct0051_z040-100.inv3"  # .inv3 file or DICOM directory, relative to this file
//! first_z = 40              # original number of the volume's slice 0
//! threshold = 300           # bone threshold, HU
//! midline = "auto"          # or M_x in mm (vertical), or [x_mm, y_mm, tilt_deg], tilt within ±45°
//! midline_slices = [88, 90] # slices (range) for "auto"; default: the defect slices
//! max_tilt_deg = 20         # the largest midline tilt searched by "auto"
//! function = "rational-cubic"  # quadratic, cubic, rational-quadratic, rational-cubic
//! continuity = "g1"         # c0, c1, g1
//! method = "mhs"            # any metaheuristic, "lm", or "<name>+lm"
//! budget = 10000            # evaluations per slice
//! seed = 2026
//! tangent_mm = 6            # outer table fitted for the end tangents
//! seat_bend_deg = 3         # A′, B′ seated where the table turns ≤ this per 3 mm
//! seat_max_mm = 6           # ... at most this far back from the tips
//! seat_change_deg_per_mm = 2    # cost of moving a seat between slices
//! thickness_setback_mm = 4  # where the bone thickness is measured
//! max_thickness_mm = 15     # cap on the implant thickness
//! max_thickness_step_mm = 0.5   # thickness change between adjacent slices
//! smooth_slices = 2         # outer-wall smoothing half-width (0: off)
//! template_source = "mirror" # mirror (the thesis; default), auto (the continuation where the mirror cannot serve), continuation, mirror3d (across the 3D plane), rim (the rim fill), auto3d (mirror3d where it serves, else rim)
//! thickness_profile = "linear" # Dis(u) linear from A′ to B′ (default), or "mirror": the other side's bone thickness
//! fill_ends = false         # true: the section reaches the bone's cut face at both ends
//!
//! [defect]                  # the real defect (optional)
//! slices = [56, 84]         # first and last slice (original numbering; [z, z]: one slice)
//! ends = "auto"             # default for slices without an [[defect.end]]
//! template = "tpl.csv"      # explicit template: columns z,x_mm,y_mm (optional)
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
//! alpha = 0.05                       # significance level of the verdicts
//!
//! [validation_3d]           # artificial defects across slices (optional)
//! ranges = [[86, 94], [90, 98]]      # first and last slice of each patch
//! positions = [210, 330]             # polar angles of the patch centres
//! widths = [20, 30]                  # mm, at the patch's middle slice
//! methods = ["mhs", "lm"]
//! runs = 5
//! margin_mm = 10
//! alpha = 0.05
//!
//! [checks]                  # plausibility limits (optional; see `spec_checks.rs`)
//! max_width_jump_mm = 15
//! ```
//!
//! Errors name the file, line, column and field, say what was expected and
//! list the valid choices ([`SpecError`]).

use std::path::{Path, PathBuf};

use toml::de::DeValue;

use super::pipeline::{DefectConfig, Ends, MidlineSpec, SliceSpec, Smoothing};
use super::template::read_templates;
use super::units::ImplantRopes;
use super::wall::WallOptions;
use super::wall_input::{TemplateChoice, ThicknessProfile};
use crate::ct::MidLine;
use metabezier_spec::{type_name, SpecError, Table, Value};

/// The implant spec's reader: the grammar's [`metabezier_spec::Parser`]
/// (the file's path and text, and the primitives), reached through `Deref`,
/// with the implant's section readers as methods.
struct Parser<'a>(metabezier_spec::Parser<'a>);

#[path = "spec_checks.rs"]
mod checks;

impl<'a> std::ops::Deref for Parser<'a> {
    type Target = metabezier_spec::Parser<'a>;

    fn deref(&self) -> &Self::Target {
        &self.0
    }
}
use crate::fit::FunctionType;
use crate::geometry::{Continuity, Point};
use crate::reconstruction::Method;
use crate::stats::DEFAULT_ALPHA;

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
    /// The significance level α of the verdicts against the baselines
    /// (default [`crate::stats::DEFAULT_ALPHA`] = 0.05).
    pub alpha: f64,
    /// The regions of practical equivalence of the verdicts' Bayesian
    /// signed-rank tests (`rope_overlap`, `rope_mm`).
    pub ropes: ImplantRopes,
}

/// The 3D validation part: patches cut out of intact bone across slices.
#[derive(Clone, Debug)]
pub struct Validation3dSpec {
    /// First and last slice of each patch (original numbering).
    pub ranges: Vec<(usize, usize)>,
    /// Polar angles of the patch centres (degrees).
    pub positions: Vec<f64>,
    /// Widths at the patch's middle slice (mm).
    pub widths: Vec<f64>,
    /// Curve-fit methods.
    pub methods: Vec<Method>,
    /// Runs per stochastic method.
    pub runs: usize,
    /// Boundary-Dice band (mm).
    pub margin_mm: f64,
    /// The significance level α of the verdicts against the baselines
    /// (default [`crate::stats::DEFAULT_ALPHA`] = 0.05).
    pub alpha: f64,
    /// The regions of practical equivalence of the verdicts' Bayesian
    /// signed-rank tests (`rope_overlap`, `rope_mm`).
    pub ropes: ImplantRopes,
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
    /// The 3D validation part.
    pub validation_3d: Option<Validation3dSpec>,
}

const IMPLANT_KEYS: [&str; 22] = [
    "volume",
    "first_z",
    "threshold",
    "midline",
    "midline_slices",
    "max_tilt_deg",
    "function",
    "continuity",
    "method",
    "budget",
    "seed",
    "tangent_mm",
    "seat_bend_deg",
    "seat_max_mm",
    "seat_change_deg_per_mm",
    "thickness_setback_mm",
    "max_thickness_mm",
    "max_thickness_step_mm",
    "smooth_slices",
    "template_source",
    "thickness_profile",
    "fill_ends",
];
const DEFECT_KEYS: [&str; 7] = [
    "slices",
    "thickness_mm",
    "ends",
    "overlays",
    "ring_points",
    "end",
    "template",
];
const VALIDATION_3D_KEYS: [&str; 9] = [
    "ranges",
    "positions",
    "widths",
    "methods",
    "runs",
    "margin_mm",
    "alpha",
    "rope_overlap",
    "rope_mm",
];
const END_KEYS: [&str; 3] = ["z", "a", "b"];
const VALIDATION_KEYS: [&str; 9] = [
    "slices",
    "positions",
    "widths",
    "methods",
    "runs",
    "margin_mm",
    "alpha",
    "rope_overlap",
    "rope_mm",
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
                    "expected an integer in {min}..={max}, found {}{}",
                    self.show(v),
                    if matches!(v.get_ref(), DeValue::Float(_)) {
                        " (a float: write an integer without a decimal point or exponent)"
                    } else {
                        ""
                    }
                ),
            )),
        }
    }

    /// A boolean (`true` or `false`).
    fn boolean(&self, v: &Value<'_>, field: &str) -> Result<bool, SpecError> {
        match v.get_ref() {
            DeValue::Boolean(b) => Ok(*b),
            _ => Err(self.error(
                v.span(),
                field,
                format!("expected true or false, found {}", self.show(v)),
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

    /// The optional ropes `rope_overlap` (Dice, in [0, 1]) and `rope_mm`
    /// (distances, in [0, 100] mm) of `section`, by default
    /// [`ImplantRopes::default`].
    fn ropes(&self, t: &Table<'_>, section: &str) -> Result<ImplantRopes, SpecError> {
        let mut ropes = ImplantRopes::default();
        for (key, hi, slot) in [
            ("rope_overlap", 1.0, &mut ropes.overlap),
            ("rope_mm", 100.0, &mut ropes.distance_mm),
        ] {
            let Some(v) = self.get(t, key) else { continue };
            let field = format!("{section}.{key}");
            let x = self.finite_real(v, &field)?;
            if !(0.0..=hi).contains(&x) {
                return Err(self.error(
                    v.span(),
                    &field,
                    format!(
                        "expected a rope half-width in [0, {hi}], found {}",
                        self.show(v)
                    ),
                ));
            }
            *slot = x;
        }
        Ok(ropes)
    }

    /// The optional significance level `field` of table `t`: a real
    /// strictly between 0 and 1, by default [`DEFAULT_ALPHA`].
    fn alpha(&self, t: &Table<'_>, field: &str) -> Result<f64, SpecError> {
        let Some(v) = self.get(t, "alpha") else {
            return Ok(DEFAULT_ALPHA);
        };
        let a = self.finite_real(v, field)?;
        if a > 0.0 && a < 1.0 {
            Ok(a)
        } else {
            Err(self.error(
                v.span(),
                field,
                format!(
                    "expected a significance level strictly between 0 and 1, found {}",
                    self.show(v)
                ),
            ))
        }
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
        let mut rc = [0.0; 2];
        for (i, x) in a.iter().enumerate() {
            rc[i] = self.finite_real(x, field)?;
            if rc[i] < 0.0 {
                return Err(self.error(
                    x.span(),
                    field,
                    format!(
                        "expected a pixel {} ≥ 0 (rows and columns count from the image's top left), found {}",
                        ["row", "column"][i],
                        self.show(x)
                    ),
                ));
            }
        }
        Ok((rc[0], rc[1]))
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

    /// `[first, last]` slice numbers with `first ≤ last`.
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
        if z1 < z0 {
            return Err(self.error(
                v.span(),
                field,
                format!("expected first ≤ last, found [{z0}, {z1}]"),
            ));
        }
        Ok((z0, z1))
    }

    fn implant_spec(&self) -> Result<ImplantSpec, SpecError> {
        let doc = self.toml()?;
        let root = doc.get_ref();
        self.check_keys(
            root,
            "",
            &["implant", "defect", "validation", "validation_3d", "checks"],
        )?;
        let imp = self
            .get(root, "implant")
            .ok_or_else(|| self.error(0..0, "implant", "missing section [implant]".into()))?;
        let mut implant = self.implant_section(self.table(imp, "implant")?)?;
        if let Some(c) = self.get(root, "checks") {
            self.checks_section(c, &mut implant.config.wall.checks)?;
        }
        let defect = match self.get(root, "defect") {
            Some(d) => Some(self.defect_section(d, &mut implant.config)?),
            None => None,
        };
        let validation = match self.get(root, "validation") {
            Some(v) => Some(self.validation_section(v, &implant.method)?),
            None => None,
        };
        let validation_3d = match self.get(root, "validation_3d") {
            Some(v) => Some(self.validation_3d_section(v, &implant.method)?),
            None => None,
        };
        if defect.is_none() && validation.is_none() && validation_3d.is_none() {
            return Err(self.error(
                0..0,
                "",
                "nothing to run: add a [defect], [validation] or [validation_3d] section".into(),
            ));
        }
        self.check_midline_source(&implant.config, imp)?;
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
            validation_3d,
        })
    }

    /// An estimated midline needs slices: `midline_slices`, or defect
    /// slices, several of them (one defect slice is no symmetric sample).
    fn check_midline_source(&self, cfg: &DefectConfig, imp: &Value<'_>) -> Result<(), SpecError> {
        if let MidlineSpec::Auto(zs) = &cfg.midline {
            if zs.is_empty() && cfg.slices.len() < 2 {
                let what = if cfg.slices.is_empty() {
                    "without a [defect] section"
                } else {
                    "for a one-slice study"
                };
                let span = self
                    .table(imp, "implant")
                    .ok()
                    .and_then(|t| self.get(t, "midline"))
                    .map_or(imp.span(), |v| v.span());
                return Err(self.error(
                    span,
                    "implant.midline",
                    format!("`midline = \"auto\"` {what} needs `midline_slices` (intact slices to estimate it from); or give `midline` in mm"),
                ));
            }
        }
        Ok(())
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
        let real_or = |k: &str, d: f64, min: f64| -> Result<f64, SpecError> {
            match self.get(imp, k) {
                None => Ok(d),
                Some(v) => {
                    let x = self.finite_real(v, &format!("implant.{k}"))?;
                    if x < min {
                        return Err(self.error(
                            v.span(),
                            &format!("implant.{k}"),
                            format!("expected a number ≥ {min}, found {x}"),
                        ));
                    }
                    Ok(x)
                }
            }
        };
        let mut wall = wall;
        wall.tangent_mm = real_or("tangent_mm", wall.tangent_mm, 0.5)?;
        wall.seat_bend_deg = real_or("seat_bend_deg", wall.seat_bend_deg, 0.0)?;
        wall.seat_max_mm = real_or("seat_max_mm", wall.seat_max_mm, 0.0)?;
        wall.thickness_setback_mm =
            real_or("thickness_setback_mm", wall.thickness_setback_mm, 0.0)?;
        wall.max_thickness_mm = real_or("max_thickness_mm", wall.max_thickness_mm, 0.1)?;
        let smoothing = Smoothing {
            max_thickness_step_mm: real_or(
                "max_thickness_step_mm",
                Smoothing::default().max_thickness_step_mm,
                0.0,
            )?,
            wall_half_width: int_or(
                "smooth_slices",
                Smoothing::default().wall_half_width as i64,
                0,
                20,
            )? as usize,
            seat_change_deg_per_mm: real_or(
                "seat_change_deg_per_mm",
                Smoothing::default().seat_change_deg_per_mm,
                0.0,
            )?,
        };
        let max_tilt_deg = real_or("max_tilt_deg", 20.0, 0.0)?.min(45.0);
        Ok(ImplantSection {
            volume,
            volume_label,
            method,
            seed,
            config: DefectConfig {
                first_z,
                slices: Vec::new(),
                midline,
                max_tilt_deg,
                threshold,
                wall,
                smoothing,
                templates: None,
                plane: None,
                ring_points: 160,
                thickness_mm: None,
            },
        })
    }

    /// `implant.function`, `implant.continuity` and
    /// `implant.template_source` (default `mirror`, the thesis's technique,
    /// as [`WallOptions::default`]: going beyond the thesis is asked for)
    /// on the default wall options with `budget`.
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
        wall.template = match self.get(imp, "template_source") {
            None => TemplateChoice::Mirror,
            Some(v) => {
                let s = self.string(v, "implant.template_source")?;
                TemplateChoice::from_name(&s).ok_or_else(|| {
                    self.error(
                        v.span(),
                        "implant.template_source",
                        format!(
                            "unknown template source \"{s}\"; valid choices: {} (\"mirror\", the default: the thesis's technique; \"auto\": the mirror, and the continuation of both sides where the mirror cannot serve a defect, across or next to the midline; \"mirror3d\": the outer table mirrored across the mid-sagittal plane found in 3D; \"rim\": a thin-plate spline surface through the bone around the defect; \"auto3d\": per slice the 3D mirror where it serves, else the rim fill (the 3D choices need a volume of at least 3 slices); an explicit template file is `[defect] template`)",
                            quoted(&TemplateChoice::NAMES)
                        ),
                    )
                })?
            }
        };
        if let Some(v) = self.get(imp, "fill_ends") {
            wall.fill_ends = self.boolean(v, "implant.fill_ends")?;
        }
        if let Some(v) = self.get(imp, "thickness_profile") {
            let s = self.string(v, "implant.thickness_profile")?;
            wall.thickness_profile = ThicknessProfile::from_name(&s).ok_or_else(|| {
                self.error(
                    v.span(),
                    "implant.thickness_profile",
                    format!(
                        "unknown thickness profile \"{s}\"; valid choices: {} (\"linear\", the default: Dis(u) from t_A to t_B; \"mirror\": the other side's bone thickness across the gap)",
                        quoted(&ThicknessProfile::NAMES)
                    ),
                )
            })?;
        }
        Ok(wall)
    }

    /// `implant.midline` (`"auto"`, M_x in mm for a vertical line, or
    /// `[x_mm, y_mm, tilt_deg]`) and `implant.midline_slices`.
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
            Some(v) => {
                match v.get_ref() {
                    DeValue::String(s) if s.as_ref() == "auto" => MidlineSpec::Auto(midline_slices),
                    DeValue::Integer(_) | DeValue::Float(_) => MidlineSpec::Given(
                        MidLine::vertical(self.finite_real(v, "implant.midline")?),
                    ),
                    DeValue::Array(a) if a.len() == 3 => {
                        let a = self.array(v, "implant.midline")?;
                        let f = |i: usize| self.finite_real(a[i], &format!("implant.midline[{i}]"));
                        let tilt = f(2)?;
                        if tilt.abs() > 45.0 {
                            return Err(self.error(
                            a[2].span(),
                            "implant.midline[2]",
                            format!("expected a tilt from vertical in -45..=45 degrees, found {tilt}"),
                        ));
                        }
                        MidlineSpec::Given(MidLine {
                            point: Point::new(f(0)?, f(1)?),
                            tilt: tilt.to_radians(),
                        })
                    }
                    _ => {
                        return Err(self.error(
                            v.span(),
                            "implant.midline",
                            format!(
                                "expected \"auto\", M_x in mm or [x_mm, y_mm, tilt_deg], found {}",
                                self.show(v)
                            ),
                        ))
                    }
                }
            }
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
        if let Some(v) = self.get(d, "thickness_mm") {
            let x = self.finite_real(v, "defect.thickness_mm")?;
            if !(x > 0.0 && x <= 50.0) {
                return Err(self.error(
                    v.span(),
                    "defect.thickness_mm",
                    format!("expected a slab thickness in mm, 0 < t ≤ 50, found {x}"),
                ));
            }
            cfg.thickness_mm = Some(x);
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
        if let Some(v) = self.get(d, "template") {
            let label = self.string(v, "defect.template")?;
            let base = self.path.parent().unwrap_or(Path::new("."));
            cfg.templates = Some(read_templates(&base.join(&label), (z0, z1))?);
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
            alpha: self.alpha(t, "validation.alpha")?,
            ropes: self.ropes(t, "validation")?,
        })
    }
}

impl Parser<'_> {
    /// The `[validation_3d]` section; its methods default to `[method]`.
    fn validation_3d_section(
        &self,
        v: &Value<'_>,
        method: &Method,
    ) -> Result<Validation3dSpec, SpecError> {
        let t = self.table(v, "validation_3d")?;
        self.check_keys(t, "validation_3d", &VALIDATION_3D_KEYS)?;
        let need = |k: &str| {
            self.get(t, k).ok_or_else(|| {
                self.error(
                    v.span(),
                    &format!("validation_3d.{k}"),
                    format!("missing field `{k}`"),
                )
            })
        };
        let mut ranges = Vec::new();
        for (i, r) in self
            .array(need("ranges")?, "validation_3d.ranges")?
            .iter()
            .enumerate()
        {
            let f = format!("validation_3d.ranges[{i}]");
            let (z0, z1) = self.range(r, &f)?;
            if z1 - z0 < 2 {
                return Err(self.error(
                    r.span(),
                    &f,
                    format!("expected a patch of at least 3 slices, found [{z0}, {z1}]"),
                ));
            }
            ranges.push((z0, z1));
        }
        let reals = |k: &str, positive: bool| -> Result<Vec<f64>, SpecError> {
            let f = format!("validation_3d.{k}");
            let a = self.array(need(k)?, &f)?;
            a.iter()
                .enumerate()
                .map(|(i, x)| {
                    let y = self.finite_real(x, &format!("{f}[{i}]"))?;
                    if positive && y <= 0.0 {
                        return Err(self.error(
                            x.span(),
                            &format!("{f}[{i}]"),
                            "expected a width > 0 mm".into(),
                        ));
                    }
                    Ok(y)
                })
                .collect()
        };
        let methods = match self.get(t, "methods") {
            None => vec![method.clone()],
            Some(m) => self
                .array(m, "validation_3d.methods")?
                .iter()
                .enumerate()
                .map(|(i, x)| self.method(x, &format!("validation_3d.methods[{i}]")))
                .collect::<Result<Vec<_>, _>>()?,
        };
        Ok(Validation3dSpec {
            ranges,
            positions: reals("positions", false)?,
            widths: reals("widths", true)?,
            methods,
            runs: match self.get(t, "runs") {
                None => 5,
                Some(x) => self.int(x, "validation_3d.runs", 1, 100_000)? as usize,
            },
            margin_mm: match self.get(t, "margin_mm") {
                None => 10.0,
                Some(x) => self.finite_real(x, "validation_3d.margin_mm")?,
            },
            alpha: self.alpha(t, "validation_3d.alpha")?,
            ropes: self.ropes(t, "validation_3d")?,
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
        Parser(metabezier_spec::Parser { path, text }).implant_spec()
    }

    /// Reads and parses the spec file.
    pub fn load(path: &Path) -> Result<ImplantSpec, SpecError> {
        let text = SpecError::read(path)?;
        Self::parse(path, &text)
    }
}
