"""MkDocs hook of the parakin docs: runs the scripts of ``examples/`` while the site builds and puts
their figures and printed output on the gallery page, so the gallery always shows what the
examples do now. It also prepares the environment of the executed tutorial snippets.

- on_config: the venv's ``bin`` first on PATH (the ``sh`` snippets call ``parakin``), the
  ``parakin`` logger quiet (its "compiling ..." line depends on the cache, not on the code), a
  fresh scratch folder ``.docs-work`` (the tutorials' ``workdir``) holding the files they
  show;
- on_pre_build: starts every example in the background (two at a time, headless matplotlib),
  each writing its figure into a temporary folder;
- on_files: adds those figures to the site as ``gallery/*.png``;
- on_env: waits for the examples (an example that fails or draws nothing fails the build);
- on_post_page: replaces ``<!-- example-output: NAME -->`` in the gallery page by the text
  that example printed (the pages are rendered before on_env: the output is filled in last).
"""

from __future__ import annotations

import html
import os
import shutil
import subprocess
import sys
import tempfile
import time
from concurrent.futures import Future, ThreadPoolExecutor
from pathlib import Path

from mkdocs.config.defaults import MkDocsConfig
from mkdocs.exceptions import PluginError
from mkdocs.structure.files import File, Files
from mkdocs.structure.pages import Page

ROOT = Path(__file__).resolve().parents[2]
WORK = ROOT / ".docs-work"
GALLERY_PAGE = "gallery.md"
#: files the tutorials show (included from docs/tutorials/) and then use in their scratch folder
TUTORIAL_FILES = ("my_robot.py", "track_five_bar.c")

#: example script -> the figures it writes, given as its arguments (a file, or a folder and the
#: files the script writes there); a script with none only prints
EXAMPLES: dict[str, tuple[list[str], list[str]]] = {
    "sam_walkthrough": ([], []),
    "sphere2r_walkthrough": ([], []),
    "spm_walkthrough": (["spm_walkthrough.png"], ["spm_walkthrough.png"]),
    "sps_section5": (["sps_section5.png"], ["sps_section5.png"]),
    "gough_architecture": (["gough_architecture.png"], ["gough_architecture.png"]),
    "atlas": (
        ["atlas"],
        [
            "atlas/sam_workspace_type_ii.png",
            "atlas/sam_mode_count.png",
            "atlas/spm_orientation_workspace_type_ii.png",
            "atlas/spm_design_space_workspace_volume.png",
            "atlas/five_bar_singularity_map.png",
        ],
    ),
}

_state: dict[str, object] = {}


def _run(name: str, arguments: list[str], folder: Path) -> tuple[str, float]:
    began = time.perf_counter()
    process = subprocess.run(
        [sys.executable, str(ROOT / "examples" / f"{name}.py"), *(str(folder / a) for a in arguments)],
        cwd=ROOT,
        env={**os.environ, "MPLBACKEND": "Agg"},
        capture_output=True,
        text=True,
        check=False,
    )
    if process.returncode != 0:
        raise PluginError(f"examples/{name}.py failed (exit {process.returncode}):\n{process.stderr[-3000:]}")
    return process.stdout, time.perf_counter() - began


def on_config(config: MkDocsConfig) -> MkDocsConfig:
    os.environ["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}"
    os.environ.setdefault("PARAKIN_LOG", "warning")
    shutil.rmtree(WORK, ignore_errors=True)
    WORK.mkdir(parents=True)
    for name in TUTORIAL_FILES:
        shutil.copy(ROOT / "docs" / "tutorials" / name, WORK / name)
    return config


def on_pre_build(config: MkDocsConfig) -> None:
    folder = Path(tempfile.mkdtemp(prefix="parakin-gallery-"))
    pool = ThreadPoolExecutor(max_workers=2)
    # the slowest first, so that the two workers finish together
    order = sorted(EXAMPLES, key=lambda n: n != "gough_architecture")
    _state.update(
        folder=folder,
        pool=pool,
        runs={name: pool.submit(_run, name, EXAMPLES[name][0], folder) for name in order},
        outputs={},
    )


def on_files(files: Files, config: MkDocsConfig) -> Files:
    folder = _state["folder"]
    assert isinstance(folder, Path)
    for _, figures in EXAMPLES.values():
        for figure in figures:
            files.append(File.generated(config, f"gallery/{figure}", abs_src_path=str(folder / figure)))
    return files


def on_env(env, config: MkDocsConfig, files: Files):
    runs = _state["runs"]
    assert isinstance(runs, dict)
    outputs: dict[str, str] = {}
    for name, run in runs.items():
        assert isinstance(run, Future)
        outputs[name], seconds = run.result()
        print(f"INFO    -  gallery: examples/{name}.py ran in {seconds:.1f} s", file=sys.stderr)
    _state["outputs"] = outputs
    folder = _state["folder"]
    assert isinstance(folder, Path)
    missing = [f for _, figures in EXAMPLES.values() for f in figures if not (folder / f).is_file()]
    if missing:
        raise PluginError(f"the examples drew no {', '.join(missing)}")
    return env


def on_post_page(output: str, page: Page, config: MkDocsConfig) -> str:
    if 'exec="on"' in output:
        # markdown-exec leaves a block as text when its options do not validate (a missing workdir)
        raise PluginError(f"{page.file.src_uri}: a code block was not executed (its exec options are invalid)")
    if page.file.src_uri != GALLERY_PAGE:
        return output
    outputs = _state["outputs"]
    assert isinstance(outputs, dict)
    for name in EXAMPLES:
        marker = f"<!-- example-output: {name} -->"
        if marker not in output:
            raise PluginError(f"{GALLERY_PAGE} does not show the output of examples/{name}.py ({marker})")
        block = f'<div class="highlight"><pre><code>{html.escape(outputs[name].rstrip())}</code></pre></div>'
        output = output.replace(marker, block)
    return output


def on_post_build(config: MkDocsConfig) -> None:
    pool = _state.get("pool")
    if isinstance(pool, ThreadPoolExecutor):
        pool.shutdown(wait=True)
    folder = _state.get("folder")
    if isinstance(folder, Path):
        shutil.rmtree(folder, ignore_errors=True)
