"""Real spherical harmonics in sympy, shared by derivations/sphere_nonuniform.py and its test.

Real orthonormal harmonics Y_{l,0}, sqrt2 Re Y_{l,k} (k > 0), sqrt2 Im Y_{l,|k|} (k < 0) with the
Condon-Shortley phase (spectralshell's convention, spectralshell/discretise/shtns_adapter.py).
"""

from __future__ import annotations

import sympy as sp
from sympy.physics.wigner import gaunt


def complex_parts(l: int, k: int) -> dict:
    """Yr_{l,k} as {(l, m): coefficient} of the complex Y_{l,m} (Y_{l,-m} = (-1)^m conj Y_{l,m})."""
    if k == 0:
        return {(l, 0): 1}
    a, s = abs(k), (-1) ** abs(k)
    if k > 0:
        return {(l, a): 1 / sp.sqrt(2), (l, -a): s / sp.sqrt(2)}
    return {(l, a): 1 / (sp.I * sp.sqrt(2)), (l, -a): -s / (sp.I * sp.sqrt(2))}


def real_gaunt(c: tuple[int, int], a: tuple[int, int], b: tuple[int, int]):
    """int Yr_c Yr_a Yr_b dOmega exactly, from the complex Gaunt coefficients."""
    total = 0
    for (l1, m1), x in complex_parts(*c).items():
        for (l2, m2), y in complex_parts(*a).items():
            for (l3, m3), z in complex_parts(*b).items():
                total += x * y * z * gaunt(l1, l2, l3, m1, m2, m3)
    return sp.expand(total)
