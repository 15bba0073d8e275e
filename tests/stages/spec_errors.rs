//! Bad specs: each must fail with one message naming the file, the line and the key, and saying what
//! is allowed. Never a panic, never a partial spec.

use hemilab::spec::parse_spec;
use std::path::Path;

const FILE: &str = "experiments/bad.toml";

/// A valid spec whose `@TOP@` / `@TABLE@` / `@ROW@` markers are replaced to make it bad.
const BASE: &str = r#"name = "t"
scenes = ["../scenes/cornell-box.toml"]
@TOP@
[[table]]
name = "t2"
rays = [8, 16]
@TABLE@
rows = [
  { distribution = "sine", sequence = "random" @ROW@},
]
"#;

fn spec(top: &str, table: &str, row: &str) -> String {
    BASE.replace("@TOP@", top).replace("@TABLE@", table).replace("@ROW@", row)
}

fn error(text: &str) -> String {
    let e = parse_spec(text, Path::new(FILE)).expect_err("this spec must be refused");
    let e = e.to_string();
    assert!(e.starts_with(FILE), "message must name the file: {e}");
    e
}

fn assert_has(msg: &str, parts: &[&str]) {
    for p in parts {
        assert!(msg.contains(p), "expected {p:?} in:\n{msg}");
    }
}

#[test]
fn base_spec_is_valid() {
    let s = parse_spec(&spec("", "", ""), Path::new(FILE)).unwrap();
    assert_eq!(s.groups.len(), 1);
}

#[test]
fn unknown_top_level_key() {
    let e = error(&spec("raplicates = 2", "", ""));
    assert_has(&e, &["line 3", "raplicates", "replicates"]);
}

#[test]
fn unknown_key_in_a_row() {
    let e = error(&spec("", "", ", seedmode = \"static\" "));
    assert_has(&e, &["line 9", "seedmode", "seed_mode"]);
}

#[test]
fn wrong_type_of_ray_count() {
    let e = error(&spec("", "", "").replace("rays = [8, 16]", "rays = [8, \"16\"]"));
    assert_has(&e, &["line 6", "key `table.rays`"]);
}

#[test]
fn wrong_type_of_replicates() {
    let e = error(&spec("replicates = \"four\"", "", ""));
    assert_has(&e, &["line 3", "key `replicates`"]);
}

#[test]
fn ray_count_zero() {
    let e = error(&spec("", "", "").replace("rays = [8, 16]", "rays = [8, 0]"));
    assert_has(&e, &["line 6", "table.rays", "0 is out of range", "1..=65536"]);
}

#[test]
fn ray_count_too_large() {
    let e = error(&spec("", "", "").replace("rays = [8, 16]", "rays = [100000]"));
    assert_has(&e, &["line 6", "table.rays", "1..=65536"]);
}

#[test]
fn empty_ray_list() {
    let e = error(&spec("", "", "").replace("rays = [8, 16]", "rays = []"));
    assert_has(&e, &["line 6", "table.rays", "empty"]);
}

#[test]
fn empty_axis() {
    let text = spec("", "distributions = []\nsequences = [\"random\"]", "")
        .replace("rows = [\n  { distribution = \"sine\", sequence = \"random\" },\n]\n", "");
    let e = error(&text);
    assert_has(&e, &["line 7", "table.distributions", "empty"]);
}

#[test]
fn unknown_distribution_lists_choices() {
    let e = error(&spec("", "", "").replace("\"sine\"", "\"cosine\""));
    assert_has(&e, &["line 9", "table.rows.distribution", "'cosine'", "uniform, sine, sine-cosine"]);
}

#[test]
fn unknown_sequence_lists_choices() {
    let e = error(&spec("", "", "").replace("\"random\"", "\"halton2\""));
    assert_has(&e, &["line 9", "rows.sequence", "'halton2'", "fibonacci"]);
}

#[test]
fn unknown_seed_mode_lists_choices() {
    let e = error(&spec("", "", ", seed_mode = \"per-pixel\" "));
    assert_has(&e, &["line 9", "rows.seed_mode", "'per-pixel'", "static, rotation, shift, blue-noise"]);
}

#[test]
fn unknown_name_in_an_axis_lists_choices() {
    let text = spec("", "distributions = [\"sine\"]\nsequences = [\"random\", \"sobel\"]", "")
        .replace("rows = [\n  { distribution = \"sine\", sequence = \"random\" },\n]\n", "");
    let e = error(&text);
    assert_has(&e, &["line 8", "table.sequences", "'sobel'", "sobol"]);
}

#[test]
fn replicates_zero() {
    let e = error(&spec("replicates = 0", "", ""));
    assert_has(&e, &["line 3", "key `replicates`", "1..=1000"]);
}

#[test]
fn table_replicates_zero() {
    let e = error(&spec("", "replicates = 0", ""));
    assert_has(&e, &["line 7", "table.replicates", "1..=1000"]);
}

#[test]
fn resolution_zero() {
    let e = error(&spec("resolution = [0, 120]", "", ""));
    assert_has(&e, &["line 3", "key `resolution`", "1..=16384"]);
}

/// The documented limit is the enforced one: sides up to 16384, at most 67108864 pixels in all.
#[test]
fn resolution_limit_is_the_documented_one() {
    let e = error(&spec("resolution = [16384, 16384]", "", ""));
    assert_has(&e, &["line 3", "key `resolution`", "16384x16384 is too large", "at most 67108864 pixels"]);
    let ok = |r: &str| parse_spec(&spec(r, "", ""), Path::new(FILE)).is_ok();
    assert!(ok("resolution = [8192, 8192]") && ok("resolution = [16384, 4096]"));
    assert!(!ok("resolution = [16385, 1]"));
}

#[test]
fn resolution_needs_two_sides() {
    let e = error(&spec("resolution = [160]", "", ""));
    assert_has(&e, &["line 3", "key `resolution`", "[width, height]"]);
}

#[test]
fn duplicate_table_name() {
    let mut text = spec("", "", "");
    text.push_str("[[convergence]]\nname = \"t2\"\nrays = [1, 2]\n");
    text.push_str("rows = [{ distribution = \"sine\", sequence = \"random\" }]\n");
    let e = error(&text);
    assert_has(&e, &["line 12", "convergence.name", "duplicate name 't2'"]);
}

#[test]
fn missing_rows() {
    let text =
        spec("", "", "").replace("rows = [\n  { distribution = \"sine\", sequence = \"random\" },\n]\n", "");
    let e = error(&text);
    assert_has(&e, &["line 4", "table.rows", "missing"]);
}

#[test]
fn rows_and_axes_together() {
    let e = error(&spec("", "distributions = [\"sine\"]\nsequences = [\"random\"]", ""));
    assert_has(&e, &["table.rows", "not both"]);
}

#[test]
fn empty_rows() {
    let text = spec("", "", "")
        .replace("rows = [\n  { distribution = \"sine\", sequence = \"random\" },\n]", "rows = []");
    let e = error(&text);
    assert_has(&e, &["line 8", "table.rows", "empty"]);
}

#[test]
fn missing_row_field() {
    let e = error(&spec("", "", "").replace(", sequence = \"random\"", ""));
    assert_has(&e, &["line 9", "sequence"]);
}

#[test]
fn bad_flip_ppd() {
    for bad in ["flip_ppd = 0", "flip_ppd = -67.0", "flip_ppd = 1001", "flip_ppd = \"67\"", "flip_ppd = nan"]
    {
        let e = error(&spec(bad, "", ""));
        assert_has(&e, &["line 3", "key `flip_ppd`", "(0, 1000]"]);
    }
}

#[test]
fn bad_ao_distance() {
    let e = error(&spec("ao_distance = -1.0", "", ""));
    assert_has(&e, &["line 3", "key `ao_distance`", "\"infinite\""]);
    let e = error(&spec("ao_distance = \"far\"", "", ""));
    assert_has(&e, &["line 3", "key `ao_distance`"]);
    // Distances the f32 renderer would turn into 0 or infinity.
    let e = error(&spec("ao_distance = 1e-300", "", ""));
    assert_has(&e, &["line 3", "key `ao_distance`", "\"infinite\""]);
    let e = error(&spec("ao_distance = 1e300", "", ""));
    assert_has(&e, &["line 3", "key `ao_distance`"]);
}

#[test]
fn bad_reference_settings() {
    let e = error(&spec(
        "[reference]\nrays = 0\nreplicates = 1\ndistribution = \"cos\"\nallocation = \"smart\"",
        "",
        "",
    ));
    assert_has(&e, &["line 4, key `reference.rays`", "\"auto\""]);
    assert_has(&e, &["line 5, key `reference.replicates`", "2..=1000"]);
    assert_has(&e, &["line 6, key `reference.distribution`", "sine-cosine"]);
    assert_has(&e, &["line 7, key `reference.allocation`", "\"even\" or \"adaptive\""]);
}

#[test]
fn unknown_reference_key() {
    let e = error(&spec("[reference]\nray = 4096", "", ""));
    assert_has(&e, &["line 4", "ray", "reference"]);
}

#[test]
fn no_scenes() {
    let e = error(&spec("", "", "").replace("[\"../scenes/cornell-box.toml\"]", "[]"));
    assert_has(&e, &["line 2", "key `scenes`", "empty"]);
}

#[test]
fn unknown_scene_in_a_table() {
    let e = error(&spec("", "scenes = [\"kitchen\"]", ""));
    assert_has(&e, &["line 7", "table.scenes", "unknown scene 'kitchen'", "valid: cornell-box"]);
}

#[test]
fn no_tables_at_all() {
    let e = error("scenes = [\"a.toml\"]\n");
    assert_has(&e, &["table", "convergence"]);
}

#[test]
fn bad_table_name() {
    let e = error(&spec("", "", "").replace("name = \"t2\"", "name = \"table 2/x\""));
    assert_has(&e, &["line 5", "table.name", "letters, digits"]);
}

#[test]
fn toml_syntax_error_has_line() {
    let e = error(&spec("seed = \"1", "", ""));
    assert_has(&e, &["line 3"]);
}

#[test]
fn all_problems_are_reported_at_once() {
    let text = spec("replicates = 0", "", "")
        .replace("rays = [8, 16]", "rays = [0, 16]")
        .replace("\"sine\"", "\"cos\"");
    let e = error(&text);
    assert_has(
        &e,
        &["line 3, key `replicates`", "line 6, key `table.rays`", "line 9, key `table.rows.distribution`"],
    );
}

/// Regression: tables named so that their figure files clash (`banding`, `a` and `a_error`, a point
/// figure's name) used to overwrite each other's PNGs silently.
#[test]
fn figure_file_names_must_not_clash() {
    let t = |name: &str| {
        format!(
            "[[table]]\nname = \"{name}\"\nrays = [4]\nrows = [{{ distribution = \"sine\", sequence = \"random\" }}]\n"
        )
    };
    let head = "scenes = [\"../scenes/cornell-box.toml\"]\n";
    let e = error(&format!("{head}{}", t("banding")));
    assert_has(&e, &["line 3", "key `table.name`", "banding.png", "banding figure"]);
    let e = error(&format!("{head}{}{}", t("a"), t("a_error")));
    assert_has(&e, &["line 7", "a_error.png", "table 'a'"]);
    let e = error(&format!("{head}point_figures = true\n{}", t("table1")));
    assert_has(&e, &["table1.png", "point figure"]);
    let ok = format!("{head}{}", t("table1"));
    assert!(parse_spec(&ok, Path::new(FILE)).is_ok(), "table1 is free without point figures");
}

#[test]
fn timing_section_defaults_and_ranges() {
    let s = parse_spec(&spec("seed = 9", "", ""), Path::new(FILE)).unwrap();
    assert_eq!((s.timing.repeats, s.timing.seed), (3, 9), "defaults: 3 repeats, the base seed");
    let s = parse_spec(&spec("[timing]\nrepeats = 7\nseed = 2\n", "", ""), Path::new(FILE)).unwrap();
    assert_eq!((s.timing.repeats, s.timing.seed), (7, 2));
    let e = error(&spec("[timing]\nrepeats = 0\n", "", ""));
    assert_has(&e, &["line 4", "key `timing.repeats`", "1..=100"]);
    let e = error(&spec("[timing]\nrepeat = 5\n", "", ""));
    assert_has(&e, &["line 4", "repeat", "repeats"]);
}

/// `[convergence]` (one table) where `[[convergence]]` (an array of tables) belongs: the message
/// says so at the header's line, instead of serde's "invalid type: map" at the key before it.
#[test]
fn single_bracket_group_says_double_brackets() {
    for kind in ["convergence", "table"] {
        let text = spec("", "", "").replace("[[table]]", &format!("[reference]\nrays = 64\n\n[{kind}]"));
        let e = error(&text);
        assert_eq!(e.lines().count(), 1, "{e}");
        assert_has(&e, &["line 7", &format!("key `{kind}`"), &format!("`[[{kind}]]` with double brackets")]);
        assert!(!e.contains("reference") && !e.contains("sequence"), "{e}");
    }
}

/// Key paths are TOML's: a group named like its kind is not repeated in the path; the name follows.
#[test]
fn key_paths_do_not_repeat_the_group_name() {
    let text =
        spec("", "", "").replace("[[table]]\nname = \"t2\"", "[[convergence]]\nname = \"convergence\"");
    let e = error(&text.replace("\"random\"", "\"fibonaci\""));
    assert_has(
        &e,
        &["line 9, key `convergence.rows.sequence` (sweep 'convergence'): unknown sequence 'fibonaci'"],
    );
    assert!(!e.contains("convergence.convergence"), "{e}");
}

/// A missing required key: no line 1 (toml points there, whatever it holds), the key and the fix.
#[test]
fn missing_keys_name_the_key_and_the_fix() {
    let e = error(&format!(
        "# my spec\n{}",
        spec("", "", "").replace("scenes = [\"../scenes/cornell-box.toml\"]\n", "")
    ));
    assert_eq!(
        e,
        format!(
            "{FILE}: key `scenes`: missing; add `scenes = [\"../scenes/kitchen.toml\"]`, paths relative to the spec file"
        )
    );
    let e = error(&spec("", "", "").replace("name = \"t2\"\n", ""));
    assert_has(&e, &["line 4, key `table.name`: missing; give it a `name"]);
    let e = error(&spec("", "", "").replace("distribution = \"sine\", ", ""));
    assert_has(&e, &["key `table.rows.distribution`: missing", "\"sine-cosine\""]);
}

/// `ao_distance` takes "inf" as well as "infinite", as the scene files and `bench --distances` do.
#[test]
fn ao_distance_inf_is_infinite() {
    let s = parse_spec(&spec("ao_distance = \"inf\"", "", ""), Path::new(FILE)).unwrap();
    assert_eq!(s.ao_distance, Some(hemilab::spec::AoDistance::Infinite));
}

/// A scene file given where a spec belongs: said so, at the camera's header.
#[test]
fn a_scene_file_is_not_a_spec() {
    let scene =
        "mesh = \"m.obj\"\nresolution = [8, 8]\nao_distance = 1.0\n\n[camera.perspective]\neye = [0, 0, 5]\n";
    let e = error(scene);
    assert_has(&e, &["line 5, key `camera.perspective`", "this is a scene file, not a spec"]);
}

/// The report's words for a value name the value to write.
#[test]
fn the_reports_words_point_at_the_value() {
    let e = error(&spec("", "", ", seed_mode = \"per-pixel seed\" "));
    assert_has(&e, &["key `table.rows.seed_mode`", "('per-pixel seed' is written `rotation`)"]);
}

#[test]
fn realtime_keys_bad_values_name_line_key_and_choices() {
    let e = error(&spec("", "frames = 0", ""));
    assert_has(&e, &["line 7", "table.frames", "0 is out of range", "1..=1024"]);
    let e = error(&spec("", "pipelines = [\"raw\", \"blur\"]", ""));
    assert_has(&e, &["line 7", "table.pipelines", "'blur'", "ema0.1+atrous"]);
    let e = error(&spec("", "pipelines = []", ""));
    assert_has(&e, &["line 7", "table.pipelines", "is empty"]);
    let e = error(&spec("", "schedules = [\"r2d2\"]", ""));
    assert_has(&e, &["line 7", "table.schedules", "r2d2", "independent", "r1"]);
    let ok = parse_spec(
        &spec("", "frames = 8\npipelines = [\"raw\", \"ema0.1+atrous\", \"raw\"]", ""),
        Path::new(FILE),
    )
    .unwrap();
    assert_eq!(ok.groups[0].frames, 8);
    assert_eq!(ok.groups[0].pipelines.len(), 2, "duplicates merged");
    let plain = parse_spec(&spec("", "", ""), Path::new(FILE)).unwrap();
    assert_eq!(plain.groups[0].frames, 1);
    assert_eq!(plain.groups[0].pipelines, vec![hemilab::denoise::Pipeline::RAW]);
}
