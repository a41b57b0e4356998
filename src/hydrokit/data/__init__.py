"""Bundled data: vehicles, missions, geometries and the virtual tank campaigns.

Paths only (stdlib); every reader lives in ``hydrokit.io``. The campaigns are *virtual*
launches written by the virtual rig (see each campaign's README.md for the true values).
"""

from __future__ import annotations

from pathlib import Path

from hydrokit.errors import InputError

DATA_DIR = Path(__file__).resolve().parent


def _names(folder: Path, pattern: str) -> list[str]:
    return sorted(p.stem if p.is_file() else p.name for p in folder.glob(pattern))


def campaign_files(campaign: str, rig: str) -> tuple[Path, list[Path]]:
    """The rig file and launch CSVs of a bundled campaign's rig (e.g. "udrobot", "spring_x").

    Raises InputError naming the bundled campaigns or rigs when ``campaign`` or ``rig`` is unknown.
    """
    folder = DATA_DIR / "campaigns" / campaign
    if not folder.is_dir():
        raise InputError(
            f"no bundled campaign '{campaign}' (bundled: {', '.join(_names(DATA_DIR / 'campaigns', '*'))})"
        )
    rig_file = folder / f"{rig}.yaml"
    if not rig_file.is_file():
        raise InputError(f"campaign '{campaign}' has no rig '{rig}' (rigs: {', '.join(_names(folder, '*.yaml'))})")
    launches = folder / rig
    if not launches.is_dir():  # a campaign with one rig keeps its launches in its only folder
        launches = next(p for p in sorted(folder.iterdir()) if p.is_dir())
    return rig_file, sorted(launches.glob("*.csv"))


def campaign_rigs(campaign: str) -> list[str]:
    """Names of the rigs of a bundled campaign (its rig files without .yaml)."""
    return _names(DATA_DIR / "campaigns" / campaign, "*.yaml")


def body_file(name: str) -> Path:
    """Path of a bundled CFD body (e.g. "myring": a profile CSV of a body of revolution)."""
    for suffix in (".csv", ".stl", ".obj", ".yaml"):
        p = DATA_DIR / "bodies" / f"{name}{suffix}"
        if p.is_file():
            return p
    raise InputError(
        f"no such file or bundled body '{name}' (bundled: {', '.join(_names(DATA_DIR / 'bodies', '*.*'))})"
    )


def geometry_file(name: str) -> Path:
    """Path of a bundled geometry file (e.g. "sphere", "rehman_assembly")."""
    p = DATA_DIR / "geometry" / f"{name}.yaml"
    if not p.is_file():
        raise InputError(
            f"no bundled geometry '{name}' (bundled: {', '.join(_names(DATA_DIR / 'geometry', '*.yaml'))})"
        )
    return p
