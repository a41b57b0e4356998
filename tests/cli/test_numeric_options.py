"""Issue #32 class 4: every numeric option refuses NaN and ±∞ — and values outside its physical
sign or range (a ratio, mass, density, duration or step ≤ 0, a count < 1) — with the option's
name, exit 2 and one line, before anything runs. The options share the click types of
:mod:`hydrokit.cli._types`; a test walks the command group so a new option cannot miss them."""

from __future__ import annotations

import click
import pytest

from hydrokit.cli._types import Number, Numbers
from hydrokit.data import campaign_files

RIG, LAUNCHES = campaign_files("udrobot", "spring_x")
PENDULUM, _ = campaign_files("udrobot", "pendulum_x")
TRUTH = {"--added-mass": "0.3", "--linear-damping": "2", "--quadratic-damping": "5", "--amplitudes": "20"}


def _truth(**bad: str) -> list[str]:
    opts = TRUTH | {f"--{k.replace('_', '-')}": v for k, v in bad.items()}
    return [x for kv in opts.items() for x in kv]


# (command line, option the line must name, bad value it must show)
CASES: dict[str, tuple[list[object], str, str]] = {
    "scale-added-mass-nan": (["scale", "--ratio", "0.3", "--added-mass", "nan"], "--added-mass", "nan"),
    "scale-damping-inf": (["scale", "--ratio", "0.3", "--linear-damping", "inf"], "--linear-damping", "inf"),
    "scale-quadratic-minus-inf": (["scale", "--ratio", "0.3", "--quadratic-damping", "-inf"], "--quadratic", "-inf"),
    "scale-ratio-zero": (["scale", "--ratio", "0", "--added-mass", "1"], "--ratio", "0"),
    "scale-ratio-negative": (["scale", "--ratio", "-0.3", "--added-mass", "1"], "--ratio", "-0.3"),
    "scale-volume-nan": (
        ["scale", "--ratio", "0.3", "--added-mass", "1", "--model-volume", "nan", "--full-volume", "1"],
        "--model-volume",
        "nan",
    ),
    "scale-volume-negative": (
        ["scale", "--ratio", "0.3", "--added-mass", "1", "--model-volume", "1", "--full-volume", "-2"],
        "--full-volume",
        "-2",
    ),
    "simulate-dt-zero": (["simulate", "minerva", "--dt", "0", "--out", "o.csv"], "--dt", "0"),
    "simulate-dt-nan": (["simulate", "minerva", "--dt", "nan", "--out", "o.csv"], "--dt", "nan"),
    "simulate-duration-negative": (["simulate", "minerva", "--duration", "-5", "--out", "o.csv"], "--duration", "-5"),
    "simulate-force-nan": (["simulate", "minerva", "--force", "30,0,nan,0,0,0", "--out", "o.csv"], "--force", "nan"),
    "simulate-force-overflow": (
        ["simulate", "minerva", "--force", "1e400,0,0,0,0,0", "--out", "o"],
        "--force",
        "1e400",
    ),
    "simulate-velocity-inf": (
        ["simulate", "minerva", "--initial-velocity", "inf,0,0,0,0,0", "--out", "o.csv"],
        "--initial-velocity",
        "inf",
    ),
    "simulate-current-short": (["simulate", "minerva", "--current-ned", "1,2", "--out", "o.csv"], "--current-ned", "3"),
    "simulate-output-every-zero": (["simulate", "minerva", "--output-every", "0", "--out", "o"], "--output-every", "0"),
    "transport-dt-negative": (
        ["transport", "rehman_transport", "--duration", "1", "--dt", "-0.01", "--out", "o"],
        "--dt",
        "-0.01",
    ),
    "transport-duration-nan": (
        ["transport", "rehman_transport", "--duration", "nan", "--dt", "0.01", "--out", "o"],
        "--duration",
        "nan",
    ),
    "transport-every-zero": (
        ["transport", "rehman_transport", "--duration", "1", "--dt", "0.01", "--every", "0", "--out", "o"],
        "--every",
        "0",
    ),
    "mission-duration-nan": (["mission", "minerva_square", "--duration", "nan", "--out", "o"], "--duration", "nan"),
    "mission-duration-negative": (["mission", "minerva_square", "--duration", "-1", "--out", "o"], "--duration", "-1"),
    "tune-duration-inf": (
        ["tune", "minerva_square", "--controller", "pid", "--duration", "inf", "--out", "o"],
        "--duration",
        "inf",
    ),
    "tune-bounds-nan": (
        ["tune", "minerva_square", "--controller", "pid", "--bounds", "nan,5", "--out", "o"],
        "--bounds",
        "nan",
    ),
    "tune-maxiter-zero": (
        ["tune", "minerva_square", "--controller", "pid", "--maxiter", "0", "--out", "o"],
        "--maxiter",
        "0",
    ),
    "tune-seed-negative": (
        ["tune", "minerva_square", "--controller", "pid", "--seed", "-1", "--out", "o"],
        "--seed",
        "-1",
    ),
    "rig-simulate-added-mass-nan": (
        ["rig", "simulate", RIG, *_truth(added_mass="nan"), "--out", "o"],
        "--added-mass",
        "nan",
    ),
    "rig-simulate-sample-rate-zero": (
        ["rig", "simulate", RIG, *_truth(), "--sample-rate", "0", "--out", "o"],
        "--sample-rate",
        "0",
    ),
    "rig-simulate-noise-negative": (
        ["rig", "simulate", RIG, *_truth(), "--noise", "-1", "--out", "o"],
        "--noise",
        "-1",
    ),
    "rig-simulate-hold-inf": (["rig", "simulate", RIG, *_truth(), "--hold", "inf", "--out", "o"], "--hold", "inf"),
    "rig-simulate-launches-zero": (
        ["rig", "simulate", RIG, *_truth(), "--launches", "0", "--out", "o"],
        "--launches",
        "0",
    ),
    "rig-simulate-seed-negative": (
        ["rig", "simulate", RIG, *_truth(), "--seed", "-3", "--out", "o"],
        "--seed",
        "-3",
    ),
    "rig-simulate-amplitudes-nan": (
        ["rig", "simulate", RIG, *_truth(amplitudes="10,nan"), "--out", "o"],
        "--amplitudes",
        "nan",
    ),
    "rig-plan-duration-nan": (["rig", "plan", RIG, *_truth(), "--duration", "nan"], "--duration", "nan"),
    "rig-plan-quadratic-inf": (["rig", "plan", RIG, *_truth(quadratic_damping="inf")], "--quadratic-damping", "inf"),
    "fit-forces-area-zero": (
        ["fit-forces", "f.csv", "--area", "0", "--density", "1000"],
        "--area",
        "0",
    ),
    "fit-forces-density-nan": (
        ["fit-forces", "f.csv", "--area", "0.1", "--density", "nan"],
        "--density",
        "nan",
    ),
    "identify-start-nan": (["identify", RIG, LAUNCHES[0], "--json", "o.json", "--start", "nan"], "--start", "nan"),
    "identify-end-inf": (["identify", RIG, LAUNCHES[0], "--json", "o.json", "--end", "inf"], "--end", "inf"),
    "ingest-fps-nan": (
        ["ingest", LAUNCHES[0], "--rig", RIG, "--out", "o", "--fps", "nan"],
        "--fps",
        "nan",
    ),
    "allocate-tau-inf": (["allocate", "minerva", "--tau", "inf,0,0,0,0,0"], "--tau", "inf"),
    "allocate-weights-negative": (
        ["allocate", "minerva", "--tau", "1,0,0,0,0,0", "--method", "pinv", "--weights", "1,-1,1,1,1,1"],
        "--weights",
        "-1",
    ),
    "export-trim-nan": (
        ["export", "minerva", "--format", "python-control", "--out", "o.npz", "--trim", "nan,0,0,0,0,0"],
        "--trim",
        "nan",
    ),
    "run-samples-negative": (["run", "udrobot", "--samples", "-1", "--out", "o"], "--samples", "-1"),
    "run-workers-negative": (["run", "udrobot", "--workers", "-2", "--out", "o"], "--workers", "-2"),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_a_non_finite_or_unphysical_option_is_one_line_naming_it(run_cli, tmp_path, monkeypatch, case):
    args, option, value = CASES[case]
    monkeypatch.chdir(tmp_path)
    (tmp_path / "f.csv").write_text("speed,force\n0.1,1\n0.2,4\n0.3,9\n")
    code, out, err = run_cli(*args)
    lines = err.splitlines()
    assert len(lines) == 1, err[:600]
    line = lines[0]
    assert code == 2, line
    assert line.startswith("error: ") and option in line and value in line, line
    assert "expected" in line, line
    assert out == "", "nothing is computed or printed for a refused option"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["f.csv"], "nothing is written"


def _every_option() -> list[tuple[str, click.Parameter]]:
    from hydrokit.cli.main import cli

    ctx = click.Context(cli)
    found = []

    def walk(cmd: click.Command, path: str) -> None:
        if isinstance(cmd, click.Group):
            for name in cmd.list_commands(ctx):
                sub = cmd.get_command(ctx, name)
                if sub is not None:
                    walk(sub, f"{path} {name}".strip())
            return
        found.extend((f"{path} {p.name}", p) for p in cmd.params)

    walk(cli, "")
    return found


OPTIONS = _every_option()


def test_no_option_takes_a_bare_float_or_int():
    """A bare ``type=float`` takes nan and inf; a bare ``type=int`` any count, however unphysical."""
    bare = [
        name
        for name, p in OPTIONS
        if type(p.type) in (click.types.FloatParamType, click.types.IntParamType)
        or isinstance(p.type, click.types.FloatRange)
    ]
    assert bare == [], f"options without a shared type (hydrokit.cli._types): {bare}"
    assert sum(isinstance(p.type, (Number, Numbers)) for _, p in OPTIONS) >= 40


@pytest.mark.parametrize("name", [n for n, p in OPTIONS if isinstance(p.type, (Number, Numbers))])
def test_every_number_option_refuses_nan_and_infinities(name):
    param = dict(OPTIONS)[name]
    n = getattr(param.type, "n", None) or 1
    for bad in ("nan", "inf", "-inf", "1e999", "NaN", "abc", ""):
        text = ",".join([bad] * n)
        with pytest.raises(click.ClickException, match="expected"):
            param.type.convert(text, param, None)


@pytest.mark.parametrize(
    ("kind", "good", "bad"),
    [
        (Number(), ["-1e9", "0", "3.5"], ["nan"]),
        (Number(above=0), ["1e-9", "2"], ["0", "-1"]),
        (Number(at_least=0), ["0", "2"], ["-1e-300"]),
        (Number(above=0, at_most=1), ["1", "0.5"], ["1.0000001", "0"]),
        (Numbers(3), ["1,2,3", "1;2;3"], ["1,2", "1,2,3,4", "1,,nan"]),
        (Numbers(None, positive=True), ["1", "1,2,3"], ["0", "1,-2"]),
        (Numbers(None, nonzero=True), ["-1,2"], ["0,1"]),
    ],
)
def test_the_shared_types_take_their_range_and_refuse_the_rest(kind, good, bad):
    for g in good:
        kind.convert(g, None, None)
    for b in bad:
        with pytest.raises(click.ClickException, match="expected"):
            kind.convert(b, None, None)


def test_a_long_bad_value_is_cut_in_the_message():
    with pytest.raises(click.ClickException) as info:
        Number().convert("x" * 100_000, None, None)
    assert len(info.value.format_message()) < 300
