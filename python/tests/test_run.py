"""`hemilab.run` and `load_results` against `hemilab run` on the smoke spec (the Cornell box at
32x32 against its committed reference), and `metrics` against the errors the run recorded."""

import json
import pathlib

import numpy as np
import pytest

import hemilab

MEASURED = ["rmse", "bias", "autocorr_x", "autocorr_y", "lowpass_rmse", "whiteness_z", "lowfreq_ratio", "flip"]


def _records(value):
    # A DataFrame when pandas is installed, else a list of dicts.
    return value.to_dict("records") if hasattr(value, "to_dict") else value


@pytest.fixture(scope="module")
def runs(tmp_path_factory, root, cli):
    tmp = tmp_path_factory.mktemp("run")
    spec = root / "experiments" / "smoke.toml"
    p = cli("run", spec, "--out", tmp / "cli", "--quiet", "--no-build-reference")
    assert p.returncode == 0, p.stderr
    out = hemilab.run(spec, out=tmp / "py", no_build_reference=True)
    return tmp / "cli", out


def test_run_writes_the_records_the_command_line_writes(runs):
    cli_out, py_out = runs
    ours = _records(hemilab.load_results(py_out))
    theirs = json.loads((cli_out / "results.json").read_text())
    assert len(ours) == len(theirs) == 16
    key = lambda r: r["key"]
    for a, b in zip(sorted(ours, key=key), sorted(theirs, key=key)):
        for col in ["scene", "distribution", "sequence", "seed_mode", "rays", "replicate", "seed", "image", *MEASURED]:
            assert a[col] == b[col], (col, a, b)
    assert (pathlib.Path(py_out) / "index.html").exists()


def test_metrics_are_the_runs_and_its_images_are_renders(runs, root):
    _, py_out = runs
    out = pathlib.Path(py_out)
    scene = hemilab.Scene.load(root / "scenes" / "cornell-box.toml")
    mean, coverage, _, _ = scene.reference(resolution=(32, 32))
    for r in _records(hemilab.load_results(out))[:6]:
        image = hemilab.read_exr(out / r["image"])
        m = hemilab.metrics(image["Y"], mean, coverage)
        for col in MEASURED:
            assert m[col] == r[col], (col, m[col], r[col])
        ao, _ = scene.render(
            rays=r["rays"], distribution=r["distribution"], sequence=r["sequence"],
            seed_mode=r["seed_mode"], seed=r["seed"], resolution=(32, 32),
        )
        assert np.array_equal(ao, image["Y"])


def test_load_results_of_the_committed_paper_run(root):
    records = _records(hemilab.load_results(root / "experiments" / "outputs" / "paper"))
    assert len(records) == 704
    assert {r["scene"] for r in records} == {"kitchen"}


def test_load_results_of_a_directory_without_results_is_an_error(tmp_path):
    with pytest.raises(hemilab.Error, match="no results.json here"):
        hemilab.load_results(tmp_path)


def test_run_of_a_bad_spec_raises_the_command_lines_message(tmp_path, cli):
    spec = tmp_path / "bad.toml"
    spec.write_text('name = "bad"\nscenes = ["nowhere.toml"]\nbogus_key = 1\n')
    p = cli("run", spec, "--out", tmp_path / "cli", "--quiet")
    assert p.returncode == 2
    with pytest.raises(hemilab.Error) as e:
        hemilab.run(spec, out=tmp_path / "py")
    assert p.stderr.startswith("error: ")
    assert str(e.value) == p.stderr.strip()[len("error: "):]
    assert not (tmp_path / "py").exists(), "nothing written"
