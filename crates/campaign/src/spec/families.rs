//! The problem families a registry offers a spec: COCO's bbob, built in,
//! then those a library user registers ([`Registry::register_family`]).
//! The registry sits below the spec and keeps a registered family behind
//! `Any`; this file, which knows [`ProblemFamily`], registers and reads
//! them.

use std::sync::Arc;

use super::bbob::BbobSuite;
use super::family::ProblemFamily;
use crate::registry::{spec_name, Registry};

/// The families every registry has, in the order `metabezier list` shows
/// them.
static BUILTIN: [&(dyn ProblemFamily + 'static); 1] = [&BbobSuite];

/// Why a problem family cannot be registered.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum FamilyRegistryError {
    /// An earlier family has the suite name.
    #[error("a suite named \"{0}\" already exists (the registered suites: {1})")]
    Taken(String, String),
    /// The suite name is not one a spec can write.
    #[error("\"{0}\" cannot name a suite: expected 1 to 60 ASCII letters, digits, '_' or '-', starting with a letter")]
    BadName(String),
}

impl Registry {
    /// Adds a problem family, read from a `[[problem]]` whose `suite` is
    /// its [`ProblemFamily::suite`]; refuses a suite name an earlier family
    /// has, or one a spec cannot write.
    pub fn register_family(
        &mut self,
        family: Arc<dyn ProblemFamily>,
    ) -> Result<(), FamilyRegistryError> {
        let name = family.suite();
        if !spec_name(name) {
            return Err(FamilyRegistryError::BadName(name.to_owned()));
        }
        if self.family(name).is_some() {
            let suites = self.suites().join(", ");
            return Err(FamilyRegistryError::Taken(name.to_owned(), suites));
        }
        self.push_family_slot(Arc::new(family));
        Ok(())
    }

    /// The family of `suite = "<suite>"`.
    pub fn family(&self, suite: &str) -> Option<&dyn ProblemFamily> {
        self.families().find(|f| f.suite() == suite)
    }

    /// The families, COCO's bbob first, then the registered ones in
    /// registration order.
    pub fn families(&self) -> impl Iterator<Item = &dyn ProblemFamily> {
        let registered = self
            .family_slots()
            .iter()
            .filter_map(|slot| slot.downcast_ref::<Arc<dyn ProblemFamily>>())
            .map(|f| &**f);
        BUILTIN.iter().map(|f| &**f).chain(registered)
    }

    /// The names `[[problem]] suite` accepts.
    pub fn suites(&self) -> Vec<&str> {
        self.families().map(|f| f.suite()).collect()
    }
}
