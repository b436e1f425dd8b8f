"""tau_min against the P_2 amplitude eps of a non-uniform stiffness, one line per branch (l, |k|)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

from ._canvas import colours, save_figure, subplots

LINE = {"subharmonic": "-", "harmonic": "--"}


def save(rows: Sequence[dict[str, Any]], path: str | Path, *, title: str) -> Path:
    """One line per branch (kind, l, |k|) of ``rows`` {"eps", "kind", "l", "k", "tau_min"}
    (:func:`spectralshell.runner.nonuniform.p2_branches`), labelled by its dominant mode."""
    fig, ax = subplots(figsize=(6.4, 4.6))
    branches = sorted({(r["kind"], r["l"], r["k"]) for r in rows}, key=lambda b: (b[1], b[2], b[0]))
    palette = colours()
    for i, (kind, l, k) in enumerate(branches):
        points = sorted((r["eps"], r["tau_min"]) for r in rows
                        if (r["kind"], r["l"], r["k"]) == (kind, l, k))
        ax.plot([p[0] for p in points], [p[1] for p in points], LINE[kind], marker=".",
                color=palette[i % len(palette)], label=f"l = {l}, |k| = {k} ({kind})")
    ax.set_xlabel("ε, amplitude of P₂(cos θ) in κ = κ₀ (1 + ε P₂(cos θ)) (dimensionless)")
    ax.set_ylabel("τ_min, forcing amplitude (dimensionless)")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7, frameon=False)
    return save_figure(fig, path, dpi=120)
