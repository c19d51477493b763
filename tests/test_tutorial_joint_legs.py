"""The own-mechanism tutorial (docs/tutorials/own_mechanism.md) documents the passive leg and the
leg written joint by joint (a new user's review found them nowhere but in the source and a test
fixture): the signatures it prints are checked against the functions and dataclasses themselves
(``inspect.signature``: every parameter, in order, with its default), its Tricept block is run
and its legs counted from the joints it writes, and its named-examples block is the examples part
of the tutorial's own ``my_robot.py``, verbatim, after the ``# Examples`` line the shipped files
use."""

from __future__ import annotations

import ast
import inspect
import re
from pathlib import Path

import pytest

joints = pytest.importorskip("parakin.generator.joints")
graph = pytest.importorskip("parakin.generator.graph")

DOCS = Path(__file__).resolve().parent.parent / "docs" / "tutorials"
TUTORIAL = DOCS / "own_mechanism.md"


def _section(title: str) -> str:
    text = TUTORIAL.read_text()
    start = text.index(f"## {title}")
    end = text.index("\n## ", start + 1)
    return text[start:end]


def _blocks(section: str, executed: bool) -> list[str]:
    """The section's Python blocks: the executed ones (``exec="on"``) or the plain ones."""
    found = re.findall(r"```python([^\n]*)\n(.*?)```", section, re.S)
    return [code for options, code in found if ('exec="on"' in options) == executed]


def test_the_tutorial_prints_the_passive_leg_joint_and_chain_signatures_as_they_are():
    (block,) = _blocks(_section("A passive leg, and a leg joint by joint"), executed=False)
    calls = [node for node in ast.walk(ast.parse(block)) if isinstance(node, ast.Call)]
    printed = {(c.func.attr if isinstance(c.func, ast.Attribute) else c.func.id): c for c in calls}
    targets = {
        "passive_leg": joints.passive_leg,
        "central_joint": joints.central_joint,
        "Joint": graph.Joint,
        "Chain": graph.Chain,
    }
    assert set(printed) == set(targets)
    for name, call in printed.items():
        actual = inspect.signature(targets[name]).parameters.values()
        shown = [(a.id, inspect.Parameter.empty) for a in call.args]
        shown += [(k.arg, ast.literal_eval(k.value)) for k in call.keywords]
        assert shown == [(p.name, p.default) for p in actual], name


def test_the_tutorials_tricept_has_three_actuated_legs_and_one_passive_leg():
    tricept, skew = _blocks(_section("A passive leg, and a leg joint by joint"), executed=True)
    namespace: dict[str, object] = {}
    exec(compile(tricept, "own_mechanism.md", "exec"), namespace)
    model = namespace["TRICEPT"]
    assert isinstance(model, joints.DistanceMechanism)
    # the kinds as the block writes them: U (universal_axis) - P actuated - S, and U-P-F
    assert [chain.kinds for chain in model.graph.legs] == ["U-P_-S"] * 3 + ["U-P-F"]
    assert (len(model.legs), len(model.passive)) == (3, 1)
    # three lengths and the passive leg's three constraints hold six twist components
    assert len(model.legs) + 3 * len(model.passive) == len(model.motion.twist) == 6
    assert {"leg4_line_reachable", "leg4_u_joint_reachable"} <= set(model.inverse().validity)
    exec(compile(skew, "own_mechanism.md", "exec"), namespace)
    form = namespace["form"]
    # a skew elbow axis is no closed form's: numeric, from the middle of limits (-1, 2)
    assert form.kind == "crank" and form.elbow_axis is not None
    assert form.start == 0.5


def test_the_named_examples_block_is_my_robots_examples_part():
    (block,) = _blocks(_section("Named examples"), executed=False)
    source = (DOCS / "my_robot.py").read_text()
    model, marker, examples = source.partition("\n# Examples\n")
    assert marker and block == marker.lstrip("\n") + examples
    assert "examples=EXAMPLES" in model and "EXAMPLES =" not in model
