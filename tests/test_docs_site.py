"""The documentation site is self-contained (issue 36, item 5): no web fonts, no script or
stylesheet from the network (the hook strips a notebook's CDN MathJax and flags anything else
that would load from the network), pages as files so that every link works from file://, and the
API reference read as NumPy-style docstrings. The configuration and the hook are checked here;
`make docs` builds the site (strict)."""

import importlib.util
from pathlib import Path
from types import SimpleNamespace

import yaml

ROOT = Path(__file__).resolve().parent.parent


class _Loader(yaml.SafeLoader):
    """mkdocs.yml with its !!python/name tags read as plain strings (not imported)."""


_Loader.add_multi_constructor("tag:yaml.org,2002:python/", lambda loader, suffix, node: suffix)


def _config() -> dict:
    return yaml.load((ROOT / "mkdocs.yml").read_text(), Loader=_Loader)


def _hook():
    spec = importlib.util.spec_from_file_location("offline", ROOT / "docs" / "hooks" / "offline.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_site_loads_no_fonts_and_links_files():
    config = _config()
    assert config["theme"]["font"] is False  # material's default fetches Google Fonts
    assert config["use_directory_urls"] is False  # links to page.html, not folders: file:// works
    assert "docs/hooks/offline.py" in config["hooks"]
    python = next(p["mkdocstrings"] for p in config["plugins"] if isinstance(p, dict) and "mkdocstrings" in p)
    assert python["handlers"]["python"]["options"]["docstring_style"] == "numpy"


def test_the_offline_hook_removes_network_scripts_and_flags_other_loads(caplog):
    hook = _hook()
    page = SimpleNamespace(file=SimpleNamespace(src_uri="notebooks/first_steps.ipynb"))
    html = (
        '<head><script src="https://cdnjs.cloudflare.com/ajax/libs/mathjax/2.7.7/MathJax.js?config=TeX"></script>'
        '<link rel="stylesheet" href="https://fonts.googleapis.com/css?family=Roboto">'
        '<script src="../assets/javascripts/bundle.js"></script>'
        '<link rel="stylesheet" href="../assets/stylesheets/main.css"></head>'
        '<body><a href="https://github.com/">a link is no load</a></body>'
    )
    cleaned = hook.on_post_page(html, page, None)
    assert "cdnjs" not in cleaned and "googleapis" not in cleaned
    assert '<script src="../assets/javascripts/bundle.js"></script>' in cleaned
    assert '<link rel="stylesheet" href="../assets/stylesheets/main.css">' in cleaned
    assert '<a href="https://github.com/">' in cleaned and not caplog.records
    hook.on_post_page('<img src="https://example.org/x.png">', page, None)
    assert any("loads" in r.getMessage() and "example.org" in r.getMessage() for r in caplog.records)


def test_the_plotting_reference_examples_run(tmp_path, monkeypatch):
    """The Examples sections of parakin.interfaces.plot (rendered on the API page) run as written
    and print what they show (doctest)."""
    import doctest

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from parakin.interfaces import plot

    monkeypatch.chdir(tmp_path)  # the animation example writes its GIF here
    try:
        result = doctest.testmod(plot, optionflags=doctest.NORMALIZE_WHITESPACE)
    finally:
        plt.close("all")
    assert result.attempted >= 12 and result.failed == 0, result
    assert (tmp_path / "five_bar.gif").stat().st_size > 1000


def test_the_results_reference_examples_run():
    """The Examples sections of parakin.results (the Results API page): hand-worked values (the
    delta's level arms, the five-bar's two circle intersections, the 3-RRR's certificate)."""
    import doctest

    from parakin import results

    result = doctest.testmod(results, optionflags=doctest.NORMALIZE_WHITESPACE)
    assert result.attempted >= 7 and result.failed == 0, result
