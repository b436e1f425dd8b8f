"""Exact release from rest of an unforced Hill system by numerical Laplace inversion.

A massless membrane moving with a fluid that is at rest at t = 0 obeys, per mode, the
unforced system D(d/dt) X = 0 of :class:`~spectralshell.models.base.HillSystem`, where
D(s) = s Z(s) + K splits into the fluid's load s Z(s) (zero at s = 0) and the elastic
stiffness K = D(0). The fluid load is Z acting on the membrane velocity, whose transform is
s X^ - X0 when the fluid starts at rest, so the transform of the release from X(0) = X0 is

    X^(s) = (X0 - D(s)^-1 K X0) / s,        V^(s) = s X^(s) - X0 = -D(s)^-1 K X0

(V the velocity). X^ is analytic on the physical sheet except at the natural modes (zeros of
det D, simple poles) and the branch cut of the fluid on the negative real axis. The inverse
is split exactly: the poles' residues r_j (trapezoidal rule on a small circle around each
mode) give sum_j r_j exp(gamma_j t), and the rest, analytic off the cut and holding the
continuous spectrum, is inverted on Weideman's optimised Talbot contour (J. A. C. Weideman,
SIAM J. Numer. Anal. 44 (2006); error ~ exp(-1.36 n) for n nodes), which wraps the cut and,
the poles being removed, needs no more nodes at late times. The model enters only through D.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError

#: Weideman's cotangent contour s(theta) = (n / t) (SIGMA + MU theta cot(ALPHA theta)
#: + i NU theta), theta in (-pi, pi): the parameters optimised for double precision.
SIGMA, MU, ALPHA, NU = -0.6122, 0.5017, 0.6407, 0.2645
#: Nodes of the Talbot contour and of each pole's residue circle.
TALBOT_NODES = 24
CIRCLE_NODES = 32
#: Residue circle radius as a fraction of the pole's distance to the nearest other
#: singularity (another pole or the cut, the negative real axis).
CIRCLE_FRACTION = 0.25


@dataclass(frozen=True)
class Release:
    """A release from rest: X(t), dX/dt (shape (len(t), b), real) and their error bounds
    |X_n - X_n'| (two Talbot contours and two residue circles) at times t."""

    t: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    position_error: np.ndarray
    velocity_error: np.ndarray


def release_transforms(unforced: Callable[[np.ndarray], np.ndarray], x0: np.ndarray
                       ) -> Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]:
    """s -> (X^(s), V^(s)), each (len(s), b): the transforms of position and velocity after a
    release from rest at X0 with the fluid at rest, from D(s) = ``unforced`` (K = D(0))."""
    x0 = np.asarray(x0, dtype=complex)
    stiffness = unforced(np.zeros(1))[0]

    def transforms(s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        s = np.asarray(s, dtype=complex).ravel()
        velocity = -np.linalg.solve(unforced(s), np.broadcast_to(stiffness @ x0, (s.size, x0.size))
                                    [..., None])[..., 0]
        return (x0 + velocity) / s[:, None], velocity

    return transforms


def residues(transform: Callable[[np.ndarray], tuple[np.ndarray, ...]], poles: Sequence[complex],
             nodes: int) -> list[tuple[np.ndarray, ...]]:
    """The residues of each of ``transform``'s outputs at each pole: the mean of F(p + rho w) rho w
    over the ``nodes``-th roots of unity w (exact up to (rho / distance)^nodes), rho a fraction
    CIRCLE_FRACTION of the distance to the nearest other pole or the negative real axis."""
    poles = np.asarray(poles, dtype=complex)
    w = np.exp(2j * np.pi * (np.arange(nodes) + 0.5) / nodes)
    out = []
    for j, p in enumerate(poles):
        others = np.delete(poles, j)
        distance = min([abs(p.imag) if p.real < 0 else abs(p)] + list(np.abs(others - p)))
        if distance == 0:
            raise ParameterError(f"pole {p!r} is invalid: it lies on the cut or on another pole")
        rho = CIRCLE_FRACTION * distance
        values = transform(p + rho * w)
        out.append(tuple(np.mean(v * (rho * w)[:, None], axis=0) for v in values))
    return out


def talbot(transform: Callable[[np.ndarray], tuple[np.ndarray, ...]], t: np.ndarray,
           nodes: int) -> list[np.ndarray]:
    """The inverse Laplace transforms (real, shape (len(t), b)) of ``transform``'s outputs at
    times t > 0 on Weideman's contour with ``nodes`` nodes (F real: F(conj s) = conj F(s),
    so only the upper half is evaluated)."""
    theta = np.pi * (2 * np.arange(nodes // 2) + 1) / nodes        # upper half, midpoints
    shape = SIGMA + MU * theta / np.tan(ALPHA * theta) + 1j * NU * theta
    dshape = (MU / np.tan(ALPHA * theta) - MU * ALPHA * theta / np.sin(ALPHA * theta) ** 2
              + 1j * NU)
    scale = nodes / t[:, None]                                     # (len(t), nodes / 2)
    s = scale * shape
    values = transform(s.ravel())
    weight = (np.exp(s * t[:, None]) * scale * dshape).ravel()[:, None]
    return [(2.0 / nodes) * np.sum((weight * v).reshape(t.size, nodes // 2, -1), axis=1).imag
            for v in values]


def _invert(transforms, t: np.ndarray, poles: np.ndarray, talbot_nodes: int,
            circle_nodes: int) -> list[np.ndarray]:
    """The inverse transforms at t: the poles' residues plus the Talbot inverse of the rest."""
    res = residues(transforms, poles, circle_nodes)

    def rest(s):
        return tuple(v - sum(r[k][None, :] / (s[:, None] - p) for r, p in zip(res, poles))
                     for k, v in enumerate(transforms(s)))

    continuous = talbot(rest, t, talbot_nodes)
    return [c + sum(np.outer(np.exp(p * t), r[k]) for r, p in zip(res, poles)).real
            for k, c in enumerate(continuous)]


def release(unforced: Callable[[np.ndarray], np.ndarray], x0: np.ndarray, t: np.ndarray,
            modes: Sequence[complex], *, talbot_nodes: int = TALBOT_NODES,
            circle_nodes: int = CIRCLE_NODES) -> Release:
    """X(t) and dX/dt after the release from rest at X0 of the system D(s) = ``unforced`` whose
    natural modes with Im gamma >= 0 are ``modes`` (all of them: the conjugates are added),
    at times t >= 0 (t = 0: X0 and zero velocity, exactly). Error bound: the change with
    talbot_nodes - 8 and circle_nodes / 2 nodes."""
    t = np.asarray(t, dtype=float)
    if t.ndim != 1 or t.size == 0 or not np.all(t >= 0):
        raise ParameterError("t is invalid: must be a 1-d array of times >= 0")
    modes = np.asarray(modes, dtype=complex)
    poles = np.concatenate([modes, np.conj(modes[modes.imag > 0])])
    transforms = release_transforms(unforced, x0)
    later = t > 0
    fine = _invert(transforms, t[later], poles, talbot_nodes, circle_nodes)
    coarse = _invert(transforms, t[later], poles, talbot_nodes - 8, circle_nodes // 2)
    start = (np.asarray(x0, dtype=float), np.zeros(len(x0)))    # t = 0: the initial state

    def full(k: int, values: np.ndarray) -> np.ndarray:
        out = np.empty((t.size, len(x0)))
        out[~later], out[later] = start[k], values
        return out

    return Release(t=t, position=full(0, fine[0]), velocity=full(1, fine[1]),
                   position_error=full(1, np.abs(fine[0] - coarse[0])),
                   velocity_error=full(1, np.abs(fine[1] - coarse[1])))
