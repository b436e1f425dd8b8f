"""
Time stepping the sphere
========================

The family of thesis Figs 6.7-6.11 (simulations of chapter 6): a sphere at kappa = 0.06,
nu = 0.002 forced at tau = 0.25, started in the degree-2 mode; the fitted growth rate of the
mode is positive, as the Floquet analysis of the same point predicts (degree 2 unstable, through
the subharmonic kind: the fitted frequency is 1/2). Entry points: :func:`spectralshell.simulate`
and :func:`spectralshell.stability`.
"""

import spectralshell as ss
from spectralshell.plots import trajectory

params = {"kappa": 0.06, "nu": 0.002, "tau": 0.25}
run = ss.simulate({"params": params, "initial": {"shape": "2:0"}, "simulate": {"t_end": 60}})
print(run.summary())

print(ss.stability("sphere", m=2, **params).summary())
trajectory.save_amplitudes(run, "sphere_simulation.png")
