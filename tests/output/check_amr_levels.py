"""The adaptive grid's level file follows run.output.fields (docs/output.md).

Usage: /usr/bin/python3 check_amr_levels.py RUN_DIR FIELD...
The last snapshot's step_N_levels.h5 must hold, on every level, exactly the
fields asked (plus nodes, cells, vorticity and level), each with the units of
the uniform snapshot step_N.h5, and each leaf's value must equal the uniform
snapshot's value at a point inside the leaf bit for bit (the uniform grid is
the finest level's; a fine cell shows the leaf that holds it). Two levels or
more must be present, so that coarse leaves are compared too.
"""
import glob
import sys

import h5py
import numpy as np

run, asked = sys.argv[1], sys.argv[2:]
snap = sorted(glob.glob(f"{run}/fluid/step_*[0-9].h5"))[-1]
uniform, levels = h5py.File(snap, "r"), h5py.File(snap[:-3] + "_levels.h5", "r")
shape = uniform[asked[0]].shape[:3]  # [nz][ny][nx]
names = sorted({k.split("_", 1)[0] for k in levels})  # level0 .. levelM, empty ones included
filled = [n for n in names if len(levels[f"{n}_cells"]) > 0]
assert len(filled) >= 2, f"leaves on one level only: {filled}"
worst, compared = 0.0, 0
for level in names:
    got = sorted(k.split("_", 1)[1] for k in levels if k.startswith(level + "_"))
    want = sorted(asked + ["cells", "nodes", "vorticity", "level"])
    assert got == want, f"{level}: datasets {got}, expected {want}"
    cells = levels[f"{level}_cells"][:]
    if len(cells) == 0:
        continue
    nodes = levels[f"{level}_nodes"][:][cells]  # [cell][corner][xyz]
    spacing = nodes.max(axis=1) - nodes.min(axis=1)
    fine = spacing[0] / (2 ** (len(names) - 1 - int(level[5:])))  # the finest level's cell
    inside = nodes.min(axis=1) + 0.5 * fine  # a point in the leaf's first finest cell
    h = np.where(fine > 0, fine, 1.0)
    index = np.floor(inside / h).astype(int)  # the box starts at 0 in the test's config
    for name in asked:
        assert levels[f"{level}_{name}"].attrs["units"] == uniform[name].attrs["units"], name
        value = levels[f"{level}_{name}"][:]  # [leaf][component]
        seen = uniform[name][:][0 if shape[0] == 1 else index[:, 2], index[:, 1], index[:, 0]]
        seen = seen.reshape(len(value), -1)
        assert seen.shape[1] <= value.shape[1], (name, seen.shape, value.shape)
        d = np.abs(value[:, : seen.shape[1]] - seen)
        assert np.all(np.isfinite(d)), f"{level}_{name}: NaN"
        worst = max(worst, float(d.max()))
        compared += len(value)
print(f"{snap[:-3]}_levels.h5: levels {names}, datasets as asked ({', '.join(asked)}), "
      f"{compared} leaf values against the uniform snapshot: largest difference {worst:.3e}")
assert worst <= 0, worst
