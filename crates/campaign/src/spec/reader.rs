//! The spec reader's state: the grammar, the limits and the registry
//! every section reader of a campaign spec works with.

use std::ops::Deref;

use super::SpecLimits;
use crate::registry::Registry;

/// The spec reader: the grammar's [`metabezier_spec::Parser`] (the file's
/// path and text, for errors located by line and column, and the
/// primitives: fields, tables, strings, numbers, known keys), reached
/// through `Deref`, with the limits and the registry a campaign spec is
/// read under.
pub(crate) struct Parser<'a> {
    /// The file and its text, and the grammar's primitives.
    pub(crate) grammar: metabezier_spec::Parser<'a>,
    /// The limits of runs and budgets.
    pub(crate) limits: SpecLimits,
    /// The optimisers and problems names resolve in.
    pub(crate) registry: &'a Registry,
}

impl<'a> Deref for Parser<'a> {
    type Target = metabezier_spec::Parser<'a>;

    fn deref(&self) -> &Self::Target {
        &self.grammar
    }
}
