"""Marginal forcing amplitudes tau of a Hill pencil A v = tau B v, and their convergence in N.

Structured path
---------------
A is block diagonal, so T = A^{-1} B costs O(N b^3) and its eigenvalues are mu = 1/tau. When B
couples only Fourier indices of opposite parity (``HillMatrices.bipartite``: no self-coupling),
T = [[0, X], [Y, 0]] in an even/odd ordering and mu^2 are the eigenvalues of the half-size
product W = X Y (:mod:`spectralshell.solvers.half_product`). Real tau correspond to real
positive mu^2 (tau and -tau, a time shift by pi, always come together). Two ways to solve a
truncation:

* ``method = "dense"`` (the reference): every eigenvalue of W; reports every real tau of the
  truncation (``method = "structured"`` in the result). The form, and real mu^2, by kind:

  - harmonic of a block model (b > 1): the real form is bipartite, so W is real, solved by
    LAPACK ?geev in O((N b)^3), and a real tau is an exactly real eigenvalue of W (LAPACK
    returns zero imaginary part for it): classification is exact.
  - subharmonic: the real form has an n = 0 self-coupling and is not bipartite; the two-sided
    form is. Its W is complex with real-or-conjugate-pair spectrum (the reality condition (2.8)
    makes W = Z conj(Z)), and mu^2 counts as real when |Im mu^2| <= 1e-9 |mu^2|. LAPACK ?geev,
    O((N b)^3), for b > 1.
  - a scalar model (b = 1: Mathieu, and the sphere and fibre at nu = 0), both kinds: the
    two-sided form, whose W is tridiagonal. Its eigenvalues come from the compiled O(N^2)
    kernel of :mod:`spectralshell.solvers.tridiagonal` (LAPACK when the kernel declines,
    ~0.1 % of Mathieu cases), and are classified as for the subharmonic above. At N = 40 this
    solves a truncation ~22x faster than QZ of the real-form pencil, against ~8x with ?geev
    on the real W (validation/bench_floquet.py).

* ``method = "krylov"``: the eigenvalues of largest modulus of W (harmonic) or T (subharmonic)
  of the real form by Arnoldi iteration, in real arithmetic, so that real tau are exactly real
  for both kinds (:func:`~spectralshell.solvers.half_product.smallest_taus`); for the
  subharmonic kind of blocks larger than 2 x 2, of the complex W of the two-sided form instead,
  real mu^2 classified as on the dense subharmonic path (:func:`krylov_form`): O(N b^3) once,
  O(N b^2) per step. It reports the smallest real tau with a completeness radius
  (``MarginalTau.complete_to``): every real tau up to it is listed. When the Arnoldi space
  would need more than a third of the operator (a short truncation, or many eigenvalues with
  |tau| below the wanted ones) or A is ill conditioned, the truncation is solved by the dense
  path instead, and the Arnoldi work is lost.
  The run gives up past ARNOLDI_WORK_FRACTION (= 1) of the dense solve's estimated work
  (:func:`krylov_budget`, counted in operator products):
  where the wanted eigenvalues cluster ARPACK otherwise restarts up to 10 n times (on one
  Fig 5.18 point, 290 s of its 392 s; 148 s in all with the cap).
  With a finite tau_max that run is cut to one Arnoldi step (k = 8 eigenvalues of W, 16 of T),
  and if it does not reach min(tau_min, tau_max) the rest of [0, tau_max] is covered by
  shift-invert Arnoldi at real shifts (:mod:`spectralshell.solvers.shift_invert`, result
  ``method = "shift-invert"``): the eigenvalues near the real interval only, each disk
  certified complete, up to the smallest real tau. Within one solve each truncation starts from
  the previous one's shifts (or its tau_min, or the caller's ``hint``). The cover gives up
  (dense path) past a work budget of ~0.6 of the dense cost. Measured in
  validation/bench_hill_large.py: the cochlea at low forcing frequency, where the
  smallest-|tau| run gives up, 5-10x faster than dense eig at block size 128.
* ``method = "smallest"`` (the maps' sweeps, which store tau_min only): for models with 2 x 2
  blocks (the viscous sphere and fibre) and a finite tau_max, only the smallest real
  tau <= tau_max of the two-sided form, with the argument principle's count as the certificate
  that no smaller one exists (:mod:`spectralshell.solvers.contour`, result
  ``method = "contour"``, ``complete_to`` just above tau_min, or tau_max when there is none):
  O(N) per point of the contour against O(N^3) for the eig of W. Where the count does not
  certify the answer (a complex eigenvalue close to the real axis below it, two real tau
  closer than 1e-3 relative, the node budget), and for other models, as ``"auto"``.
* blocks larger than 2 x 2 (the cochlea), ``"auto"`` and ``"smallest"`` with a finite
  tau_max: the truncation N >= COUNT_MIN_N after one with no tau <= tau_max is first tried
  by the argument principle's zero count alone
  (:func:`~spectralshell.solvers.contour.none_up_to`, result ``method = "contour"``,
  ``complete_to`` = tau_max): where it proves a thin strip around [0, tau_max^2] free of
  eigenvalues, the Krylov / shift-invert work is skipped; else the
  truncation is solved as below. Measured on the Fig 5.18 cell that climbs furthest (gerbil,
  116.9 Hz, sigma = 1.16e9: no tau <= 1/2, N = 141, M = 32; serial, one BLAS thread, CPU time,
  2 cores under a load of 5-11): 56.2 s before, 52.3 s with the count, which replaced the four
  N = 141 truncations (M = 16 and 32, both kinds; 165 nodes each, 0.03 s CPU per node), the
  same answer. Counting also after a truncation whose tau_min lies within 1 % of tau_max (the
  N = 94 ones here) cost 88.8 s: most such counts meet the tau and are lost. (These counts
  walked the closed rectangle; since the merge with the half-contour kernel they walk its upper
  half, about half the nodes: 106 and 92 instead of 211 and 183 at N = 141, M = 32,
  harmonic and subharmonic; the cell's times were not measured again.) Cells whose
  kinds converge below COUNT_MIN_N are unchanged (3 of the seeded sample: 7.6 / 3.3 / 10.3 s
  before, 8.1 / 3.1 / 9.1 s after, within the load's noise).
* ``method = "auto"`` (default): Krylov for truncations with (N + 1) b >= KRYLOV_MIN_ORDER
  (= 600; (N + 1) b is the order of W), dense below; for blocks larger than 2 x 2 from
  BLOCK_KRYLOV_MIN_ORDER (= 250) until a truncation of the solve falls back to dense
  (:func:`krylov_min_order`). With that, the subharmonic Arnoldi on the two-sided W
  (:func:`krylov_form`) and the coarser M's tau_min as the hint
  (:mod:`spectralshell.solvers.spatial_refinement`), measured on 20 cells of the seeded Fig 5.18
  sample (validation/bench_sweep.py, every 5th; each cell alone, the previous package and this
  one alternately, one BLAS thread, CPU time, 2 cores under a load of 7-15): 64.1 s before,
  59.2 s after in all; the cells that end at M <= 64 without a shift-invert cover 2-4x faster
  (0.5 -> 0.15 s), those that need M = 256, 512 1.0-1.3x (their cost is the block inverses of
  A and products with them, memory-bound at M >= 256), the crowded low-frequency cell (human,
  63.6 Hz, sigma = 1.85e9: real tau crowding towards 1/2, shift-invert covers of 10-20 disks)
  28.9 s before, 30.1 s after; the same tau_min (to 2.4e-15), error estimates (to 5e-15),
  truncation pairs and M pairs. Measured in
  validation/bench_hill_large.py (one BLAS thread): where Arnoldi succeeds it is about as fast
  as dense eig of W at order ~200 (sphere, N = 80) and 5-10x faster at ~400-600 (M = 20, 30
  coupled oscillators); but the sphere at low beat rate (Fig 6.13, order up to ~350, with
  70-80 eigenvalues inside |tau| < 1/2 and none real) makes Arnoldi give up, at 4-10x the
  dense cost. The threshold keeps Mathieu (b = 1) and sphere and fibre (b = 2) truncations
  dense up to N = 298 and sends block models (b >~ 30) to Arnoldi. For b = 2 with
  tau_max = 1/2 the crossover was measured on Fig 6.13 cells (smallest-|tau| run, then the
  shift-invert cover, work limit lifted, against dense eig of W): the Krylov path took
  0.5-10x (mostly 1.5-3x) the dense time at N = 120-250 and 0.25-2x at N = 350 (the map
  needs N <= 175), even with its block elimination replaced by a band LU (35x cheaper
  products; ARPACK's own work then dominates), so the threshold stands for b = 2.

Cost of the empty answers' proofs (issue 25). Since the maps' empty answers are proved or
marked (``certify_empty``, issue 23), the same 20 cells of the seeded Fig 5.18 sample cost 6x
the 59.2 s above: the zero count of the kind that has nothing below the other kind's tau_min
(17 nodes of a block LU sweep each, ~96 K M^3 complex flops, at both truncations of every M)
took ~85 % of their time (cProfile), 19.6 s of the 25.8 s CPU of one cell that ends at
M = 256 (human, 8.35 kHz, sigma = 5.7e8).
Two changes, each proving the same claim: (1) a disk free of eigenvalues from the block norms
of W (:func:`~spectralshell.solvers.half_product.free_radius`, tried by
:func:`~spectralshell.solvers.contour.none_up_to` before its count; ~3.7 K M^3 flops) proves
the strip empty where every eigenvalue lies far beyond the cap: on those cells the nearest
|tau| is 4-14 times the cap and the bound's radius 2-2.4 times it at M = 64..256, so no count
is walked; (2) a refinement in M proves only the finest M's empty answers, the ones it
returns (:mod:`spectralshell.solvers.spatial_refinement`), so the counts that must still run
(real tau crowding towards 1/2, where the bound fails) are not paid at coarser M. Measured on
those 20 cells (every 5th of the seeded 100, each alone in its own process by
``run_sweep(executor="serial")`` as validation/bench_sweep.py does, one BLAS thread, CPU time,
the code before and after alternately per cell, 2 cores under a load of 9-12): 360.8 s before,
91.8 s after (3.9x); every cell's tau_min, error estimate, complete_to, has_tau, n_temporal
and n_spatial bitwise equal. Per cell: the six ending at M = 256 21.4-23.6 s -> 2.6-3.3 s,
the one at M = 512 (gerbil, 35.5 kHz, sigma = 1.54e8) 147.7 -> 12.8 s, the crowded one
(human, 63.6 Hz, sigma = 1.85e9: its subharmonic empty below the harmonic 0.4943 is proved
by counts of 133-156 nodes at M = 64) 47.0 -> 39.5 s, the rest within the load's noise.
Projected as mean x 80 000 cells / 16 workers: 25 h before, 6.4 h after for both panels; the
crowded cell is now 43 % of the sample (cProfile: its counts at the finest M ~46 %, the
shift-invert covers ~42 %, of which their block solves ~23 % and ARPACK's own work ~10 %, the
dense eig ~8 %), the M = 256, 512 cells' Krylov runs on W, block inverses and the disk's bound
(~0.75 s at M = 256) the next share. Tried and dropped: the shift-invert solves with
S_j^{-1} U_j and S_j^{-1} L_j kept from the factorisation (3 block products per block instead
of 4, the same tau_min bitwise): 44.2 s against 38.0 and 40.0 s on the crowded cell, no gain
measurable under that load.
Profile of the crowded cell since (cProfile, CPU time, one BLAS thread, 57.1 s under the
profiler): the zero counts at M = 64 (789 nodes of the block LU sweep, 0.031 s each, in the
empty subharmonic's proof and in truncation_taus) 24.7 s = 43 %, flop-bound (~5 M^3 complex
multiply-adds per block and node: LU, the solve with [U, S'], the products with L);
the shift-invert covers 23.9 s = 42 % (140 disks; 17 086 solves 11.1 s, ARPACK's own work 7.5 s,
the factorisations 2.2 s); the dense eig of W 5.8 s = 10 %. The solves were per-block numpy
calls; they now run in the compiled kernel (:mod:`~spectralshell.solvers.shift_invert`,
2-9x per solve). Measured on the 20 cells above plus human 59.9 Hz, sigma = 1.41e9 (each
alone, this package's code and the previous one alternately per cell, one BLAS thread, CPU
time, 2 cores under a load of ~6): the 20 cells 125.6 s before, 105.9 s after (1.19x; the
crowded cell 66.8 -> 46.0 s and, measured again, 59.0 -> 44.2 s; 59.9 Hz 7.0 -> 6.1 s; the
cells without covers unchanged within the load's +-30 % noise); every returned variable of
every cell bitwise equal. After it (profiled again, under a heavier load): the counts 48 %, the
covers 35 % (their solves 11 %, ARPACK's own work 14 %), the dense eig 12 %.
The shift-invert cover's work model, refitted to the compiled solves
(:mod:`~spectralshell.solvers.shift_invert`, "Cover"), sends the truncations where the cover is
now the cheaper path to it instead of dense eig: on the crowded cell the subharmonic kind at
M = 16 and the harmonic at M = 32 (dense eig 6.9 -> 0.6 s of the cell's CPU; the Krylov run's
budget, :func:`krylov_budget`, is unchanged). Measured (each cell alone in its own process as
validation/bench_sweep.py solves it, one BLAS thread, CPU time, the code before (47c4bd3) and
this one alternately, 2 cores under a load of 3-5): the crowded cell 52.6, 51.7 s before,
44.4, 51.3 s after; gerbil 175.4 Hz, sigma = 1.69e9 5.0 -> 3.5 s; the 20 cells (best of the
crowded cell's two) 111.3 s before, 100.5 s after, the 19 others 59.6 -> 56.1 s (mostly
within the load's noise). Values: 16 of the 20 cells bitwise equal;
in the other four the truncations that changed path move tau_min by at most 5.6e-16 (error
estimates 1.6e-15), each within 3.4e-15 of dense eig at its (M, N), the same n_temporal,
n_spatial and has_tau.

Expected empty answers. A refinement in M solves the kind that does not attain the minimum
with tau_max lowered to the other kind's tau_min (:mod:`spectralshell.solvers.spatial_refinement`),
and where that kind had nothing below its cap at the coarser M it usually has nothing at the
finer one either. ``marginal_tau(..., expect_empty=True)`` then tries each truncation first by
the zero count (:func:`~spectralshell.solvers.contour.none_up_to`: its disk bound, then the
count; :func:`truncation_taus`' ``expect_empty``; the next truncation only if this one was so
proved, or was found empty by its solve without a failed count): where it succeeds the
truncation is proved empty (method ``"contour"``) without the Krylov solve or the
shift-invert cover, and an answer whose two truncations were both so proved
carries ``empty_proved``, so that its later certification (:func:`certify_empty_answer`) costs
nothing. Where the count fails the truncation is solved as before and marked
``count_failed``, and so is the answer whose pair holds it: its certification at the same
tau_max (the refinement's, at the kind's cap) fails at once instead of walking the same
deterministic count again. The values do not depend on any of it: a truncation the count
proves empty is empty on every path.
Measured on the seeded 100-cell Fig 5.18 sample (validation/bench_sweep.py's points, each
alone by ``run_sweep(executor="serial")``, one BLAS thread, CPU time, the code before and
after side by side on the 2 cores), every stored variable of every cell bitwise equal each
time: with the disk bound alone (the count not walked), 403.0 s before, 347.4 s
after (1.16x); again with the pairs of equal W blocks of
:func:`~spectralshell.solvers.half_product.free_radius` formed once, 391.3 s before, 351.0 s
after (1.11x; single cells vary by up to +-40 % between such runs); with the full count and
the record of failed counts, 358.7 s before, 330.6 s after (1.085x): human, 313.8 Hz,
sigma = 7.08e8 (pair M = 64, 128; its subharmonic empty below the harmonic 0.4216) 13.9 ->
10.5 s, its M = 128 subharmonic solve and proof 3.5 + 4.7 s -> 5.5 s. Where the counts go
then (the same sample, CPU time): counts the solves walked first 114 s, of which 10.5 s at an
M below the final pair (where the proof is not asked, 3.9 s of it failed counts), and
certifications of answers not so solved 49 s. A full count tried without the record of
failures (a failed count walked twice) made cells slower, e.g. gerbil 192.7 Hz.
The disk bounds of a pair (N, N') share their block solves (:meth:`Pencils.coupled_solves`:
N's blocks are N''s, solved once): the same sample 323.2 s before, 319.2 s after, the cells
ending at M = 256 66.2 -> 60.1 s, every stored variable bitwise equal. Tried and dropped: the
count's rectangle started at 0.9 times the disk's reach instead of at 0 (the part inside the
disk holds no zero): 1.0-1.2x slower on three crowded cells (human 313.8 Hz, 54.7 Hz; gerbil
631.2 Hz), the same answers; and counting every truncation of an expected-empty solve, not
only the first and those after a proved one: 294.9 s before, 295.5 s after (the crowded cell,
human 63.6 Hz, 36.6 -> 28.6 s, whose first truncation's count fails and the next two are proved
only at the certification; the cells ending at M = 256, 57.8 -> 64.5 s, where the counts after
a failed one fail as well).
The middle way kept: the truncation after one that its solve found empty (a shift-invert cover
or Krylov run with nothing below the cap, no count walked there or none failed) is counted
first too. Such an empty answer, at the pair a refinement in M returns, is proved by that very
count afterwards (:func:`certify_empty_answer`), so the count replaces the cover instead of
following it; after a truncation with a tau below the cap or a failed count nothing changes
(tests/test_free_radius.py::test_expected_empty_counts_after_an_empty_truncation). The seeded
sample, the code before and this one side by side (one process each, 2 cores, CPU time):
169.4 -> 163.5 s (1.036x), every stored variable of every cell bitwise equal; the crowded cell
(human, 63.6 Hz, sigma = 1.85e9) 20.7 -> 17.7 s, whose subharmonic at M = 32 and 64 is empty
at N = 34 and 51 after a tau at N = 23: the N = 51 covers (0.5 and 2.2 s) are gone, their
counts moved from the certification into the solve (issue 25).
The disk bound of a mirrored two-sided pencil (A_{K-1-k} = conj(A_k):
:attr:`~spectralshell.discretise.hill.HillMatrices.mirrored`) solves the first half of its
blocks and, with K odd (harmonic), forms the first half of W's blocks, the others being their
conjugate reflections; the two-sided diagonal is assembled C-contiguous (the cochlea's came as a
strided stack that every block operation copied); the pencils' structure checks run once per
largest truncation, block by block. The seeded sample, the code before (7bebe93) and after
side by side (one process each, 2 cores, one BLAS thread, CPU time, each code on both halves):
86.8 -> 71.4 s (1.22x), every point's tau_min, error estimate and M bitwise equal (issue 25).

What an answer proves
---------------------
Each truncation states ``complete_to``: its list of real tau is complete up to it (for the
dense path 1/sqrt of the floor below which mu^2 counts as zero, inf for QZ, the certified radius
for Krylov and shift-invert). A pair of successive truncations is accepted
(:func:`converged_pair`) only if it also certifies its answer (:func:`certified_bound`): every
non-real eigenvalue of the larger truncation below the claimed amplitude sits farther from the
real axis than SEPARATION times its change from the smaller one, so no real tau can hide among
them (for models whose D(s) is a matrix polynomial; see :func:`certified_bound` for the
others). An empty answer therefore means "no real tau <= tau_max", and with tau_max = inf
it is not given at all (the truncation is raised to find a tau, or a ConvergenceError states the
amplitude up to which none exists). For the viscous models, whose drifting spectra this test
cannot use, ``marginal_tau(..., certify_empty=True)`` (what ``floquet`` asks) proves an empty
answer by the zero count at both truncations or refuses it (issue 23). The spectra test
catches the strongly damped Mathieu equation (nu >~ 20), whose periodic solutions vary by
~exp(pi nu / 2) within a cycle: no double-precision Hill truncation resolves them, and
before this test the solver answered "no tau" for nu = 30
where a time-stepped monodromy matrix has marginal tau 1923.87 (harmonic) and 2030.16
(subharmonic; tests/test_hostile_oracle.py). A bound on the neglected Fourier tail
(2 tau ||D(s_k)^{-1} G|| < 1 beyond N) was tried as a resolution test and dropped: the sphere's
barely damped Psi row has a resonance near k = 170 at m = 6, kappa = 1.4, nu = 2.4e-4, which
holds that bound below 0.2 up to N = 184 while the subharmonic tau_min = 0.52608108 has
settled at N = 82.

Truncations of one solve share their pencils and block inverses (:class:`Pencils`): a smaller
truncation is cut out of a larger one, a larger one reuses the inverses of the blocks it shares
(blocks of size >= 32). :func:`marginal_tau` assembles the second truncation first (every solve
needs both) and cuts the first out of it. The dense eig calls LAPACK ?gebal/?geev directly
(the same calls and workspace as ``scipy.linalg.matrix_balance``/``eigvals``, without their
per-call overhead: the same numbers), the routines and the workspace size looked up once per
dtype and order of W; a W of order 100..599 is solved on one BLAS thread (ONE_THREAD_ORDERS),
and every solve of a block model (b > 2) runs on one (:func:`on_block_threads`).

Infinite tau (mu = 0: B is singular, and the harmonic Im u_0 slot is a zero row) are removed as
mu^2 <= 64 eps ||W_bal||_F, W_bal the diagonally balanced W that the eigen-solver works on (for
the tridiagonal kernel its symmetric form, ||W_bal||_F^2 = sum |d_i|^2 + 2 sum |p_i|): such
eigenvalues are indistinguishable from zero. Spurious, truncation-made eigenvalues are removed by
requiring each reported tau to reappear at the previous truncation.

If a diagonal block of A is singular or ill conditioned, in itself (1-norm condition > 1e8) or
against the coupling (||A_k^{-1}|| ||B_k|| > 1e8: some tau ~< 1e-8, e.g. undamped Mathieu at
sqrt(kappa) = k/2, where tau = 0 is an eigenvalue), squaring would lose the small tau and the
solver falls back to QZ on the real form (``method = "qz"``), which handles singular A and B.
A singular A makes tau = 0 an exact eigenvalue, often defective (two fingers leave the axis
together), which rounding spreads by ~eps^(1/2); such a cluster within ZERO_CLUSTER = 1e-6 of 0
is reported as one tau = 0 whose uncertainty is its largest magnitude (:func:`qz_taus`).
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from .._threads import one_blas_thread
from ..discretise.hill import HillMatrices, assemble
from ..errors import ConvergenceError, ParameterError
from ..models.base import HillSystem
from ..results.records import MarginalTau
from . import tridiagonal
from .contour import STRIPS, none_up_to, smallest_real_tau
from .half_product import (REAL_RTOL, BlockInverses, block_inverses, coupled_solves,
                           cut_solves, dense_half_product, smallest_taus,
                           tau_from_squares, tridiagonal_half_product, well_conditioned)
from .shift_invert import Shift, interval_taus

ZERO_CLUSTER = 1e-6
N_MAX = 400
#: The first truncation lies this many Fourier indices above the model's resonant index.
FIRST_MARGIN = 8
METHODS = ("auto", "dense", "krylov", "smallest")
KRYLOV_MIN_ORDER = 600
#: The smallest N whose truncation (blocks larger than 2 x 2) is tried by the zero count first
#: (:func:`truncation_taus`): a count (~250 nodes of ~45 K M^3 flops, K ~ 2N blocks) undercuts
#: the dense eig of W (~3 (K M)^3) only from K ~ 60; on a Fig 5.18 cell whose empty kind
#: converged at N = 33 (human, 59.9 Hz) the count made the cell 1.7x slower (CPU time).
#: Measured with closed contours; measured again with the half contours (issue 25; human,
#: 63.6 Hz, sigma = 1.85e9, one BLAS thread, CPU time under load): from N = 20 the count proves
#: the subharmonic empty at N = 51 (M = 32 and 64) in 3.2 and 9.0 s, where the shift-invert
#: cover took 1.2 and 3.4 s, so the threshold stands.
COUNT_MIN_N = 60
#: KRYLOV_MIN_ORDER for models with blocks larger than 2 x 2 (the cochlea), until a truncation
#: of the solve has fallen back from Arnoldi to dense (:func:`krylov_min_order`). Measured on
#: Fig 5.18 cells (one truncation, tau_max = 1/2, one BLAS thread, CPU time): at orders
#: 256-512 (M = 16, N = 15..34; M = 32, N = 9, 15) Arnoldi took 1/3-1/25 of the dense time
#: where it answers (human, 8353 Hz, sigma = 5.7e8), the cover 1/2-1/6 at orders >= 384
#: (human, 262 Hz, sigma = 7.4e7), and 1.2-1.9 times it where both fail and dense answers
#: (human, 63.6 Hz, sigma = 1.85e9: real tau crowding towards 1/2); at order 160 either way
#: about the same.
BLOCK_KRYLOV_MIN_ORDER = 250
#: The smallest-|tau| Arnoldi run of a truncation gives up past this fraction of the estimated
#: cost of its dense solve (:func:`krylov_budget`).
ARNOLDI_WORK_FRACTION = 1.0
#: :func:`krylov_budget`'s model: a product costs K (s0^2 + s^2), s0 = KRYLOV_BLOCK_OVERHEAD,
#: dense eig K^2 s^3 / KRYLOV_DENSE_RATE of them.
KRYLOV_BLOCK_OVERHEAD = 137.0
KRYLOV_DENSE_RATE = 7.6
EPS = np.finfo(float).eps
#: A non-real eigenvalue certifies "no real tau here" once its distance from the real axis is
#: SEPARATION x its change between two truncations (:func:`certified_bound`); measured: 1e3..1e13
#: on well-conditioned pencils, 0.4..7 on the ill-conditioned Mathieu pencils at nu >= 30.
SEPARATION = 100.0
#: Orders of W whose dense eig runs on one BLAS thread (:func:`structured_taus`): there OpenBLAS's
#: threads only cost (2 threads vs 1 on a 2-core machine, sphere W: 1.1-2x slower at orders
#: 162-598, the same at 82); the ~11 us switch is not worth it on smaller W.
ONE_THREAD_ORDERS = range(100, KRYLOV_MIN_ORDER)


def structured_taus(hill: HillMatrices, inv: BlockInverses | None = None) -> np.ndarray | None:
    """Every real tau >= 0 of a bipartite pencil by dense eig of the half-size product W (None if
    A is ill conditioned; see the module notes). ``inv``: the block inverses, if already known."""
    found = structured_spectrum(hill, inv)
    return None if found is None else tau_from_squares(*found)


def structured_spectrum(hill: HillMatrices,
                        inv: BlockInverses | None = None) -> tuple[np.ndarray, float, bool] | None:
    """Every eigenvalue mu^2 = 1/tau^2 of the half-size product W of a bipartite pencil, with the
    floor below which mu^2 counts as zero (tau infinite) and whether real mu^2 are exactly real
    (``tau_from_squares`` takes these three); None if A is ill conditioned."""
    if not hill.bipartite:
        raise ValueError("structured_taus needs a bipartite pencil (no self-coupling in B)")
    inv = block_inverses(hill) if inv is None else inv
    if inv is None:
        return None
    if hill.diag.shape[1] == 1:  # a scalar model: W is tridiagonal, O(N^2) kernel
        d, p = tridiagonal_half_product(hill, inv)
        lam = tridiagonal.eigenvalues(d, p)
        if lam is not None:  # else (~0.1 % of Mathieu W) LAPACK below
            floor = 64 * EPS * math.sqrt(np.vdot(d, d).real + 2 * np.abs(p).sum())
            return lam, floor, False
    W = dense_half_product(hill, inv)
    gebal = _eigen_routines(W.dtype, len(W))[0]
    with one_blas_thread() if len(W) in ONE_THREAD_ORDERS else contextlib.nullcontext():
        balanced = gebal(W, scale=1, permute=0, overwrite_a=1)[0]  # scaling only (matrix_balance)
        floor = 64 * EPS * np.linalg.norm(balanced)
        lam = _eigenvalues(balanced)
    return lam, floor, hill.is_real


@functools.lru_cache(maxsize=256)
def _eigen_routines(dtype: np.dtype, n: int) -> tuple[Callable, Callable, int]:
    """LAPACK ?gebal, ?geev and ?geev's optimal workspace size for n x n matrices of ``dtype``,
    looked up once per (dtype, n): on a small W the lookups cost as much as the balancing."""
    gebal, geev, geev_lwork = sla.lapack.get_lapack_funcs(("gebal", "geev", "geev_lwork"),
                                                          dtype=dtype)
    work, info = geev_lwork(n, compute_vl=0, compute_vr=0)
    if info != 0:
        raise np.linalg.LinAlgError(f"?geev workspace query failed (info = {info})")
    return gebal, geev, int(work.real)


def _eigenvalues(W: np.ndarray) -> np.ndarray:
    """Eigenvalues of the square W (overwritten) by LAPACK ?geev without eigenvectors, the
    calls ``scipy.linalg.eigvals`` makes (same workspace, so the same numbers) without its
    wrapper's checks; a real W's real eigenvalues have an exactly zero imaginary part."""
    _, geev, lwork = _eigen_routines(W.dtype, len(W))
    out = geev(W, lwork=lwork, compute_vl=0, compute_vr=0, overwrite_a=1)
    if out[-1] != 0:
        raise np.linalg.LinAlgError(f"?geev failed (info = {out[-1]})")
    return out[0] + 1j * out[1] if np.isrealobj(W) else out[0]


def _finite_eigenvalues(hill: HillMatrices) -> np.ndarray:
    """Finite eigenvalues of the pencil by dense QZ; infinite ones (beta = 0) are dropped."""
    alpha, beta = sla.eigvals(hill.A.toarray(), hill.B.toarray(), homogeneous_eigvals=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        tau = alpha / beta
    return tau[np.isfinite(tau)]


def _real_part_of_real(tau: np.ndarray, exact: bool) -> np.ndarray:
    real = tau.imag == 0.0 if exact else np.abs(tau.imag) <= REAL_RTOL * np.maximum(np.abs(tau), 1.0)
    return np.sort(tau.real[real])


def dense_taus(hill: HillMatrices) -> np.ndarray:
    """Real tau (either sign) of the pencil by dense QZ (``scipy.linalg.eigvals(A, B)``): the
    reference path."""
    return _real_part_of_real(_finite_eigenvalues(hill), hill.is_real)


def qz_taus(hill: HillMatrices) -> tuple[np.ndarray, float]:
    """Real tau >= 0 by QZ; a defective zero eigenvalue is reported as one exact 0.

    Returns (tau, spread): see :func:`qz_real_taus`.
    """
    return qz_real_taus(_finite_eigenvalues(hill), hill.is_real)


def qz_real_taus(tau: np.ndarray, exact_real: bool) -> tuple[np.ndarray, float]:
    """Real tau >= 0 of the finite QZ eigenvalues ``tau`` of a pencil, and ``spread``:
    eigenvalues within ZERO_CLUSTER of 0 that are not a simple +-tau pair (symmetric to 1 %, as
    the tau -> -tau symmetry makes every simple one) are the rounding spread of a multiple zero
    and are merged into tau = 0 with ``spread`` their largest magnitude."""
    near = np.abs(tau) <= ZERO_CLUSTER
    cluster = tau[near]
    simple_pair = (len(cluster) == 2 and np.all(cluster.imag == 0)
                   and abs(cluster.real.sum()) <= 1e-2 * np.abs(cluster.real).max())
    if simple_pair or not near.any():
        near[:] = False
    positive = _real_part_of_real(tau[~near], exact_real)
    positive = positive[positive >= 0]
    if not near.any():
        return positive, 0.0
    return np.concatenate([[0.0], positive]), float(np.max(np.abs(cluster)))


def preferred_form(kind: str, block_size: int) -> str:
    """The bipartite form solved densely: two-sided for subharmonic, and for a scalar model
    (``block_size`` 1, tridiagonal W) of either kind; real for the harmonic of block models."""
    return "real" if kind == "harmonic" and block_size > 1 else "two-sided"


@dataclass(frozen=True, kw_only=True, eq=False)
class Truncation:
    """Real tau >= 0 of one truncation: ascending ``tau``, the ``method`` that found them, the
    uncertainty ``spread`` of a reported tau = 0 (QZ path), ``complete_to``: every real
    tau <= complete_to of the truncation is listed (inf: the whole real spectrum); the
    ``shifts`` of the shift-invert cover (a plan for the next truncation; empty on the other
    paths), and ``spectrum``: every finite eigenvalue tau
    (complex, folded by :func:`_folded`) where the path computed them all (dense and QZ) and
    the model's D(s) is a matrix polynomial (:func:`certified_bound`), else None.
    ``count_failed``: the zero count of this truncation at tau_max was walked first and could
    not prove it empty (:func:`~spectralshell.solvers.contour.none_up_to` is deterministic, so
    a proof asked for later at the same tau_max fails without walking it again).
    """

    tau: np.ndarray
    method: str
    spread: float = 0.0
    complete_to: float = np.inf
    shifts: tuple[Shift, ...] = ()
    spectrum: np.ndarray | None = None
    count_failed: bool = False


def _folded(tau: np.ndarray) -> np.ndarray:
    """|Re tau| + i |Im tau|: one representative of each eigenvalue quadruple (tau, -tau and,
    by the reality conditions (2.7)/(2.8), their conjugates), so that two truncations' spectra
    compare without a branch choice."""
    return np.abs(tau.real) + 1j * np.abs(tau.imag)


def _spectrum_from_squares(lam: np.ndarray, floor: float) -> np.ndarray:
    """Folded tau = 1/sqrt(mu^2) of the mu^2 above ``floor``."""
    lam = lam[np.abs(lam) > floor]
    return _folded(1.0 / np.sqrt(lam.astype(complex)))


def certified_bound(found: Truncation, previous: Truncation) -> float:
    """The amplitude up to which two successive truncations prove their list of real tau
    complete: both truncations' ``complete_to``, lowered to the smallest |tau| of any non-real
    eigenvalue of the larger truncation that lies closer to the real axis than SEPARATION times
    its distance to the nearest eigenvalue of the smaller one.

    Notes
    -----
    Rounding and truncation move each eigenvalue by about its change between the truncations.
    A non-real eigenvalue far from the axis against that change cannot be a real one displaced;
    one that is not (an ill-conditioned pencil: strong damping, where the periodic solutions
    vary over many orders of magnitude within a cycle and their Fourier coefficients lose
    them) could be, so the claim "no other real tau" stops below it. Real eigenvalues
    (|Im tau| <= REAL_RTOL |tau|) and the zero cluster (|tau| <= ZERO_CLUSTER) are reported, not
    tested. Paths that do not compute the whole spectrum (Krylov, shift-invert) certify their
    own ``complete_to``.

    The test needs every eigenvalue of the truncated pencil to converge in N, which holds where
    D(s) is a matrix polynomial (finitely many natural modes: the Mathieu equation, the
    inviscid cochlea). Where D(s) has a branch cut (a viscous fluid: the sphere, the fibre, the
    viscous cochlea) the truncations also carry eigenvalues that sample the continuous spectrum
    and drift with N without settling: measured on the sphere at 50 beats/min (m = 2..6, the
    Fig 6.13 map), eigenvalues with |tau| = 0.4-0.5 move by about their distance from the real
    axis at every N from 25 to 171. There the list rests, as before, on two truncations agreeing
    (a real tau must reappear, a drifting eigenvalue does not), and ``complete_to`` is the
    truncation's own.
    """
    bound = min(found.complete_to, previous.complete_to)
    if found.spectrum is None or previous.spectrum is None or not previous.spectrum.size:
        return bound
    z = found.spectrum
    z = z[(np.abs(z) <= bound) & (np.abs(z) > ZERO_CLUSTER)
          & (np.abs(z.imag) > REAL_RTOL * np.abs(z))]
    if not z.size:
        return bound
    change = np.abs(z[:, None] - previous.spectrum[None, :]).min(axis=1)
    loose = np.abs(z.imag) <= SEPARATION * change
    return float(min(bound, np.abs(z[loose]).min())) if loose.any() else bound


def half_order(system: HillSystem, n_temporal: int) -> int:
    """(N + 1) b: the order of W, the dense problem of one truncation (real for harmonic, complex
    for subharmonic); the switch rule of ``method = "auto"`` compares it with KRYLOV_MIN_ORDER."""
    return (int(n_temporal) + 1) * system.block_size


class Pencils:
    """The Hill pencils of one system and kind, with their block inverses, reused across
    truncations: per form, the largest truncation assembled so far is kept; a smaller one is cut
    out of it (:meth:`HillMatrices.truncated`, its inverses likewise), and a larger one reuses the
    inverses of the blocks it shares with it (after checking those blocks are bitwise equal).
    ``reserve``: assemble at least this truncation (a solve that will need it sets it first, so
    that D(s) is evaluated once per Fourier index; assembly was 26 % of a Fig 6.13 map's time
    with one assembly per truncation, 17 % with one per solve: cProfile, 10 x 10 sub-grid)."""

    def __init__(self, system: HillSystem, kind: str):
        self.system, self.kind = system, kind
        self._largest: dict[str, HillMatrices] = {}
        self._inverses: dict[str, BlockInverses | None] = {}  # of the largest, once asked for
        self._conditioned: dict[str, bool] = {}  # well_conditioned(the largest), once asked for
        self._cut: dict[tuple[int, str], HillMatrices] = {}  # smaller ones cut out of it
        self._solves: dict[str, tuple[Callable, bool]] = {}  # of the largest, once asked for
        self.reserve = 0

    def pencil(self, n_temporal: int, form: str) -> HillMatrices:
        """The pencil of truncation ``n_temporal`` (no block inverses: the contour path)."""
        big = self._largest.get(form)
        if big is None or big.n_temporal < n_temporal:
            big = self._assemble(max(n_temporal, self.reserve), form)
        if big.n_temporal == n_temporal:
            return big
        cut = self._cut.get((n_temporal, form))
        if cut is None:
            cut = self._cut[n_temporal, form] = big.truncated(n_temporal)
        return cut

    def well_conditioned(self, n_temporal: int, form: str) -> bool:
        """Whether truncation ``n_temporal`` has its block inverses (:func:`well_conditioned`),
        without forming them; decided once on the largest pencil, whose blocks include this
        one's (and B is the same coupling G throughout), so that its passing implies this one's."""
        hill = self.pencil(n_temporal, form)
        if form not in self._conditioned:
            self._conditioned[form] = well_conditioned(self._largest[form])
        return self._conditioned[form] or well_conditioned(hill)

    def get(self, n_temporal: int, form: str) -> tuple[HillMatrices, BlockInverses | None]:
        """(pencil, block inverses or None if ill conditioned) of truncation ``n_temporal``."""
        hill = self.pencil(n_temporal, form)
        big = self._largest[form]
        if form not in self._inverses:
            self._inverses[form] = block_inverses(big)
        inv = self._inverses[form]
        if big.n_temporal == n_temporal:
            return hill, inv
        if inv is None:  # the larger pencil's bad block may lie outside this one
            return hill, block_inverses(hill)
        return hill, inv.subset(big.block_range(n_temporal))

    def coupled_solves(self, n_temporal: int, form: str) -> tuple[Callable, bool]:
        """(solve, negated) of :func:`~spectralshell.solvers.half_product.coupled_solves` for
        truncation ``n_temporal`` (the disk bound's block solves, :func:`none_up_to`'s
        ``solves``), each block solved once per largest pencil and kept (at most two M x M
        blocks per block of A, the pencil's own size): a smaller truncation's are the largest
        one's (:func:`~spectralshell.solvers.half_product.cut_solves`), so that the disk bound
        of the pair (N, N') solves the blocks of N' only, the same numbers."""
        hill = self.pencil(n_temporal, form)
        big = self._largest[form]
        if form not in self._solves:
            solve, negated = coupled_solves(big)
            self._solves[form] = functools.cache(solve), negated
        solve, negated = self._solves[form]
        if hill is big:
            return solve, negated
        return cut_solves(solve, big.block_range(n_temporal)), hill.negated

    def _assemble(self, n_temporal: int, form: str) -> HillMatrices:
        """Assemble a larger truncation; its block inverses are formed when asked for, reusing
        those of the blocks it shares with the previous one (when bitwise equal)."""
        previous, known_inv = self._largest.get(form), self._inverses.pop(form, None)
        self._conditioned.pop(form, None)
        self._solves.pop(form, None)
        self._cut = {key: cut for key, cut in self._cut.items() if key[1] != form}
        hill = assemble(self.system, self.kind, n_temporal, form)
        self._largest[form] = hill
        if previous is not None and known_inv is not None:
            rows = hill.block_range(previous.n_temporal)
            if np.array_equal(hill.diag[rows], previous.diag):
                self._inverses[form] = block_inverses(hill, (rows, known_inv))
        return hill


def krylov_budget(hill: HillMatrices) -> float:
    """Operator products the smallest-|tau| Arnoldi run of this truncation may spend:
    ARNOLDI_WORK_FRACTION of the estimated cost of dense eig of W, counted in products that
    cost K (s0^2 + s^2) (s0 = KRYLOV_BLOCK_OVERHEAD, a per-block overhead), i.e.
    K^2 s^3 / (KRYLOV_DENSE_RATE (s^2 + s0^2)) for a bipartite real-form pencil, 2.5 times that
    otherwise. This is the shift-invert cover's model before its solves were compiled (issue
    25; fitted then to timings with one BLAS thread for s = 4..256 within a factor ~1.5): the
    run's own products (numpy block products with the inverses of A) were not measured again,
    so its budget is unchanged."""
    K, s, _ = hill.diag.shape
    cost = K * K * s**3 / (KRYLOV_DENSE_RATE * (s * s + KRYLOV_BLOCK_OVERHEAD**2))
    return ARNOLDI_WORK_FRACTION * cost * (1.0 if hill.bipartite and hill.is_real else 2.5)


def krylov_form(kind: str, block_size: int) -> str:
    """The form the Arnoldi run of ``method = "krylov"`` works on: the real one (real
    arithmetic, exactly real tau), except for the subharmonic kind of blocks larger than 2 x 2,
    whose bipartite two-sided form gives a complex W of half the order of T and half the
    eigenvalues to find (:func:`~spectralshell.solvers.half_product.smallest_taus`; 1.7-4.6x
    faster on the cochlea); the shift-invert cover stays on the real form."""
    return "two-sided" if kind == "subharmonic" and block_size > 2 else "real"


def krylov_min_order(system: HillSystem, fell_back: bool = False) -> int:
    """The smallest :func:`half_order` that ``method = "auto"`` solves by Arnoldi:
    KRYLOV_MIN_ORDER, lowered to BLOCK_KRYLOV_MIN_ORDER for blocks larger than 2 x 2 unless a
    truncation of the same solve has fallen back to dense (``fell_back``: there the Krylov work
    was lost, and the next, larger truncation is likely to lose it too)."""
    if system.block_size > 2 and not fell_back:
        return min(BLOCK_KRYLOV_MIN_ORDER, KRYLOV_MIN_ORDER)
    return KRYLOV_MIN_ORDER


def truncation_taus(system: HillSystem, kind: str, n_temporal: int, *,
                    tau_max: float = np.inf, method: str = "auto",
                    pencils: Pencils | None = None, hint: float | None = None,
                    plan: tuple[Shift, ...] = (), count_first: bool = False,
                    expect_empty: bool = False, fell_back: bool = False) -> Truncation:
    """Real tau >= 0 of one truncation by ``method`` (module notes): 'dense' lists all of them;
    'krylov' (and 'auto' when ``half_order`` >= :func:`krylov_min_order`, given ``fell_back``)
    at least every real tau <= min(tau_min, tau_max), on the form of :func:`krylov_form`,
    falling back to 'dense' when it cannot; QZ when A is ill conditioned; 'smallest' only the
    smallest real tau <= a finite tau_max of a
    model with 2 x 2 blocks, certified by the argument principle (result ``method =
    "contour"``), else (and where the certificate fails) as 'auto'. ``pencils``: a cache
    shared by the truncations of one solve.
    With a finite ``tau_max`` the Krylov path is one Arnoldi run for the smallest |tau| and, if
    that does not reach min(tau_min, tau_max), a shift-invert cover of the rest of
    [0, tau_max] (:func:`~spectralshell.solvers.shift_invert.interval_taus`), started at
    ``hint`` (a real tau expected nearby) and at the shifts of ``plan`` (a previous
    truncation's ``shifts``). ``count_first`` (a previous truncation of the solve had no
    tau <= tau_max): for models with blocks larger than 2 x 2 and a finite ``tau_max``, 'auto'
    and 'smallest' first try to prove by the argument principle's zero count that this one has
    none either (:func:`~spectralshell.solvers.contour.none_up_to`; result ``method =
    "contour"``, ``complete_to`` = tau_max), from N = COUNT_MIN_N on, and solve as before
    where it cannot. ``expect_empty`` (none is expected: the caller's ``expect_empty``, or the
    previous truncation was proved empty, or found empty in a solve that expects it): the
    same proof at any N (the disk bound first, then
    the count), which replaces the solve where it succeeds (module notes, "Expected empty
    answers"). A count walked here that fails marks the result ``count_failed``."""
    if method not in METHODS:
        raise ValueError(f"method = {method!r} is invalid: must be one of {METHODS}")
    if not np.count_nonzero(system.forcing):
        return Truncation(tau=np.empty(0), method="structured")  # no finite marginal amplitude
    pencils = Pencils(system, kind) if pencils is None else pencils
    counted = expect_empty or (count_first and n_temporal >= COUNT_MIN_N)
    if (counted and system.block_size > 2
            and method in ("auto", "smallest") and math.isfinite(tau_max)):
        if none_up_to(pencils.pencil(n_temporal, "two-sided"), tau_max,
                      solves=pencils.coupled_solves(n_temporal, "two-sided")):
            return Truncation(tau=np.empty(0), method="contour", complete_to=tau_max)
        # the count was walked and failed: a later proof at tau_max need not walk it again
        return dataclasses.replace(
            truncation_taus(system, kind, n_temporal, tau_max=tau_max, method=method,
                            pencils=pencils, hint=hint, plan=plan, fell_back=fell_back),
            count_failed=True)
    if method == "smallest" and system.block_size == 2 and math.isfinite(tau_max):
        found = (smallest_real_tau(pencils.pencil(n_temporal, "two-sided"), tau_max, hint)
                 if pencils.well_conditioned(n_temporal, "two-sided") else None)
        if found is not None:
            return Truncation(tau=np.array([] if found[0] is None else [found[0]]),
                              method="contour", complete_to=found[1])
    krylov = method == "krylov" or (method in ("auto", "smallest") and
                                    half_order(system, n_temporal)
                                    >= krylov_min_order(system, fell_back))
    if krylov:
        hill, inv = pencils.get(n_temporal, krylov_form(kind, system.block_size))
        bounded = bool(np.isfinite(tau_max))
        found = None if inv is None else smallest_taus(
            hill, tau_max=tau_max, inverses=inv, max_rounds=1 if bounded else None,
            max_products=krylov_budget(hill))
        if found is not None and (found.tau.size or found.complete_to >= tau_max):
            return Truncation(tau=found.tau, method="krylov", complete_to=found.complete_to)
        if bounded and inv is not None:
            cover = interval_taus(pencils.pencil(n_temporal, "real"), tau_max, hint=hint,
                                  plan=plan, smallest_only=True,
                                  none_below=0.0 if found is None else found.complete_to)
            if cover is not None:
                return Truncation(tau=cover.tau, method="shift-invert",
                                  complete_to=cover.complete_to, shifts=cover.shifts)
    hill, inv = pencils.get(n_temporal, preferred_form(kind, system.block_size))
    certifiable = system.polynomial is not None  # see certified_bound
    if inv is None:
        hill = pencils.get(n_temporal, "real")[0]
        eigenvalues = _finite_eigenvalues(hill)
        taus, spread = qz_real_taus(eigenvalues, hill.is_real)
        return Truncation(tau=taus, method="qz", spread=spread,
                          spectrum=_folded(eigenvalues) if certifiable else None)
    lam, floor, exact_real = structured_spectrum(hill, inv)
    return Truncation(tau=tau_from_squares(lam, floor, exact_real), method="structured",
                      complete_to=1.0 / math.sqrt(floor) if floor > 0 else 0.0,
                      spectrum=_spectrum_from_squares(lam, floor) if certifiable else None)


def solve_truncation(system: HillSystem, kind: str,
                     n_temporal: int) -> tuple[np.ndarray, str, float]:
    """All real tau >= 0 of one truncation (dense): (ascending tau, method, uncertainty of a
    reported 0)."""
    found = truncation_taus(system, kind, n_temporal, method="dense")
    return found.tau, found.method, found.spread


def finer(n: int) -> int:
    """The truncation after N in a schedule: N + max(6, N // 2)."""
    return n + max(6, n // 2)


def coarser(n: int) -> int:
    """The truncation a fixed N is compared with: max(1, N - max(2, N // 4))."""
    return max(1, n - max(2, n // 4))


@dataclass(frozen=True)
class TruncationSchedule:
    """The truncations N that :func:`marginal_tau` solves, in order: the one owner of the rule
    (the sweep's continuation and the cost estimate read it here).

    x_0 = min(ceil(n_resonant) + FIRST_MARGIN, coarser(n_max)) -- just above the Fourier index
    at which the model's modes resonate -- and x_{i+1} = min(finer(x_i), n_max).
    """

    first: int
    n_max: int = N_MAX

    @classmethod
    def of(cls, system: HillSystem, n_max: int = N_MAX) -> TruncationSchedule:
        """The schedule of ``system`` up to ``n_max``."""
        return _schedule_of(cls, math.ceil(system.n_resonant), n_max)

    def sequence(self) -> tuple[int, ...]:
        """x_0 < x_1 < ... <= n_max."""
        return _schedule(self.first, self.n_max)


@functools.lru_cache(maxsize=1024)
def _schedule_of(cls: type, resonant: int, n_max: int) -> TruncationSchedule:
    """:meth:`TruncationSchedule.of` a system whose resonant index rounds up to ``resonant``,
    kept (the schedules are few, and a sweep asks at every point and kind)."""
    return cls(min(resonant + FIRST_MARGIN, coarser(n_max)), n_max)


@functools.lru_cache(maxsize=1024)
def _schedule(first: int, n_max: int) -> tuple[int, ...]:
    """:meth:`TruncationSchedule.sequence`, kept per (first, n_max): a sweep's continuation
    reads it at every point and kind."""
    out = [first]
    while out[-1] < n_max:
        out.append(min(finer(out[-1]), n_max))
    return tuple(out)


def _matched(tau: np.ndarray, previous: np.ndarray, tol: float) -> np.ndarray:
    if not tau.size or not previous.size:
        return tau[:0]
    dist = np.abs(tau[:, None] - previous[None, :]).min(axis=1)
    return tau[dist <= tol * np.maximum(1.0, tau)]


def _tau_min_error(tau: np.ndarray, prev: np.ndarray, spread: float) -> float | None:
    """The error estimate of tau_min: its change between the truncations (at least ``spread`` and
    8 eps), the whole value where only the larger truncation has one, None where it has none."""
    if tau.size and prev.size:
        return float(max(abs(float(tau[0] - prev[0])), spread, 8 * EPS * max(1.0, tau[0])))
    return float(tau[0]) if tau.size else None


def unconfirmed(tau: np.ndarray, prev: np.ndarray, tol: float, tau_max: float) -> float:
    """The smallest tau <= ``tau_max`` of either truncation (``tau``, ``prev``) with no partner
    within ``tol`` (relative above 1) in the other, inf if every one has one (a partner may lie
    just above ``tau_max``).

    A real tau seen at one truncation only, or moving by more than ``tol`` between the two, is
    not reported (:func:`_result`); the list is then complete only below it, whatever the
    eigenvalue count proves (e.g. the fibre, m = 2, nu = 2e-4, kappa = 0.172, subharmonic: the
    second tau is 0.7602 at N = 12 and 0.75999 from N = 17 on, while tau_min = 0.605133 settles
    at N = 15)."""
    out = np.inf
    if not tau.size and not prev.size:  # most of a map's truncation pairs (issue 25)
        return out
    for a, b in ((_capped(tau, tau_max), prev), (_capped(prev, tau_max), tau)):
        if not a.size:
            continue
        dist = (np.abs(a[:, None] - b[None, :]).min(axis=1) if b.size
                else np.full(a.size, np.inf))
        loose = a[dist > tol * np.maximum(1.0, a)]
        if loose.size:
            out = min(out, float(loose.min()))
    return out


def _result(kind, found: Truncation, previous: Truncation, n, n_prev, tol, tau_max,
            bound: float, empty_proved: bool = False) -> MarginalTau:
    """The answer of a pair of truncations: tau_min of ``found`` with its error estimate, the tau
    that reappear in ``previous`` within max(tol, error), and ``complete_to``: the pair's
    certified ``bound``, lowered to the smallest tau left out (:func:`unconfirmed`);
    ``empty_proved`` as the zero count found it (:func:`marginal_tau`), ``count_failed`` where
    a count walked at either truncation failed."""
    tau, prev = _capped(found.tau, tau_max), _capped(previous.tau, tau_max)
    err = _tau_min_error(tau, prev, found.spread)
    match = max(tol, err or 0.0)
    kept = _matched(tau, prev, match)
    if tau.size and (not kept.size or kept[0] != tau[0]):
        kept = np.concatenate([tau[:1], kept[kept > tau[0]]])
    return MarginalTau(kind=kind, tau=kept, tau_min=float(tau[0]) if tau.size else None,
                       n_temporal=n, n_previous=n_prev, error_estimate=err, method=found.method,
                       complete_to=min(bound, unconfirmed(found.tau, previous.tau, match,
                                                          tau_max)),
                       empty_proved=empty_proved,
                       count_failed=found.count_failed or previous.count_failed)


def _capped(tau: np.ndarray, tau_max: float) -> np.ndarray:
    if not tau.size or tau_max == np.inf:
        return tau
    return tau[tau <= tau_max]  # tau is never NaN


def converged_pair(found: Truncation, previous: Truncation, tol: float,
                   tau_max: float, every: bool = False) -> bool:
    """The convergence test of two successive truncations (the larger one ``found``): both have
    a tau_min <= tau_max, they differ by less than ``tol``, and the pair certifies that no smaller
    real tau exists (:func:`certified_bound` >= tau_min); or neither has one and the pair
    certifies that none exists up to a finite ``tau_max``. With ``every``, also each other
    tau <= tau_max reappears within ``tol`` and the pair certifies the list complete up to
    ``tau_max`` (:func:`unconfirmed`)."""
    return _passes(found, previous, tol, tau_max, certified_bound(found, previous), every)


def _passes(found: Truncation, previous: Truncation, tol: float, tau_max: float,
            bound: float, every: bool = False) -> bool:
    """:func:`converged_pair` given the pair's :func:`certified_bound` ``bound``."""
    tau, prev = _capped(found.tau, tau_max), _capped(previous.tau, tau_max)
    if every and min(bound, unconfirmed(found.tau, previous.tau, tol, tau_max)) < tau_max:
        return False
    if tau.size and prev.size:
        return abs(float(tau[0] - prev[0])) < tol and bound >= tau[0]
    return not tau.size and not prev.size and math.isfinite(tau_max) and bound >= tau_max


def _not_converged(kind: str, found: Truncation, previous: Truncation, n: int, tol: float,
                   tau_max: float, bound: float, every: bool = False) -> ConvergenceError:
    """Why the last pair of truncations failed :func:`converged_pair` (``bound``: its
    :func:`certified_bound`), and what to change."""
    tau, prev = _capped(found.tau, tau_max), _capped(previous.tau, tau_max)
    first = unconfirmed(found.tau, previous.tau, tol, tau_max)
    if every and _passes(found, previous, tol, tau_max, bound):
        why = (f"the marginal tau near {first:.6g} moves by more than tol between the last two "
               "truncations, or appears in only one" if first <= bound else
               "their eigenvalues near the real axis do not settle (an ill-conditioned Hill "
               "pencil)")
        return ConvergenceError(
            f"{kind} tau_min has converged to tol={tol:g} by n_temporal={n}, but the list of "
            f"every tau <= tau_max={tau_max:g} (every=True) is proved complete only up to "
            f"{min(first, bound):.4g}: {why}; lower tau_max= below it, or relax tol=")
    if not tau.size and not prev.size:
        return ConvergenceError(
            f"{kind}: no marginal tau found up to n_temporal={n}, but that is proved only for "
            f"tau <= {bound:.4g} (beyond it the truncations' eigenvalues near the real axis do "
            "not settle: an ill-conditioned Hill pencil, e.g. under strong damping): give "
            f"tau_max= at most {bound:.4g} to accept 'none below it', or lower the damping")
    if tau.size and prev.size and abs(float(tau[0] - prev[0])) < tol:
        return ConvergenceError(
            f"{kind} tau_min = {float(tau[0]):.6g} has converged to tol={tol:g} at "
            f"n_temporal={n}, but the truncations prove no smaller real tau only below "
            f"{bound:.4g} (their eigenvalues near the real axis do not settle: an "
            "ill-conditioned Hill pencil, e.g. under strong damping); fix "
            "n_temporal= to get the values with that bound (complete_to), or lower the damping")
    change = (f"last change {abs(float(tau[0] - prev[0])):.3g}" if tau.size and prev.size
              else "a tau at one of the last two truncations only")
    beyond = ""
    if tau_max > 0.5 and min(tau[:1].tolist() + prev[:1].tolist()) > 0.5:
        beyond = (f"; these tau_min ({tau[0] if tau.size else prev[0]:.6g} at the last N) "
                  "exceed 1/2, where the stiffness turns negative: tau_max=0.5 "
                  "asks only for the physical range")
    lowest = min([bound] + tau[:1].tolist() + prev[:1].tolist())
    return ConvergenceError(
        f"{kind} tau_min did not converge to tol={tol:g} by n_temporal={n} "
        f"({change}; that no marginal tau exists is proved only for tau <= {lowest:.4g}); "
        f"relax tol=, or fix n_temporal= and read the error "
        f"estimate{beyond}")


def _empty_pair(system: HillSystem, found: Truncation, previous: Truncation,
                tau_max: float) -> bool:
    """Whether the pair's empty answer needs the zero count (:func:`marginal_tau`'s
    ``certify_empty``): no tau <= a finite tau_max at either truncation, of a model whose D(s)
    is not a matrix polynomial (for the others :func:`certified_bound` tests the spectra)."""
    return (system.polynomial is None and math.isfinite(tau_max)
            and not _capped(found.tau, tau_max).size and not _capped(previous.tau, tau_max).size)


def _empty_certified(pencils: Pencils, pair: tuple[tuple[Truncation, int], ...],
                     tau_max: float) -> bool:
    """Whether each (truncation, N) of ``pair`` is proved to have no real tau <= tau_max: by
    its own path (the contour path's ``complete_to``) or by the zero count of its two-sided
    pencil (:func:`~spectralshell.solvers.contour.none_up_to`).

    The dense path's empty list is exact for its truncation but not robust: a viscous model's
    truncations carry complex eigenvalues within ~1 % of the real axis that drift with N
    (:func:`certified_bound`), and one of them may be a real tau displaced by rounding. The
    count proves a strip of half-height 1e-6..1e-2 tau_max^2 around the real axis free of any
    eigenvalue. A truncation whose count at tau_max was already walked and failed
    (``count_failed``) is not proved, without walking it again."""
    return all(_counted_empty(found, tau_max)
               or (not found.count_failed
                   and none_up_to(pencils.pencil(n, "two-sided"), tau_max,
                                  solves=pencils.coupled_solves(n, "two-sided")))
               for found, n in pair)


def _counted_empty(found: Truncation, tau_max: float) -> bool:
    """Whether the truncation's own path proved it empty up to tau_max (the contour path)."""
    return found.method == "contour" and found.complete_to >= tau_max


def empty_not_certified(kind: str, n_prev: int, n: int, tau_max: float) -> ConvergenceError:
    """The error of an empty answer the zero count could not prove (:func:`marginal_tau`)."""
    return ConvergenceError(
        f"{kind}: no marginal tau <= tau_max={tau_max:g} at n_temporal={n_prev} and {n}, but "
        "the zero count cannot prove that none exists (an eigenvalue within "
        f"{min(STRIPS):g} tau_max^2 of the real axis, or the count's node budget): the "
        "truncations' near-axis complex eigenvalues could hide one; give a smaller or larger "
        "tau_max=, or fix n_temporal= to get the values with what is proved (complete_to)")


def on_block_threads(solver: Callable) -> Callable:
    """``solver(system, ...)`` on one BLAS thread where ``system`` has blocks larger than 2 x 2
    (the cochlea's M x M): its block inverses, products, LUs and counts are LAPACK and BLAS calls
    on M x M blocks (M <= 1024), where OpenBLAS's threads only cost. Measured on the human
    cochlea (Table 5.1) at 2826 and 3000 Hz, sigma = 2.72e8, M = 128 fixed, both kinds, as a
    serial sweep (2 cores, nothing else running, two runs each): 6.5-6.9 s wall (12.6-13.3 s
    CPU) on OpenBLAS's two threads, 1.0-1.1 s on one, the same values; a refinement in M to
    192 11.6 s against 1.4 s (spatial_refinement notes, "Threads"). The dense eig of W inside
    loses a little at large orders (random complex W, best of 3: 1.0x at order 600, 1.2x at
    900, 1.6x at 1300 slower on one thread); sphere, fibre and Mathieu keep the dense eig's own
    policy (ONE_THREAD_ORDERS). Sweep workers run on one thread anyway (runner/executors.py)."""

    @functools.wraps(solver)
    def limited(system: HillSystem, *args, **kwargs):
        with one_blas_thread() if system.block_size > 2 else contextlib.nullcontext():
            return solver(system, *args, **kwargs)

    return limited


@on_block_threads
def certify_empty_answer(system: HillSystem, kind: str, answer: MarginalTau, tau_max: float,
                         certify_empty: bool | str) -> MarginalTau:
    """``answer`` (of :func:`marginal_tau` with ``n_temporal=None`` and no ``certify_empty``,
    at ``tau_max``) as ``certify_empty`` would have given it: an empty answer that needs the
    zero count (a viscous model, finite tau_max) gets ``complete_to`` min(its own, tau_max)
    where both truncations of its pair are proved empty (:func:`_empty_certified`), else 0
    with ``'mark'``, else the ConvergenceError of :func:`marginal_tau`; other answers are
    returned as they are. For a caller that keeps only some answers (a refinement in M keeps
    the finest): the proof is paid for those alone. Without ``n_temporal`` an empty answer
    means both truncations of the pair are empty (:func:`converged_pair`), which the proof
    needs (with ``n_temporal`` given, pass ``certify_empty`` to :func:`marginal_tau`
    instead)."""
    if not certify_empty or answer.tau_min is not None or not answer.n_temporal \
            or system.polynomial is not None or not math.isfinite(tau_max):
        return answer
    if answer.empty_proved:  # both truncations proved empty by the solve's own path
        return dataclasses.replace(answer, complete_to=min(answer.complete_to, tau_max))
    if answer.count_failed:  # the solve walked one of the counts at tau_max and it failed
        return _unproved_answer(answer, kind, tau_max, certify_empty)
    pencils = Pencils(system, kind)
    pencils.reserve = answer.n_temporal
    previous = Truncation(tau=np.empty(0), method="", complete_to=0.0)  # nothing proved yet
    found = Truncation(tau=np.empty(0), method=answer.method,
                       complete_to=tau_max if answer.method == "contour" else 0.0)
    if _empty_certified(pencils, ((found, answer.n_temporal), (previous, answer.n_previous)),
                        tau_max):
        return dataclasses.replace(answer, complete_to=min(answer.complete_to, tau_max))
    return _unproved_answer(answer, kind, tau_max, certify_empty)


def _unproved_answer(answer: MarginalTau, kind: str, tau_max: float,
                     certify_empty: bool | str) -> MarginalTau:
    """An empty answer the count could not prove: marked (complete_to 0) with 'mark', else the
    ConvergenceError of :func:`empty_not_certified`."""
    if certify_empty != "mark":
        raise empty_not_certified(kind, answer.n_previous, answer.n_temporal, tau_max)
    return dataclasses.replace(answer, complete_to=0.0)


@on_block_threads
def marginal_tau(system: HillSystem, kind: str, *, tol: float = 1e-10,
                 n_temporal: int | None = None, n_max: int = N_MAX,
                 tau_max: float = np.inf, method: str = "auto",
                 hint: float | None = None, every: bool = False,
                 certify_empty: bool | str = False, expect_empty: bool = False) -> MarginalTau:
    """Marginal amplitudes tau of one Floquet kind, converged in the truncation N.

    Parameters
    ----------
    system : the model's physics (D(s), G).
    kind : 'harmonic' (gamma = 0) or 'subharmonic' (gamma = i/2).
    tol : with ``n_temporal=None``, N is raised (N -> N + max(6, N // 2), starting above the
        model's resonant index) until two successive truncations pass :func:`converged_pair`:
        tau_min changes by less than ``tol`` (absolute) and the pair proves that no smaller real
        tau exists (``complete_to`` >= tau_min).
    n_temporal : fixed truncation N instead; the error estimate then compares with a smaller N,
        and ``complete_to`` says how far the list is proved complete (it may lie below tau_min).
    tau_max : only tau <= tau_max are wanted (e.g. 1/2, where the stiffness stays positive, or
        the amplitude a stability question asks about): larger ones are dropped at every
        truncation before the convergence test, so the truncation is raised only as far as the
        wanted values need. ``tau_min`` is None only when two successive truncations prove that
        no tau <= tau_max exists (``complete_to`` >= tau_max); with tau_max = inf an empty answer
        is never returned unless the model has no forcing (N is raised to find a tau instead).
    method : 'auto' (default), 'dense', 'krylov' or 'smallest', per truncation (module notes).
        tau_min and its error estimate do not depend on it; ``tau`` lists every real
        tau <= tau_max with 'dense', and those up to ``complete_to`` (at least tau_min) with
        'krylov' (whose truncations report 'krylov' or, with a finite tau_max, 'shift-invert')
        and 'smallest' (tau_min alone where its truncations report 'contour').
    hint : a real tau expected near tau_min (e.g. a neighbouring point's tau_min in a sweep):
        where the shift-invert cover of a big truncation with finite ``tau_max`` starts
        (:func:`truncation_taus`); later truncations start from the previous one's shifts, or
        its tau_min. Only speed depends on it.
    every : with ``n_temporal=None``, also raise N until every tau <= tau_max (finite) has
        converged to ``tol`` and the list is complete up to tau_max (``complete_to`` >=
        tau_max), not only tau_min: what a boundary tracer needs, whose curves follow the
        larger tau too.
    certify_empty : for a model whose D(s) is not a matrix polynomial (a viscous fluid:
        sphere, fibre, viscous cochlea), an empty answer (no tau <= a finite tau_max) is
        returned only where the argument principle's zero count proves, at both truncations
        of the pair, a thin strip around [0, tau_max^2] free of eigenvalues
        (:func:`_empty_certified`; ``complete_to`` is then tau_max); where it cannot, a
        ConvergenceError says so (with ``n_temporal`` given, ``complete_to`` is 0 instead).
        ``'mark'``: the same proof, but an empty answer it cannot give is returned with
        ``complete_to`` = 0 (proved for no tau: the maps' sweeps store it as uncertified)
        instead of raising. Without it such an empty answer
        rests on two dense truncations agreeing (:func:`certified_bound`). Where the solve's
        own path has proved both truncations empty (the contour path, e.g. ``expect_empty``),
        the answer says so (``empty_proved``) with or without it, and the proof is not repeated.
    expect_empty : the caller expects no tau <= a finite ``tau_max`` (e.g. none at a coarser
        spatial truncation, :mod:`spectralshell.solvers.spatial_refinement`): for blocks larger
        than 2 x 2 the first truncation, and each one after a truncation so proved, is first
        tried by the zero count (its disk bound first; :func:`truncation_taus`'
        ``expect_empty``), and so is each one after a truncation its solve found empty
        without a failed count. The answer does not depend on it (module notes, "Expected
        empty answers").

    Raises
    ------
    ConvergenceError : no pair of truncations up to N = ``n_max`` passes the test; the message
        says which part failed and what to change.
    """
    if every and not math.isfinite(tau_max):
        raise ParameterError(f"tau_max = {tau_max} is invalid with every=True: must be finite "
                             "(every tau up to it is converged)")
    pencils = Pencils(system, kind)
    start = {"hint": hint, "plan": (), "count_first": False,  # from one truncation to the next
             "expect_empty": expect_empty, "fell_back": False}

    def solve(n: int) -> Truncation:
        found = truncation_taus(system, kind, n, tau_max=tau_max, method=method,
                                pencils=pencils, **start)
        if (method in ("auto", "smallest") and found.method in ("structured", "qz")
                and half_order(system, n) >= krylov_min_order(system, start["fell_back"])):
            start["fell_back"] = True  # Arnoldi was tried and lost (krylov_min_order)
        capped = _capped(found.tau, tau_max)
        if found.shifts or capped.size:  # its shifts, else its tau_min, else the hint as it was
            start.update(plan=found.shifts,
                         hint=None if found.shifts else float(capped[0]))
        start["count_first"] = not capped.size
        start["expect_empty"] = _counted_empty(found, tau_max) or (
            expect_empty and not capped.size and not found.count_failed)
        return found

    def proved(found: Truncation, previous: Truncation, n: int, n_prev: int,
               bound: float) -> tuple[float | None, bool]:
        """(the pair's certified_bound ``bound``, whether its empty answer is proved by the zero
        count at both truncations): proved where both truncations' own path proved them
        (:func:`_counted_empty`); else with certify_empty, for an empty pair that needs it, the
        count decides: tau_max where it proves it and None where it cannot."""
        empty = _empty_pair(system, found, previous, tau_max)
        if empty and _counted_empty(found, tau_max) and _counted_empty(previous, tau_max):
            return min(bound, tau_max), True
        if not certify_empty or not empty:
            return bound, False
        if _empty_certified(pencils, ((found, n), (previous, n_prev)), tau_max):
            return min(bound, tau_max), True
        return None, False

    if not np.count_nonzero(system.forcing):  # no finite marginal amplitude at all
        return MarginalTau(kind=kind, tau=np.empty(0), tau_min=None, n_temporal=0, n_previous=0,
                           error_estimate=None, method="structured")
    if n_temporal is not None:
        n_prev = coarser(n_temporal)
        found, previous = solve(n_temporal), solve(n_prev)
        bound, counted = proved(found, previous, n_temporal, n_prev,
                                certified_bound(found, previous))
        return _result(kind, found, previous, n_temporal, n_prev, tol, tau_max,
                       0.0 if bound is None else bound, counted)
    if system.n_resonant >= n_max:
        raise ConvergenceError(
            f"{kind} tau_min needs more than n_temporal={n_max} Fourier terms: the natural "
            f"frequency is {system.n_resonant:.4g} forcing frequencies; lower the stiffness "
            "(kappa) or the mode number m, or raise the forcing frequency")
    n_prev = TruncationSchedule.of(system, n_max).first
    pencils.reserve = min(finer(n_prev), n_max)  # both are always solved
    previous = solve(n_prev)
    while True:
        n = min(finer(n_prev), n_max)
        found = solve(n)
        bound = certified_bound(found, previous)  # once per pair: O(N^2) for Mathieu
        if _passes(found, previous, tol, tau_max, bound, every):
            bound, counted = proved(found, previous, n, n_prev, bound)
            if bound is None and certify_empty != "mark":
                raise empty_not_certified(kind, n_prev, n, tau_max)
            return _result(kind, found, previous, n, n_prev, tol, tau_max,
                           0.0 if bound is None else bound, counted)
        if n >= n_max:
            raise _not_converged(kind, found, previous, n, tol, tau_max, bound, every)
        previous, n_prev = found, n
