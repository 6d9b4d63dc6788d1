"""Problems found in input files, reported all at once.

Readers and validators collect :class:`Problem` records instead of stopping at the
first one; :class:`ModelError` carries them all, and the CLI prints one line each,
``file:line: item: message``, and exits with status 2.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Problem:
    """One thing wrong (or suspicious) in an input file.

    Attributes
    ----------
    file : str
        Path of the file as given by the user.
    line : int or None
        1-based line number, when known.
    item : str
        What the problem is about (``CP C3``, ``parameter kLU``, ``section (4) TSD``).
    message : str
        What is wrong, in words.
    """

    file: str
    line: int | None
    item: str
    message: str

    def __str__(self) -> str:
        where = f"{self.file}:{self.line}" if self.line is not None else self.file
        return f"{where}: {self.item}: {self.message}" if self.item else f"{where}: {self.message}"


class ModelError(ValueError):
    """A model that cannot be used; :attr:`problems` lists every reason."""

    def __init__(self, problems: list[Problem] | tuple[Problem, ...]):
        self.problems = tuple(problems)
        super().__init__("\n".join(str(problem) for problem in self.problems))


class UsageError(ValueError):
    """A command-line mistake (a bad ``--set``, an output over an input, a bad option
    value); the CLI prints it as one ``error:`` line and exits with status 2."""
