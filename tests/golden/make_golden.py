"""Reference results of the hand-derived mechanisms, for ``tests/test_golden.py`` (run by hand, not by CI).

Before the joint language (``generator/joints.py``, commit 71d1c7d) every mechanism derived its
loop closure, rate model, inverse and singularity factors by hand. This script evaluates the
packages of that commit with that commit's own runtime and stores, per mechanism, inputs and
outputs in ``tests/golden/NAME.npz`` (with ``source_commit``, the commit evaluated): the golden
data the re-expressed mechanisms are held to. From the root of this checkout:

    git -C /work/main worktree add --detach /work/wt-hand 71d1c7d^ && make -C /work/wt-hand setup
    .venv/bin/python tests/golden/make_golden.py /work/wt-hand [NAMES...]

It runs an extractor with the hand-derived checkout's own interpreter (``HAND/.venv/bin/python``,
whose editable install loads that checkout's ``generated/``). The inputs, all seeded, so that a
rerun writes the same numbers:

- ``pose``, ``actuated``: the first SAMPLES of the old package's ``sample_configurations`` (seed 11,
  spread 0.05; the mechanism parameters are the same in both versions), with every inverse branch
  (``inverse_actuated``, ``inverse_valid``, and ``inverse_failures`` (..., branch, condition)
  where each validity condition ``inverse_failure_names`` failed), the twist for random actuated rates (seed 12;
  ``actuated_rates``, ``twist``) and every singularity factor (``singularity_names``,
  ``singularity_values``);
- ``wide_pose``: poses farther out, P0 expm(k logm(P0^-1 P)) for the first WIDE_SAMPLES sampled
  poses P, P0 the first and k uniform in [1, WIDE) (seed 14): the same kind of pose (each screw
  motion from P0 scaled up), many out of reach of some legs, so that the validity and NaN patterns
  of the inverse branches are exercised (``wide_inverse_actuated``, ``wide_inverse_valid``, ...; left out
  where every branch of every wide pose is valid, as for legs of unbounded length);
- the real assembly modes of the first ``MODE_INPUTS[name]`` sampled actuated inputs (fewer where
  a mechanism takes seconds per input): ``mode_count`` per input, ``mode_fingerprint`` (per mode,
  in order, the sum of ``fingerprint_weights`` (seed 13) times its 3 x 4 pose: one number that
  tells poses apart) and, for the first MODE_POSES inputs only (the poses dominate the files'
  size), ``mode_poses`` (3 x 4 each).
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
from pathlib import Path

#: the mechanisms re-expressed in the joint language since the hand-derived commit
NAMES = ("delta", "five_bar", "gough", "planar_3rpr", "planar_3rrr", "prs3", "rus6", "spm", "sps", "stewart")
SAMPLES = 1000
#: rus6's all-modes solver takes about a second per input
MODE_INPUTS = {"rus6": 12}
MODE_POSES = 50
#: the wide poses scale the sampled screw motions from the first pose by up to this factor
WIDE = 30
#: wide poses: the first of the samples' (fewer for rus6, whose 64 inverse branches dominate its file)
WIDE_SAMPLES = {"rus6": 250}

EXTRACT = r"""
import subprocess, sys
import numpy as np
from scipy.linalg import expm, logm
import parakin
from parakin.sampling import sample_configurations

name, path, samples, mode_inputs, mode_poses, wide, wide_samples = sys.argv[1:]
samples, mode_inputs, mode_poses, wide, wide_samples = map(int, (samples, mode_inputs, mode_poses, wide, wide_samples))
m = parakin.load(name)
conf = sample_configurations(m, 4 * samples, spread=0.05, seed=11)  # fewer close where Newton fails
conf = type(conf)(conf.actuated[:samples], conf.passive[:samples], conf.pose[:samples])
assert conf.actuated.shape[0] == samples, conf.actuated.shape
out = {"source_commit": subprocess.check_output(["git", "rev-parse", "HEAD"], text=True).strip()}
out["pose"], out["actuated"] = conf.pose, conf.actuated


def inverse(prefix, poses):
    result = m.inverse_pose(poses, strict=False)
    out[prefix + "inverse_actuated"], out[prefix + "inverse_valid"] = result.actuated, result.valid
    out[prefix + "inverse_failure_names"] = np.array(list(result.failures))
    out[prefix + "inverse_failures"] = np.stack(list(result.failures.values()), -1)
    return result.valid


inverse("", conf.pose)
rates = np.random.default_rng(12).standard_normal(conf.actuated.shape)
out["actuated_rates"] = rates
if m.capabilities.rates is not None:
    out["twist"] = m.forward_rate(conf, rates)
values = m.singularities(conf)
out["singularity_names"] = np.array(list(values))
out["singularity_values"] = np.stack([values[k] for k in values], -1)

first = conf.pose[0]
scale = np.random.default_rng(14).uniform(1.0, wide, wide_samples)
screws = [logm(np.linalg.solve(first, pose)).real for pose in conf.pose[:wide_samples]]
wide_pose = np.stack([first @ expm(k * screw) for k, screw in zip(scale, screws)])
wide_pose[:, 3, :] = (0.0, 0.0, 0.0, 1.0)
valid = inverse("wide_", wide_pose)
if valid.all():  # nothing to exercise (every leg reaches every pose: the prismatic ones)
    out = {key: value for key, value in out.items() if not key.startswith("wide_")}
else:
    out["wide_pose"] = wide_pose

theta = conf.actuated[:mode_inputs]
modes = m.forward_pose_all(theta, strict=False)
poses = [modes.poses[i][np.nonzero(modes.valid[i])[0]][:, :3, :] for i in range(theta.shape[0])]
weights = np.random.default_rng(13).standard_normal((3, 4))
out["mode_count"] = np.asarray(modes.count)
assert (out["mode_count"] == [len(p) for p in poses]).all()
out["fingerprint_weights"] = weights
out["mode_fingerprint"] = np.concatenate([(p * weights).sum((-2, -1)) for p in poses])
out["mode_poses"] = np.concatenate(poses[:mode_poses])  # input i's: after sum(count[:i])
np.savez_compressed(path, **out)
print(f"{name}: {samples} samples, wide poses with every/some/no branch valid "
      f"{valid.all(-1).sum()}/{(valid.any(-1) & ~valid.all(-1)).sum()}/{(~valid.any(-1)).sum()}, "
      f"{theta.shape[0]} mode inputs, {out['mode_count'].sum()} modes")
"""


def main(argv: list[str]) -> None:
    """Write ``tests/golden/NAME.npz`` for NAMES (default: all) from the checkout at ``argv[0]``."""
    hand = Path(argv[0]).resolve()
    names = argv[1:] or list(NAMES)
    here = Path(__file__).parent
    with tempfile.TemporaryDirectory() as scratch:
        script = Path(scratch) / "extract.py"
        script.write_text(EXTRACT)
        for name in names:
            counts = (SAMPLES, MODE_INPUTS.get(name, SAMPLES), MODE_POSES, WIDE, WIDE_SAMPLES.get(name, SAMPLES))
            arguments = [name, str(here / f"{name}.npz"), *map(str, counts)]
            subprocess.run([str(hand / ".venv/bin/python"), str(script), *arguments], cwd=hand, check=True)


if __name__ == "__main__":
    main(sys.argv[1:])
