"""Benchmark: the cost of certifying an empty cochlea kind (issue 23) by the argument
principle's zero count, against M, next to the dense solve of the same truncation.

``marginal_tau(..., certify_empty=True)`` proves "no tau <= tau_max" of a viscous model by
:func:`spectralshell.solvers.contour.none_up_to` on the two-sided pencil of both truncations of
the final pair. For the cochlea (M x M blocks) one node of the count is one LAPACK LU per block:
(N + 1) LUs of order M. This script times, at one Fig 5.18 point (gerbil: L = 1.3 cm,
lambda_c = 3.7 /cm, Table 5.1 fluid) where a kind is empty below a cap:

* the count of one truncation (CPU time, nodes walked, seconds per node and per (N + 1) M^3);
* the dense solve of the same truncation (eig of the half-size product W, the baseline);

for M = 32, 64, 128, 256 at the point's N. One BLAS thread. CPU time (``time.process_time``)
is reported as well as wall time: the machine is shared.

Measured (2 cores under a load of 6-7, one BLAS thread): 17 nodes where the strip lies far
below the spectrum (cap 0.0707): M = 128 1.7 s CPU, M = 256 10.1 s (dense eig of W: 3.8 s and
26 s); 93-95 nodes where a zero lies near it (cap 0.24, which the dense path shows is not
empty: 0.2108 at M = 128): 9.6 s at M = 128. Per node 3.0e-9 (M = 128) and 2.2e-9 (M = 256) s
per (N + 1) M^3: solvers/cost.py's COUNT_SECONDS. Since (issue 25, session 22; main's code
and this one alternately, load ~3): cap 0.24 declined after 1 evaluation by the sign of g at
the rectangle's corner (contour._odd_below), M = 64 1.6-1.8 s -> 0.02-0.03 s, M = 128
8.3-8.7 s -> 0.14-0.16 s CPU; a node 25-35 % cheaper (contour.block_log_det: blocks below
M = 128 inverted, chained couplings), e.g. the cap 0.24 count at M = 32 (18 nodes, proved)
0.07-0.08 s -> 0.04-0.05 s. Nodes are counted as block_log_det evaluations.

On a whole sweep (the gerbil cochlea, frequency 2, 5, 20 kHz x sigma 1.5e8, 5e8, tau <= 1/2,
over_kinds = 'minimum', M refined to 128-256, serial): 188 s CPU before the certificate, 248 s
with it (+32 %: the capped kinds' empty answers counted at each M), the same values and M.
The viscous sphere's map (Fig 6.13 setting, 12 x 12 x m 2..6 x 2 kinds, 1234 of 1440 points
empty): 1.20 s CPU before, 1.21 s with it, the same values (its contour path proves its empty
points itself).

Run: python validation/bench_certify_cochlea.py [--json-rows] [--max-m 256]   (--quick: M = 32)
"""

from __future__ import annotations

import math
import sys
import time

from threadpoolctl import threadpool_limits

from _bench import quick, row
from spectralshell.models.registry import hill_system
from spectralshell.params.physical import cochlea_params
from spectralshell.params.registry import make_params
from spectralshell.solvers import contour
from spectralshell.solvers.marginal import Pencils, truncation_taus

#: The Fig 5.18 gerbil point: 5 kHz, sigma = 1.5e8; tau_min: harmonic 0.248, subharmonic 0.071
#: (M = 32), so that a minimum map asks the harmonic kind for "none below 0.0707".
POINT = {"rho": 1.0, "mu": 0.02, "length": 1.3, "lambda_c": 3.7, "sigma": 1.5e8,
         "omega": 2 * math.pi * 5000.0}
KIND, N = "harmonic", 15
#: The caps: the subharmonic tau_min (what a minimum map asks), and just below the harmonic
#: tau_min 0.2477 itself (a zero close to the contour: more nodes).
CAPS = (0.0707, 0.24)


def counted(hill, tau_max):
    """(proved, nodes, CPU s, wall s) of none_up_to, its nodes (block_log_det evaluations)
    counted."""
    nodes = [0]
    original = contour.block_log_det

    def spy(*args):
        nodes[0] += 1
        return original(*args)

    contour.block_log_det = spy
    try:
        c0, w0 = time.process_time(), time.perf_counter()
        proved = contour.none_up_to(hill, tau_max)
        return proved, nodes[0], time.process_time() - c0, time.perf_counter() - w0
    finally:
        contour.block_log_det = original


def main(max_m: int) -> None:
    values = cochlea_params(dict(POINT))
    for m in (32, 64, 128, 256):
        if m > max_m:
            break
        system = hill_system(make_params("cochlea", {**values, "n_spatial": m}))
        pencils = Pencils(system, KIND)
        hill = pencils.pencil(N, "two-sided")
        with threadpool_limits(1):
            c0, w0 = time.process_time(), time.perf_counter()
            dense = truncation_taus(system, KIND, N, method="dense", pencils=pencils)
            dense_cpu, dense_wall = time.process_time() - c0, time.perf_counter() - w0
        for cap in CAPS:
            with threadpool_limits(1):
                proved, nodes, cpu, wall = counted(hill, cap)
            below = dense.tau[dense.tau <= cap]
            unit = cpu / max(nodes, 1) / ((N + 1) * m ** 3)
            print(f"M = {m:4d}, N = {N}, cap {cap}: count {'proved' if proved else 'declined'} "
                  f"in {nodes} nodes, {cpu:.2f} s CPU ({wall:.2f} s wall), "
                  f"{cpu / max(nodes, 1) * 1e3:.1f} ms per node = {unit:.2e} s per (N + 1) M^3; "
                  f"dense eig of W {dense_cpu:.2f} s CPU ({dense_wall:.2f} s wall), "
                  f"tau <= cap: {below.tolist()}")
            row(task=f"zero count, cochlea {KIND} N = {N}, M = {m} (none <= {cap})",
                package_s=wall, baseline="dense eig of W (same truncation)",
                baseline_s=dense_wall, error=None,
                note=f"{nodes} nodes; CPU {cpu:.2f} s vs {dense_cpu:.2f} s; dense finds "
                     f"{below.size} tau <= cap")


if __name__ == "__main__":
    limit = int(sys.argv[sys.argv.index("--max-m") + 1]) if "--max-m" in sys.argv else 256
    limit = min(limit, 32) if quick() else limit  # a smoke run (validation/_bench.py)
    main(limit)
