#!/usr/bin/env python3
"""Writes the LDR-FLIP check data for tests/stages/metrics_flip.rs, once, with NVIDIA's
flip-evaluator 1.7 (PyPI, BSD-3-Clause). CI never runs this; it reads the committed outputs.

Made with (from the repository root):
    python3 -m venv /tmp/flipenv
    /tmp/flipenv/bin/pip install 'flip-evaluator==1.7.*' 'numpy>=1.26'
    /tmp/flipenv/bin/python tests/data/flip/make_expected.py

Writes, beside this file: <case>_ref.f32 and <case>_test.f32 (64 x 48 grey images, row-major,
little-endian float32; AO values, some outside [0, 1] so that the clamp is exercised) and
expected.json: for each case the pixels per degree, the mean FLIP and per-pixel FLIP at 64 sampled
pixels. AO is linear grey: v becomes the linear RGB colour (v, v, v), inputsRGB=False.
"""
import json
import os

import flip_evaluator as flip
import numpy as np

W, H = 64, 48
HERE = os.path.dirname(os.path.abspath(__file__))
rng = np.random.default_rng(20201)
xs, ys = np.meshgrid(np.arange(W, dtype=np.float64), np.arange(H, dtype=np.float64))


def ao_like():
    """Occlusion darkening towards two walls and a blob (a corner and an object on a floor)."""
    corner = np.exp(-xs / 9.0) + np.exp(-(H - 1 - ys) / 7.0)
    blob = 0.6 * np.exp(-((xs - 40.0) ** 2 + (ys - 20.0) ** 2) / 60.0)
    return np.clip(0.95 - 0.5 * corner - blob, 0.0, 1.0)


gradient = xs / (W - 1)
ao = ao_like()
edges = np.where((xs // 16 + ys // 12) % 2 == 0, 0.8, 0.2)
edges_test = np.where(((xs + 1) // 16 + ys // 12) % 2 == 0, 0.8, 0.2)
edges_test[30, 5:60] = 0.5

cases = [
    # name, reference, test, pixels per degree
    ("gradient_noise", gradient, gradient + rng.normal(0.0, 0.05, (H, W)), 67.0),
    ("ao_one_ray", ao, (rng.random((H, W)) < ao).astype(np.float64), 67.0),
    ("ao_one_ray_ppd30", ao, (rng.random((H, W)) < ao).astype(np.float64), 30.0),
    ("edges", edges, edges_test, 67.0),
    ("offset", ao, ao + 0.05, 67.0),
]

samples = [(0, 0), (W - 1, 0), (0, H - 1), (W - 1, H - 1)]
samples += [(int(x), int(y)) for x, y in zip(rng.integers(0, W, 60), rng.integers(0, H, 60))]

out = {"generator": "flip-evaluator " + getattr(flip, "__version__", "1.7"), "width": W, "height": H, "cases": []}
for name, ref, test, ppd in cases:
    ref = ref.astype(np.float32)
    test = test.astype(np.float32)
    ref.astype("<f4").tofile(os.path.join(HERE, name + "_ref.f32"))
    test.astype("<f4").tofile(os.path.join(HERE, name + "_test.f32"))
    rgb = lambda a: np.ascontiguousarray(np.repeat(a[:, :, None], 3, axis=2), dtype=np.float32)
    fmap, mean, _ = flip.evaluate(rgb(ref), rgb(test), "LDR", inputsRGB=False, applyMagma=False,
                                  computeMeanError=True, parameters={"ppd": ppd})
    fmap = np.asarray(fmap)[:, :, 0]
    out["cases"].append({
        "name": name,
        "ppd": ppd,
        "mean": float(mean),
        "samples": [[x, y, float(fmap[y, x])] for x, y in samples],
    })
    print(f"{name}: mean FLIP {mean:.6f}")

with open(os.path.join(HERE, "expected.json"), "w") as f:
    json.dump(out, f, indent=1)
    f.write("\n")
