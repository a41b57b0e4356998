"""Finding OpenFOAM and running its programs with captured output, a timeout and clean-up.

OpenFOAM is a system dependency (Debian/Ubuntu: ``apt-get install -y openfoam``, v1912). Its
programs are on ``PATH``; each needs ``WM_PROJECT_DIR`` in its environment to find the
installation's ``etc`` files (Debian installs them under ``/usr/share/openfoam``); sourcing
``etc/bashrc`` is not needed.

Every program runs in its own process group with stdout and stderr in ``log.<program>`` in the
case folder. What it prints never reaches the user's terminal: a failure becomes one
:class:`SolverError` line quoting OpenFOAM's own reason (the ``FOAM FATAL ERROR`` text), and the
full log stays in the case. A timeout, an exception or a termination signal in the caller ends
the whole process group (SIGTERM, then SIGKILL after a grace period), so no solver outlives a
sweep.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import signal
import subprocess
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from hydrokit.errors import HydrokitError

#: the install command named in the "OpenFOAM is missing" message
INSTALL_COMMAND = "sudo apt-get install -y openfoam"
#: where Debian's package puts OpenFOAM's etc/ files (WM_PROJECT_DIR)
DEBIAN_PROJECT_DIR = "/usr/share/openfoam"
#: programs hydrokit drives; the first must exist for OpenFOAM to count as installed
PROGRAMS = ("simpleFoam", "blockMesh", "snappyHexMesh", "surfaceFeatureExtract", "checkMesh", "pimpleFoam")
#: seconds between SIGTERM and SIGKILL when a run is ended early
GRACE = 3.0


class MissingSolverError(HydrokitError):
    """OpenFOAM is not installed (or not on PATH); the message names the install command."""


class SolverError(HydrokitError):
    """An OpenFOAM program failed or timed out; the message quotes its reason and names its log."""


@dataclass(frozen=True)
class OpenFOAM:
    """An OpenFOAM installation: the folder of its programs and its ``WM_PROJECT_DIR``."""

    bin_dir: Path
    project_dir: Path

    def env(self) -> dict[str, str]:
        """The environment a program runs in: the caller's, with WM_PROJECT_DIR set and one MPI/OpenMP thread."""
        env = dict(os.environ)
        env["WM_PROJECT_DIR"] = str(self.project_dir)
        env.setdefault("OMP_NUM_THREADS", "1")
        # a run is a child of hydrokit: no colour codes or banners meant for a terminal
        env.pop("FOAM_SIGFPE", None)
        # Dask's nanny sets MALLOC_TRIM_THRESHOLD_=65536 in its workers: glibc then hands memory
        # back to the system after every field OpenFOAM frees, and simpleFoam runs at half speed
        # (10.9 s → 20.6 s for 400 iterations of a small case, system time 1.7 → 7.3 s)
        env.pop("MALLOC_TRIM_THRESHOLD_", None)
        return env

    def run(
        self,
        program: str,
        case: Path,
        args: Sequence[str] = (),
        *,
        timeout: float = 3600.0,
        log: str | None = None,
        check: bool = True,
        monitor: Callable[[], bool] | None = None,
        poll: float = 1.0,
        processes: int = 1,
    ) -> int:
        """Run ``program -case CASE ARGS`` to completion; output goes to ``CASE/log.<program>``.

        Parameters
        ----------
        program : str — an OpenFOAM program name, e.g. ``blockMesh``
        case : Path — the case folder
        args : sequence of str — further arguments
        timeout : float — wall-clock limit, s; the run is ended and SolverError raised beyond it
        log : str, optional — log file name inside ``case`` (default ``log.<program>``)
        check : bool — raise SolverError on a non-zero exit status
        monitor : callable, optional — called every ``poll`` s while the program runs; when it
            returns True the run is asked to write its state and stop (``stopAt writeNow`` in
            ``system/controlDict``, which a solver re-reads every iteration)
        poll : float — seconds between calls of ``monitor``
        processes : int — more than 1 runs ``mpirun -np N program -parallel`` on a case that
            decomposePar has split (OpenFOAM's own MPI, for one big case)

        Returns
        -------
        int — the exit status

        Raises
        ------
        SolverError
            Non-zero exit (with ``check``), a missing program or the timeout; one line quoting the
            reason OpenFOAM gave and the log's path.
        """
        exe = self.bin_dir / program
        case = Path(case).resolve()
        if not exe.exists():
            raise MissingSolverError(
                f"OpenFOAM program {program!r} is not in {self.bin_dir}; expected a complete OpenFOAM: {INSTALL_COMMAND}"
            )
        logfile = case / (log or f"log.{program}")
        cmd = [str(exe), "-case", str(case), *args]
        env = self.env()
        if processes > 1:
            mpirun = shutil.which("mpirun")
            if mpirun is None:
                raise MissingSolverError(
                    f"{processes} processes need MPI's mpirun, which is not on PATH; expected OpenFOAM's MPI "
                    f"(it comes with {INSTALL_COMMAND}) or one process"
                )
            # as root (containers, CI) Open MPI refuses to start unless told that is intended
            env.update(
                OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1"
            )
            cmd = [mpirun, "-np", str(processes), *cmd, "-parallel"]
        # SIGTERM the program when the thread that started it dies (a Dask worker torn down
        # mid-task), so no solver outlives hydrokit: util-linux's setpriv sets PR_SET_PDEATHSIG
        # and execs it (a preexec_fn would do the same but may deadlock when threads run)
        setpriv = shutil.which("setpriv")
        if setpriv is not None:
            cmd = [setpriv, "--pdeathsig", "TERM", *cmd]
        with open(logfile, "wb") as out:
            proc = subprocess.Popen(
                cmd,
                stdout=out,
                stderr=subprocess.STDOUT,
                stdin=subprocess.DEVNULL,
                env=env,
                cwd=case,
                start_new_session=True,  # its own process group: ended as a whole
            )
            start = time.monotonic()
            stopping = False
            try:
                while True:
                    left = timeout - (time.monotonic() - start)
                    try:
                        status = proc.wait(timeout=max(0.0, min(poll, left)) if monitor else max(0.0, left))
                        break
                    except subprocess.TimeoutExpired:
                        if time.monotonic() - start >= timeout:
                            raise
                    if monitor is not None and not stopping and monitor():
                        stop_now(case)
                        stopping = True
            except subprocess.TimeoutExpired:
                end_process_group(proc)
                raise SolverError(
                    f"{program} did not finish within {timeout:g} s; expected a smaller case or a longer timeout "
                    f"(log: {logfile})"
                ) from None
            except BaseException:
                end_process_group(proc)
                raise
        if status != 0 and check:
            raise SolverError(f"{program} failed (exit {status}): {fatal_reason(logfile)} (log: {logfile})")
        return status


def stop_now(case: Path) -> None:
    """Ask a running solver to write its current state and stop after this iteration.

    The controlDict is parsed and written whole (foamlib's in-place edit fails now and then with
    a ``BufferError`` under Dask) and replaced by a rename, so the solver never reads half a file.
    """
    from hydrokit.cfd.case import foamlib

    FoamFile = foamlib().FoamFile  # noqa: N806 -- foamlib's class
    path = case / "system" / "controlDict"
    entries = dict(FoamFile.loads(path.read_bytes(), include_header=True))
    entries["stopAt"] = "writeNow"
    tmp = path.with_name(".controlDict.tmp")
    tmp.write_bytes(FoamFile.dumps(entries, ensure_header=False))
    os.replace(tmp, path)


def end_process_group(proc: subprocess.Popen[bytes]) -> None:
    """End a program started in its own session: SIGTERM to its group, SIGKILL after :data:`GRACE` s."""
    if proc.poll() is not None:
        return
    with contextlib.suppress(ProcessLookupError, PermissionError):
        os.killpg(proc.pid, signal.SIGTERM)
    deadline = time.monotonic() + GRACE
    while proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    if proc.poll() is None:
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()


def fatal_reason(logfile: Path, limit: int = 240) -> str:
    """OpenFOAM's own reason for a failure, from the log: the text after ``FOAM FATAL ERROR``
    (or ``FOAM FATAL IO ERROR``), else the last non-empty line; one line of at most ``limit`` characters."""
    try:
        text = logfile.read_text(errors="replace")
    except OSError:
        return "no log"
    lines = [ln.strip() for ln in text.splitlines()]
    for i, ln in enumerate(lines):
        if "FOAM FATAL" in ln:
            words = [w for w in lines[i + 1 : i + 12] if w and not w.startswith(("From ", "in file", "FOAM exiting"))]
            reason = " ".join(words)
            break
    else:
        tail = [ln for ln in lines if ln]
        reason = tail[-1] if tail else "no output"
    reason = " ".join(reason.split())
    return reason if len(reason) <= limit else reason[: limit - 1] + "…"


def find_openfoam(required: Sequence[str] = PROGRAMS[:1]) -> OpenFOAM:
    """The installed OpenFOAM, or :class:`MissingSolverError` naming the install command.

    ``WM_PROJECT_DIR`` is taken from the environment when set, else Debian's
    ``/usr/share/openfoam``, else the ``share/openfoam`` folder next to the programs.
    """
    found = shutil.which(required[0])
    if found is None:
        raise MissingSolverError(
            f"hydrokit cfd needs OpenFOAM, and {required[0]!r} is not on PATH; install it "
            f"(Debian/Ubuntu): {INSTALL_COMMAND}"
        )
    bin_dir = Path(found).resolve().parent
    for name in required[1:]:
        if not (bin_dir / name).exists():
            raise MissingSolverError(
                f"OpenFOAM in {bin_dir} has no {name!r}; expected a complete installation: {INSTALL_COMMAND}"
            )
    candidates = [os.environ.get("WM_PROJECT_DIR", ""), DEBIAN_PROJECT_DIR, str(bin_dir.parent / "share" / "openfoam")]
    for c in candidates:
        if c and (Path(c) / "etc" / "controlDict").exists():
            return OpenFOAM(bin_dir, Path(c))
    raise MissingSolverError(
        f"OpenFOAM's programs are in {bin_dir} but its etc/controlDict is not in any of "
        f"{[c for c in candidates if c]}; set WM_PROJECT_DIR to the installation folder or reinstall: {INSTALL_COMMAND}"
    )
