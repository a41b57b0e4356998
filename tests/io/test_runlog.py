"""Run files of ``hydrokit sysid`` (issue #44): the frozen CSV contract and its bad inputs."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

from hydrokit.errors import InputError
from hydrokit.io.runlog import read_run, run_csv

THRUSTERS = ("A", "B")


def _write(tmp_path: Path, text: str, name: str = "run.csv") -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


def test_round_trip_keeps_gaps_rates_and_unwraps_psi(tmp_path: Path) -> None:
    # a yaw angle turning through +π: the file holds it wrapped, the reader gives the continuous
    # angle back (independent: the series the file was made from)
    t = np.arange(0.0, 2.0, 0.02)
    psi_true = 3.0 + 0.8 * t
    z = np.full(t.size, np.nan)
    z[::5] = 1.0 + 0.1 * t[::5]  # depth at 10 Hz: empty cells between
    text = run_csv(t, {"psi": np.angle(np.exp(1j * psi_true)), "z": z}, {"A": np.sin(t), "B": np.cos(t)})
    run = read_run(_write(tmp_path, text), THRUSTERS)
    ts, ys = run.channels["psi"]
    np.testing.assert_allclose(ys, psi_true, atol=1e-8)  # 9 significant digits in the file
    tz, yz = run.channels["z"]
    assert tz.size == t[::5].size  # only the sampled rows: an empty cell is no sample
    np.testing.assert_allclose(yz, z[::5], atol=1e-8)
    np.testing.assert_allclose(run.commands["A"], np.sin(t), atol=1e-8)
    assert run.duration == pytest.approx(t[-1] - t[0])
    assert "psi (100)" in run.describe()


def test_measured_thrust_column_and_ignored_column_warned(tmp_path: Path) -> None:
    text = "time,u,A,thrust:B,battery\n0,0.1,0.2,3.0,16\n0.1,,0.2,3.5,16\n0.2,0.12,0.3,4,15.9\n"
    run = read_run(_write(tmp_path, text), THRUSTERS)
    np.testing.assert_allclose(run.thrusts["B"], [3.0, 3.5, 4.0])
    assert run.channels["u"][0].tolist() == [0.0, 0.2]
    assert run.warnings == ("ignored column(s) matching nothing: battery",)


@pytest.mark.parametrize(
    ("text", "match"),
    [
        (
            "time,u,A,B\n0,0,0,0\n0.1,0,0,0\n0.1,0,0,0\n",
            r"column 'time' = 0\.1 at line 4 after 0\.1; expected strictly",
        ),
        ("time,u,A\n0,0,0\n0.1,0,0\n0.2,0,0\n", r"no column for thruster 'B'"),
        ("time,u,A,Bx\n0,0,0,0\n0.1,0,0,0\n0.2,0,0,0\n", r"no column for thruster 'B' \(ignored columns: Bx\)"),
        ("time,u,A,B,thrust:C\n0,0,0,0,0\n0.1,0,0,0,0\n0.2,0,0,0,0\n", r"column 'thrust:C' names no thruster"),
        ("time,A,B\n0,0,0\n0.1,0,0\n0.2,0,0\n", r"no motion channel"),
        ("time,u,A,B\n0,fast,0,0\n0.1,0,0,0\n0.2,0,0,0\n", r"line 2, column 'u' = 'fast': expected a number"),
        ("time,u,A,B\n0,0,,0\n0.1,0,0,0\n0.2,0,0,0\n", r"line 2, column 'A' is empty; expected the input on every row"),
        ("time,u,A,B,u\n0,0,0,0,0\n0.1,0,0,0,0\n0.2,0,0,0,0\n", r"column 'u' appears twice"),
        ("time,u,A,B\n0,nan,0,0\n0.1,0,0,0\n0.2,0,0,0\n", r"line 2, column 'u' = nan: expected a finite number"),
        ("time,u,A,B\n0,,0,0\n0.1,,0,0\n0.2,,0,0\n", r"hold no sample"),
        ("u,A,B\n0,0,0\n0.1,0,0\n0.2,0,0\n", r"no column 'time'"),
        ("time,u,A,B\n0,0,0,0\n", r"1 data row\(s\); expected a header"),
        ("time,u,A,B,thrust:A\n0,0,0,0,0\n0.1,0,0,0,0\n0.2,0,0,0,0\n", r"thruster 'A' has both"),
    ],
)
def test_bad_run_files_name_file_column_and_value(tmp_path: Path, text: str, match: str) -> None:
    p = _write(tmp_path, text)
    with pytest.raises(InputError, match=match) as info:
        read_run(p, THRUSTERS)
    assert str(p) in str(info.value) and "\n" not in str(info.value)


@pytest.mark.parametrize(
    ("body", "limits", "needle", "says"),
    [
        ("0,0,0,0,0\n0.1,fast,0,0,0\n0.2,0,0,0,0\n", None, "fast", "column 'u' = 'fast'"),
        ("0,0,0,0,0\n0.1,0,0,,0\n0.2,0,0,0,0\n", None, ",,", "column 'B' is empty"),
        ("0,0,0,0,0\n0.1,0,0,0,0\n0.1,0,0,0,1e-3\n", None, "1e-3", "column 'time' = 0.1 at"),
        ("0,0,0,0,0\n0.1,0,0,0,0\n0.2,0,0,0,0.9\n", [0.5], "0.9", "column 'rudder' = 0.9 rad"),
    ],
)
def test_errors_give_the_files_own_line_number_past_comments_and_blank_lines(
    tmp_path: Path, body: str, limits: Any, needle: str, says: str
) -> None:
    # two comment lines, the header, blank lines between data rows: the error names the line
    # an editor shows, found here independently as the line of the text holding the bad cell
    first, *rest = body.splitlines()
    text = "# a dive\n# logged by hand\ntime,u,A,B,rudder\n\n" + first + "\n\n" + "\n".join(rest) + "\n"
    line = next(k + 1 for k, ln in enumerate(text.splitlines()) if needle in ln)
    assert line >= 7  # past the comments and blank lines: a data-row count would say less
    with pytest.raises(InputError, match=rf"line {line}\b") as info:
        read_run(_write(tmp_path, text), THRUSTERS, ["rudder"], limits)
    assert says in str(info.value)


def test_writer_refuses_unknown_channel() -> None:
    with pytest.raises(InputError, match=r"channel\(s\) speed: expected some of x, y, z"):
        run_csv(np.zeros(2), {"speed": np.zeros(2)}, {})


# --------------------------------------------------------------- control surfaces (issue #45)
SURFACES = ("rudder", "bowplane")


def test_deflection_columns_read_in_vehicle_order_and_round_trip(tmp_path: Path) -> None:
    # the writer puts the surfaces in the order given; the reader returns them in the vehicle's
    # order (the compiled kernels' δ columns), whatever the file's column order (independent: the
    # series the file was made from)
    t = np.arange(0.0, 1.0, 0.1)
    rudder = np.radians(20.0) * np.sign(np.sin(3 * t))
    plane = np.full(t.size, -0.05)
    text = run_csv(t, {"r": 0.1 * t}, {"A": t, "B": t}, deflections={"bowplane": plane, "rudder": rudder})
    assert text.splitlines()[0] == "time,r,A,B,bowplane,rudder"
    run = read_run(_write(tmp_path, text), THRUSTERS, SURFACES, np.radians([35.0, 25.0]))
    assert list(run.deflections) == list(SURFACES)
    np.testing.assert_allclose(run.deflections["rudder"], rudder, atol=1e-9)
    np.testing.assert_allclose(run.deflections["bowplane"], plane, atol=1e-9)
    assert run.warnings == () and "2 deflection(s)" in run.describe()
    # without the vehicle's surfaces the columns match nothing: ignored and named in the warning
    plain = read_run(_write(tmp_path, text), THRUSTERS)
    assert plain.deflections == {} and plain.warnings == ("ignored column(s) matching nothing: bowplane, rudder",)


def test_deflection_at_its_limit_is_accepted(tmp_path: Path) -> None:
    # a file holding the limit to its 9 significant digits is within it
    lim = np.radians(35.0)
    text = f"time,r,A,B,rudder,bowplane\n0,0,0,0,{lim:.9g},0\n0.1,0,0,0,{-lim:.9g},0\n0.2,0,0,0,0,0\n"
    run = read_run(_write(tmp_path, text), THRUSTERS, SURFACES, [lim, lim])
    assert run.deflections["rudder"][0] == pytest.approx(lim)


@pytest.mark.parametrize(
    ("text", "limits", "match"),
    [
        (
            "time,r,A,B,rudder\n0,0,0,0,0\n0.1,0,0,0,0\n0.2,0,0,0,0\n",
            None,
            r"no column for control surface 'bowplane'; expected a column 'bowplane' with its deflection in rad",
        ),
        (
            "time,r,A,B,rudder,plane\n0,0,0,0,0,0\n0.1,0,0,0,0,0\n0.2,0,0,0,0,0\n",
            None,
            r"no column for control surface 'bowplane' \(ignored columns: plane\)",
        ),
        (
            "time,r,A,B,rudder,bowplane\n0,0,0,0,0,0\n0.1,0,0,0,0.7,0\n0.2,0,0,0,0,0\n",
            [np.radians(35.0), 0.5],
            r"line 3, column 'rudder' = 0\.7 rad \(40\.11°\) is beyond the surface's limit; "
            r"expected \|deflection\| ≤ 0\.610865 rad \(35°, max_deflection_deg\)",
        ),
        (
            "time,r,A,B,rudder,bowplane\n0,0,0,0,0,0\n0.1,0,0,0,0,-0.6\n0.2,0,0,0,0,0\n",
            [1.0, 0.5],
            r"line 3, column 'bowplane' = -0\.6 rad",
        ),
        (
            "time,r,A,B,rudder,bowplane\n0,0,0,0,,0\n0.1,0,0,0,0,0\n0.2,0,0,0,0,0\n",
            None,
            r"line 2, column 'rudder' is empty; expected the input on every row",
        ),
        ("time,r,A,B,rudder,bowplane\n0,0,0,0,0,0\n0.1,0,0,0,0,0\n", [1.0], r"1 deflection limit\(s\) for 2"),
    ],
)
def test_bad_deflection_columns(tmp_path: Path, text: str, limits: Any, match: str) -> None:
    p = _write(tmp_path, text)
    with pytest.raises(InputError, match=match) as info:
        read_run(p, THRUSTERS, SURFACES, limits)
    assert str(p) in str(info.value) and "\n" not in str(info.value)


def test_surface_named_as_a_thruster_or_channel_is_refused(tmp_path: Path) -> None:
    p = _write(tmp_path, "time,r,A,B\n0,0,0,0\n0.1,0,0,0\n0.2,0,0,0\n")
    for clash in ("A", "r"):
        with pytest.raises(InputError, match=rf"control surface '{clash}' has the name of a thruster or channel"):
            read_run(p, THRUSTERS, (clash,))
