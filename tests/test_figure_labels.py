"""Figure text of issue 26: every line named, no raw parameter dumps, typeset symbols. Figures
are written as SVG with text kept as text, and the text is read back."""

import re

import matplotlib
import numpy as np
import pytest

import spectralshell as ss
from spectralshell.cli import main
from spectralshell.plots import cochlea, sweep_plot, trajectory


def svg_text(write, path) -> str:
    """All text drawn by ``write(path)`` (an SVG written with fonts as text)."""
    with matplotlib.rc_context({"svg.fonttype": "none"}):
        write(path)
    return " ".join(re.sub(r"<[^>]*>", " ", path.read_text()).split())


def test_det_contour_legend_names_the_real_and_imaginary_parts(tmp_path):
    re_, im_ = np.meshgrid(np.linspace(-1, 1, 20), np.linspace(0, 1, 20))
    det = (re_ + 0.3) + 1j * (im_ - 0.5)
    text = svg_text(lambda p: cochlea.save_det_contours(
        [("panel", re_, im_, det, np.array([-0.3 + 0.5j]))], p), tmp_path / "det.svg")
    assert "Re det T = 0" in text and "Im det T = 0" in text


def test_response_figure_is_titled_in_symbols_with_every_line_labelled(tmp_path):
    png = tmp_path / "r.svg"
    with matplotlib.rc_context({"svg.fonttype": "none"}):
        assert main(["response", "cochlea", "--omega", "1000", "--n-spatial", "16",
                     "--png", str(png)]) == 0
    text = " ".join(re.sub(r"<[^>]*>", " ", png.read_text()).split())
    assert "None" not in text and "spatial_mode" not in text and "n_spatial" not in text
    assert "ω = 1000 rad/s" in text and "κ = " in text and "M = 16" in text
    for line in ("envelope", "profile", "envelope peak", "WKB peak"):
        assert f"tone: {line}" in text or f"): {line}" in text


def test_simulation_figures_typeset_x_y_and_the_shape_has_a_colour_bar(tmp_path):
    traj = ss.simulate({"params": {"kappa": 1.0, "nu": 0.05}, "initial": {"shape": "2:0"},
                        "simulate": {"t_end": 6.0, "n_radial": 16}})
    fig, ax = trajectory.subplots(figsize=(5, 3))
    trajectory.draw_amplitudes(ax, traj)
    assert ax.get_ylabel().startswith("$X^Y") and "X^Y(t) /" not in ax.get_ylabel()
    theta = np.linspace(0.1, np.pi - 0.1, 8)
    phi = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    X = np.cos(theta)[:, None] * np.ones(8)
    text = svg_text(lambda p: trajectory.save_shape(theta, phi, [X], [0.0], p),
                    tmp_path / "shape.svg")
    letters = "".join(text.split())  # mathtext labels come letter by letter
    assert "(red:outward,blue:inward)" in letters  # the colour bar's label
    assert "−1.00" in text and "0.00" in text      # and its ticks


def test_plot_of_a_line_sweep_names_the_kinds_in_words(tmp_path):
    ds = ss.sweep({"model": "mathieu", "ask": ["tau_min"], "params": {"nu": 0.1},
                   "grid": {"kappa": {"start": 0.1, "stop": 1.2, "num": 12},
                            "kind": ["harmonic", "subharmonic"]}}, executor="serial")
    text = svg_text(lambda p: sweep_plot.save(ds, p), tmp_path / "line.svg")
    assert "harmonic" in text and "subharmonic" in text
