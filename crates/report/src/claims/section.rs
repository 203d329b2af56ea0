//! The claims section of a report's summary, rendered from the answers
//! of [`super::answers`]: a paragraph on the primary rows and a table of
//! the claims with their rows and verdicts.

use std::path::Path;

use super::super::format::{effect_interval, p_value, posterior};
use super::{answers, Claim, ClaimError};
use crate::stats::VerdictRow;

/// The claims of `campaign` answered by their primary rows: the summary's
/// section (empty when the file has no claim of this campaign), or the
/// error naming a claim whose row is missing.
pub(crate) fn section(
    path: &Path,
    claims: &[Claim],
    campaign: &str,
    rows: &[VerdictRow],
    alpha: f64,
) -> Result<String, ClaimError> {
    let answers = answers(path, claims, campaign, rows, alpha)?;
    if answers.is_empty() {
        return Ok(String::new());
    }
    let mut md = format!(
        "### The thesis's claims (primary rows)\n\nEach claim of the thesis that this campaign \
         answers, with its one primary row of tables/verdicts.csv (from {}); every other row \
         of this report is exploratory. The primary rows were chosen after the data were \
         seen. The claims' family is their primary rows: p (primary Holm) corrects over the \
         {} primary row(s) of this campaign, and the verdict is decided on it (equivalent \
         where P(≈) ≥ 0.95; better or worse where p (primary Holm) < α; else undecided); \
         p_Holm (family) is the row's exploratory correction within its table and scope.\n\n",
        path.display(),
        answers.len()
    );
    md.push_str(
        "| Claim | Primary row | Units +/=/− | HL [95 % CI] | p_Holm (family) | p (primary Holm) \
         | P(better/≈/worse) | Verdict | The claim |\n| :-- | :-- | --: | --: | --: | --: | --: \
         | :-- | :-- |\n",
    );
    for answer in &answers {
        let r = answer.row;
        let a = &r.across;
        let e = &r.equivalence;
        md.push_str(&format!(
            "| {} | {} against {}, {}, `{}` | {}/{}/{} | {} | {} ({}) | {} | {} | {} | {} |\n",
            answer.claim.claim,
            r.algorithm,
            r.reference,
            r.measure,
            r.scope,
            a.better,
            a.equal,
            a.worse,
            effect_interval(r.shift.estimate, r.shift.low, r.shift.high),
            p_value(r.p_adjusted),
            r.family,
            p_value(answer.primary_holm),
            posterior(e.better, e.within, e.worse),
            answer.verdict,
            answer.reading
        ));
    }
    md.push('\n');
    Ok(md)
}
