"""marginal_tau and certify_empty_answer run block models (blocks larger than 2 x 2: the
cochlea's M x M) on one BLAS thread, where OpenBLAS's threads only cost (solvers/marginal.py,
on_block_threads), and leave the limit as it was; other models keep the caller's threads."""

import dataclasses
import math

import numpy as np
import pytest
from threadpoolctl import threadpool_info, threadpool_limits

from spectralshell.models.cochlea import hill_system as cochlea_system
from spectralshell.models.mathieu import hill_system as mathieu_system
from spectralshell.params.physical import cochlea_forced
from spectralshell.solvers import marginal


def _threads() -> int:
    return max(d["num_threads"] for d in threadpool_info() if d["user_api"] == "blas")


COCHLEA = cochlea_system(n_spatial=16, **cochlea_forced(
    rho=1.0, mu=0.02, sigma=2.72e8, length=3.5, lambda_c=1.4, omega=2 * math.pi * 2826.0))


@pytest.mark.parametrize("system, limited", [(COCHLEA, True),
                                             (mathieu_system(kappa=0.26, nu=0.1),
                                              False)])
def test_block_models_solve_on_one_blas_thread(system, limited, monkeypatch):
    seen = []
    solve = marginal.truncation_taus

    def recording(*args, **kwargs):
        seen.append(_threads())
        return solve(*args, **kwargs)

    monkeypatch.setattr(marginal, "truncation_taus", recording)
    with threadpool_limits(2, user_api="blas"):
        outer = _threads()  # 1 where BLAS has one thread only: the Mathieu case tells less
        answer = marginal.marginal_tau(system, "subharmonic", n_temporal=6, tau_max=0.5)
        assert _threads() == outer  # restored
        empty = dataclasses.replace(answer, tau_min=None, tau=np.empty(0), empty_proved=False,
                                    count_failed=False)
        monkeypatch.setattr(marginal, "_empty_certified",
                            lambda *args: seen.append(_threads()) or True)
        marginal.certify_empty_answer(system, "subharmonic", empty, 0.5, True)
        assert _threads() == outer
    # two truncations, and the count of the viscous cochlea's empty answer (Mathieu's D(s) is a
    # polynomial: its empty answers need no count)
    assert len(seen) == (3 if limited else 2) and set(seen) == ({1} if limited else {outer})
