use super::*;

fn cmd(args: &[&str]) -> DenoiseCommand {
    DenoiseCommand {
        program: "x".into(),
        args: args.iter().map(|a| a.to_string()).collect(),
        timeout_s: 60.0,
    }
}

#[test]
fn a_command_must_name_both_files_and_only_known_placeholders() {
    assert!(cmd(&["{input}", "-o", "{output}"]).validate().is_ok());
    assert!(cmd(&["--in={input}", "--out={output}", "{\"json\": 1}"]).validate().is_ok());
    assert!(cmd(&["{input}"]).validate().unwrap_err().contains("args must contain {output}"));
    let e = cmd(&["{input}", "{output}", "{frame}"]).validate().unwrap_err();
    assert!(e.contains("args[2] holds the placeholder {frame}"), "{e}");
    let e = DenoiseCommand { timeout_s: 0.0, ..cmd(&["{input}", "{output}"]) }.validate().unwrap_err();
    assert!(e.contains("timeout_s"), "{e}");
    let e = DenoiseCommand { program: " ".into(), ..cmd(&["{input}", "{output}"]) }.validate().unwrap_err();
    assert!(e.contains("program"), "{e}");
}

#[test]
fn messages_quote_arguments_as_a_shell_would_need() {
    assert_eq!(quoted("/tmp/a-b.exr"), "/tmp/a-b.exr");
    assert_eq!(quoted("echo hi"), "'echo hi'");
    assert_eq!(quoted("it's"), "'it'\\''s'");
    assert_eq!(quoted(""), "''");
}

#[test]
fn resolve_takes_relative_paths_from_the_spec_dir_and_leaves_names_to_path() {
    let c = |p: &str| DenoiseCommand { program: p.into(), ..cmd(&[]) }.resolve(Path::new("/specs"));
    assert_eq!(c("tools/denoise").program, "/specs/tools/denoise");
    assert_eq!(c("python3").program, "python3");
    assert_eq!(c("/usr/bin/env").program, "/usr/bin/env");
}

#[test]
fn resolve_takes_an_argument_naming_a_file_beside_the_spec_from_there() {
    // A script beside the spec is found from any working directory; options, placeholders and
    // names of nothing there are passed as written.
    let dir = std::env::temp_dir().join(format!("hemilab-denoise-args-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("tools")).unwrap();
    std::fs::write(dir.join("tools/denoise.py"), "").unwrap();
    std::fs::write(dir.join("weights.tza"), "").unwrap();
    let args = ["tools/denoise.py", "--quality", "fast", "weights.tza", "{input}", "{output}", "missing.py"];
    let c = DenoiseCommand { program: "python3".into(), ..cmd(&args) }.resolve(&dir);
    let at = |p: &str| dir.join(p).to_string_lossy().into_owned();
    assert_eq!(
        c.args,
        [
            at("tools/denoise.py"),
            "--quality".into(),
            "fast".into(),
            at("weights.tza"),
            "{input}".into(),
            "{output}".into(),
            "missing.py".into()
        ]
    );
    assert_eq!(c.program, "python3");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_output_value_is_y_or_the_mean_of_rgb_checked() {
    let img = |v: f32| Image::from_vec(2, 1, vec![v, v]);
    let named = |list: &[(&str, f32)]| list.iter().map(|&(n, v)| (n.to_string(), img(v))).collect::<Vec<_>>();
    assert_eq!(value_of(&named(&[("Y", 0.5), ("R", 0.1)]), 2, 1).unwrap(), img(0.5));
    assert!(
        (value_of(&named(&[("R", 0.3), ("G", 0.6), ("B", 0.9)]), 2, 1).unwrap().data[0] - 0.6).abs() < 1e-6
    );
    assert!(value_of(&named(&[("R", 0.3), ("G", 0.6)]), 2, 1).unwrap_err().contains("channels [R, G]"));
    assert!(value_of(&named(&[("Y", 0.5)]), 3, 1).unwrap_err().contains("2x1, the frame 3x1"));
    assert!(value_of(&named(&[("Y", f32::NAN)]), 2, 1).unwrap_err().contains("not finite at pixel (0, 0)"));
}
