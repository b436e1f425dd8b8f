"""Where the thesis is wrong: confirmed misprints and claims that do not hold, as data.

Each :class:`Finding` records where the thesis goes wrong, what holds instead, the evidence that
decided it (a residual, a reciprocity or limit check, a second method) and which script or test
produced that evidence. Sources: ``/work/shared/ERRATA.md`` (the list of suspects) and the
verdicts of ``derivations/*_result.md`` and ``derivations/lindstedt_sphere.py``. The validation
report (:mod:`spectralshell.reports.validation`) prints them, with the live result of every
validation case named in ``cases`` and the value of ``live`` recomputed in the same run.

To add a finding, append a :class:`Finding` to :data:`FINDINGS` (``kind`` 'misprint' for printed
algebra, 'claim' for a statement or table entry that fails at converged truncation, 'open' for a
suspect not yet decided).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

KINDS = ("misprint", "claim", "open")


@dataclass(frozen=True, kw_only=True)
class Finding:
    """One place where the printed thesis is wrong (or an erratum not yet decided).

    where : thesis location (chapter, equation, table, figure).
    kind : 'misprint', 'claim' or 'open' (:data:`KINDS`).
    thesis : what is printed or claimed, in short.
    holds : what holds instead.
    evidence : the checks that decided it.
    decided_by : scripts and tests that carry those checks.
    cases : names of validation cases whose results support the verdict.
    live : optional callable returning a one-line recomputation shown in the report.
    """

    where: str
    kind: str
    thesis: str
    holds: str
    evidence: str
    decided_by: tuple[str, ...] = ()
    cases: tuple[str, ...] = ()
    live: Callable[[], str] | None = None


def _table_7_3_nonlinear() -> str:
    """Balloon A, R = 6 cm: the (7.5) frequency times 1 + c_2 eps^2 at eps = 0.2, printed and exact c_2."""
    from ..params.physical import balloon
    from ..runner.lp import lp_coefficient
    from ..runner.modes import natural_modes as solve_natural_modes

    b = balloon("A", 6.0)
    inviscid = float(solve_natural_modes("sphere", m=2, kappa=1.0, nu=0.0).gamma[0].imag) / b.time_scale
    printed_c2, exact_c2 = -7061 / (3136 * 3.141592653589793), lp_coefficient(2)
    return (f"balloon A, R = 6 cm: inviscid {inviscid:.2f} 1/s; with the printed c_2 = {printed_c2:.4f}: "
            f"{inviscid * (1 + 0.04 * printed_c2):.2f} 1/s (the printed 44.15); with the exact "
            f"c_2 = {exact_c2:.4f}: {inviscid * (1 + 0.04 * exact_c2):.2f} 1/s")


def _fibre_table_4_1_unstable() -> str:
    """Every degree m = 2..6 unstable at tau = 0.45 in the two Table 4.1 cases (corrected model)."""
    from ..params.physical import TABLE_4_1, fibre_forced
    from ..runner.floquet import stability

    parts = []
    for case in (1, 2):
        res = stability("fibre", tau=0.45, m="2:6", **fibre_forced(**TABLE_4_1[case]))
        found = [f"m = {d['m']} {d['kind']} (tau_min {min(d['tau_' + d['kind']]):.4f})"
                 for d in res.modes if d["unstable"]]
        parts.append(f"case {case}: " + ", ".join(found))
    return "; ".join(parts)


def _cardiac_nu() -> str:
    from ..params.physical import CARDIAC, PhysicalSphere, bpm_to_rad_per_s

    nu = PhysicalSphere(rho=CARDIAC["rho"], mu=CARDIAC["mu"], radius=CARDIAC["radius"], sigma=1e4,
                        omega=bpm_to_rad_per_s(CARDIAC["bpm_typical_svt"])).forced()["nu"]
    return (f"R = 2 cm, mu = 0.04, 400 bpm as 2 pi 400/60 rad/s gives nu = {nu:.4g} (the printed "
            f"2.39e-4); read as 400/60 1/s it would give {nu * 2 * 3.141592653589793:.4g}")


FIBRE = "derivations/fibre_linear.py (fibre_linear_result.md)"
SPHERE = "derivations/sphere_linear.py (sphere_linear_result.md)"
LINDSTEDT = "derivations/lindstedt_sphere.py"
COCHLEA_SCRIPT = "derivations/cochlea_linear.py (cochlea_linear_result.md)"

FINDINGS: tuple[Finding, ...] = (
    # ---------------------------------------------------------------- chapter 2
    Finding(where="ch. 2, text after the block matrices of the Hill system (2.6)", kind="misprint",
            thesis="the eigenproblem is said to determine values of tau and nu",
            holds="tau (the eigenvalue) along kappa (the swept parameter); nu is fixed",
            evidence="the pencil A v = tau B v has tau as eigenvalue at fixed (kappa, nu); the package "
                     "traces it along kappa and reproduces scipy's Mathieu characteristic values",
            decided_by=("derivations/mathieu_mapping.py", "tests/test_mathieu.py"),
            cases=("mathieu.scipy.a1.q1.3",)),
    # ---------------------------------------------------------------- chapter 4
    Finding(where="ch. 4, (4.24)-(4.25), per-mode 2x2 system", kind="misprint",
            thesis="the X^theta terms of (4.25) (D_n with its -i m^2, and the m^2 tau term) carry one sign",
            holds="the opposite sign: the two rows use opposite conventions for X^theta, and flipping "
                  "the X^theta column of one row gives the system derived from the fields",
            evidence="(i) fields satisfying the primitive equations to 1e-30 give the corrected system; "
                     "(ii) reciprocity: the row-normalised off-diagonal ratio H_12/H_21 is +1 for the "
                     "derived load and -1 at every omega for the printed one; (iii) the printed elastic "
                     "matrix is non-singular at m = 1 (det -2), so a rigid translation would be loaded; "
                     "(iv) the printed inviscid limit is lambda0^2 = kappa m(m^2+1)/2, not Rayleigh's "
                     "kappa m(m^2-1)/2; (v) Table 4.1: only the corrected system makes m = 3 (case 1) and "
                     "m = 2 (case 2) the least-threshold subharmonic modes (printed: case 2 gives m = 3 "
                     "harmonic, 0.306)",
            decided_by=(FIBRE, "tests/test_fibre_model.py"),
            cases=("fibre.table4.1.case1.mode", "fibre.table4.1.case2.mode", "fibre.inviscid.scipy.m3")),
    Finding(where="ch. 4, (4.24) right-hand side and the beta = 0 Green's function prefactor",
            kind="misprint", thesis="k tau (X_{n-1} - X_{n+1}) and prefactor -1/(2k)",
            holds="m in both places (k is undefined in chapter 4)",
            evidence="with m the right-hand side equals the derived forcing matrix G; the Green's "
                     "function with -1/(2m) satisfies its jump condition",
            decided_by=(FIBRE,)),
    Finding(where="ch. 4, display after (4.27)", kind="misprint",
            thesis="tau R (X_{n+1} - X_{n-1})",
            holds="tau R (X_{n-1} - X_{n+1}), the convention of (4.24)-(4.25) and of the B matrix; "
                  "harmless: tau -> -tau is the time shift t -> t + pi, so the marginal |tau| agree",
            evidence="a Hill null vector reproduces direct time integration to 4e-13 with the (4.24) "
                     "convention and misses by 1.2 with the opposite one",
            decided_by=(FIBRE,)),
    Finding(where="ch. 4, beta = 0 (steady) problem", kind="misprint",
            thesis="a_0 = b_0 = 0 is derived from continuity; the Green's function has powers "
                   "z^(m-1), z^(m+2); the inside u_0^r has the sign of its b_0 term wrong",
            holds="G = -(1/(2m)) r^(m-1)/z^m (r < z), -(1/(2m)) z^m/r^(m+1) (r > z); u_0^r is then C^1 "
                  "at r = 1 for every a_0, b_0, and a_0 = b_0 = 0 follows from the kinematic condition "
                  "u(1) = s X = 0",
            evidence="sympy: the printed Green's function jumps by (z - 1)/(2m) at r = z; the printed "
                     "fields leave a_0 free",
            decided_by=(FIBRE,)),
    # ---------------------------------------------------------------- chapter 6
    Finding(where="ch. 6, 4x4 real block A_n after (6.34), entry (1,4)", kind="misprint",
            thesis="-Im{A_n}", holds="-Im{B_n}",
            evidence="the real form of A X^r + B X^Psi reproduces the complex product on random data "
                     "only with -Im{B_n}",
            decided_by=(SPHERE,)),
    Finding(where="ch. 6 before (6.27), and ch. 7: kinematic X^Psi expression", kind="misprint",
            thesis="mixes j and h: (j_m(i beta) + i beta h'_m(i beta))",
            holds="j only: (j_m + i beta j'_m) h_{m-1}",
            evidence="with the pressure amplitudes of the true fields the printed expression differs "
                     "from s X^Psi; the j-only form equals it to 1e-25; (6.27) matches the j-only form",
            decided_by=(SPHERE,)),
    Finding(where="ch. 6, harmonic n = 0 block", kind="misprint",
            thesis="the printed B-tilde is combined with the A_0 that (6.34) would give",
            holds="A_0 = I_4, i.e. X_0 = 2 tau Im X_1 (D(0) = q I)",
            evidence="D(0) = q I from the beta -> 0 limit of the derived load; the printed B-tilde "
                     "reproduces X_0 = 2 tau Im X_1 only with A_0 = I_4",
            decided_by=(SPHERE, "tests/test_sphere_floquet.py")),
    Finding(where="Appendix (B.5), vector Laplacian", kind="misprint",
            thesis="components labelled Psi and Phi", holds="the labels swapped (as in (6.20a-c))",
            evidence="symbolic VSH calculus on explicit harmonics (2,0), (2,1), (3,2)",
            decided_by=(SPHERE,)),
    Finding(where="ch. 6, section 6.3, beta = 0 steady fields after (6.33)", kind="misprint",
            thesis="u_0^r coefficients m a0/(nu(2m+3)) and (m+1) b0/(nu(2m-1)); u_0^Psi r^-m "
                   "coefficient -(m-1) b0/(nu m(2m-1)); the ODE's last term written r^2 p0' nu",
            holds="m a0/(2 nu (2m+3)), (m+1) b0/(2 nu (2m-1)), -(m-2) b0/(2 nu m(2m-1)), r^2 p0'/nu; "
                  "(6.31)-(6.33) are right",
            evidence="sympy: the printed u_0^r does not satisfy its own ODE; the corrected one equals "
                     "the Green's-function solution and is C^1 at r = 1",
            decided_by=(SPHERE,)),
    Finding(where="ch. 6, section 6.5 (cardiac parameters)", kind="misprint",
            thesis="frequencies quoted as 1/s and bpm without the factor 2 pi",
            holds="angular frequencies in rad/s: 400 bpm = 2 pi 400/60 rad/s",
            evidence="only the rad/s reading reproduces the printed nu = 2.39e-4",
            decided_by=("tests/test_physical.py",), live=_cardiac_nu),
    # ---------------------------------------------------------------- chapter 7
    Finding(where="ch. 7, 7.3: lambda_2 and the printed c_2", kind="misprint",
            thesis="lambda_2 = -(3531 sqrt30/(3920 pi)) sqrt(kappa) implies c_2 = -7062/(3136 pi); "
                   "the text prints c_2 = -7061/(3136 pi) = -0.7167",
            holds="neither: c_2 = -81161/(122304 pi) = -0.21123 (enclosed volume of the unit sphere, "
                  "radial-only membrane)",
            evidence="exact Lindstedt-Poincare algebra with Gaunt coefficients (rational arithmetic) "
                     "and, independently, Newton on the time-periodic orbit of the full nonlinear "
                     "equations (no expansion in eps), agreeing to ~1e-9; no variant tried (degree 0 "
                     "dropped, literal volume, radial force law) gives -0.7167",
            decided_by=(LINDSTEDT, "tests/test_lindstedt.py"), cases=("lp.c2.direct",)),
    Finding(where="ch. 7, (7.19b)", kind="misprint",
            thesis="the stress balance after the change of variables r = X r*",
            holds="the time derivative at fixed r* and the gradient pick up grad_S X terms that the "
                  "print drops; the velocity term and the factor kappa of Delta_S X are misprinted",
            evidence="re-derivation in physical variables (no change of variables), checked by the "
                     "direct orbit solve's residual < 1e-13",
            decided_by=(LINDSTEDT, "spectralshell/models/sphere_nonlinear.py")),
    Finding(where="ch. 7, (7.21)-(7.22)", kind="misprint",
            thesis="(7.21) (without kappa in the (m^2+m-1)/lambda0^2 term) gives (7.22a); (7.22a) "
                   "constant -9/56 sqrt(5/pi); (7.22b) cos 2t coefficient 403/378",
            holds="(7.21) evaluated with exact projections does not give (7.22a); the constant is "
                  "+9/56 sqrt(5/pi) and the coefficient 439/378",
            evidence="exact O(eps^2) fields of the Lindstedt-Poincare solve; the direct periodic-orbit "
                     "solve reproduces their x_2 coefficients",
            decided_by=(LINDSTEDT,)),
    Finding(where="ch. 7, 7.3: the O(eps^2) sums start at degree 2", kind="misprint",
            thesis="degrees 0 and 1 omitted without argument",
            holds="degree 0 (the enclosed volume) must be kept: dropping it gives c_2 = -0.28086; "
                  "degree 1 never enters at O(eps^2) and does not change c",
            evidence="exact solve with and without degree 0; Gaunt parity for degree 1",
            decided_by=(LINDSTEDT,)),
    # ---------------------------------------------------------------- claims
    Finding(where="ch. 7, 7.3: nonlinear coefficients for m = 2, 3, 4", kind="claim",
            thesis="c_2, c_3, c_4 = -0.7167, -0.8485, -1.0645",
            holds="c_2, c_3, c_4 = -0.21123, -0.46241, -0.79644 (exact rationals over pi)",
            evidence="exact Lindstedt-Poincare coefficients confirmed by the direct periodic-orbit "
                     "solve (fitted eps^2 slope) to 1e-6 relative or better",
            decided_by=(LINDSTEDT, "tests/test_lindstedt.py"),
            cases=("lp.c2.direct", "lp.c3.direct", "lp.c4.direct")),
    Finding(where="ch. 7, Table 7.3, column 'Nonlinear Theory (eps = 0.2)'", kind="claim",
            thesis="frequencies about 2.9 % below the inviscid ones (e.g. 44.15 1/s for balloon A, 6 cm)",
            holds="with the exact c_2 the shift is -0.84 % (e.g. 45.07 1/s): the column is built on the "
                  "misprinted c_2",
            evidence="(7.5) frequency times 1 + c_2 eps^2 reproduces the printed column only with "
                     "c_2 = -0.7167",
            decided_by=(LINDSTEDT, "tests/test_physical.py"), cases=("sphere.table7.3.inviscid",),
            live=_table_7_3_nonlinear),
    Finding(where="ch. 7, 7.3, last paragraph (non-axisymmetric modes)", kind="claim",
            thesis="|Psi_{m,k}|^2 excites infinitely many degrees",
            holds="products of band-limited harmonics are band-limited (degrees <= 2m); the real "
                  "obstruction is that for 1 <= k and 3k <= m the O(eps^3) forcing contains Y_{m,3k} "
                  "at the oscillation frequency, so the single real harmonic is not a nonlinear "
                  "normal mode and c_{m,k} is undefined there",
            evidence="exact Gaunt expansion of the O(eps^2) and O(eps^3) forcing",
            decided_by=(LINDSTEDT,)),
    Finding(where="ch. 4, section 4.4 / Table 4.1 (tau = 0.45)", kind="claim",
            thesis="the principal subharmonic mode is the instability the simulations should show",
            holds="it is the least-threshold one, but an m = 5 harmonic tongue also lies below 0.45 "
                  "(tau_min 0.2954 in case 1, 0.3978 in case 2), which the thesis does not report",
            evidence="converged Floquet thresholds (error estimate < 1e-10) of the corrected model",
            decided_by=(FIBRE, "tests/test_fibre_model.py"),
            cases=("fibre.table4.1.case1.mode", "fibre.table4.1.case2.mode"),
            live=_fibre_table_4_1_unstable),
    # ---------------------------------------------------------------- chapter 5
    Finding(where="ch. 5, Table 5.1 (dimensionless ranges)", kind="misprint",
            thesis="nu in [8.06e-6, 1.61e-4] and kappa in [0.135, 53.9] for omega in [400, 1600] 1/s",
            holds="those are the values at omega = 2000 and 100 rad/s; at 400-1600 rad/s nu is in "
                  "[1.007e-5, 4.03e-5] and kappa in [0.2104, 3.366]",
            evidence="the conversion formulas of 5.2 evaluated at both ends of each frequency range",
            decided_by=(COCHLEA_SCRIPT,)),
    Finding(where="ch. 5, vertical velocity v_k^n, y > 0 branch", kind="misprint",
            thesis="the e^{-ky} term without a factor k, and e^{ky} written with k instead of |k|",
            holds="coefficient 2 k beta b/(beta^2 - k^2); |k| in the exponent (irrelevant for the "
                  "cosine system, k >= 1)",
            evidence="fields that satisfy the unsteady Stokes equations in both chambers; with the "
                     "factor k the printed v equals the derived field; the final (5.9)-(5.12) are "
                     "correct (D(0) = kappa C); a monodromy check of the inviscid coupled system gives "
                     "a multiplier -1 to 3e-7 at the Hill pencil's subharmonic tau",
            decided_by=(COCHLEA_SCRIPT,), cases=("cochlea.inviscid.scipy.k2",)),
    Finding(where="ch. 5, steady (s = 0) fields of 5.3", kind="misprint",
            thesis="k a/(2 nu) y e^{ky}, and c k e^{ky} in the horizontal velocity",
            holds="a/(2 nu) y e^{ky} and i c e^{ky} (continuity); harmless: every coefficient vanishes",
            evidence="symbolic substitution into the steady Stokes equations",
            decided_by=(COCHLEA_SCRIPT,)),
    # ---------------------------------------------------------------- open
    Finding(where="ch. 5, matrix display of 5.3, first block row", kind="open",
            thesis="B-tilde named twice", holds="suspected: the text's definitions (B-check, B-tilde) "
            "are meant", evidence="not decided: the package assembles the blocks from the derived D "
            "and G (derivations/cochlea_linear.py), not from this display"),
)
