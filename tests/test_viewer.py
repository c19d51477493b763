"""The interactive viewer (parakin.interfaces.viewer): its server drives the tracker for every mechanism, follows
the mode asked for, names every refusal, and its page works in a real headless browser (Debian's
chromium and chromium-driver through selenium), checked on screenshots."""

import io
import json
import os
import shutil
import subprocess
import sys
import urllib.error
import urllib.request
import warnings

import numpy as np
import pytest

import parakin
from parakin.errors import BadInputError
from parakin.interfaces.viewer import ViewerSession, main, serve, show
from parakin.results import Configuration

NAMES = parakin.available()
#: a slider nudge, as a fraction of each slider's range: small enough that every mechanism's home
#: configuration tracks it without meeting a singularity (stewart's Dietmaier home, 40 real modes
#: packed close, meets one 0.5 % of l1's range away in one direction)
NUDGE = -0.01


@pytest.fixture(scope="module")
def loaded():
    """One mechanism per name (compiled when available), loaded once for this module."""
    cache = {}

    def load(name):
        if name not in cache:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # a NumPy fallback warns; the viewer works on any backend
                cache[name] = parakin.load(name)
        return cache[name]

    return load


def _nudged(session, fraction=NUDGE):
    """Every slider moved by ``fraction`` of its range from the current input (SI values)."""
    sliders = session.scene()["sliders"]
    here = session.state()["actuated"]
    return [value + fraction * (s["high"] - s["low"]) for value, s in zip(here, sliders, strict=True)]


# ---------------------------------------------------------------------------- the server, no browser
# parametrised as `mechanism`, not `name`: no all-modes solve here, so even the heavy families run
@pytest.mark.parametrize("mechanism", NAMES)
def test_a_slider_move_draws_a_configuration_that_closes_at_the_requested_input(loaded, mechanism):
    m = loaded(mechanism)
    session = ViewerSession(m)
    target = _nudged(session)
    reply = session.move(target)
    assert reply["ok"], reply["error"]
    assert reply["error"] is None
    np.testing.assert_array_equal(reply["actuated"], target)  # the tracker solved this very input
    passive = np.array(reply["passive"], dtype=float)
    scale = max(1.0, session.scene()["scale"])
    if m.passive_names:  # the loop closes at the requested input, to the tracker's tolerance
        closure = np.abs(m.loop_closure(target, passive)["residual"]).max()
        assert closure <= 1e-10 * scale, f"{mechanism}: closure residual {closure:.3g} at the requested input"
        assert reply["residual"] == pytest.approx(closure, abs=1e-15)
    config = Configuration(np.array(target), passive, m.platform_pose(target, passive))
    drawing = m.drawing(config)
    assert set(reply["polylines"]) == set(m.capabilities.drawing.polylines)
    for line, vertices in m.capabilities.drawing.polylines.items():
        expected = np.stack([drawing[s][:, i] for s, i in vertices], axis=-1)
        np.testing.assert_allclose(reply["polylines"][line], expected, atol=1e-12 * scale, err_msg=line)
    measures = m.singularities(config)
    assert [n for n, _ in reply["measures"]] == list(measures)
    np.testing.assert_allclose([v for _, v in reply["measures"]], [float(v) for v in measures.values()], rtol=1e-9)


@pytest.mark.parametrize("mechanism", NAMES)
def test_a_value_outside_an_actuators_range_is_refused_by_its_named_error(loaded, mechanism):
    m = loaded(mechanism)
    session = ViewerSession(m)
    before = session.state()
    low, _ = m.actuated_bounds
    target = list(before["actuated"])
    target[0] = float(low[0]) - 1.0 - abs(float(low[0]))  # below the range every solver checks
    reply = session.move(target)
    with pytest.raises(BadInputError) as solver:
        m.forward_pose(target)
    assert not reply["ok"]
    assert reply["error"] == {"type": "BadInputError", "message": str(solver.value)}
    assert "outside its range" in reply["error"]["message"]
    assert reply["actuated"] == before["actuated"]  # nothing moved
    assert reply["requested"] == target


@pytest.mark.parametrize("name", NAMES)  # `name`: conftest skips the heavy all-modes families by default
def test_choosing_a_mode_restarts_the_tracker_there(loaded, name):
    m = loaded(name)
    session = ViewerSession(m)
    home = np.array(session.state()["actuated"])
    listing = session.modes()
    modes = m.forward_pose_all(home)
    assert listing["ok"] and listing["count"] == len(modes) >= 1
    assert listing["current"] is not None, "the home configuration is one of its input's modes"
    assert session.state()["mode"] == listing["current"]
    chosen = len(modes) - 1 if listing["current"] != len(modes) - 1 else 0
    reply = session.select(chosen)
    assert reply["ok"], reply["error"]
    assert reply["mode"] == chosen, f"{name}: asked for mode {chosen} of {len(modes)}, drew mode {reply['mode']}"
    np.testing.assert_allclose(
        reply["pose"], parakin.xyz_euler_deg_from_pose(modes.mode(chosen).pose), atol=1e-7, err_msg="mode pose"
    )
    assert session.modes()["current"] == chosen
    # the tracker now follows the chosen mode: a move starts from it
    moved = session.move(_nudged(session, 0.001))
    assert moved["ok"] or moved["error"]["type"] in ("AssemblyModeChangeError", "ConvergenceError")
    missing = session.select(len(modes))
    assert not missing["ok"] and missing["error"]["type"] == "NoSuchModeError"
    assert f"there are {len(modes)} modes" in missing["error"]["message"]


def test_a_step_across_a_singularity_is_reported_not_taken(loaded):
    """Stewart's Dietmaier home: l1 + 0.05 m crosses a type II singularity (or ends the branch):
    the move stops at the last input tracked on the branch, with the tracker's error."""
    m = loaded("stewart")
    # started at the paper's home itself (the viewer's own home has room to move: test_viewer_home)
    session = ViewerSession(m, start=m.forward_pose(m.home_actuated, guess=m.home_passive))
    home = session.state()
    target = list(home["actuated"])
    target[0] += 0.05
    reply = session.move(target)
    assert not reply["ok"]
    assert reply["error"]["type"] in ("AssemblyModeChangeError", "ConvergenceError", "SingularConfigurationError")
    assert home["actuated"][0] <= reply["actuated"][0] < target[0]
    assert reply["residual"] < 1e-10  # what is drawn still closes, at the input it shows
    again = session.select(home["mode"] if home["mode"] is not None else 0, home["actuated"])
    assert again["ok"]


def test_the_server_answers_over_http(loaded):
    m = loaded("planar_3rpr")
    with serve(m) as viewer:
        page = urllib.request.urlopen(viewer.url, timeout=10).read().decode()
        assert "<canvas" in page and "http://" not in page and "https://" not in page  # self-contained

        def post(path, body):
            request = urllib.request.Request(viewer.url + path, data=body, headers={"Content-Type": "application/json"})
            try:
                return 200, json.loads(urllib.request.urlopen(request, timeout=10).read())
            except urllib.error.HTTPError as error:
                return error.code, json.loads(error.read())

        status, scene = post("api/scene", b"{}")
        assert status == 200 and [s["name"] for s in scene["sliders"]] == m.actuated_names and scene["planar"]
        status, reply = post("api/move", json.dumps({"actuated": _nudged(viewer.session)}).encode())
        assert status == 200 and reply["ok"]
        assert post("api/move", b"not json")[0] == 400
        status, reply = post("api/nothing", b"{}")
        assert status == 400 and reply["error"]["type"] == "BadInputError"
        status, reply = post("api/move", json.dumps({"actuated": ["a", 1, 2]}).encode())
        assert status == 200 and reply["error"]["type"] == "BadInputError"
        assert viewer.url in viewer._repr_html_() and "<iframe" in viewer._repr_html_()
    with pytest.raises(OSError):
        urllib.request.urlopen(viewer.url, timeout=2)


def test_show_and_the_module_entry(loaded):
    frame = show(loaded("five_bar"))
    viewer = getattr(frame, "viewer", frame)  # an IPython IFrame keeps its viewer; else the Viewer
    assert viewer.url.startswith("http://127.0.0.1:")
    viewer.close()
    assert main(["no_such_mechanism"]) == 2
    process = subprocess.Popen(
        [sys.executable, "-m", "parakin.interfaces.viewer", "five_bar", "--port", "0"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        url = process.stdout.readline().strip()
        assert url.startswith("http://127.0.0.1:"), process.stderr.read() if process.poll() is not None else url
        assert b"<canvas" in urllib.request.urlopen(url, timeout=10).read()
    finally:
        process.terminate()
        process.wait(timeout=10)


# ---------------------------------------------------------------------------- a real headless browser
CHROMIUM = os.environ.get("PARAKIN_CHROMIUM") or shutil.which("chromium") or "/usr/bin/chromium"
CHROMEDRIVER = os.environ.get("PARAKIN_CHROMEDRIVER") or shutil.which("chromedriver") or "/usr/bin/chromedriver"


@pytest.fixture(scope="module")
def chromium(tmp_path_factory):
    """Headless chromium driven by selenium, one per module (and xdist worker); skipped with the
    reason when either is missing. Tests take it through ``browser``."""
    webdriver = pytest.importorskip("selenium.webdriver", reason="selenium is not installed (pip install selenium)")
    pytest.importorskip("PIL", reason="Pillow is not installed (it reads the screenshots)")
    for path, package in ((CHROMIUM, "chromium"), (CHROMEDRIVER, "chromium-driver")):
        if not os.access(path, os.X_OK):
            pytest.skip(f"no {path}: apt-get install -y {package} (the browser test needs chromium and chromedriver)")
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for flag in (
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--window-size=1400,1000",
        f"--user-data-dir={tmp_path_factory.mktemp('chromium-profile')}",
    ):
        options.add_argument(flag)
    from selenium.webdriver.chrome.service import Service

    driver = webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)
    driver.set_page_load_timeout(60)
    yield driver
    driver.quit()


def _leave_page(driver) -> None:
    """The browser on about:blank and its console log drained: the page of an earlier test, whose
    viewer server has closed, can request nothing more (its mode list was still asking /api/modes:
    'ERR_CONNECTION_REFUSED' in the next test's log), and what it logged is not the next test's."""
    driver.get("about:blank")
    driver.get_log("browser")


@pytest.fixture
def browser(chromium):
    """The module's browser for one test: it starts and ends on about:blank with an empty log, so
    that ``get_log("browser") == []`` in a test speaks of that test's page alone."""
    _leave_page(chromium)
    yield chromium
    _leave_page(chromium)


def _updates(driver) -> int:
    return int(driver.execute_script("return document.body.dataset.updates || '0'"))


def _canvas(driver, path):
    """The drawing area as an RGB array; the whole page saved to ``path`` for people to look at."""
    from PIL import Image
    from selenium.webdriver.common.by import By

    driver.save_screenshot(str(path))
    png = driver.find_element(By.ID, "view").screenshot_as_png
    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB"), dtype=np.int16)


def _drawn_fraction(image) -> float:
    """The share of the drawing area's pixels that are not its white background."""
    return float((np.abs(image - 255).max(-1) > 40).mean())


#: the longest wait for the page (s): a bound, not a measure; a loaded machine (CI at a load of 9,
#: ``pytest -n 2``) has taken seconds for one refused stewart step (bisection, then its modes)
WAIT = 90.0


def _wait(driver, condition, what):
    from selenium.webdriver.support.ui import WebDriverWait

    WebDriverWait(driver, WAIT, poll_frequency=0.05).until(lambda d: condition(), message=what)


def _set_slider(driver, slider, value) -> float:
    """Slider ``slider`` moved to ``value`` as a user would (its value, then the input and change
    events); the value it took (rounded to its step), as the page reads it."""
    return float(
        driver.execute_script(
            "const s = arguments[0]; s.value = arguments[1]; const taken = parseFloat(s.value);"
            "s.dispatchEvent(new Event('input')); s.dispatchEvent(new Event('change')); return taken;",
            slider,
            value,
        )
    )


def _drawn(driver) -> dict:
    """The reply the page draws now (its ``current``): ok, requested (the slider values it
    answers; None for Home and a mode choice) and the actuated values drawn; and whether a slider
    request is in flight or pending (``busy``: the page sends one at a time, the latest after)."""
    return driver.execute_script(
        "return {busy: moving !== null || movePending, ok: current ? current.ok : null,"
        " requested: current ? current.requested : null, actuated: current ? current.actuated : null};"
    )


def _answered(driver, k, value) -> bool:
    """The page has drawn the reply to the request of slider ``k`` at ``value`` and sends nothing
    more: the reply to this step, not to an earlier one still in flight when the slider moved."""
    drawn = _drawn(driver)
    requested = drawn["requested"]
    return (
        not drawn["busy"]
        and isinstance(requested, list)
        and abs(float(requested[k]) - value) <= 1e-12 * max(1.0, abs(value))
    )


def test_a_closed_viewers_page_is_left_before_the_next_test(browser, loaded):
    """The failure the ``browser`` fixture prevents, reproduced: a page whose viewer server has
    closed logs its next request as refused (as the mode list's /api/modes did into the spm test's
    log on CI); leaving the page (about:blank, the log drained) leaves nothing for the next test."""
    with serve(loaded("planar_3rpr")) as viewer:
        browser.get(viewer.url)
        _wait(browser, lambda: _updates(browser) >= 1, "the first state drawn")
    browser.execute_script("call('modes', {}).catch(() => null)")  # the page asks once more
    _wait(browser, lambda: (log := browser.get_log("browser")) and _refused(log), "the refused request logged")
    browser.execute_script("call('modes', {}).catch(() => null)")
    _leave_page(browser)
    assert browser.current_url == "about:blank" and browser.get_log("browser") == []


def _refused(log: list[dict]) -> bool:
    return any("ERR_CONNECTION_REFUSED" in entry["message"] and "/api/modes" in entry["message"] for entry in log)


@pytest.mark.parametrize("mechanism", ["planar_3rpr", "stewart"])
def test_the_page_in_a_headless_browser(browser, loaded, mechanism, tmp_path):
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.by import By

    m = loaded(mechanism)
    with serve(m) as viewer:
        browser.get(viewer.url)
        _wait(browser, lambda: _updates(browser) >= 1, "the first state drawn")
        _wait(browser, lambda: browser.find_elements(By.CSS_SELECTOR, "#modes tr.drawn"), "the mode list")
        before = _canvas(browser, tmp_path / f"{mechanism}_home.png")
        measures = browser.find_element(By.ID, "measures").text
        status = browser.find_element(By.ID, "status").text
        assert _drawn_fraction(before) > 0.005, "the drawing area is blank"
        assert status.startswith("following mode"), status
        assert all(name in measures for name in m.singularities(viewer.session._config)), measures
        assert browser.get_log("browser") == []  # no script error, no failed request

        # a slider moved as a user would (its value, then the input and change events)
        slider = browser.find_element(By.ID, "slider-0")
        low, high = (float(slider.get_attribute(a)) for a in ("min", "max"))
        asked = _set_slider(browser, slider, float(slider.get_attribute("value")) + NUDGE * (high - low))
        _wait(browser, lambda: _answered(browser, 0, asked), "the reply to the slider")
        _wait(
            browser,
            lambda: browser.find_elements(By.CSS_SELECTOR, "#modebox:not(.stale) #modes tr.drawn"),
            "the new input's modes, the drawn one marked",
        )
        after = _canvas(browser, tmp_path / f"{mechanism}_moved.png")
        status = browser.find_element(By.ID, "status").text
        assert status.startswith("following mode"), status
        assert browser.find_element(By.ID, "measures").text != measures, "the measures did not update"
        changed = float((np.abs(after - before).max(-1) > 40).mean())
        assert changed > 0.001, f"the drawing did not change with the slider ({changed:.2%} of pixels)"
        assert _drawn(browser)["actuated"] == viewer.session.state()["actuated"]  # what the server holds
        assert viewer.session.state()["actuated"][0] == pytest.approx(asked, abs=1e-12)
        assert asked == pytest.approx(float(slider.get_attribute("value")), abs=1e-12)

        # choosing another assembly mode redraws it and says so
        rows = browser.find_elements(By.CSS_SELECTOR, "#modes tbody tr")
        drawn = browser.find_element(By.CSS_SELECTOR, "#modes tr.drawn").get_attribute("data-mode")
        other = next(row for row in rows if row.get_attribute("data-mode") != drawn)
        wanted = other.get_attribute("data-mode")
        count = _updates(browser)
        browser.execute_script("arguments[0].scrollIntoView({block: 'center'})", other)
        other.click()
        _wait(browser, lambda: _updates(browser) > count, "the reply to the mode choice")
        _wait(
            browser,
            lambda: browser.find_element(By.ID, "status").text.startswith(f"following mode {wanted}"),
            f"mode {wanted} followed",
        )
        chosen = _canvas(browser, tmp_path / f"{mechanism}_mode{wanted}.png")
        assert float((np.abs(chosen - after).max(-1) > 40).mean()) > 0.001, "another mode, the same drawing"

        if not viewer.session.scene()["planar"]:  # 3-D: a mouse drag orbits the view
            canvas = browser.find_element(By.ID, "view")
            ActionChains(browser).move_to_element(canvas).click_and_hold().move_by_offset(120, 40).release().perform()
            orbited = _canvas(browser, tmp_path / f"{mechanism}_orbited.png")
            assert float((np.abs(orbited - chosen).max(-1) > 40).mean()) > 0.001, "the drag did not orbit"
        assert browser.get_log("browser") == []
