//! The spec differences `compare` shows: both `spec.toml` copies flattened
//! to dotted keys (`experiment.seed`, `algorithm[1].params.hmcr`), and the
//! keys whose values differ or that one side lacks.

use std::collections::BTreeMap;
use std::path::Path;

use crate::files::{read_text_limited, MAX_TEXT_BYTES};

/// The spec.toml of `dir` as dotted key → value (its TOML text), or `None`
/// when it is missing or not valid TOML.
pub(crate) fn flat_spec(dir: &Path) -> Option<BTreeMap<String, String>> {
    let text = read_text_limited(&dir.join("spec.toml"), MAX_TEXT_BYTES, "a spec").ok()?;
    let table: toml::Table = text.parse().ok()?;
    let mut out = BTreeMap::new();
    for (k, v) in &table {
        flatten(k, v, &mut out);
    }
    Some(out)
}

/// Adds `value` under `key`: a table's keys as `key.sub`, an array of
/// tables' elements as `key[i]`, every other value as its TOML text.
fn flatten(key: &str, value: &toml::Value, out: &mut BTreeMap<String, String>) {
    match value {
        toml::Value::Table(t) => {
            for (k, v) in t {
                flatten(&format!("{key}.{k}"), v, out);
            }
        }
        toml::Value::Array(a) if !a.is_empty() && a.iter().all(toml::Value::is_table) => {
            for (i, v) in a.iter().enumerate() {
                flatten(&format!("{key}[{i}]"), v, out);
            }
        }
        other => {
            out.insert(key.to_owned(), other.to_string());
        }
    }
}

/// The keys of `a` and `b` whose values differ, with each side's value
/// (`None`: the side lacks the key), in key order.
pub(crate) fn differences(
    a: &BTreeMap<String, String>,
    b: &BTreeMap<String, String>,
) -> Vec<(String, Option<String>, Option<String>)> {
    let mut keys: Vec<&String> = a.keys().chain(b.keys()).collect();
    keys.sort_unstable();
    keys.dedup();
    keys.into_iter()
        .filter(|k| a.get(*k) != b.get(*k))
        .map(|k| (k.clone(), a.get(k).cloned(), b.get(k).cloned()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_flatten_and_differ_by_value_or_absence() {
        let parse = |t: &str| {
            let table: toml::Table = t.parse().unwrap();
            let mut out = BTreeMap::new();
            for (k, v) in &table {
                flatten(k, v, &mut out);
            }
            out
        };
        let a = parse("[experiment]\nseed = 1\nruns = 5\n[[algorithm]]\nname = \"hs\"\n");
        let b = parse("[experiment]\nseed = 2\nruns = 5\n[[algorithm]]\nname = \"hs\"\n[[algorithm]]\nname = \"mhs\"\n");
        assert_eq!(a["algorithm[0].name"], "\"hs\"");
        let d = differences(&a, &b);
        assert_eq!(
            d,
            vec![
                ("algorithm[1].name".into(), None, Some("\"mhs\"".into())),
                ("experiment.seed".into(), Some("1".into()), Some("2".into())),
            ]
        );
    }
}
