"""
The heart: a minimum-tau map in physical units
==============================================

The family of thesis Fig 6.13 on a coarse grid: the smallest forcing amplitude tau <= 1/2 that
makes an atrium-sized sphere (R = 2 cm, blood: rho = 1 g/cm^3, mu = 0.04 g/(cm s)) resonate in
some degree m = 2..4, against the membrane stiffness sigma (dyn/cm) and the beat rate (beats per
minute). Entry point: :func:`spectralshell.tau_map` (a sweep run in memory).
"""

import spectralshell as ss
from spectralshell.plots import tau_map
from spectralshell.results.maps import minimum_map

ds = ss.tau_map("sphere", x=("sigma", "1e3:2e4:8"), y=("bpm", "50:650:8"), m="2:4",
                physical={"rho": 1.0, "mu": 0.04, "radius": 2.0}, workers=1)
smallest = minimum_map(ds, "sigma", "bpm")  # the smallest tau over m and kind, per cell
print(smallest)

tau_map.save(ds, "sphere_tau_map.png",
             boxes=[((1e3, 2e4), (60.0, 100.0), "healthy heart", "tab:blue")])
