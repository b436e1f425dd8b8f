"""Cochlea figures (thesis 5.4, 5.6.1): files written, and the data behind them checked against
independent facts (Table 5.2's principal subharmonic finger; natural modes decay)."""

import json

import numpy as np
import pytest

from spectralshell.reports.figures import FIGURES, make_figure


def test_registered():
    assert {"fig-5.5", "fig-5.7", "fig-5.8", "fig-5.9", "fig-5.12", "fig-5.14"} <= set(FIGURES)


@pytest.mark.slow
def test_fig_5_7_and_5_12(tmp_path):
    paths = make_figure("fig-5.7", tmp_path) + make_figure("fig-5.12", tmp_path)
    assert all(p.exists() and p.stat().st_size > 0 for p in paths)
    modes = json.loads((tmp_path / "fig-5.7.json").read_text())
    assert all(m["gamma_re"] < 0 for d in modes.values() for m in d["modes"])  # all modes decay
    data = json.loads((tmp_path / "fig-5.12.json").read_text())
    omega = np.array(data["omega"])
    k1 = data["modes"]["1"]
    sub = np.array([t[0] if t else np.inf for t in k1["tau"]["subharmonic"]])
    # k = 1: the principal subharmonic finger reaches tau ~ 0 near sqrt(kappa/2) = 1/2, i.e.
    # omega = sqrt(2 sigma pi/(rho L)) = 1036 rad/s (inviscid); Table 5.2: unstable at 1000.
    inviscid = np.sqrt(2 * 6e5 * np.pi / 3.5)
    assert abs(omega[np.argmin(sub)] - inviscid) < 20
    tip = min((t for t in k1["tips"] if t["kind"] == "subharmonic"), key=lambda t: t["tau"])
    assert abs(tip["omega"] - inviscid) < 20 and tip["tau"] <= sub.min()
    # the traced boundaries pass through every grid value of tau <= 1
    on_curves = np.concatenate([b["tau"] for b in k1["boundaries"] if b["kind"] == "subharmonic"])
    grid = np.concatenate([t for t in k1["tau"]["subharmonic"]])
    grid = grid[grid <= 1.0]
    assert np.abs(grid[:, None] - on_curves[None, :]).min(axis=1).max() < 1e-12
