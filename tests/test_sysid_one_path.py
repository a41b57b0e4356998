"""One function reads runs and identifies (issue #50): the API, ``hydrokit sysid`` and the main
job's ``sysid:`` source all go through :func:`hydrokit.api.identify_runs`."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from hydrokit.errors import InputError


def test_api_cli_and_main_job_identify_through_one_function(
    monkeypatch: pytest.MonkeyPatch, run_cli: Any, tmp_path: Path
) -> None:
    import hydrokit.api
    from hydrokit.io.project import SysidSpec
    from hydrokit.pipeline.sysid import sysid_step

    calls: list[tuple[list[str], list[str], list[str], str]] = []

    def reached(vehicle: Any, runs: Any, free: Any, holdout: Any = (), **options: Any) -> Any:
        calls.append(([str(r) for r in runs], list(free), [str(h) for h in holdout], options["method"]))
        raise InputError("reached identify_runs")

    monkeypatch.setattr(hydrokit.api, "identify_runs", reached)
    run, held = str(tmp_path / "a.csv"), str(tmp_path / "b.csv")
    with pytest.raises(InputError, match="reached identify_runs"):
        hydrokit.sysid([run], "bluerov2-heavy", "added_mass.surge", holdout=[held])
    code, _, err = run_cli(
        "sysid", "fit", run, "--vehicle", "bluerov2-heavy", "--free", "added_mass.surge", "--holdout", held,
        "--out", tmp_path / "out",
    )  # fmt: skip
    assert code == 2 and "reached identify_runs" in err, err
    spec = SysidSpec((Path(run),), (Path(held),), ("added_mass.surge",), "output-error", 0.01, "*.csv")
    with pytest.raises(InputError, match="reached identify_runs"):
        sysid_step(spec, hydrokit.load_vehicle("bluerov2-heavy"), 0, lambda n: None, str)
    assert calls == [([run], ["added_mass.surge"], [held], "output-error")] * 3


def test_options_are_checked_before_any_run_is_read(tmp_path: Path) -> None:
    """A bad free name is the error, not the run file that does not exist."""
    import hydrokit
    from hydrokit.api import identify_runs

    with pytest.raises(InputError, match="added_mass.sideways"):
        identify_runs(hydrokit.load_vehicle("bluerov2-heavy"), [tmp_path / "missing.csv"], ["added_mass.sideways"])
    with pytest.raises(InputError, match="missing.csv"):
        identify_runs(hydrokit.load_vehicle("bluerov2-heavy"), [tmp_path / "missing.csv"], ["added_mass.surge"])
