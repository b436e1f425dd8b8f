"""The public drawing functions (``spectralshell.plot``): each draws one result on ``ax`` and
returns that Axes.

With ``ax=None`` each makes a new figure outside pyplot (:mod:`._canvas`) and returns its Axes
(``ax.figure`` saves it, ``ax.figure.savefig(...)``); the user's backend is never touched. In a
notebook, pass an Axes of your own figure::

    fig, ax = plt.subplots()
    ss.plot.tongues(ss.tongues("mathieu", kappa="0:3:301", nu=0.1), ax=ax)

The result objects with a picture draw themselves the same way: ``result.plot(ax=ax)``
(:func:`draw` picks the function by the result's type).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from . import (cochlea, ince_strutt, natural_modes as modes_plot, stepped as stepped_plot,
               trajectory as trajectory_plot)
from ._canvas import axes_or_new
from ..errors import ParameterError
from ..results.floquet import FloquetResult, TonguesResult
from ..results.modes import NaturalModesResult
from ..results.response import ResponseResult
from ..results.stepped import SteppedRun
from ..results.trajectory import Trajectory

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.axes import Axes

__all__ = ["tongues", "tau_map", "floquet", "natural_modes", "response", "trajectory", "stepped",
           "draw"]


def tongues(result: TonguesResult, ax: Axes | None = None, **options: Any) -> Axes:
    """Ince-Strutt diagram of :func:`spectralshell.tongues` (``options``: tau_max, title,
    x_scale, x_label of :func:`spectralshell.plots.ince_strutt.draw`)."""
    ax = axes_or_new(ax, figsize=(6.4, 4.8))
    ince_strutt.draw(ax, result, **options)
    return ax


def tau_map(ds: xr.Dataset, ax: Axes | None = None, *, min_cells: int = 6) -> Axes:
    """A sweep or tau-map Dataset (:func:`spectralshell.tau_map`, :func:`spectralshell.sweep`):
    the labelled minimum-tau map with its colour bar over two real axes, tau_min curves over
    one."""
    from . import sweep_plot  # lazy: xarray

    ax = axes_or_new(ax, figsize=(7.5, 5.5))
    sweep_plot.draw(ax, ds, min_cells=min_cells)
    return ax


def floquet(result: FloquetResult, ax: Axes | None = None, *, tau_max: float | None = None) -> Axes:
    """The marginal amplitudes of each kind of :func:`spectralshell.floquet` on a tau axis."""
    ax = axes_or_new(ax, figsize=(6.4, 2.8))
    ince_strutt.draw_marginals(ax, result, tau_max=tau_max)
    return ax


def natural_modes(result: NaturalModesResult, ax: Axes | None = None) -> Axes:
    """The modes of :func:`spectralshell.natural_modes` in the complex gamma plane."""
    ax = axes_or_new(ax, figsize=(6.0, 4.5))
    modes_plot.draw(ax, result)
    return ax


def response(result: ResponseResult, ax: Axes | None = None) -> Axes:
    """Envelope and profile of :func:`spectralshell.response` along the membrane."""
    ax = axes_or_new(ax, figsize=(10.5, 3.6))
    cochlea.draw_response(ax, result)
    ax.set_title(cochlea.response_title(result), fontsize=9)
    ax.legend(fontsize=6, loc="center left", bbox_to_anchor=(1.01, 0.5))
    return ax


def trajectory(result: Trajectory, ax: Axes | None = None, *, log: bool = False) -> Axes:
    """Mode amplitudes of :func:`spectralshell.simulate` against time, each rescaled to start
    at 1; ``log``: their moduli on a log axis with the fitted envelopes."""
    ax = axes_or_new(ax, figsize=(7.5, 4.0))
    if log:
        trajectory_plot.draw_log_amplitudes(ax, result)
        ax.legend(fontsize=6, ncol=2)
    else:
        trajectory_plot.draw_amplitudes(ax, result)
    return ax


def stepped(result: SteppedRun, ax: Axes | None = None, *,
            exponent: complex | None = None) -> Axes:
    """The fitted series of a time-stepped fibre or cochlea (``ss.simulate``) on a log axis
    against time in forcing periods, with its fitted growth and, given ``exponent`` (e.g.
    :func:`spectralshell.runner.simulate.leading_exponent` of the run), the Floquet
    exponent's slope."""
    ax = axes_or_new(ax, figsize=(7.5, 4.5))
    stepped_plot.draw(ax, result, exponent=exponent)
    return ax


#: The drawing function of each result type with a picture.
DRAWERS = {TonguesResult: tongues, FloquetResult: floquet, NaturalModesResult: natural_modes,
           ResponseResult: response, Trajectory: trajectory, SteppedRun: stepped}


def draw(result: Any, ax: Axes | None = None, **options: Any) -> Axes:
    """Draw any result with a picture (a result object, or a sweep/tau-map Dataset) on ``ax``.

    Raises
    ------
    ParameterError : ``result`` has no picture.
    """
    for kind, function in DRAWERS.items():
        if isinstance(result, kind):
            return function(result, ax, **options)
    if type(result).__name__ == "Dataset":
        return tau_map(result, ax, **options)
    names = ", ".join(k.__name__ for k in DRAWERS)
    raise ParameterError(f"result = a {type(result).__name__} is invalid for plotting: it has no "
                         f"picture (drawn: {names} and sweep Datasets)")
