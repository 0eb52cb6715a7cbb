"""The ``domes`` command line: one subcommand per pipeline stage.

Each stage's subpackage owns its subcommand in a ``cli`` module with a
``register(subparsers)`` function; this module only lists them and runs
the chosen one. Errors in the input exit with status 2 and a message on
stderr; Ctrl-C exits with status 130 and no traceback.

>>> main(["chains", "--links", "6", "--dof", "1", "--count"])
2
0
"""

from __future__ import annotations

import argparse
import importlib
import logging
import signal
import sys

from domes import __version__
from domes.errors import DomesError
from domes.execution.threads import limited_threads

#: Modules that register a subcommand, in the order of the pipeline.
SUBCOMMAND_MODULES = (
    "domes.cli.synthesis",
    "domes.cli.chains",
    "domes.cli.regenerate",
    "domes.cli.kb",
    "domes.cli.kinematics",
    "domes.cli.tolerance",
    "domes.cli.dynamics",
    "domes.cli.curves",
    "domes.cli.synthesize",
    "domes.cli.cam",
    "domes.cli.catalogue",
    "domes.cli.draw",
    "domes.cli.design",
    "domes.cli.drum",
    "domes.cli.studio",
)


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The argument parser with every stage's subcommand registered.

    Given ``command`` (the subcommand a command line names, :func:`chosen`), only the module that owns it
    registers its options and loads what they need; every other subcommand is listed by its name and help line
    (its module's ``COMMANDS``), which is all ``domes --help`` and argparse's errors show of it.
    """
    parser = argparse.ArgumentParser(
        prog="domes",
        description="DOMES-py: creative mechanism design by type synthesis.",
    )
    parser.add_argument("--version", action="version", version=f"domes {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for name in SUBCOMMAND_MODULES:
        module = importlib.import_module(name)
        commands = getattr(module, "COMMANDS", None)
        if command is None or commands is None or command in commands:
            module.register(sub)
        else:
            for word, text in commands.items():
                sub.add_parser(word, help=text)
    return parser


def chosen(argv: list[str]) -> str:
    """The subcommand a command line names: its first word that is not an option ("" for none, as in
    ``domes --help``; the top-level options take no value)."""
    return next((word for word in argv if not word.startswith("-")), "")


def _notices() -> None:
    """Notices of the package (e.g. "created your case base ...") go to stderr as ``domes: ...``."""
    logger = logging.getLogger("domes")
    if not logger.handlers:
        handler = logging.StreamHandler()
        handler.setFormatter(logging.Formatter("domes: %(message)s"))
        logger.addHandler(handler)
        logger.setLevel(logging.INFO)
        logger.propagate = False


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    _notices()
    argv = sys.argv[1:] if argv is None else list(argv)
    parser = build_parser(chosen(argv))
    args = parser.parse_args(argv)
    try:
        with limited_threads():  # BLAS and OpenMP: one thread unless DOMES_THREADS says more
            return int(args.func(args) or 0)
    except DomesError as exc:
        print(f"domes {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"\ndomes {args.command}: interrupted", file=sys.stderr)
        return 128 + signal.SIGINT
    except BrokenPipeError:
        # The reader went away (e.g. `domes chains ... | head`): not an error.
        sys.stderr.close()
        return 0
