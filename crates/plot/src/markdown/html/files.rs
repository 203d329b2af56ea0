//! The files a page takes in: figures (SVG checked inert, PNG as Base64)
//! and CSV tables.

use std::io::Read;
use std::path::Path;

use super::MAX_CSV_ROWS;

/// The largest SVG or PNG inlined (a larger one is named as too large).
const MAX_IMAGE_BYTES: u64 = 64 << 20;

/// `bytes` in standard Base64 (RFC 4648, with padding).
pub fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            chunk.get(1).copied().unwrap_or(0),
            chunk.get(2).copied().unwrap_or(0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(char::from(ALPHABET[(n >> (18 - 6 * k)) as usize & 63]));
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// The bytes of `path`, when it is a file of at most [`MAX_IMAGE_BYTES`].
pub(super) fn read_limited(path: &Path) -> std::io::Result<Vec<u8>> {
    let file = std::fs::File::open(path)?;
    let mut bytes = Vec::new();
    file.take(MAX_IMAGE_BYTES + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > MAX_IMAGE_BYTES {
        return Err(std::io::Error::new(
            std::io::ErrorKind::FileTooLarge,
            "too large to inline",
        ));
    }
    Ok(bytes)
}

/// The `<svg>` element of an SVG file, without what comes before it (the
/// XML prolog, a doctype, comments) or after it; `None` when it holds
/// anything that could run or load: a script, a foreign object, an
/// animation, a style sheet, an event handler, a link, a `url(…)` or an
/// address outside its `xmlns` attributes.
pub(super) fn inline_svg(text: &str) -> Option<String> {
    let start = text.find("<svg")?;
    let end = text.rfind("</svg>")? + "</svg>".len();
    let svg = text.get(start..end)?;
    svg_is_inert(svg).then(|| svg.to_owned())
}

/// Whether every tag of `svg` is plain drawing (see [`inline_svg`]).
fn svg_is_inert(svg: &str) -> bool {
    const ACTIVE: [&str; 11] = [
        "script",
        "foreignobject",
        "iframe",
        "style",
        "a",
        "use",
        "image",
        "animate",
        "set",
        "animatemotion",
        "animatetransform",
    ];
    let b = svg.as_bytes();
    let mut i = 0;
    while let Some(off) = svg.get(i..).and_then(|r| r.find('<')) {
        i += off + 1;
        match b.get(i) {
            Some(b'/') => continue,
            Some(b'!' | b'?') => return false,
            _ => {}
        }
        let name_len = b[i..]
            .iter()
            .take_while(|c| c.is_ascii_alphanumeric() || matches!(c, b':' | b'-' | b'_'))
            .count();
        let name = svg[i..i + name_len].to_ascii_lowercase();
        let local = name.rsplit(':').next().unwrap_or("");
        if name.is_empty() || ACTIVE.contains(&local) {
            return false;
        }
        i += name_len;
        // The attributes, up to the closing '>'.
        loop {
            while b
                .get(i)
                .is_some_and(|c| c.is_ascii_whitespace() || *c == b'/')
            {
                i += 1;
            }
            match b.get(i) {
                None => return false,
                Some(b'>') => break,
                _ => {}
            }
            let n = b[i..]
                .iter()
                .take_while(|c| !c.is_ascii_whitespace() && !matches!(c, b'=' | b'>' | b'/'))
                .count();
            if n == 0 {
                return false;
            }
            let attr = svg[i..i + n].to_ascii_lowercase();
            i += n;
            while b.get(i).is_some_and(u8::is_ascii_whitespace) {
                i += 1;
            }
            let mut value = "";
            if b.get(i) == Some(&b'=') {
                i += 1;
                while b.get(i).is_some_and(u8::is_ascii_whitespace) {
                    i += 1;
                }
                let Some(&q @ (b'"' | b'\'')) = b.get(i) else {
                    return false;
                };
                let Some(len) = svg[i + 1..].find(char::from(q)) else {
                    return false;
                };
                value = &svg[i + 1..i + 1 + len];
                i += len + 2;
            }
            let v = value.to_ascii_lowercase();
            let namespace = attr == "xmlns" || attr.starts_with("xmlns:");
            if attr.starts_with("on")
                || attr.ends_with("href")
                || (!namespace && (v.contains("://") || v.contains("url(")))
                || v.contains("javascript:")
            {
                return false;
            }
        }
    }
    true
}

/// The start of a CSV file.
pub(super) struct CsvHead {
    /// The header row.
    pub header: Vec<String>,
    /// The first [`MAX_CSV_ROWS`] rows.
    pub rows: Vec<Vec<String>>,
    /// The number of rows in the file.
    pub total: usize,
}

/// The start of a CSV file, or why it cannot be read.
pub(super) fn read_csv(path: &Path) -> Result<CsvHead, String> {
    let file = std::fs::File::open(path).map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => "the file is missing".to_owned(),
        _ => e.kind().to_string(),
    })?;
    let mut reader = csv::ReaderBuilder::new()
        .flexible(true)
        .from_reader(std::io::BufReader::new(file));
    let header: Vec<String> = reader
        .byte_headers()
        .map_err(|e| e.to_string())?
        .iter()
        .map(|f| String::from_utf8_lossy(f).into_owned())
        .collect();
    let mut rows = Vec::new();
    let mut total = 0usize;
    let mut record = csv::ByteRecord::new();
    while reader
        .read_byte_record(&mut record)
        .map_err(|e| e.to_string())?
    {
        if rows.len() < MAX_CSV_ROWS {
            rows.push(
                record
                    .iter()
                    .map(|f| String::from_utf8_lossy(f).into_owned())
                    .collect(),
            );
        }
        total += 1;
    }
    Ok(CsvHead {
        header,
        rows,
        total,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_rfc_4648() {
        assert_eq!(base64(b""), "");
        assert_eq!(base64(b"f"), "Zg==");
        assert_eq!(base64(b"fo"), "Zm8=");
        assert_eq!(base64(b"foo"), "Zm9v");
        assert_eq!(base64(b"foobar"), "Zm9vYmFy");
        assert_eq!(base64(&[0xff, 0xfe, 0xfd, 0xfc]), "//79/A==");
    }

    #[test]
    fn svg_checks() {
        assert!(svg_is_inert(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width='3'><rect x=\"1\"/></svg>"
        ));
        for bad in [
            "<svg><script>x</script></svg>",
            "<svg><a href=\"#x\"><rect/></a></svg>",
            "<svg><rect fill=\"url(http://e/x)\"/></svg>",
            "<svg><rect ONCLICK=\"x\"/></svg>",
            "<svg><!-- c --></svg>",
            "<svg><rect x=\"1></svg>",
            "<svg><svg:script/></svg>",
        ] {
            assert!(!svg_is_inert(bad), "{bad}");
        }
    }
}
