"""The one module that calls SHTns: grids, real-harmonic transforms, rotations, products on the grid.

Conventions
-----------
* Angles: polar ``theta`` in [0, pi], azimuth ``phi`` in [0, 2 pi) (the thesis calls them phi and
  theta, section 6.1). Gauss-Legendre nodes in cos(theta), equispaced phi.
* SHTns is used with orthonormal complex harmonics Y_{m,k} with the Condon-Shortley phase, the
  same functions as (6.7) and ``scipy.special.sph_harm_y`` (checked in the tests). A real field
  is f = sum_m a_{m,0} Y_{m,0} + 2 Re sum_{k>0} a_{m,k} Y_{m,k}.
* spectralshell labels a real field by coefficients c_{m,k}, k = -m..m, of the real orthonormal
  harmonics Yr_{m,0} = Y_{m,0}, Yr_{m,k} = sqrt(2) Re Y_{m,k}, Yr_{m,-k} = sqrt(2) Im Y_{m,k}
  (k > 0); so a_{m,k} = (c_{m,k} - i c_{m,-k}) / sqrt(2). Yr_{m,k} (k >= 0) is sqrt(2) times the
  thesis's Y^c_{m,k} (its real part of (6.7)) for k > 0 and equal to it for k = 0.
* Tangential vector fields: v = sum S_{m,k} r grad Yr_{m,k} + T_{m,k} rhat x r grad Yr_{m,k}
  (the Psi and Phi harmonics of the thesis); SHTns's spheroidal/toroidal transforms, whose
  toroidal part has the opposite sign (-rhat x grad), flipped here.

Products. A product of two fields of degree <= l_max has degree <= 2 l_max; it is computed on a
grid with n_theta >= (3 l_max + 1)/2 Gauss nodes and n_phi >= 3 l_max + 1 (the 3/2 rule), where the
quadrature of the analysis is exact for the product times any harmonic of degree <= l_max, so the
coefficients up to l_max are exact (no aliasing). shtns.py prints a banner on import; it is
swallowed (stdout redirected during the import) so that JSON output stays clean.
"""

from __future__ import annotations

import contextlib
import functools
import io
from collections.abc import Callable, Mapping

import numpy as np

from .._validate import require_int_in_range
from ..errors import BackendUnavailable, ParameterError

SQRT2 = np.sqrt(2.0)
N_THETA_MIN = 32      # SHTns aborts the process on smaller Gauss grids


@functools.lru_cache(maxsize=1)
def _shtns():
    try:
        with contextlib.redirect_stdout(io.StringIO()):   # shtns.py prints a banner
            import shtns
    except ImportError as exc:           # pragma: no cover - shtns is a dependency
        raise BackendUnavailable("shtns is not installed (pip install shtns)") from exc
    shtns.set_verbosity(0)
    return shtns


class Grid:
    """An SHTns transform of degree <= l_max on a Gauss grid of n_theta x n_phi points.

    Real coefficients are handled as dicts {(m, k): c} or, faster, as vectors ordered like
    :attr:`modes` (``*_array`` methods); :meth:`index` gives a mode's position.
    """

    def __init__(self, l_max: int, n_theta: int | None = None, n_phi: int | None = None) -> None:
        shtns = _shtns()
        self.l_max = require_int_in_range("l_max", l_max, 1, 1000)
        n_theta = max(N_THETA_MIN, n_theta or (3 * self.l_max) // 2 + 2)
        n_phi = max(4, n_phi or 2 * (3 * self.l_max // 2 + 1))
        # one thread: the transforms are small, threads only contend with the caller's work
        self._sh = shtns.sht(self.l_max, self.l_max, norm=shtns.sht_orthonormal, nthreads=1)
        self.n_theta, self.n_phi = self._sh.set_grid(
            n_theta, n_phi, shtns.sht_gauss | shtns.SHT_PHI_CONTIGUOUS)
        self.theta = np.arccos(self._sh.cos_theta)
        self.phi = 2 * np.pi * np.arange(self.n_phi) / self.n_phi
        l, m = np.asarray(self._sh.l), np.asarray(self._sh.m)
        modes = [(int(a), 0) for a in l[m == 0]]
        modes += [(int(a), int(b)) for a, b in zip(l[m > 0], m[m > 0])]
        modes += [(int(a), -int(b)) for a, b in zip(l[m > 0], m[m > 0])]
        self.modes = tuple(modes)
        self._position = {mk: i for i, mk in enumerate(self.modes)}
        self._zero = np.flatnonzero(m == 0)
        self._positive = np.flatnonzero(m > 0)
        n0, n1 = self._zero.size, self._positive.size
        self._slices = (slice(0, n0), slice(n0, n0 + n1), slice(n0 + n1, n0 + 2 * n1))

    def index(self, modes) -> np.ndarray:
        """Positions of the modes (m, k) in the coefficient vectors."""
        try:
            return np.array([self._position[tuple(mk)] for mk in modes], dtype=int)
        except KeyError as exc:
            raise ParameterError(f"mode (m, k) = {exc.args[0]} is invalid: must have "
                                 f"0 <= m <= {self.l_max} and |k| <= m") from None

    # ----------------------------------------------------------------- real <-> complex labels
    def _complex_array(self, c: np.ndarray) -> np.ndarray:
        a = self._sh.spec_array()
        z, p, n = self._slices
        a[self._zero] = c[z]
        a[self._positive] = (c[p] - 1j * c[n]) / SQRT2
        return a

    def _real_array(self, a: np.ndarray) -> np.ndarray:
        z, p, n = self._slices
        c = np.empty(len(self.modes))
        c[z] = a[self._zero].real
        c[p] = SQRT2 * a[self._positive].real
        c[n] = -SQRT2 * a[self._positive].imag
        return c

    def vector(self, coeffs: Mapping[tuple[int, int], float]) -> np.ndarray:
        """The coefficient vector of a dict {(m, k): c}."""
        c = np.zeros(len(self.modes))
        if coeffs:
            np.add.at(c, self.index(list(coeffs)), list(coeffs.values()))
        return c

    def _complex(self, coeffs: Mapping[tuple[int, int], float]) -> np.ndarray:
        return self._complex_array(self.vector(coeffs))

    def _real(self, a: np.ndarray) -> dict[tuple[int, int], float]:
        return dict(zip(self.modes, self._real_array(a).tolist()))

    # ----------------------------------------------------------------- arrays
    def synthesise_array(self, c: np.ndarray) -> np.ndarray:
        """The real field of a coefficient vector on the grid."""
        return self._sh.synth(self._complex_array(c))

    def analyse_array(self, field: np.ndarray) -> np.ndarray:
        """The coefficient vector of a real field on the grid."""
        return self._real_array(self._sh.analys(np.ascontiguousarray(field, dtype=float)))

    def synthesise_tangential_array(self, s: np.ndarray, t: np.ndarray):
        """(v_theta, v_phi) of spheroidal and toroidal coefficient vectors."""
        # SHTns's toroidal field is -rhat x grad: flip the sign (checked in the tests)
        return self._sh.synth(self._complex_array(s), -self._complex_array(t))

    def analyse_tangential_array(self, v_theta: np.ndarray, v_phi: np.ndarray):
        """Spheroidal and toroidal coefficient vectors of a tangential field."""
        S, T = self._sh.analys(np.ascontiguousarray(v_theta, dtype=float),
                               np.ascontiguousarray(v_phi, dtype=float))
        return self._real_array(S), -self._real_array(T)

    # ----------------------------------------------------------------- scalar fields
    def synthesise(self, coeffs: Mapping[tuple[int, int], float]) -> np.ndarray:
        """The real field sum c_{m,k} Yr_{m,k} on the grid, shape (n_theta, n_phi)."""
        return self._sh.synth(self._complex(coeffs))

    def analyse(self, field: np.ndarray) -> dict[tuple[int, int], float]:
        """Real coefficients c_{m,k} (m <= l_max) of a real field given on the grid."""
        field = np.ascontiguousarray(field, dtype=float)
        if field.shape != (self.n_theta, self.n_phi):
            raise ParameterError(f"field shape {field.shape} is invalid: must be "
                                 f"{(self.n_theta, self.n_phi)}")
        return self._real(self._sh.analys(field))

    def evaluate(self, function: Callable[[np.ndarray, np.ndarray], np.ndarray]) -> np.ndarray:
        """function(theta, phi) on the grid (broadcast), shape (n_theta, n_phi)."""
        th, ph = np.meshgrid(self.theta, self.phi, indexing="ij")
        values = np.broadcast_to(np.asarray(function(th, ph), dtype=float), th.shape)
        if not np.all(np.isfinite(values)):
            raise ParameterError("the function is not finite everywhere on the sphere")
        return np.ascontiguousarray(values)

    # ----------------------------------------------------------------- tangential fields
    def synthesise_tangential(self, spheroidal: Mapping, toroidal: Mapping) -> tuple[np.ndarray,
                                                                                     np.ndarray]:
        """(v_theta, v_phi) of sum S r grad Yr + T rhat x r grad Yr on the grid."""
        return self.synthesise_tangential_array(self.vector(spheroidal), self.vector(toroidal))

    def analyse_tangential(self, v_theta: np.ndarray, v_phi: np.ndarray) -> tuple[dict, dict]:
        """Real spheroidal and toroidal coefficients (S, T) of a tangential field on the grid."""
        S, T = self.analyse_tangential_array(v_theta, v_phi)
        return dict(zip(self.modes, S.tolist())), dict(zip(self.modes, T.tolist()))

    # ----------------------------------------------------------------- rotation
    def rotate(self, coeffs: Mapping[tuple[int, int], float], *, alpha: float, beta: float,
               gamma: float) -> dict[tuple[int, int], float]:
        """Coefficients of the field rotated by the ZYZ Euler angles (alpha, beta, gamma)
        (SHTns's rotation, applied to the real field's complex coefficients)."""
        rot = _shtns().rotation(self.l_max, self.l_max)
        rot.set_angles_ZYZ(alpha, beta, gamma)
        return self._real(rot.apply_real(self._complex(coeffs)))


@functools.lru_cache(maxsize=16)
def grid(l_max: int) -> Grid:
    """A cached dealiased grid for products of fields of degree <= l_max (3/2 rule)."""
    return Grid(l_max)
