"""Shared fixtures: the repository, the `hemilab` binary the module is compared with, and a
runner for it. The binary is the one `cargo test --release` (or `cargo build --release`) built:
$HEMILAB_BIN, else $CARGO_TARGET_DIR/release/hemilab, else target/release/hemilab."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


def _binary() -> pathlib.Path:
    if os.environ.get("HEMILAB_BIN"):
        return pathlib.Path(os.environ["HEMILAB_BIN"])
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    return target / "release" / "hemilab"


@pytest.fixture(scope="session")
def root() -> pathlib.Path:
    return ROOT


@pytest.fixture(scope="session")
def cli():
    """Runs `hemilab ARGS...` and returns the completed process (never raises on failure)."""
    binary = _binary()
    if not binary.exists():
        pytest.fail(f"{binary} not found: build it with `cargo build --release` or set HEMILAB_BIN")

    def run(*args, cwd=None):
        return subprocess.run(
            [str(binary), *map(str, args)], cwd=cwd, capture_output=True, text=True, timeout=600
        )

    return run


@pytest.fixture(scope="session")
def cornell(root):
    import hemilab

    return hemilab.Scene.load(root / "scenes" / "cornell-box.toml")
