//! Declared, validated algorithm parameters.
//!
//! Each optimiser declares its parameters as a table of [`ParamDef`]s (name,
//! meaning, admissible range and default). Experiment specs are checked
//! against these tables before anything runs, and a run's parameters are
//! recorded as the canonical text [`ParamSet::canonical`].

use std::borrow::Cow;
use std::fmt;
use std::marker::PhantomData;

/// The admissible values of one parameter.
#[derive(Clone, Copy, Debug)]
pub enum Kind {
    /// An integer in `min..=max`.
    Count {
        /// Smallest admissible value.
        min: u64,
        /// Largest admissible value.
        max: u64,
    },
    /// A finite real number in `[min, max]`, or `(min, max]` when `open_min`.
    Real {
        /// Lower end of the range.
        min: f64,
        /// Upper end of the range.
        max: f64,
        /// Whether `min` itself is excluded.
        open_min: bool,
    },
    /// One of a fixed set of names.
    Choice(&'static [&'static str]),
    /// A `+`-separated list of names from a fixed set, such as `"hs+ga+pso"`.
    Sequence(&'static [&'static str]),
}

/// A resolved parameter value.
#[derive(Clone, Debug, PartialEq)]
pub enum Setting {
    /// An integer.
    Count(u64),
    /// A real number.
    Real(f64),
    /// A name from a [`Kind::Choice`].
    Choice(&'static str),
    /// Names from a [`Kind::Sequence`], in order.
    Sequence(Cow<'static, [&'static str]>),
}

impl fmt::Display for Setting {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Setting::Count(n) => write!(f, "{n}"),
            Setting::Real(x) => write!(f, "{x}"),
            Setting::Choice(s) => f.write_str(s),
            Setting::Sequence(v) => f.write_str(&v.join("+")),
        }
    }
}

impl Setting {
    /// The value as a spec would write it, so that it can be checked
    /// against a declaration again (a registered default, say).
    pub fn to_raw(&self) -> Raw {
        match self {
            Setting::Count(n) => i64::try_from(*n).map_or(Raw::Float(*n as f64), Raw::Int),
            Setting::Real(x) => Raw::Float(*x),
            Setting::Choice(s) => Raw::Text((*s).to_owned()),
            Setting::Sequence(v) => Raw::Text(v.join("+")),
        }
    }
}

/// The key of a declared parameter whose values are of type `T`: the one
/// place its name is written, used both in its [`ParamDef`] (`name:
/// KEY.name`) and to read it ([`ParamSet::get`]), so that a misspelt
/// name or a value read as the wrong kind is a compile error.
pub struct Param<T> {
    /// The parameter's name in specs.
    pub name: &'static str,
    kind: PhantomData<fn() -> T>,
}

impl<T> Param<T> {
    /// The key of the parameter `name`.
    pub const fn new(name: &'static str) -> Self {
        Param {
            name,
            kind: PhantomData,
        }
    }
}

impl<T> Clone for Param<T> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<T> Copy for Param<T> {}

impl<T> fmt::Debug for Param<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Param({})", self.name)
    }
}

/// A type a parameter's [`Setting`] is read as.
pub trait ParamValue: Sized {
    /// The kind's name, for the panic of a mismatched key.
    const KIND: &'static str;
    /// The value, if `s` is of this kind.
    fn of(s: &Setting) -> Option<Self>;
}

impl ParamValue for u64 {
    const KIND: &'static str = "a count";
    fn of(s: &Setting) -> Option<Self> {
        match s {
            Setting::Count(n) => Some(*n),
            _ => None,
        }
    }
}

impl ParamValue for f64 {
    const KIND: &'static str = "a real";
    fn of(s: &Setting) -> Option<Self> {
        match s {
            Setting::Real(x) => Some(*x),
            _ => None,
        }
    }
}

impl ParamValue for &'static str {
    const KIND: &'static str = "a choice";
    fn of(s: &Setting) -> Option<Self> {
        match s {
            Setting::Choice(c) => Some(c),
            _ => None,
        }
    }
}

impl ParamValue for Vec<&'static str> {
    const KIND: &'static str = "a sequence";
    fn of(s: &Setting) -> Option<Self> {
        match s {
            Setting::Sequence(v) => Some(v.to_vec()),
            _ => None,
        }
    }
}

/// A raw value from a spec, before validation.
#[derive(Clone, Debug, PartialEq)]
pub enum Raw {
    /// A TOML integer.
    Int(i64),
    /// A TOML float.
    Float(f64),
    /// A TOML string.
    Text(String),
    /// Any other TOML type, by its name (`"boolean"`, `"table"`, ...).
    Other(&'static str),
}

impl Raw {
    /// The value as an error names it where an integer was expected: a
    /// float is called a float (`1e3` reads as 1000.0, not 1000), with the
    /// integer to write instead when it is one.
    pub fn found_for_integer(&self) -> String {
        match self {
            Raw::Float(x) if x.is_finite() && x.fract() == 0.0 && x.abs() < 9.0e15 => format!(
                "the float {x:?} (write an integer without a decimal point or exponent: {})",
                *x as i64
            ),
            Raw::Float(x) => format!("the float {x:?}"),
            other => other.to_string(),
        }
    }

    /// The value as a real number, for a TOML integer or float (the values
    /// a [`Kind::Real`] parameter admits); `None` for any other type.
    pub fn as_real(&self) -> Option<f64> {
        match self {
            Raw::Int(n) => Some(*n as f64),
            Raw::Float(x) => Some(*x),
            Raw::Text(_) | Raw::Other(_) => None,
        }
    }
}

impl fmt::Display for Raw {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Raw::Int(n) => write!(f, "{n}"),
            Raw::Float(x) => write!(f, "{x}"),
            Raw::Text(s) => write!(f, "\"{s}\""),
            Raw::Other(t) => write!(f, "a {t}"),
        }
    }
}

/// The declaration of one algorithm parameter.
#[derive(Clone, Debug)]
pub struct ParamDef {
    /// The key used in specs and in the canonical text.
    pub name: &'static str,
    /// What it means, with its symbol in the literature.
    pub doc: &'static str,
    /// Admissible values.
    pub kind: Kind,
    /// The value used when a spec does not give one.
    pub default: Setting,
    /// Whether the canonical text leaves this parameter out while it has
    /// its default value: set for parameters added after results were
    /// recorded, so that the keys, seeds and `params` columns of existing
    /// campaigns do not change.
    pub omit_at_default: bool,
}

impl ParamDef {
    /// What this parameter admits, as a phrase for error messages.
    pub fn expected(&self) -> String {
        match self.kind {
            Kind::Count { min, max } if max == u64::MAX => format!("an integer ≥ {min}"),
            Kind::Count { min, max } => format!("an integer in {min}..={max}"),
            Kind::Real { min, max, open_min } => {
                let lo = if open_min { "(" } else { "[" };
                let fmt_end = |x: f64| {
                    if x.is_infinite() {
                        if x > 0.0 { "∞" } else { "−∞" }.to_string()
                    } else {
                        format!("{x}")
                    }
                };
                format!("a real number in {lo}{}, {}]", fmt_end(min), fmt_end(max))
            }
            Kind::Choice(names) => format!("one of {}", quoted_list(names)),
            Kind::Sequence(names) => format!(
                "a \"+\"-separated list of {}, such as \"{}\"",
                quoted_list(names),
                names.join("+")
            ),
        }
    }

    /// Checks a raw spec value against this declaration.
    pub fn check(&self, raw: &Raw) -> Result<Setting, SettingError> {
        let bad = || SettingError::Inadmissible {
            expected: self.expected(),
            found: match self.kind {
                Kind::Count { .. } => raw.found_for_integer(),
                _ => raw.to_string(),
            },
        };
        match (self.kind, raw, raw.as_real()) {
            (Kind::Count { min, max }, Raw::Int(n), _) => {
                let n = u64::try_from(*n).map_err(|_| bad())?;
                if n < min || n > max {
                    return Err(bad());
                }
                Ok(Setting::Count(n))
            }
            (Kind::Real { min, max, open_min }, _, Some(x)) => {
                let above = if open_min { x > min } else { x >= min };
                if !x.is_finite() || !above || x > max {
                    return Err(bad());
                }
                Ok(Setting::Real(x))
            }
            (Kind::Choice(names), Raw::Text(s), _) => names
                .iter()
                .find(|n| **n == s)
                .map(|n| Setting::Choice(n))
                .ok_or_else(bad),
            (Kind::Sequence(names), Raw::Text(s), _) => {
                let mut out = Vec::new();
                for part in s.split('+') {
                    let part = part.trim();
                    match names.iter().find(|n| **n == part) {
                        Some(n) => out.push(*n),
                        None => return Err(bad()),
                    }
                }
                Ok(Setting::Sequence(Cow::Owned(out)))
            }
            _ => Err(bad()),
        }
    }
}

/// A raw value that a parameter does not admit, or an unknown parameter.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SettingError {
    /// The value is not admissible for the parameter.
    #[error("expected {expected}, found {found}")]
    Inadmissible {
        /// What the parameter admits ([`ParamDef::expected`]).
        expected: String,
        /// The value found, as written in the spec.
        found: String,
    },
    /// The algorithm has no parameter of this name.
    #[error("unknown parameter \"{0}\"")]
    Unknown(String),
}

/// `"a", "b" or "c"`.
pub fn quoted_list(names: &[&str]) -> String {
    let quoted: Vec<String> = names.iter().map(|n| format!("\"{n}\"")).collect();
    match quoted.len() {
        0 => String::new(),
        1 => quoted[0].clone(),
        n => format!("{} or {}", quoted[..n - 1].join(", "), quoted[n - 1]),
    }
}

/// A complete, validated assignment of an algorithm's parameters.
#[derive(Clone, Debug)]
pub struct ParamSet {
    defs: &'static [ParamDef],
    values: Vec<Setting>,
}

impl ParamSet {
    /// All parameters at their defaults.
    pub fn defaults(defs: &'static [ParamDef]) -> Self {
        Self {
            defs,
            values: defs.iter().map(|d| d.default.clone()).collect(),
        }
    }

    /// The declarations this set follows.
    pub fn defs(&self) -> &'static [ParamDef] {
        self.defs
    }

    /// Sets one parameter from a raw value; the error names what was expected.
    pub fn set(&mut self, name: &str, raw: &Raw) -> Result<(), SettingError> {
        let i = self
            .defs
            .iter()
            .position(|d| d.name == name)
            .ok_or_else(|| SettingError::Unknown(name.to_owned()))?;
        self.values[i] = self.defs[i].check(raw)?;
        Ok(())
    }

    /// Sets a parameter to an already validated value (panics if `name` is
    /// not declared: a programming error).
    pub fn put(&mut self, name: &str, value: Setting) {
        let i = self
            .defs
            .iter()
            .position(|d| d.name == name)
            .unwrap_or_else(|| panic!("parameter {name} is not declared"));
        self.values[i] = value;
    }

    fn value(&self, name: &str) -> &Setting {
        let i = self
            .defs
            .iter()
            .position(|d| d.name == name)
            .unwrap_or_else(|| panic!("parameter {name} is not declared"));
        &self.values[i]
    }

    /// The value of the declared parameter `key`, of the key's kind.
    ///
    /// Panics if this set does not declare `key` with that kind: a
    /// programming error (the key of another optimiser's parameters), not a
    /// user error; a misspelt key does not compile.
    pub fn get<T: ParamValue>(&self, key: Param<T>) -> T {
        let value = self.value(key.name);
        T::of(value)
            .unwrap_or_else(|| panic!("parameter {} is {value:?}, not {}", key.name, T::KIND))
    }

    /// `name=value;name=value;...` in declaration order: the stable text that
    /// identifies a parameter cell in `runs.csv` and in seed derivation.
    /// Parameters marked [`ParamDef::omit_at_default`] appear only when they
    /// differ from their default.
    pub fn canonical(&self) -> String {
        let parts: Vec<String> = self
            .defs
            .iter()
            .zip(&self.values)
            .filter(|(d, v)| !(d.omit_at_default && **v == d.default))
            .map(|(d, v)| format!("{}={v}", d.name))
            .collect();
        parts.join(";")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    static DEFS: [ParamDef; 4] = [
        ParamDef {
            name: "hms",
            doc: "memory size",
            kind: Kind::Count {
                min: 1,
                max: u64::MAX,
            },
            default: Setting::Count(5),
            omit_at_default: false,
        },
        ParamDef {
            name: "hmcr",
            doc: "rate",
            kind: Kind::Real {
                min: 0.0,
                max: 1.0,
                open_min: false,
            },
            default: Setting::Real(0.9),
            omit_at_default: false,
        },
        ParamDef {
            name: "bounds",
            doc: "policy",
            kind: Kind::Choice(&["clip", "reflect"]),
            default: Setting::Choice("clip"),
            omit_at_default: false,
        },
        ParamDef {
            name: "operators",
            doc: "ops",
            kind: Kind::Sequence(&["hs", "ga", "pso"]),
            default: Setting::Sequence(Cow::Borrowed(&["hs"])),
            omit_at_default: false,
        },
    ];

    #[test]
    fn integers_and_floats_are_reals_and_nothing_else_is() {
        assert_eq!(Raw::Int(-3).as_real(), Some(-3.0));
        assert_eq!(Raw::Float(0.25).as_real(), Some(0.25));
        assert_eq!(Raw::Text("0.5".into()).as_real(), None);
        assert_eq!(Raw::Other("boolean").as_real(), None);
        let real = &DEFS[1];
        assert_eq!(real.check(&Raw::Int(1)), Ok(Setting::Real(1.0)));
        assert!(real.check(&Raw::Text("0.5".into())).is_err());
    }

    #[test]
    fn checks_ranges_and_types_with_clear_messages() {
        let mut p = ParamSet::defaults(&DEFS);
        assert_eq!(
            p.set("hmcr", &Raw::Float(1.5)).unwrap_err().to_string(),
            "expected a real number in [0, 1], found 1.5"
        );
        assert_eq!(
            p.set("hms", &Raw::Int(0)).unwrap_err().to_string(),
            "expected an integer ≥ 1, found 0"
        );
        assert_eq!(
            p.set("hms", &Raw::Float(2.5)).unwrap_err().to_string(),
            "expected an integer ≥ 1, found the float 2.5"
        );
        assert_eq!(
            p.set("hms", &Raw::Float(5.0)).unwrap_err().to_string(),
            "expected an integer ≥ 1, found the float 5.0 (write an integer without a decimal point or exponent: 5)"
        );
        assert_eq!(
            p.set("bounds", &Raw::Text("wrap".into()))
                .unwrap_err()
                .to_string(),
            "expected one of \"clip\" or \"reflect\", found \"wrap\""
        );
        assert_eq!(
            p.set("operators", &Raw::Text("hs+de".into())).unwrap_err().to_string(),
            "expected a \"+\"-separated list of \"hs\", \"ga\" or \"pso\", such as \"hs+ga+pso\", found \"hs+de\""
        );
        assert_eq!(
            p.set("hmc", &Raw::Int(1)).unwrap_err().to_string(),
            "unknown parameter \"hmc\""
        );
        p.set("hmcr", &Raw::Int(1)).unwrap();
        p.set("operators", &Raw::Text("ga + pso".into())).unwrap();
        assert_eq!(p.canonical(), "hms=5;hmcr=1;bounds=clip;operators=ga+pso");
        assert_eq!(p.get(Param::<Vec<&str>>::new("operators")), ["ga", "pso"]);
    }
}
