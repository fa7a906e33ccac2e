"""Exceptions of rbimpact. Bad arguments raise the built-in ``ValueError``."""


class NoSolutionError(RuntimeError):
    """The impact has no solution in the chosen law.

    Raised for a Painleve-type jam in Routh's law (the normal velocity cannot reach zero
    while sliding), for Kane & Levinson or Smith when no slip direction is consistent,
    and when an iteration fails to converge (``mode_code`` says which).
    """

    def __init__(self, message, mode_code=None):
        super().__init__(message)
        self.mode_code = mode_code


class SimulationError(RuntimeError):
    """A simulation cannot continue: non-finite state, a missed event, an unsupported scene."""


class OutputError(OSError):
    """A result could not be written to a file (missing directory, a directory path, no
    permission, disk full). ``summary`` holds the text of the finished run, so that the
    work is not lost; ``paths`` the files that failed."""

    def __init__(self, message, summary="", paths=()):
        super().__init__(message)
        self.summary = summary
        self.paths = tuple(paths)

    def __str__(self):
        return self.args[0] if self.args else ""
