//! The few fields of a `CITATION.cff` (Citation File Format 1.2.0,
//! <https://citation-file-format.github.io>) that a Zenodo deposition
//! takes: the authors, the keywords and the software's repository URL.
//!
//! Only the top-level keys are read (the authors of a `references:` entry
//! are not the software's), in the block style the repository's own file
//! uses: `key: value` and lists of `- item` or `- name: value` mappings.
//! Nothing is made up: a field the file does not hold is left empty.

/// What a Zenodo deposition takes from a `CITATION.cff`.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Citation {
    /// The software's title.
    pub title: Option<String>,
    /// The authors as Zenodo names creators: "Family, Given" for a person,
    /// the name itself for an entity.
    pub authors: Vec<String>,
    /// The keywords.
    pub keywords: Vec<String>,
    /// `repository-code`, else `repository`, else `url`.
    pub repository: Option<String>,
}

/// Reads the fields of [`Citation`] from the text of a `CITATION.cff`.
pub fn read_citation(text: &str) -> Citation {
    let mut c = Citation::default();
    let mut repo: [Option<String>; 3] = Default::default();
    let mut section = "";
    // The fields of the author being read: name, family, given.
    let mut author: [Option<String>; 3] = Default::default();
    for line in text.lines() {
        let content = line.trim_end();
        if content.trim_start().starts_with('#') || content.trim().is_empty() {
            continue;
        }
        if !line.starts_with([' ', '-']) {
            push_author(&mut c.authors, &mut author);
            let (key, value) = content.split_once(':').unwrap_or((content, ""));
            section = match key {
                "authors" => "authors",
                "keywords" => "keywords",
                _ => "",
            };
            let value = scalar(value);
            match (key, value) {
                ("title", Some(v)) => c.title = Some(v),
                ("repository-code", Some(v)) => repo[0] = Some(v),
                ("repository", Some(v)) => repo[1] = Some(v),
                ("url", Some(v)) => repo[2] = Some(v),
                _ => {}
            }
            continue;
        }
        let item = content.trim_start();
        let (fresh, item) = match item.strip_prefix("- ") {
            Some(rest) => (true, rest.trim_start()),
            None => (false, item),
        };
        match section {
            "keywords" if fresh => c.keywords.extend(scalar(item)),
            "authors" => {
                if fresh {
                    push_author(&mut c.authors, &mut author);
                }
                if let Some((key, value)) = item.split_once(':') {
                    let slot = match key.trim() {
                        "name" => 0,
                        "family-names" => 1,
                        "given-names" => 2,
                        _ => continue,
                    };
                    author[slot] = scalar(value);
                }
            }
            _ => {}
        }
    }
    push_author(&mut c.authors, &mut author);
    c.repository = repo.into_iter().flatten().next();
    c
}

/// Ends the author being read: a person as "Family, Given", an entity by
/// its name.
fn push_author(authors: &mut Vec<String>, author: &mut [Option<String>; 3]) {
    let [name, family, given] = std::mem::take(author);
    let full = match (family, given, name) {
        (Some(f), Some(g), _) => Some(format!("{f}, {g}")),
        (Some(f), None, _) => Some(f),
        (None, _, Some(n)) => Some(n),
        (None, Some(g), None) => Some(g),
        (None, None, None) => None,
    };
    authors.extend(full);
}

/// A YAML scalar written in one line: double- or single-quoted, or plain
/// (a ` #` comment ends it); `None` when empty or a block scalar (`>`, `|`).
fn scalar(value: &str) -> Option<String> {
    let v = value.trim();
    let text = if let Some(rest) = v.strip_prefix('"') {
        let mut out = String::new();
        let mut chars = rest.chars();
        while let Some(ch) = chars.next() {
            match ch {
                '"' => break,
                '\\' => out.extend(chars.next()),
                _ => out.push(ch),
            }
        }
        out
    } else if let Some(rest) = v.strip_prefix('\'') {
        let end = rest.find('\'').unwrap_or(rest.len());
        rest[..end].to_owned()
    } else {
        let plain = v.split(" #").next().unwrap_or("").trim();
        if plain.starts_with(['>', '|']) {
            return None;
        }
        plain.to_owned()
    };
    (!text.is_empty()).then_some(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_top_level_authors_keywords_and_repository_are_read() {
        let text = "cff-version: 1.2.0\n\
            title: \"metabezier: curves\"\n\
            authors:\n  - name: \"The metabezier developers\"\n\
            \x20 - family-names: Doe\n    given-names: 'Jane'\n\
            repository-code: https://example.org/metabezier # the code\n\
            url: https://example.org\n\
            keywords:\n  - Bézier curves\n  - \"harmony search\"\n\
            abstract: >-\n  Text.\n\
            references:\n  - type: thesis\n    authors:\n      - name: \"Someone else\"\n";
        let c = read_citation(text);
        assert_eq!(c.title.as_deref(), Some("metabezier: curves"));
        assert_eq!(c.authors, ["The metabezier developers", "Doe, Jane"]);
        assert_eq!(c.keywords, ["Bézier curves", "harmony search"]);
        assert_eq!(
            c.repository.as_deref(),
            Some("https://example.org/metabezier")
        );
    }

    #[test]
    fn a_file_without_the_fields_gives_nothing_made_up() {
        let c = read_citation("cff-version: 1.2.0\nmessage: cite it\n");
        assert_eq!(c, Citation::default());
    }
}
