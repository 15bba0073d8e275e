//! Lines and keys of byte offsets in the spec text, so every message can say where to look.

/// 1-based line of a byte offset.
pub(crate) fn line_of(text: &str, offset: usize) -> usize {
    text.as_bytes()[..offset.min(text.len())].iter().filter(|&&b| b == b'\n').count() + 1
}

/// Best-effort dotted key at a byte offset, for toml's own errors (which carry a span, not the key):
/// the enclosing `[header]` and the last `key =` at or before the offset (the offset's own key
/// included, for "unknown field" errors that point at the key).
pub(crate) fn key_at(text: &str, offset: usize) -> Option<String> {
    let offset = offset.min(text.len());
    let rest = &text[offset..];
    // An error at a table header (e.g. `[convergence]` where `[[convergence]]` belongs) is about
    // that table, not about the last key before it.
    let line_start = text[..offset].rfind('\n').map_or(0, |i| i + 1);
    let before = text[line_start..offset].trim();
    // At or inside a header (toml points at `[`, or at a key within `[camera.perspective]`).
    if (rest.starts_with('[') && before.is_empty())
        || (before.starts_with('[') && !before.contains(['=', '"']))
    {
        let line = text[line_start..].lines().next().unwrap_or_default();
        let header = line.split('#').next().unwrap_or_default().trim();
        let name = header.trim_matches(|c| c == '[' || c == ']').trim();
        if header.ends_with(']') && !name.is_empty() && !name.contains([',', '=', '"']) {
            return Some(name.to_string());
        }
    }
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

/// One line for a TOML shape error (serde's, with a span): `line N, key `K`: what`, or for a
/// missing key `key `K`: missing; …` with the line of the table it belongs in (toml points a
/// missing top-level key at the file's first character, whatever is there). `hint(key, message)`
/// may replace serde's message with what to write instead.
pub(crate) fn describe(
    text: &str,
    e: &toml::de::Error,
    hint: &dyn Fn(&str, &str) -> Option<String>,
) -> String {
    let msg = e.message().trim_end().replace("expected i64", "expected an integer");
    let span = e.span();
    if let Some(field) = msg.strip_prefix("missing field `").and_then(|m| m.strip_suffix('`')) {
        let span = span.filter(|s| !s.is_empty());
        let table = span.as_ref().and_then(|s| key_at(text, s.start));
        let key = table.as_ref().map_or(field.to_string(), |t| format!("{t}.{field}"));
        let what = hint(&key, &msg).map_or("missing".to_string(), |h| format!("missing; {h}"));
        return match (&table, &span) {
            (Some(_), Some(s)) => format!("line {}, key `{key}`: {what}", line_of(text, s.start)),
            _ => format!("key `{key}`: {what}"),
        };
    }
    match span {
        Some(s) => {
            let key = key_at(text, s.start);
            let what = hint(key.as_deref().unwrap_or(""), &msg).unwrap_or(msg);
            match key {
                Some(k) => format!("line {}, key `{k}`: {what}", line_of(text, s.start)),
                None => format!("line {}: {what}", line_of(text, s.start)),
            }
        }
        None => hint("", &msg).unwrap_or(msg),
    }
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
        let t = "a = 1\n[convergence]  # one sweep\nname = \"c\"\n";
        assert_eq!(key_at(t, t.find('[').unwrap()).as_deref(), Some("convergence"));
        let t = "mesh = \"m.obj\"\n[camera.perspective]\n";
        assert_eq!(key_at(t, t.find("camera").unwrap()).as_deref(), Some("camera.perspective"));
        let t = "[[table]]\nrays = [8]\n";
        assert_eq!(key_at(t, t.find("[8]").unwrap()).as_deref(), Some("table.rays"), "a value, not a header");
        let t = "a = 1\nraplicates = 2\n";
        assert_eq!(key_at(t, t.find("raplicates").unwrap()).as_deref(), Some("raplicates"));
    }
}
