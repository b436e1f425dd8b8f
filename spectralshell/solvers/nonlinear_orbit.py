"""Direct (non-perturbative) solve of the time-periodic nonlinear membrane orbit; eps^2 frequency slope.

Independent check of the Lindstedt-Poincare coefficients of thesis 7.3 (generated in
:mod:`spectralshell.models.nonlinear_coefficients`): it solves the full nonlinear equations of
:mod:`spectralshell.models.sphere_nonlinear` (radial-only membrane, inviscid potential flow inside
and outside, exact normal-stress law, exact kinematic condition on the displaced surface r = R)
without expanding in eps. The pointwise laws (membrane load, kinematic residual, Bernoulli head,
stress balance) come in as an argument ``physics`` (the caller passes that module), so this
solver does not import the model.

Discretisation (a Fourier-Galerkin x spherical-harmonic-Galerkin method, evaluated by collocation on
the grid of :mod:`spectralshell.discretise.orbit_grid`)::

    R   = 1 + sum X_{n,l,j} cos(j tau) Yr_{n,l},                         j = 0..J, n <= N
    Phi_in  = sum A_{n,l,j} sin(j tau) r^n Yr_{n,l}      (+ q(tau) = sum Q_j cos(j tau) as
                                                          d/dtau of the degree-0 interior part)
    Phi_out = sum B_{n,l,j} sin(j tau) r^-(n+1) Yr_{n,l}

The harmonic series are evaluated ON the displaced surface r = R (no Taylor expansion about r = 1;
this relies on the Rayleigh hypothesis, harmless for the small amplitudes used here, and is
monitored by the spectral tail). Unknowns: X, A, Q, B and Lambda = (lambda/lambda0)^2. Equations:
both kinematic conditions projected on sin(j tau) Yr_{n,l} (j >= 1), the stress balance projected on
cos(j tau) Yr_{n,l} (j >= 0), the amplitude X_{m,k,1} = eps (eps = the cos(tau) Yr_{m,k} amplitude,
which defines eps to O(eps^2) as in the Lindstedt expansion) and the enclosed volume = 4 pi/3
(time mean). The system is square. It is solved by a chord-Newton iteration whose Jacobian is
assembled exactly from pointwise derivatives (time x angle separable blocks, :meth:`_Problem.jacobian`);
a complex-step Jacobian (every operation is analytic) is kept as the slow reference and the tests
compare the two. The symmetries of :mod:`~spectralshell.discretise.orbit_grid` remove the time
shift and the rigid translation, so the only neutral direction left (the secular one) is fixed by the
amplitude condition, with Lambda as its partner unknown.

lambda/lambda0 is even in eps (eps -> -eps is the half-period shift), so the slope c is fitted as
(lambda/lambda0 - 1)/eps^2 = c + d eps^2 + e eps^4 over several eps; the quoted uncertainty is the
change of c between this fit and the fit with one term fewer on the smaller half of the eps values.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .._validate import require_choice, require_int_in_range, require_positive
from ..discretise.orbit_grid import OrbitGrid, allowed, make_grid
from ..errors import ConvergenceError, ParameterError

_STATS = {"jacobians": 0}  # Jacobian evaluations (for benchmarks)

__all__ = ["PeriodicOrbit", "SlopeFit", "periodic_orbit", "frequency_slope"]


@dataclass(frozen=True, kw_only=True, eq=False)
class PeriodicOrbit:
    """A converged time-periodic orbit and its frequency ratio lambda/lambda0 (radial-only model)."""

    m: int
    k: int
    eps: float
    law: str
    n_max: int
    j_max: int
    lambda_ratio: float
    residual: float
    tail: float
    newton_iterations: int
    x_coefficients: dict = field(repr=False)


@dataclass(frozen=True, kw_only=True, eq=False)
class SlopeFit:
    """Fitted eps^2 slope c of lambda/lambda0 = 1 + c eps^2 + ..., with the orbits behind it."""

    m: int
    k: int
    law: str
    c: float
    uncertainty: float
    eps: tuple[float, ...]
    lambda_ratio: tuple[float, ...]
    orbits: tuple[PeriodicOrbit, ...] = field(repr=False)


class _Problem:
    """Unknown/equation index maps and the residual F(z) (vectorised over a batch of z) of the
    pointwise ``physics`` (see :func:`periodic_orbit`)."""

    def __init__(self, physics, grid: OrbitGrid, eps: float, law: str):
        self.phys, self.grid, self.eps, self.law = physics, grid, eps, law
        m, k, J = grid.m, grid.k, grid.j_max
        self.kp = physics.kappa_prime(m)
        ok = [[allowed(n, l, j, m=m, k=k) for j in range(J + 1)] for (n, l) in grid.modes]
        nm = len(grid.modes)
        self.x_idx = [(i, j) for i in range(nm) for j in range(J + 1) if ok[i][j]]
        self.a_idx = [(i, j) for (i, j) in self.x_idx if j >= 1 and grid.modes[i][0] >= 1]
        self.q_idx = [j for (i, j) in self.x_idx if grid.modes[i] == (0, 0)]
        self.b_idx = [(i, j) for (i, j) in self.x_idx if j >= 1]
        self.s_rows = list(self.x_idx)  # stress: cos, j >= 0
        self.k_rows = list(self.b_idx)  # kinematic: sin, j >= 1
        sizes = [len(self.x_idx), len(self.a_idx), len(self.q_idx), len(self.b_idx), 1]
        self.off = np.cumsum([0] + sizes)
        self.size = int(self.off[-1])
        n_rows = 2 * len(self.k_rows) + len(self.s_rows) + 2
        if n_rows != self.size:  # pragma: no cover - index bookkeeping
            raise AssertionError((n_rows, self.size))
        self.i_amp = self.x_idx.index((grid.modes.index((m, k)), 1))
        t = grid.tau[:, None]
        j = np.arange(J + 1)[None, :]
        self.C, self.S = np.cos(j * t), np.sin(j * t)
        self.jC, self.jS = j * self.C, j * self.S
        G = grid.Y.shape[1] * grid.Y.shape[2]
        self.Y = grid.Y.reshape(nm, G)
        self.Yth = grid.Yth.reshape(nm, G)
        self.Yph = grid.Yph.reshape(nm, G)
        self.w = grid.w.reshape(G)
        self.nn = np.array([n for (n, _) in grid.modes])
        self.by_degree = {}
        for i, (n, _) in enumerate(grid.modes):
            self.by_degree.setdefault(n, []).append(i)
        nt = len(grid.tau)
        self.Pc = self.C * (2.0 / nt)
        self.Pc[:, 0] = 1.0 / nt
        self.Ps = self.S * (2.0 / nt)

    # ---- packing --------------------------------------------------------------------------
    def _scatter(self, z, idx, lo):
        out = np.zeros((z.shape[0], len(self.grid.modes), self.grid.j_max + 1), dtype=z.dtype)
        if idx:
            ii, jj = np.array(idx).T
            out[:, ii, jj] = z[:, lo:lo + len(idx)]
        return out

    def unpack(self, z):
        o = self.off
        X = self._scatter(z, self.x_idx, o[0])
        A = self._scatter(z, self.a_idx, o[1])
        Q = np.zeros((z.shape[0], self.grid.j_max + 1), dtype=z.dtype)
        Q[:, self.q_idx] = z[:, o[2]:o[3]]
        B = self._scatter(z, self.b_idx, o[3])
        return X, A, Q, B, z[:, o[4]]

    def initial(self):
        """Linear orbit eps cos(tau) Yr_{m,k}, Lambda = 1."""
        m = self.grid.m
        z = np.zeros(self.size)
        z[self.off[0] + self.i_amp] = self.eps
        i = self.grid.modes.index((m, self.grid.k))
        z[self.off[1] + self.a_idx.index((i, 1))] = -self.eps / m
        z[self.off[3] + self.b_idx.index((i, 1))] = self.eps / (m + 1)
        z[-1] = 1.0
        return z

    # ---- residual ---------------------------------------------------------------------------
    def _potential(self, Cf, R, inner):
        """Phi_r, Phi_tau, Phi_theta, Phi_phi/sin at r = R for one side."""
        At = np.einsum("bmj,tj->btm", Cf, self.S)
        Att = np.einsum("bmj,tj->btm", Cf, self.jC)
        pr = np.zeros_like(R)
        pt = np.zeros_like(R)
        pth = np.zeros_like(R)
        pph = np.zeros_like(R)
        for n, idx in self.by_degree.items():
            if inner and n == 0:
                continue
            a, at = At[:, :, idx], Att[:, :, idx]
            if not np.any(a) and not np.any(at):
                continue
            e = n if inner else -n - 1
            Re = R ** e
            pr += e * (R ** (e - 1)) * (a @ self.Y[idx])
            pt += Re * (at @ self.Y[idx])
            pth += Re * (a @ self.Yth[idx])
            pph += Re * (a @ self.Yph[idx])
        return pr, pt, pth, pph

    def residual(self, z):
        z = np.atleast_2d(z)
        X, A, Q, B, Lam = self.unpack(z)
        Xt = np.einsum("bmj,tj->btm", X, self.C)
        Xtt = -np.einsum("bmj,tj->btm", X, self.jS)
        x = Xt @ self.Y
        R = 1.0 + x
        R_tau = Xtt @ self.Y
        R_th = Xt @ self.Yth
        R_ph = Xt @ self.Yph
        lap_R = (Xt * (-self.nn * (self.nn + 1.0))) @ self.Y
        g = R_th * R_th + R_ph * R_ph
        heads, kins = [], []
        for Cf, inner in ((A, True), (B, False)):
            pr, pt, pth, pph = self._potential(Cf, R, inner)
            if inner:
                pt = pt + (Q @ self.C.T)[:, :, None] * self.Y[0][None, None, :]
            kins.append(self.phys.kinematic_residual(R_tau, pr, R_th * pth + R_ph * pph, R))
            heads.append(self.phys.bernoulli_head(pt, pr, pth * pth + pph * pph, R))
        load = self.phys.membrane_load(R, lap_R, g, law=self.law)
        stress = self.phys.stress_residual(Lam[:, None, None], heads[0], heads[1], load, self.kp)
        out = np.empty((z.shape[0], self.size), dtype=z.dtype)
        row = 0
        for field_, proj, rows in ((kins[0], self.Ps, self.k_rows), (kins[1], self.Ps, self.k_rows),
                                   (stress, self.Pc, self.s_rows)):
            coef = np.einsum("btm,tj->bmj", (field_ * self.w) @ self.Y.T, proj)
            ii, jj = np.array(rows).T
            out[:, row:row + len(rows)] = coef[:, ii, jj]
            row += len(rows)
        out[:, row] = X[:, *self.x_idx[self.i_amp]] - self.eps
        vol = ((R ** 3 - 1.0) / 3.0 * self.w).sum(axis=-1).mean(axis=-1)
        out[:, row + 1] = vol
        return out

    def jacobian_complex_step(self, z, batch: int = 64):
        """Exact Jacobian by complex-step differentiation (slow reference for :meth:`jacobian`)."""
        h = 1e-30
        n = self.size
        Jm = np.empty((n, n))
        for lo in range(0, n, batch):
            cols = np.arange(lo, min(lo + batch, n))
            Z = np.tile(z.astype(complex), (len(cols), 1))
            Z[np.arange(len(cols)), cols] += 1j * h
            Jm[:, cols] = (self.residual(Z).imag / h).T
        return Jm

    # ---- analytic Jacobian -------------------------------------------------------------------
    def _side(self, Cf, R, inner):
        """Surface values of Phi_r, Phi_tau, Phi_th, Phi_ph and their r-derivatives (one z)."""
        At = Cf @ self.S.T  # (m, t)
        Att = Cf @ self.jC.T
        names = ("r", "rr", "t", "tr", "th", "thr", "ph", "phr")
        out = {key: np.zeros_like(R) for key in names}
        for n, idx in self.by_degree.items():
            if inner and n == 0:
                continue
            a, at = At[idx].T, Att[idx].T
            if not np.any(a) and not np.any(at):
                continue
            e = n if inner else -n - 1
            T, Tt, Tth, Tph = a @ self.Y[idx], at @ self.Y[idx], a @ self.Yth[idx], a @ self.Yph[idx]
            p0, p1, p2 = R ** e, e * R ** (e - 1), e * (e - 1) * R ** (e - 2)
            out["r"] += p1 * T
            out["rr"] += p2 * T
            out["t"] += p0 * Tt
            out["tr"] += p1 * Tt
            out["th"] += p0 * Tth
            out["thr"] += p1 * Tth
            out["ph"] += p0 * Tph
            out["phr"] += p1 * Tph
        return out

    def _block(self, coef, Lt, La, Rt, Ra):
        """sum_{t,g} Lt[t,j'] La[a,g] w[g] coef[t,g] Rt[t,j] Ra[b,g] as an (a, j', b, j) array."""
        Rt_ = Ra.T if Ra.ndim == 2 else Ra.transpose(0, 2, 1)  # Ra: (b, g) or per time (t, b, g)
        M = ((La * self.w)[None, :, :] * coef[:, None, :]) @ Rt_  # (t, a, b)
        W = Lt[:, :, None] * Rt[:, None, :]  # (t, j', j)
        return np.tensordot(W, M, axes=(0, 0)).transpose(2, 0, 3, 1)

    def jacobian(self, z):
        """Exact Jacobian assembled from pointwise derivatives (separable in time and angle)."""
        z = np.asarray(z, dtype=float)
        X, A, Q, B, Lam = (v[0] for v in self.unpack(z[None, :]))
        Xt = X @ self.C.T  # (m, t)
        R = 1.0 + Xt.T @ self.Y
        R_th, R_ph = Xt.T @ self.Yth, Xt.T @ self.Yph
        lap_R = (Xt.T * (-self.nn * (self.nn + 1.0))) @ self.Y
        g = R_th * R_th + R_ph * R_ph
        h = 1e-30
        L_R = self.phys.membrane_load(R + 1j * h, lap_R, g, law=self.law).imag / h
        L_lap = self.phys.membrane_load(R, lap_R + 1j * h, g, law=self.law).imag / h
        L_g = self.phys.membrane_load(R, lap_R, g + 1j * h, law=self.law).imag / h
        sides = [self._side(A, R, True), self._side(B, R, False)]
        sides[0]["t"] = sides[0]["t"] + np.outer(Q @ self.C.T, self.Y[0])
        Y, Yth, Yph, C, S, Ps, Pc = self.Y, self.Yth, self.Yph, self.C, self.S, self.Ps, self.Pc
        nm, J1 = len(self.grid.modes), self.grid.j_max + 1
        lapY = -(self.nn * (self.nn + 1.0))[:, None] * Y
        R2, R3 = R * R, R * R * R
        kin_X, head_R = [], []
        for sd in sides:
            kin_X.append((-sd["rr"] + (R_th * sd["thr"] + R_ph * sd["phr"]) / R2
                          - 2 * (R_th * sd["th"] + R_ph * sd["ph"]) / R3, sd["th"] / R2, sd["ph"] / R2))
            head_R.append(sd["tr"] + sd["r"] * sd["rr"] + (sd["th"] * sd["thr"] + sd["ph"] * sd["phr"]) / R2
                          - (sd["th"] ** 2 + sd["ph"] ** 2) / R3)
        one = np.ones_like(R)
        # d/dX: kinematic (sin projection) and stress (cos projection) blocks, shape (nm, J1, nm, J1)
        dKX = []
        for aR, ath, aph in kin_X:
            dKX.append(self._block(aR, Ps, Y, C, Y) + self._block(one, Ps, Y, -self.jS, Y)
                       + self._block(ath, Ps, Y, C, Yth) + self._block(aph, Ps, Y, C, Yph))
        sR = Lam * (head_R[0] - head_R[1]) - self.kp * L_R
        dSX = (self._block(sR, Pc, Y, C, Y) + self._block(-self.kp * L_lap, Pc, Y, C, lapY)
               + self._block(-2 * self.kp * L_g * R_th, Pc, Y, C, Yth)
               + self._block(-2 * self.kp * L_g * R_ph, Pc, Y, C, Yph))
        # d/d(potential coefficients), degree by degree
        dK_pot, dS_pot = [], []
        for sd, inner in zip(sides, (True, False)):
            e = (self.nn if inner else -self.nn - 1.0).astype(float)
            live = (self.nn > 0) if inner else np.ones(nm, bool)
            E0 = R[:, None, :] ** e[None, :, None] * live[None, :, None]  # (t, b, g): R^e per column
            E1 = e[None, :, None] * R[:, None, :] ** (e[None, :, None] - 1) * live[None, :, None]
            dK_pot.append(self._block(one, Ps, Y, S, -E1 * Y) + self._block(R_th / R2, Ps, Y, S, E0 * Yth)
                          + self._block(R_ph / R2, Ps, Y, S, E0 * Yph))
            dh = (self._block(one, Pc, Y, self.jC, E0 * Y) + self._block(sd["r"], Pc, Y, S, E1 * Y)
                  + self._block(sd["th"] / R2, Pc, Y, S, E0 * Yth)
                  + self._block(sd["ph"] / R2, Pc, Y, S, E0 * Yph))
            dS_pot.append((1.0 if inner else -1.0) * Lam * dh)
        dSQ = Lam * np.einsum("tj,tk,a->ajk", Pc, C, (Y * self.w) @ Y[0])  # q(tau) Yr_00 in head_in
        head_in = self.phys.bernoulli_head(sides[0]["t"], sides[0]["r"], sides[0]["th"] ** 2 + sides[0]["ph"] ** 2, R)
        head_out = self.phys.bernoulli_head(sides[1]["t"], sides[1]["r"], sides[1]["th"] ** 2 + sides[1]["ph"] ** 2, R)
        dSL = np.einsum("tj,at->aj", Pc, (Y * self.w) @ (head_in - head_out).T)
        # assemble rows x columns
        Jm = np.zeros((self.size, self.size))
        o = self.off
        kr = np.array(self.k_rows).T
        sr = np.array(self.s_rows).T
        xc, ac, bc = (np.array(v).T for v in (self.x_idx, self.a_idx, self.b_idx))
        r0 = 0
        for s_i in range(2):
            rows = slice(r0, r0 + len(self.k_rows))
            Jm[rows, o[0]:o[1]] = dKX[s_i][kr[0], kr[1]][:, xc[0], xc[1]]
            cols, lo = (ac, o[1]) if s_i == 0 else (bc, o[3])
            Jm[rows, lo:lo + cols.shape[1]] = dK_pot[s_i][kr[0], kr[1]][:, cols[0], cols[1]]
            r0 += len(self.k_rows)
        rows = slice(r0, r0 + len(self.s_rows))
        Jm[rows, o[0]:o[1]] = dSX[sr[0], sr[1]][:, xc[0], xc[1]]
        Jm[rows, o[1]:o[2]] = dS_pot[0][sr[0], sr[1]][:, ac[0], ac[1]]
        Jm[rows, o[3]:o[4]] = dS_pot[1][sr[0], sr[1]][:, bc[0], bc[1]]
        Jm[rows, o[2]:o[3]] = dSQ[sr[0], sr[1]][:, self.q_idx]
        Jm[rows, o[4]] = dSL[sr[0], sr[1]]
        r0 += len(self.s_rows)
        Jm[r0, o[0] + self.i_amp] = 1.0
        nt = len(self.grid.tau)
        dV = (C.T @ ((R2 * self.w) @ Y.T)) / nt  # (j, m)
        Jm[r0 + 1, o[0]:o[1]] = dV[xc[1], xc[0]]
        return Jm


def _defaults(m: int, eps: float, n_max, j_max):
    """Truncation p m in degree and p in time, p = max(6, ceil(7 / -log10(3 eps))).

    Coefficients of degree ~ p m and harmonic p are O((c eps)^p) with c ~ 1-2 (measured for
    m <= 4); lambda converges faster than the coefficients (it sees the tail only through the
    secular projection), e.g. m = 4, eps = 0.02: lambda/lambda0 agrees to 1e-16 between
    (n_max, j_max) = (24, 6), (32, 8) and (40, 10), while the tail drops from 2e-9 to 3e-16.
    """
    p = max(6, int(np.ceil(7.0 / -np.log10(3.0 * abs(eps)))))
    return n_max or min(p * m, 64), j_max or min(p, 16)


def _newton(prob: _Problem, jac, tol: float, max_iter: int):
    """Chord-Newton from the linear orbit; the Jacobian is refreshed only on poor contraction."""
    z = prob.initial()
    res = prev = np.inf
    for it in range(1, max_iter + 1):
        F = prob.residual(z)[0].real
        res = float(np.max(np.abs(F)))
        if res < tol:
            return z, jac, it, res
        if jac is None or res > 0.25 * prev:
            jac = prob.jacobian(z)
            _STATS["jacobians"] += 1
        prev = res
        z = z - np.linalg.solve(jac, F)
    raise ConvergenceError(f"Newton did not converge for m={prob.grid.m}, k={prob.grid.k}, eps={prob.eps}:"
                           f" residual {res:.2e} > tol {tol:.1e}; lower eps or raise n_max/j_max")


def _check(physics, m, k, law):
    m = require_int_in_range("m", m, 2)
    k = abs(require_int_in_range("k", k, -m, m))
    require_choice("law", law, physics.FORCE_LAWS)
    return m, k


def _orbit(prob: _Problem, z, it, res, law) -> PeriodicOrbit:
    g = prob.grid
    X = prob.unpack(z[None, :])[0][0]
    coeffs = {(g.modes[i][0], g.modes[i][1], j): float(X[i, j]) for (i, j) in prob.x_idx}
    tail = max([abs(v) for (n, l, j), v in coeffs.items() if n > g.n_max - g.m or j > g.j_max - 1] + [0.0])
    return PeriodicOrbit(m=g.m, k=g.k, eps=prob.eps, law=law, n_max=g.n_max, j_max=g.j_max,
                         lambda_ratio=float(np.sqrt(z[-1])), residual=res, tail=tail,
                         newton_iterations=it, x_coefficients=coeffs)


def periodic_orbit(physics, m: int, k: int = 0, *, eps: float, n_max: int | None = None,
                   j_max: int | None = None, law: str = "normal", tol: float = 1e-13,
                   max_iter: int = 40) -> PeriodicOrbit:
    """Time-periodic orbit through 1 + eps Yr_{m,k} (radial-only membrane) by Newton's method.

    ``physics``: the pointwise laws of the model (a namespace with FORCE_LAWS, kappa_prime(m),
    membrane_load(R, lap_R, g, law=), kinematic_residual, bernoulli_head, stress_residual), e.g.
    the module :mod:`spectralshell.models.sphere_nonlinear`; the solver knows only this interface.
    Raises ParameterError for m < 2, |k| > m, eps <= 0 or an unknown law;
    ConvergenceError if Newton does not reach ``tol`` (max-norm of the projected residual).
    """
    m, k = _check(physics, m, k, law)
    eps = require_positive("eps", eps)
    n_max, j_max = _defaults(m, eps, n_max, j_max)
    if n_max < 2 * m or j_max < 2:
        raise ParameterError(f"n_max = {n_max} and j_max = {j_max} are invalid: must be >= 2m and >= 2")
    prob = _Problem(physics, make_grid(m=m, k=k, n_max=n_max, j_max=j_max), eps, law)
    z, _, it, res = _newton(prob, None, tol, max_iter)
    return _orbit(prob, z, it, res, law)


def frequency_slope(physics, m: int, k: int = 0, *, eps=(0.005, 0.01, 0.015, 0.02),
                    law: str = "normal", n_max: int | None = None, j_max: int | None = None,
                    tol: float = 1e-13) -> SlopeFit:
    """Fit lambda/lambda0 = 1 + c eps^2 + d eps^4 + e eps^6 to direct orbit solves at ``eps``.

    ``physics`` as in :func:`periodic_orbit`. One truncation (the default for the largest eps)
    and one chord Jacobian serve every eps.
    The uncertainty is |c - c'|, c' from the fit with one power fewer on the smaller half of eps.
    Raises ParameterError for fewer than 4 amplitudes or a non-positive one.
    """
    m, k = _check(physics, m, k, law)
    eps = tuple(sorted(require_positive("eps", e) for e in eps))
    if len(eps) < 4:
        raise ParameterError(f"eps = {eps!r} is invalid: must hold at least 4 amplitudes")
    n_max, j_max = _defaults(m, eps[-1], n_max, j_max)
    grid = make_grid(m=m, k=k, n_max=n_max, j_max=j_max)
    jac, orbits = None, []
    for e in eps:
        prob = _Problem(physics, grid, e, law)
        z, jac, it, res = _newton(prob, jac, tol, 60)
        orbits.append(_orbit(prob, z, it, res, law))
    e = np.array(eps)
    y = (np.array([o.lambda_ratio for o in orbits]) - 1.0) / e**2
    full = np.polynomial.polynomial.polyfit(e**2, y, 2)
    half = len(e) // 2 + 1
    fewer = np.polynomial.polynomial.polyfit(e[:half] ** 2, y[:half], 1)
    return SlopeFit(m=m, k=k, law=law, c=float(full[0]), uncertainty=float(abs(full[0] - fewer[0])),
                    eps=eps, lambda_ratio=tuple(o.lambda_ratio for o in orbits), orbits=tuple(orbits))
