"""The viewer driven as a user would, in headless Chromium (issue 36): every slider of stewart and
planar_3rpr pushed from the home towards each end of its range in steps. Each step either draws
the configuration that closes at the slider's value, or is refused with a message in the user's
terms (the mode's number, the input and where it stops, what is there; no solver vocabulary), the
drawing staying at a solved input between the home and the value asked for. Screenshots of where
each drive stopped are kept in the test's tmp_path. Skipped without chromium and chromedriver, as
test_viewer's browser test."""

import numpy as np
import pytest
from test_viewer import (  # noqa: F401 (fixtures: browser, chromium, loaded)
    _answered,
    _canvas,
    _drawn,
    _set_slider,
    _updates,
    _wait,
    browser,
    chromium,
    loaded,
)

from parakin.interfaces.viewer import serve

#: steps from the home to a slider's end (the page asks the server once per step)
STEPS = 8
API_WORDS = ("batch index", "guess", "tracker", "strict", "iterations", "Traceback")


@pytest.mark.parametrize("mechanism", ["planar_3rpr", pytest.param("stewart", marks=pytest.mark.slow)])
def test_a_scripted_drive_across_each_slider(browser, loaded, mechanism, tmp_path):  # noqa: F811
    from selenium.webdriver.common.by import By

    m = loaded(mechanism)
    refused = reached = 0
    with serve(m) as viewer:
        browser.get(viewer.url)
        _wait(browser, lambda: _updates(browser) >= 1, "the first state drawn")
        sliders = viewer.session.scene()["sliders"]
        for k, spec in enumerate(sliders):
            for end in ("high", "low"):
                # nothing in flight (a refused step's second request may be), then Home: the only
                # reply drawn after it is Home's (requested None), so the home read is Home's
                _wait(browser, lambda: not _drawn(browser)["busy"], "no slider request in flight")
                count = _updates(browser)
                browser.find_element(By.ID, "home").click()
                _wait(
                    browser,
                    lambda count=count: _updates(browser) > count and _drawn(browser)["requested"] is None,
                    "home drawn",
                )
                home = viewer.session.state()["actuated"]
                assert _drawn(browser)["actuated"] == home
                element = browser.find_element(By.ID, f"slider-{k}")
                for step in range(1, STEPS + 1):
                    value = home[k] + (spec[end] - home[k]) * step / STEPS
                    asked = _set_slider(browser, element, value)  # as the slider rounds it to its step
                    # the page keeps one request in flight and sends the latest values after it: wait
                    # until it has drawn the reply to this step's values and has nothing more to send
                    # (a reply drawn earlier may be the previous step's, or this step's first request
                    # answered while the second is in flight)
                    _wait(
                        browser,
                        lambda k=k, asked=asked: _answered(browser, k, asked),
                        f"the reply to {spec['name']} = {asked}",
                    )
                    # nothing in flight: the server's configuration is the one the page draws
                    state, drawn_reply = viewer.session.state(), _drawn(browser)
                    assert drawn_reply["actuated"] == state["actuated"]
                    box = browser.find_element(By.ID, "status")
                    assert ("bad" in box.get_attribute("class")) == (not drawn_reply["ok"]), box.text
                    if drawn_reply["ok"]:
                        # the drawn input is the slider's (as the page rounds it to the slider's step)
                        assert state["ok"] and state["actuated"][k] == pytest.approx(
                            asked, abs=1e-9 * max(1.0, abs(value))
                        )
                        assert float(element.get_attribute("value")) == asked
                        assert box.text.startswith("following mode"), box.text
                        continue
                    message = box.text
                    assert message.startswith("Mode ") and f"{spec['name']} = " in message, message
                    assert any(w in message for w in ("a fold", "type II singularity", "could not be followed"))
                    assert not any(word in message for word in API_WORDS), message
                    assert "choose another mode" in message, message
                    drawn = state["actuated"][k]
                    low, high = sorted((home[k], value))
                    assert low - 1e-12 <= drawn <= high + 1e-12, (drawn, home[k], value)
                    # the slider is put back where the drawing is
                    _wait(
                        browser,
                        lambda e=element, d=drawn, s=spec: (
                            float(e.get_attribute("value")) == pytest.approx(d, abs=s["step"])
                        ),
                        "the slider back at the drawn input",
                    )
                    _canvas(browser, tmp_path / f"{mechanism}_{spec['name']}_{end}.png")
                    refused += 1
                    break
                else:
                    assert viewer.session.state()["actuated"][k] == pytest.approx(spec[end], abs=2 * spec["step"])
                    reached += 1
        assert browser.get_log("browser") == []
    assert refused + reached == 2 * len(sliders)
    # the viewer's home has room to move (test_viewer_home): at least half the slider ends are
    # reached (from the paper's home 1 of planar_3rpr's 6 and 1 of stewart's 12 were)
    print(f"{mechanism}: {reached} of {2 * len(sliders)} slider ends reached, {refused} refused")
    assert reached >= len(sliders), (reached, refused)


def test_a_spherical_mechanism_is_drawn_on_its_sphere(browser, loaded, tmp_path):  # noqa: F811
    """spm: every drawn point lies on the unit sphere about the fixed centre (computed here from the
    drawing kernel's points), the page draws that sphere and arcs (as `parakin plot spm`) and labels
    it instead of a scale bar in metres (once "0.20 m" on a unit sphere)."""
    from selenium.webdriver.common.by import By

    m = loaded("spm")
    with serve(m) as viewer:
        sphere = viewer.session.scene()["sphere"]
        config = viewer.session._config
        points = np.concatenate([p for p in m.drawing(config).values()], axis=-1)
        radii = np.linalg.norm(points - np.asarray(config.pose)[:3, 3:], axis=0)
        assert sphere is not None and sphere["radius"] == pytest.approx(float(radii.mean()), rel=1e-9)
        assert np.ptp(radii) < 1e-9 and sphere["radius"] == pytest.approx(1.0)
        browser.get(viewer.url)
        _wait(browser, lambda: _updates(browser) >= 1, "the first state drawn")
        assert browser.execute_script("return document.body.dataset.scale") == "sphere"
        image = _canvas(browser, tmp_path / "spm_sphere.png")
        canvas = browser.find_element(By.ID, "view")
        # the silhouette: a light blue disc about the centre, out to the sphere's radius on screen
        height, width = image.shape[:2]
        tinted = (image.min(-1) >= 235) & (image.min(-1) < 255) & (image[..., 2] > image[..., 0])
        assert tinted.mean() > 0.2, f"no sphere drawn ({tinted.mean():.1%} of the canvas tinted)"
        assert canvas.size["width"] > 0 and width > 0 and height > 0
        assert browser.get_log("browser") == []
