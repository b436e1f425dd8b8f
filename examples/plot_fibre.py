"""
The immersed circular fibre
===========================

The family of thesis Figs 4.1-4.4 (chapter 4): Ince-Strutt diagram of the fibre's wavenumber
m = 3 at nu = 2e-4, and the marginal tau of one point with :func:`spectralshell.floquet`.
"""

import spectralshell as ss
from spectralshell.plots import ince_strutt

point = ss.floquet("fibre", m=3, kappa=0.02, nu=2e-4)
print(point.summary())

diagram = ss.tongues("fibre", m=3, nu=2e-4, kappa="0.005:0.1:40", tau_max=1.0, workers=1)
ince_strutt.save([diagram], "fibre_tongues.png", title="fibre, m = 3, ν = 2e-4")
