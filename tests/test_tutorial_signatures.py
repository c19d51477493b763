"""The own-mechanism tutorial (docs/tutorials/own_mechanism.md) gives the leg builders'
signatures and what ``sign`` means (a new user's review: ``slider_leg``'s signature and ``sign``
were nowhere but in the source). The signatures printed there are checked against the functions
themselves (``inspect.signature``): every parameter, in order, with its default."""

from __future__ import annotations

import ast
import inspect
import re
from pathlib import Path

import pytest

joints = pytest.importorskip("parakin.generator.joints")

TUTORIAL = Path(__file__).resolve().parent.parent / "docs" / "tutorials" / "own_mechanism.md"


def _section() -> str:
    text = TUTORIAL.read_text()
    start = text.index("## The leg builders' signatures")
    end = text.index("\n## ", start + 1)
    return text[start:end]


def test_the_tutorial_prints_each_leg_builders_signature_as_the_function_has_it():
    (block,) = re.findall(r"```python\n(.*?)```", _section(), re.S)  # not executed: no exec="on"
    calls = [node for node in ast.walk(ast.parse(block)) if isinstance(node, ast.Call)]
    printed = {call.func.attr: call for call in calls if isinstance(call.func, ast.Attribute)}
    assert set(printed) == {"platform", "prismatic_leg", "crank_leg", "slider_leg"}
    for name, call in printed.items():
        actual = inspect.signature(getattr(joints, name)).parameters.values()
        shown = [(a.id, inspect.Parameter.empty) for a in call.args]
        shown += [(k.arg, ast.literal_eval(k.value)) for k in call.keywords]
        assert shown == [(p.name, p.default) for p in actual], name


def test_the_tutorial_says_what_sign_means_for_cranks_and_sliders():
    section = _section()
    meaning = section.partition("**What `sign` means.**")[2]
    assert "`crank_leg`, `sign=1`: sigma_k = +1 turns the crank counter-clockwise" in meaning
    assert "`slider_leg`, `sign=1`: sigma_k = +1 puts the slider behind the platform joint along k" in meaning
    # the same meaning as the functions' own docstrings say
    crank, slider = (" ".join((f.__doc__ or "").split()) for f in (joints.crank_leg, joints.slider_leg))
    assert "Branch sign +1 turns the crank counter-clockwise from the line A -> C" in crank
    assert "Branch sign +1 puts the slider behind the platform joint along k" in slider
