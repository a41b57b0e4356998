"""``hydrokit sysid generate --zigzags``: the zigzag trials of a KVLCC2-like tanker as run files, its
truth and a start 20–30 % off (issue #56), the texts the command writes."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any


def zigzag_files(out_dir: str, n_runs: int, duration: float, seed: int, spread: float, noise: float) -> dict[str, str]:
    """The run files, ``truth.yaml``, ``start.yaml`` and ``truth.json`` of the zigzag data set.

    Parameters
    ----------
    out_dir : str — the folder the file names are in
    n_runs : int — the first ``n_runs`` zigzags of :data:`hydrokit.sysid.ship.ZIGZAGS`, each side
        in turn (12: all)
    duration : float — length of each run, s
    seed : int — seed of the initial headings, the noise and the start's factors
    spread : float — each free term of start.yaml is the truth's × (1 ± uniform(spread − 0.1,
        spread)), the sign drawn (fraction; 0.3: 20–30 % off)
    noise : float — multiplier of every sensor σ (0: noise-free logs)

    Returns
    -------
    dict — path → text: zigzagA-B{s,p}.csv (:func:`hydrokit.io.runlog.run_csv`), the ship
    (:data:`hydrokit.sysid.ship.TANKER`) as truth.yaml, the start as start.yaml, truth.json (the
    free names and their true values, SI) and free.txt (the free names, for ``--free "$(cat …)"``)
    """
    import numpy as np

    from hydrokit.api import vehicle_from_dict
    from hydrokit.io.runlog import run_csv
    from hydrokit.io.vehicle import vehicle_text
    from hydrokit.sysid.ship import TANKER, TANKER_FREE, TANKER_TERMS, ZIGZAGS, tanker_start, zigzag_runs

    truth = vehicle_from_dict(TANKER, "kvlcc2-like")
    zigzags = ZIGZAGS[: (n_runs + 1) // 2]
    runs = zigzag_runs(truth, seed, zigzags, duration=duration, noise=noise)[:n_runs]
    start = tanker_start(seed, spread)
    low = max(spread - 0.1, 0.0)
    out = Path(out_dir)
    files: dict[str, str] = {}
    for r in runs:
        note = f"zigzag trial {r.name} of the KVLCC2-like tanker (hydrokit sysid generate --zigzags, seed {seed})"
        rows: dict[str, Any] = {c: y for c, (_, y) in r.channels.items()}
        rows["psi"] = np.angle(np.exp(1j * rows["psi"]))
        files[str(out / f"{r.name}.csv")] = run_csv(r.time, rows, r.commands, comment=note, deflections=r.deflections)
    head = "KVLCC2-like 7 m tanker model (hydrokit.sysid.ship.TANKER): the truth of the zigzags"
    files[str(out / "truth.yaml")] = vehicle_text(TANKER, head)
    files[str(out / "start.yaml")] = vehicle_text(start, f"the truth's terms {100 * low:g}–{100 * spread:g} % off")
    doc = {
        "vehicle": TANKER["name"],
        "seed": seed,
        "spread": spread,
        "free": list(TANKER_FREE),
        "hidden": {f"terms.{k}": v for k, v in TANKER_TERMS.items()},
    }
    files[str(out / "truth.json")] = json.dumps(doc, indent=2) + "\n"
    files[str(out / "free.txt")] = ",".join(TANKER_FREE) + "\n"
    return files
