//! The `.zenodo.json` of an archive: the deposition metadata Zenodo reads
//! (<https://developers.zenodo.org/#representation>, "Deposit metadata"),
//! written as plain JSON with its keys in a fixed order, so that the same
//! campaigns always give the same bytes.

use super::cff::Citation;
use super::{CampaignInfo, Software};

/// The SPDX licence id the deposition names. Cargo.toml licenses the
/// software `MIT OR Apache-2.0`, at the user's choice; Zenodo takes one
/// licence id, so the record names the first, and its description says
/// both.
pub const ZENODO_LICENSE: &str = "MIT";

/// The relation of the archived results to the software's repository
/// (DataCite's `IsCompiledBy`: "B is used to compile or create A", as a
/// dataset is made by software).
pub const SOFTWARE_RELATION: &str = "isCompiledBy";

/// The keywords every archive adds to those of the `CITATION.cff`.
const OWN_KEYWORDS: [&str; 3] = ["metabezier", "benchmark results", "seeded campaign"];

/// The text of `.zenodo.json` for `campaigns`, written by `software`, whose
/// citation is `citation`: title, upload type, creators, version, licence,
/// description, related identifiers (when the citation names a
/// repository) and keywords.
pub fn zenodo_json(software: &Software, citation: &Citation, campaigns: &[CampaignInfo]) -> String {
    let names: Vec<&str> = campaigns.iter().map(|c| c.name.as_str()).collect();
    let title = format!(
        "{}: results of {}{} {} campaign{}",
        names.join(", "),
        if names.len() == 1 { "a " } else { "" },
        software.name,
        software.version,
        if names.len() == 1 { "" } else { "s" }
    );
    let creators: Vec<String> = citation
        .authors
        .iter()
        .map(|a| format!("{{\"name\": {}}}", string(a)))
        .collect();
    let related: Vec<String> = citation
        .repository
        .iter()
        .map(|url| {
            format!(
                "{{\"identifier\": {}, \"relation\": {}, \"resource_type\": \"software\"}}",
                string(url),
                string(SOFTWARE_RELATION)
            )
        })
        .collect();
    let mut keywords: Vec<&str> = citation.keywords.iter().map(String::as_str).collect();
    for own in OWN_KEYWORDS {
        if !keywords.contains(&own) {
            keywords.push(own);
        }
    }
    let mut fields = vec![
        ("title", string(&title)),
        ("upload_type", string("dataset")),
        ("creators", list(&creators)),
        ("version", string(software.version)),
        ("license", string(ZENODO_LICENSE)),
        ("access_right", string("open")),
        (
            "description",
            string(&description(software, citation, campaigns)),
        ),
        (
            "keywords",
            list(&keywords.iter().map(|k| string(k)).collect::<Vec<_>>()),
        ),
    ];
    // Only with an identifier: the CITATION.cff may name no repository.
    if !related.is_empty() {
        fields.insert(7, ("related_identifiers", list(&related)));
    }
    let body: Vec<String> = fields
        .iter()
        .map(|(key, value)| format!("  \"{key}\": {value}"))
        .collect();
    format!("{{\n{}\n}}\n", body.join(",\n"))
}

/// The description: what the campaigns are, what the archive holds and how
/// to check it.
fn description(software: &Software, citation: &Citation, campaigns: &[CampaignInfo]) -> String {
    let runs: Vec<String> = campaigns
        .iter()
        .map(|c| match c.runs {
            Some(n) => format!("{} ({n} runs)", c.name),
            None => c.name.clone(),
        })
        .collect();
    let cited = citation
        .title
        .as_deref()
        .map_or(String::new(), |t| format!(" ({t})"));
    format!(
        "Results of the seeded campaign{} {} written by {} {}{cited}: the spec copy, \
         runs.csv and the records beside it, meta.toml, provenance.toml and the reports, \
         with the software's CITATION.cff. SHA256SUMS lists the SHA-256 of every file \
         (check with `sha256sum -c SHA256SUMS`, or `{} archive --verify`). The software \
         is licensed MIT OR Apache-2.0 at the user's choice; this record names {}.",
        if campaigns.len() == 1 { "" } else { "s" },
        runs.join(", "),
        software.name,
        software.version,
        software.name,
        ZENODO_LICENSE
    )
}

/// A JSON list of already written values, on one line.
fn list(values: &[String]) -> String {
    format!("[{}]", values.join(", "))
}

/// `text` as a JSON string (RFC 8259: quote, backslash and control
/// characters escaped).
fn string(text: &str) -> String {
    let mut out = String::with_capacity(text.len() + 2);
    out.push('"');
    for ch in text.chars() {
        match ch {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            '\r' => out.push_str("\\r"),
            c if u32::from(c) < 0x20 => out.push_str(&format!("\\u{:04x}", u32::from(c))),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strings_are_escaped_as_json_wants() {
        assert_eq!(string("a\"b\\c\nd\u{1}é"), "\"a\\\"b\\\\c\\nd\\u0001é\"");
    }

    #[test]
    fn the_fields_come_from_the_citation_and_the_campaigns() {
        let software = Software {
            name: "metabezier",
            version: "9.9.9",
            citation_cff: "",
        };
        let citation = Citation {
            title: Some("T".into()),
            authors: vec!["Doe, Jane".into()],
            keywords: vec!["metabezier".into(), "curves".into()],
            repository: Some("https://example.org/r".into()),
        };
        let campaigns = [CampaignInfo {
            name: "ch4".into(),
            runs: Some(6),
        }];
        let json = zenodo_json(&software, &citation, &campaigns);
        for part in [
            "\"title\": \"ch4: results of a metabezier 9.9.9 campaign\"",
            "\"creators\": [{\"name\": \"Doe, Jane\"}]",
            "\"version\": \"9.9.9\"",
            "\"license\": \"MIT\"",
            "\"upload_type\": \"dataset\"",
            "ch4 (6 runs)",
            "{\"identifier\": \"https://example.org/r\", \"relation\": \"isCompiledBy\", \"resource_type\": \"software\"}",
            "\"keywords\": [\"metabezier\", \"curves\", \"benchmark results\", \"seeded campaign\"]",
        ] {
            assert!(json.contains(part), "{part} not in {json}");
        }
    }
}
