//! Experiment spec (`experiments/*.toml`): what to render and compare, validated before any work.
//!
//! Parsing is two-phase so that errors point at lines: serde (with `deny_unknown_fields`) checks the
//! shape and stops at the first unknown key or wrong type; then every value carries its span
//! (`toml::Spanned`) and the range/name checks run over the whole file, gathering all problems at once.
//! Every message reads `line N, key K: what is wrong; what is allowed`.

use crate::error::{Error, Result};
use crate::sampling::{Distribution, SeedMode, Sequence};
use serde::Deserialize;
use std::path::{Component, Path, PathBuf};
use toml::Spanned;

/// Ray counts above this are a typo, not an experiment (an image at 64k rays is a reference).
pub const MAX_RAYS: u32 = 65_536;
/// References may go higher: they are rendered once and committed.
pub const MAX_REFERENCE_RAYS: u32 = 1 << 22;
pub const MAX_REPLICATES: u32 = 1000;
pub const MAX_SIDE: u32 = 16_384;

/// AO distance d: rays hitting farther than this count as open.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AoDistance {
    Finite(f64),
    Infinite,
}

impl AoDistance {
    /// Stable text (shortest round-tripping float), used in job keys and manifests.
    pub fn canonical(&self) -> String {
        match self {
            AoDistance::Finite(d) => format!("{d:?}"),
            AoDistance::Infinite => "infinite".into(),
        }
    }

    pub fn as_f32(&self) -> f32 {
        match self {
            AoDistance::Finite(d) => *d as f32,
            AoDistance::Infinite => f32::INFINITY,
        }
    }
}

/// One estimator: a row of the paper's tables.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Row {
    pub distribution: Distribution,
    pub sequence: Sequence,
    pub seed_mode: SeedMode,
}

impl Row {
    pub fn new(distribution: Distribution, sequence: Sequence, seed_mode: SeedMode) -> Self {
        Self { distribution, sequence, seed_mode }
    }

    /// Pseudo-random numbers are fresh per pixel whether "rotated" or "shifted", so both name the
    /// same images; `rotation` is the one kept. (`static` + random is a distinct, odd choice.)
    pub fn canonical(self) -> Self {
        match (self.sequence, self.seed_mode) {
            (Sequence::Random, SeedMode::Shift) => Self { seed_mode: SeedMode::Rotation, ..self },
            _ => self,
        }
    }

    pub fn label(&self) -> String {
        format!("{}/{}/{}", self.distribution, self.sequence, self.seed_mode)
    }
}

/// A scene as the spec names it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SceneRef {
    /// Where to load it from: the spec's directory joined with `id`.
    pub path: PathBuf,
    /// The path as written in the spec, lexically normalized; part of job keys (portable across clones).
    pub id: String,
    /// File stem: the `scene` column of the results.
    pub name: String,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GroupKind {
    /// Like the paper's tables 2 and 3: images side by side.
    Table,
    /// Error against ray count and time, for slopes.
    Convergence,
}

/// A `[[table]]` or `[[convergence]]`: rows × ray counts × replicates, for some scenes.
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    pub kind: GroupKind,
    pub name: String,
    /// Canonical rows (see `Row::canonical`), duplicates merged, in file order.
    pub rows: Vec<Row>,
    /// Duplicates merged, in file order.
    pub rays: Vec<u32>,
    pub replicates: u32,
    /// Indices into `Spec::scenes`.
    pub scenes: Vec<usize>,
    pub line: usize,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReferenceRays {
    Fixed(u32),
    /// Enough that the noise floor is at most 1/10 of the smallest RMSE measured (decided by the app).
    Auto,
}

#[derive(Debug, Clone, PartialEq)]
pub struct ReferenceSpec {
    /// Rays per pixel of each reference replicate.
    pub rays: ReferenceRays,
    /// Independent renders; their spread gives the per-pixel standard error (so at least 2).
    pub replicates: u32,
    pub seed: u64,
    pub estimator: Row,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Spec {
    pub path: PathBuf,
    /// Default output directory is `out/<name>/`.
    pub name: String,
    pub scenes: Vec<SceneRef>,
    pub resolution: Option<[u32; 2]>,
    pub ao_distance: Option<AoDistance>,
    pub replicates: u32,
    pub seed: u64,
    pub reference: ReferenceSpec,
    /// Tables and sweeps in file order.
    pub groups: Vec<Group>,
}

impl Spec {
    pub fn group(&self, name: &str) -> Option<&Group> {
        self.groups.iter().find(|g| g.name == name)
    }
}

// ---- raw shape (phase 1) ----

type S<T> = Spanned<T>;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSpec {
    name: Option<S<String>>,
    scenes: S<Vec<S<String>>>,
    resolution: Option<S<Vec<S<i64>>>>,
    ao_distance: Option<S<toml::Value>>,
    replicates: Option<S<i64>>,
    seed: Option<S<i64>>,
    reference: Option<RawReference>,
    #[serde(default)]
    table: Vec<S<RawGroup>>,
    #[serde(default)]
    convergence: Vec<S<RawGroup>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawReference {
    rays: Option<S<toml::Value>>,
    replicates: Option<S<i64>>,
    seed: Option<S<i64>>,
    distribution: Option<S<String>>,
    sequence: Option<S<String>>,
    seed_mode: Option<S<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawGroup {
    name: S<String>,
    rays: S<Vec<S<i64>>>,
    replicates: Option<S<i64>>,
    scenes: Option<S<Vec<S<String>>>>,
    rows: Option<S<Vec<S<RawRow>>>>,
    distributions: Option<S<Vec<S<String>>>>,
    sequences: Option<S<Vec<S<String>>>>,
    seed_modes: Option<S<Vec<S<String>>>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRow {
    distribution: S<String>,
    sequence: S<String>,
    seed_mode: Option<S<String>>,
}

// ---- validation (phase 2) ----

/// Collects problems with their lines, so one run of `hemilab plan` reports all of them.
struct Problems<'a> {
    text: &'a str,
    list: Vec<(usize, String)>,
}

impl Problems<'_> {
    fn add(&mut self, span: std::ops::Range<usize>, key: &str, what: impl std::fmt::Display) {
        self.list.push((line_of(self.text, span.start), format!("key `{key}`: {what}")));
    }

    fn int(&mut self, v: &S<i64>, key: &str, min: i64, max: i64) -> Option<u32> {
        let x = *v.get_ref();
        if x < min || x > max {
            self.add(v.span(), key, format!("{x} is out of range; allowed {min}..={max}"));
            None
        } else {
            Some(x as u32)
        }
    }

    fn name<T: std::str::FromStr<Err = String>>(&mut self, v: &S<String>, key: &str) -> Option<T> {
        v.get_ref().parse::<T>().map_err(|e| self.add(v.span(), key, e)).ok()
    }

    fn seed(&mut self, v: &S<i64>, key: &str) -> u64 {
        self.int(v, key, 0, u32::MAX as i64).map_or(0, u64::from)
    }

    fn ident(&mut self, v: &S<String>, key: &str) -> Option<String> {
        let s = v.get_ref();
        let ok = !s.is_empty() && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_');
        if !ok {
            self.add(
                v.span(),
                key,
                format!("'{s}' is not a usable name; allowed: letters, digits, '-', '_'"),
            );
        }
        ok.then(|| s.clone())
    }

    fn non_empty<T>(&mut self, v: &S<Vec<T>>, key: &str) -> bool {
        if v.get_ref().is_empty() {
            self.add(v.span(), key, "is empty; list at least one value");
        }
        !v.get_ref().is_empty()
    }
}

/// 1-based line of a byte offset.
fn line_of(text: &str, offset: usize) -> usize {
    text.as_bytes()[..offset.min(text.len())].iter().filter(|&&b| b == b'\n').count() + 1
}

/// Best-effort dotted key at a byte offset, for toml's own errors (which carry a span, not the key):
/// the enclosing `[header]` and the nearest `key =` at or above the offset within it.
fn key_at(text: &str, offset: usize) -> Option<String> {
    let upto = &text[..offset.min(text.len())];
    let mut key = None;
    for line in upto.lines().rev() {
        let t = line.trim();
        if t.starts_with('[') {
            let header = t.trim_matches(|c| c == '[' || c == ']').trim();
            return Some(match key {
                Some(k) => format!("{header}.{k}"),
                None => header.to_string(),
            });
        }
        if key.is_none()
            && let Some((k, _)) = t.split_once('=')
        {
            let k = k.trim().trim_start_matches(['{', ',']).trim();
            if !k.is_empty() && k.chars().all(|c| c.is_ascii_alphanumeric() || "_-.\"".contains(c)) {
                key = Some(k.to_string());
            }
        }
    }
    key
}

/// Parses and validates a spec. No IO: `path` is for messages and for resolving scene paths.
pub fn parse_spec(text: &str, path: &Path) -> Result<Spec> {
    let raw: RawSpec = toml::from_str(text).map_err(|e| {
        let what = match e.span() {
            Some(span) => {
                let key = key_at(text, span.start).map(|k| format!(", key `{k}`")).unwrap_or_default();
                format!("line {}{key}: {}", line_of(text, span.start), e.message().trim_end())
            }
            None => e.message().trim_end().to_string(),
        };
        Error::input(path, what)
    })?;
    let mut p = Problems { text, list: Vec::new() };
    let spec = validate(raw, path, &mut p);
    if p.list.is_empty() {
        Ok(spec)
    } else {
        p.list.sort_by_key(|(line, _)| *line);
        let lines: Vec<String> = p.list.iter().map(|(l, m)| format!("line {l}, {m}")).collect();
        Err(Error::input(path, lines.join("\n")))
    }
}

fn validate(raw: RawSpec, path: &Path, p: &mut Problems) -> Spec {
    let name = match &raw.name {
        Some(n) => p.ident(n, "name").unwrap_or_default(),
        None => path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "spec".into()),
    };
    let dir = path.parent().unwrap_or(Path::new(""));
    let mut scenes: Vec<SceneRef> = Vec::new();
    if p.non_empty(&raw.scenes, "scenes") {
        for s in raw.scenes.get_ref() {
            let id = normalize(s.get_ref());
            let stem = Path::new(&id).file_stem().map(|x| x.to_string_lossy().into_owned());
            match stem {
                None => p.add(s.span(), "scenes", format!("'{}' is not a file path", s.get_ref())),
                Some(stem) if scenes.iter().any(|o| o.name == stem) => p.add(
                    s.span(),
                    "scenes",
                    format!("a second scene named '{stem}'; scene file names must differ"),
                ),
                Some(stem) => scenes.push(SceneRef { path: dir.join(&id), id, name: stem }),
            }
        }
    }
    let resolution = raw.resolution.as_ref().and_then(|r| {
        if r.get_ref().len() != 2 {
            p.add(r.span(), "resolution", "must be [width, height]");
            return None;
        }
        let w = p.int(&r.get_ref()[0], "resolution", 1, MAX_SIDE as i64);
        let h = p.int(&r.get_ref()[1], "resolution", 1, MAX_SIDE as i64);
        Some([w?, h?])
    });
    let ao_distance = raw.ao_distance.as_ref().and_then(|v| distance(v, p));
    let replicates =
        raw.replicates.as_ref().map_or(Some(1), |r| p.int(r, "replicates", 1, MAX_REPLICATES as i64));
    let seed = raw.seed.as_ref().map_or(1, |s| p.seed(s, "seed"));
    let reference = reference(raw.reference.as_ref(), seed, p);

    let mut groups = Vec::new();
    let all = raw
        .table
        .iter()
        .map(|g| (GroupKind::Table, g))
        .chain(raw.convergence.iter().map(|g| (GroupKind::Convergence, g)));
    let mut all: Vec<_> = all.collect();
    all.sort_by_key(|(_, g)| g.span().start);
    if all.is_empty() {
        p.add(0..0, "table", "the spec has no [[table]] and no [[convergence]]; add at least one");
    }
    for (kind, g) in all {
        if let Some(group) = group(kind, g, &scenes, replicates.unwrap_or(1), p) {
            if groups.iter().any(|o: &Group| o.name == group.name) {
                p.add(
                    g.get_ref().name.span(),
                    &format!("{}.name", kind_key(kind)),
                    format!("duplicate name '{}'; table and convergence names must be unique", group.name),
                );
            }
            groups.push(group);
        }
    }
    Spec {
        path: path.to_path_buf(),
        name,
        scenes,
        resolution,
        ao_distance,
        replicates: replicates.unwrap_or(1),
        seed,
        reference,
        groups,
    }
}

fn kind_key(kind: GroupKind) -> &'static str {
    match kind {
        GroupKind::Table => "table",
        GroupKind::Convergence => "convergence",
    }
}

fn distance(v: &S<toml::Value>, p: &mut Problems) -> Option<AoDistance> {
    let d = match v.get_ref() {
        toml::Value::String(s) if s == "infinite" => return Some(AoDistance::Infinite),
        toml::Value::Float(f) => *f,
        toml::Value::Integer(i) => *i as f64,
        _ => f64::NAN,
    };
    if d.is_finite() && d > 0.0 {
        Some(AoDistance::Finite(d))
    } else {
        p.add(
            v.span(),
            "ao_distance",
            format!("{} is not allowed; a number > 0 or \"infinite\"", v.get_ref()),
        );
        None
    }
}

fn reference(raw: Option<&RawReference>, seed: u64, p: &mut Problems) -> ReferenceSpec {
    let mut r = ReferenceSpec {
        rays: ReferenceRays::Auto,
        replicates: 4,
        seed,
        estimator: Row::new(Distribution::SineCosine, Sequence::Fibonacci, SeedMode::Shift),
    };
    let Some(raw) = raw else { return r };
    if let Some(v) = &raw.rays {
        match v.get_ref() {
            toml::Value::String(s) if s == "auto" => {}
            toml::Value::Integer(i) if (1..=MAX_REFERENCE_RAYS as i64).contains(i) => {
                r.rays = ReferenceRays::Fixed(*i as u32)
            }
            other => p.add(
                v.span(),
                "reference.rays",
                format!("{other} is not allowed; \"auto\" or 1..={MAX_REFERENCE_RAYS}"),
            ),
        }
    }
    if let Some(n) = &raw.replicates {
        r.replicates = p.int(n, "reference.replicates", 2, MAX_REPLICATES as i64).unwrap_or(2);
    }
    if let Some(s) = &raw.seed {
        r.seed = p.seed(s, "reference.seed");
    }
    let e = &mut r.estimator;
    if let Some(d) = raw.distribution.as_ref().and_then(|v| p.name(v, "reference.distribution")) {
        e.distribution = d;
    }
    if let Some(s) = raw.sequence.as_ref().and_then(|v| p.name(v, "reference.sequence")) {
        e.sequence = s;
    }
    if let Some(m) = raw.seed_mode.as_ref().and_then(|v| p.name(v, "reference.seed_mode")) {
        e.seed_mode = m;
    }
    *e = e.canonical();
    r
}

fn group(
    kind: GroupKind,
    g: &S<RawGroup>,
    scenes: &[SceneRef],
    replicates: u32,
    p: &mut Problems,
) -> Option<Group> {
    let k = kind_key(kind);
    let raw = g.get_ref();
    let name = p.ident(&raw.name, &format!("{k}.name"));
    let at = |key: &str| format!("{k}.{}.{key}", raw.name.get_ref());
    let mut rays = Vec::new();
    if p.non_empty(&raw.rays, &at("rays")) {
        for r in raw.rays.get_ref() {
            if let Some(n) = p.int(r, &at("rays"), 1, MAX_RAYS as i64)
                && !rays.contains(&n)
            {
                rays.push(n);
            }
        }
    }
    let replicates = match &raw.replicates {
        Some(r) => p.int(r, &at("replicates"), 1, MAX_REPLICATES as i64).unwrap_or(1),
        None => replicates,
    };
    let group_scenes = match &raw.scenes {
        None => (0..scenes.len()).collect(),
        Some(list) => {
            p.non_empty(list, &at("scenes"));
            let mut out = Vec::new();
            for s in list.get_ref() {
                let id = normalize(s.get_ref());
                match scenes.iter().position(|o| o.id == id || o.name == *s.get_ref()) {
                    Some(i) if !out.contains(&i) => out.push(i),
                    Some(_) => {}
                    None => {
                        let valid: Vec<&str> = scenes.iter().map(|o| o.name.as_str()).collect();
                        p.add(
                            s.span(),
                            &at("scenes"),
                            format!("unknown scene '{}'; valid: {}", s.get_ref(), valid.join(", ")),
                        )
                    }
                }
            }
            out
        }
    };
    let rows = rows(raw, &at(""), g.span(), p);
    Some(Group {
        kind,
        name: name?,
        rows: rows?,
        rays,
        replicates,
        scenes: group_scenes,
        line: line_of(p.text, g.span().start),
    })
}

fn rows(raw: &RawGroup, at: &str, span: std::ops::Range<usize>, p: &mut Problems) -> Option<Vec<Row>> {
    let axes = raw.distributions.is_some() || raw.sequences.is_some() || raw.seed_modes.is_some();
    let mut out = Vec::new();
    let mut push = |r: Row| {
        let r = r.canonical();
        if !out.contains(&r) {
            out.push(r);
        }
    };
    match (&raw.rows, axes) {
        (Some(rows), true) => {
            p.add(
                rows.span(),
                &format!("{at}rows"),
                "give either `rows` or the axes `distributions`/`sequences`/`seed_modes`, not both",
            );
            return None;
        }
        (None, false) => {
            p.add(span, &format!("{at}rows"), "missing; give `rows = [{ distribution = .., sequence = .., seed_mode = .. }]` or the axes `distributions` and `sequences` (and optionally `seed_modes`)");
            return None;
        }
        (Some(rows), false) => {
            if !p.non_empty(rows, &format!("{at}rows")) {
                return None;
            }
            let mut ok = true;
            for row in rows.get_ref() {
                let r = row.get_ref();
                let d = p.name::<Distribution>(&r.distribution, &format!("{at}rows.distribution"));
                let s = p.name::<Sequence>(&r.sequence, &format!("{at}rows.sequence"));
                let m = match &r.seed_mode {
                    Some(m) => p.name::<SeedMode>(m, &format!("{at}rows.seed_mode")),
                    None => Some(SeedMode::Rotation),
                };
                match (d, s, m) {
                    (Some(d), Some(s), Some(m)) => push(Row::new(d, s, m)),
                    _ => ok = false,
                }
            }
            ok.then_some(out)
        }
        (None, true) => {
            let ds = axis::<Distribution>(&raw.distributions, &format!("{at}distributions"), span.clone(), p);
            let ss = axis::<Sequence>(&raw.sequences, &format!("{at}sequences"), span, p);
            let ms = match &raw.seed_modes {
                None => Some(vec![SeedMode::Rotation]),
                Some(v) => axis::<SeedMode>(&Some(v.clone()), &format!("{at}seed_modes"), 0..0, p),
            };
            let (ds, ss, ms) = (ds?, ss?, ms?);
            for &d in &ds {
                for &s in &ss {
                    for &m in &ms {
                        push(Row::new(d, s, m));
                    }
                }
            }
            Some(out)
        }
    }
}

fn axis<T: std::str::FromStr<Err = String>>(
    v: &Option<S<Vec<S<String>>>>,
    key: &str,
    span: std::ops::Range<usize>,
    p: &mut Problems,
) -> Option<Vec<T>> {
    let Some(v) = v else {
        p.add(span, key, "missing; with the axes form give both `distributions` and `sequences`");
        return None;
    };
    if !p.non_empty(v, key) {
        return None;
    }
    let parsed: Vec<Option<T>> = v.get_ref().iter().map(|s| p.name::<T>(s, key)).collect();
    parsed.into_iter().collect()
}

/// Lexical normalization ("./a/../b" → "b"), with '/' separators so keys match across platforms.
fn normalize(path: &str) -> String {
    let mut parts: Vec<String> = Vec::new();
    for c in Path::new(path).components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir if parts.last().is_some_and(|l| l != "..") => {
                parts.pop();
            }
            other => parts.push(other.as_os_str().to_string_lossy().into_owned()),
        }
    }
    let joined = parts.join("/");
    if path.starts_with('/') && !joined.starts_with('/') { format!("/{joined}") } else { joined }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalize_paths() {
        assert_eq!(normalize("./a/../b.toml"), "b.toml");
        assert_eq!(normalize("../scenes/kitchen.toml"), "../scenes/kitchen.toml");
        assert_eq!(normalize("../../x"), "../../x");
    }

    #[test]
    fn key_at_finds_header_and_key() {
        let t = "name = \"x\"\n[[table]]\nname = \"t\"\nrays = [\"a\"]\n";
        let off = t.find("\"a\"").unwrap();
        assert_eq!(key_at(t, off).as_deref(), Some("table.rays"));
        assert_eq!(line_of(t, off), 4);
    }

    #[test]
    fn random_shift_is_random_rotation() {
        let r = Row::new(Distribution::Sine, Sequence::Random, SeedMode::Shift).canonical();
        assert_eq!(r.seed_mode, SeedMode::Rotation);
        let f = Row::new(Distribution::Sine, Sequence::Fibonacci, SeedMode::Shift).canonical();
        assert_eq!(f.seed_mode, SeedMode::Shift);
        let s = Row::new(Distribution::Sine, Sequence::Random, SeedMode::Static).canonical();
        assert_eq!(s.seed_mode, SeedMode::Static);
    }
}
