//! Lines and keys of byte offsets in the spec text, so every message can say where to look.

/// 1-based line of a byte offset.
pub(super) fn line_of(text: &str, offset: usize) -> usize {
    text.as_bytes()[..offset.min(text.len())].iter().filter(|&&b| b == b'\n').count() + 1
}

/// Best-effort dotted key at a byte offset, for toml's own errors (which carry a span, not the key):
/// the enclosing `[header]` and the last `key =` at or before the offset (the offset's own key
/// included, for "unknown field" errors that point at the key).
pub(super) fn key_at(text: &str, offset: usize) -> Option<String> {
    let offset = offset.min(text.len());
    let rest = &text[offset..];
    let ident_len = rest.find(|c: char| !is_key_char(c)).unwrap_or(rest.len());
    let after = &rest[ident_len..];
    let eq = after
        .find(|c: char| c != ' ' && c != '\t')
        .filter(|&i| after[i..].starts_with('='))
        .map_or(0, |i| i + 1);
    let upto = &text[..offset + ident_len + eq];
    let mut key = None;
    for line in upto.lines().rev() {
        let t = line.trim();
        if t.starts_with('[') && t.ends_with(']') && !t.contains([',', '=', '"']) {
            let header = t.trim_matches(|c| c == '[' || c == ']').trim();
            return Some(match key {
                Some(k) => format!("{header}.{k}"),
                None => header.to_string(),
            });
        }
        if key.is_none() {
            key = last_key(line);
        }
    }
    key
}

fn is_key_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_' || c == '-'
}

/// The identifier before the last `=` of a line (outside quotes, roughly), if any.
fn last_key(line: &str) -> Option<String> {
    let mut found = None;
    let mut in_str = false;
    for (i, c) in line.char_indices() {
        match c {
            '"' => in_str = !in_str,
            '=' if !in_str => {
                let before = line[..i].trim_end();
                let start = before.rfind(|c: char| !is_key_char(c)).map_or(0, |j| j + 1);
                if start < before.len() {
                    found = Some(before[start..].to_string());
                }
            }
            _ => {}
        }
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn key_at_finds_header_and_key() {
        let t = "name = \"x\"\n[[table]]\nname = \"t\"\nrays = [\"a\"]\n";
        let off = t.find("\"a\"").unwrap();
        assert_eq!(key_at(t, off).as_deref(), Some("table.rays"));
        assert_eq!(line_of(t, off), 4);
        let t = "[[table]]\nrows = [\n  { distribution = \"sine\", seedmode = \"x\" },\n]\n";
        assert_eq!(key_at(t, t.find("seedmode").unwrap()).as_deref(), Some("table.seedmode"));
        assert_eq!(key_at(t, t.find("\"sine\"").unwrap()).as_deref(), Some("table.distribution"));
        let t = "a = 1\nraplicates = 2\n";
        assert_eq!(key_at(t, t.find("raplicates").unwrap()).as_deref(), Some("raplicates"));
    }
}
