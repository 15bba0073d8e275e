//! Phase 2 of reading a spec (ranges, names, duplicates; all problems gathered with their lines),
//! over phase 1's raw shape (`raw`: serde's shape, unknown keys, types).

use super::group::group;
use super::position::{describe, line_of};
use super::raw::{CameraChoice, Named, RawReference, RawSpec, S};
use super::*;
use crate::error::{Error, Result};

// ---- validation (phase 2) ----

/// Collects problems with their lines, so one run of `hemilab plan` reports all of them.
pub(super) struct Problems<'a> {
    pub(super) text: &'a str,
    pub(super) list: Vec<(usize, String)>,
    /// The group being checked (`table 't2'`), said after its keys: the key path is TOML's
    /// (`table.rays`), and the line and the name say which of several groups it is.
    pub(super) group: Option<String>,
    /// Reads the textures and point sets entries name.
    pub(super) files: &'a dyn Files,
}

impl Problems<'_> {
    pub(super) fn add(&mut self, span: std::ops::Range<usize>, key: &str, what: impl std::fmt::Display) {
        let of =
            self.group.as_ref().filter(|_| key.contains('.')).map_or(String::new(), |g| format!(" ({g})"));
        self.list.push((line_of(self.text, span.start), format!("key `{key}`{of}: {what}")));
    }

    /// A problem of the whole file (something missing), with no line to point at.
    fn add_file(&mut self, key: &str, what: impl std::fmt::Display) {
        self.list.push((0, format!("key `{key}`: {what}")));
    }

    pub(super) fn int(&mut self, v: &S<i64>, key: &str, min: i64, max: i64) -> Option<u32> {
        let x = *v.get_ref();
        if x < min || x > max {
            self.add(v.span(), key, format!("{x} is out of range; allowed {min}..={max}"));
            None
        } else {
            Some(x as u32)
        }
    }

    pub(super) fn name<T: std::str::FromStr<Err = String>>(&mut self, v: &S<String>, key: &str) -> Option<T> {
        v.get_ref().parse::<T>().map_err(|e| self.add(v.span(), key, e)).ok()
    }

    /// A seed mode: a name, or `{ texture = "PATH", use = "offset" | "rotation" | "vector" }`.
    pub(super) fn seed_mode(&mut self, v: &S<toml::Value>, key: &str) -> Option<SeedMode> {
        self.file_entry(v, key, "texture", &["use"], |files, path, t| {
            let use_ = match t.get("use") {
                None => crate::sampling::texture::TextureUse::Offset,
                Some(toml::Value::String(u)) => crate::sampling::texture::TextureUse::parse(u)?,
                Some(other) => {
                    return Err(format!("`use` is {other}; allowed: \"offset\", \"rotation\", \"vector\""));
                }
            };
            files.texture(path, use_)
        })
    }

    /// A sequence: a name, or `{ points = "PATH" }`.
    pub(super) fn sequence(&mut self, v: &S<toml::Value>, key: &str) -> Option<Sequence> {
        self.file_entry(v, key, "points", &[], |files, path, _| files.points(path))
    }

    /// A name (parsed as `T`), or a table `{ <file> = "PATH", <extra>… }` read by `read`.
    fn file_entry<T: std::str::FromStr<Err = String>>(
        &mut self,
        v: &S<toml::Value>,
        key: &str,
        file: &str,
        extra: &[&str],
        read: impl FnOnce(&dyn Files, &str, &toml::Table) -> std::result::Result<T, String>,
    ) -> Option<T> {
        let how = format!(
            "a name, or {{ {file} = \"PATH\"{} }}",
            extra.iter().map(|e| format!(", {e} = ..")).collect::<String>()
        );
        let result = match v.get_ref() {
            toml::Value::String(s) => s.parse::<T>(),
            toml::Value::Table(t) => match t.get(file) {
                _ if t.keys().any(|k| k != file && !extra.contains(&k.as_str())) => {
                    let bad: Vec<&str> =
                        t.keys().map(String::as_str).filter(|k| *k != file && !extra.contains(k)).collect();
                    Err(format!("unknown key `{}`; {how}", bad.join("`, `")))
                }
                Some(toml::Value::String(path)) => read(self.files, path, t),
                Some(other) => Err(format!("`{file}` is {other}, not a path; {how}")),
                None => Err(format!("missing `{file}`; {how}")),
            },
            other => Err(format!("{other} is not {how}")),
        };
        result.map_err(|e| self.add(v.span(), key, e)).ok()
    }

    fn seed(&mut self, v: &S<i64>, key: &str) -> u64 {
        self.int(v, key, 0, u32::MAX as i64).map_or(0, u64::from)
    }

    pub(super) fn ident(&mut self, v: &S<String>, key: &str) -> Option<String> {
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

    pub(super) fn non_empty<T>(&mut self, v: &S<Vec<T>>, key: &str) -> bool {
        if v.get_ref().is_empty() {
            self.add(v.span(), key, "is empty; list at least one value");
        }
        !v.get_ref().is_empty()
    }
}

/// Parses and validates a spec. No IO: `path` is for messages and for resolving scene paths; a
/// texture or point file entry is an error (`parse_spec_with` reads them).
pub fn parse_spec(text: &str, path: &Path) -> Result<Spec> {
    parse_spec_with(text, path, &NoFiles)
}

/// `parse_spec`, reading the textures and point sets the spec names through `files`.
pub fn parse_spec_with(text: &str, path: &Path, files: &dyn Files) -> Result<Spec> {
    // Every unknown key at once (serde names only the first); the rest of the spec is then checked
    // without them (their text blanked, its lines kept), so that typos and bad values are all
    // reported by one run.
    let mut unknown = super::keys::unknown(text);
    // A scene file given for a spec: one message that says so (`shape_hint`), not a list of its keys.
    if unknown.iter().any(|(_, m, _)| m.starts_with("key `mesh`:") || m.starts_with("key `camera`:")) {
        unknown.clear();
    }
    let mut list: Vec<(usize, String)> = unknown.iter().map(|(l, m, _)| (*l, m.clone())).collect();
    let spans: Vec<std::ops::Range<usize>> = unknown.into_iter().map(|(_, _, s)| s).collect();
    let rest = super::keys::blank(text, &spans);
    match checked(rest.as_deref().unwrap_or(text), path, files) {
        Ok(spec) if list.is_empty() => return Ok(spec),
        Ok(_) => {}
        // Unless blanking broke the file (then the unknown keys alone are the news).
        Err(more) if spans.is_empty() || rest.is_some() => list.extend(more),
        Err(_) => {}
    }
    list.sort_by_key(|(line, _)| *line);
    // One line per problem, each naming the file, so every line alone says where to look.
    let lines: Vec<String> =
        list.iter().map(|(l, m)| if *l == 0 { m.clone() } else { format!("line {l}, {m}") }).collect();
    Err(Error::input(path, lines.join(&format!("\n{}: ", path.display()))))
}

/// Phases 1 and 2 on a spec's text: the spec, or its problems with their lines (0: the message
/// says its own line, or has none).
fn checked(text: &str, path: &Path, files: &dyn Files) -> std::result::Result<Spec, Vec<(usize, String)>> {
    let raw: RawSpec = toml::from_str(text).map_err(|e| vec![(0, describe(text, &e, &shape_hint))])?;
    let mut p = Problems { text, list: Vec::new(), group: None, files };
    let spec = validate(raw, path, &mut p);
    if p.list.is_empty() { Ok(spec) } else { Err(p.list) }
}

/// What to write instead, for the shape errors a person makes (serde's words name types, not fixes).
fn shape_hint(key: &str, message: &str) -> Option<String> {
    let group = matches!(key, "table" | "convergence");
    if group && message.contains("invalid type: map, expected a sequence") {
        return Some(format!(
            "write `[[{key}]]` with double brackets, not `[{key}]`: each `[[{key}]]` is one {}, and a spec \
             may have several",
            if key == "table" { "table" } else { "sweep" }
        ));
    }
    if ["`mesh`", "`camera`"].iter().any(|k| message.starts_with(&format!("unknown field {k}"))) {
        return Some(
            "this is a scene file, not a spec: `hemilab run` and `plan` take a spec (like \
             experiments/smoke.toml), which names its scene files in `scenes = [..]`; `render` and `bench` \
             take a scene file"
                .into(),
        );
    }
    if !message.starts_with("missing field") {
        return None;
    }
    let field = key.rsplit('.').next().unwrap_or(key);
    Some(match field {
        "scenes" => "add `scenes = [\"../scenes/kitchen.toml\"]`, paths relative to the spec file".into(),
        "name" => "give it a `name = \"...\"` (letters, digits, '-', '_')".into(),
        "rays" => "add `rays = [8, 16, 32]`, the ray counts per pixel".into(),
        "distribution" => format!("add `distribution = ..`, one of {}", names(Distribution::ALL)),
        "sequence" => format!("add `sequence = ..`, one of {}", names(&Sequence::all())),
        _ => return None,
    })
}

pub(super) fn names<T: std::fmt::Display>(all: &[T]) -> String {
    all.iter().map(|x| format!("\"{x}\"")).collect::<Vec<_>>().join(", ")
}

/// The figure files (stems, `.png`) a group's report writes: `report::run::figures` names them so.
fn figure_stems(g: &Group, scenes: &[SceneRef]) -> Vec<String> {
    let suffixes: &[&str] = match g.kind {
        GroupKind::Table => &["", "_error"],
        GroupKind::Convergence => &["_rays", "_time", "_efficiency"],
    };
    let bases: Vec<String> = if g.scenes.len() > 1 {
        g.scenes.iter().map(|&si| format!("{}_{}", g.name, scenes[si].name)).collect()
    } else {
        vec![g.name.clone()]
    };
    bases.iter().flat_map(|b| suffixes.iter().map(move |s| format!("{b}{s}"))).collect()
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
                Some(stem) => {
                    let line = line_of(p.text, s.span().start);
                    scenes.push(SceneRef {
                        path: dir.join(&id),
                        id,
                        name: stem,
                        line,
                        integrand: Integrand::Ao,
                    })
                }
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
        let (w, h) = (w?, h?);
        if !resolution_ok(w as u64, h as u64) {
            p.add(r.span(), "resolution", format!("{w}x{h} is too large; {RESOLUTION_RULE}"));
            return None;
        }
        Some([w, h])
    });
    let ao_distance = raw.ao_distance.as_ref().and_then(|v| distance(v, p));
    let flip_ppd = raw.flip_ppd.as_ref().map_or(crate::metrics::DEFAULT_PPD, |v| ppd(v, p));
    let tiles = raw.tiles.as_ref().and_then(|t| super::tiles::tiles(t, resolution, p));
    let replicates = raw
        .replicates
        .as_ref()
        .map_or(Some(DEFAULT_REPLICATES), |r| p.int(r, "replicates", 1, MAX_REPLICATES as i64));
    let seed = raw.seed.as_ref().map_or(1, |s| p.seed(s, "seed"));
    let reference = reference(raw.reference.as_ref(), seed, p);
    let reference_dir = match raw.reference.as_ref().and_then(|r| r.dir.as_ref()) {
        Some(d) if d.get_ref().trim().is_empty() => {
            p.add(
                d.span(),
                "reference.dir",
                "is empty; a directory relative to the spec file, e.g. \"reference\"",
            );
            dir.join("reference")
        }
        Some(d) => dir.join(d.get_ref()),
        None => dir.join("reference"),
    };
    let timing = TimingSpec {
        repeats: raw
            .timing
            .as_ref()
            .and_then(|t| t.repeats.as_ref())
            .map_or(crate::timing::DEFAULT_REPEATS, |r| {
                p.int(r, "timing.repeats", 1, MAX_TIMING_REPEATS as i64).unwrap_or(1)
            }),
        seed: raw.timing.as_ref().and_then(|t| t.seed.as_ref()).map_or(seed, |s| p.seed(s, "timing.seed")),
    };

    let mut groups = Vec::new();
    let all = raw
        .table
        .iter()
        .map(|g| (GroupKind::Table, g))
        .chain(raw.convergence.iter().map(|g| (GroupKind::Convergence, g)));
    let mut all: Vec<_> = all.collect();
    all.sort_by_key(|(_, g)| g.span().start);
    if all.is_empty() {
        p.add_file("table", "the spec has no [[table]] and no [[convergence]]; add at least one");
    }
    let point_figures = raw.point_figures.as_ref().is_some_and(|b| *b.get_ref());
    // Figure files already taken: the banding plot, and the point figures when drawn.
    let mut taken: Vec<(String, String)> = vec![("banding".into(), "the banding figure".into())];
    if point_figures {
        for f in ["table1", "figure2", "figure3", "figure4"] {
            taken.push((f.into(), "a point figure (point_figures = true)".into()));
        }
    }
    let mut cameras: Vec<(String, CameraChoice)> = Vec::new();
    for (name, c) in &raw.cameras {
        if name == crate::plan::CameraId::STATIC_NAME
            || !name.chars().all(|ch| ch.is_ascii_alphanumeric() || ch == '-' || ch == '_')
            || name.is_empty()
        {
            p.add(
                c.span(),
                &format!("cameras.{name}"),
                "a camera's name is letters, digits, '-' and '_', and not `static` (the scene's own camera, always there)",
            );
            continue;
        }
        cameras.push((
            name.clone(),
            CameraChoice { path: c.get_ref().path.clone(), jitter: c.get_ref().jitter },
        ));
    }
    let mut denoisers: Vec<crate::plan::Denoiser> = Vec::new();
    for (name, d) in &raw.denoisers {
        let key = format!("denoisers.{name}");
        match d.get_ref().validate() {
            Err(e) => p.add(d.span(), &key, e),
            Ok(()) => denoisers.push(crate::plan::Denoiser {
                name: name.clone(),
                command: d.get_ref().clone().resolve(dir),
            }),
        }
    }
    let named = Named { cameras: &cameras, denoisers: &denoisers };
    for (kind, g) in all {
        if let Some(group) = group(kind, g, &mut scenes, replicates.unwrap_or(DEFAULT_REPLICATES), &named, p)
        {
            let key = format!("{}.name", kind_key(kind));
            if groups.iter().any(|o: &Group| o.name == group.name) {
                p.add(
                    g.get_ref().name.span(),
                    &key,
                    format!("duplicate name '{}'; table and convergence names must be unique", group.name),
                );
            } else {
                // Two groups must not write the same figure file, or one silently replaces the other.
                for file in figure_stems(&group, &scenes) {
                    if let Some((_, owner)) = taken.iter().find(|(f, _)| *f == file) {
                        p.add(
                            g.get_ref().name.span(),
                            &key,
                            format!(
                                "name '{}' would write {file}.png, which {owner} also writes; choose another name",
                                group.name
                            ),
                        );
                        break;
                    }
                }
                let owner = format!("{} '{}'", kind_key(kind), group.name);
                taken.extend(figure_stems(&group, &scenes).into_iter().map(|f| (f, owner.clone())));
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
        flip_ppd,
        tiles,
        steady_state: false,
        replicates: replicates.unwrap_or(DEFAULT_REPLICATES),
        seed,
        point_figures,
        reference,
        reference_dir,
        timing,
        groups,
    }
}

pub(super) fn kind_key(kind: GroupKind) -> &'static str {
    match kind {
        GroupKind::Table => "table",
        GroupKind::Convergence => "convergence",
    }
}

/// The most pixels per degree `flip_ppd` may say: a pixel of 1/1000 of a degree is finer than any
/// display a person looks at (FLIP's own default is 67).
pub const MAX_FLIP_PPD: f64 = 1000.0;

fn ppd(v: &S<toml::Value>, p: &mut Problems) -> f64 {
    let d = match v.get_ref() {
        toml::Value::Float(f) => *f,
        toml::Value::Integer(i) => *i as f64,
        _ => f64::NAN,
    };
    if d.is_finite() && d > 0.0 && d <= MAX_FLIP_PPD {
        return d;
    }
    p.add(
        v.span(),
        "flip_ppd",
        format!(
            "{} is not allowed; pixels per degree for LDR-FLIP, a number in (0, {MAX_FLIP_PPD}] (FLIP's default 67)",
            v.get_ref()
        ),
    );
    crate::metrics::DEFAULT_PPD
}

fn distance(v: &S<toml::Value>, p: &mut Problems) -> Option<AoDistance> {
    let d = match v.get_ref() {
        toml::Value::String(s) if is_infinite(s) => return Some(AoDistance::Infinite),
        toml::Value::Float(f) => *f,
        toml::Value::Integer(i) => *i as f64,
        _ => f64::NAN,
    };
    // The renderer works in f32: a distance that rounds to 0 or to infinity there is not the one asked for.
    let f = d as f32;
    if d.is_finite() && d > 0.0 && f.is_finite() && f >= f32::MIN_POSITIVE {
        Some(AoDistance::Finite(d))
    } else {
        p.add(
            v.span(),
            "ao_distance",
            format!(
                "{} is not allowed; a number in [{:e}, {:e}] or \"infinite\" (or \"inf\")",
                v.get_ref(),
                f32::MIN_POSITIVE,
                f32::MAX
            ),
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
        adaptive: false,
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
    if let Some(a) = &raw.allocation {
        match a.get_ref().as_str() {
            "even" => r.adaptive = false,
            "adaptive" => r.adaptive = true,
            other => p.add(
                a.span(),
                "reference.allocation",
                format!("'{other}' is not allowed; \"even\" or \"adaptive\""),
            ),
        }
    }
    r
}
