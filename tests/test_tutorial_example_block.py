"""The own-mechanism tutorial shows how to give a package named examples (``parakin demo`` of a
package without any prints "(no named examples ...)"). Its block, run beside the tutorial's own
``my_robot.py``, makes an inverse ``Example`` whose printed leg lengths are the distances
|p + c_i - A_i| computed here with NumPy from my_robot's points at the example's pose."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("parakin.generator.joints")

DOCS = Path(__file__).resolve().parent.parent / "docs" / "tutorials"


def test_the_tutorials_example_block_prints_my_robots_leg_lengths():
    text = (DOCS / "own_mechanism.md").read_text()
    start = text.index("## Named examples")
    (block,) = re.findall(r"```python\n(.*?)```", text[start : text.index("\n## ", start + 1)], re.S)
    namespace: dict[str, object] = {}
    exec(compile((DOCS / "my_robot.py").read_text(), "my_robot.py", "exec"), namespace)
    exec(compile(block, "own_mechanism.md", "exec"), namespace)
    from parakin.generator.model import Example

    (example,) = namespace["EXAMPLES"]  # type: ignore[misc]
    assert isinstance(example, Example) and example.branch == 0
    pose = np.array(example.pose)
    base = np.array([(0, 0), (1, 0), (0.5, 0.9)], dtype=float)  # as printed in my_robot.py
    platform = np.array([(-0.2, -0.1), (0.2, -0.1), (0.15, 0.25)])
    lengths = np.linalg.norm(pose[:2, 3] + platform @ pose[:2, :2].T - base, axis=1)
    assert pose[:2, 3].tolist() == [0.5, 0.3] and np.allclose(pose[:3, :3], np.eye(3), atol=0)
    assert example.expected["actuated"] == pytest.approx(lengths, abs=1e-15)
    assert lengths == pytest.approx([0.36055512754639896, 0.36055512754639896, 0.3807886552931954], abs=1e-15)
