"""Sweeps started together on one store (issue 31 item 10). At 44aede2 every process built the
store in the same scratch folder and removed the others' (raw FileNotFoundError / OSError). Now
one process writes a store at a time: another one started meanwhile is refused by name
(StoreInUseError, naming the store), one started after it resumes; the store ends with exactly
the values of a sweep in one process."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap
import threading
import time

import numpy as np
import pytest

pytest.importorskip("xarray")
pytest.importorskip("dask")
pytest.importorskip("zarr")

import parakin  # noqa: E402
from parakin.errors import StoreInUseError  # noqa: E402
from parakin.studies import sweep as sweep_module  # noqa: E402
from parakin.studies.sweep import sweep  # noqa: E402

QUANTITIES = ["reachable", "branches", "type_ii_distance"]
AXES = {"x": np.linspace(-0.5, 0.5, 40), "y": np.linspace(-0.5, 0.6, 30)}
# 14 chunks of 3 rows: a sweep of several batches, so that processes started together overlap
CHUNK = 100

#: one sweep process: waits for the start signal, sweeps, reports its outcome as one JSON line
SCRIPT = textwrap.dedent(
    """
    import json, pathlib, sys, time
    import numpy as np
    import parakin
    from parakin.studies.sweep import sweep
    store, go = sys.argv[1], pathlib.Path(sys.argv[2])
    axes = {"x": np.linspace(-0.5, 0.5, 40), "y": np.linspace(-0.5, 0.6, 30)}
    parakin.load("five_bar")  # the library is loaded before the start: the sweeps start together
    while not go.exists():
        time.sleep(0.001)
    try:
        result = sweep("five_bar", ["reachable", "branches", "type_ii_distance"], axes, chunk=100, store=store)
        result.load()
        print(json.dumps({"outcome": "finished", "computed": result.attrs["chunks_computed"]}))
    except parakin.errors.StoreInUseError as error:
        print(json.dumps({"outcome": "refused", "message": str(error)}))
    """
)


@pytest.fixture(scope="module")
def fresh():
    """The same sweep in one process, in memory: the values every store must end with."""
    return sweep("five_bar", QUANTITIES, AXES, chunk=CHUNK)


def _assert_equal_to(result, fresh) -> None:
    assert sorted(result.data_vars) == sorted(fresh.data_vars)
    for name in fresh.data_vars:
        got, want = result[name].values, fresh[name].values
        assert got.dtype == want.dtype, name
        np.testing.assert_array_equal(got, want, err_msg=name)


def _started_together(store, go, count: int) -> list[subprocess.Popen]:
    processes = [
        subprocess.Popen(
            [sys.executable, "-c", SCRIPT, str(store), str(go)],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        for _ in range(count)
    ]
    time.sleep(2.0)  # every process has imported parakin and waits for the signal
    go.write_text("go")
    return processes


@pytest.mark.parametrize("count", [2, 3])
def test_sweeps_started_together_finish_or_are_refused_by_name(tmp_path, fresh, count):
    """Each process finishes (computing, or resuming a store another one finished) or is refused
    with StoreInUseError naming the store; none dies of a raw error; the store is the sweep's."""
    store = tmp_path / "s.zarr"
    go = tmp_path / "go"
    outcomes = []
    for process in _started_together(store, go, count):
        out, err = process.communicate(timeout=120)
        assert process.returncode == 0, err  # a raw exception exits 1 with a traceback
        outcome = json.loads(out.strip().splitlines()[-1])
        if outcome["outcome"] == "refused":
            assert str(store) in outcome["message"] and "another sweep" in outcome["message"], outcome
        outcomes.append(outcome)
    finished = [o for o in outcomes if o["outcome"] == "finished"]
    assert finished, outcomes
    assert sum(o["computed"] for o in finished) == 14  # every chunk computed once, none twice
    again = sweep("five_bar", QUANTITIES, AXES, chunk=CHUNK, store=store)
    assert again.attrs["chunks_computed"] == 0  # the store is complete and verifies
    _assert_equal_to(again, fresh)
    leftovers = sorted(p.name for p in tmp_path.iterdir() if p.name not in ("s.zarr", "go"))
    assert all(name == ".s.zarr.lock" for name in leftovers), leftovers  # no scratch folder left


def test_a_sweep_started_while_another_writes_is_refused_then_resumes(tmp_path, fresh, monkeypatch):
    """Deterministic: a second sweep (a thread of the same process) while the first is between
    two batches is refused by name and changes nothing; after the first ends, it resumes."""
    import dask

    store = tmp_path / "s.zarr"
    compute = dask.compute
    paused, release = threading.Event(), threading.Event()
    calls: list[int] = []

    def pausing(*args, **kwargs):
        calls.append(1)
        if len(calls) == 2:  # the first batch is written and recorded
            paused.set()
            release.wait(60)
        return compute(*args, **kwargs)

    monkeypatch.setattr(dask, "compute", pausing)
    outcome: dict[str, object] = {}

    def first() -> None:
        try:
            outcome["result"] = sweep("five_bar", QUANTITIES, AXES, chunk=CHUNK, store=store, scheduler="synchronous")
        except BaseException as error:  # reported to the test below
            outcome["error"] = error

    writer = threading.Thread(target=first)
    writer.start()
    assert paused.wait(60)
    record = (store / "finished.json").read_text()
    with pytest.raises(StoreInUseError, match="another sweep is writing") as refused:
        sweep("five_bar", QUANTITIES, AXES, chunk=CHUNK, store=store)
    assert str(store) in str(refused.value)
    assert isinstance(refused.value, parakin.ParakinError)
    assert (store / "finished.json").read_text() == record  # the refused sweep touched nothing
    release.set()
    writer.join(60)
    assert "error" not in outcome, outcome
    monkeypatch.setattr(dask, "compute", compute)
    again = sweep("five_bar", QUANTITIES, AXES, chunk=CHUNK, store=store)
    assert again.attrs["chunks_computed"] == 0
    _assert_equal_to(again, fresh)


def test_the_store_is_free_again_after_a_failed_sweep(tmp_path, fresh, monkeypatch):
    """A sweep that fails (here: interrupted in its first batch) releases the store: the next
    one in the same process is not refused."""
    import dask

    store = tmp_path / "s.zarr"
    compute = dask.compute

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt("simulated interrupt")

    monkeypatch.setattr(dask, "compute", interrupted)
    with pytest.raises(KeyboardInterrupt):
        sweep("five_bar", QUANTITIES, AXES, chunk=CHUNK, store=store)
    monkeypatch.setattr(dask, "compute", compute)
    _assert_equal_to(sweep("five_bar", QUANTITIES, AXES, chunk=CHUNK, store=store), fresh)


def test_the_scratch_folder_is_never_a_live_sweeps(tmp_path, fresh, monkeypatch):
    """The folder a store is initialised in is touched only under the store's lock: a process
    that finds one left over (a kill during initialisation) holds the lock, so its maker is gone."""
    store = tmp_path / "s.zarr"
    seen = []
    scratch = sweep_module._scratch

    def checked(path):
        seen.append(sweep_module._holds_lock(path))
        return scratch(path)

    monkeypatch.setattr(sweep_module, "_scratch", checked)
    sweep("five_bar", QUANTITIES, AXES, chunk=CHUNK, store=store)
    assert seen and all(seen)
