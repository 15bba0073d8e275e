"""`Scene.render` against `hemilab render`: the same arguments give the same float32 image, bit
for bit (the EXR's Y and A channels, read by the module's own reader)."""

import numpy as np
import pytest

import hemilab

CASES = [
    # (flags, keyword arguments): the command's defaults, then other estimators, sizes and frames.
    ([], {}),
    (["--distribution", "uniform", "--sequence", "random", "--seed-mode", "static", "--seed", "7"],
     dict(distribution="uniform", sequence="random", seed_mode="static", seed=7)),
    (["--distribution", "sine", "--sequence", "sobol", "--seed-mode", "shift", "--frame", "3", "--schedule", "r1"],
     dict(distribution="sine", sequence="sobol", seed_mode="shift", frame=3, schedule="r1")),
    (["--sequence", "halton", "--seed-mode", "blue-noise", "--integrand", "visibility"],
     dict(sequence="halton", seed_mode="blue-noise", integrand="visibility")),
]


@pytest.mark.parametrize("flags,kwargs", CASES)
def test_render_is_the_command_line_render_bit_for_bit(tmp_path, root, cli, cornell, flags, kwargs):
    scene = root / "scenes" / "cornell-box.toml"
    exr = tmp_path / "x.exr"
    p = cli("render", scene, "--rays", 8, "--resolution", "48x36", "--output", exr, "--quiet", *flags)
    assert p.returncode == 0, p.stderr
    written = hemilab.read_exr(exr)
    ao, coverage = cornell.render(rays=8, resolution=(48, 36), **kwargs)
    assert ao.dtype == np.float32 and ao.shape == (36, 48)
    assert np.array_equal(ao, written["Y"]), "AO differs from the command line's"
    assert np.array_equal(coverage, written["A"]), "coverage differs from the command line's"
    assert np.count_nonzero(coverage) > 0


def test_render_defaults_to_the_scene_size_and_any_thread_count_gives_the_same_image(cornell):
    ao, _ = cornell.render(rays=4)
    w, h = cornell.resolution
    assert ao.shape == (h, w)
    one, _ = cornell.render(rays=4, threads=1)
    assert np.array_equal(ao, one)


def test_gbuffer_coverage_is_the_renders(cornell):
    _, coverage = cornell.render(rays=2, resolution=(40, 30))
    g = cornell.gbuffer(resolution=(40, 30))
    assert (g.width, g.height) == (40, 30)
    assert np.array_equal(g.coverage, coverage)
    assert g.normal.shape == (30, 40, 3) and g.depth.shape == (30, 40)
    covered = coverage > 0
    assert np.all(g.depth[covered] > 0) and np.all(g.depth[~covered] == 0)
    assert np.allclose(np.linalg.norm(g.normal[covered], axis=1), 1.0, atol=1e-5)


def test_reference_is_the_committed_file(root, cornell):
    mean, coverage, stderr, manifest = cornell.reference(resolution=(32, 32))
    assert manifest["resolution"] == [32, 32]
    stem = [p for p in (root / "reference").glob("cornell-box-32x32-*.json")]
    files = {p.with_suffix(".exr") for p in stem}
    assert files, "the committed 32x32 reference"
    # The one the store picked is one of the committed files, read bit for bit.
    assert any(np.array_equal(hemilab.read_exr(f)["Y"], mean) for f in files)
    assert mean.shape == coverage.shape == stderr.shape == (32, 32)


def test_no_stored_reference_is_an_error_naming_the_scene(cornell):
    with pytest.raises(hemilab.Error, match="no stored reference of 'cornell-box' at 33x31"):
        cornell.reference(resolution=(33, 31))
