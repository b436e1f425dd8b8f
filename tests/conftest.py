"""Shared oracles for the tests."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp


def mathieu_monodromy(kappa: float, nu: float, tau: float, periods: int = 1) -> np.ndarray:
    """Monodromy matrix of u'' + nu u' + kappa (1 + 2 tau sin t) u = 0 over ``periods`` x 2 pi,
    integrated with scipy's DOP853 at rtol 1e-12 (an oracle independent of the Hill method)."""

    def rhs(t, y):
        return [y[1], -nu * y[1] - kappa * (1 + 2 * tau * np.sin(t)) * y[0]]

    cols = [solve_ivp(rhs, (0, 2 * np.pi * periods), y0, method="DOP853", rtol=1e-12,
                      atol=1e-14).y[:, -1] for y0 in ([1.0, 0.0], [0.0, 1.0])]
    return np.column_stack(cols)


@pytest.fixture
def monodromy():
    return mathieu_monodromy


@pytest.fixture(scope="session")
def built():
    """``built(name)``: the result of ``result_cases.CASES[name]``, built once per session."""
    from result_cases import CASES  # on first use: spectralshell is not imported by conftest

    cache = {}

    def get(name):
        if name not in cache:
            cache[name] = CASES[name][0]()
        return cache[name]

    return get
