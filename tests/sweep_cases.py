"""Shared steps of the sweep tests."""

import pytest

from spectralshell.runner.sweep import run_sweep


def interrupted(scene, out, chunks: int) -> None:
    """Run the sweep ``scene`` serially into the store ``out`` and stop it as Ctrl-C would once
    ``chunks`` chunks are stored."""
    def stop(n, _):
        if n == chunks:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_sweep(scene, executor="serial", out=out, on_chunk=stop)
