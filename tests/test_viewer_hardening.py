"""The viewer's server against hostile requests and its wording for users (issue 31, items 9, 11 and
the viewer part of 16), driven over real sockets on localhost.

- Only the viewer's own address may be named in Host and Origin (a DNS-rebinding page names its
  own host; a cross-origin page sends its own origin), POSTs are application/json only (a "simple"
  cross-origin text/plain POST runs without a CORS preflight), and GET never changes state.
- Every malformed request gets a JSON error reply: nothing drops the connection, nothing hangs a
  server thread forever.
- A followed assembly mode keeps its number while it is followed; a refused move says what
  happened in the user's terms.
"""

import json
import re
import socket
import time
import warnings

import numpy as np
import pytest

import parakin
from parakin.interfaces import viewer as viewer_module
from parakin.interfaces.viewer import ViewerSession, serve


@pytest.fixture(scope="module")
def planar():
    """planar_3rpr (closed-form modes, a few milliseconds each), loaded once."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a NumPy fallback warns; the viewer works on any backend
        return parakin.load("planar_3rpr")


@pytest.fixture(scope="module")
def server(planar):
    """One server for the module: every test compares the state with its own start."""
    with serve(planar) as running:
        yield running


def _exchange(viewer, raw: bytes, timeout: float = 10.0) -> tuple[int, dict, bytes]:
    """Send ``raw`` bytes, read the reply to the end: status, headers (lower-case names), body."""
    with socket.create_connection((viewer.host, viewer.port), timeout=timeout) as sock:
        sock.sendall(raw)
        reply = b""
        while chunk := sock.recv(65536):
            reply += chunk
    head, _, body = reply.partition(b"\r\n\r\n")
    lines = head.decode("latin-1").split("\r\n")
    assert lines[0].startswith("HTTP/"), f"no HTTP reply: {reply[:200]!r}"
    headers = dict(line.split(":", 1) for line in lines[1:] if ":" in line)
    return int(lines[0].split()[1]), {k.strip().lower(): v.strip() for k, v in headers.items()}, body


def _request(viewer, method: str, path: str, body: bytes = b"", headers: dict | None = None) -> tuple[int, dict]:
    """One HTTP request with the viewer's own Host unless ``headers`` says otherwise; the reply's
    status and its JSON body (parsed strictly: NaN or Infinity in it fail)."""
    fields = {"Host": f"127.0.0.1:{viewer.port}", "Content-Length": str(len(body))}
    if method == "POST":
        fields["Content-Type"] = "application/json"
    fields.update(headers or {})
    head = f"{method} {path} HTTP/1.1\r\n" + "".join(f"{k}: {v}\r\n" for k, v in fields.items() if v is not None)
    status, reply_headers, data = _exchange(viewer, head.encode("latin-1") + b"Connection: close\r\n\r\n" + body)
    assert reply_headers.get("content-type", "").startswith("application/json"), (status, reply_headers, data[:200])
    return status, json.loads(data, parse_constant=_refuse)


def _refuse(name: str) -> None:
    raise AssertionError(f"the reply holds {name}: not JSON")


def _error_reply(reply: dict) -> str:
    assert reply["ok"] is False and reply["error"]["message"], reply
    return reply["error"]["message"]


# ---------------------------------------------------------------------------- item 9: who may ask
@pytest.mark.parametrize("host", ["evil.example", "evil.example:{port}", "127.0.0.1:1", "localhost.evil.example"])
def test_a_foreign_host_header_is_refused(server, host):
    """DNS rebinding: a page on evil.example whose name now resolves to 127.0.0.1 sends Host:
    evil.example[:port]; the viewer answers it with an error, on the page and on the API."""
    named = host.format(port=server.port)
    for method, path in (("GET", "/"), ("POST", "/api/state"), ("GET", "/api/state")):
        status, reply = _request(server, method, path, b"{}" if method == "POST" else b"", {"Host": named})
        assert status == 403, (method, path, status, reply)
        assert named.split(":")[0] in _error_reply(reply)


def test_the_viewers_own_names_are_accepted(server):
    for host in (f"127.0.0.1:{server.port}", f"localhost:{server.port}", f"LOCALHOST:{server.port}"):
        status, reply = _request(server, "POST", "/api/state", b"{}", {"Host": host, "Origin": f"http://{host}"})
        assert status == 200 and reply["ok"], (host, reply)


def test_a_cross_origin_post_is_refused(server):
    before = server.session.state()["actuated"]
    body = json.dumps({"actuated": [v * 1.001 for v in before]}).encode()
    for origin in (
        "http://evil.example",
        f"http://evil.example:{server.port}",
        "null",
        f"https://127.0.0.1:{server.port}",
    ):
        status, reply = _request(server, "POST", "/api/move", body, {"Origin": origin})
        assert status == 403, (origin, status, reply)
        assert "origin" in _error_reply(reply).lower()
    assert server.session.state()["actuated"] == before  # nothing moved


@pytest.mark.parametrize(
    "content_type", ["text/plain", "text/plain;charset=UTF-8", "application/x-www-form-urlencoded", None]
)
def test_a_post_that_is_not_declared_json_is_refused(server, content_type):
    """A cross-origin page may POST text/plain without a CORS preflight: such a body is never run."""
    before = server.session.state()["actuated"]
    body = json.dumps({"actuated": [v * 1.001 for v in before]}).encode()
    status, reply = _request(server, "POST", "/api/move", body, {"Content-Type": content_type})
    assert status == 415, (status, reply)
    assert "application/json" in _error_reply(reply)
    assert server.session.state()["actuated"] == before


def test_get_never_changes_state(server):
    home = server.session.state()["actuated"]
    status, moved = _request(server, "POST", "/api/move", json.dumps({"actuated": [v * 1.001 for v in home]}).encode())
    assert status == 200 and moved["ok"], moved
    for call in ("home", "move", "select", "modes"):
        status, reply = _request(server, "GET", f"/api/{call}")
        assert status == 405, (call, status, reply)
        assert "POST" in _error_reply(reply)
    assert server.session.state()["actuated"] == moved["actuated"]  # still where the POST put it
    status, state = _request(server, "GET", "/api/state")  # reading stays possible
    assert status == 200 and state["actuated"] == moved["actuated"]


# ---------------------------------------------------------------------------- item 11: malformed requests
NESTED = b'{"actuated": ' + b"[" * 20000 + b"]" * 20000 + b"}"
BODIES = {
    "NaN": b'{"actuated": [NaN, 15, 13]}',
    "Infinity": b'{"actuated": [Infinity, 15, 13]}',
    "-Infinity": b'{"mode": -Infinity}',
    "1e400": b'{"actuated": [1e400, 15, 13]}',
    "a 400-digit integer": b'{"actuated": [1' + b"0" * 400 + b", 15, 13]}",
    "20000 nested brackets": NESTED,
    "10000 nested objects": b'{"a":' * 10000 + b"1" + b"}" * 10000,
    "not JSON": b"not json",
    "a list": b"[1, 2, 3]",
    "not UTF-8": b'{"actuated": "\xff\xfe"}',
}


@pytest.mark.parametrize("what", list(BODIES))
def test_a_malformed_body_gets_a_400_json_reply(server, what):
    before = server.session.state()["actuated"]
    status, reply = _request(server, "POST", "/api/move", BODIES[what])
    assert status == 400, (what, status, reply)
    message = _error_reply(reply)
    assert len(message) < 500, f"the reply echoes the whole body: {message[:200]}..."
    assert server.session.state()["actuated"] == before


@pytest.mark.parametrize("length", ["abc", "-5", "1e3", "  ", "12, 13"])
def test_a_bad_content_length_gets_a_400_json_reply(server, length):
    status, reply = _request(server, "POST", "/api/state", b"{}", {"Content-Length": length})
    assert status == 400, (length, status, reply)
    assert "Content-Length" in _error_reply(reply)


def test_an_oversized_body_gets_a_413_json_reply_read_to_the_end(server):
    """The body is read (and dropped) before the reply, so the client sees the reply rather than a
    connection reset for the bytes it was still sending."""
    body = b'{"actuated": [' + b" " * (8 * viewer_module.MAX_BODY) + b"]}"
    status, reply = _request(server, "POST", "/api/move", body)
    assert status == 413, (status, reply)
    assert str(viewer_module.MAX_BODY) in _error_reply(reply)


def test_a_malformed_request_line_gets_a_json_reply(server):
    status, headers, body = _exchange(server, b"GET / / HTTP/1.1\r\n\r\n")
    assert status == 400 and headers["content-type"].startswith("application/json")
    assert not json.loads(body)["ok"]
    status, headers, body = _exchange(
        server, f"PUT /api/move HTTP/1.1\r\nHost: 127.0.0.1:{server.port}\r\n\r\n".encode()
    )
    assert status in (405, 501) and headers["content-type"].startswith("application/json")
    assert not json.loads(body)["ok"]


def test_a_silent_client_is_dropped_after_the_timeout(planar, monkeypatch):
    """A client that connects and sends nothing (or stops half-way) does not hold a server thread
    forever: the socket times out and the server closes it, other clients being served meanwhile."""
    monkeypatch.setattr(viewer_module, "REQUEST_TIMEOUT", 0.5, raising=False)
    with serve(planar) as running:
        silent = socket.create_connection((running.host, running.port), timeout=5)
        half = socket.create_connection((running.host, running.port), timeout=5)
        half.sendall(f"POST /api/state HTTP/1.1\r\nHost: 127.0.0.1:{running.port}\r\nContent-Length: 10\r\n".encode())
        status, reply = _request(running, "POST", "/api/state", b"{}")  # served meanwhile
        assert status == 200 and reply["ok"]
        start = time.monotonic()
        try:
            assert silent.recv(1024) == b""  # closed by the server, not by our own 5 s timeout
            half.recv(65536)  # a 408 reply or nothing, then the close
            while half.recv(65536):
                pass
        except TimeoutError:
            pytest.fail("the server kept a silent connection open for 5 s")
        finally:
            silent.close()
            half.close()
        assert time.monotonic() - start < 4


# ---------------------------------------------------------------------------- item 16: mode numbers and wording
def _drawn_row(listing: dict) -> list[str] | None:
    rows = [row for row in listing["rows"] if int(row[0]) == listing["current"]]
    return rows[0] if rows else None


#: walks from planar_3rpr's home (mode chosen, slider, direction) along which, in the solver's own
#: order, the followed mode changes number (two modes swap places; none is created or lost): the
#: first one still doing so is used
WALKS = [(1, 0, 1), (1, 1, -1), (2, 0, 1), (2, 1, -1), (0, 0, 1), (0, 1, 1), (3, 0, 1), (4, 2, -1)]


def _at_paper_home(m) -> ViewerSession:
    """A session started at the manifest's home (the paper's input, 6 modes), not at the viewer's
    own home with room to move (tests/test_viewer_home.py): the walks below start there."""
    return ViewerSession(m, start=m.forward_pose(m.home_actuated, guess=m.home_passive))


def _solver_number(m, reply) -> int:
    """The followed configuration's number in the solver's own order at its input."""
    modes = m.forward_pose_all(reply["actuated"])
    found = [k for k in range(len(modes)) if np.allclose(modes.mode(k).passive, reply["passive"], atol=1e-7)]
    assert len(found) == 1, found
    return found[0]


def test_a_followed_mode_keeps_its_number(planar):
    """planar_3rpr from home, a mode chosen, one slider moved in small steps: in the solver's own
    order the followed mode changes number on the way; the viewer goes on calling it by the number
    it was chosen by, in each move's reply, in its state and in its table (whose numbers stay 0 to
    count - 1), and a number from the table selects that row."""
    session = _at_paper_home(planar)
    home = session.state()["actuated"]
    sliders = session.scene()["sliders"]
    components = session.scene()["pose_components"]
    assert session.modes()["headers"] == ["mode", "x [m]", "y [m]", "phi [deg]", "conditioning"]
    for mode, k, direction in WALKS:
        session.home()
        assert session.modes()["count"] == 6
        reply = session.select(mode, home)
        assert reply["ok"] and reply["mode"] == mode
        numbers = {_solver_number(planar, reply)}
        called = []  # what each move's own reply calls the followed mode (before any table of its input)
        for step in range(1, 41):
            target = list(home)
            target[k] += direction * step * (sliders[k]["high"] - sliders[k]["low"]) / 400
            reply = session.move(target)
            if not reply["ok"]:
                break  # the walk ends at a fold: what it did so far still counts
            listing = session.modes()
            assert listing["current"] == mode, f"step {step}: the table marks mode {listing['current']}, not {mode}"
            assert session.state()["mode"] == mode
            called.append(reply["mode"])
            row = _drawn_row(listing)
            # the table's columns are the pose kind's (x, y, phi): those of the reply's six
            shown = [reply["pose"][i] for i in components]
            np.testing.assert_allclose([float(v) for v in row[1:-1]], shown, rtol=1e-5, atol=1e-6)
            assert sorted(int(r[0]) for r in listing["rows"]) == list(range(listing["count"]))
            numbers.add(_solver_number(planar, reply))
        assert called == [mode] * len(called), called
        if len(numbers) > 1:
            break
    else:
        pytest.fail("the premise: on no walk does the solver's own order renumber the followed mode")
    other = next(r for r in listing["rows"] if int(r[0]) != mode)
    chosen = session.select(int(other[0]), reply["actuated"])
    assert chosen["ok"] and chosen["mode"] == int(other[0])
    shown = [chosen["pose"][i] for i in components]
    np.testing.assert_allclose(shown, [float(v) for v in other[1:-1]], rtol=1e-5, atol=1e-6)


def test_a_move_past_a_fold_says_so_in_the_users_terms(planar):
    """rho1 pushed to its top: the followed mode ends at a fold of the forward kinematics (it meets
    another mode; beyond, both are gone). The message names the input and where, and is true: the
    configuration is singular there and the input just beyond has two modes fewer."""
    session = _at_paper_home(planar)
    home = session.state()["actuated"]
    target = list(home)
    slider = session.scene()["sliders"][0]
    target[0] = slider["high"]
    reply = session.move(target)
    assert not reply["ok"]
    message = reply["error"]["message"]
    for api_word in ("batch index", "guess", "tracker", "strict", "iterations"):
        assert api_word not in message, message
    assert "fold" in message and "choose another mode or step back" in message, message
    found = re.search(r"rho1 = ([0-9.]+) m", message)
    assert found, message
    fold = float(found.group(1))
    drawn = reply["actuated"][0]
    piece = (slider["high"] - slider["low"]) / viewer_module.TRACK_PIECES  # the step the tracker refused
    assert drawn < fold < drawn + piece, (drawn, fold, message)
    before = list(reply["actuated"])
    beyond = list(reply["actuated"])
    beyond[0] = fold + 1e-4 * (fold - home[0])
    assert len(planar.forward_pose_all(beyond)) == len(planar.forward_pose_all(before)) - 2


def test_a_mode_the_input_lacks_is_named_with_the_modes_it_has(planar):
    session = _at_paper_home(planar)
    session.modes()
    reply = session.select(99)
    assert reply["error"]["type"] == "NoSuchModeError"
    message = reply["error"]["message"]
    assert "no mode 99" in message and "there are 6 modes" in message and "slot" not in message, message
