"""Exception types of spectralshell (a leaf module: imports nothing from the package).

Every error the package raises on purpose derives from :class:`SpectralShellError`, so that
callers can catch the package's errors without catching programming mistakes.
"""


class SpectralShellError(Exception):
    """Base class of every error raised on purpose by spectralshell."""


class ParameterError(SpectralShellError, ValueError):
    """A parameter is outside its allowed range; the message names parameter, value and range."""


class ConvergenceError(SpectralShellError, RuntimeError):
    """A computation did not reach its requested accuracy; the message says what to change."""


class BackendUnavailable(SpectralShellError, ImportError):
    """An optional backend (e.g. an extra) is not installed; the message names the extra."""


class StoreDamaged(ParameterError):
    """A sweep store holds chunks that are missing, unreadable or altered since they were
    written, or was written before ``complete_to`` existed (its empty points never proved);
    the message counts them and says how to recompute them."""


class StoreBusy(ParameterError):
    """A sweep store is being written by another process; the message names it (pid, host,
    since when)."""


class UncertifiedWarning(UserWarning):
    """A map or sweep holds points where no marginal tau was found but the zero count could
    not prove that none exists (issue 23): they are marked (``complete_to`` below the point's
    bound), not "none"; the message counts them and says what to change."""


class SweepInterrupted(KeyboardInterrupt):
    """Ctrl-C during a sweep: ``kept`` grid points (of ``points``) are in the store ``out``
    (None: the sweep was in memory only, nothing is kept); rerunning the same sweep with the
    same ``out`` resumes from there."""

    def __init__(self, kept: int, points: int, out: str | None):
        super().__init__(kept, points, out)
        self.kept, self.points, self.out = kept, points, out

    def __str__(self) -> str:
        if self.out is None:
            return f"nothing kept: the sweep of {self.points} points had no store (out)"
        return f"{self.kept} of {self.points} points are stored in {self.out}"
