//! Phase 2 of reading a spec for one `[[table]]` or `[[convergence]]` group: its name, rays,
//! replicates, scenes and rows (explicit `rows`, or the product of `distributions` × `sequences` ×
//! `seed_modes`), every problem gathered with its line.

use super::position::line_of;
use super::raw::{Named, RawGroup, S};
use super::validate::{Problems, kind_key};
use super::*;
use crate::plan::{CameraId, CameraRun, DenoiserId};

pub(super) fn group(
    kind: GroupKind,
    g: &S<RawGroup>,
    scenes: &mut Vec<SceneRef>,
    replicates: u32,
    named: &Named,
    p: &mut Problems,
) -> Option<Group> {
    let k = kind_key(kind);
    let raw = g.get_ref();
    let name = p.ident(&raw.name, &format!("{k}.name"));
    let word = if kind == GroupKind::Table { "table" } else { "sweep" };
    p.group = Some(format!("{word} '{}'", raw.name.get_ref()));
    let at = |key: &str| format!("{k}.{key}");
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
    let group_scenes: Vec<usize> = match &raw.scenes {
        None => (0..scenes.len()).filter(|&i| scenes[i].integrand == Integrand::Ao).collect(),
        Some(list) => {
            p.non_empty(list, &at("scenes"));
            let mut out = Vec::new();
            for s in list.get_ref() {
                let id = normalize(s.get_ref());
                let named =
                    |o: &SceneRef| o.integrand == Integrand::Ao && (o.id == id || o.name == *s.get_ref());
                match scenes.iter().position(named) {
                    Some(i) if !out.contains(&i) => out.push(i),
                    Some(_) => {}
                    None => {
                        let valid: Vec<&str> = scenes
                            .iter()
                            .filter(|o| o.integrand == Integrand::Ao)
                            .map(|o| o.name.as_str())
                            .collect();
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
    // A file's point set holds so many points per pixel: more rays than that is refused.
    for r in rows.iter().flatten() {
        if let Some(max) = r.sequence.imp().max_count()
            && let Some(&big) = rays.iter().filter(|&&n| n > max).max()
        {
            p.add(
                raw.rays.span(),
                &at("rays"),
                format!(
                    "{big} rays, but sequence '{}' holds {max} points per pixel; allowed 1..={max}",
                    r.sequence
                ),
            );
        }
    }
    let frames = raw.frames.as_ref().map_or(Some(1), |f| p.int(f, &at("frames"), 1, MAX_FRAMES as i64));
    let schedules = match &raw.schedules {
        None => Some(vec![Schedule::Independent]),
        Some(v) => axis::<Schedule>(&Some(v.clone()), &at("schedules"), 0..0, p).map(dedup),
    };
    let pipelines = match &raw.pipelines {
        None => Some(vec![Pipeline::RAW]),
        Some(v) if !p.non_empty(v, &at("pipelines")) => None,
        Some(v) => {
            let parsed: Vec<Option<Pipeline>> = v
                .get_ref()
                .iter()
                .map(|s| {
                    s.get_ref().parse::<Pipeline>().map_err(|e| p.add(s.span(), &at("pipelines"), e)).ok()
                })
                .collect();
            parsed.into_iter().collect::<Option<Vec<_>>>().map(dedup)
        }
    };
    let integrands = match &raw.integrands {
        None => Some(vec![Integrand::Ao]),
        Some(v) => axis::<Integrand>(&Some(v.clone()), &at("integrands"), 0..0, p).map(dedup),
    };
    let group_scenes = with_integrands(group_scenes, integrands.as_deref().unwrap_or(&[]), scenes);
    let cameras = match (&raw.cameras, frames) {
        (None, _) => Some(vec![CameraId::STATIC]),
        (Some(v), _) if !p.non_empty(v, &at("cameras")) => None,
        (Some(v), f) => {
            let mut out = Vec::new();
            let mut ok = true;
            for s in v.get_ref() {
                let name = s.get_ref();
                if name == CameraId::STATIC_NAME {
                    out.push(CameraId::STATIC);
                    continue;
                }
                match named.cameras.iter().find(|(n, _)| n == name) {
                    Some((n, c)) => out.push(CameraId::intern(CameraRun {
                        name: n.clone(),
                        path: c.path.clone(),
                        jitter: c.jitter,
                        frames: f.unwrap_or(1),
                    })),
                    None => {
                        ok = false;
                        let mut valid = vec![CameraId::STATIC_NAME.to_string()];
                        valid.extend(named.cameras.iter().map(|(n, _)| n.clone()));
                        p.add(
                            s.span(),
                            &at("cameras"),
                            format!(
                                "unknown camera '{}'; valid: {} (define one as [cameras.NAME] with a `path`)",
                                name.escape_debug(),
                                valid.join(", ")
                            ),
                        );
                    }
                }
            }
            ok.then(|| dedup(out))
        }
    };
    let denoisers = match &raw.denoisers {
        None => Some(vec![DenoiserId::NONE]),
        Some(v) if !p.non_empty(v, &at("denoisers")) => None,
        Some(v) => {
            let mut out = Vec::new();
            let mut ok = true;
            for s in v.get_ref() {
                let name = s.get_ref();
                if name == "none" {
                    out.push(DenoiserId::NONE);
                    continue;
                }
                match named.denoisers.iter().find(|d| d.name == *name) {
                    Some(d) => out.push(DenoiserId::intern(d.clone())),
                    None => {
                        ok = false;
                        let mut valid = vec!["none".to_string()];
                        valid.extend(named.denoisers.iter().map(|d| d.name.clone()));
                        p.add(
                            s.span(),
                            &at("denoisers"),
                            format!(
                                "unknown denoiser '{}'; valid: {} (define one as [denoisers.NAME] with `program` and `args`)",
                                name.escape_debug(),
                                valid.join(", ")
                            ),
                        );
                    }
                }
            }
            ok.then(|| dedup(out))
        }
    };
    p.group = None;
    integrands?;
    Some(Group {
        kind,
        name: name?,
        rows: rows?,
        rays,
        replicates,
        scenes: group_scenes,
        line: line_of(p.text, g.span().start),
        frames: frames?,
        schedules: schedules?,
        pipelines: pipelines?,
        cameras: cameras?,
        denoisers: denoisers?,
    })
}

/// The scenes of a group measured under each of `integrands`: the scene itself for `ao`, else its
/// variant of that integrand (`SceneRef::integrand`), added to `scenes` the first time a group asks.
fn with_integrands(base: Vec<usize>, integrands: &[Integrand], scenes: &mut Vec<SceneRef>) -> Vec<usize> {
    let mut out = Vec::new();
    for si in base {
        for &i in integrands {
            let at = if i == Integrand::Ao {
                si
            } else {
                let of = |o: &SceneRef| o.id == scenes[si].id && o.integrand == i;
                match scenes.iter().position(of) {
                    Some(v) => v,
                    None => {
                        let name = format!("{}-{i}", scenes[si].name);
                        scenes.push(SceneRef { name, integrand: i, ..scenes[si].clone() });
                        scenes.len() - 1
                    }
                }
            };
            if !out.contains(&at) {
                out.push(at);
            }
        }
    }
    out
}

/// Later duplicates dropped, file order kept.
fn dedup<T: PartialEq>(v: Vec<T>) -> Vec<T> {
    let mut out: Vec<T> = Vec::new();
    for x in v {
        if !out.contains(&x) {
            out.push(x);
        }
    }
    out
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
            None
        }
        (None, false) => {
            const HOW: &str = "missing; give `rows = [{ distribution = .., sequence = .., seed_mode = .. }]` \
                               or the axes `distributions` and `sequences` (and optionally `seed_modes`)";
            p.add(span, &format!("{at}rows"), HOW);
            None
        }
        (Some(rows), false) => {
            if !p.non_empty(rows, &format!("{at}rows")) {
                return None;
            }
            let mut ok = true;
            for row in rows.get_ref() {
                let r = row.get_ref();
                let d = p.name::<Distribution>(&r.distribution, &format!("{at}rows.distribution"));
                let s = p.sequence(&r.sequence, &format!("{at}rows.sequence"));
                let m = match &r.seed_mode {
                    Some(m) => p.seed_mode(m, &format!("{at}rows.seed_mode")),
                    None => Some(SeedMode::Rotation),
                };
                match (d, s, m) {
                    (Some(d), Some(s), Some(m)) => match Row::new(d, s, m).invalid() {
                        Some(e) => {
                            p.add(row.span(), &format!("{at}rows"), e);
                            ok = false;
                        }
                        None => push(Row::new(d, s, m)),
                    },
                    _ => ok = false,
                }
            }
            ok.then_some(out)
        }
        (None, true) => {
            let ds = axis::<Distribution>(&raw.distributions, &format!("{at}distributions"), span.clone(), p);
            let ss = entries(&raw.sequences, &format!("{at}sequences"), span.clone(), p, |p, v, k| {
                p.sequence(v, k)
            });
            let ms = match &raw.seed_modes {
                None => Some(vec![SeedMode::Rotation]),
                Some(v) => entries(&Some(v.clone()), &format!("{at}seed_modes"), 0..0, p, |p, v, k| {
                    p.seed_mode(v, k)
                }),
            };
            let (ds, ss, ms) = (ds?, ss?, ms?);
            let mut ok = true;
            for &d in &ds {
                for &s in &ss {
                    for &m in &ms {
                        match Row::new(d, s, m).invalid() {
                            // Said once per seed mode and distribution, at the seed modes.
                            Some(e) if s == ss[0] => {
                                let at_modes = raw.seed_modes.as_ref().map_or(span.clone(), |v| v.span());
                                p.add(
                                    at_modes,
                                    &format!("{at}seed_modes"),
                                    format!("{e} (give such rows in `rows`)"),
                                );
                                ok = false;
                            }
                            Some(_) => ok = false,
                            None => push(Row::new(d, s, m)),
                        }
                    }
                }
            }
            ok.then_some(out)
        }
    }
}

/// An axis whose entries are names or file tables (`seed_modes`, `sequences`), read by `one`.
fn entries<'t, T>(
    v: &Option<S<Vec<S<toml::Value>>>>,
    key: &str,
    span: std::ops::Range<usize>,
    p: &mut Problems<'t>,
    one: impl Fn(&mut Problems<'t>, &S<toml::Value>, &str) -> Option<T>,
) -> Option<Vec<T>> {
    let Some(v) = v else {
        p.add(span, key, "missing; with the axes form give both `distributions` and `sequences`");
        return None;
    };
    if !p.non_empty(v, key) {
        return None;
    }
    let parsed: Vec<Option<T>> = v.get_ref().iter().map(|s| one(p, s, key)).collect();
    parsed.into_iter().collect()
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
