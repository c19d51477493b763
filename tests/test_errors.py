"""Bad input gets a clear exception naming the problem, never a silent NaN."""

import os

import numpy as np
import pytest

import parakin


@pytest.fixture(scope="module")
def m():
    return parakin.load("sam", backend="numpy")


def test_unknown_mechanism_lists_the_valid_ones():
    with pytest.raises(parakin.UnknownMechanismError, match="available: .*sam"):
        parakin.load("no_such_robot")


def test_unknown_parameter_lists_the_valid_ones():
    with pytest.raises(parakin.BadInputError, match=r"unknown parameter 'L9' for 'sam'; valid: \['L1', 'L4'\]"):
        parakin.load("sam", L9=1.0)


@pytest.mark.parametrize(
    ("given", "suggested"),
    [("l1", "'L1'"), ("L1x", "'L1'"), ("l4", "'L4'")],
)
def test_unknown_parameter_is_a_parameter_error_suggesting_the_closest_name(given, suggested):
    """`load("sam", l1=0.5)` once raised UnknownMechanismError ("unknown mechanism" is the wrong
    claim): a misspelt parameter is a BadInputError suggesting the case-insensitive match first,
    then the closest spelling (difflib)."""
    with pytest.raises(parakin.BadInputError, match=f"unknown parameter '{given}'.*did you mean {suggested}") as error:
        parakin.load("sam", backend="numpy", **{given: 0.5})
    assert not isinstance(error.value, parakin.UnknownMechanismError)
    assert "valid: ['L1', 'L4']" in str(error.value)


def test_parameters_override_defaults():
    m = parakin.load("sam", backend="numpy", L1=0.6)
    assert m.parameters == {"L1": 0.6, "L4": 0.3556}
    config = m.inverse_pose(parakin.pose_from_xyz_euler([0, 0.05, 0.7, 0.1, 0, 0])).branch(0)
    assert abs(m.platform_pose(config.actuated, config.passive)[1, 3] - 0.05) < 1e-12


def test_nan_and_shape_errors(m):
    with pytest.raises(parakin.BadInputError, match="non-finite"):
        m.forward_pose([0, np.nan, 0, 0, 0, 0])
    with pytest.raises(parakin.BadInputError, match=r"shape \(\.\.\., 6\)"):
        m.forward_pose([0, 0, 0])
    with pytest.raises(parakin.BadInputError, match=r"\(\.\.\., 4, 4\)"):
        m.inverse_pose(np.eye(3))
    with pytest.raises(parakin.BadInputError, match="not a rigid transform"):
        m.inverse_pose(2 * np.eye(4))
    with pytest.raises(parakin.BadInputError, match="reflection"):
        m.inverse_pose(np.diag([1.0, 1.0, -1.0, 1.0]))
    with pytest.raises(parakin.BadInputError, match="twist"):
        m.inverse_rate(m.inverse_pose(parakin.pose_from_xyz_euler([0, 0, 0.7, 0.1, 0.1, 0])).branch(0), [1, 2])


def test_unknown_backend_and_limit():
    with pytest.raises(parakin.BadInputError, match="unknown backend"):
        parakin.load("sam", backend="gpu")
    with pytest.raises(parakin.BadInputError, match="unknown limit 'l2'.*did you mean 'L2'") as error:
        parakin.load("sam", limits={"l2": (0, 1)})
    assert not isinstance(error.value, parakin.UnknownMechanismError)


@pytest.mark.parametrize("name", [5, None, b"sam", 2.5, ["sam"]])
def test_load_of_something_that_is_no_name_is_a_bad_input_error(name):
    """`parakin.load(5)` and `load(None)` once raised Python's TypeError from pathlib."""
    with pytest.raises(parakin.BadInputError, match="a mechanism is a name .* or a package folder path, got"):
        parakin.load(name)
    with pytest.raises(parakin.BadInputError):
        parakin.metadata(name)


def test_a_name_too_long_for_a_path_is_an_unknown_mechanism():
    """A 5,000-character name once raised OSError (file name too long) from the folder test."""
    with pytest.raises(
        parakin.UnknownMechanismError, match=r"unknown mechanism 'xxxx.*\.\.\.': not a package"
    ) as error:
        parakin.load("x" * 5000)
    assert len(str(error.value)) < 1000  # the message shows the start of the name, not all of it


def test_unreachable_pose_outside_stroke():
    m = parakin.load("sam", backend="numpy", limits={"L2": (0.3, 0.9), "L3": (0.3, 0.9)})
    with pytest.raises(parakin.UnreachablePoseError, match="batch index \\(1,\\)"):
        m.inverse_pose(parakin.pose_from_xyz_euler([[0, 0, 0.7, 0.1, 0, 0], [0, 0, 2.5, 0.1, 0, 0]]))
    result = m.inverse_pose(parakin.pose_from_xyz_euler([0, 0, 2.5, 0.1, 0, 0]), strict=False)
    assert not result.valid.any() and result.failures["limits"].all()


def test_serial_singular_pose_is_reported(m):
    """A U joint on the leg line's extension of {P}'s Z axis makes phi3 undefined (phi2 = 0)."""
    actuated = np.array([0.2, -0.3, 0.1, 0.0, 0.3, 0.0])
    passive = np.array([0.7, 0.0, 0.4, 0.7, -0.3, 0.0])
    pose = m.platform_pose(actuated, passive)
    result = m.inverse_pose(pose, strict=False)
    assert result.failures["left_u_joint_not_aligned"].all()
    assert not np.isnan(result.actuated[~result.failures["finite"]]).any()


def test_newton_non_convergence_reports_the_residual(m):
    config = m.inverse_pose(parakin.pose_from_xyz_euler([0.02, 0.03, 0.68, 0.1, 0.05, 0.08])).branch(2)
    with pytest.raises(parakin.ConvergenceError, match="residual") as error:
        m.forward_pose(config.actuated, guess=config.passive + 0.5, max_iterations=2)
    assert error.value.residual is not None and error.value.residual > 1e-12


def test_forward_all_at_self_motion_is_a_singular_error(m):
    nominal = m.inverse_pose(parakin.pose_from_xyz_euler([0, 0, 0.664, 0, 0, 0])).branch(2)
    with pytest.raises(parakin.SingularConfigurationError, match="u_joint_axes_parallel"):
        m.forward_pose_all(nominal.actuated)


def test_tracker_errors():
    m = parakin.load("sam", backend="compiled")
    config = m.inverse_pose(parakin.pose_from_xyz_euler([0.02, 0.03, 0.68, 0.1, 0.05, 0.08])).branch(2)
    tracker = m.tracker(config)
    with pytest.raises(parakin.BadInputError):
        tracker.solve([np.nan] * 6)
    with pytest.raises(parakin.BadInputError):
        tracker.solve([0.0] * 4)


def unusable_caches(tmp_path):
    """A file where the cache folder should be, and a cache folder below a file."""
    blocker = tmp_path / "not_a_folder"
    blocker.write_text("a file in the cache's place\n")
    return [(blocker, "FileExistsError"), (blocker / "cache", "NotADirectoryError")]


def test_unusable_cache_auto_falls_back_to_numpy_and_says_why(tmp_path, monkeypatch):
    """An unwritable C cache, or a file in its place, once raised a raw FileExistsError /
    PermissionError even with backend 'auto'. Now 'auto' runs on NumPy with a
    BackendFallbackWarning naming the cause, and 'compiled' raises CacheUnavailableError."""
    from parakin.errors import CacheUnavailableError

    reference = parakin.load("sphere2r", backend="numpy")
    inputs = np.deg2rad([30.0, 50.0])
    for cache, cause in unusable_caches(tmp_path):
        monkeypatch.setenv("PARAKIN_CACHE", str(cache))
        with pytest.warns(parakin.BackendFallbackWarning, match=f"on NumPy.*CacheUnavailableError.*{cause}"):
            m = parakin.load("sphere2r", backend="auto")
        assert m.backend.name == "numpy"
        np.testing.assert_array_equal(m.forward_pose(inputs).pose, reference.forward_pose(inputs).pose)
        with pytest.raises(CacheUnavailableError, match=f"cache {cache} cannot be used.*{cause}.*PARAKIN_CACHE"):
            parakin.load("sphere2r", backend="compiled")
        assert issubclass(CacheUnavailableError, parakin.ParakinError)
    assert (tmp_path / "not_a_folder").read_text() == "a file in the cache's place\n"  # untouched


def test_unwritable_cache_is_a_named_error(tmp_path, monkeypatch):
    """No permission to write the cache: a PermissionError from the file system (injected where
    the process runs as root, which may write anywhere) becomes CacheUnavailableError."""
    import tempfile

    from parakin.errors import CacheUnavailableError

    cache = tmp_path / "cache"
    cache.mkdir()
    monkeypatch.setenv("PARAKIN_CACHE", str(cache))
    if os.geteuid() == 0:

        def refuse(*args, **kwargs):
            raise PermissionError(13, "Permission denied", str(cache))

        monkeypatch.setattr(tempfile, "mkstemp", refuse)
    else:
        cache.chmod(0o500)
    try:
        with pytest.raises(CacheUnavailableError, match="PermissionError"):
            parakin.load("sphere2r", backend="compiled")
        with pytest.warns(parakin.BackendFallbackWarning, match="PermissionError"):
            assert parakin.load("sphere2r", backend="auto").backend.name == "numpy"
    finally:
        cache.chmod(0o700)
    assert list(cache.iterdir()) == []


def test_no_compiler_auto_says_it_runs_on_numpy(monkeypatch):
    from parakin.errors import CompilerUnavailableError

    monkeypatch.setenv("CC", "no-such-compiler-for-parakin")
    with pytest.warns(parakin.BackendFallbackWarning, match="on NumPy.*CompilerUnavailableError: no C compiler"):
        assert parakin.load("sphere2r").backend.name == "numpy"
    with pytest.raises(CompilerUnavailableError, match="no C compiler"):
        parakin.load("sphere2r", backend="compiled")


def test_every_named_error_and_warning_is_exported_at_the_top_level():
    """A user catches ``parakin.StoreInUseError`` without knowing the module it lives in: every
    exception and warning class of ``parakin.errors`` is in ``parakin.__all__``."""
    import inspect

    import parakin
    import parakin.errors as errors

    named = {
        name
        for name, value in vars(errors).items()
        if inspect.isclass(value) and issubclass(value, Warning | Exception) and value.__module__ == errors.__name__
    }
    assert len(named) >= 20
    assert named - set(parakin.__all__) == set()
    assert all(getattr(parakin, name) is getattr(errors, name) for name in named)
