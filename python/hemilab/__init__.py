"""hemilab from Python: render, sample, filter and measure ambient occlusion into numpy.

The module is built from the same crate as the `hemilab` command (PyO3, maturin, abi3), and every
function calls the library function the command calls for the same work — no second
implementation. A render is therefore `hemilab render` bit for bit, settings are read by the
command line's own parser (defaults, ranges and names are the flags'), and a bad value raises
`hemilab.Error` with the command line's message.

>>> import hemilab
>>> scene = hemilab.Scene.load("scenes/cornell-box.toml")
>>> ao, coverage = scene.render(rays=16, resolution=(64, 48))      # float32 (48, 64) arrays
>>> mean, cov, stderr, manifest = scene.reference(resolution=(32, 32))  # the committed reference
>>> hemilab.metrics(scene.render(rays=16, resolution=(32, 32))[0], mean, cov)["rmse"]

Relative paths are relative to the current directory, as on the command line; a spec finds its
scenes and references relative to itself. The GIL is released while hemilab works (rendering,
filtering, measuring, running a spec), so other Python threads run meanwhile.

Build the API reference with `pdoc hemilab -o docs/python-api` (see docs/python.md).
"""

from __future__ import annotations

import json
import os
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import _hemilab
from ._hemilab import Error, GBuffer, PixelSet, Sampler, __version__

__all__ = [
    "Error",
    "GBuffer",
    "PixelSet",
    "Sampler",
    "Scene",
    "__version__",
    "denoise",
    "load_results",
    "metrics",
    "points",
    "read_exr",
    "register_sampler",
    "run",
    "sequences",
]

PathLike = Union[str, "os.PathLike[str]"]
Array = np.ndarray


def _image(a: Any, what: str) -> Array:
    """A 2-D float32 C-contiguous copy or view of `a`, as hemilab's images are held."""
    arr = np.ascontiguousarray(a, dtype=np.float32)
    if arr.ndim != 2:
        raise Error(f"{what}: an (H, W) image wanted, got an array of shape {arr.shape}")
    return arr


class Scene:
    """A scene file loaded once — mesh, camera, BVH — to render, trace a G-buffer of, or find the
    stored reference of, at any size. `Scene.load(path)` reads it as every command does (the
    scene TOML and its mesh; errors name the file, line and key)."""

    def __init__(self, native: "_hemilab.Scene") -> None:
        self._native = native

    @staticmethod
    def load(path: PathLike) -> "Scene":
        """Loads the scene file `path` (TOML beside its mesh; see scenes/README.md)."""
        return Scene(_hemilab.Scene.load(os.fspath(path)))

    @property
    def name(self) -> str:
        """The scene's name (its file's stem unless the TOML names it)."""
        return self._native.name

    @property
    def path(self) -> str:
        """The scene file, as given to `load`."""
        return os.fspath(self._native.path)

    @property
    def resolution(self) -> Tuple[int, int]:
        """The scene's own image size (width, height): the default of every size argument."""
        return self._native.resolution

    @property
    def ao_distance(self) -> float:
        """The AO distance d in scene units (`inf` for unbounded)."""
        return self._native.ao_distance

    @property
    def content_hash(self) -> str:
        """The hash of the scene file and mesh that references and results are keyed by."""
        return self._native.content_hash

    def __repr__(self) -> str:
        return repr(self._native)

    def render(
        self,
        rays: int,
        distribution: Optional[str] = None,
        sequence: Optional[str] = None,
        seed_mode: Optional[str] = None,
        seed: Optional[int] = None,
        resolution: Optional[Tuple[int, int]] = None,
        frame: Optional[int] = None,
        schedule: Optional[str] = None,
        integrand: Optional[str] = None,
        threads: Optional[int] = None,
    ) -> Tuple[Array, Array]:
        """One AO image: `hemilab render SCENE --rays RAYS ...` without its files.

        Returns `(ao, coverage)`, float32 arrays of shape (H, W): `ao` is the EXR's `Y` channel
        (1 − the occlusion estimate, 1 = open; not clamped), `coverage` its `A` (1 where the
        primary ray hit the scene). Bit for bit the image `hemilab render` writes with the same
        arguments, whatever `threads`.

        Every argument left as None takes the flag's default: `distribution` "sine-cosine"
        (also uniform, sine, concentric-cosine), `sequence` "fibonacci" (random, stratified,
        sobol, halton, pmj02bn, zsobol, r2, `points:PATH`, or a sampler registered with
        `register_sampler`), `seed_mode` "rotation" (static, shift, blue-noise, stbn, ign,
        bayer, magic-square, r2-dither, `texture:PATH[:use]`), `seed` 1, `resolution` the
        scene's (width, height), `frame` 0 and `schedule` "independent", `integrand` "ao"
        (visibility, cos-lobe-N), `threads` all cores.
        """
        return self._native.render(
            rays, distribution, sequence, seed_mode, seed, resolution, frame, schedule, integrand, threads
        )

    def gbuffer(self, resolution: Optional[Tuple[int, int]] = None) -> GBuffer:
        """The G-buffer at `resolution` (default: the scene's): depth, normal and coverage of
        each pixel's primary ray — the hits `render`'s AO rays start from — to guide `denoise`.
        The scene's camera is still, so every frame has this G-buffer."""
        return self._native.gbuffer(resolution)

    def reference(
        self, resolution: Optional[Tuple[int, int]] = None, reference_dir: Optional[PathLike] = None
    ) -> Tuple[Array, Array, Array, Dict[str, Any]]:
        """The stored reference of this scene at `resolution`, found as `hemilab advise` finds
        it (`reference_dir`, else `reference/` beside the scene file or its folder's parent's):
        the AO reference of this size, AO distance, scene content and camera with the lowest
        noise floor. Returns `(mean, coverage, stderr, manifest)`: three float32 (H, W) arrays
        and the manifest (a dict: rays, replicates, noise floor, ...). Raises `hemilab.Error`
        when none is stored; `hemilab advise SCENE` or `hemilab reference SPEC` builds one."""
        d = None if reference_dir is None else os.fspath(reference_dir)
        mean, coverage, stderr, manifest = self._native.reference(resolution, d)
        return mean, coverage, stderr, json.loads(manifest)


def points(
    distribution: str,
    sequence: str,
    seed_mode: Optional[str] = None,
    n: int = 64,
    pixel: Tuple[int, int] = (0, 0),
    width: Optional[int] = None,
    frame: Optional[int] = None,
    schedule: Optional[str] = None,
    seed: Optional[int] = None,
) -> Tuple[Array, Array]:
    """One pixel's point set: `hemilab points --distribution D --sequence S --count N` without
    the picture.

    Returns `(points, directions)`: float32 arrays of shape (n, 2), the unit-square points the
    sequence and seed mode give pixel `pixel` = (x, y), and (n, 3), the directions the
    distribution warps them to (z along the normal). `seed_mode` defaults to the `points`
    command's "static" (the render's default is "rotation"); `seed` to 1; `frame` to 0. A pixel
    below the first row needs the image's `width` (its index, which keys per-pixel numbers, is
    y * width + x).
    """
    return _hemilab.points(distribution, sequence, seed_mode, n, tuple(pixel), width, frame, schedule, seed)


def sequences() -> List[str]:
    """Every sequence name `sequence=` and specs accept: the built-ins, then registered ones."""
    return list(_hemilab.sequences())


def metrics(image: Any, reference: Any, coverage: Any) -> Dict[str, float]:
    """Every error statistic `hemilab run` records for an image against a reference, over the
    pixels where `coverage` > 0: `rmse`, `bias` (mean of image − reference), `lowpass_rmse`
    (RMSE of the error after a σ = 1.5 px Gaussian), `lowfreq_ratio` (its low-pass energy over
    white noise's: 1 white, < 1 blue, > 1 clumped or banded — the structure verdict),
    `autocorr_x`, `autocorr_y` (lag-1 autocorrelation of the error), `whiteness_z`,
    `covered` (pixels measured) and `flip` (mean LDR-FLIP, Andersson et al. 2020, at 67 pixels
    per degree, AO as linear grey: the run's `flip` column). The three arrays must have one size."""
    return dict(
        _hemilab.metrics(_image(image, "image"), _image(reference, "reference"), _image(coverage, "coverage"))
    )


def denoise(frames: Union[Array, Sequence[Any]], pipeline: str = "svgf", gbuffer: Optional[GBuffer] = None) -> Array:
    """A still camera's frames through a filter pipeline, as `hemilab run` pushes them.

    `frames`: an (F, H, W) array or a list of (H, W) images (frame 1 first); `pipeline`: a
    pipeline name as specs write it — raw, gauss, atrous[:K], mean, emaA, taaA, svgf[:K], or a
    temporal part then a spatial one joined by '+' (e.g. "ema0.1+atrous"); `gbuffer`: the
    frames' G-buffer (`Scene.gbuffer`), which the edge-stopping filters read. Returns the
    output after each frame, an (F, H, W) float32 array."""
    if gbuffer is None:
        raise Error("denoise: gbuffer= is required (Scene.gbuffer(resolution) of the frames' scene and size)")
    images = [_image(f, f"frames[{i}]") for i, f in enumerate(frames)]
    out = _hemilab.denoise(images, pipeline, gbuffer)
    if not out:
        return np.zeros((0, gbuffer.height, gbuffer.width), dtype=np.float32)
    return np.stack(out)


def run(
    spec: PathLike,
    out: Optional[PathLike] = None,
    reference_dir: Optional[PathLike] = None,
    force: bool = False,
    no_build_reference: bool = False,
    timing_repeats: Optional[int] = None,
    threads: Optional[int] = None,
    quiet: bool = True,
) -> str:
    """`hemilab run SPEC`: every job of the spec rendered, timed, measured against its reference
    and reported, through the command's own code (resumes a killed run; `force` re-renders).
    Returns the output directory (`out`, default `out/<spec name>/`); `load_results` reads its
    records. A sampler registered with `register_sampler` may be named in the spec."""
    o = None if out is None else os.fspath(out)
    r = None if reference_dir is None else os.fspath(reference_dir)
    return os.fspath(_hemilab.run(os.fspath(spec), o, r, force, no_build_reference, timing_repeats, threads, quiet))


def load_results(dir: PathLike) -> Any:
    """The records of a run's output directory (`results.json`, one per image: scene,
    distribution, sequence, seed_mode, rays, replicate, seed, rmse, bias, lowpass_rmse,
    lowfreq_ratio, times, ...): a pandas DataFrame when pandas is importable, else a list of
    dicts."""
    records = json.loads(_hemilab.results_json(os.fspath(dir)))
    try:
        import pandas  # type: ignore[import-not-found]
    except ImportError:
        return records
    return pandas.DataFrame.from_records(records)


def read_exr(path: PathLike) -> Dict[str, Array]:
    """The channels of an EXR file hemilab wrote, by name, as float32 (H, W) arrays: a render's
    `Y` (AO) and `A` (coverage), a reference's `Y`, `A` and `stderr`."""
    return dict(_hemilab.read_exr(os.fspath(path)))


def register_sampler(name: str, fill: Callable[[PixelSet], Any], label: Optional[str] = None) -> Sampler:
    """Registers a Python callable as the point sequence `name`, the way a Rust program registers
    a `PointSequence` (`hemilab::sampling::register`): from then on `sequence=name` in `render`
    and `points`, and `sequence = "name"` in a spec `run` reads, use it like a built-in one.

    `fill(set)` receives a `PixelSet` (`count` points in the whole set, `n` wanted, pixel `x`,
    `y` and index `pixel`, the set's `key` — fresh per pixel under the `shift` seed mode, the
    run's otherwise — and `offset`, the seed mode's offsets to add mod 1) and returns at least
    `n` points in [0, 1)² as an (n, 2) array or list of pairs. It must depend only on `set`.

    The renderer's threads call it one at a time; the time spent inside it is counted apart
    (`Sampler.seconds`, `Sampler.calls`): it is Python's cost, not the sampler's, so compare
    samplers' render times only between samplers of one kind. Registering a name again replaces
    its callable. An exception or a bad return value raises `hemilab.Error` when the call into
    hemilab returns.
    """
    return _hemilab.register_sampler(name, fill, label)
