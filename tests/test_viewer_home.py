"""The viewer's home has room to move (issue 36, item 4): stewart's Dietmaier input (40 real modes
packed close) and planar_3rpr's paper input sit a few percent of a slider's range from a fold, so
most sliders stopped at once. The viewer starts instead at a closed configuration near the
manifest's home chosen for room (a seeded search: the same start every time), which is a mode its
input's list shows. Measured by driving the session itself: every slider moved by a tenth of its
range either way from the home is followed without a refusal, where from the paper's home most
are refused."""

import warnings

import numpy as np
import pytest

import parakin
from parakin.interfaces.viewer import ViewerSession

SHARE = 0.1


def _refused(session: ViewerSession, start) -> list[str]:
    """The slider moves (name and sign) refused from ``start``, a tenth of each range either way."""
    refused = []
    for k, slider in enumerate(session.scene()["sliders"]):
        for sign in (1.0, -1.0):
            session._config = session._restart(start)
            target = np.array(start.actuated, dtype=float)
            target[k] = np.clip(
                target[k] + sign * SHARE * (slider["high"] - slider["low"]), slider["low"], slider["high"]
            )
            if not session.move(target.tolist())["ok"]:
                refused.append(f"{slider['name']}{'+' if sign > 0 else '-'}")
    return refused


@pytest.mark.parametrize(("name", "refused_before"), [("stewart", 8), ("planar_3rpr", 2)])
def test_the_viewer_starts_with_room_to_move(name, refused_before):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a NumPy fallback warns; either backend will do
        m = parakin.load(name)
    session = ViewerSession(m)
    start = session._home()
    assert np.abs(start.actuated - m.home_actuated).max() > 0  # it moved away from the paper's input
    state = session.state()
    assert state["ok"] and state["residual"] < 1e-10  # it closes
    assert session.modes()["current"] is not None  # and is one of its input's listed modes
    assert [s["home"] for s in session.scene()["sliders"]] == pytest.approx(list(start.actuated))
    assert _refused(session, start) == []
    paper = m.forward_pose(m.home_actuated, guess=m.home_passive)
    assert len(_refused(session, paper)) >= refused_before
    # the same start every time
    np.testing.assert_array_equal(ViewerSession(m)._home().actuated, start.actuated)
