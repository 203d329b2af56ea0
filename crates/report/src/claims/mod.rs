//! Primary endpoints: each thesis claim names the one row of
//! `verdicts.csv` that answers it (campaign, table, measure, algorithm,
//! reference, scope), in a claims file (`experiments/claims.toml`). A
//! report given the file (`--claims`) opens its summary with the primary
//! rows of its campaign, Holm-corrected over them as a family of their own,
//! and marks every other row exploratory; a claim whose row the campaign
//! does not have is an error located in the claims file.
//!
//! Pre-registration is the standard of a confirmatory analysis (Nosek,
//! Ebersole, DeHaven & Mellor 2018, "The preregistration revolution", PNAS
//! 115(11):2600–2606); the thesis's rows were chosen after the data were
//! seen, and the summary says so.

use std::path::Path;

use metabezier_spec::{Parser, SpecError};

use crate::stats::{holm_bonferroni, Verdict, VerdictRow, VerdictTest};

mod section;

pub(crate) use self::section::section;

/// The keys of a `[[claim]]`.
const CLAIM_KEYS: [&str; 11] = [
    "id",
    "holds_if",
    "claim",
    "source",
    "campaign",
    "table",
    "measure",
    "algorithm",
    "reference",
    "scope",
    "note",
];

/// One thesis claim and its primary row.
#[derive(Clone, Debug, PartialEq)]
pub struct Claim {
    /// A short name (`mhs-accuracy`).
    pub id: String,
    /// The claim in words.
    pub claim: String,
    /// Where the thesis makes it.
    pub source: String,
    /// The campaign (`[experiment] name`) whose report answers it.
    pub campaign: String,
    /// The primary row's table, measure, algorithm, reference and scope.
    pub row: [String; 5],
    /// The verdict of the primary row that supports the claim (`better`
    /// or `worse`, from the row's algorithm's point of view: "MHS beats HS"
    /// holds if the row HS against MHS is `worse`).
    pub holds_if: Verdict,
    /// Why this row (optional).
    pub note: String,
    /// The 1-based line of the `[[claim]]`, for errors.
    pub line: usize,
}

/// The claims of the file `path`; an unknown key, a missing one or a value
/// of the wrong type is an error naming the file, line and field.
pub fn read_claims(path: &Path) -> Result<Vec<Claim>, SpecError> {
    let text = SpecError::read(path)?;
    let p = Parser { path, text: &text };
    let doc = p.toml()?;
    let root = doc.get_ref();
    p.check_keys(root, "", &["claim"])?;
    let mut claims = Vec::new();
    for (i, v) in p
        .array_of_tables(root, "claim", doc.span())?
        .into_iter()
        .enumerate()
    {
        let section = format!("claim[{}]", i + 1);
        let t = p.table(v, &section)?;
        p.check_keys(t, &section, &CLAIM_KEYS)?;
        let field = |key: &str| -> Result<String, SpecError> {
            let v = p.required(t, &section, key, v.span())?;
            p.string(v, &format!("{section}.{key}"))
        };
        let holds_v = p.required(t, &section, "holds_if", v.span())?;
        let holds_if = match p.string(holds_v, &format!("{section}.holds_if"))?.as_str() {
            "better" => Verdict::Better,
            "worse" => Verdict::Worse,
            other => {
                return Err(p.error(
                    holds_v.span(),
                    &format!("{section}.holds_if"),
                    format!(
                        "expected \"better\" or \"worse\" (the primary row's verdict that \
                         supports the claim), found \"{other}\""
                    ),
                ))
            }
        };
        let note = match p.get(t, "note") {
            Some(n) => p.string(n, &format!("{section}.note"))?,
            None => String::new(),
        };
        claims.push(Claim {
            id: field("id")?,
            claim: field("claim")?,
            source: field("source")?,
            campaign: field("campaign")?,
            row: [
                field("table")?,
                field("measure")?,
                field("algorithm")?,
                field("reference")?,
                field("scope")?,
            ],
            holds_if,
            note,
            line: p.error(v.span(), "", String::new()).line,
        });
    }
    Ok(claims)
}

/// Why the claims cannot be answered.
#[derive(Debug, thiserror::Error)]
pub enum ClaimError {
    /// The claims file does not load.
    #[error(transparent)]
    Spec(#[from] SpecError),
    /// A claim of this campaign names a row its verdicts do not have: the
    /// claims file and line, the claim, the row, and the scopes the
    /// campaign has for that comparison.
    #[error("{0}")]
    NoRow(String),
}

/// The primary row of `claim` among `rows`.
fn primary<'r>(claim: &Claim, rows: &'r [VerdictRow]) -> Option<&'r VerdictRow> {
    let [table, measure, algorithm, reference, scope] = &claim.row;
    rows.iter().find(|r| {
        r.test == VerdictTest::WilcoxonSignedRank
            && &r.table == table
            && &r.measure == measure
            && &r.algorithm == algorithm
            && &r.reference == reference
            && &r.scope == scope
    })
}

/// A claim of the campaign answered by its primary row: the row, its p
/// corrected over the campaign's primary rows (Holm), and the verdict
/// decided on that p.
pub(crate) struct Answer<'c, 'r> {
    /// The claim.
    pub claim: &'c Claim,
    /// Its primary row of `verdicts.csv`.
    pub row: &'r VerdictRow,
    /// The row's p, Holm-corrected over the primary rows of the campaign.
    pub primary_holm: f64,
    /// The verdict decided on `primary_holm`.
    pub verdict: Verdict,
    /// What the verdict makes of the claim ([`reading`]).
    pub reading: &'static str,
}

/// The claims of `campaign` answered by their primary rows, the primary
/// rows Holm-corrected as a family of their own (empty when the file has
/// no claim of this campaign), or the error naming a claim whose row is
/// missing (`path` is the claims file's, for the message).
pub(crate) fn answers<'c, 'r>(
    path: &Path,
    claims: &'c [Claim],
    campaign: &str,
    rows: &'r [VerdictRow],
    alpha: f64,
) -> Result<Vec<Answer<'c, 'r>>, ClaimError> {
    let ours: Vec<&Claim> = claims.iter().filter(|c| c.campaign == campaign).collect();
    let mut found = Vec::new();
    for c in &ours {
        let row = primary(c, rows).ok_or_else(|| no_row(path, c, campaign, rows))?;
        found.push(row);
    }
    let raw: Vec<f64> = found.iter().map(|r| r.across.p_value).collect();
    let holm = holm_bonferroni(&raw).unwrap_or_else(|_| vec![f64::NAN; raw.len()]);
    Ok(ours
        .into_iter()
        .zip(found)
        .zip(holm)
        .map(|((claim, row), primary_holm)| {
            let verdict = Verdict::decide(
                primary_holm,
                alpha,
                row.across.improvement,
                &row.equivalence,
            );
            Answer {
                claim,
                row,
                primary_holm,
                verdict,
                reading: reading(claim, verdict),
            }
        })
        .collect())
}

/// The error of a claim whose primary row the campaign does not have,
/// with the scopes it has for that comparison.
fn no_row(path: &Path, c: &Claim, campaign: &str, rows: &[VerdictRow]) -> ClaimError {
    let scopes: Vec<&str> = rows
        .iter()
        .filter(|r| {
            r.test == VerdictTest::WilcoxonSignedRank
                && r.algorithm == c.row[2]
                && r.reference == c.row[3]
                && r.measure == c.row[1]
        })
        .map(|r| r.scope.as_str())
        .collect();
    let [table, measure, algorithm, reference, scope] = &c.row;
    ClaimError::NoRow(format!(
        "{}:{}: claim \"{}\": campaign {campaign} has no Wilcoxon verdict row \
         table={table}, measure={measure}, algorithm={algorithm}, \
         reference={reference}, scope={scope} (its scopes for this comparison: {})",
        path.display(),
        c.line,
        c.id,
        if scopes.is_empty() {
            "none".to_owned()
        } else {
            scopes.join(", ")
        }
    ))
}

/// What the primary row's verdict makes of the claim: `holds`,
/// `contradicted` (the opposite difference), `no practical difference`
/// (equivalent) or `undecided`.
fn reading(claim: &Claim, verdict: Verdict) -> &'static str {
    match verdict {
        Verdict::Equivalent => "no practical difference",
        Verdict::Undecided => "undecided",
        v if v == claim.holds_if => "holds",
        _ => "contradicted",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::{across_units, decide_family, Equivalence, ShiftInterval, Verdict};

    fn row(algorithm: &str, scope: &str, d: &[f64]) -> VerdictRow {
        let mut r = VerdictRow {
            table: "reference".into(),
            measure: "final-error".into(),
            algorithm: algorithm.into(),
            reference: "MHS".into(),
            scope: scope.into(),
            problems: d.len(),
            test: VerdictTest::WilcoxonSignedRank,
            across: across_units(d, true).unwrap(),
            p_adjusted: f64::NAN,
            family: 0,
            shift: ShiftInterval::unknown(),
            equivalence: Equivalence::unknown(0.3),
            verdict: Verdict::Undecided,
        };
        r.weigh(d, true, 0.3);
        r
    }

    const CLAIMS: &str =
        "[[claim]]\nid = \"acc\"\nclaim = \"MHS beats HS\"\nsource = \"abstract\"\n\
        campaign = \"c\"\ntable = \"reference\"\nmeasure = \"final-error\"\n\
        algorithm = \"HS\"\nreference = \"MHS\"\nscope = \"all\"\nholds_if = \"worse\"\n";

    fn file(text: &str) -> (tempfile::TempDir, std::path::PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("claims.toml");
        std::fs::write(&path, text).unwrap();
        (dir, path)
    }

    #[test]
    fn a_claim_is_answered_by_its_primary_row_and_a_missing_row_is_located() {
        let (_d, path) = file(CLAIMS);
        let claims = read_claims(&path).unwrap();
        assert_eq!(claims.len(), 1);
        assert_eq!(claims[0].line, 1);
        let mut rows = vec![
            row("HS", "all", &[0.5; 10]),
            row("HS", "dim=30", &[0.5; 10]),
        ];
        decide_family(&mut rows, 0.05);
        let md = section(&path, &claims, "c", &rows, 0.05).unwrap();
        assert!(
            md.contains("| MHS beats HS | HS against MHS, final-error, `all` | 0/0/10 |"),
            "{md}"
        );
        assert!(md.contains("| worse | holds |"), "{md}");
        // Another campaign's report has nothing to answer.
        assert!(section(&path, &claims, "other", &rows, 0.05)
            .unwrap()
            .is_empty());
        // A row the campaign lacks is an error naming the file, the line
        // and the scopes it has.
        let e = section(&path, &claims, "c", &rows[1..], 0.05)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("claims.toml:1: claim \"acc\"")
                && e.contains("scopes for this comparison: dim=30"),
            "{e}"
        );
    }

    #[test]
    fn a_bad_claims_file_is_a_located_error() {
        let (_d, path) = file(&CLAIMS.replace("scope = ", "scoop = "));
        let e = read_claims(&path).unwrap_err().to_string();
        assert!(
            e.contains("claims.toml:10:1: claim[1].scoop: unknown field") && e.contains("scope"),
            "{e}"
        );
        let (_d, path) = file(&CLAIMS.replace("scope = \"all\"\n", ""));
        let e = read_claims(&path).unwrap_err().to_string();
        assert!(e.contains("missing required field \"scope\""), "{e}");
    }

    #[test]
    fn the_projects_claims_file_loads() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../experiments/claims.toml");
        let claims = read_claims(&path).unwrap();
        assert!(claims.len() >= 6);
        for c in &claims {
            let spec = Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../../experiments")
                .join(format!("{}.toml", c.campaign));
            let text = std::fs::read_to_string(&spec).unwrap();
            assert!(
                text.contains(&format!("name = \"{}\"", c.campaign)),
                "{}",
                c.id
            );
        }
    }
}
