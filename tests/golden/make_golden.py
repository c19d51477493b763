"""Reference results of the hand-derived mechanisms, for ``tests/test_golden.py`` (run by hand).

Before the joint language (``generator/joints.py``, commit 71d1c7d) every mechanism derived its
loop closure, rate model, inverse and singularity factors by hand. This script evaluates the
packages of that commit with that commit's own runtime and stores, per mechanism, inputs and
outputs in ``tests/golden/NAME.npz``: the golden data the re-expressed mechanisms are held to.

    git worktree add --detach /work/wt-hand 71d1c7d^ && make -C /work/wt-hand setup
    .venv/bin/python tests/golden/make_golden.py /work/wt-hand [NAMES...]

The inputs are the first SAMPLES of the old package's ``sample_configurations`` (seed 11, spread 0.05; the same
mechanism parameters in both versions), random actuated rates (seed 12) and, for the all-modes
solver, the first ``MODE_INPUTS[name]`` sampled actuated inputs (fewer where a mechanism takes
seconds per input).
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
from pathlib import Path

#: the mechanisms re-expressed in the joint language since the hand-derived commit
NAMES = ("delta", "five_bar", "gough", "planar_3rpr", "planar_3rrr", "prs3", "rus6", "spm", "sps", "stewart")
SAMPLES = 1000
#: inputs of the all-modes comparison: every mode's pose is stored (3 x 4 each), which dominates the
#: files' size, so fewer than the other comparisons' SAMPLES; rus6 takes seconds per input
MODE_INPUTS = {"rus6": 12}
MODES_DEFAULT = 200

EXTRACT = r"""
import subprocess, sys
import numpy as np
import parakin
from parakin.sampling import sample_configurations

name, path, samples, mode_inputs = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
m = parakin.load(name)
conf = sample_configurations(m, 4 * samples, spread=0.05, seed=11)  # fewer close where Newton fails
conf = type(conf)(conf.actuated[:samples], conf.passive[:samples], conf.pose[:samples])
out = {"source_commit": subprocess.check_output(["git", "rev-parse", "HEAD"], text=True).strip()}
out["pose"], out["actuated"] = conf.pose, conf.actuated
inverse = m.inverse_pose(conf.pose, strict=False)
out["inverse_actuated"], out["inverse_valid"] = inverse.actuated, inverse.valid
rates = np.random.default_rng(12).standard_normal(conf.actuated.shape)
out["actuated_rates"] = rates
if m.capabilities.rates is not None:
    out["twist"] = m.forward_rate(conf, rates)
values = m.singularities(conf)
out["singularity_names"] = np.array(list(values))
out["singularity_values"] = np.stack([values[k] for k in values], -1)
theta = conf.actuated[:mode_inputs]
modes = m.forward_pose_all(theta, strict=False)
poses = [modes.poses[i][np.nonzero(modes.valid[i])[0]][:, :3, :] for i in range(theta.shape[0])]
out["mode_actuated"], out["mode_count"] = theta, np.asarray(modes.count)
out["mode_poses"] = np.concatenate(poses) if poses else np.zeros((0, 3, 4))  # input i's: after sum(count[:i])
np.savez_compressed(path, **out)
print(name, "samples", conf.actuated.shape[0], "mode inputs", theta.shape[0])
"""


def main(argv: list[str]) -> None:
    hand = Path(argv[0]).resolve()
    names = argv[1:] or list(NAMES)
    here = Path(__file__).parent
    with tempfile.TemporaryDirectory() as scratch:
        script = Path(scratch) / "extract.py"
        script.write_text(EXTRACT)
        for name in names:
            target = here / f"{name}.npz"
            command = [str(hand / ".venv/bin/python"), str(script), name, str(target), str(SAMPLES)]
            subprocess.run([*command, str(MODE_INPUTS.get(name, MODES_DEFAULT))], cwd=hand, check=True)


if __name__ == "__main__":
    main(sys.argv[1:])
