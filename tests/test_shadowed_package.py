"""A user's package named like another on the search path is not hidden silently (a new user's
``rps3`` on ``$PARAKIN_PATH`` loaded as the shipped rps3 with no word): loading by that name, and
``parakin.available()`` and ``parakin list``, say which folder is taken and which is hidden; the
hidden one loads by its folder path without a warning."""

from __future__ import annotations

import shutil
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

import parakin
from parakin.errors import ShadowedPackageWarning
from parakin.packages.package import GeneratedPackage

NAME = "sphere2r"  # the smallest shipped package


@pytest.fixture
def user_copy(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    shipped = GeneratedPackage.find(NAME).path
    copy = tmp_path / "mine" / NAME
    shutil.copytree(shipped, copy)
    monkeypatch.setenv("PARAKIN_PATH", str(tmp_path / "mine"))
    return copy


def test_loading_a_shadowed_name_says_which_folder_is_taken(user_copy: Path) -> None:
    with pytest.warns(ShadowedPackageWarning) as caught:
        m = parakin.load(NAME, backend="numpy")
    message = str(caught[0].message)
    assert str(user_copy) in message and str(m.package.path) in message and "hidden" in message
    assert m.package.path != user_copy.resolve()  # the shipped package comes first
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert parakin.load(str(user_copy), backend="numpy").package.path == user_copy.resolve()
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # once per process: a command loads a package many times
        parakin.load(NAME, backend="numpy")
        assert NAME in parakin.available()


def test_available_warns_too(user_copy: Path) -> None:
    with pytest.warns(ShadowedPackageWarning, match=str(user_copy)):
        assert NAME in parakin.available()


def test_parakin_list_names_the_hidden_package(user_copy: Path) -> None:
    done = subprocess.run([sys.executable, "-m", "parakin", "list"], capture_output=True, text=True)
    assert done.returncode == 0
    assert f"two packages are named '{NAME}'" in done.stderr and str(user_copy) in done.stderr
    assert done.stdout.count(f"{NAME} ") == 1


def test_no_warning_without_a_second_folder(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("PARAKIN_PATH", str(tmp_path))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        parakin.load(NAME, backend="numpy")
