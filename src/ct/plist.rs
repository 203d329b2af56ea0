//! A minimal reader of Apple XML property lists, enough for InVesalius's
//! `main.plist` (elements `dict`, `key`, `array`, `string`, `integer`, `real`,
//! `true`, `false`, `date`, `data`; comments, the XML declaration and the
//! DOCTYPE are skipped; the entities `&amp; &lt; &gt; &quot; &apos;` are
//! decoded). Format: Apple, "Property List Programming Guide", XML plist DTD 1.0.

/// A property-list value.
#[derive(Clone, Debug, PartialEq)]
pub enum PlistValue {
    /// `<dict>`: keys and values in file order.
    Dict(Vec<(String, PlistValue)>),
    /// `<array>`.
    Array(Vec<PlistValue>),
    /// `<string>`, `<date>` or `<data>` (kept as text).
    String(String),
    /// `<integer>`.
    Integer(i64),
    /// `<real>`.
    Real(f64),
    /// `<true/>` or `<false/>`.
    Bool(bool),
}

impl PlistValue {
    /// The value of `key` in a dict, or `None`.
    pub fn get(&self, key: &str) -> Option<&PlistValue> {
        match self {
            PlistValue::Dict(entries) => entries.iter().find(|(k, _)| k == key).map(|(_, v)| v),
            _ => None,
        }
    }

    /// The number held by an `<integer>` or `<real>`.
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            PlistValue::Integer(i) => Some(*i as f64),
            PlistValue::Real(r) => Some(*r),
            _ => None,
        }
    }

    /// The integer held by an `<integer>`.
    pub fn as_i64(&self) -> Option<i64> {
        match self {
            PlistValue::Integer(i) => Some(*i),
            _ => None,
        }
    }

    /// The text of a `<string>`.
    pub fn as_str(&self) -> Option<&str> {
        match self {
            PlistValue::String(s) => Some(s),
            _ => None,
        }
    }

    /// The items of an `<array>`.
    pub fn as_array(&self) -> Option<&[PlistValue]> {
        match self {
            PlistValue::Array(a) => Some(a),
            _ => None,
        }
    }
}

/// Parses an XML property list; the error says what is malformed and where
/// (byte offset).
pub fn parse_plist(text: &str) -> Result<PlistValue, String> {
    let mut p = Parser { s: text, pos: 0 };
    p.skip_misc()?;
    let (name, empty) = p.open_tag()?;
    if name != "plist" || empty {
        return Err(format!("expected <plist> at byte {}", p.pos));
    }
    p.skip_misc()?;
    let v = p.value()?;
    p.skip_misc()?;
    p.close_tag("plist")?;
    Ok(v)
}

struct Parser<'a> {
    s: &'a str,
    pos: usize,
}

impl<'a> Parser<'a> {
    fn rest(&self) -> &'a str {
        &self.s[self.pos..]
    }

    /// Skips whitespace, comments, `<?...?>` and `<!DOCTYPE ...>`.
    fn skip_misc(&mut self) -> Result<(), String> {
        loop {
            let trimmed = self.rest().trim_start();
            self.pos = self.s.len() - trimmed.len();
            let r = self.rest();
            let end = if r.starts_with("<!--") {
                r.find("-->").map(|i| i + 3)
            } else if r.starts_with("<?") {
                r.find("?>").map(|i| i + 2)
            } else if r.starts_with("<!") {
                r.find('>').map(|i| i + 1)
            } else {
                return Ok(());
            };
            match end {
                Some(e) => self.pos += e,
                None => return Err(format!("unterminated markup at byte {}", self.pos)),
            }
        }
    }

    /// Reads `<name>` or `<name/>`; returns the name and whether it is empty.
    fn open_tag(&mut self) -> Result<(String, bool), String> {
        let r = self.rest();
        if !r.starts_with('<') || r.starts_with("</") {
            return Err(format!("expected an opening tag at byte {}", self.pos));
        }
        let end = r
            .find('>')
            .ok_or_else(|| format!("unterminated tag at byte {}", self.pos))?;
        let inner = &r[1..end];
        let empty = inner.ends_with('/');
        let inner = inner.trim_end_matches('/');
        let name = inner.split_whitespace().next().unwrap_or("").to_string();
        self.pos += end + 1;
        Ok((name, empty))
    }

    fn close_tag(&mut self, name: &str) -> Result<(), String> {
        let want = format!("</{name}>");
        if self.rest().starts_with(&want) {
            self.pos += want.len();
            Ok(())
        } else {
            Err(format!("expected {want} at byte {}", self.pos))
        }
    }

    /// Text up to the next `<`, entity-decoded.
    fn text(&mut self) -> Result<String, String> {
        let r = self.rest();
        let end = r
            .find('<')
            .ok_or_else(|| format!("unterminated text at byte {}", self.pos))?;
        let raw = r[..end].to_string();
        self.pos += end;
        Ok(raw
            .replace("&lt;", "<")
            .replace("&gt;", ">")
            .replace("&quot;", "\"")
            .replace("&apos;", "'")
            .replace("&amp;", "&"))
    }

    fn value(&mut self) -> Result<PlistValue, String> {
        let at = self.pos;
        let (name, empty) = self.open_tag()?;
        if empty {
            return match name.as_str() {
                "true" => Ok(PlistValue::Bool(true)),
                "false" => Ok(PlistValue::Bool(false)),
                "string" | "date" | "data" => Ok(PlistValue::String(String::new())),
                "dict" => Ok(PlistValue::Dict(Vec::new())),
                "array" => Ok(PlistValue::Array(Vec::new())),
                _ => Err(format!("unexpected <{name}/> at byte {at}")),
            };
        }
        let v = match name.as_str() {
            "dict" => {
                let mut entries = Vec::new();
                loop {
                    self.skip_misc()?;
                    if self.rest().starts_with("</") {
                        break;
                    }
                    let (k, kempty) = self.open_tag()?;
                    if k != "key" || kempty {
                        return Err(format!("expected <key> in <dict> at byte {}", self.pos));
                    }
                    let key = self.text()?;
                    self.close_tag("key")?;
                    self.skip_misc()?;
                    let v = self.value()?;
                    entries.push((key, v));
                }
                PlistValue::Dict(entries)
            }
            "array" => {
                let mut items = Vec::new();
                loop {
                    self.skip_misc()?;
                    if self.rest().starts_with("</") {
                        break;
                    }
                    items.push(self.value()?);
                }
                PlistValue::Array(items)
            }
            "string" | "date" | "data" => PlistValue::String(self.text()?),
            "integer" => {
                let t = self.text()?;
                PlistValue::Integer(
                    t.trim()
                        .parse()
                        .map_err(|_| format!("bad <integer> {t:?} at byte {at}"))?,
                )
            }
            "real" => {
                let t = self.text()?;
                PlistValue::Real(
                    t.trim()
                        .parse()
                        .map_err(|_| format!("bad <real> {t:?} at byte {at}"))?,
                )
            }
            _ => return Err(format!("unknown element <{name}> at byte {at}")),
        };
        self.close_tag(&name)?;
        Ok(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_nested_values() {
        let t = "<?xml version=\"1.0\"?>\n<!DOCTYPE plist>\n<!-- c -->\n<plist version=\"1.0\">\n<dict>\n\
                 <key>a</key><array><integer>3</integer><real>1.5</real></array>\n\
                 <key>b</key><dict><key>c</key><string>x &amp; y</string></dict>\n\
                 <key>e</key><dict>\n</dict><key>t</key><true/>\n</dict>\n</plist>\n";
        let v = parse_plist(t).unwrap();
        let a = v.get("a").unwrap().as_array().unwrap();
        assert_eq!(a[0].as_i64(), Some(3));
        assert_eq!(a[1].as_f64(), Some(1.5));
        assert_eq!(
            v.get("b").unwrap().get("c").unwrap().as_str(),
            Some("x & y")
        );
        assert_eq!(v.get("e"), Some(&PlistValue::Dict(vec![])));
        assert_eq!(v.get("t"), Some(&PlistValue::Bool(true)));
    }

    #[test]
    fn rejects_malformed() {
        assert!(
            parse_plist("<plist><dict><key>a</key><integer>x</integer></dict></plist>").is_err()
        );
        assert!(parse_plist("<plist><dict><key>a</key>").is_err());
        assert!(parse_plist("<dict></dict>").is_err());
    }
}
