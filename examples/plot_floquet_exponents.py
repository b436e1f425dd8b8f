"""
Marginal amplitudes and Floquet exponents
=========================================

:func:`spectralshell.floquet` returns the marginal forcing amplitudes tau of the damped Mathieu
equation (kappa = 0.25, the principal subharmonic resonance, nu = 0.1);
:func:`spectralshell.exponents` returns the Floquet exponents gamma at a given tau. The largest
growth rate Re gamma crosses zero exactly at the subharmonic tau_min.
"""

import numpy as np
from matplotlib.figure import Figure

import spectralshell as ss

res = ss.floquet("mathieu", kappa=0.25, nu=0.1)
print(res.summary())
tau_min = res.subharmonic.tau_min

taus = np.linspace(0.0, 0.4, 41)
growth = [ss.exponents("mathieu", kappa=0.25, nu=0.1, tau=t).gamma.real.max() for t in taus]

fig = Figure(figsize=(5.0, 3.5))
ax = fig.add_subplot()
ax.plot(taus, growth, label="max Re γ")
ax.axhline(0.0, color="grey", lw=0.8)
ax.axvline(tau_min, color="tab:red", ls="--", label=f"subharmonic τ_min = {tau_min:.4f}")
ax.set_xlabel("τ, forcing amplitude (dimensionless)")
ax.set_ylabel("growth rate Re γ (per unit time)")
ax.legend()
fig.tight_layout()
fig.savefig("floquet_exponents.png", dpi=120)
