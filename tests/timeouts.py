"""A call that must return in time, for tests of inputs that could block (a FIFO, a device)."""

from __future__ import annotations

import threading

import pytest


def within(seconds: float, fn, *args):
    """``fn(*args)`` in a daemon thread: its result or exception, or a failure if it has
    not returned after ``seconds`` (a blocked open cannot hang the test run)."""
    box: dict[str, object] = {}

    def target() -> None:
        try:
            box["value"] = fn(*args)
        except BaseException as exc:  # noqa: BLE001 - handed to the caller
            box["error"] = exc

    t = threading.Thread(target=target, daemon=True)
    t.start()
    t.join(seconds)
    if t.is_alive():
        pytest.fail(f"{fn.__name__} did not return within {seconds} s")
    if "error" in box:
        raise box["error"]  # type: ignore[misc]
    return box["value"]
