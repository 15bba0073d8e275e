fn main() {
    let p = std::path::Path::new("experiments/bad.toml");
    for t in [
        "scenes = [\"a.toml\"]\nraplicates = 2\n[[table]]\nname=\"x\"\nrays=[1]\nrows=[{distribution=\"sine\",sequence=\"random\"}]\n",
        "scenes = [\"a.toml\"]\n[[table]]\nname=\"x\"\nrays=[1, \"2\"]\nrows=[{distribution=\"sine\",sequence=\"random\"}]\n",
        "scenes = [\"a.toml\"]\n[[table]]\nname=\"x\"\nrays=[1]\nrows=[{distribution=\"sine\"}]\n",
        "scenes = [\"a.toml\"]\nreplicates=0\n[[table]]\nname=\"x\"\nrays=[0]\nrows=[{distribution=\"cos\",sequence=\"random\"}]\n",
        "scenes = [\"a.toml\"]\n[[table]]\nname=\"x\"\nrays=[1]\n",
        "scenes = [\"a.toml\"]\nseed = \"1\n",
    ] {
        println!("{}\n-----", hemilab::spec::parse_spec(t, p).unwrap_err());
    }
    for f in ["experiments/smoke.toml", "experiments/paper.toml"] {
        let s =
            hemilab::spec::parse_spec(&std::fs::read_to_string(f).unwrap(), std::path::Path::new(f)).unwrap();
        let plan = hemilab::plan::plan(&s);
        let est = hemilab::plan::estimate(&plan, |_| [160, 120], 10e6);
        let txt = hemilab::plan::format_plan(std::path::Path::new(f), &plan, &est, 10e6);
        let lines: Vec<&str> = txt.lines().collect();
        println!("{}\n...\n{}", lines[..6].join("\n"), lines[lines.len() - 3..].join("\n"));
        println!("{:?}", s.scenes);
    }
}
