"""Sweep stores never return unverified data (issue 18 item 3): every finished chunk carries the
sha256 of each variable's values in the store's record; resume and read verify it. A deleted chunk
file, a record that lists a chunk never written, one flipped byte in a chunk and a kill before the
first record each end in exactly the values of a fresh in-memory sweep, or in BadInputError."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import numpy as np
import pytest

pytest.importorskip("xarray")
pytest.importorskip("dask")
pytest.importorskip("zarr")

import parakin  # noqa: E402
from parakin.studies import sweep as sweep_module  # noqa: E402
from parakin.studies.sweep import sweep  # noqa: E402

QUANTITIES = ["reachable", "branches", "type_ii_distance"]
# 40 x 30 poses in chunks of 300: 4 chunks of 10 rows of x; about half the grid is reachable, so
# every variable has chunk files with data in them
AXES = {"x": np.linspace(-0.5, 0.5, 40), "y": np.linspace(-0.5, 0.6, 30)}
CHUNK = 300


@pytest.fixture(scope="module")
def fresh():
    """The same sweep in memory: the reference every repaired store must equal."""
    return sweep("five_bar", QUANTITIES, AXES, chunk=CHUNK)


def _stored(store, **options):
    return sweep("five_bar", QUANTITIES, AXES, chunk=CHUNK, store=store, **options)


def _assert_equal_to(result, fresh) -> None:
    """Every variable, value for value (NaN where NaN), and the same dtypes."""
    assert sorted(result.data_vars) == sorted(fresh.data_vars)
    for name in fresh.data_vars:
        got, want = result[name].values, fresh[name].values
        assert got.dtype == want.dtype, name
        np.testing.assert_array_equal(got, want, err_msg=name)


def _chunk_file(store, name: str, k: int):
    """The file of chunk k (rows of the first axis) of a variable (zarr 3 layout c/<k>/0)."""
    path = store / name / "c" / str(k) / "0"
    assert path.is_file(), f"{path} was not written"
    return path


def test_a_deleted_chunk_is_recomputed_not_read_as_unreachable(tmp_path, fresh):
    """At 6bfa97b zarr filled a deleted chunk with its fill value: reachable False ('unreachable')."""
    store = tmp_path / "s.zarr"
    first = _stored(store)
    assert first.attrs["chunks_computed"] == 4
    assert fresh.reachable.values[20:30].any()  # the chunk deleted below holds reachable poses
    _chunk_file(store, "reachable", 2).unlink()
    with pytest.raises(parakin.BadInputError, match="chunk 2 of 'reachable' does not match"):
        first.reachable.load()  # the dataset returned earlier verifies the chunk when it reads it
    again = _stored(store)
    assert (again.attrs["chunks_computed"], again.attrs["chunks_unverified"]) == (1, 1)
    _assert_equal_to(again, fresh)
    assert _stored(store).attrs["chunks_computed"] == 0  # repaired for good


def test_a_record_that_lists_an_unwritten_chunk_is_not_believed(tmp_path, fresh, monkeypatch):
    """A run killed after its first batch (chunks 0, 1) whose record is then edited to list
    chunks 2 and 3 as finished, with chunk 0's checksums: 2 and 3 are recomputed."""
    import dask

    store = tmp_path / "s.zarr"
    compute = dask.compute
    calls = []

    def killed_in_the_second_batch(*args, **kwargs):
        calls.append(1)
        if len(calls) == 2:
            raise KeyboardInterrupt("simulated kill")
        return compute(*args, **kwargs)

    monkeypatch.setattr(dask, "compute", killed_in_the_second_batch)
    with pytest.raises(KeyboardInterrupt):
        _stored(store, scheduler="synchronous")
    monkeypatch.setattr(dask, "compute", compute)
    record = json.loads((store / "finished.json").read_text())
    assert sorted(record["chunks"]) == ["0", "1"]
    assert not (store / "type_ii_distance" / "c" / "2").exists()  # never written
    record["chunks"]["2"] = record["chunks"]["3"] = record["chunks"]["0"]
    (store / "finished.json").write_text(json.dumps(record))
    again = _stored(store)
    assert (again.attrs["chunks_computed"], again.attrs["chunks_unverified"]) == (2, 2)
    _assert_equal_to(again, fresh)


def test_a_record_without_checksums_is_recomputed(tmp_path, fresh):
    """A record of the format before checksums (a list of chunk numbers) verifies nothing."""
    store = tmp_path / "s.zarr"
    _stored(store)
    record = json.loads((store / "finished.json").read_text())
    (store / "finished.json").write_text(json.dumps({"spec": record["spec"], "chunks": [0, 1, 2, 3]}))
    again = _stored(store)
    assert again.attrs["chunks_computed"] == 4
    _assert_equal_to(again, fresh)


@pytest.mark.parametrize("where", [0.25, 0.5, 0.9])
def test_one_flipped_byte_is_never_returned(tmp_path, fresh, where):
    """At 6bfa97b a flipped byte read back as 2.6e167 in a distance that lies in [0, 1]. Whether
    the flip breaks the compressed stream or only changes a value, the chunk does not verify."""
    store = tmp_path / "s.zarr"
    first = _stored(store)
    path = _chunk_file(store, "type_ii_distance", 1)
    data = bytearray(path.read_bytes())
    data[int(where * (len(data) - 1))] ^= 0xFF
    path.write_bytes(bytes(data))
    with pytest.raises(parakin.BadInputError, match="chunk 1 of 'type_ii_distance'"):
        first.type_ii_distance.load()
    again = _stored(store)
    assert (again.attrs["chunks_computed"], again.attrs["chunks_unverified"]) == (1, 1)
    _assert_equal_to(again, fresh)
    distance = again.type_ii_distance.values
    assert np.nanmax(distance) <= 1.0 and np.nanmin(distance) >= 0.0


def test_a_store_killed_before_its_first_record_resumes(tmp_path, fresh, monkeypatch):
    """A kill while the store is created (before its record exists) leaves no store, only the
    scratch folder it was built in; the next run builds it anew and finishes."""
    store = tmp_path / "s.zarr"
    write = sweep_module._write_record

    def killed(*args, **kwargs):
        raise KeyboardInterrupt("simulated kill")

    monkeypatch.setattr(sweep_module, "_write_record", killed)
    with pytest.raises(KeyboardInterrupt):
        _stored(store)
    monkeypatch.setattr(sweep_module, "_write_record", write)
    assert not store.exists() and (tmp_path / ".s.zarr.initialising" / "zarr.json").exists()
    again = _stored(store)
    assert again.attrs["chunks_computed"] == 4
    _assert_equal_to(again, fresh)
    assert not (tmp_path / ".s.zarr.initialising").exists()


def test_a_store_without_a_record_is_recognised_as_this_sweep(tmp_path, fresh):
    """The layout a kill before the first record left at 6bfa97b (metadata, no record), refused
    then as 'holds another sweep': its own attributes name the sweep, so it resumes; a store of
    another sweep without a record is still refused."""
    store = tmp_path / "s.zarr"
    _stored(store)
    (store / "finished.json").unlink()
    again = _stored(store)
    assert again.attrs["chunks_computed"] == 4
    _assert_equal_to(again, fresh)
    (store / "finished.json").unlink()
    with pytest.raises(parakin.BadInputError, match="holds another sweep"):
        sweep("five_bar", ["reachable"], AXES, chunk=CHUNK, store=store)


def test_a_process_killed_before_its_first_record_resumes(tmp_path, fresh):
    """The same with a real kill: the process ends (os._exit, no cleanup) where the record would
    be written for the first time (the first write of a file named finished*)."""
    store = tmp_path / "s.zarr"
    script = textwrap.dedent(
        f"""
        import os, pathlib
        import numpy as np
        from parakin.studies import sweep as module
        write = pathlib.Path.write_text
        def killed(path, *args, **kwargs):
            if path.name.startswith("finished"):
                os._exit(9)
            return write(path, *args, **kwargs)
        pathlib.Path.write_text = killed
        module.sweep("five_bar", {QUANTITIES!r}, {{"x": np.linspace(-0.5, 0.5, 40), "y": np.linspace(-0.5, 0.6, 30)}},
                     chunk={CHUNK}, store={str(store)!r})
        """
    )
    killed = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300)
    assert killed.returncode == 9, killed.stderr
    assert not store.exists()  # the store appears with its record or not at all
    again = _stored(store)
    assert again.attrs["chunks_computed"] == 4
    _assert_equal_to(again, fresh)


def test_an_empty_folder_is_an_empty_store_and_a_foreign_folder_is_refused(tmp_path, fresh):
    empty = tmp_path / "empty.zarr"
    empty.mkdir()
    _assert_equal_to(_stored(empty), fresh)
    foreign = tmp_path / "notes"
    foreign.mkdir()
    (foreign / "notes.txt").write_text("mine")
    with pytest.raises(parakin.BadInputError, match="holds another sweep"):
        _stored(foreign)
    assert (foreign / "notes.txt").read_text() == "mine"


def test_damaged_metadata_or_record_rebuilds_the_store(tmp_path, fresh):
    """A variable's zarr metadata deleted, or a record that is not JSON: the store is still this
    sweep's (its own attributes say so), rebuilt and recomputed, not read."""
    store = tmp_path / "s.zarr"
    _stored(store)
    (store / "type_ii_distance" / "zarr.json").unlink()
    again = _stored(store)
    assert again.attrs["chunks_computed"] == 4
    _assert_equal_to(again, fresh)
    (store / "finished.json").write_text('{"spec": "trunc')
    again = _stored(store)
    assert again.attrs["chunks_computed"] == 4
    _assert_equal_to(again, fresh)
