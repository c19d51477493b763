"""``parakin inspect``: every symbol a report prints is defined, matrices print as labelled
matrices, the JSON reads back to the very objects of ``parakin.symbolic``, and the LaTeX
report is a document that compiles."""

import json
import math
import shutil
import subprocess
from functools import cache

import pytest
import sympy as sp

import parakin
from parakin.interfaces.inspect import POSE_INPUTS, _report, inspect

MECHANISMS = sorted(parakin.available())


@cache
def symbolic(name: str) -> dict:
    return parakin.symbolic(name)


def read_back(data: dict) -> dict:
    """The objects of an inspect JSON report, parsed as its module docstring says."""
    names = {d: sp.Symbol(s["name"], **s["assumptions"]) for d, s in data["symbols"].items()}
    shared: dict = {}
    for display, value in data["shared"]:
        shared[sp.Symbol(display)] = sp.parse_expr(value, local_dict=names).xreplace(shared)

    def parse(text: str):
        return sp.parse_expr(text, local_dict=names).xreplace(shared)

    objects = {}
    for key, item in data["objects"].items():
        if item["kind"] == "matrix":
            rows, columns = item["shape"]
            objects[key] = sp.Matrix(rows, columns, [parse(e) for row in item["entries"] for e in row])
        elif item["kind"] == "definitions":
            steps = [tuple(parse(part) for part in step) for step in item["steps"]]
            objects[key] = sp.Tuple(*(sp.Tuple(*step) for step in steps))
        else:
            objects[key] = parse(item["value"])
    return objects


@pytest.mark.parametrize("mechanism", MECHANISMS)
def test_json_reads_back_to_the_symbolic_objects_and_defines_every_symbol(mechanism):
    """Every object, parsed back from its strings, is structurally == the generated one; every
    free symbol is in the symbol table (a variable, a parameter, or described)."""
    name = mechanism
    data = json.loads(inspect(name, "json"))
    assert data["schema"] == "parakin.interfaces.inspect/1" and data["manifest"] == name
    original = symbolic(name)
    back = read_back(data)
    assert set(back) == set(original)
    for key, value in original.items():
        assert back[key] == value, f"{name} {key} does not read back"
    table = {sp.Symbol(s["name"], **s["assumptions"]) for s in data["symbols"].values()}
    used = set().union(*(v.free_symbols for v in original.values()))
    assert used <= table, sorted(map(str, used - table))
    manifest = parakin.metadata(name)
    kinds = {s["kind"] for s in data["symbols"].values()}
    assert "other" not in kinds  # nothing left to "defined by the mechanism file"
    for variable in manifest.actuated:
        assert data["symbols"][variable.name]["unit"] == variable.unit
    for parameter in manifest.parameters:
        if parameter.name in data["symbols"]:
            assert data["symbols"][parameter.name]["value"] == parameter.default


@pytest.mark.parametrize("mechanism", MECHANISMS)
def test_text_defines_every_symbol_it_prints(mechanism):
    """Each symbol of the report that is not a variable or a parameter is listed under "other
    symbols" with what it is, and each step target is printed as `name = ...`."""
    name = mechanism
    report = _report(name)
    text = inspect(name)
    header, _, body = text.partition("\n== ")
    printed = set()
    for section in report.sections:
        value = report.objects[section.key]
        items = [value]
        if hasattr(value, "shape"):
            items = list(value)
        elif isinstance(value, sp.Tuple):
            items = [part for step in value for part in step]
        printed |= set().union(*(getattr(e, "free_symbols", set()) for e in items))
    shown = {entry.symbol for entry in report.symbols.values()}
    assert printed <= shown, sorted(map(str, printed - shown))
    listed = header.split("other symbols:\n", 1)[1] if "other symbols:" in header else ""
    for display, entry in report.symbols.items():
        if entry.kind in ("actuated", "passive"):  # with its home value, or its unit where it has none
            assert f" {display} = " in header or f" {display} [" in header, display
        elif entry.kind == "parameter":
            assert f"{display} = " in header
        else:
            assert display in listed.replace("\n    ", " "), f"{name}: {display} ({entry.kind}) is not defined"
    for key in ("inverse_steps", "forward_auxiliary"):
        for target, _ in report.objects.get(key, ()):
            assert f"\n{target} = " in body


def test_pose_inputs_are_the_generators():
    from parakin.generator.model import POSE_SYMBOLS

    assert tuple(map(str, POSE_SYMBOLS)) == POSE_INPUTS


def test_sam_forward_polynomial_helpers_are_defined():
    """The issue's example: a_lin, c_lin, line_norm2 in sam's forward polynomial."""
    text = inspect("sam", width=10**4, lines=10**4)
    for helper in ("a_lin", "c_lin", "line_norm2"):
        assert f"\n{helper} = " in text
        assert f"{helper}" in text.split("other symbols:", 1)[1].split("\n== ", 1)[0]


def test_sps_name_clash_is_told_apart():
    """sps: the parameter b12 (|B1 B2|) and the forward auxiliary b12 are different symbols."""
    data = json.loads(inspect("sps", "json"))
    assert data["symbols"]["b12"]["kind"] == "parameter"
    assert data["symbols"]["b12_fwd"]["name"] == "b12" and data["symbols"]["b12_fwd"]["kind"] == "defined"
    assert "b12_fwd" in data["objects"]["forward_polynomial"]["value"]


def test_matrices_print_as_matrices_with_labels():
    """stewart's B = diag(l) is a grid with the actuated names over its columns; A is listed
    entry by entry, labelled (equation, twist component); sam's leg Jacobian rows are (v, w)."""
    text = inspect("stewart", width=100)
    b = text.split("== B (columns: the actuated rates)\n", 1)[1].split("\n\n", 1)[0].splitlines()
    assert b[0].split() == ["l1", "l2", "l3", "l4", "l5", "l6"]
    assert b[1].split() == ["[0]", "l1", "0", "0", "0", "0", "0"] and len(b) == 7
    a = text.split("== A of A twist", 1)[1].split("\n== ", 1)[0]
    assert "\n[0, vx] " in a and "\n[5, wz] " in a and "[35]" not in a
    sam = inspect("sam", width=100)
    assert "\n[wz, phi3] " in sam.split("== Leg Jacobian left", 1)[1]


def test_latex_is_one_document_that_compiles(tmp_path):
    """A complete document (five_bar); stewart's stays under 1 MB; pdflatex compiles it."""
    document = inspect("five_bar", "latex")
    assert document.startswith("\\documentclass") and document.rstrip().endswith("\\end{document}")
    assert "==" not in document and "\\begin{document}" in document
    assert len(inspect("stewart", "latex").encode()) < 10**6
    if shutil.which("pdflatex") is None:
        pytest.skip("pdflatex is not installed")
    (tmp_path / "five_bar.tex").write_text(document)
    done = subprocess.run(
        ["pdflatex", "-interaction=nonstopmode", "-halt-on-error", "five_bar.tex"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stdout[-2000:]
    assert (tmp_path / "five_bar.pdf").stat().st_size > 1000


def test_the_header_states_the_platforms_motion_with_the_controlled_coordinates(capsys):
    """``parakin inspect prs3`` (the command line, text and JSON): the header's motion line is the
    manifest's joints.motion.text, read here from manifest.json with json, and names the
    coordinates the actuators control (height and tilt) and the parasitic ones; a package
    without a screw analysis (sphere2r) prints none and its JSON says null."""
    from parakin.interfaces.cli import main
    from parakin.packages.package import GeneratedPackage

    manifest = json.loads((GeneratedPackage.find("prs3").path / "manifest.json").read_text())
    expected = manifest["joints"]["motion"]["text"]
    assert "controlled: the height p . k and the tilt n = R^T k" in expected and "parasitic: " in expected
    assert main(["inspect", "prs3"]) == 0
    header = capsys.readouterr().out.partition("\n== ")[0].splitlines()
    start = [k for k, line in enumerate(header) if line.startswith("motion: ")]
    assert len(start) == 1, header
    wrapped = [header[start[0]]]
    for line in header[start[0] + 1 :]:
        if not line.startswith("    "):
            break
        wrapped.append(line[4:])
    assert max(len(line) for line in header[start[0] : start[0] + len(wrapped)]) <= 100
    assert " ".join(wrapped) == f"motion: {expected}"
    assert main(["inspect", "prs3", "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out)["motion"] == expected
    assert "\nmotion: " not in inspect("sphere2r").partition("\n== ")[0]
    assert json.loads(inspect("sphere2r", "json"))["motion"] is None


def _home_line(header: list[str], title: str) -> dict[str, tuple[float, str]]:
    """``name: (value, unit)`` from the header's ``TITLE (at home): ...`` line and its continuations."""
    import re

    start = next(k for k, line in enumerate(header) if line.startswith(f"{title} (at home): "))
    text = header[start].partition(": ")[2]
    for line in header[start + 1 :]:
        if not line.startswith("    "):
            break
        text += " " + line.strip()
    found = {}
    for part in text.split(", "):
        match = re.fullmatch(r"(\w+) = (\S+)(?: (m|rad))?(?: \((\S+) deg\))?", part)
        assert match is not None, part
        found[match[1]] = (float(match[2]), match[3] or "")
        if match[4] is not None:  # a revolute value is also given in degrees: the same angle
            assert abs(float(match[4]) - math.degrees(float(match[2]))) < 1e-3, part
    return found


def test_the_header_gives_the_home_configuration_with_units(capsys):
    """``parakin inspect NAME`` once named the variables without their home values. Now the header
    gives the home configuration, actuated and passive, each value with its unit (a revolute one
    also in degrees). Checked by hand geometry at the printed digits (6 significant): the
    five-bar's home P = (0, 0.33) m with the distal links b = 0.25 m from the elbows
    A_i + a (cos theta_i, sin theta_i), A_i = (-+0.15, 0), a = 0.2 m; the 3-PRS at z = 0.6 m, no
    tilt, each rail at d = 0.6 - sqrt(0.35^2 - (0.2 - 0.1)^2) m; the JSON gives the same homes."""
    from parakin.interfaces.cli import main

    assert main(["inspect", "five_bar"]) == 0
    header = capsys.readouterr().out.partition("\n== ")[0].splitlines()
    actuated, passive = _home_line(header, "actuated"), _home_line(header, "passive")
    assert set(actuated) == {"theta1", "theta2"} and {u for _, u in actuated.values()} == {"rad"}
    assert passive == {"x": (0.0, "m"), "y": (0.33, "m")}
    for (theta, _), base in zip(actuated.values(), (-0.15, 0.15), strict=True):
        elbow = (base + 0.2 * math.cos(theta), 0.2 * math.sin(theta))
        assert abs(math.dist(elbow, (0.0, 0.33)) - 0.25) < 1e-5, theta

    assert main(["inspect", "prs3"]) == 0
    header = capsys.readouterr().out.partition("\n== ")[0].splitlines()
    rail = 0.6 - math.sqrt(0.35**2 - 0.1**2)
    actuated = _home_line(header, "actuated")
    assert set(actuated) == {"d1", "d2", "d3"} and all(u == "m" and abs(d - rail) < 1e-5 for d, u in actuated.values())
    assert _home_line(header, "passive") == {
        "x": (0.0, "m"), "y": (0.0, "m"), "z": (0.6, "m"), "q0": (1.0, ""), "q1": (0.0, ""), "q2": (0.0, ""), "q3": (0.0, "")
    }  # fmt: skip
    symbols = json.loads(inspect("prs3", "json"))["symbols"]
    assert abs(symbols["d1"]["home"] - rail) < 1e-12 and symbols["z"]["home"] == 0.6
    assert all(len(line) <= 100 for line in header if "(at home): " in line or line.startswith("    "))
