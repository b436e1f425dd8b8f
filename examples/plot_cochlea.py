"""
The cochlea: natural modes and a pure-tone response
===================================================

The family of thesis chapter 5 (Table 5.1 parameters, cgs, omega in rad/s): the least-damped
natural modes of the basilar membrane (section 5.4), and the envelope of its passive response to
a pure tone, whose peak moves towards the base as the frequency rises (section 5.5). Entry
points: :func:`spectralshell.natural_modes` and :func:`spectralshell.response`.
"""

import spectralshell as ss
from spectralshell.plots import cochlea

modes = ss.natural_modes("cochlea", physical={"sigma": 6e5}, n_spatial=16, count=3)  # s^-1
print(modes.summary())

omegas = (400.0, 800.0, 1600.0)
tones = [ss.response("cochlea", omega=omega) for omega in omegas]
for omega, tone in zip(omegas, tones):
    print(f"omega = {omega:g} rad/s: envelope peak {tone.to_cm(tone.peak_x):.4f} cm from the "
          f"base (+- {tone.to_cm(tone.peak_error):.1e} cm)")
cochlea.save_responses([("pure tones, ω = 400, 800, 1600 rad/s", tones)], "cochlea_tones.png")
