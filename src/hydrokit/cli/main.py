"""The ``hydrokit`` command.

Subcommands are registered by name and imported only when invoked, so ``hydrokit --help``
starts quickly (no numpy/scipy/numba/matplotlib import); heavy imports go inside commands.

Errors: a :class:`hydrokit.errors.HydrokitError` (bad input) prints one line on stderr and
exits with code 2, as do click's usage errors, an operating-system error (disk full, no
permission) and running out of memory. SIGTERM, SIGINT and SIGHUP unwind the command (staged
outputs are removed, see :mod:`hydrokit._atomic`), print one line and exit with 128 + the
signal number (143 for SIGTERM). Anything else is a bug: one line and exit 1 (set
``HYDROKIT_DEBUG=1`` for the traceback).
"""

from __future__ import annotations

import importlib
import os
import signal
import sys

import click

# name -> "module:attribute", imported lazily.
COMMANDS: dict[str, tuple[str, str]] = {
    "run": ("hydrokit.cli.run:run", "The main job: tank launches to an identified, flown vehicle and one report."),
    "demo": ("hydrokit.cli.demo:demo", "Identify the bundled UDrobot campaign and write an HTML report."),
    "identify": ("hydrokit.cli.identify:identify", "Identify coefficients from free-decay launches."),
    "ingest": ("hydrokit.cli.ingest:ingest", "Recordings to launch files; vehicle logs to run files (--run-out)."),
    "scale": ("hydrokit.cli.scale:scale", "Scale model-test coefficients to full size (similitude)."),
    "rig": ("hydrokit.cli.rig:rig", "Virtual rig: simulate launches, plan an experiment."),
    "simulate": ("hydrokit.cli.simulate:simulate", "Simulate a vehicle under a constant or tabulated force."),
    "allocate": ("hydrokit.cli.control:allocate", "Allocate a demanded force/moment to thrusters."),
    "mission": ("hydrokit.cli.mission:mission", "Run a closed-loop waypoint mission."),
    "tune": ("hydrokit.cli.tune:tune", "Tune a mission's controller gains (differential evolution over fleets)."),
    "estimate": ("hydrokit.cli.estimate:estimate", "Estimate coefficients from geometry."),
    "fit-forces": ("hydrokit.cli.estimate:fit_forces", "Fit damping models to a force-speed curve."),
    "cfd": ("hydrokit.cli.cfd:cfd", "Virtual tow tank and rotating arm on OpenFOAM: forces to coefficients."),
    "export": ("hydrokit.cli.export:export", "Export a vehicle to Gazebo, uuv_simulator or python-control."),
    "transport": ("hydrokit.cli.transport:transport", "Fly joined vehicles carrying a payload; joint loads."),
    "manoeuvre": ("hydrokit.cli.manoeuvre:manoeuvre", "Standard manoeuvres: turning circle, zigzag, spiral, pull-out."),
    "sysid": ("hydrokit.cli.sysid:sysid", "Identify added mass and damping from free-running dives (run CSVs)."),
}


class LazyGroup(click.Group):
    """A click group whose subcommands are imported on first use."""

    def list_commands(self, ctx: click.Context) -> list[str]:  # noqa: D102
        return sorted(COMMANDS)

    def get_command(self, ctx: click.Context, cmd_name: str) -> click.Command | None:
        if cmd_name not in COMMANDS:
            return None
        target = COMMANDS[cmd_name][0]
        module_name, attr = target.split(":")
        try:
            module = importlib.import_module(module_name)
        except ModuleNotFoundError as exc:  # a command whose module is not built yet
            if exc.name == module_name:
                return None
            raise
        return getattr(module, attr)

    def format_commands(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        # Short help without importing every subcommand module.
        with formatter.section("Commands"):
            formatter.write_dl([(name, COMMANDS[name][1]) for name in self.list_commands(ctx)])


@click.group(cls=LazyGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="hydrokit")
@click.option("--verbose", is_flag=True, help="Also show what libraries (pymavlink, scipy …) printed, as [name] lines.")
def cli(verbose: bool) -> None:
    """hydrokit: from a tank test to a 6-DOF underwater-vehicle model and controller.

    All quantities are SI (m, kg, s, N, rad) unless an option says otherwise. What third-party
    libraries print is kept off the terminal (--verbose shows it; HYDROKIT_LOG=FILE appends it).
    """
    from hydrokit import _quiet

    _quiet.clear()  # one command's captures
    _quiet.show(verbose)


def main(argv: list[str] | None = None) -> int:
    """Entry point; returns the process exit code (0 ok, 2 bad input, 1 internal error, 128+N signal N)."""
    from hydrokit._atomic import Interrupted, interrupt_on_signals
    from hydrokit.errors import HydrokitError

    # the CLI alone picks a backend: figures are rendered to files, never shown
    os.environ.setdefault("MPLBACKEND", "Agg")
    try:
        with interrupt_on_signals():  # SIGTERM/SIGINT unwind through the staging of outputs
            cli.main(args=argv, prog_name="hydrokit", standalone_mode=False)
    except (Interrupted, KeyboardInterrupt) as exc:
        signum = getattr(exc, "signum", signal.SIGINT)
        done = "the outputs were completed first" if getattr(exc, "written", False) else "no output written"
        click.echo(f"interrupted ({signal.Signals(signum).name}); {done}", err=True)
        return _exit(128 + signum)
    except click.exceptions.Exit as exc:
        return _exit(exc.exit_code)
    except click.ClickException as exc:
        ctx = getattr(exc, "ctx", None)
        hint = f" (see '{ctx.command_path} --help')" if isinstance(exc, click.UsageError) and ctx else ""
        click.echo(f"error: {_one_line(exc.format_message())}{hint}", err=True)
        return _exit(2)
    except click.exceptions.Abort:
        click.echo("Aborted.", err=True)
        return _exit(2)
    except HydrokitError as exc:
        click.echo(f"error: {_one_line(str(exc))}", err=True)
        return _exit(2)
    except MemoryError:
        click.echo(
            "error: not enough memory for this run; expected a smaller one (duration, samples, output step)", err=True
        )
        return _exit(2)
    except OverflowError as exc:  # a number from the input too large to compute with (e.g. a duration of 1e308 s)
        why = _one_line(str(exc), 200)
        click.echo(
            f"error: a number is too large to compute with ({why}); expected values of a realistic size", err=True
        )
        return _exit(2)
    except OSError as exc:  # the machine refused (disk full, permissions, a path that vanished)
        where = f"{_one_line(str(exc.filename), 200)}: " if exc.filename else ""
        why = exc.strerror or _one_line(str(exc))
        click.echo(f"error: {where}{why}; expected a path the system can read or write", err=True)
        return _exit(2)
    except Exception as exc:  # a bug, not bad input: still no traceback unless asked
        if os.environ.get("HYDROKIT_DEBUG"):
            raise
        msg = _one_line(str(exc))
        click.echo(f"internal error: {type(exc).__name__}: {msg} (set HYDROKIT_DEBUG=1 for details)", err=True)
        return _exit(1)
    return _exit(0)


def _one_line(text: str, limit: int = 600) -> str:
    """``text`` on one line and at most ``limit`` characters (its end, the 'expected …', is kept)."""
    line = " ".join(text.split())
    return line if len(line) <= limit else f"{line[: limit - 120]} … {line[-100:]}"


def _exit(code: int | None) -> int:
    # The console-script wrapper calls sys.exit(main()), so returning is enough.
    return 0 if code is None else int(code)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
