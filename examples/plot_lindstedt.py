"""
Nonlinear frequency corrections
===============================

Thesis section 7.3: an inviscid sphere oscillating with amplitude eps in degree m has frequency
lambda = lambda_0 (1 + c eps^2). The coefficients c are exact rationals over pi (computed once
with sympy); the thesis's printed values for m = 2, 3, 4 (-0.7167, -0.8485, -1.0645) do not
survive the derivation. Entry point: :func:`spectralshell.lp_coefficient`.
"""

from matplotlib.figure import Figure

import spectralshell as ss

degrees = list(range(2, 9))
c = [ss.lp_coefficient(m) for m in degrees]
for m, value in zip(degrees, c):
    print(f"m = {m}: c = {value:+.6f}")

fig = Figure(figsize=(5.0, 3.5))
ax = fig.add_subplot()
ax.plot(degrees, c, "o-", label="spectralshell (exact)")
ax.plot([2, 3, 4], [-0.7167, -0.8485, -1.0645], "x", label="thesis, as printed")
ax.set_xlabel("degree m")
ax.set_ylabel("c in λ = λ₀ (1 + c ε²) (dimensionless)")
ax.legend()
fig.tight_layout()
fig.savefig("lindstedt.png", dpi=120)
