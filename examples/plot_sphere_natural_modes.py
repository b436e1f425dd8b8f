"""
Natural modes of the sphere
===========================

The family of thesis Fig 7.1: the least-damped natural mode gamma (tau = 0, X ~ exp(gamma t)) of
the immersed sphere against zeta = nu / sqrt(kappa), for degrees m = 2 and 3. As zeta -> 0 the
frequency tends to the inviscid lambda_0. Entry point: :func:`spectralshell.natural_modes`.
"""

import numpy as np

import spectralshell as ss
from spectralshell.plots import natural_modes

zeta = np.logspace(-3, 1, 25)
by_degree = {m: [ss.natural_modes("sphere", m=m, zeta=z) for z in zeta] for m in (2, 3)}
print(by_degree[2][0].summary())

# the inviscid frequency lambda_0 = sqrt(kappa m (m + 1) (m - 1) (m + 2) / (2m + 1)), kappa = 1
inviscid = {m: float(np.sqrt(m * (m + 1) * (m - 1) * (m + 2) / (2 * m + 1))) for m in by_degree}
natural_modes.save(zeta, by_degree, inviscid, "sphere_natural_modes.png")
