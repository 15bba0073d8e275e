//! Every unknown key of a spec at once. serde's `deny_unknown_fields` stops at the first one, so a
//! spec with two typos took two runs to fix; this walk of the parsed TOML (with spans, so each key
//! has its line) names them all, and `validate::parse_spec_with` reports them in one error.
//!
//! The key lists are those of `validate`'s raw structs; a unit test below checks each list against
//! the one serde itself prints, so the two cannot drift apart.

use super::position::line_of;
use std::ops::Range;
use toml::de::{DeTable, DeValue};

pub(super) const TOP: &[&str] = &[
    "name",
    "scenes",
    "resolution",
    "ao_distance",
    "replicates",
    "seed",
    "point_figures",
    "flip_ppd",
    "reference",
    "timing",
    "tiles",
    "cameras",
    "denoisers",
    "table",
    "convergence",
];
pub(super) const REFERENCE: &[&str] =
    &["dir", "rays", "replicates", "seed", "distribution", "sequence", "seed_mode", "allocation"];
pub(super) const TIMING: &[&str] = &["repeats", "seed"];
pub(super) const TILES: &[&str] = &["count", "size"];
pub(super) const GROUP: &[&str] = &[
    "name",
    "rays",
    "replicates",
    "scenes",
    "rows",
    "distributions",
    "sequences",
    "seed_modes",
    "frames",
    "pipelines",
    "schedules",
    "integrands",
    "cameras",
    "denoisers",
];
pub(super) const ROW: &[&str] = &["distribution", "sequence", "seed_mode"];
pub(super) const CAMERA: &[&str] = &["path", "jitter"];

/// Each unknown key of `text`: its line, the message (serde's words, and the nearest known key when
/// one is a likely typo) and the span of `key = value`, in the order of the file. Empty when the
/// text is not TOML at all: serde's error then says where the syntax breaks.
pub(super) fn unknown(text: &str) -> Vec<(usize, String, Range<usize>)> {
    let Ok(doc) = DeTable::parse(text) else { return Vec::new() };
    let mut found = Vec::new();
    walk(text, doc.get_ref(), "", TOP, &mut found);
    found.sort_by_key(|(line, _, _)| *line);
    found
}

type Found = Vec<(usize, String, Range<usize>)>;

fn walk(text: &str, table: &DeTable, path: &str, known: &[&str], found: &mut Found) {
    for (key, value) in table.iter() {
        let name: &str = key.get_ref();
        let dotted = if path.is_empty() { name.to_string() } else { format!("{path}.{name}") };
        if !known.contains(&name) {
            let near = nearest(name, known).map_or(String::new(), |k| format!(" (did you mean `{k}`?)"));
            let list = known.iter().map(|k| format!("`{k}`")).collect::<Vec<_>>().join(", ");
            found.push((
                line_of(text, key.span().start),
                format!("key `{dotted}`: unknown field `{name}`{near}, expected one of {list}"),
                key.span().start..value.span().end.max(key.span().end),
            ));
            continue;
        }
        let inner: Option<&[&str]> = match (path, name) {
            ("", "reference") => Some(REFERENCE),
            ("", "timing") => Some(TIMING),
            ("", "tiles") => Some(TILES),
            ("", "table" | "convergence") => Some(GROUP),
            ("table" | "convergence", "rows") => Some(ROW),
            _ => None,
        };
        match (value.get_ref(), inner) {
            (DeValue::Table(t), Some(k)) => walk(text, t, &dotted, k, found),
            (DeValue::Array(items), Some(k)) => {
                for item in items.iter() {
                    if let DeValue::Table(t) = item.get_ref() {
                        walk(text, t, &dotted, k, found);
                    }
                }
            }
            // `[cameras.NAME]`: each named camera's own keys.
            (DeValue::Table(named), None) if path.is_empty() && name == "cameras" => {
                for (cam, v) in named.iter() {
                    if let DeValue::Table(t) = v.get_ref() {
                        walk(text, t, &format!("cameras.{}", cam.get_ref()), CAMERA, found);
                    }
                }
            }
            _ => {}
        }
    }
}

/// `text` with each span (and a comma right after it) blanked to spaces, newlines kept, so the rest
/// of the spec can be checked with its lines unchanged; None when there is nothing to blank or the
/// blanked text is no longer TOML.
pub(super) fn blank(text: &str, spans: &[Range<usize>]) -> Option<String> {
    if spans.is_empty() {
        return None;
    }
    let mut cut: Vec<Range<usize>> = spans.to_vec();
    for c in &mut cut {
        let after = text[c.end..].find(|ch: char| !ch.is_whitespace()).map(|i| c.end + i);
        if let Some(i) = after.filter(|&i| text[i..].starts_with(',')) {
            c.end = i + 1;
        }
    }
    let out: String = text
        .char_indices()
        .map(|(i, ch)| if ch != '\n' && cut.iter().any(|c| c.contains(&i)) { ' ' } else { ch })
        .collect();
    DeTable::parse(&out).is_ok().then_some(out)
}

/// The known key within two edits of `name` (a typo), if there is exactly one nearest.
fn nearest<'a>(name: &str, known: &[&'a str]) -> Option<&'a str> {
    let mut best: Option<(usize, &str)> = None;
    for &k in known {
        let d = strsim::levenshtein(name, k);
        if d <= 2 && best.is_none_or(|(b, _)| d < b) {
            best = Some((d, k));
        }
    }
    best.map(|(_, k)| k)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// serde's own list of expected fields for an unknown key at `text`'s first unknown.
    fn serde_list(text: &str) -> Vec<String> {
        let e = crate::spec::parse_spec(text, std::path::Path::new("s.toml")).unwrap_err().to_string();
        let list = e.split("expected one of ").nth(1).unwrap_or_else(|| panic!("{e}"));
        list.split(", ").map(|k| k.trim().trim_matches('`').to_string()).collect()
    }

    const BASE: &str = "scenes = [\"a.toml\"]\n";

    #[test]
    fn the_key_lists_are_serdes() {
        let group = "[[table]]\nname = \"t\"\nrays = [1]\n";
        let cases: [(String, &[&str]); 5] = [
            (format!("{BASE}zz = 1\n"), TOP),
            (format!("{BASE}[reference]\nzz = 1\n"), REFERENCE),
            (format!("{BASE}[timing]\nzz = 1\n"), TIMING),
            (format!("{BASE}{group}zz = 1\n"), GROUP),
            (
                format!(
                    "{BASE}{group}rows = [{{ distribution = \"sine\", sequence = \"random\", zz = 1 }}]\n"
                ),
                ROW,
            ),
        ];
        for (text, list) in cases {
            assert_eq!(serde_list(&text), *list, "{text}");
        }
    }

    #[test]
    fn every_unknown_key_is_found_with_its_line() {
        let text = format!(
            "{BASE}resolutoin = [8, 8]\n[reference]\nray = 4\n[[table]]\nname = \"t\"\nrays = [1]\n\
             rows = [{{ distribution = \"sine\", sequence = \"random\", seedmode = \"x\" }}]\n"
        );
        let u = unknown(&text);
        let lines: Vec<usize> = u.iter().map(|(l, _, _)| *l).collect();
        assert_eq!(lines, [2, 4, 8], "{u:?}");
        assert!(
            u[0].1.starts_with("key `resolutoin`: unknown field `resolutoin` (did you mean `resolution`?)")
        );
        assert!(u[1].1.starts_with("key `reference.ray`: unknown field `ray` (did you mean `rays`?)"));
        assert!(u[2].1.contains("`seedmode` (did you mean `seed_mode`?)"), "{u:?}");
        assert!(unknown(BASE).is_empty());
        // Blanked, the rest is the same spec with the same lines.
        let spans: Vec<_> = u.iter().map(|(_, _, s)| s.clone()).collect();
        let rest = blank(&text, &spans).expect("still TOML");
        assert_eq!(rest.lines().count(), text.lines().count());
        assert!(unknown(&rest).is_empty(), "{rest}");
        assert!(rest.contains("sequence = \"random\","), "{rest}");
    }
}
