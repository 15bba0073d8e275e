"""The paper's Table 2 from Python: a script a notebook could be (one cell per paragraph).

It renders the table's 36 images of the kitchen (three distributions with pseudo-random numbers,
8, 16 and 32 rays, four replicates) with `hemilab.Scene.render`, measures each against the
committed reference with `hemilab.metrics`, checks every replicate's RMSE against the committed
run's record (`hemilab.load_results`), and prints the table as the README quotes it — then fails
(exit status 1) unless it is the README's `paper/table2` block, character for character.

    pip install ./python             # once, from the repository's root
    python examples/notebook.py      # a few seconds

`.ci/run` runs it.
"""

import pathlib
import re
import sys

import numpy as np

import hemilab

ROOT = pathlib.Path(__file__).resolve().parents[1]

# experiments/paper.toml: the kitchen at 160x120, run seed 1, 4 replicates; Table 2's rows are
# the three distributions with pseudo-random numbers (seed mode `rotation`, the spec's default).
RESOLUTION = (160, 120)
RAYS = [8, 16, 32]
REPLICATES = 4
ROWS = [("uniform", "uniform, pseudo-random"), ("sine", "sine, pseudo-random"),
        ("sine-cosine", "sine-cosine, pseudo-random")]

# The committed run: one record per image, with the seed each replicate was rendered with.
records = hemilab.load_results(ROOT / "experiments" / "outputs" / "paper")
records = records.to_dict("records") if hasattr(records, "to_dict") else records

# The scene, and its committed reference at the run's size (found as `hemilab advise` finds it).
kitchen = hemilab.Scene.load(ROOT / "scenes" / "kitchen.toml")
reference, coverage, _, manifest = kitchen.reference(resolution=RESOLUTION)
print(f"{kitchen!r}: reference of {manifest['replicates']} x {manifest['rays']} rays, "
      f"noise floor {manifest['noise_floor']:.1e}")


def fixed(x, digits):
    """`x` to `digits` decimals, without the minus sign of a value that rounds to zero."""
    t = f"{x:.{digits}f}"
    return t.lstrip("-") if set(t.lstrip("-")) <= {"0", "."} else t


def mean_sd(values):
    v = np.asarray(values, dtype=np.float64)
    return v.mean(), v.std(ddof=1)


# Render and measure every cell; each replicate must be the committed run's image, measured alike.
table = ["| configuration | 8 rays | 16 rays | 32 rays |", "|---|---|---|---|"]
for distribution, label in ROWS:
    cells = []
    for rays in RAYS:
        rmse, rho = [], []
        for replicate in range(REPLICATES):
            record = next(r for r in records if r["distribution"] == distribution and r["sequence"] == "random"
                          and r["rays"] == rays and r["replicate"] == replicate and r["pipeline"] == "raw")
            ao, _ = kitchen.render(rays=rays, distribution=distribution, sequence="random",
                                   seed_mode="rotation", seed=record["seed"], resolution=RESOLUTION)
            m = hemilab.metrics(ao, reference, coverage)
            if m["rmse"] != record["rmse"]:
                sys.exit(f"{distribution} at {rays} rays, replicate {replicate}: RMSE {m['rmse']!r} "
                         f"from Python, {record['rmse']!r} in the committed run")
            rmse.append(m["rmse"])
            rho.append(0.5 * (m["autocorr_x"] + m["autocorr_y"]))
        (m_, s_), (r_, _) = mean_sd(rmse), mean_sd(rho)
        cells.append(f"{m_:.4f} ± {s_:.4f} (ρ {fixed(r_, 2)})")
    table.append(f"| {label} | " + " | ".join(cells) + " |")
ours = "\n".join(table)
print(ours)

# The README's quoted block, which tests/claims/readme.rs ties to the committed run.
readme = (ROOT / "README.md").read_text(encoding="utf-8")
quoted = re.search(r"<!-- quote paper/table2 -->\n(.*?)\n<!-- /quote -->", readme, re.S)
if quoted is None or quoted.group(1).strip() != ours:
    sys.exit("the table above is not the README's paper/table2 block")
print("= the README's Table 2 (paper/table2), rendered and measured from Python")
