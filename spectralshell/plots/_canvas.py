"""The one matplotlib set-up of plots/: the non-interactive backend, and how a figure is written."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

__all__ = ["plt", "save_figure"]


def save_figure(fig, path: str | Path, *, dpi: int = 120,
                rect: tuple[float, float, float, float] | None = None) -> Path:
    """Lay out ``fig`` (inside ``rect``, figure coordinates), write it as PNG, close it."""
    fig.tight_layout(rect=rect)
    path = Path(path)
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return path
