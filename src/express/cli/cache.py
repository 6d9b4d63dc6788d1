"""``express cache info|clear``: the derivation cache's place, size and entries, or empty it
(:mod:`express.io.cache`, ``docs/cache.md``)."""

from __future__ import annotations

import sys
from collections.abc import Sequence

from express.cli.runner import run_command

__all__ = ["add_parser", "main", "run"]


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "cache", help="show or empty the derivation cache (info, clear)",
        description="The derivation cache keeps each model's derived equations and compiled functions, so that "
        "a second run of any command on the same files skips the symbolic work. `info` shows its place "
        "(EXPRESS_CACHE_DIR, else the user's cache directory), size, bound (EXPRESS_CACHE_MB) and entries; "
        "`clear` removes every entry. EXPRESS_NO_CACHE=1 or --no-cache works without it. See docs/cache.md.",
    )
    parser.add_argument("action", choices=("info", "clear"), help="info: place, size and entries; clear: remove them")
    parser.set_defaults(handler=run)


def run(action: str) -> int:
    """Print the cache's information or clear it; returns the exit status."""
    from express.io.cache import cache_info, clear_cache

    if action == "clear":
        removed = clear_cache()
        print(f"removed {removed} entr{'y' if removed == 1 else 'ies'} from {cache_info().directory}")
        return 0
    info = cache_info()
    state = "on" if info.enabled else "off (EXPRESS_NO_CACHE)"
    if info.refused is not None:
        state = f"not used: the folder {info.refused}"
    print(f"place: {info.directory}")
    print(f"state: {state}")
    print(f"size: {_megabytes(info.size)} in {info.entries} entr{'y' if info.entries == 1 else 'ies'} "
          f"(bound {_megabytes(info.bound)}, least recently used removed first; EXPRESS_CACHE_MB)")
    for key, name, size in info.models:
        print(f"  {key[:16]}  {_megabytes(size):>10}  {name}")
    return 0


def _megabytes(size: int) -> str:
    return f"{size / (1024 * 1024):.2f} MB"


def main(argv: Sequence[str] | None = None) -> int:
    """``express cache`` with ``argv`` (default ``sys.argv[1:]``) alone: its exit status
    (:func:`express.cli.runner.run_command`, the parsing and errors of :func:`express.cli.main`)."""
    return run_command(sys.modules[__name__], argv)
