"""Griffe extension of the parakin docs: parakin's docstrings start a list on the line after its
introduction ("checked for\\n- a crossing ..."), as plain text reads well, but Markdown needs a
blank line before a list or it runs the items into the paragraph. This inserts that blank line
when the docstrings are loaded for the API reference; the sources are unchanged."""

from __future__ import annotations

import re
from typing import Any

import griffe

ITEM = re.compile(r"^\s*([-*]|\d+\.) ")


def blank_before_lists(text: str) -> str:
    """``text`` with a blank line before every list item that follows a line of prose."""
    lines = text.splitlines()
    out: list[str] = []
    in_list = False
    for line in lines:
        if ITEM.match(line):
            if out and out[-1].strip() and not in_list:
                out.append("")
            in_list = True
        elif not line.strip():
            in_list = False
        out.append(line)
    return "\n".join(out)


class BlankLineBeforeLists(griffe.Extension):
    def on_object(self, *, obj: griffe.Object, loader: griffe.GriffeLoader, **kwargs: Any) -> None:
        if obj.docstring is not None:
            obj.docstring.value = blank_before_lists(obj.docstring.value)
