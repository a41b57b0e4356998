"""A termination signal whose raise is swallowed by a C callback is raised again (hydrokit._atomic)."""

from __future__ import annotations

import ctypes
import os
import signal

import pytest

from hydrokit._atomic import Interrupted, interrupt_on_signals, raise_if_interrupted


def test_a_sigterm_swallowed_inside_a_c_callback_is_raised_at_the_next_check(monkeypatch):
    # numba's compiler calls back into Python while it caches; a signal handled there raises
    # into the callback, and ctypes prints "Exception ignored" and carries on. The next
    # raise_if_interrupted() must stop the work
    import sys

    reported: list[BaseException] = []  # what would be printed as "Exception ignored … Traceback"
    monkeypatch.setattr(sys, "unraisablehook", lambda u: reported.append(u.exc_value))
    callback = ctypes.CFUNCTYPE(None)(lambda: os.kill(os.getpid(), signal.SIGTERM))
    with interrupt_on_signals():
        raise_if_interrupted()  # nothing arrived yet: a no-op
        callback()  # the handler runs inside the callback; its Interrupted is swallowed
        swallowed = True  # still running: the raise did not reach this frame
        assert reported == []  # no "Exception ignored" traceback: stderr stays one line
        with pytest.raises(Interrupted) as err:
            raise_if_interrupted()
        assert swallowed and err.value.signum == signal.SIGTERM
    raise_if_interrupted()  # outside the block (and in the next one) nothing is pending
    with interrupt_on_signals():
        raise_if_interrupted()


def test_a_failure_after_a_swallowed_signal_is_reported_as_the_signal():
    # a SIGTERM landing inside numba's compiler is swallowed there and leaves the function half
    # built; the next call fails with numba's "no compiled object yet". The block reports the
    # signal (the CLI's "interrupted (SIGTERM)", exit 143), not an internal error. A failure
    # without a signal stays what it is
    callback = ctypes.CFUNCTYPE(None)(lambda: os.kill(os.getpid(), signal.SIGTERM))
    with pytest.raises(Interrupted) as err:
        with interrupt_on_signals():
            callback()
            raise RuntimeError("no compiled object yet")
    assert err.value.signum == signal.SIGTERM and isinstance(err.value.__cause__, RuntimeError)
    with pytest.raises(RuntimeError, match="a plain failure"):
        with interrupt_on_signals():
            raise RuntimeError("a plain failure")


@pytest.mark.filterwarnings("ignore::pytest.PytestUnraisableExceptionWarning")
def test_outputs_are_not_written_after_a_swallowed_signal(tmp_path):
    from hydrokit._atomic import write_files, write_text

    callback = ctypes.CFUNCTYPE(None)(lambda: os.kill(os.getpid(), signal.SIGTERM))
    with interrupt_on_signals():
        callback()
        with pytest.raises(Interrupted):
            write_files({tmp_path / "a.json": b"{}", tmp_path / "b.csv": b"x\\n"})
        with pytest.raises(Interrupted):
            write_text(tmp_path / "c.txt", "late")
    assert sorted(p.name for p in tmp_path.iterdir()) == []
    write_text(tmp_path / "c.txt", "after the block")  # a new command writes as usual
    assert (tmp_path / "c.txt").read_text() == "after the block"
