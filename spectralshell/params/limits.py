"""Size and cost limits checked before any work starts: the numbers, and how to raise each.

Every limit has a default, an environment variable that replaces the default for a whole process
(and the workers it starts), and, where a call can ask for more, an API keyword and a CLI flag:

======================  ==============  =============================  ================  ==============
limit                   default         environment variable           API keyword       CLI flag
======================  ==============  =============================  ================  ==============
grid points             1 000 000       SPECTRALSHELL_MAX_POINTS       ``max_points``    --max-points
result memory (bytes)   half the RAM    SPECTRALSHELL_MAX_MEMORY       --                --
estimated seconds       600             SPECTRALSHELL_MAX_SECONDS      ``max_seconds``   --max-seconds
======================  ==============  =============================  ================  ==============

Grid points are counted per axis where a range is parsed (before any array of it exists) and in
total once the axes are known (tongues: the kappa grid; tau maps: x * y * degrees; sweeps: every
[grid] axis, kind included). Result memory is the total times the bytes a point's result takes
(:data:`RESULT_BYTES`, :data:`SWEEP_BYTES`). Estimated seconds bound the cost of a solve that
can be predicted from its parameters (the cochlea's spatial and temporal truncations,
:mod:`spectralshell.solvers.cost`; the dense eigenproblems and steps of a fibre or cochlea
``simulate``, :func:`spectralshell.runner.simulate.price_stepping`). Integer ranges of a model
(degrees m <= 200, spatial modes <= 2000) are validity ranges of the model, not limits: they
are checked on a range's ends (:func:`spectralshell.params.grid.parse_int_range`) and cannot be
raised.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

from .._validate import parse_real, require_positive
from ..errors import ParameterError


def _half_the_memory() -> float:
    """Half the physical memory in bytes (4 GiB where the platform does not say)."""
    try:
        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE") / 2
    except (AttributeError, OSError, ValueError):
        return 4.0 * 2**30


@dataclass(frozen=True)
class Limit:
    """A ceiling on a computation: what it counts (``what``), its ``default``, the environment
    variable ``env`` that replaces the default, and the API ``keyword`` that raises it for one
    call (empty where there is none; the CLI names its flag instead, see ``cli.main``)."""

    what: str
    default: float
    env: str
    keyword: str = ""

    def value(self, given: float | None = None) -> float:
        """The limit in force: ``given`` (a call's keyword), else $``env``, else the default."""
        if given is not None:
            return require_positive(self.keyword, given)
        text = os.environ.get(self.env)
        return self.default if text is None else require_positive(self.env,
                                                                  parse_real(self.env, text))

    def how_to_raise(self) -> str:
        """'raise it with ...': the keyword and environment variable of this limit."""
        ways = [f"{self.keyword}="] if self.keyword else []
        return f"raise it with {' or '.join(ways + [f'{self.env}=...'])}"

    def check(self, name: str, amount: float, given: float | None = None,
              advice: str = "") -> None:
        """Refuse ``amount`` (of ``what``) needed by ``name`` above the limit in force.

        Raises
        ------
        ParameterError : one line naming ``name``, the amount, the limit and how to raise it
            (and ``advice``, another way out, after it).
        """
        limit = self.value(given)
        if amount > limit:
            raise ParameterError(f"{name} is invalid: it needs {_show(amount)} {self.what}, "
                                 f"above the limit of {_show(limit)}; {self.how_to_raise()}"
                                 f"{'; or ' + advice if advice else ''}")


def _show(amount: float) -> str:
    """A count as an integer (1000000), other amounts to 3 digits (1.2e+10)."""
    return str(int(amount)) if float(amount).is_integer() and amount < 1e12 else f"{amount:.3g}"


POINTS = Limit("grid points", 1_000_000, "SPECTRALSHELL_MAX_POINTS", "max_points")
MEMORY = Limit("bytes of results", _half_the_memory(), "SPECTRALSHELL_MAX_MEMORY")
SECONDS = Limit("seconds (estimated)", 600.0, "SPECTRALSHELL_MAX_SECONDS", "max_seconds")
#: Bytes a solved point takes as result objects (tongues and tau-map rows: each kind's
#: MarginalTau with its tau array); measured with tracemalloc: ~1 KB for Mathieu, both kinds.
RESULT_BYTES = 2048
#: Bytes a sweep grid point takes: its stored variables (at most 51 bytes: tau_min,
#: error_estimate, complete_to, n_temporal, n_spatial, has_tau, spatial_converged, computed)
#: and the Dataset.
SWEEP_BYTES = 64
#: Another way out of a points limit, named in its message.
SPLIT = "split the grid into sweeps with a store (sweep with out=PATH.zarr)"


def check_points(name: str, count: int, max_points: int | None = None) -> None:
    """Refuse a range ``name`` of ``count`` points above the points limit (ParameterError)."""
    POINTS.check(name, count, max_points, SPLIT)


def check_grid(name: str, shape: tuple[int, ...], bytes_per_point: int,
               max_points: int | None = None) -> None:
    """Refuse a grid ``name`` of ``shape`` above the points limit, or whose results
    (``bytes_per_point`` each) exceed the memory limit (ParameterError)."""
    count = math.prod(shape)
    what = f"{name} = {' x '.join(map(str, shape))}" if len(shape) > 1 else name
    check_points(what, count, max_points)
    MEMORY.check(what, count * bytes_per_point, advice=SPLIT)
