"""Errors the library raises on purpose, and the problems found in input files.

Readers and validators collect :class:`Problem` records instead of stopping at the
first one; :class:`ModelError` carries them all.  Every error a user can cause is an
:class:`InputError`; an analysis that ran on good input but could not give a valid
result raises :class:`AnalysisError`.  The command line maps them to exit statuses:

==================  ======  ===========================================================
exception           status  meaning
==================  ======  ===========================================================
(none)              0       success
``AnalysisError``   1       no valid result (diverged run, ``NoCriticalSpeedError``)
``InputError``      2       bad input: ``ModelError`` (one line per problem),
                            ``UsageError`` (command line), ``OutputError`` (a
                            destination that cannot be written), ``ArgumentError``
                            (a library function given a value outside its domain)
anything else       70      an internal error (a bug): one line, traceback on ``--debug``
==================  ======  ===========================================================

``InputError`` derives from :class:`ValueError` so that callers written against the
older API (``except ValueError``) still catch bad input.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = [
    "EXIT_ANALYSIS",
    "EXIT_ASSESSMENT",
    "EXIT_INPUT",
    "EXIT_INTERNAL",
    "EXIT_OK",
    "AnalysisError",
    "ArgumentError",
    "ExpressError",
    "InputError",
    "ModelError",
    "ModelWarning",
    "NoCriticalSpeedError",
    "OutputError",
    "Problem",
    "RowProblems",
    "UsageError",
    "excerpt",
]

#: Exit statuses of the command line (``docs/cli.md``); 70 is ``EX_SOFTWARE`` of sysexits.h;
#: 3: a result was given and its assessment fails (``simulate --assess``).
EXIT_OK, EXIT_ANALYSIS, EXIT_INPUT, EXIT_ASSESSMENT, EXIT_INTERNAL = 0, 1, 2, 3, 70


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


def excerpt(text: str, limit: int = 40) -> str:
    """``text`` quoted for a message and cut to ``limit`` characters: an error may quote
    a short excerpt of a file, never more (the file may not be the user's own).

    Examples
    --------
    >>> excerpt("root:x:0:0:root:/root:/bin/bash", 12)
    "'root:x:0...'"
    """
    return repr(text if len(text) <= limit else text[: limit - 3] + "...")


class RowProblems:
    """The bad rows of a data file (a CSV profile), reported within bounds: the first
    ``most`` rows listed, then a count; only one quotes what it found, as a short
    :func:`excerpt`, since the file may not be the user's own.

    Examples
    --------
    >>> rows = RowProblems("p.csv", most=1)
    >>> rows.add(2, "", "expected 2 columns", "root:x:0:0")
    >>> rows.add(3, "", "expected 2 columns", "daemon:x:1:1")
    >>> [str(p) for p in rows.problems()]
    ["p.csv:2: expected 2 columns: 'root:x:0:0'", 'p.csv: 2 bad rows in all, the first 1 listed']
    """

    def __init__(self, file: str, most: int = 20):
        self.file, self.most = file, most
        self.listed: list[Problem] = []
        self.count = 0
        self.quoted = False  # set when the file was quoted already (a bad header)

    def add(self, line: int, item: str, message: str, found: str, template: str = "{message}: {found}") -> None:
        """One bad row: ``message`` says what is wrong, ``found`` is what the row holds;
        ``template`` places both in the one message that quotes."""
        self.count += 1
        if self.count <= self.most:
            shown = message if self.quoted else template.format(message=message, found=excerpt(found))
            self.quoted = True
            self.listed.append(Problem(self.file, line, item, shown))

    def problems(self) -> list[Problem]:
        """The listed problems, then the count when some were left out."""
        if self.count <= self.most:
            return list(self.listed)
        return [*self.listed, Problem(self.file, None, "", f"{self.count} bad rows in all, the first {self.most} listed")]


class ExpressError(Exception):
    """Base of the errors EXPRESS raises on purpose (anything else is a bug)."""


class InputError(ExpressError, ValueError):
    """Bad input of any kind: a model or track file, a command-line value, a destination.

    The command line prints ``error: <message>`` and exits with status 2.
    """

    def lines(self) -> list[str]:
        """The message as the lines the command line prints (one per problem)."""
        return str(self).split("\n") if str(self) else [type(self).__name__]


class ModelError(InputError):
    """A model (or track, or other input file) that cannot be used; :attr:`problems`
    lists every reason, one :class:`Problem` each."""

    def __init__(self, problems: list[Problem] | tuple[Problem, ...]):
        self.problems = tuple(problems)
        super().__init__("\n".join(str(problem) for problem in self.problems))

    def lines(self) -> list[str]:
        return [str(problem) for problem in self.problems]


class UsageError(InputError):
    """A command-line mistake (a bad ``--set``, an option out of its range, an output
    over an input); the CLI prints it as one ``error:`` line and exits with status 2."""


class OutputError(InputError):
    """A destination that cannot be written (a directory, a path below a file, no
    permission, an input file); nothing was replaced."""


class ArgumentError(InputError):
    """A library function called with a value outside its domain: a speed that is not
    positive, ``v_min >= v_max``, an unknown DOF, parameter or option, a profile the
    wheels cannot reach.  Raised by the analyses and the rail modules (``analysis/``,
    ``rail/``, ``numeric/``); the command line prints the message and exits with status 2.
    A :class:`ValueError` too, as every :class:`InputError`."""


class AnalysisError(ExpressError, RuntimeError):
    """An analysis ran on valid input but could not give a valid result (a diverged
    simulation, a singular response, no critical speed where one was required).

    The command line prints ``error: <message>`` and exits with status 1.
    """


class NoCriticalSpeedError(AnalysisError):
    """A result that needs a crossing of the stability boundary found none in the range
    scanned (already unstable at the lowest speed, stable up to the highest, or a
    crossing that is not a simple oscillatory mode)."""


class ModelWarning(UserWarning):
    """A value that is legal but unusual enough to mention (a negative stiffness or
    damping: a modelling device, whose consequences the analyses check themselves);
    the command line prints it as one ``warning:`` line."""
