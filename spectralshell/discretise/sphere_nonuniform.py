"""Hill systems of the sphere with non-uniform stiffness kappa(theta, phi): degrees coupled.

Physics: that of the time stepper's non-uniform load (:mod:`.sphere_coupled`), so that the two
check each other. The membrane load is K(theta, phi, t) F1[X], K = kappa(theta, phi)
(1 + 2 tau sin t), F1[X] = -sum (l-1)(l+2) (X^Y Yr rhat + X^Psi Psi + X^Phi Phi), projected on
the modes (l, k) of degrees 2 <= l <= l_max (:func:`.sphere_coupled.weighted_load`, the same
product on the same dealiased SHTns grid). Written as P[kappa F1[X]] = -C X, the coupling matrix
C replaces the uniform model's q I = kappa (l-1)(l+2) I: with the fluid response H_l(s) of each
degree (the uniform D(s) of :mod:`spectralshell.models.sphere` at kappa = 0, exact Bessel
ratios), the Hill form (2) of :mod:`spectralshell.models.base` holds with

    D(s) = blockdiag_l H_l(s) + C,      G = C.

A uniform kappa0 gives C = diag(kappa0 (l-1)(l+2)): each degree's own system, the same numbers.

Slots. Every mode (l, k) has the slots (l, k, 'Y'), (l, k, 'Psi') (poloidal) and (l, k, 'Phi')
(toroidal). C is checked exactly against Gaunt coefficients in tests/test_sphere_nonuniform.py
(``derivations/sphere_nonuniform.py`` derives the projection).

Sectors. The slots split into sectors that neither H (which couples Y and Psi of one mode) nor
C couples (connected components of the coupling graph; entries below COUPLING_TOL times the
largest count as zero): an axisymmetric kappa decouples the orders |k| (and cos from sin), an
equatorially symmetric one the parity of l + k. Sectors equal up to the sign of their toroidal
slots (the cos and sin copies of an order, the 2l + 1 orders of a uniform kappa) are solved
once. Sectors of toroidal slots only (e.g. the orders k = 0 of an axisymmetric kappa, or
every toroidal mode of a uniform one) are kept and sorted last: the toroidal component is no
mere relaxation (its natural modes oscillate, e.g. gamma = -0.355 + 0.594 i for l = 2, kappa =
0.02, nu = 0.006, and the per-degree solver finds a subharmonic tau_min of 1.16 there), so a
toroidal sector can attain tau_min where the poloidal ones lie higher. Solved last, each is
capped by the smallest tau_min found before it (its uncapped harmonic tau_min can be ~1e5 and
out of reach of the truncation).
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import connected_components

from .._validate import require_int_in_range, require_positive
from ..models.base import HillSystem
from ..params.sphere import L_MAX_RANGE
from ..models.sphere import lambda0_squared, poloidal_unforced, toroidal_unforced
from ..special.spherical import spherical_jn_zeros
from .shtns_adapter import grid as dealiased_grid
from .sphere_coupled import COUPLING_TOL, StiffnessField, stiffness_field, weighted_load

COMPONENT_OF = {"Y": "poloidal", "Psi": "poloidal", "Phi": "toroidal"}
L_MAX_LIMIT = L_MAX_RANGE[1]   # the largest degree truncation


@dataclass(frozen=True, kw_only=True, eq=False)
class Sector:
    """One decoupled set of slots: ``slots`` ((l, k, name), ...), their positions ``indices`` in
    :func:`slots`, its coupling matrix ``coupling`` (those rows and columns of C) and ``copies``
    (how many sectors it stands for)."""

    slots: tuple[tuple[int, int, str], ...]
    indices: np.ndarray
    coupling: np.ndarray
    copies: int = 1

    @property
    def degrees(self) -> tuple[int, ...]:
        return tuple(sorted({l for l, _, _ in self.slots}))

    @property
    def toroidal(self) -> bool:
        """Whether the sector holds toroidal slots only."""
        return all(name == "Phi" for _, _, name in self.slots)

    @property
    def modes(self) -> tuple[tuple[int, int, str], ...]:
        """The modes (l, k, component) of the sector, in slot order."""
        seen = dict.fromkeys((l, k, COMPONENT_OF[n]) for l, k, n in self.slots)
        return tuple(seen)


def slots(l_max: int) -> tuple[tuple[int, int, str], ...]:
    """Every slot (l, k, name) of degrees 2..l_max: poloidal Y, Psi and toroidal Phi."""
    return tuple((l, k, name) for l in range(2, l_max + 1) for k in range(-l, l + 1)
                 for name in ("Y", "Psi", "Phi"))


def coupling_matrix(weight: np.ndarray, l_max: int) -> tuple[np.ndarray, tuple]:
    """C with P[w F1[X]] = -C X over :func:`slots` (module docstring), and the slots; ``weight``
    is w (kappa, or a change of it) on the dealiased grid of degree l_max.

    Each column is one product on the grid, Y and Psi of a mode together (radial and
    tangential loads do not mix). C is linear in w."""
    grid = dealiased_grid(l_max)
    every = slots(l_max)
    where = {s: i for i, s in enumerate(every)}
    modes = [(l, k) for l, k, name in every if name == "Y"]
    rows = np.array([[where[(l, k, n)] for n in ("Y", "Psi", "Phi")] for l, k in modes])
    pos = grid.index(modes)
    C = np.zeros((len(every), len(every)))
    zero = np.zeros(len(grid.modes))

    def column(radial, sph, tor) -> np.ndarray:
        load = weighted_load(grid, weight, radial, sph, tor)
        return -np.stack([c[pos] for c in load], axis=1)    # (modes, 3): Y, Psi, Phi rows

    for (l, k), p, own in zip(modes, pos, rows):
        unit = zero.copy()
        unit[p] = -(l - 1) * (l + 2)                         # F1 of a unit displacement
        poloidal = column(unit, unit, zero)
        C[rows[:, 0], own[0]] = poloidal[:, 0]               # radial load of X^Y
        C[rows[:, 1], own[1]] = poloidal[:, 1]               # tangential loads of X^Psi
        C[rows[:, 2], own[1]] = poloidal[:, 2]
        toroidal = column(zero, zero, unit)
        C[rows[:, 1], own[2]] = toroidal[:, 1]
        C[rows[:, 2], own[2]] = toroidal[:, 2]
    return C, every


def _same(a: Sector, b: Sector) -> bool:
    """Equal degrees and names slot by slot, and equal C up to the sign of the toroidal slots."""
    if [(l, n) for l, _, n in a.slots] != [(l, n) for l, _, n in b.slots]:
        return False
    sign = np.array([-1.0 if n == "Phi" else 1.0 for _, _, n in a.slots])
    scale = max(np.abs(a.coupling).max(), 1e-300)
    return any(np.allclose(a.coupling, sign[:, None] * b.coupling * sign[None, :] if flip
                           else b.coupling, rtol=0.0, atol=1e-12 * scale)
               for flip in (False, True))


def sectors(C: np.ndarray, every: tuple) -> tuple[Sector, ...]:
    """The decoupled sectors of C over the slots ``every`` (module docstring), copies merged,
    sorted by their lowest degree (then size), the purely toroidal ones last."""
    scale = max(float(np.abs(C).max()), 1e-300)
    link = np.abs(C) > COUPLING_TOL * scale
    where = {s: i for i, s in enumerate(every)}
    for l, k, name in every:
        if name == "Y":
            link[where[(l, k, "Y")], where[(l, k, "Psi")]] = True
    n, label = connected_components(csr_matrix(link), directed=True, connection="weak")
    found: list[Sector] = []
    for j in range(n):
        idx = np.flatnonzero(label == j)
        chosen = tuple(every[i] for i in idx)
        new = Sector(slots=chosen, indices=idx, coupling=C[np.ix_(idx, idx)])
        twin = next((i for i, s in enumerate(found) if _same(s, new)), None)
        if twin is None:
            found.append(new)
        else:
            old = found[twin]
            found[twin] = dataclasses.replace(old, copies=old.copies + 1)
    return tuple(sorted(found, key=lambda s: (s.toroidal, s.degrees[0], len(s.slots))))


def sector_system(sector: Sector, *, nu: float, kappa_mean: float) -> HillSystem:
    """The Hill system D(s) = blockdiag H_l(s) + C, G = C of one sector (module docstring)."""
    C = sector.coupling
    groups = []   # (H_l callable, slot positions) per mode
    for l, k, component in sector.modes:
        names = ("Y", "Psi") if component == "poloidal" else ("Phi",)
        pos = [sector.slots.index((l, k, n)) for n in names]
        groups.append((l, component, np.array(pos)))

    def unforced(s: np.ndarray) -> np.ndarray:
        s = np.asarray(s, dtype=complex).ravel()
        out = np.broadcast_to(C, (s.size,) + C.shape).astype(complex, order="C")
        cache: dict[tuple[int, str], np.ndarray] = {}
        for l, component, pos in groups:
            if (l, component) not in cache:
                own = poloidal_unforced if component == "poloidal" else toroidal_unforced
                cache[l, component] = own(s, m=l, kappa=0.0, nu=nu)
            out[:, pos[:, None], pos[None, :]] += cache[l, component]
        return out

    # the natural frequency of the sector's highest degree; none for toroidal slots only, as
    # for the uniform model's toroidal component (models.sphere.hill_system)
    top = 0.0 if sector.toroidal else float(np.sqrt(lambda0_squared(max(sector.degrees),
                                                                     kappa_mean)))
    orders = tuple(sorted({l + 1 if c == "poloidal" else l for l, _, c in sector.modes}))
    return HillSystem(name="sphere", block_size=len(sector.slots), unforced=unforced,
                      forcing=C.copy(), n_resonant=top, n_highest=top or None,
                      cut_poles=functools.partial(interior_poles, orders=orders, nu=nu))


def interior_poles(x: float, *, orders: tuple[int, ...], nu: float) -> np.ndarray:
    """The poles of a sector's D(s) on the cut in [x, 0): the interior fluid's decay rates
    s = -nu z^2, z the zeros of j_n for n in ``orders`` (a poloidal degree l enters through
    1/P_l, P_l = beta i_{l+1}(beta)/i_l(beta): n = l + 1; a toroidal degree l through P_l: n =
    l). A poloidal l and a toroidal l + 1 in one sector share theirs: det D has double poles
    there (``HillSystem.cut_poles``)."""
    z_max = np.sqrt(max(-x, 0.0) / nu)
    zeros = [spherical_jn_zeros(n, z_max) for n in orders]
    return np.unique(-nu * np.concatenate(zeros) ** 2) if zeros else np.zeros(0)


def perturbation_system(sector: Sector, weight: np.ndarray, l_max: int) -> HillSystem:
    """The derivative of a sector's Hill system when kappa changes by eps w (``weight``: w on the
    dealiased grid of degree l_max): D' = C', G' = C', C' = the sector's rows and columns of
    :func:`coupling_matrix` (w), since D and G are linear in kappa."""
    full, _ = coupling_matrix(weight, l_max)
    dC = full[np.ix_(sector.indices, sector.indices)]
    return HillSystem(name="sphere", block_size=len(sector.slots), forcing=dC,
                      unforced=lambda s: np.broadcast_to(dC, (np.size(s),) + dC.shape)
                      .astype(complex))


@dataclass(frozen=True, kw_only=True, eq=False)
class NonUniformSphere:
    """The sectors of one truncation l_max and their Hill systems, the stiffness field and the
    viscosity nu."""

    l_max: int
    nu: float
    field: StiffnessField
    sectors: tuple[Sector, ...]
    systems: tuple[HillSystem, ...]


def nonuniform_sphere(*, kappa: Callable[[np.ndarray, np.ndarray], np.ndarray], nu: float,
                      l_max: int) -> NonUniformSphere:
    """The decoupled Hill systems of the sphere with stiffness kappa(theta, phi) (a numpy
    function) truncated to degrees 2..l_max.

    Raises
    ------
    ParameterError : nu not > 0, l_max out of 2..L_MAX_LIMIT, kappa not positive everywhere.
    """
    nu = require_positive("nu", nu)
    l_max = require_int_in_range("l_max", l_max, 2, L_MAX_LIMIT)
    field = stiffness_field(dealiased_grid(l_max), kappa)
    C, every = coupling_matrix(field.weight, l_max)
    found = sectors(C, every)
    systems = tuple(sector_system(s, nu=nu, kappa_mean=field.mean) for s in found)
    return NonUniformSphere(l_max=l_max, nu=nu, field=field, sectors=found, systems=systems)
