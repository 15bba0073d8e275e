//! Lines and keys of byte offsets in the spec text, so every message can say where to look.

/// 1-based line of a byte offset.
pub(crate) fn line_of(text: &str, offset: usize) -> usize {
    text.as_bytes()[..offset.min(text.len())].iter().filter(|&&b| b == b'\n').count() + 1
}

/// Best-effort dotted key at a byte offset, for toml's own errors (which carry a span, not the key):
/// the enclosing `[header]` and the last `key =` at or before the offset (the offset's own key
/// included, for "unknown field" errors that point at the key).
pub(crate) fn key_at(text: &str, offset: usize) -> Option<String> {
    let mut offset = offset.min(text.len());
    // toml's spans fall on characters; a mutated file must not make a slice panic all the same.
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
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
    let this = &text[line_start..offset + ident_len + eq];
    // Outside any bracket the line is a statement of its own, and its key is on it even when its
    // `=` is missing (`ao_distance 1.0`); only inside a value that spans lines (an array of rows)
    // is the key on a line above.
    let top_level = depth_at(text, line_start) == 0;
    let mut key = last_key(this).or_else(|| if top_level { leading_key(this) } else { None });
    if let Some(h) = header_of(this.trim()) {
        return Some(h);
    }
    for line in text[..line_start].lines().rev() {
        if let Some(header) = header_of(line.trim()) {
            return Some(match key {
                Some(k) => format!("{header}.{k}"),
                None => header,
            });
        }
        if key.is_none() && !top_level {
            key = last_key(line);
        }
    }
    key
}

/// The table a `[header]` or `[[header]]` line names.
fn header_of(t: &str) -> Option<String> {
    (t.starts_with('[') && t.ends_with(']') && !t.contains([',', '=', '"']))
        .then(|| t.trim_matches(|c| c == '[' || c == ']').trim().to_string())
}

/// Brackets and braces open before byte `end`, outside strings and comments: a value goes on over
/// lines only inside them. (Their delimiters are ASCII, so a byte scan never splits a character.)
fn depth_at(text: &str, end: usize) -> usize {
    let b = &text.as_bytes()[..end];
    let (mut depth, mut i) = (0usize, 0usize);
    // The open string's quote, and whether it is a triple-quoted (multi-line) one.
    let mut quote: Option<(u8, bool)> = None;
    while i < b.len() {
        let c = b[i];
        match quote {
            None => match c {
                b'#' => {
                    while i < b.len() && b[i] != b'\n' {
                        i += 1;
                    }
                }
                b'"' | b'\'' => {
                    let triple = b[i..].starts_with(&[c, c, c]);
                    quote = Some((c, triple));
                    i += if triple { 2 } else { 0 };
                }
                b'[' | b'{' => depth += 1,
                b']' | b'}' => depth = depth.saturating_sub(1),
                _ => {}
            },
            Some((q, triple)) => {
                if c == b'\\' && q == b'"' {
                    i += 1;
                } else if triple && b[i..].starts_with(&[q, q, q]) {
                    quote = None;
                    i += 2;
                } else if !triple && (c == q || c == b'\n') {
                    // A one-line string ends at its quote, or (unterminated) at the end of its line.
                    quote = None;
                }
            }
        }
        i += 1;
    }
    depth
}

/// The bare key a line starts with, if it starts with one.
fn leading_key(line: &str) -> Option<String> {
    let t = line.trim_start();
    let len = t.find(|c: char| !is_key_char(c)).unwrap_or(t.len());
    (len > 0).then(|| t[..len].to_string())
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

/// A character of a bare key: TOML 1.1 allows letters and digits of any script, `_` and `-`.
fn is_key_char(c: char) -> bool {
    c.is_alphanumeric() || c == '_' || c == '-'
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
                // Just after the last character that is not part of a key (which may take more
                // than one byte: `é`).
                let start = before
                    .char_indices()
                    .rev()
                    .find(|&(_, c)| !is_key_char(c))
                    .map_or(0, |(j, c)| j + c.len_utf8());
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

    #[test]
    fn a_line_without_its_equals_sign_is_blamed_not_the_key_before_it() {
        // Once a panic: the key before was not ASCII, and the slice after it cut `é` in two.
        let t = "mesh = \"m.obj\"\né = [256, 256]\nao_distance -0 150.0\n";
        assert_eq!(key_at(t, t.find("-0").unwrap()).as_deref(), Some("ao_distance"));
        assert_eq!(key_at(t, t.find('=').unwrap() + 3).as_deref(), Some("mesh"));
        assert_eq!(key_at(t, t.find('é').unwrap() + 1).as_deref(), Some("é"), "inside a character");
        let t = "[camera.perspective]\nup [0, 1, 0]\n";
        assert_eq!(key_at(t, t.find("[0").unwrap()).as_deref(), Some("camera.perspective.up"));
        // Inside a multi-line array the key is on a line above, even past a `#` with a bracket.
        let t = "[[table]]\nrows = [ # [\n  \"x\",\n  7,\n]\n";
        assert_eq!(key_at(t, t.find('7').unwrap()).as_deref(), Some("table.rows"));
    }
}
