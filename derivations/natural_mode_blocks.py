"""Derive, with sympy, the Hill blocks in a basis of natural modes (discretise/natural_modes.py).

The Hill system of a model in b spatial modes is D(s_n) u_n = i tau G (u_{n-1} - u_{n+1})
(models/base.py (2)), with D(s) = G + s^2 Mass + E(s): G, Mass real symmetric, Mass positive
definite (the inviscid inertia), E(s) the viscous part (E = 0 inviscid; the cochlea's
D(s) - G - s^2 Mass = diag(Z_k(s) - 2 s^2 / k), so D(s) - G is diagonal there).

1. Galerkin. With u_n = V a_n and the rows multiplied by V^T, where V^T Mass V = I and
   V^T G V = W = diag(w_j^2), the system keeps its form with D_m(s) = W + V^T (D(s) - G) V =
   W + s^2 I + V^T E(s) V and forcing G_m = W.
2. Inviscid decoupling: E = 0 gives D_m(s) = W + s^2 I, G_m = W: mode j is the Mathieu system
   of models/mathieu.py with kappa = w_j^2, nu = 0 (a_j'' + w_j^2 (1 + 2 tau sin t) a_j = 0).
3. Congruence: with all b modes (V square), det D_m(s) = det(V)^2 det D(s) for every s and
   every E: the same Floquet exponents, hence the same marginal tau (an exact two-mode
   example with symbolic E(s) = diag(z1, z2)).
4. Counting: the number of negative eigenvalues of G - w^2 Mass is the number of natural
   frequencies w_j < w (Sylvester's law of inertia; checked on the example at several w).

Run: python derivations/natural_mode_blocks.py (exit status 0 when every check passes).
"""

import sys

import sympy as sp

from _checks import check, section, summary


def galerkin() -> None:
    section("1-2. Galerkin projection of the Hill system onto natural modes")
    b, m = 3, 2
    s, tau = sp.symbols("s tau")
    # natural modes first: V = P^{-1} for an exact unimodular P, Mass = P^T P and
    # G = P^T W P (symbolic w_j^2), so that V^T Mass V = I and V^T G V = W hold by construction
    P = sp.Matrix([[1, 0, 0], [2, 1, 0], [-1, 3, 1]]) * sp.Matrix([[1, -2, 1], [0, 1, 4], [0, 0, 1]])
    Vfull = P.inv()
    w2 = sp.symbols("w1_2 w2_2 w3_2", positive=True)
    Mass = P.T * P
    G = P.T * sp.diag(*w2) * P
    check("Mass symmetric positive definite (leading minors), G symmetric",
          Mass.is_symmetric() and all(Mass[:k, :k].det() > 0 for k in (1, 2, 3))
          and G.is_symmetric())
    check("V^T Mass V = I", sp.simplify(Vfull.T * Mass * Vfull - sp.eye(b)) == sp.zeros(b, b))
    check("V^T G V = diag(w^2)",
          sp.simplify(Vfull.T * G * Vfull - sp.diag(*w2)) == sp.zeros(b, b))
    E = sp.Matrix(b, b, lambda i, j: sp.Function(f"e{min(i, j)}{max(i, j)}")(s))
    D = G + s**2 * Mass + E
    V = Vfull[:, :m]
    a = {k: sp.Matrix(m, 1, lambda i, _: sp.Symbol(f"a{k}_{i}")) for k in (-1, 0, 1)}
    residual = D * V * a[0] - sp.I * tau * G * (V * a[-1] - V * a[1])
    projected = V.T * residual
    Dm = sp.diag(*w2[:m]) + V.T * (D - G) * V
    expected = Dm * a[0] - sp.I * tau * sp.diag(*w2[:m]) * (a[-1] - a[1])
    check("V^T [D(s_n) V a_n - i tau G V (a_{n-1} - a_{n+1})] = D_m a_n - i tau W (a_{n-1} - a_{n+1})",
          sp.simplify(projected - expected) == sp.zeros(m, 1))
    check("D_m(s) = W + s^2 I + V^T E(s) V",
          sp.simplify(Dm - (sp.diag(*w2[:m]) + s**2 * sp.eye(m) + V.T * E * V)) == sp.zeros(m, m))
    inviscid = Dm.subs({e: 0 for e in E})
    check("inviscid: D_m(s) = diag(s^2 + w_j^2), G_m = diag(w_j^2): decoupled Mathieu modes "
          "(models/mathieu.py with kappa = w_j^2, nu = 0)",
          sp.simplify(inviscid - sp.diag(*[s**2 + w for w in w2[:m]])) == sp.zeros(m, m))


def congruence_and_count() -> None:
    section("3-4. Congruence with all modes; counting natural frequencies below w")
    s, z1, z2 = sp.symbols("s z1 z2")
    # two cosine modes k = 1, 2 of the cochlea's inviscid form: Mass = diag(2/k), G = kappa C
    Mass = sp.diag(2, 1)
    G = sp.Matrix([[3, 1], [1, 2]])
    w2 = sorted(sp.solve(sp.det(G - sp.Symbol("x") * Mass), sp.Symbol("x")),
                key=lambda r: float(r))
    cols = []
    for x in w2:
        v = (G - x * Mass).nullspace()[0]
        cols.append(sp.simplify(v / sp.sqrt((v.T * Mass * v)[0])))
    V = sp.Matrix.hstack(*cols)
    check("exact modes of (G, Mass): V^T Mass V = I, V^T G V = diag(w^2)",
          sp.simplify(V.T * Mass * V - sp.eye(2)) == sp.zeros(2, 2)
          and sp.simplify(V.T * G * V - sp.diag(*w2)) == sp.zeros(2, 2),
          f"w^2 = {[sp.nsimplify(x) for x in w2]}")
    D = G + s**2 * Mass + sp.diag(z1, z2)
    Dm = sp.diag(*w2) + V.T * (D - G) * V
    check("m = b: det D_m(s) = det(V)^2 det D(s) for any viscous diagonal (z1, z2)",
          sp.simplify(Dm.det() - V.det()**2 * D.det()) == 0)
    ok = True
    for w in (sp.Rational(1, 2), 1, sp.Rational(3, 2), 2, 3):
        negative = sum(1 for x in (G - w**2 * Mass).eigenvals(multiple=True) if float(x) < 0)
        below = sum(1 for x in w2 if float(x) < float(w**2))
        ok &= negative == below
    check("negative eigenvalues of G - w^2 Mass = natural frequencies below w (w = 1/2 .. 3)", ok)


if __name__ == "__main__":
    galerkin()
    congruence_and_count()
    sys.exit(summary())
