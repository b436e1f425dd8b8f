"""
Ince-Strutt diagrams of the Mathieu equation
============================================

The family of thesis Figs 2.2-2.3: the marginal forcing amplitudes tau of
u'' + nu u' + kappa (1 + 2 tau sin t) u = 0 over kappa, undamped (nu = 0) and damped (nu = 0.1).
Fingers open at sqrt(kappa) = k/2; damping lifts them off the axis. Entry point:
:func:`spectralshell.tongues`.
"""

import spectralshell as ss
from spectralshell.plots import ince_strutt

diagrams = [ss.tongues("mathieu", kappa="0.01:3:120", nu=nu, tau_max=1.0, workers=1)
            for nu in (0.0, 0.1)]
for diagram in diagrams:
    for tip in diagram.tips:  # finger minima, each with its error estimate
        print(f"nu = {diagram.params['nu']:g}  {tip.kind:11s}  kappa = {tip.kappa:.6f}  "
              f"tau = {tip.tau:.6f}")

ince_strutt.save(diagrams, "mathieu_tongues.png")
