"""
Which degrees resonate
======================

:func:`spectralshell.stability` answers, per degree m of the sphere, whether forcing at amplitude
tau makes it unstable and through which kind (harmonic or subharmonic); the panel draws the
marginal tau of each degree (from :func:`spectralshell.floquet`) with those unstable at tau
highlighted (the layout of thesis Fig 6.6).
"""

import spectralshell as ss
from spectralshell.plots import degree_stability

params = {"kappa": 0.02, "nu": 0.006}
verdict = ss.stability("sphere", tau=0.45, m="2:6", **params)
print(verdict.summary())

by_degree = {m: ss.floquet("sphere", m=m, **params) for m in range(2, 7)}
degree_stability.save([("sphere: ν = 0.006, κ = 0.02", by_degree, verdict)], "stability.png")
