"""Floquet-Fourier conventions: the one module that owns them.

Time is scaled so that the forcing period is T = 2 pi (thesis 2.2); the stiffness is
K(t) = kappa (1 + 2 tau sin t). A Floquet solution is u(t) = exp(gamma t) sum_n u_n exp(i n t)
(thesis (2.5)); the marginal (|q| = 1, q = exp(2 pi gamma)) kinds are

* harmonic:    gamma = 0,     u(t + T) = u(t),   reality u_{-n} = conj(u_n)        (2.7)
* subharmonic: gamma = i / 2, u(t + T) = -u(t),  reality u_{-n} = conj(u_{n-1})    (2.8)

Fourier indices of a truncation at N:

* two-sided complex form: k = -N..N (harmonic), k = -N-1..N (subharmonic), so that the reflection
  k -> -k (harmonic) or k -> -k-1 (subharmonic) maps the index set onto itself;
* real form (reality conditions imposed): n = 0..N. Unknowns are packed per index as
  [Re u_n, Im u_n] (each of the model's block size b), except harmonic n = 0, where u_0 is real and
  only Re u_0 is kept. Both forms then have the same real dimension and the same spectrum.
"""

from __future__ import annotations

import functools

import numpy as np

from .._validate import require_choice

KINDS = ("harmonic", "subharmonic")
GAMMA = {"harmonic": 0.0, "subharmonic": 0.5}  # imaginary part of the Floquet exponent


def check_kind(kind: str) -> str:
    """Return ``kind`` if it is 'harmonic' or 'subharmonic'."""
    return require_choice("kind", kind, KINDS)


def expand_kind(kind: str) -> tuple[str, ...]:
    """Return the kinds meant by a user's ``kind`` ('both', 'harmonic' or 'subharmonic')."""
    require_choice("kind", kind, ("both",) + KINDS)
    return KINDS if kind == "both" else (kind,)


def two_sided_indices(kind: str, n_temporal: int) -> np.ndarray:
    """Fourier indices k of the two-sided complex form truncated at N = ``n_temporal``."""
    lo = -n_temporal - 1 if check_kind(kind) == "subharmonic" else -n_temporal
    return np.arange(lo, n_temporal + 1)


def real_indices(n_temporal: int) -> np.ndarray:
    """Fourier indices n = 0..N of the real form."""
    return np.arange(n_temporal + 1)


def frequencies(kind: str, indices: np.ndarray) -> np.ndarray:
    """Complex frequencies s_k = gamma + i k of the Fourier components."""
    return 1j * (GAMMA[check_kind(kind)] + np.asarray(indices, dtype=float))


def truncation_frequencies(kind: str, n_temporal: int, two_sided: bool) -> np.ndarray:
    """The frequencies s_k of a truncation's Fourier indices, :func:`frequencies` of
    :func:`two_sided_indices` (``two_sided``) or of :func:`real_indices`: a new array, copied
    from one kept per (kind, N, form), since a map's sweep assembles the same few truncations
    at every point (issue 25)."""
    return _kept_frequencies(check_kind(kind), int(n_temporal), bool(two_sided)).copy()


@functools.lru_cache(maxsize=1024)
def _kept_frequencies(kind: str, n_temporal: int, two_sided: bool) -> np.ndarray:
    indices = two_sided_indices(kind, n_temporal) if two_sided else real_indices(n_temporal)
    out = frequencies(kind, indices)
    out.setflags(write=False)
    return out
