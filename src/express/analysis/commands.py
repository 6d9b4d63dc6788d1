"""Command-line subcommands of the analyses (added by :func:`add_analysis_commands`)."""

from __future__ import annotations


def add_analysis_commands(commands, add_model_arguments) -> None:
    """Register ``simulate``, ``frf``, ``eigen``, ``critical-speed`` and ``demo``."""
