"""The cache ($PARAKIN_CACHE) is trusted only when it is private (issue 31, items 8, 12 and 15).

A compiled library runs its code inside the process that loads it, and a start-system record
sets a proven root count, so neither is taken from a folder (or file) that another user owns or
can write: the compiled backend raises UntrustedCacheError there ('auto' falls back to NumPy
saying why) and the generator ignores the record and computes the start systems again. A library
under the cache's name that lacks the package's symbols is a StaleLibraryError, not a raw
AttributeError. A compile killed with SIGKILL leaves a scratch file named with its host and
process id; the next compile removes it (and only files named that way).

The tests run as root in CI: "another user" is a folder or file chowned to another uid (skipped
where the process cannot chown)."""

from __future__ import annotations

import json
import logging
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import parakin
from parakin.errors import BackendFallbackWarning, CacheUnavailableError, StaleLibraryError, UntrustedCacheError
from parakin.packages import compiled

SOURCE = "sphere2r"  # the smallest package: quick to compile
OTHER_UID = 4242  # no user of this machine: "another local user"
COMPILER = shutil.which(os.environ.get("CC", "cc"))
pytestmark = pytest.mark.skipif(COMPILER is None, reason="no C compiler")
as_root = pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() != 0, reason="chown needs root")

PLANTED = r"""
#include <stdio.h>
/* what another user would plant: code that runs as soon as the library is loaded */
__attribute__((constructor)) static void planted(void) {
    FILE *marker = fopen("%(marker)s", "w");
    if (marker) { fputs("ran\n", marker); fclose(marker); }
}
int unrelated_function(void) { return 42; }
"""


@pytest.fixture(scope="module")
def library_name(tmp_path_factory) -> str:
    """The file name the cache expects for SOURCE's library (compiled once, privately)."""
    cache = tmp_path_factory.mktemp("private") / "cache"
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("PARAKIN_CACHE", str(cache))
        library = Path(parakin.load(SOURCE, backend="compiled").backend.path)
    assert library.parent == cache
    return library.name


@pytest.fixture(scope="module")
def reference():
    m = parakin.load(SOURCE, backend="numpy")
    inputs = np.deg2rad([30.0, 50.0])
    return inputs, m.forward_pose(inputs).pose


def plant(path: Path, marker: Path | None = None) -> None:
    """A shared library at ``path`` with none of the package's symbols (a constructor that writes
    ``marker`` when given)."""
    source = path.parent.parent / f"{path.name}.c"
    source.write_text(PLANTED % {"marker": marker} if marker else "int unrelated_function(void) { return 42; }\n")
    subprocess.run([COMPILER, "-shared", "-fPIC", str(source), "-o", str(path)], check=True)
    source.unlink()
    path.chmod(0o755)


def falls_back(reference, match: str) -> None:
    """Backend 'auto' warns with ``match`` and runs on NumPy with NumPy's results."""
    inputs, pose = reference
    with pytest.warns(BackendFallbackWarning, match=match):
        m = parakin.load(SOURCE, backend="auto")
    assert m.backend.name == "numpy"
    np.testing.assert_array_equal(m.forward_pose(inputs).pose, pose)


def hostile_caches(tmp_path: Path, library_name: str):
    """(case, cache folder, what makes it hostile, the regex the error must match)."""
    cases = []
    for case, mode in [("world-writable", 0o777), ("group-writable", 0o775), ("sticky world-writable", 0o1777)]:
        cache = tmp_path / case.replace(" ", "_")
        cache.mkdir()
        cases.append(
            (case, cache, lambda c, m=mode: c.chmod(m), rf"{re.escape(str(cache))} is writable by .*chmod go-w")
        )
    cache = tmp_path / "open" / "cache"
    cache.mkdir(parents=True)
    cases.append(
        ("in a folder anyone may write", cache, lambda c: c.parent.chmod(0o777), r"open, which anyone may write")
    )
    cache = tmp_path / "library_writable"
    cache.mkdir()
    cases.append(
        ("a library others may write", cache, lambda c: (c / library_name).chmod(0o666), r"\.so is writable by")
    )
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        cache = tmp_path / "foreign"
        cache.mkdir()
        cases.append(("another user's", cache, lambda c: os.chown(c, OTHER_UID, OTHER_UID), r"belongs to .*uid 4242"))
        cache = tmp_path / "foreign_library"
        cache.mkdir()
        cases.append(
            (
                "another user's library",
                cache,
                lambda c: os.chown(c / library_name, OTHER_UID, OTHER_UID),
                r"\.so belongs to .*uid 4242",
            )
        )
    return cases


def test_a_library_planted_in_a_cache_others_can_write_is_never_loaded(tmp_path, monkeypatch, library_name, reference):
    """Item 8: another user plants NAME-<hash>.so in a shared cache; its constructor ran in our
    process at load. Now a cache folder (or library) that another user owns or can write, or that
    lies in a folder anyone can rename in, is an UntrustedCacheError naming the folder, what is
    wrong and what to do; 'auto' falls back to NumPy; the planted code never runs."""
    for case, cache, make_hostile, reason in hostile_caches(tmp_path, library_name):
        marker = tmp_path / f"{cache.name}.ran"
        plant(cache / library_name, marker)
        make_hostile(cache)
        monkeypatch.setenv("PARAKIN_CACHE", str(cache))
        before = sorted(cache.iterdir())
        with pytest.raises(UntrustedCacheError, match=r"(?s)cache .* is not private: .*" + reason) as raised:
            parakin.load(SOURCE, backend="compiled")
        assert "PARAKIN_CACHE" in str(raised.value), case
        falls_back(reference, "on NumPy.*UntrustedCacheError")
        assert not marker.exists(), f"{case}: the planted constructor ran"
        assert sorted(cache.iterdir()) == before, f"{case}: something was written into an untrusted cache"
    assert issubclass(UntrustedCacheError, CacheUnavailableError)


def test_a_cache_others_can_write_gets_no_new_library_either(tmp_path, monkeypatch, reference):
    """An empty world-writable cache is refused before the compiler runs: a library compiled
    into it could be swapped before it is loaded."""
    cache = tmp_path / "shared"
    cache.mkdir()
    cache.chmod(0o777)
    monkeypatch.setenv("PARAKIN_CACHE", str(cache))
    with pytest.raises(
        UntrustedCacheError, match=r"shared is writable by its group and others \(mode 0777; `chmod go-w "
    ):
        parakin.load(SOURCE, backend="compiled")
    falls_back(reference, "UntrustedCacheError")
    assert list(cache.iterdir()) == []


def test_a_new_cache_is_private(tmp_path, monkeypatch):
    """The folder parakin creates is the user's alone (mode 0700) and its library not writable
    by others, whatever the umask: the next load trusts what this one wrote."""
    cache = tmp_path / "new" / "cache"
    monkeypatch.setenv("PARAKIN_CACHE", str(cache))
    previous = os.umask(0o002)
    try:
        library = Path(parakin.load(SOURCE, backend="compiled").backend.path)
    finally:
        os.umask(previous)
    assert cache.stat().st_mode & 0o777 == 0o700
    assert library.stat().st_mode & 0o022 == 0
    assert compiled.distrust(cache) is None and compiled.distrust(library) is None
    assert parakin.load(SOURCE, backend="compiled").backend.path == library


def test_a_library_without_the_packages_symbols_is_a_named_error(tmp_path, monkeypatch, library_name, reference):
    """Item 12: a stale or foreign library under the cache's name (in a private cache) raised a
    raw AttributeError even with backend 'auto'. Now it is a StaleLibraryError naming the file
    and the missing symbols and saying to delete it; 'auto' falls back to NumPy."""
    cache = tmp_path / "cache"
    cache.mkdir()
    plant(cache / library_name)
    monkeypatch.setenv("PARAKIN_CACHE", str(cache))
    library = re.escape(str(cache / library_name))
    with pytest.raises(StaleLibraryError, match=rf"(?s){library} lacks .* symbols .*sphere2r_.*delete it"):
        parakin.load(SOURCE, backend="compiled")
    falls_back(reference, "on NumPy.*StaleLibraryError")
    assert issubclass(StaleLibraryError, CacheUnavailableError)
    # deleted, it is rebuilt by the next process (this one keeps the library it has loaded)
    (cache / library_name).unlink()
    inputs, pose = reference
    code = (
        f"import numpy as np, parakin; m = parakin.load({SOURCE!r}, backend='compiled'); "
        f"print(np.abs(m.forward_pose({inputs.tolist()}).pose - np.array({pose.tolist()})).max())"
    )
    environment = {**os.environ, "PARAKIN_CACHE": str(cache), "PARAKIN_LOG": "warning"}
    done = subprocess.run([sys.executable, "-c", code], env=environment, capture_output=True, text=True, check=True)
    assert float(done.stdout) < 1e-12 and (cache / library_name).is_file()


def test_a_compile_killed_with_sigkill_leaves_nothing_after_the_next_compile(tmp_path, monkeypatch):
    """Item 15: a first compile killed with SIGKILL left its scratch library in the cache
    forever. Now the scratch file names the compile's host and process, and the next compile
    removes it once that process is gone."""
    cache = tmp_path / "cache"
    slow = tmp_path / "slow_cc"
    slow.write_text(f'#!/bin/sh\nsleep 60\nexec {COMPILER} "$@"\n')
    slow.chmod(0o755)
    environment = {**os.environ, "PARAKIN_CACHE": str(cache), "CC": str(slow), "PARAKIN_LOG": "warning"}
    process = subprocess.Popen(
        [sys.executable, "-c", f"import parakin; parakin.load({SOURCE!r}, backend='compiled')"],
        env=environment,
        start_new_session=True,  # its own process group: the kill takes the compiler with it
    )
    deadline = time.monotonic() + 30
    while not (cache.is_dir() and any(cache.iterdir())):
        assert process.poll() is None and time.monotonic() < deadline, "the compile never started"
        time.sleep(0.01)
    os.killpg(process.pid, signal.SIGKILL)
    process.wait()
    left = [p.name for p in cache.iterdir()]
    assert len(left) == 1 and not left[0].endswith(".so"), left  # the killed compile's scratch file
    monkeypatch.setenv("PARAKIN_CACHE", str(cache))
    library = Path(parakin.load(SOURCE, backend="compiled").backend.path)
    assert [p.name for p in cache.iterdir()] == [library.name]


def test_only_scratch_files_of_dead_compiles_are_removed(tmp_path, monkeypatch):
    """The next compile removes a scratch library of this host whose process is gone, and any
    parakin scratch file (the old mkstemp names too) older than a day; a live compile's, another
    machine's recent one, and every file or folder parakin does not name that way stay."""
    cache = tmp_path / "cache"
    cache.mkdir()
    finished = subprocess.Popen(["true"])
    finished.wait()
    dead = finished.pid  # a process that has exited (and been reaped)
    host = compiled.host_tag()
    library = "five_bar-0123456789abcdef.so"
    day_old = time.time() - 2 * compiled.STALE_SCRATCH_AGE
    removed = {
        f"{library}.{host}.{dead}.k3j_x9ab.partial": None,  # its compile was killed
        f"{library}.elsewhere-1.{dead}.abcdefgh.partial": day_old,  # another machine's, a day old
        f"{library}.{host}.{os.getpid()}.abcdefgh.partial": day_old,  # a day old: the pid was reused
        "tmpk3j_x9ab.so": day_old,  # the scratch name before the host and pid were in it
    }
    kept = {
        f"{library}.{host}.{os.getpid()}.k3j_x9ab.partial": None,  # a live compile (this process)
        f"{library}.elsewhere-1.{dead}.k3j_x9ab.partial": None,  # another machine's, recent
        "tmpzzzzzzzz.so": None,  # an old-style scratch file, recent: perhaps an older parakin compiling
        "notes.txt": day_old,
        "mine.so": day_old,
        "tmpabc.so": day_old,
        "tmpk3j_x9ab.so.bak": day_old,
        f"{library}.partial": day_old,
        f"{library}.{host}.{dead}.partial": day_old,
        f"five_bar.so.{host}.{dead}.abcdefgh.partial": day_old,
    }
    for name, when in {**removed, **kept}.items():
        (cache / name).write_text("scratch\n")
        if when is not None:
            os.utime(cache / name, (when, when))
    folder = cache / f"{library}.{host}.{dead}.abcdefgh.partial"  # a folder, not a scratch file
    folder.mkdir()
    monkeypatch.setenv("PARAKIN_CACHE", str(cache))
    library_path = Path(parakin.load(SOURCE, backend="compiled").backend.path)
    names = {p.name for p in cache.iterdir()}
    assert names == {library_path.name, folder.name} | set(kept), names ^ ({library_path.name, folder.name} | set(kept))


# ---------------------------------------------------------------- start-system records


def toy_family():
    """x^2 + y^2 = p, x y = r: four solutions, the pair (z, -z) twice; seconds to prove."""
    from parakin.generator.polynomial_form import PolynomialForm

    x, y, p, r = sp.symbols("x y p r")
    form = PolynomialForm([x, y], [x**2 + y**2 - p, x * y - r], [(p, p), (r, r)], [x, y])
    return form, list(form.equations)


def start_systems(**patches):
    from parakin.generator import start_systems as homotopy

    form, equations = toy_family()
    with pytest.MonkeyPatch.context() as patch:
        for name, value in patches.items():
            patch.setattr(homotopy, name, value)
        return homotopy.start_systems("toy_cache_trust", form, equations, 2026, "automatic")[1]


def shrunk(record: dict) -> dict:
    """The record with one sign pair of its four solutions: it passes every check of the record's
    content (the solutions solve the instance and are closed under z -> -z), and its forged proof
    claims two roots."""

    def one_pair(rows: list) -> list:
        first = np.array([complex(*c) for c in rows[0]])
        return [row for row in rows if np.abs(np.array([complex(*c) for c in row]) ** 2 - first**2).max() < 1e-9]

    forged = {key: record[key] for key in ("instance", "second_instance")}
    forged["solutions"] = one_pair(record["solutions"])
    forged["second_solutions"] = one_pair(record["second_solutions"])
    assert len(forged["solutions"]) == len(forged["second_solutions"]) == 2
    forged["proof"] = {
        **record["proof"],
        "method": "total-degree homotopy (2 independent runs of 4 paths, regular endpoints 2, 2)",
        "regular_endpoints": [2, 2],
    }
    return forged


@pytest.fixture(scope="module")
def toy_record(tmp_path_factory) -> dict:
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("PARAKIN_CACHE", str(tmp_path_factory.mktemp("toy") / "cache"))
        record = start_systems()
    assert len(record["solutions"]) == 4 and record["proof"]["proven"]
    return record


def hostile_records(tmp_path: Path):
    """(case, cache root, how to make the planted record untrusted)."""
    cases = []
    for case in ["world-writable cache", "world-writable folder", "writable record", "no family key", "wrong key"]:
        cases.append((case, tmp_path / case.replace(" ", "_")))
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        cases += [(case, tmp_path / case.replace(" ", "_")) for case in ["foreign folder", "foreign record"]]
    return cases


def test_a_planted_start_system_record_cannot_shrink_the_root_count(tmp_path, monkeypatch, toy_record):
    """Item 8: a record planted in $PARAKIN_CACHE/homotopy with fewer solutions and a forged proof
    passed every content check and became the proven root count. Now a record is used only from a
    folder and file this user owns and no one else can write, naming the family it is for; any
    other is ignored and the start systems computed again (4 roots, proven)."""
    from parakin.generator import start_systems as homotopy

    key = toy_record["key"]
    for case, root in hostile_records(tmp_path):
        folder = root / "homotopy"
        folder.mkdir(parents=True)
        planted = shrunk(toy_record)
        if case != "no family key":
            planted["family_key"] = key if case != "wrong key" else "0" * 64
        path = folder / f"{key}.json"
        path.write_text(json.dumps(planted))
        path.chmod(0o644)
        if case == "world-writable cache":
            root.chmod(0o777)
        elif case == "world-writable folder":
            folder.chmod(0o777)
        elif case == "writable record":
            path.chmod(0o666)
        elif case == "foreign folder":
            os.chown(folder, OTHER_UID, OTHER_UID)
        elif case == "foreign record":
            os.chown(path, OTHER_UID, OTHER_UID)
        monkeypatch.setenv("PARAKIN_CACHE", str(root))
        assert homotopy._cache_path(key) == path
        record = start_systems()
        assert len(record["solutions"]) == 4, f"{case}: the planted record was trusted"
        assert record["proof"]["regular_endpoints"] == [4, 4], case


def test_a_record_parakin_wrote_is_reused_and_private(tmp_path, monkeypatch, toy_record):
    """The record the generator stores names its family and is private (folder 0700, file not
    writable by others, whatever the umask); the next build reuses it without recomputing."""
    from parakin.generator import start_systems as homotopy

    root = tmp_path / "cache"
    monkeypatch.setenv("PARAKIN_CACHE", str(root))
    previous = os.umask(0o002)
    try:
        first = start_systems()
    finally:
        os.umask(previous)
    path = homotopy._cache_path(first["key"])
    assert json.loads(path.read_text())["family_key"] == first["key"]
    assert (root.stat().st_mode & 0o777, path.parent.stat().st_mode & 0o777) == (0o700, 0o700)
    assert path.stat().st_mode & 0o022 == 0
    assert [p.name for p in path.parent.iterdir()] == [path.name]  # no partial file left

    def recompute(*arguments):
        raise AssertionError("the stored record was not reused")

    again = start_systems(_start_instance=recompute)
    assert again["solutions"] == first["solutions"] and again["proof"] == first["proof"]
    assert "family_key" not in again


def test_an_untrusted_cache_is_not_written_by_the_generator(tmp_path, monkeypatch, caplog):
    """The generator stores no record in a cache folder others can write (it would not be read
    back) and says so; it still returns the start systems."""
    root = tmp_path / "shared"
    root.mkdir()
    root.chmod(0o777)
    monkeypatch.setenv("PARAKIN_CACHE", str(root))
    logger = logging.getLogger("parakin")
    logger.addHandler(caplog.handler)  # the parakin logger does not propagate to the root logger
    try:
        record = start_systems()
    finally:
        logger.removeHandler(caplog.handler)
    assert len(record["solutions"]) == 4
    assert list(root.iterdir()) == []
    assert any("not stored" in message and str(root) in message for message in caplog.messages)
