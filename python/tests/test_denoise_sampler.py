"""`denoise` through the run's filters, and a Python sampler end to end (render and run)."""

import json
import pathlib

import numpy as np
import pytest

import hemilab


def test_raw_is_the_frames_and_mean_is_their_running_mean(cornell):
    g = cornell.gbuffer(resolution=(32, 24))
    frames = [cornell.render(rays=1, resolution=(32, 24), seed=s)[0] for s in (1, 2, 3)]
    raw = hemilab.denoise(frames, "raw", gbuffer=g)
    assert raw.shape == (3, 24, 32) and np.array_equal(raw, np.stack(frames))
    mean = hemilab.denoise(frames, "mean", gbuffer=g)
    covered = g.coverage > 0
    expected = np.cumsum(np.stack(frames).astype(np.float64), axis=0) / np.arange(1, 4)[:, None, None]
    assert np.allclose(mean[:, covered], expected[:, covered], atol=1e-6)


def test_svgf_cuts_the_error_of_one_ray_frames(cornell):
    mean, coverage, _, _ = cornell.reference(resolution=(32, 32))
    g = cornell.gbuffer(resolution=(32, 32))
    frames = [cornell.render(rays=1, resolution=(32, 32), seed=s, sequence="random")[0] for s in range(1, 5)]
    out = hemilab.denoise(np.stack(frames), "svgf", gbuffer=g)
    before = hemilab.metrics(frames[-1], mean, coverage)["rmse"]
    after = hemilab.metrics(out[-1], mean, coverage)["rmse"]
    assert after < 0.7 * before, (before, after)


def test_bad_pipeline_and_sizes_are_errors(cornell):
    g = cornell.gbuffer(resolution=(16, 16))
    f = np.zeros((16, 16), np.float32)
    with pytest.raises(hemilab.Error, match="svgf"):
        hemilab.denoise([f], "median", gbuffer=g)
    with pytest.raises(hemilab.Error, match="the G-buffer is 16x16"):
        hemilab.denoise([np.zeros((8, 8), np.float32)], "raw", gbuffer=g)


def replay(width, seed, mode):
    """A sampler that hands back `hemilab.points`' Fibonacci points for each pixel."""

    def fill(s):
        pts, _ = hemilab.points("sine-cosine", "fibonacci", mode, n=s.count, pixel=(s.x, s.y), width=width, seed=seed)
        return pts[: s.n]

    return fill


def test_a_python_sampler_renders_what_its_points_say(cornell):
    sampler = hemilab.register_sampler("py-replay", replay(40, 3, "rotation"))
    assert "py-replay" in hemilab.sequences()
    ours, _ = cornell.render(rays=8, resolution=(40, 30), sequence="py-replay", seed=3)
    lattice, _ = cornell.render(rays=8, resolution=(40, 30), sequence="fibonacci", seed=3)
    assert np.array_equal(ours, lattice), "points() and a sampler replaying them give the lattice's image"
    assert sampler.calls > 0 and sampler.seconds > 0
    sampler.reset()
    assert sampler.calls == 0


def hammersley(s):
    """The Hammersley set shifted mod 1 by the set's key and the seed mode's offsets (the Rust
    extension example's sampler, in Python)."""
    i = np.arange(s.n)
    x = (2 * i + 1) / (2 * s.count)
    y = np.array([int(format(k, "032b")[::-1], 2) / 2**32 for k in i])
    rng = np.random.default_rng(s.key)
    kx, ky = rng.random(2)
    return np.stack([(x + kx + s.offset[0]) % 1.0, (y + ky + s.offset[1]) % 1.0], axis=1)


def test_a_python_sampler_runs_through_hemilab_run(tmp_path, root):
    sampler = hemilab.register_sampler("py-hammersley", hammersley, label="Hammersley (Python)")
    spec = tmp_path / "s.toml"
    spec.write_text(
        f"""name = "py"
scenes = ["{(root / 'scenes' / 'cornell-box.toml').as_posix()}"]
resolution = [24, 18]
replicates = 2
seed = 1

[reference]
dir = "ref"
rays = 256
replicates = 2

[[table]]
name = "t"
rays = [4, 16]
rows = [
  {{ distribution = "sine-cosine", sequence = "py-hammersley", seed_mode = "shift" }},
  {{ distribution = "sine-cosine", sequence = "random" }},
]
"""
    )
    out = pathlib.Path(hemilab.run(spec, out=tmp_path / "out"))
    records = json.loads((out / "results.json").read_text())
    ours = [r for r in records if r["sequence"] == "py-hammersley"]
    assert len(ours) == 4
    for r in ours:
        assert 0 < r["rmse"] < 0.5
        twin = next(t for t in records if t["sequence"] == "random" and t["rays"] == r["rays"] and t["replicate"] == r["replicate"])
        assert r["rmse"] < twin["rmse"], "a stratified set beats pseudo-random numbers"
    assert sampler.calls > 0 and sampler.seconds > 0


def test_a_failing_sampler_raises_its_error(cornell):
    def broken(s):
        raise ValueError("no points today")

    hemilab.register_sampler("py-broken", broken)
    with pytest.raises(hemilab.Error, match="sampler 'py-broken' at pixel .*no points today"):
        cornell.render(rays=4, resolution=(16, 16), sequence="py-broken")
    hemilab.register_sampler("py-broken", lambda s: np.full((s.n, 2), 1.5))
    with pytest.raises(hemilab.Error, match=r"outside \[0, 1\)"):
        cornell.render(rays=4, resolution=(16, 16), sequence="py-broken")
    hemilab.register_sampler("py-broken", lambda s: np.zeros((s.n, 3)))
    with pytest.raises(hemilab.Error, match=r"\(n, 2\)"):
        cornell.render(rays=4, resolution=(16, 16), sequence="py-broken")
    with pytest.raises(hemilab.Error, match="lower-case"):
        hemilab.register_sampler("Bad Name", broken)
    with pytest.raises(hemilab.Error, match="exists already"):
        hemilab.register_sampler("sobol", broken)
