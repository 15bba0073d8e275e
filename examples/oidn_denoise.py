#!/usr/bin/env python3
"""Intel Open Image Denoise as hemilab's `denoise_command`.

Reads the EXR hemilab writes for a frame (channels: R, G, B = the AO; A = coverage; N.X, N.Y, N.Z
= unit normals; Z = depth; albedo.R, albedo.G, albedo.B = 1), runs OIDN's "RT" filter on the
colour with the albedo and normal as auxiliary images, and writes an EXR whose Y channel is the
denoised AO (the mean of OIDN's three output channels; background pixels are copied as they came).

Needs two PyPI packages, installed with pip (neither is a hemilab dependency):

    pip install pyoidn openexr      # OIDN 2.x bundled in the wheel; OpenEXR's Python bindings

Used from a spec as

    [denoise_command]
    program = "python3"
    args = ["examples/oidn_denoise.py", "{input}", "{output}"]

Options: --quality high|balanced|fast (default high); --no-aux (colour only, for comparison);
--ldr (OIDN's LDR mode instead of HDR, for comparison);
--clean-aux (tell OIDN the auxiliary images are noise-free, which hemilab's are: one primary
ray per pixel centre, no noise). Exit status 1 with a message on stderr on any failure, so
hemilab reports it.
"""

import argparse
import sys

import numpy as np


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("input")
    parser.add_argument("output")
    parser.add_argument("--quality", default="high", choices=["high", "balanced", "fast"])
    parser.add_argument("--no-aux", action="store_true")
    parser.add_argument("--clean-aux", action="store_true")
    parser.add_argument("--ldr", action="store_true")
    args = parser.parse_args()
    try:
        import OpenEXR
        import pyoidn
    except ImportError as e:
        print(f"oidn_denoise: {e}; install with: pip install pyoidn openexr", file=sys.stderr)
        return 1

    with OpenEXR.File(args.input, separate_channels=True) as f:
        channels = f.channels()
        need = ["R", "G", "B", "A", "N.X", "N.Y", "N.Z", "albedo.R", "albedo.G", "albedo.B"]
        missing = [c for c in need if c not in channels]
        if missing:
            print(f"oidn_denoise: {args.input} lacks channels {missing}", file=sys.stderr)
            return 1
        get = lambda name: np.asarray(channels[name].pixels, dtype=np.float32)
        stack = lambda names: np.ascontiguousarray(np.stack([get(n) for n in names], axis=-1))
        color = stack(["R", "G", "B"])
        coverage = get("A")
        normal = stack(["N.X", "N.Y", "N.Z"])
        albedo = stack(["albedo.R", "albedo.G", "albedo.B"])

    # AO is linear light under a uniform white sky, so OIDN's HDR mode fits it (values >= 0; a few
    # estimators' weights overshoot 1 or undershoot 0 slightly, so negatives are clamped). Its LDR
    # mode (--ldr, input clamped to [0, 1]) was tried on the kitchen and is far worse on 1-ray
    # frames: it pulls the 0/1 noise towards white (docs/realtime.md).
    color = np.maximum(color, 0.0)
    ldr = np.clip(color, 0.0, 1.0)
    aux = {} if args.no_aux else {"albedo": albedo, "normal": normal, "clean_aux": args.clean_aux}
    out = pyoidn.denoise(color if not args.ldr else ldr, hdr=not args.ldr, quality=args.quality, **aux)
    y = out.mean(axis=-1).astype(np.float32)
    y = np.where(coverage > 0.5, y, color[..., 0])
    if not np.all(np.isfinite(y)):
        print("oidn_denoise: OIDN returned non-finite values", file=sys.stderr)
        return 1
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with OpenEXR.File(header, {"Y": y, "A": coverage}) as f:
        f.write(args.output)
    return 0


if __name__ == "__main__":
    sys.exit(main())
