"""`points`, and bad arguments: each raises `hemilab.Error` with the command line's message."""

import numpy as np
import pytest

import hemilab


def test_points_are_unit_square_points_and_hemisphere_directions():
    pts, dirs = hemilab.points("sine-cosine", "fibonacci", n=64)
    assert pts.shape == (64, 2) and dirs.shape == (64, 3)
    assert pts.dtype == np.float32 and dirs.dtype == np.float32
    assert np.all((pts >= 0) & (pts < 1))
    assert np.allclose(np.linalg.norm(dirs, axis=1), 1.0, atol=1e-6)
    assert np.all(dirs[:, 2] >= 0)
    # The lattice's y = (i + 1/2) / n, shifted mod 1 by the static seed's offset (exact in fixed point).
    frac = pts[:, 1] * 64 % 1.0
    assert np.ptp(frac) == 0.0


def test_points_per_pixel_follow_the_seed_mode():
    a, _ = hemilab.points("sine-cosine", "fibonacci", "rotation", n=16, pixel=(3, 0))
    b, _ = hemilab.points("sine-cosine", "fibonacci", "rotation", n=16, pixel=(4, 0))
    s, _ = hemilab.points("sine-cosine", "fibonacci", "static", n=16, pixel=(4, 0))
    s0, _ = hemilab.points("sine-cosine", "fibonacci", "static", n=16, pixel=(0, 0))
    assert not np.array_equal(a, b)
    assert np.array_equal(s, s0)
    with pytest.raises(hemilab.Error, match="needs width="):
        hemilab.points("sine", "random", n=4, pixel=(1, 2))
    c, _ = hemilab.points("sine", "random", "rotation", n=4, pixel=(1, 2), width=10)
    d, _ = hemilab.points("sine", "random", "rotation", n=4, pixel=(21, 0))
    assert np.array_equal(c, d), "pixel (1, 2) of a 10-wide image is pixel 21"


def _cli_error(cli, *args):
    p = cli(*args)
    assert p.returncode == 2, p.stderr
    first = p.stderr.strip().splitlines()[0]
    assert first.startswith("error: ")
    return first[len("error: "):]


@pytest.mark.parametrize(
    "flags,kwargs",
    [
        (["--rays", "0"], dict(rays=0)),
        (["--rays", "4", "--distribution", "cosine"], dict(rays=4, distribution="cosine")),
        (["--rays", "4", "--sequence", "fibonaci"], dict(rays=4, sequence="fibonaci")),
        (["--rays", "4", "--seed-mode", "per-pixel"], dict(rays=4, seed_mode="per-pixel")),
        (["--rays", "4", "--resolution", "0x10"], dict(rays=4, resolution=(0, 10))),
        (["--rays", "4", "--seed-mode", "texture:missing.png"], dict(rays=4, seed_mode="texture:missing.png")),
    ],
)
def test_bad_render_arguments_raise_the_command_lines_message(tmp_path, root, cli, cornell, flags, kwargs):
    scene = root / "scenes" / "cornell-box.toml"
    expected = _cli_error(cli, "render", scene, "--output", tmp_path / "x.exr", *flags)
    with pytest.raises(hemilab.Error) as e:
        cornell.render(**kwargs)
    message = str(e.value)
    # An unknown sequence's message lists the names: here with the samplers registered from Python.
    assert message == expected or (flags[2] == "--sequence" and message.startswith(expected + ", ")), message
    assert not list(tmp_path.iterdir()), "nothing written"


def test_a_missing_scene_raises_the_command_lines_message(tmp_path, cli):
    missing = tmp_path / "nowhere.toml"
    expected = _cli_error(cli, "render", missing, "--rays", "4", "--output", tmp_path / "x.exr")
    with pytest.raises(hemilab.Error) as e:
        hemilab.Scene.load(missing)
    assert str(e.value) == expected


def test_bad_points_arguments(cli, tmp_path):
    expected = _cli_error(cli, "points", "--distribution", "sine", "--sequence", "random", "--count", "0",
                          "--output", tmp_path / "p.png")
    with pytest.raises(hemilab.Error) as e:
        hemilab.points("sine", "random", n=0)
    assert str(e.value) == expected


def test_metrics_of_mismatched_sizes_is_an_error():
    a = np.zeros((4, 5), np.float32)
    with pytest.raises(hemilab.Error, match="mismatched images are never compared"):
        hemilab.metrics(a, np.zeros((4, 4), np.float32), np.ones((4, 5), np.float32))
    with pytest.raises(hemilab.Error, match="no pixel is covered"):
        hemilab.metrics(a, a, a)
