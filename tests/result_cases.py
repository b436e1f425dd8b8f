"""A cheap real result of every type, and the command line that prints its summary (shared by
the tests of the result objects: tests/test_results_base.py, tests/test_results_notebook.py)."""

import spectralshell as ss

SIMULATION = {"params": {"kappa": 0.06, "nu": 0.002, "tau": 0.0}, "initial": {"shape": "2:0"},
              "simulate": {"t_end": 20.0}}

#: name -> (a cheap real result, the command line that prints its summary)
CASES = {
    "floquet": (lambda: ss.floquet("mathieu", kappa=0.3, nu=0.1),
                "floquet mathieu --kappa 0.3 --nu 0.1"),
    "floquet-none-below": (lambda: ss.floquet("mathieu", kappa=0.3, nu=0.1, tau_max=0.01),
                           "floquet mathieu --kappa 0.3 --nu 0.1 --tau-max 0.01"),
    "spatial-floquet": (lambda: ss.floquet("cochlea", omega=1000, alpha=0, n_spatial=4),
                        "floquet cochlea --omega 1000 --alpha 0 --n-spatial 4"),
    "tongues": (lambda: ss.tongues("mathieu", kappa="0:2:21", nu=0.1, workers=1),
                "tongues mathieu --kappa 0:2:21 --nu 0.1 --workers 1"),
    "exponents": (lambda: ss.exponents("mathieu", kappa=1, nu=0.1, tau=0.3),
                  "exponents mathieu --kappa 1 --nu 0.1 --tau 0.3"),
    "stability": (lambda: ss.stability("sphere", tau=0.45, m="2:4", kappa=0.02, nu=0.006),
                  "stability sphere --tau 0.45 --m 2:4 --kappa 0.02 --nu 0.006"),
    "modes": (lambda: ss.natural_modes("sphere", m=2, kappa=1, nu=0.01),
              "modes sphere --m 2 --kappa 1 --nu 0.01"),
    "modes-digits": (lambda: ss.natural_modes("sphere", m=2, kappa=1, nu=0.01, count=2,
                                              precision=30),
                     "modes sphere --m 2 --kappa 1 --nu 0.01 --count 2 --precision 30"),
    "modes-continued": (lambda: ss.natural_modes("cochlea", zeta=1e-2, alpha=1.56, n_spatial=6),
                        "modes cochlea --zeta 1e-2 --alpha 1.56 --n-spatial 6"),
    "response": (lambda: ss.response("cochlea", omega=800, n_spatial=32),
                 "response cochlea --omega 800 --n-spatial 32"),
    "trajectory": (lambda: ss.simulate(SIMULATION),
                   "simulate sphere --m 2 --kappa 0.06 --nu 0.002 --t-end 20"),
    "stepped-run": (lambda: ss.simulate("fibre", m=3, kappa=0.02, nu=2e-4, tau=0.3, t_end=70,
                                        n_inner=24, n_outer=32),
                    "simulate fibre --m 3 --kappa 0.02 --nu 2e-4 --tau 0.3 --t-end 70 "
                    "--n-inner 24 --n-outer 32"),
}
