"""Work-precision benchmark (issue 25): run time against the ACHIEVED error of tau_min.

One point of each model, its subharmonic tau_min (the smaller of the two kinds at each point), as
the accuracy asked for tightens, by three methods:

* package: ``spectralshell.solvers.marginal.marginal_tau(system, kind, tol=tol)``, the solve
  ``ss.floquet`` runs per kind (for the cochlea at a fixed M = 16 cosine modes, without
  floquet's second solve at M // 2 for the spatial error), tol = 1e-4, 1e-6, ..., 1e-12;
* dense QZ: the real-form Hill pencil assembled at truncation N
  (``discretise.hill.assemble``), every real tau by ``scipy.linalg.eigvals(A, B)``
  (``solvers.marginal.dense_taus``), the smallest positive one; N grows from 1 to 80 (to 20
  for the cochlea, whose blocks are 32 x 32);
* monodromy, where D(s) is a polynomial (here Mathieu only: the other three points are viscous,
  D(s) has a branch cut and no ODE in t): the multiplier -1 by ``brentq`` on det(M(tau) + I),
  M from ``solve_ivp`` (DOP853) at rtol = tol, xtol = tol, bracket reference +- 0.02
  (``bench_floquet.monodromy_det``).

Achieved error = |tau_min - reference|. The reference, computed once per point by none of the
timed methods: the eigenvalue of the real-form pencil at N_ref, Newton-refined on
(A - tau B) v = 0, c.v = 1 with residuals in 80-bit long double, started from QZ at a small N;
its truncation error is estimated by the change to a second N_ref, and for Mathieu it is
checked against an mpmath (30 digits) root of the Hill determinant with exact D(s). The D(s)
blocks are the model's double-precision values (the problem every method solves); the
reference's own uncertainty (printed) is ~1e-20, below the error of the correctly rounded double
(drawn as a vertical line: no double answer can do better).

Every run is on one BLAS thread (the package solves W of these orders on one anyway); times are
the best of up to 5 calls.
Rows for ``make bench`` (validation/_bench.py), at tol = 1e-4, 1e-8, 1e-12: the package against
the monodromy at rtol = tol, and against dense QZ at the cheapest N of its sweep whose achieved
error is <= tol (chosen WITH the reference, an oracle no user has; where none is, the most
accurate N).
Run: python validation/bench_work_precision.py   (draws validation/work_precision.png; with
     --quick into a new temporary directory)
"""

from __future__ import annotations

import math
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import mpmath
import numpy as np
import scipy.sparse as sp
from scipy.optimize import brentq
from scipy.sparse.linalg import splu, spsolve

import bench_floquet
from _bench import best_time, quick, row
from spectralshell._threads import one_blas_thread
from spectralshell.discretise.hill import HillMatrices, assemble
from spectralshell.models import fibre, mathieu, sphere
from spectralshell.models.base import HillSystem
from spectralshell.models.registry import hill_system
from spectralshell.params.registry import make_params, physical_values
from spectralshell.solvers.marginal import dense_taus, marginal_tau

HERE = Path(__file__).resolve().parent
KIND = "subharmonic"
TOLS = (1e-4, 1e-6, 1e-8, 1e-10, 1e-12)
ROW_TOLS = (1e-4, 1e-8, 1e-12)
LD = np.longdouble
FLOOR = 1e-21  # an error of exactly 0 is drawn here (the reference resolves ~1e-20)


@dataclass(frozen=True)
class Point:
    """One parameter point: its Hill system, the dense sweep's N, the two reference N, and the
    monodromy function (tau, rtol) -> det(M + I), if the model has one."""

    title: str
    system: Callable[[], HillSystem]
    dense_ns: tuple[int, ...]
    ref_ns: tuple[int, int]
    monodromy: Callable[[float, float], float] | None = None


@dataclass(frozen=True)
class Measured:
    """One run: its setting (tol or N), wall time (best of several), answer and achieved error."""

    setting: float
    seconds: float
    tau: float
    error: float
    n_temporal: int | None = None


def cochlea_system() -> HillSystem:
    """The cochlea at omega = 1000 rad/s (Table 5.1 otherwise), M = 16 coupled cosine modes."""
    params, _ = physical_values("cochlea", {"omega": 1000.0, "n_spatial": 16})
    return hill_system(make_params("cochlea", params))


POINTS = (
    Point(f"damped Mathieu, kappa {bench_floquet.KAPPA}, nu {bench_floquet.NU}",
          lambda: mathieu.hill_system(kappa=bench_floquet.KAPPA, nu=bench_floquet.NU),
          (1, 2, 3, 5, 10, 20, 40, 80), (40, 60), bench_floquet.monodromy_det),
    Point("fibre, m = 3, kappa 0.02, nu 2e-4",
          lambda: fibre.hill_system(m=3, kappa=0.02, nu=2e-4), (1, 2, 3, 5, 10, 20, 40, 80),
          (60, 80)),
    Point("sphere (viscous), m = 3, kappa 0.02, nu 0.006",
          lambda: sphere.hill_system(m=3, kappa=0.02, nu=0.006), (1, 2, 3, 5, 10, 20, 40, 80),
          (60, 80)),
    Point("cochlea, omega 1000 rad/s, M = 16 modes", cochlea_system, (1, 2, 3, 5, 10, 20),
          (20, 30)),
)
assert bench_floquet.KIND == KIND  # the monodromy function finds the multiplier -1


def timed(fn: Callable[[], float]) -> tuple[float, float]:
    """(best wall time, answer): best of 5 calls under 0.1 s, of 2 under 1 s, else one call."""
    t, out = best_time(fn, repeat=1)
    if t < 1.0:
        t = min(t, best_time(fn, repeat=4 if t < 0.1 else 1)[0])
    return t, out


# --- the reference ---------------------------------------------------------------------------

def residual_ld(hill: HillMatrices, tau: LD, v: np.ndarray) -> np.ndarray:
    """(A - tau B) v in long double, from the pencil's block storage."""
    K, s, _ = hill.diag.shape
    V = v.reshape(K, s, 1)
    Bv = np.zeros((K, s, 1), dtype=LD)
    Bv[1:] += np.matmul(hill.lower.astype(LD), V[:-1])
    Bv[:-1] += np.matmul(hill.upper.astype(LD), V[1:])
    if hill.self_coupling is not None:
        Bv += np.matmul(hill.self_coupling.astype(LD), V)
    return (np.matmul(hill.diag.astype(LD), V) - tau * Bv).ravel()


def refined_tau(system: HillSystem, kind: str, n: int, guess: float) -> tuple[LD, float]:
    """The real eigenvalue tau near ``guess`` of the real-form pencil at truncation n, by Newton's
    method on (A - tau B) v = 0, c.v = 1 (c: the inverse-iteration vector) with the residual in
    long double and the correction solved in double (sparse LU). Returns (tau, last step)."""
    hill = assemble(system, kind, n, "real")
    A, B = hill.A.tocsc(), hill.B.tocsc()
    lu = splu(A - guess * B)
    v = np.ones(A.shape[0])
    for _ in range(3):
        v = lu.solve(B @ v)
        v /= np.linalg.norm(v)
    c = v / (v @ v)
    tau, v, step = LD(guess), v.astype(LD), math.inf
    for _ in range(8):
        rhs = np.concatenate([residual_ld(hill, tau, v), [c @ v - 1]]).astype(float)
        J = sp.bmat([[A - float(tau) * B, sp.csc_matrix(-(B @ v.astype(float))[:, None])],
                     [sp.csc_matrix(c[None, :]), None]], format="csc")
        delta = spsolve(J, -rhs)
        v, tau = v + delta[:-1], tau + LD(delta[-1])
        if abs(delta[-1]) >= abs(step) or abs(delta[-1]) <= 1e-19 * abs(float(tau)):
            step = abs(delta[-1])
            break
        step = abs(delta[-1])
    return tau, float(step)


def mathieu_mp_root(kappa: float, nu: float, kind: str, guess: float, n: int = 40) -> LD:
    """tau of the damped Mathieu equation as a root of its Hill determinant (two-sided form,
    tridiagonal, indices -N(-1)..N) in mpmath at 30 digits, D(s) = s^2 + nu s + kappa exact for
    the double-precision kappa and nu; f_j = D_j f_{j-1} - tau^2 kappa^2 f_{j-2}, scaled by
    D_j D_{j-1}."""
    with mpmath.workdps(30):
        half = mpmath.mpf(1) / 2 if kind == "subharmonic" else 0
        first = -n - 1 if kind == "subharmonic" else -n
        s = [mpmath.mpc(0, k + half) for k in range(first, n + 1)]
        d = [x * x + mpmath.mpf(nu) * x + mpmath.mpf(kappa) for x in s]
        g2 = mpmath.mpf(kappa) ** 2

        def det(tau):
            before, last = mpmath.mpf(1), mpmath.mpf(1)
            for j in range(1, len(d)):
                before, last = last, last - tau * tau * g2 / (d[j] * d[j - 1]) * before
            return last

        return LD(mpmath.nstr(mpmath.re(mpmath.findroot(det, mpmath.mpf(guess))), 25))


def dense_tau_min(system: HillSystem, kind: str, n: int) -> float:
    """Smallest positive real tau of the real-form pencil at N = n by QZ (NaN if none)."""
    taus = dense_taus(assemble(system, kind, n, "real"))
    taus = taus[taus > 0]
    return float(taus[0]) if taus.size else math.nan


@dataclass(frozen=True)
class Reference:
    tau: LD
    change: float  # |tau(N_ref) - tau(N_ref')|
    step: float  # the last Newton step
    mp_check: float | None  # |tau - mpmath root| (Mathieu)

    @property
    def rounded(self) -> float:
        """The error of the correctly rounded double: no double answer does better."""
        return self.error(float(self.tau))

    def describe(self, point: Point) -> str:
        n1, n2 = point.ref_ns
        text = (f"reference tau_min {np.format_float_positional(self.tau, 20)}: Newton-refined "
                f"eigenvalue of the real-form pencil at N = {n1} (residuals in long double), "
                f"change to N = {n2} {self.change:.1e}, last Newton step {self.step:.1e}; the "
                f"correctly rounded double is off by {self.rounded:.1e}")
        if self.mp_check is not None:
            text += (f"; an mpmath 30-digit Hill-determinant root (exact D(s)) differs by "
                     f"{self.mp_check:.1e}")
        return text

    def short(self, point: Point) -> str:
        """The note of a table row."""
        check = "" if self.mp_check is None else f", mpmath check {self.mp_check:.0e}"
        return (f"errors against a Newton-refined long-double reference at N = {point.ref_ns[0]}"
                f" (change to N = {point.ref_ns[1]}: {self.change:.0e}{check})")

    def error(self, tau: float) -> float:
        return float(abs(LD(tau) - self.tau)) if math.isfinite(tau) else math.inf


def reference(point: Point, system: HillSystem) -> Reference:
    guess = dense_tau_min(system, KIND, 10)
    n1, n2 = point.ref_ns
    tau, step = refined_tau(system, KIND, n1, guess)
    other, _ = refined_tau(system, KIND, n2, guess)
    check = None
    if point.monodromy is not None:  # Mathieu
        check = float(abs(mathieu_mp_root(bench_floquet.KAPPA, bench_floquet.NU, KIND,
                                          float(tau)) - tau))
    return Reference(tau=tau, change=float(abs(tau - other)), step=step, mp_check=check)


# --- the three methods -----------------------------------------------------------------------

def package_series(system: HillSystem, ref: Reference, tols=TOLS) -> list[Measured]:
    out = []
    for tol in tols:
        t, res = timed(lambda: marginal_tau(system, KIND, tol=tol))
        out.append(Measured(tol, t, res.tau_min, ref.error(res.tau_min), res.n_temporal))
    return out


def dense_series(system: HillSystem, ref: Reference, ns) -> list[Measured]:
    out = []
    for n in ns:
        t, tau = timed(lambda: dense_tau_min(system, KIND, n))
        out.append(Measured(n, t, tau, ref.error(tau), n))
    return out


def monodromy_series(det: Callable[[float, float], float], ref: Reference,
                     tols=TOLS) -> list[Measured]:
    out, centre = [], float(ref.tau)
    for tol in tols:
        t, tau = timed(lambda: brentq(lambda x: det(x, tol), centre - 0.02, centre + 0.02,
                                      xtol=tol))
        out.append(Measured(tol, t, tau, ref.error(tau)))
    return out


def matched(series: list[Measured], tol: float) -> Measured:
    """The cheapest run with achieved error <= tol, else the most accurate one."""
    good = [m for m in series if m.error <= tol]
    return min(good, key=lambda m: m.seconds) if good else min(series, key=lambda m: m.error)


# --- output ----------------------------------------------------------------------------------

def _err(x: float) -> str:
    return f"{x:8.1e}" if math.isfinite(x) else f"{'no tau':>8}"


def report(point: Point, ref: Reference, pkg, dense, mono) -> None:
    print(f"\n== {point.title}, {KIND} tau_min\n   {ref.describe(point)}")
    print("   dense QZ sweep (assemble + scipy.linalg.eigvals(A, B)):  "
          + ";  ".join(f"N {m.n_temporal}: {m.seconds:.1e} s, {_err(m.error).strip()}"
                       for m in dense))
    head = (f"{'tol':>8} | {'package N':>9} {'seconds':>8} {'error':>8} | {'QZ N':>5} "
            f"{'seconds':>8} {'error':>8} {'ratio':>6}")
    if mono:
        head += f" | {'monodromy s':>11} {'error':>8} {'ratio':>6}"
    print(head)
    for i, p in enumerate(pkg):
        q = matched(dense, p.setting)
        line = (f"{p.setting:8.0e} | {p.n_temporal:9d} {p.seconds:8.1e} {_err(p.error)} | "
                f"{q.n_temporal:5d} {q.seconds:8.1e} {_err(q.error)} {q.seconds / p.seconds:6.2g}")
        if mono:
            m = mono[i]
            line += f" | {m.seconds:11.1e} {_err(m.error)} {m.seconds / p.seconds:6.3g}"
        print(line, flush=True)
    note = ref.short(point)
    for p in pkg:
        if p.setting not in ROW_TOLS:
            continue
        task = (f"work-precision: {point.title}, {KIND} tau_min, tol {p.setting:.0e} "
                f"(N = {p.n_temporal})")
        q = matched(dense, p.setting)
        row(task=task, package_s=p.seconds, baseline=f"dense QZ of the real-form pencil, the "
            f"cheapest N of the sweep within tol (chosen with the reference): N = {q.n_temporal}",
            baseline_s=q.seconds, error=p.error, baseline_error=q.error, note=note)
        for m in mono:
            if m.setting == p.setting:
                row(task=task, package_s=p.seconds, baseline="solve_ivp monodromy (DOP853, rtol = "
                    "tol) + brentq (xtol = tol)", baseline_s=m.seconds, error=p.error,
                    baseline_error=m.error, note=note)


def plot(results: list[tuple[Point, Reference, list, list, list]], path: Path) -> Path:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(11.0, 8.5))
    for ax, (point, ref, pkg, dense, mono) in zip(axes.flat, results):
        ns = ", ".join(str(n) for n in sorted({m.n_temporal for m in pkg}))
        for label, series, style in (
                (f"package marginal_tau, tol 1e-4..1e-12 (final N = {ns})", pkg, "o-"),
                ("dense QZ eig(A, B), N = " + ", ".join(str(m.n_temporal) for m in dense),
                 dense, "s--"),
                ("monodromy (DOP853 + brentq), rtol = xtol = tol", mono, "^:")):
            shown = [m for m in series if math.isfinite(m.error)]
            if shown:
                ax.loglog([max(m.error, FLOOR) for m in shown], [m.seconds for m in shown], style,
                          label=label, markersize=5)
        for m in dense:
            if math.isfinite(m.error):
                ax.annotate(f"{m.n_temporal}", (max(m.error, FLOOR), m.seconds), fontsize=7,
                            xytext=(3, 3), textcoords="offset points")
        ax.axvline(max(ref.rounded, FLOOR), color="0.5", linewidth=0.8, linestyle="-.",
                   label="error of the correctly rounded double")
        ax.set_title(f"{point.title}\n{KIND} tau_min = {float(ref.tau):.12g}", fontsize=9)
        ax.set_xlabel("achieved error |tau_min - reference| (tau dimensionless)")
        ax.set_ylabel("wall time (s)")
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(fontsize=7, loc="best")
    fig.suptitle("spectralshell work-precision: run time against achieved error of tau_min "
                 "(numbers at the QZ points: truncation N)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def run_point(point: Point, tols=TOLS) -> tuple[Point, Reference, list, list, list]:
    system = point.system()
    ref = reference(point, system)
    pkg = package_series(system, ref, tols)
    dense = dense_series(system, ref, point.dense_ns)
    mono = [] if point.monodromy is None else monodromy_series(point.monodromy, ref, tols)
    report(point, ref, pkg, dense, mono)
    return point, ref, pkg, dense, mono


def main() -> None:
    print("work-precision: wall time (best of up to 5 calls, one BLAS thread) against the "
          f"achieved error of the {KIND} tau_min; ratio = baseline time / package time")
    with one_blas_thread():  # a shared 2-core machine: BLAS threads only add noise here
        results = [run_point(point) for point in POINTS]
    # a --quick smoke run (validation/_bench.py) leaves the committed chart alone
    where = Path(tempfile.mkdtemp(prefix="work-precision-")) if quick() else HERE
    print(f"\nwrote {plot(results, where / 'work_precision.png')}")


if __name__ == "__main__":
    main()
