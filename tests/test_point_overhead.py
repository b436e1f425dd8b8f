"""The per-point shortcuts of a map's sweep (issue 25) give what they replace: kept truncation
frequencies, kept truncation schedules, the block index by position, and the sweep's capped
complete_to."""

import itertools

import numpy as np
import pytest

from spectralshell.discretise.fourier import (frequencies, real_indices, truncation_frequencies,
                                              two_sided_indices)
from spectralshell.models.registry import hill_system
from spectralshell.params.registry import make_params
from spectralshell.params.sweep_grid import sweep_spec
from spectralshell.runner.layout import block_index, block_shape, chunks
from spectralshell.runner.solve import solve_chunk
from spectralshell.solvers.marginal import N_MAX, TruncationSchedule, finer


@pytest.mark.parametrize("kind", ["harmonic", "subharmonic"])
def test_truncation_frequencies_are_fresh_copies_of_the_computed_ones(kind):
    for n in (1, 7, 24, 175):
        for two_sided, indices in ((True, two_sided_indices(kind, n)), (False, real_indices(n))):
            got = truncation_frequencies(kind, n, two_sided)
            want = frequencies(kind, indices)
            assert got.dtype == want.dtype and got.tobytes() == want.tobytes()
            got[0] = 99.0  # a caller's own array: writing to it changes nothing kept
            assert truncation_frequencies(kind, n, two_sided).tobytes() == want.tobytes()


def test_kept_schedules_follow_the_rule():
    for m, kappa in ((2, 0.3), (6, 4.0), (4, 40.0)):
        system = hill_system(make_params("sphere", {"m": m, "kappa": kappa, "nu": 1e-3}))
        seq = TruncationSchedule.of(system).sequence()
        assert seq[0] == TruncationSchedule.of(system).first and seq[-1] == N_MAX
        assert all(b == min(finer(a), N_MAX) for a, b in zip(seq, seq[1:]))


def test_block_index_places_line_and_kind_wherever_the_kind_axis_is():
    spec = sweep_spec({"model": "sphere", "ask": ["tau_min"], "params": {"nu": 1e-3},
                       "grid": {"kind": ["subharmonic", "harmonic"], "m": [2, 3],
                                "kappa": [0.5, 1.0, 1.5]},
                       "tau_min": {"tau_max": 0.5}})
    line, at_kind = spec.line_axis, spec.dims.index("kind")
    for j, q in itertools.product(range(3), range(2)):
        want = tuple(q if i == at_kind else j if i == line else 0 for i in range(len(spec.axes)))
        assert block_index(spec, j, q) == want


def test_a_chunk_stores_complete_to_capped_at_tau_max():
    spec = sweep_spec({"model": "mathieu", "ask": ["tau_min"], "params": {"nu": 0.1},
                       "grid": {"kappa": [0.3, 0.9, 1.4]}, "tau_min": {"tau_max": 2.0}})
    chunk = chunks(spec)[0]
    block = solve_chunk(spec, chunk)
    assert block.arrays["complete_to"].shape == block_shape(spec, chunk)
    assert np.all(block.arrays["complete_to"] <= 2.0)
    found = block.arrays["has_tau"]
    assert np.all(block.arrays["complete_to"][found] >= block.arrays["tau_min"][found])
