"""The runtime's layout: no import circles among the modules of parakin/, counting every import
statement wherever it stands (module level, inside functions, under ``if TYPE_CHECKING``), and
a public API listed in ``parakin.__all__``."""

import ast
from pathlib import Path

import parakin

ROOT = Path(__file__).resolve().parent.parent
RUNTIME = ROOT / "parakin"


def _module_name(path: Path, root: Path) -> str:
    parts = path.relative_to(root.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def runtime_modules(root: Path = RUNTIME) -> dict[str, Path]:
    """Every module under ``root`` (a folder named parakin) by dotted name; a package is its
    ``__init__``."""
    return {_module_name(path, root): path for path in sorted(root.rglob("*.py")) if "__pycache__" not in path.parts}


def _imported(node: ast.AST, module: str, is_package: bool, modules: dict[str, Path]) -> list[str]:
    """The graph's modules that one import statement (or literal ``importlib.import_module``
    call) imports. ``from package import x`` imports the submodule x where there is one, and
    else the package, which defines x. Modules outside the graph (numpy, the generator, the
    generated packages) are left out, and so are the enclosing packages an import runs first."""
    if isinstance(node, ast.Import):
        return [alias.name for alias in node.names if alias.name in modules]
    if isinstance(node, ast.ImportFrom):
        if node.level:  # relative: from the module's own package, one level up per extra dot
            package = module if is_package else module.rpartition(".")[0]
            for _ in range(node.level - 1):
                package = package.rpartition(".")[0]
            base = f"{package}.{node.module}" if node.module else package
        else:
            base = node.module or ""
        names = [f"{base}.{alias.name}" for alias in node.names]
        return [name if name in modules else base for name in names if name in modules or base in modules]
    if (
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Attribute | ast.Name)
        and (node.func.attr if isinstance(node.func, ast.Attribute) else node.func.id)
        in ("import_module", "__import__")
        and node.args
        and isinstance(node.args[0], ast.Constant)
        and isinstance(node.args[0].value, str)
    ):
        return [node.args[0].value] if node.args[0].value in modules else []
    return []


def import_graph(root: Path = RUNTIME) -> dict[str, set[str]]:
    """Module -> the modules it imports, over every module under ``root``: every import statement
    in its syntax tree counts, at any depth."""
    modules = runtime_modules(root)
    graph: dict[str, set[str]] = {}
    for module, path in modules.items():
        tree = ast.parse(path.read_text(), str(path))
        is_package = path.name == "__init__.py"
        graph[module] = {
            target
            for node in ast.walk(tree)
            for target in _imported(node, module, is_package, modules)
            if target != module or not is_package
        }
    return graph


def components(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components that hold a circle (Tarjan): modules that import each
    other, directly or through others; each sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []

    def visit(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for nxt in sorted(graph.get(node, ())):
            if nxt not in index:
                visit(nxt)
                low[node] = min(low[node], low[nxt])
            elif nxt in on_stack:
                low[node] = min(low[node], index[nxt])
        if low[node] == index[node]:
            component = []
            while True:
                top = stack.pop()
                on_stack.discard(top)
                component.append(top)
                if top == node:
                    break
            if len(component) > 1 or node in graph.get(node, ()):
                found.append(sorted(component))

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return found


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Per module in a circle, a shortest circle through it, written a -> b -> ... -> a (each
    circle once): every module that takes part shows up in one."""
    found: list[list[str]] = []
    for component in components(graph):
        for start in component:
            circle = _circle(graph, set(component), start)
            if not any(set(circle) == set(other) and len(circle) == len(other) for other in found):
                found.append(circle)
    return found


def _circle(graph: dict[str, set[str]], component: set[str], start: str) -> list[str]:
    """A shortest path start -> ... -> start inside one strongly connected component."""
    previous: dict[str, str] = {}
    frontier = [start]
    while frontier:
        following = []
        for node in frontier:
            for nxt in sorted(graph[node] & component):
                if nxt == start:
                    path = [node]
                    while path[-1] != start:
                        path.append(previous[path[-1]])
                    return [start, *reversed(path[:-1]), start] if node != start else [start, start]
                if nxt not in previous:
                    previous[nxt] = node
                    following.append(nxt)
        frontier = following
    raise AssertionError(f"{start} is in no circle of {sorted(component)}")


def test_the_runtime_has_no_import_circle():
    graph = import_graph()
    assert len(graph) >= 25 and "parakin.mechanism" in graph, sorted(graph)
    assert sum(len(targets) for targets in graph.values()) >= 80  # the edges were read
    found = cycles(graph)
    assert found == [], "import circles:\n" + "\n".join(" -> ".join(circle) for circle in found)


#: the runtime's parts, lowest first: the foundation (errors, log, validation, pose, results,
#: tables: the other top-level modules), the generated packages, the solvers, then what is built
#: on them: the Mechanism with parakin.load (the facade), design studies and interfaces
LOWER_PARTS = ("foundation", "packages", "solvers")
#: the model's facade and the algorithms over a loaded mechanism beside it (dynamics, the MJCF
#: export, the MuJoCo bridge, the distances to singularity), which the Mechanism's methods call
FACADE = {
    "parakin",
    "parakin.__main__",
    "parakin.mechanism",
    "parakin.loading",
    "parakin.dynamics",
    "parakin.mjcf",
    "parakin.mujoco_bridge",
    "parakin.singularity",
}


def _part(module: str) -> str:
    parts = module.split(".")
    if len(parts) > 2 or (len(parts) == 2 and (RUNTIME / parts[1]).is_dir()):
        return parts[1]
    return "facade" if module in FACADE else "foundation"


def test_the_lower_parts_import_nothing_above_them():
    """The foundation imports only the foundation, packages/ the two of them, solvers/ the three:
    none of them knows the Mechanism, a study or an interface."""
    graph = import_graph()
    parts = {module: _part(module) for module in graph}
    assert set(parts.values()) == {*LOWER_PARTS, "facade", "studies", "calibration", "interfaces"}, parts
    rank = {part: LOWER_PARTS.index(part) if part in LOWER_PARTS else len(LOWER_PARTS) for part in parts.values()}
    upward = sorted(
        f"{module} ({parts[module]}) -> {target} ({parts[target]})"
        for module, targets in graph.items()
        for target in targets
        if parts[module] in LOWER_PARTS and rank[parts[target]] > rank[parts[module]]
    )
    assert upward == [], "\n".join(upward)
    assert sum(parts[m] in LOWER_PARTS for m in graph) >= 20


#: the facade's algorithms beside the Mechanism: built on the loaded mechanism alone, they serve
#: the studies and interfaces and import none of them (the Mechanism's own methods may: m.plot)
FACADE_ALGORITHMS = (
    "parakin.loading",
    "parakin.dynamics",
    "parakin.mjcf",
    "parakin.mujoco_bridge",
    "parakin.singularity",
)


def test_the_facades_algorithms_import_no_study_or_interface():
    """The MJCF export takes its near-singular measure from parakin.singularity, not from the
    plot interface; no algorithm beside the Mechanism imports a study, the calibration or an
    interface."""
    graph = import_graph()
    assert set(FACADE_ALGORITHMS) <= set(graph) and set(FACADE_ALGORITHMS) <= FACADE
    upward = sorted(
        f"{module} -> {target}"
        for module in FACADE_ALGORITHMS
        for target in graph[module]
        if _part(target) in ("studies", "calibration", "interfaces")
    )
    assert upward == [], "\n".join(upward)
    assert "parakin.singularity" in graph["parakin.mjcf"]  # the edges were read


def test_the_circle_finder_finds_circles(tmp_path):
    """The checker on a made-up runtime with the kinds of import it must see: a function-level
    import, one under TYPE_CHECKING, a relative one, ``from package import submodule``, and
    ``from parakin import name`` (the package's own name: no circle through it)."""
    root = tmp_path / "parakin"
    (root / "sub").mkdir(parents=True)
    files = {
        "__init__.py": "from parakin.a import f\n",
        "a.py": "def f():\n    from parakin.sub import b\n    return b\n",
        "sub/__init__.py": "",
        "sub/b.py": "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from .c import C\n",
        "sub/c.py": "from parakin import a\n",
        "d.py": "from parakin import f\n",
        "e.py": "import importlib\nimportlib.import_module('parakin.d')\n",
    }
    for name, text in files.items():
        (root / name).write_text(text)
    graph = import_graph(root)
    assert graph == {
        "parakin": {"parakin.a"},
        "parakin.a": {"parakin.sub.b"},
        "parakin.sub": set(),
        "parakin.sub.b": {"parakin.sub.c"},
        "parakin.sub.c": {"parakin.a"},
        "parakin.d": {"parakin"},
        "parakin.e": {"parakin.d"},
    }
    assert cycles(graph) == [["parakin.a", "parakin.sub.b", "parakin.sub.c", "parakin.a"]]
    assert cycles({"x": {"x"}}) == [["x", "x"]]
    assert cycles({"x": {"y"}, "y": set()}) == []


def test_the_public_api_is_what_all_lists():
    """Every name ``parakin`` binds (besides its submodules and dunders) is in ``__all__``, and
    every listed name resolves; ``parakin.sweep`` is the sweep function, not a module."""
    import __future__

    import types

    import parakin.studies.sweep as sweep_module

    bound = {
        name
        for name, value in vars(parakin).items()
        if not name.startswith("_") and not isinstance(value, types.ModuleType | __future__._Feature)
    }
    # the calibration's names are bound on first use (``parakin.__getattr__``)
    assert bound - set(parakin._CALIBRATION) == set(parakin.__all__) - set(parakin._CALIBRATION)
    assert len(parakin.__all__) == len(set(parakin.__all__)) >= 35
    assert all(getattr(parakin, name) is not None for name in parakin.__all__)
    from parakin import sweep

    assert sweep is parakin.sweep is sweep_module.sweep and isinstance(sweep, types.FunctionType)


def test_no_two_modules_share_a_name_across_the_layers():
    """Names say where they live (issue 32, item 5): outside package markers, no two modules of
    parakin/ and generator/ share a file name, except each layer's own ``errors.py`` (the generator's
    GenerationError; the runtime's named errors)."""
    root = Path(__file__).resolve().parent.parent
    seen: dict[str, list[str]] = {}
    for folder in ("parakin", "generator"):
        for path in (root / folder).rglob("*.py"):
            seen.setdefault(path.name, []).append(str(path.relative_to(root)))
    shared = {
        name: paths
        for name, paths in seen.items()
        if len(paths) > 1
        and name not in ("__init__.py", "__main__.py")
        and sorted(paths) != ["generator/errors.py", "parakin/errors.py"]
    }
    assert not shared, shared
