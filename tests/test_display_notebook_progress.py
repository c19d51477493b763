"""Progress bars in Jupyter (issue 36): a kernel's stderr is no terminal, but a person reads the
cell's output, so the default 'auto' setting shows a bar there (tqdm's notebook widget where
ipywidgets is installed, else its text bar); outside a kernel nothing changes."""

import sys
import types

import pytest

from parakin import log


class ZMQInteractiveShell:  # the class name IPython's kernel shell has
    pass


@pytest.fixture
def kernel(monkeypatch):
    """This process seen as a Jupyter kernel: IPython.get_ipython() returns a kernel shell."""
    fake = types.ModuleType("IPython")
    fake.get_ipython = ZMQInteractiveShell  # type: ignore[attr-defined]
    monkeypatch.setitem(sys.modules, "IPython", fake)
    monkeypatch.setenv("PARAKIN_PROGRESS", "auto")


def test_a_kernel_shows_the_bar_of_a_large_batch(kernel, capfd):
    assert log._notebook() and not log._terminal()
    with log.progress(log.LARGE_BATCH, "every assembly mode", delay=0.0) as bar:
        assert bar.active
        bar.update(log.LARGE_BATCH)
    shown = capfd.readouterr()
    widget = "ipywidgets" in sys.modules or _importable("ipywidgets")
    if not widget:  # the text bar, in the cell's output
        assert f"{log.LARGE_BATCH}/{log.LARGE_BATCH}" in shown.err, shown
    # a small batch stays silent, as on a terminal
    with log.progress(3, "three inputs", delay=0.0) as small:
        assert not small.active


def test_outside_a_kernel_auto_needs_a_terminal(monkeypatch):
    monkeypatch.setitem(sys.modules, "IPython", None)
    monkeypatch.setenv("PARAKIN_PROGRESS", "auto")
    assert not log._notebook()
    with log.progress(log.LARGE_BATCH, "a pipe", delay=0.0) as bar:
        assert bar.active is log._terminal()


def _importable(name: str) -> bool:
    import importlib.util

    return importlib.util.find_spec(name) is not None
