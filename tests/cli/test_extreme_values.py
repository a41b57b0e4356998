"""Issue 32 class 2: valid but extreme values. Every finite input gives a result or one line
naming the value out of range and the range — never "internal error" (exit 1), a numpy
RuntimeWarning, or an ``inf`` printed as a result."""

from __future__ import annotations

import re

import pytest

from hydrokit.data import DATA_DIR

RIG = str(DATA_DIR / "campaigns" / "udrobot" / "spring_x.yaml")
RIG_TRUTH = ("--added-mass", "0.3", "--linear-damping", "1", "--quadratic-damping", "1", "--duration", "2")

# (args, words the refusal line must hold); each ended in "internal error" or printed inf before
CASES = {
    "allocate-huge-demand": (["allocate", "minerva", "--tau", "1e308,0,0,0,0,0"], ["tau X = 1e+308 N", "≤ 1e+12 N"]),
    "allocate-huge-moment-pinv": (
        ["allocate", "minerva", "--tau", "0,0,0,0,0,-1e200", "--method", "pinv"],
        ["tau N = -1e+200 N·m", "≤ 1e+12 N·m"],
    ),
    "allocate-denormal-weight": (
        ["allocate", "minerva", "--tau", "1,0,0,0,0,0", "--method", "pinv", "--weights", "5e-324,1,1,1,1"],
        ["smallest, 4.941e-324", "within a factor 1e+12"],
    ),
    "export-huge-trim": (
        ["export", "minerva", "--format", "python-control", "--out", "{tmp}/o.npz", "--trim", "1e50,0,0,0,0,0"],
        ["--trim u = 1e+50 m/s", "≤ 1000 m/s"],
    ),
    "simulate-tiny-step": (
        ["simulate", "minerva", "--duration", "1", "--dt", "1e-300", "--out", "{tmp}/o.csv"],
        ["memory", "recorded trajectory (1e+300 rows)", "expected a shorter duration"],
    ),
    "scale-overflow": (["scale", "--ratio", "0.3", "--added-mass", "1e308"], ["added_mass = 1e+308 × λ^3", "float range"]),
    "scale-tiny-ratio": (
        ["scale", "--ratio", "1e-308", "--added-mass", "1", "--rotational"],
        ["λ^5 (λ = 1e+308)", "realistic size"],
    ),
    "scale-volumes": (
        ["scale", "--ratio", "0.3", "--added-mass", "1", "--model-volume", "1e-308", "--full-volume", "1"],
        ["--model-volume 1e-308 m³", "--full-volume 1 m³"],
    ),
    "fit-forces-tiny-density": (
        ["fit-forces", "{tmp}/f.csv", "--area", "0.1", "--density", "5e-324"],
        ["density = 4.941e-324 kg/m³", "C_D beyond the float range"],
    ),
    "rig-plan-huge-added-mass": (
        ["rig", "plan", RIG, "--added-mass", "1e308", "--linear-damping", "1", "--quadratic-damping", "1",
         "--amplitudes", "10", "--duration", "2"],
        ["added_mass = 1e+308", "no finite information"],
    ),
    "rig-simulate-huge-sample-rate": (
        ["rig", "simulate", RIG, *RIG_TRUTH, "--amplitudes", "10", "--launches", "1", "--sample-rate", "1e200",
         "--out", "{tmp}/rs"],
        ["sample_rate = 1e+200 Hz", "expected 2 to 1e+07 per launch"],
    ),
    "rig-simulate-huge-amplitude": (
        ["rig", "simulate", RIG, *RIG_TRUTH, "--amplitudes", "1e308", "--launches", "1", "--out", "{tmp}/rs"],
        ["amplitude = 1e+305", "leaves the float range"],
    ),
}  # fmt: skip


@pytest.mark.parametrize("case", sorted(CASES))
def test_an_extreme_finite_value_is_one_line_naming_it_and_its_range(run_cli, tmp_path, case):
    (tmp_path / "f.csv").write_text("speed,force\n0.5,10\n1,35\n1.5,80\n2,140\n")
    args, words = CASES[case]
    code, _, err = run_cli(*(a.replace("{tmp}", str(tmp_path)) for a in args))
    lines = err.strip().splitlines()
    assert code == 2, err
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    for w in words:
        assert w in lines[0], lines[0]
    assert not [p for p in tmp_path.iterdir() if p.name != "f.csv"]  # nothing written


def test_the_largest_demand_allowed_gives_a_result_with_finite_numbers(run_cli):
    code, out, err = run_cli("allocate", "minerva", "--tau", "1e12,0,0,0,0,-1e12")
    assert code == 0 and err == "", err
    assert re.search(r"residual \|Tf − τ\| = 1\.4\d*e\+12", out), out  # τ is out of reach: √2·1e12 left
    assert not re.search(r"\b(inf|nan|None)\b", out), out


def test_a_rig_plan_with_a_vanishing_coefficient_shows_no_inf_percent(run_cli):
    args = ("--added-mass", "0.3", "--linear-damping", "1", "--quadratic-damping", "5e-324")
    code, out, err = run_cli("rig", "plan", RIG, *args, "--amplitudes", "10", "--duration", "2")
    assert code == 0, err
    table = out.split("quadratic damping is best")[0]
    assert "inf %" not in table and "– %" in table, table
