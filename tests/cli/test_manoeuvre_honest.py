"""``hydrokit manoeuvre`` says what happened: refusals up front, units on what it prints, clean
numbers in manoeuvre.json (issue #49 item 3)."""

from __future__ import annotations

import pytest

from hydrokit.simulate import manoeuvre as M


@pytest.fixture
def never_flown(monkeypatch):
    """Make flying anything an error: a refusal must come before the approach starts."""

    def refuse(*a, **k):
        raise AssertionError("the manoeuvre was flown before the refusal")

    monkeypatch.setattr(M, "fly_manoeuvre", refuse)


@pytest.mark.parametrize("option", [("--depth-change", "5"), ("--vertical-zigzag", "10/10")])
def test_planar_vehicle_refuses_depth_manoeuvres_up_front(run_cli, tmp_path, never_flown, option):
    out = tmp_path / "dz"
    code, stdout, err = run_cli("manoeuvre", "mariner", "--out", out, *option, "--force", "727000,0,0,0,0,0")
    assert code == 2, err
    assert "vehicle 'mariner' is planar (dofs: surge, sway, yaw)" in err
    assert "expected a vehicle with heave and pitch in its dofs" in err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err and stdout == ""
    assert not out.exists() or not any(out.iterdir())
