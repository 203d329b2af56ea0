//! A minimal reader of Apple XML property lists, enough for InVesalius's
//! `main.plist` (elements `dict`, `key`, `array`, `string`, `integer`, `real`,
//! `true`, `false`, `date`, `data`; comments, the XML declaration and the
//! DOCTYPE are skipped; the entities `&amp; &lt; &gt; &quot; &apos;` are
//! decoded). Format: Apple, "Property List Programming Guide", XML plist DTD 1.0.

/// The deepest nesting of `<dict>` and `<array>` elements the parser
/// accepts: 64. InVesalius writes two levels (`matrix`, `masks`, ...); the
/// limit keeps the recursive parser's stack bounded on any input.
pub const MAX_PLIST_DEPTH: usize = 64;

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

/// What is malformed in a property list.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum PlistErrorKind {
    /// The document's root element is not `<plist>`.
    #[error("expected <plist>")]
    ExpectedPlist,
    /// A comment, declaration or DOCTYPE is not closed.
    #[error("unterminated markup")]
    UnterminatedMarkup,
    /// An opening tag was expected.
    #[error("expected an opening tag")]
    ExpectedOpeningTag,
    /// A tag is not closed by `>`.
    #[error("unterminated tag")]
    UnterminatedTag,
    /// The closing tag of an element was expected.
    #[error("expected </{name}>")]
    ExpectedClosingTag {
        /// The element's name.
        name: String,
    },
    /// Text runs to the end of the document.
    #[error("unterminated text")]
    UnterminatedText,
    /// An empty element (`<name/>`) that cannot be empty.
    #[error("unexpected <{name}/>")]
    UnexpectedEmpty {
        /// The element's name.
        name: String,
    },
    /// A `<dict>` entry does not start with `<key>`.
    #[error("expected <key> in <dict>")]
    ExpectedKey,
    /// The text of an `<integer>` or `<real>` is not a number.
    #[error("bad <{element}> {text:?}")]
    BadNumber {
        /// `integer` or `real`.
        element: &'static str,
        /// The text found.
        text: String,
    },
    /// An element the format does not have.
    #[error("unknown element <{name}>")]
    UnknownElement {
        /// The element's name.
        name: String,
    },
    /// `<dict>` and `<array>` nested deeper than [`MAX_PLIST_DEPTH`].
    #[error("<dict> and <array> nested more than {limit} deep (MAX_PLIST_DEPTH)")]
    TooDeep {
        /// The limit.
        limit: usize,
    },
}

/// A malformed property list: what is wrong and where.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{kind} at byte {position}")]
pub struct PlistError {
    /// The byte offset in the text.
    pub position: usize,
    /// What is wrong there.
    pub kind: PlistErrorKind,
}

impl PlistError {
    fn new(position: usize, kind: PlistErrorKind) -> Self {
        PlistError { position, kind }
    }
}

/// Parses an XML property list; the error says what is malformed and where
/// (byte offset).
pub fn parse_plist(text: &str) -> Result<PlistValue, PlistError> {
    let mut p = Parser {
        s: text,
        pos: 0,
        depth: 0,
    };
    p.skip_misc()?;
    let (name, empty) = p.open_tag()?;
    if name != "plist" || empty {
        return Err(p.error(PlistErrorKind::ExpectedPlist));
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
    /// Open `<dict>` and `<array>` elements.
    depth: usize,
}

impl<'a> Parser<'a> {
    fn rest(&self) -> &'a str {
        &self.s[self.pos..]
    }

    /// An error at the current position.
    fn error(&self, kind: PlistErrorKind) -> PlistError {
        PlistError::new(self.pos, kind)
    }

    /// Skips whitespace, comments, `<?...?>` and `<!DOCTYPE ...>`.
    fn skip_misc(&mut self) -> Result<(), PlistError> {
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
                None => return Err(self.error(PlistErrorKind::UnterminatedMarkup)),
            }
        }
    }

    /// Reads `<name>` or `<name/>`; returns the name and whether it is empty.
    fn open_tag(&mut self) -> Result<(String, bool), PlistError> {
        let r = self.rest();
        if !r.starts_with('<') || r.starts_with("</") {
            return Err(self.error(PlistErrorKind::ExpectedOpeningTag));
        }
        let end = r
            .find('>')
            .ok_or_else(|| self.error(PlistErrorKind::UnterminatedTag))?;
        let inner = &r[1..end];
        let empty = inner.ends_with('/');
        let inner = inner.trim_end_matches('/');
        let name = inner.split_whitespace().next().unwrap_or("").to_string();
        self.pos += end + 1;
        Ok((name, empty))
    }

    fn close_tag(&mut self, name: &str) -> Result<(), PlistError> {
        let want = format!("</{name}>");
        if self.rest().starts_with(&want) {
            self.pos += want.len();
            Ok(())
        } else {
            Err(self.error(PlistErrorKind::ExpectedClosingTag {
                name: name.to_string(),
            }))
        }
    }

    /// Text up to the next `<`, entity-decoded.
    fn text(&mut self) -> Result<String, PlistError> {
        let r = self.rest();
        let end = r
            .find('<')
            .ok_or_else(|| self.error(PlistErrorKind::UnterminatedText))?;
        let raw = r[..end].to_string();
        self.pos += end;
        Ok(raw
            .replace("&lt;", "<")
            .replace("&gt;", ">")
            .replace("&quot;", "\"")
            .replace("&apos;", "'")
            .replace("&amp;", "&"))
    }

    fn value(&mut self) -> Result<PlistValue, PlistError> {
        let at = self.pos;
        let (name, empty) = self.open_tag()?;
        if empty {
            return match name.as_str() {
                "true" => Ok(PlistValue::Bool(true)),
                "false" => Ok(PlistValue::Bool(false)),
                "string" | "date" | "data" => Ok(PlistValue::String(String::new())),
                "dict" => Ok(PlistValue::Dict(Vec::new())),
                "array" => Ok(PlistValue::Array(Vec::new())),
                _ => Err(PlistError::new(
                    at,
                    PlistErrorKind::UnexpectedEmpty { name },
                )),
            };
        }
        if matches!(name.as_str(), "dict" | "array") {
            if self.depth >= MAX_PLIST_DEPTH {
                return Err(PlistError::new(
                    at,
                    PlistErrorKind::TooDeep {
                        limit: MAX_PLIST_DEPTH,
                    },
                ));
            }
            self.depth += 1;
        }
        let v = match name.as_str() {
            "dict" => PlistValue::Dict(self.dict_entries()?),
            "array" => PlistValue::Array(self.array_items()?),
            "string" | "date" | "data" => PlistValue::String(self.text()?),
            "integer" => PlistValue::Integer(self.number(at, "integer")?),
            "real" => PlistValue::Real(self.number(at, "real")?),
            _ => return Err(PlistError::new(at, PlistErrorKind::UnknownElement { name })),
        };
        self.close_tag(&name)?;
        if matches!(v, PlistValue::Dict(_) | PlistValue::Array(_)) {
            self.depth -= 1;
        }
        Ok(v)
    }

    /// The `<key>`/value pairs of a `<dict>` up to its closing tag.
    fn dict_entries(&mut self) -> Result<Vec<(String, PlistValue)>, PlistError> {
        let mut entries = Vec::new();
        loop {
            self.skip_misc()?;
            if self.rest().starts_with("</") {
                return Ok(entries);
            }
            let (k, kempty) = self.open_tag()?;
            if k != "key" || kempty {
                return Err(self.error(PlistErrorKind::ExpectedKey));
            }
            let key = self.text()?;
            self.close_tag("key")?;
            self.skip_misc()?;
            let v = self.value()?;
            entries.push((key, v));
        }
    }

    /// The values of an `<array>` up to its closing tag.
    fn array_items(&mut self) -> Result<Vec<PlistValue>, PlistError> {
        let mut items = Vec::new();
        loop {
            self.skip_misc()?;
            if self.rest().starts_with("</") {
                return Ok(items);
            }
            items.push(self.value()?);
        }
    }

    /// The text of the `<element>` opened at byte `at`, parsed as a number.
    fn number<T: std::str::FromStr>(
        &mut self,
        at: usize,
        element: &'static str,
    ) -> Result<T, PlistError> {
        let t = self.text()?;
        t.trim()
            .parse()
            .map_err(|_| PlistError::new(at, PlistErrorKind::BadNumber { element, text: t }))
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

    #[test]
    fn deep_nesting_is_refused_at_the_limit() {
        let nest = |n: usize| {
            format!(
                "<plist>{}{}</plist>",
                "<array>".repeat(n),
                "</array>".repeat(n)
            )
        };
        assert!(parse_plist(&nest(MAX_PLIST_DEPTH)).is_ok());
        let e = parse_plist(&nest(MAX_PLIST_DEPTH + 1)).unwrap_err();
        assert_eq!(
            e.kind,
            PlistErrorKind::TooDeep {
                limit: MAX_PLIST_DEPTH
            }
        );
        assert_eq!(e.position, 7 + 7 * MAX_PLIST_DEPTH);
        // Without the limit, a deep enough file overflowed the stack.
        assert!(parse_plist(&nest(1_000_000)).is_err());
    }

    #[test]
    fn errors_say_what_and_where() {
        let e = parse_plist("<plist><dict><key>a</key><integer>x</integer></dict></plist>")
            .unwrap_err();
        assert_eq!(e.position, 25);
        assert_eq!(
            e.kind,
            PlistErrorKind::BadNumber {
                element: "integer",
                text: "x".into()
            }
        );
        assert_eq!(e.to_string(), "bad <integer> \"x\" at byte 25");
        let e = parse_plist("<plist><dict><key>a</key>").unwrap_err();
        assert_eq!(e.to_string(), "expected an opening tag at byte 25");
        let e = parse_plist("<plist><array></dict></plist>").unwrap_err();
        assert_eq!(e.to_string(), "expected </array> at byte 14");
    }
}
