"""``play`` asks whether an X server answers before pyglet tries (and fails with an exception)."""

from __future__ import annotations

import socket
import sys

import pytest

from across_dimensions.app.display import display_problem, x_server_problem

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="X11 sockets are a Linux matter here")


def test_a_listening_socket_counts_as_a_server(monkeypatch):
    number = 933  # unusual: other programs may run real servers on low numbers
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as server:
        server.bind(f"\0/tmp/.X11-unix/X{number}")  # abstract: leaves no file behind
        server.listen(8)
        assert x_server_problem(f":{number}") is None
        assert x_server_problem(f":{number}.0") is None
        monkeypatch.setenv("DISPLAY", f":{number}")
        assert display_problem() is None
    problem = x_server_problem(f":{number}")
    assert problem and f"DISPLAY=:{number}" in problem and "\n" not in problem


def test_no_display_variable(monkeypatch):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    assert "DISPLAY is not set" in display_problem()


def test_a_remote_display_nobody_serves():
    problem = x_server_problem("127.0.0.1:934")  # TCP port 6934
    assert problem and "DISPLAY=127.0.0.1:934" in problem


def test_an_address_it_cannot_parse_is_left_to_pyglet():
    assert x_server_problem("not a display") is None
