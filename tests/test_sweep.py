"""parakin.sweep (the function of parakin.studies.sweep): a workspace slice against its analytic
boundary, the same sweep on a 2-worker dask cluster and in one process, a resumed store, and
memory bounded by the chunk."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

xr = pytest.importorskip("xarray")
pytest.importorskip("dask")

import parakin  # noqa: E402
from parakin import sweep  # noqa: E402  (the public function: parakin.sweep)


def _five_bar_reachable(x: np.ndarray, y: np.ndarray, p: dict[str, float]) -> tuple[np.ndarray, np.ndarray]:
    """The five-bar's workspace by hand: the tool point P is reachable iff each distal link can
    close, |a_i - b_i| <= |P - A_i| <= a_i + b_i with A_1 = (-d, 0), A_2 = (d, 0). Returns the
    verdict and the distance (m) to the nearest boundary circle."""
    verdict, margin = np.ones(x.shape, bool), np.full(x.shape, np.inf)
    for center, a, b in ((-p["d"], p["a1"], p["b1"]), (p["d"], p["a2"], p["b2"])):
        r = np.hypot(x - center, y)
        inner, outer = r - abs(a - b), a + b - r
        verdict &= (inner >= 0) & (outer >= 0)
        margin = np.minimum(margin, np.minimum(np.abs(inner), np.abs(outer)))
    return verdict, margin


@pytest.mark.parametrize("parameters", [{}, {"a1": 0.25, "b2": 0.18}])
def test_five_bar_workspace_slice_matches_its_analytic_boundary(parameters):
    m = parakin.load("five_bar", **parameters)
    xs, ys = np.linspace(-0.6, 0.6, 121), np.linspace(-0.6, 0.7, 131)
    result = sweep(m, ["reachable", "branches"], {"x": xs, "y": ys}, chunk=2000)
    assert result.reachable.dims == ("x", "y")
    grid_x, grid_y = np.meshgrid(xs, ys, indexing="ij")
    expected, margin = _five_bar_reachable(grid_x, grid_y, m.parameters)
    clear = margin > 1e-9
    assert clear.sum() > 15_000 and expected[clear].any() and (~expected[clear]).any()
    np.testing.assert_array_equal(result.reachable.values[clear], expected[clear])
    # inside, the two elbows give 4 inverse branches (fewer only on the boundary circles)
    assert (result.branches.values[clear & expected] == 4).all()


def test_singularity_distances_respect_the_mirror_symmetry_and_are_nan_where_unreachable():
    """The default five-bar is symmetric about x = 0 (equal links): both distances along a line
    y = 0.3 are mirror images of themselves, in [0, 1], and NaN exactly where unreachable."""
    m = parakin.load("five_bar")
    result = sweep(
        m, ["reachable", "type_ii_distance", "type_i_distance"], {"x": np.linspace(-0.3, 0.3, 41), "y": [0.3]}
    )
    reachable = result.reachable.values[:, 0]
    assert reachable.sum() > 20
    for name in ("type_ii_distance", "type_i_distance"):
        measured = result[name].values[:, 0]
        np.testing.assert_array_equal(np.isfinite(measured), reachable)
        np.testing.assert_allclose(measured, measured[::-1], rtol=1e-9, equal_nan=True)
        assert ((measured[reachable] >= 0) & (measured[reachable] <= 1)).all()


def test_a_two_worker_cluster_gives_the_same_sweep_as_one_process():
    distributed = pytest.importorskip("distributed")
    axes = {"alpha": np.linspace(-1.0, 1.0, 24), "beta": np.linspace(-0.8, 0.8, 17)}
    quantities = ["reachable", "branches", "type_ii_distance", "type_i_distance"]
    alone = sweep("spm", quantities, axes, chunk=50, scheduler="synchronous")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        clustered = sweep("spm", quantities, axes, chunk=50, scheduler=cluster.scheduler_address)
    assert alone.reachable.values.sum() > 50
    xr.testing.assert_identical(alone, clustered)


def test_an_interrupted_store_resumes_and_recomputes_only_what_is_missing(tmp_path):
    import json

    import zarr

    store = tmp_path / "sweep.zarr"
    axes = {"x": np.linspace(-0.5, 0.5, 40), "y": np.linspace(-0.5, 0.6, 30)}
    first = sweep("five_bar", ["reachable", "type_ii_distance"], axes, chunk=300, store=store)
    assert first.attrs["chunks_computed"] == 4
    reference = first.load()
    record = json.loads((store / "finished.json").read_text())
    del record["chunks"]["2"]  # as if the run had died before chunk 2 was recorded
    (store / "finished.json").write_text(json.dumps(record))
    zarr.open_group(str(store), mode="a")["reachable"][20:30] = False
    again = sweep("five_bar", ["reachable", "type_ii_distance"], axes, chunk=300, store=store)
    assert again.attrs["chunks_computed"] == 1
    xr.testing.assert_identical(again.load().drop_attrs(), reference.drop_attrs())
    assert (
        sweep("five_bar", ["reachable", "type_ii_distance"], axes, chunk=300, store=store).attrs["chunks_computed"] == 0
    )
    with pytest.raises(parakin.BadInputError, match="another sweep"):
        sweep("five_bar", ["reachable"], axes, chunk=300, store=store)


def test_design_space_workspace_volume_and_architecture():
    """Workspace volume of the SPM over its two link angles grows with the link angles; the
    sweep over parameters loads one design per grid point."""
    links = np.linspace(0.7, 1.3, 3)
    workspace = {"alpha": np.linspace(-3, 3, 9), "beta": np.linspace(-1.4, 1.4, 9), "gamma": np.linspace(-3, 3, 9)}
    result = sweep("spm", ["workspace_volume"], {"alpha1": links, "alpha2": links}, workspace=workspace)
    volume = result.workspace_volume.values
    assert volume.shape == (3, 3) and (volume >= 0).all()
    assert volume[-1, -1] > volume[0, 0]
    gough = sweep("gough", ["architecture"], {"t11": [0.5, 1.0, 2.0]})
    assert any(name.startswith("architecture_") for name in gough.data_vars)


def test_bad_sweeps_are_refused():
    with pytest.raises(parakin.BadInputError, match="unknown quantities"):
        sweep("five_bar", ["nonsense"], {"x": [0.0]})
    with pytest.raises(parakin.BadInputError, match="axis 'q'"):
        sweep("five_bar", ["reachable"], {"q": [0.0]})
    with pytest.raises(parakin.UnsupportedOperationError, match="forward elimination"):
        sweep("sphere2r", ["modes"], {"theta1": [0.0]})


def _traced_peak(axes: dict[str, np.ndarray], chunk: int, store) -> float:
    tracemalloc.start()
    result = sweep("five_bar", ["reachable"], axes, chunk=chunk, store=store, scheduler="synchronous")
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert result.reachable.shape == tuple(len(v) for v in axes.values())
    return peak


def test_memory_does_not_grow_with_the_grid(tmp_path):
    """The default-run size of the next test: a million poses in chunks of 20,000 take no more
    peak traced memory than 62,500 poses (measured: 21 MB both), and less than the whole grid's
    intermediate arrays would (1e6 x 4 branches x 8 bytes = 32 MB). A first sweep, untraced,
    takes the one-off costs (imports, the compiled library)."""
    warm = {"x": [0.0, 0.1], "y": [0.3, 0.4]}
    sweep("five_bar", ["reachable"], warm, store=tmp_path / "warm.zarr", scheduler="synchronous")
    small = _traced_peak(
        {"x": np.linspace(-0.6, 0.6, 250), "y": np.linspace(-0.6, 0.8, 250)}, 20_000, tmp_path / "small.zarr"
    )
    big = _traced_peak(
        {"x": np.linspace(-0.6, 0.6, 1000), "y": np.linspace(-0.6, 0.8, 1000)}, 20_000, tmp_path / "big.zarr"
    )
    assert big < 1.25 * small + 1e6 and big < 32e6, f"peak {big / 1e6:.1f} MB (62,500 poses: {small / 1e6:.1f} MB)"


@pytest.mark.slow
def test_memory_is_bounded_by_the_chunk_not_the_grid(tmp_path):
    """Four million poses written to a store in chunks of 20,000: peak traced memory stays far
    below what the whole grid's intermediate arrays would take (~4e6 x 4 branches x 8 doubles)."""
    axes = {"x": np.linspace(-0.6, 0.6, 2000), "y": np.linspace(-0.6, 0.8, 2000)}
    tracemalloc.start()
    result = sweep("five_bar", ["reachable"], axes, chunk=20_000, store=tmp_path / "big.zarr", scheduler="synchronous")
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert result.reachable.shape == (2000, 2000)
    assert peak < 100e6, f"peak {peak / 1e6:.0f} MB"


def test_cli_sweep_writes_netcdf_and_a_map(tmp_path):
    import subprocess
    import sys

    pytest.importorskip("matplotlib")
    out = subprocess.run(
        [
            sys.executable, "-m", "parakin", "sweep", "five_bar", "reachable", "type_ii_distance",
            "--axis", "x=-0.5:0.5:41", "--axis", "y=-0.3:0.7:31", "--netcdf", str(tmp_path / "s.nc"),
            "--plot", str(tmp_path / "s.png"), "--plot-quantity", "type_ii_distance",
        ],
        capture_output=True, text=True, check=True,
    )  # fmt: skip
    assert "reachable" in out.stdout and (tmp_path / "s.png").stat().st_size > 10_000
    saved = xr.load_dataset(tmp_path / "s.nc")
    direct = sweep("five_bar", ["reachable"], {"x": np.linspace(-0.5, 0.5, 41), "y": np.linspace(-0.3, 0.7, 31)})
    np.testing.assert_array_equal(saved.reachable.values.astype(bool), direct.reachable.values)


def test_a_store_of_another_grid_is_refused_not_reused(tmp_path, monkeypatch):
    store = tmp_path / "s.zarr"
    sweep("five_bar", ["reachable"], {"x": np.linspace(-0.5, 0.5, 11), "y": np.linspace(-0.3, 0.6, 7)}, store=store)
    with pytest.raises(parakin.BadInputError, match="another sweep"):
        sweep("five_bar", ["reachable"], {"x": np.linspace(-0.1, 0.1, 11), "y": np.linspace(-0.3, 0.6, 7)}, store=store)
    with pytest.raises(parakin.BadInputError, match="evenly spaced ascending"):
        sweep("spm", ["workspace_volume"], {"alpha1": [1.0]}, workspace={"alpha": np.linspace(1, -1, 5)})
    import distributed

    client = distributed.Client

    def hurried(*args, timeout=30, **kwargs):
        """The real Client and connection attempt, with up to 2 s instead of sweep's 30 s to wait
        (nothing listens on port 1: only the wait differs)."""
        return client(*args, timeout=min(timeout, 2), **kwargs)

    monkeypatch.setattr(distributed, "Client", hurried)
    with pytest.raises(parakin.BadInputError, match="no dask scheduler"):
        sweep("five_bar", ["reachable"], {"x": [0.0]}, scheduler="tcp://127.0.0.1:1")
