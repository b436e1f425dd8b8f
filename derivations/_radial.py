"""Radial helpers shared by derivations/sphere_radial.py and derivations/fibre_radial.py: jumps
across r = 1, and elimination of higher derivatives with a second-order ODE."""

from __future__ import annotations

import sympy as sp


def interface_jumps(f, r, prefix: str):
    """(jump, continuity, jets) for a sympy function f(r) with one-sided jets at r = 1.

    ``jets[side]`` ('i' inside, 'o' outside) are symbols for f, f', f'', f''' at r = 1 on that
    side; ``jump(expr)`` is expr(1+) - expr(1-) with the jets put in for f and its derivatives;
    ``continuity`` substitutes [[f]] = [[f']] = 0 (outside values by inside ones).
    """
    jets = {side: sp.symbols(" ".join(f"{prefix}{k}{side}" for k in range(4))) for side in "io"}

    def at1(expr, side):
        e = expr
        for k in (3, 2, 1):
            e = e.subs(sp.Derivative(f, (r, k)), jets[side][k])
        return e.subs(f, jets[side][0]).subs(r, 1)

    def jump(expr):
        return at1(expr, "o") - at1(expr, "i")

    continuity = {jets["o"][0]: jets["i"][0], jets["o"][1]: jets["i"][1]}
    return jump, continuity, jets


def ode_reduce(expr, f, r, second):
    """expr with f'', f''', f'''' of the function f(r) replaced using f'' = ``second`` (an
    expression in r, f and f'), then simplified."""
    for _ in range(3):
        expr = expr.subs(sp.Derivative(f, (r, 4)), sp.diff(second, r, 2))
        expr = expr.subs(sp.Derivative(f, (r, 3)), sp.diff(second, r))
        expr = expr.subs(sp.Derivative(f, (r, 2)), second)
    return sp.simplify(expr)
