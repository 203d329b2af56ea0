//! Named choices parsed once, at the command line: clap checks the name
//! against the type's `NAMES` and hands the command the typed value, so no
//! command parses a name again (issue 54's typed boundaries).

use std::ffi::OsStr;
use std::marker::PhantomData;

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::error::ErrorKind;

use crate::fit::{Chain, Closing, ErrorMeasure, FunctionType, SearchSpace};
use crate::geometry::{Continuity, Parameterisation};
use crate::outline::Foreground;
use crate::report::PostHoc;

/// A choice a command line names: its names (the help's possible values,
/// in order) and the value of each.
pub(super) trait Named: Copy + Send + Sync + 'static {
    /// Every name, as the help lists them.
    const NAMES: &'static [&'static str];
    /// The value a name stands for.
    fn from_name(name: &str) -> Option<Self>;
}

/// Implements [`Named`] for library types that carry `NAMES` and
/// `from_name` of their own.
macro_rules! named {
    ($($t:ty),* $(,)?) => {$(
        impl Named for $t {
            const NAMES: &'static [&'static str] = &<$t>::NAMES;
            fn from_name(name: &str) -> Option<Self> {
                <$t>::from_name(name)
            }
        }
    )*};
}

named!(
    FunctionType,
    Continuity,
    Closing,
    SearchSpace,
    ErrorMeasure,
    Chain,
    Foreground,
    PostHoc
);

/// `--parameterisation`: the data's own choice (`auto`) or a fixed one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum ParameterisationChoice {
    /// Uniform for a glyph at its true breaks, chord length otherwise.
    Auto,
    /// The parameterisation named.
    Fixed(Parameterisation),
}

impl Named for ParameterisationChoice {
    const NAMES: &'static [&'static str] = &[
        "auto",
        Parameterisation::NAMES[0],
        Parameterisation::NAMES[1],
        Parameterisation::NAMES[2],
    ];
    fn from_name(name: &str) -> Option<Self> {
        match name {
            "auto" => Some(ParameterisationChoice::Auto),
            _ => Parameterisation::from_name(name).map(ParameterisationChoice::Fixed),
        }
    }
}

/// clap's parser of a [`Named`] choice: the possible-values check and
/// message of [`PossibleValuesParser`], then the typed value.
#[derive(Clone, Copy, Debug)]
pub(super) struct NamedParser<T>(PhantomData<fn() -> T>);

/// The parser of `T`'s names, for `#[arg(value_parser = named::<T>())]`.
pub(super) fn named<T: Named>() -> NamedParser<T> {
    NamedParser(PhantomData)
}

impl<T: Named> TypedValueParser for NamedParser<T> {
    type Value = T;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &OsStr,
    ) -> Result<T, clap::Error> {
        let name =
            PossibleValuesParser::new(T::NAMES.iter().copied()).parse_ref(cmd, arg, value)?;
        T::from_name(&name).ok_or_else(|| {
            clap::Error::raw(
                ErrorKind::InvalidValue,
                format!(
                    "\"{name}\" is a listed name that names no value; the names: {}\n",
                    T::NAMES.join(", ")
                ),
            )
        })
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        Some(Box::new(T::NAMES.iter().map(|n| PossibleValue::new(*n))))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every listed name parses to a value whose own name it is.
    fn round_trips<T: Named>() {
        for name in T::NAMES {
            assert!(T::from_name(name).is_some(), "{name} names no value");
        }
    }

    #[test]
    fn every_listed_name_names_a_value() {
        round_trips::<FunctionType>();
        round_trips::<Continuity>();
        round_trips::<Closing>();
        round_trips::<SearchSpace>();
        round_trips::<ErrorMeasure>();
        round_trips::<Chain>();
        round_trips::<Foreground>();
        round_trips::<PostHoc>();
        round_trips::<ParameterisationChoice>();
    }
}
