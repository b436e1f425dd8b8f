"""Minimum-tau maps (Fig 6.13, issue 26): cells without instability have their own colour and a
legend entry, decided by ``has_tau`` whether the store holds tau_max or NaN there."""

import matplotlib.colors
import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg

import spectralshell as ss
from spectralshell.plots import sweep_plot, tau_map
from spectralshell.plots._canvas import subplots


@pytest.fixture(scope="module")
def sweep():
    """Mathieu over (kappa, nu): at large nu no tau <= 1/2 exists (damping beats forcing)."""
    return ss.tau_map("mathieu", x=("kappa", "0.1:1.5:6"), y=("nu", "0.01:0.6:5"), workers=1)


def _cell_colours(ds):
    """RGB of the rendered map at each (nu, kappa) cell centre, read from the pixels."""
    fig, ax = subplots(figsize=(6.0, 4.5))
    tau_map.draw(ax, ds, min_cells=10_000)  # no band labels over the cell centres
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    pixels = np.asarray(canvas.buffer_rgba())[..., :3] / 255.0
    height = pixels.shape[0]
    out = np.empty((ds.sizes["nu"], ds.sizes["kappa"], 3))
    for i, nu in enumerate(ds["nu"].values):
        for j, kappa in enumerate(ds["kappa"].values):
            px, py = ax.transData.transform((kappa, nu))
            out[i, j] = pixels[int(round(height - py)), int(round(px))]
    return out, ax


@pytest.mark.parametrize("convention", ["tau_max", "nan"])
def test_cells_without_instability_are_light_grey_and_named_in_the_legend(sweep, convention):
    ds = sweep if convention == "tau_max" else sweep.assign(
        tau_min=sweep["tau_min"].where(sweep["has_tau"]))
    none = ~ds["has_tau"].any("kind").transpose("nu", "kappa").values
    assert none.any() and not none.all()
    colours, ax = _cell_colours(ds)
    grey = np.array(matplotlib.colors.to_rgb(sweep_plot.NONE_COLOUR))
    is_grey = np.all(np.abs(colours - grey) < 0.02, axis=-1)
    np.testing.assert_array_equal(is_grey, none)
    # the coloured cells are blue (Blues_r), never the grey
    assert np.all(colours[~none][:, 2] > colours[~none][:, 0] + 0.05)
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["none: no τ ≤ 0.5"]


def test_a_map_with_instability_everywhere_has_no_none_entry(sweep):
    full = sweep.isel(nu=[0])
    full = full.sel(kappa=full["has_tau"].any(["kind", "nu"]))
    ds = ss.tau_map("mathieu", x=("kappa", full["kappa"].values), y=("nu", [0.005, 0.01]),
                    workers=1)
    assert ds["has_tau"].any("kind").all()
    fig, ax = subplots(figsize=(5.0, 4.0))
    sweep_plot.draw(ax, ds)
    assert ax.get_legend() is None
