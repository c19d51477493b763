"""What a manifest names is checked when it is read: names are identifiers and file entries are
plain file names inside the package folder, so neither the compiled-library cache nor
`parakin export` can be steered outside the folders they were given (issue 18, item 13).

Each test copies a generated package into a temporary folder and edits its manifest.json."""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import parakin
from parakin.packages.manifest import Manifest
from parakin.packages.package import GeneratedPackage

SOURCE = "sphere2r"  # the smallest package: quick to compile


def crafted(tmp_path: Path, edit, folder: str = "crafted") -> Path:
    """A copy of a generated package whose manifest ``edit(data)`` changed in place."""
    package = tmp_path / "packages" / folder
    shutil.copytree(GeneratedPackage.find(SOURCE).path, package)
    path = package / "manifest.json"
    data = json.loads(path.read_text())
    edit(data)
    path.write_text(json.dumps(data))
    return package


def files_under(folder: Path) -> set[Path]:
    return {p for p in folder.rglob("*") if p.is_file() or p.is_symlink()}


def set_name(value):
    def edit(data):
        data["name"] = value

    return edit


@pytest.mark.parametrize("name", ["../../x", "a/b", "", "x y", "/tmp/x", "x;rm -rf", 5, None])
def test_a_manifest_name_that_is_no_identifier_is_refused(tmp_path, name):
    """A manifest name ``../../x`` once put the compiled library two folders above
    $PARAKIN_CACHE; now reading the manifest refuses it, naming the field."""
    package = crafted(tmp_path, set_name(name))
    with pytest.raises(parakin.BadInputError, match=r"field name: .* is not a name"):
        Manifest.read(package / "manifest.json")


def test_the_compiled_library_stays_inside_the_cache(tmp_path, monkeypatch):
    """With the manifest name ``../../x`` and backend 'compiled', nothing is written anywhere:
    the load fails on the manifest before the compiler runs (at 6bfa97b it wrote
    tmp/x-<hash>.so outside tmp/a/b/cache)."""
    cache = tmp_path / "a" / "b" / "cache"
    monkeypatch.setenv("PARAKIN_CACHE", str(cache))
    package = crafted(tmp_path, set_name("../../x"))
    before = files_under(tmp_path)
    with pytest.raises(parakin.BadInputError, match="field name"):
        parakin.load(package, backend="compiled")
    assert files_under(tmp_path) == before
    # the same package with a valid name builds its library inside the cache, and only there
    (package / "manifest.json").write_text((package / "manifest.json").read_text().replace("../../x", "renamed"))
    m = parakin.load(package, backend="compiled")
    library = Path(m.backend.path)
    assert library.parent == cache and library.name.startswith("renamed-")
    assert {p for p in files_under(tmp_path) - before} == {library}


def header_entry(value):
    def edit(data):
        data["c"]["headers"].append(value)

    return edit


def source_entry(value):
    def edit(data):
        data["c"]["sources"][0] = value

    return edit


@pytest.mark.parametrize("edit", [header_entry, source_entry])
@pytest.mark.parametrize("entry", ["../../escaped.h", "sub/escaped.h", "/tmp/escaped.h", "..", "", "a\\b.h"])
def test_export_writes_only_inside_out(tmp_path, edit, entry):
    """Entries of c.headers / c.sources once made `parakin export` write outside --out (a
    header ``../../escaped.h`` landed two folders up). Now the manifest is refused when read:
    the CLI exits 2 naming the field, and no file appears outside --out (nor inside it)."""
    package = crafted(tmp_path, edit(entry))
    (package / "escaped.h").write_text("/* planted */\n")
    out = tmp_path / "deep" / "er" / "out"
    before = files_under(tmp_path)
    done = subprocess.run(
        [sys.executable, "-W", "ignore", "-m", "parakin.interfaces.cli", "export", str(package), "--out", str(out)],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 2, done.stderr
    field = "c.headers" if edit is header_entry else "c.sources"
    assert f"field {field}" in done.stderr and "not a plain file name" in done.stderr
    assert files_under(tmp_path) == before


def test_a_file_entry_that_links_out_of_the_folder_is_refused(tmp_path):
    """A plain file name that is a symbolic link to a file outside the package folder is refused
    (the C build would read it and export would copy it)."""
    package = crafted(tmp_path, lambda data: None)
    outside = tmp_path / "secret.h"
    outside.write_text("/* not the package's */\n")
    header = Manifest.read(package / "manifest.json").c_headers[0]
    (package / header).unlink()
    (package / header).symlink_to(outside)
    with pytest.raises(parakin.BadInputError, match=f"file '{header}' resolves outside the package folder"):
        parakin.load(package, backend="numpy")


def test_export_does_not_follow_a_link_in_the_out_folder(tmp_path):
    """A file of the export that already exists in --out as a symbolic link is refused, not
    written through (the link's target outside --out keeps its content)."""
    out = tmp_path / "out"
    out.mkdir()
    target = tmp_path / "precious.txt"
    target.write_text("keep me\n")
    (out / "README_C.md").symlink_to(target)
    with pytest.raises(parakin.BadInputError, match="symbolic link"):
        GeneratedPackage.find(SOURCE).export_c(out)
    assert target.read_text() == "keep me\n"
    written = GeneratedPackage.find(SOURCE).export_c(tmp_path / "fresh")
    assert all(p.parent == tmp_path / "fresh" and p.is_file() for p in written)


def edit_path(path: tuple, value):
    def edit(data):
        node = data
        for key in path[:-1]:
            node = node[key]
        node[path[-1]] = value

    return edit


@pytest.mark.parametrize(
    ("path", "value", "field"),
    [
        (("parameters", 0, "name"), "alpha 1", "parameters.name"),
        (("actuated", 0, "name"), "../theta", "actuated.name"),
        (
            ("passive",),
            [{"name": "x-y", "kind": "revolute", "unit": "rad", "home": 0, "limits": [None, None]}],
            "passive.name",
        ),
        (("kernels", 0, "c_symbol"), "f(); system", "kernels.c_symbol"),
        (("kernels", 0, "name"), "a.b", "kernels.name"),
        (("c", "newton", "symbol"), "x y", "c.newton.symbol"),
        (("c", "header"), "../sphere2r.h", "c.header"),
        (("pose_kind",), "teleport", "pose_kind"),
        (("singularity_factors",), "abc", "singularity_factors"),
    ],
)
def test_every_name_and_file_field_is_checked(tmp_path, path, value, field):
    package = crafted(tmp_path, edit_path(path, value))
    with pytest.raises(parakin.BadInputError, match=f"field {field}"):
        Manifest.read(package / "manifest.json")


@pytest.mark.parametrize(
    "edit",
    [
        lambda data: data.pop("kernels"),
        lambda data: data["capabilities"].pop("drawing"),
        lambda data: data["capabilities"]["drawing"]["parts"].update(arm="wheel"),
        lambda data: data["capabilities"]["drawing"]["parts"].pop("arm"),
        lambda data: data["capabilities"]["drawing"].update(fixed=["nowhere"]),
        lambda data: data.update(parameters=[{"name": "x"}]),
        lambda data: data.update(actuated=5),
        lambda data: data.clear(),
    ],
    ids=[
        "no kernels",
        "no drawing",
        "unknown part",
        "polyline without a part",
        "fixed set not drawn",
        "parameter without default",
        "actuated not a list",
        "empty",
    ],
)
def test_a_malformed_manifest_is_a_named_error(tmp_path, edit):
    """A malformed manifest once crashed with KeyError / TypeError; now `load` raises
    BadInputError naming the manifest file."""
    package = crafted(tmp_path, edit)
    with pytest.raises(parakin.BadInputError, match=f"manifest {package / 'manifest.json'}"):
        parakin.load(package, backend="numpy")


def test_a_broken_package_is_reported_named_and_skipped(tmp_path, monkeypatch):
    """`parakin list` once crashed on a package with a malformed manifest. Now it lists the
    others (exit 0) and names the broken one on stderr; available() skips it with a
    BrokenPackageWarning; load of it is a BadInputError; a good package beside it loads."""
    crafted(tmp_path, lambda data: data.pop("kernels"), folder="broken_one")
    (tmp_path / "packages" / "not_json").mkdir()
    (tmp_path / "packages" / "not_json" / "manifest.json").write_text("{ this is not json")
    crafted(tmp_path, lambda data: None, folder="good_copy")
    monkeypatch.setenv("PARAKIN_PATH", str(tmp_path / "packages"))
    with pytest.warns(parakin.BrokenPackageWarning) as caught:
        names = parakin.available()
    assert "good_copy" in names and "sam" in names
    assert "broken_one" not in names and "not_json" not in names
    messages = " ".join(str(w.message) for w in caught)
    assert "'broken_one'" in messages and "'kernels' is missing" in messages and "'not_json'" in messages
    with pytest.raises(parakin.BadInputError, match="'kernels' is missing"):
        parakin.load("broken_one")
    assert parakin.load("good_copy", backend="numpy").name == SOURCE
    done = subprocess.run(
        [sys.executable, "-m", "parakin.interfaces.cli", "list"], capture_output=True, text=True, env=dict(os.environ)
    )
    assert done.returncode == 0, done.stderr
    listed = [line.split()[0] for line in done.stdout.splitlines()]
    assert listed == sorted(set(names)) and "good_copy" in listed
    assert "skipped the package 'broken_one'" in done.stderr and "skipped the package 'not_json'" in done.stderr


def test_every_shipped_manifest_passes_the_checks():
    """The generator writes only what the reader accepts: every shipped package reads."""
    readable, broken = parakin.packages.package.survey()
    assert broken == {}
    assert set(readable) >= {"sam", "spm", "sphere2r"}


def test_readme_and_load_say_that_loading_runs_the_package_code():
    readme = (Path(__file__).resolve().parent.parent / "README.md").read_text()
    for text in (readme, parakin.load.__doc__ or "", parakin.__doc__ or ""):
        flat = " ".join(text.split())
        assert "runs its code" in flat and "load only packages you trust" in flat.lower(), text[:200]
