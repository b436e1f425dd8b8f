"""The smallest real tau <= tau_max of one truncation, certified by the argument principle.

A map (Fig 6.13) asks each truncation only for its smallest real tau below tau_max, and that
no smaller one exists; the dense path answers with every eigenvalue, O((N b)^3). Here the
answer costs O(N b^3) per point of the complex plane.

The function
-------------
For a bipartite pencil A - tau B (two-sided form: B couples Fourier index k only to k +- 1) the
block elimination S_0 = A_0, S_k = A_k - z L_k S_{k-1}^{-1} U_{k-1} involves tau only through
z = tau^2, and g(z) = det(A - tau B) / det A = det(I - z W) = prod_i (1 - z mu_i^2): a polynomial
whose zeros are z_i = tau_i^2 = 1 / mu_i^2 (the compiled kernel ``_schur.c`` returns
log det(A - tau B) at many z for 2 x 2 blocks, :func:`block_log_det` by LAPACK's LU for larger
ones such as the cochlea's M x M; mu^2 = 0, tau infinite, gives no zero). The spectrum of W is
closed under conjugation (real form, or W = Z conj(Z)), so g is real on the real axis and a real
tau is a real zero z in (0, tau_max^2].

The answer and its certificate
------------------------------
A candidate z* is bracketed by a sign change of g on the real axis (within 5 % of the caller's
``hint`` squared, a neighbour's tau_min; else, once the count below finds zeros, on a grid over
[0, tau_max^2]; the points taken in turn from the lowest up to the first change; but first,
where g has opposite signs at the real ends of that count's rectangle, the sign change over
[0, tau_max^2] itself, bisected to the grid's spacing, whose root is kept if its certificate
below holds in the first strip) and
refined by Newton's method on the kernel's g'/g, safeguarded by bisection (``_schur.root``;
first to 1e-13, then again, to rounding, inside a fixed dyadic cell around
that value, so that the answer does not depend on the hint). The argument principle then
counts the zeros of g (real or not) inside

* the rectangle [-a, z* - rho/2] x [-a, a] (a = s tau_max^2 for the first s of STRIPS for which
  the count is zero: the viscous models' truncations carry complex eigenvalues within 1 % of
  the real axis at low beat rates; rho = DISK z*): none, and
* the disk |z - z*| <= rho: exactly one (z* itself),

which proves that no real tau lies below tau* = sqrt(z*) and no other one up to
sqrt(z* + rho / 2): ``complete_to``. Without a sign change near the hint the rectangle of the
first strip runs to tau_max^2 (1 + 1e-6) first; holding no zero, it proves that no real
tau <= tau_max exists; holding some, the grid looks for the sign change, and only where it
finds none are the other strips counted (none there: no real tau <= tau_max either).
Where only whether a count is zero matters (every rectangle), the kernel reads g at the
rectangle's two real ends first: of opposite signs there, g has an odd count inside, so not
zero, and the rectangle is not walked.
The count is the winding number of g along the boundary (:func:`winding`, in the compiled
kernel ``_schur.c``; g takes conjugate values at conjugate points, so the upper half of each
contour is read and its phase change doubled), and must lie within 0.05 of an integer. For
2 x 2 blocks every step above runs inside one call of the kernel (``_schur.smallest``, with
the constants of this module passed in), which places the same points with the same
arithmetic as the Python composition of :func:`winding`, :func:`rectangle`, :func:`circle` and
``_schur.root`` that it replaced (tests/test_contour.py keeps that composition and checks the
answers equal bitwise). Where any of this fails (a complex eigenvalue within 1e-6 tau_max^2 of
the real axis below tau*, another zero within rho of z*, a zero pivot, MAX_NODES evaluations)
the function returns None and the caller solves the truncation
densely: the answer is then the dense path's, never an uncertified one. Like the Krylov path's
(:mod:`spectralshell.solvers.half_product`) the count rests on sampling, here of the phase of
g, with the node spacing set by the variation of g'/g; it is checked against QZ counts in
tests/test_contour.py, including a pair of real tau 1 % apart that a coarse sampling misses.

Blocks larger than 2 x 2
------------------------
The cochlea (M = 32..250) uses the count alone, through :func:`none_up_to`: the proof that a
truncation has no real tau <= tau_max (the thin rectangle around [0, tau_max^2] holds no zero,
BLOCK_STRIPS), which :mod:`spectralshell.solvers.marginal` tries on the truncation after an
empty one and to certify an empty answer of a viscous model. One point costs a block LU sweep,
O(K M^3) (about 45 K M^3 flops), against O((K M)^3) for the dense eig; the same walk
(``_schur.winding_of``, calling :meth:`LogDet.point` back) refines the nodes, within
MAX_BLOCK_NODES, along the upper half of each contour as for 2 x 2 blocks: the cochlea's g
takes conjugate values at conjugate points too, in both bipartite forms (real blocks in the
real form, the reality condition in the two-sided one). Counts are checked against QZ, and
that symmetry on the cochlea, in tests/test_contour_blocks.py. Before counting, a disk free of
eigenvalues may prove the same (:func:`_free_disk`: from the block norms of W, no count
needed); it does where every eigenvalue lies well beyond tau_max, as on the Fig 5.18 cells
whose one kind has nothing below the other's tau_min (tests/test_free_radius.py). Where a real
tau lies below the cap the count would walk ~95 nodes to find it (cochlea, M = 64, N = 15);
instead, as g(0) = 1 and g is real on the axis, g < 0 at the rectangles' right corner shows an
odd number of real zeros inside at the cost of one evaluation (:func:`_odd_below`), and the
proof is declined there (every correct count would be nonzero). An even number (a close pair)
is left to the count, whose walk checks log |g| against its prediction as well as the phase:
with the phase alone, a pair under one segment of a thin strip went unseen (2 pi modulo 2 pi;
tests/test_contour_blocks.py::test_count_sees_close_real_pair, found in session 22).
A node's block sweep (:func:`block_log_det`) inverts blocks below M = 128 from their LU
instead of solving with them (OpenBLAS's triangular solves are slow per flop there), and on the
cochlea's chained couplings (one matrix C: lower C, upper -C) takes the derivative recursion
without a solve of its own. Issue 25, measured against the main branch (one BLAS thread, CPU
time, best of 24 evaluations, the two codes run alternately, load ~3 on 2 cores; gerbil,
5 kHz, N = 15): per node M = 32 4.4-5.1 -> 3.7-4.1 ms, M = 64 18.9-22.7 -> 13.0-15.7 ms,
M = 128 106-120 -> 76-79 ms, M = 256 566-636 -> 419-437 ms; log g bitwise the same (the LUs
are), its derivative to ~1e-15 relative. On 20 cells of the seeded Fig 5.18 sample
(validation/bench_sweep.py's sample_points, every 5th, each alone, main's code and this one
alternately per cell, load 4-5): 108.5 s -> 95.3 s CPU, the crowded cell (human, 63.6 Hz,
sigma = 1.85e9) 53.9 -> 42.4 s and 53.9 -> 41.6 s, the others within noise; every returned
variable of every cell bitwise equal. The shortcut fired on none of them (one count failed
there, at M = 16 after its node budget, with g > 0 at the corner); on
validation/bench_certify_cochlea.py's "none <= 0.24" (one real tau below) it declines after 1
evaluation instead of 93-95 nodes: M = 64 1.6-1.8 s -> 0.02-0.03 s, M = 128 8.3-8.7 s ->
0.14-0.16 s CPU.
The cochlea's two-sided pencils have one coupling block L = i kappa C, C real symmetric: the
similarity by diag(U, ..., U), C = U diag U^T, leaves g unchanged and makes the coupling
diagonal (:func:`rotated_coupling`), and each node then costs one LU, one inverse and two
products per block (:func:`diagonal_log_det`) instead of a solve and four products. Issue 25
(one BLAS thread, best of 5, gerbil 5 kHz, N = 15): per node M = 32 2.3 -> 1.9 ms, 64 9.7 ->
7.4 ms, 128 64 -> 57 ms, 256 382 -> 321 ms, log g to ~1e-12 of block_log_det's; on the seeded
100-point Fig 5.18 sample (validation/bench_sweep.py's sample_points, 2 processes) the counts
took 126.8 -> 100.2 s CPU, every returned variable of every point bitwise equal.
That rotated sweep then moved into the compiled kernel (``_schur.rotated_logdet``, SciPy's
LAPACK and BLAS called from C; issue 25): of the counts' 12,344 nodes on the seeded sample,
9,463 are at M = 16 and 32, where the ~10 numpy and LAPACK calls per block cost more than
their flops. Per node (one BLAS thread, CPU, the numpy sweep and the kernel alternately on
the crowded cell's blocks, K = 104..154): M = 16 9.0-10.2 -> 3.2 ms, M = 32 13.8-14.2 ->
7.8-7.9 ms, M = 64 48-53 -> 40-41 ms; log g to ~2e-15 relative (the sum of the LU's
logarithms in another order), its slope to ~1e-14. The seeded 100-point sample, main's code
and this one side by side (one process each, 2 cores): 336.8 -> 308.0 s CPU (1.094x), every
returned variable of every point bitwise equal.

The value agrees with the dense eig of W (tests/test_contour.py: to 1e-10 relative, in practice
~1e-14, on Fig 6.13 cells); what differs is that only tau_min and ``complete_to`` are reported,
not every real tau. The dense path's own block-LU relative, for Floquet exponents, is
:mod:`spectralshell.solvers.block_tridiagonal` (numpy, batched over a variable in A).

Cost
----
One point of a contour costs O(K) (K = 2N + 1 or 2N + 2 blocks of 2 x 2), a count some tens to
a few hundred points; the dense eig of W costs O(N^3). Measured on a 20 x 20 Fig 6.13 map (m =
2..6, both kinds, serial, one BLAS thread, CPU time under load): 17.5 s with the dense eig of W
per truncation, 7.5 s with this path (6.2 s with the sphere's fluid-load cache), the same map
to 6e-15 with the same truncation pairs. Then (issue 25, load 8-10 on 2 cores, CPU time, the
previous path and this one run alternately): the root by Newton in the kernel instead of Brent
from Python, half contours, one strip before the scan, no block inverses, per-(m, nu, kind)
fluid-load tables and the sphere's scalar coupling in the kernel took the 20 x 20 map from
5.4-6.1 s to 3.3-3.9 s, and 12 full lines of the 200 x 200 grid (sigma lines 0-3, 100-103,
196-199, 200 beat rates each) from 25.3-28.2 s to 12.0-14.6 s (two runs): the 200 x 200 map
projects to 100-120 s on 2 workers from CPU time (wall time under that load: 2-3x more; a
table's first use is a quarter of these lines' assemblies, fewer in the whole map, where each
worker meets every beat rate on many stiffness lines). What remains is about a fifth
each: the counts in the kernel (mostly at low beat rates, where many complex eigenvalues lie
near the real axis), the Bessel ratios of the fluid load (a table's first use), and the
sweep's and solver's Python per point and truncation. The whole 200 x 200 figure measured by
validation/bench_fig613.py on the same machine nearly idle (load < 1 before each run; two
runs): 67.2 s and 74.8 s wall on 2 workers (64.2 and 72.8 s CPU per worker), against the dense
path projected from 100 seeded cells at 683 s and 896 s: 10.2x and 12.0x, the sampled cells
equal to 2.5e-15 with the same has_tau masks; the issue's goal is 60 s.

Then the Python around the counts (issue 25, ``validation/bench_fig613.py --lines --against``
the main branch: the 12 lines above, serial, one BLAS thread, CPU time, the two codes run
alternately): smallest_real_tau's steps moved into the kernel (one call per truncation instead
of ~10), the fluid-load table of both kinds made in one call with its top doubled rather than
stepped and without the Bessel kernels' per-call checks, and the sweep's per-point parameter
checks made cheaper (the cgs conversion kept per process, a float fast path in the
validators). On a 2-core machine loaded by other jobs (load average 4-10), main's code and
this one in the same runs: 8.1-10.6 s -> 6.3-7.9 s (22-27 % less CPU; main's took 7.1 s at
load 0.2), the map on these lines bitwise equal to main's (tau_min, has_tau,
error_estimate, n_temporal). The whole 200 x 200 map on 2 workers, run once each, one after
the other, at load 6-12: workers' CPU 150.0 s (main) -> 122.5 s (18 % less: the tables,
a sixth of the gain on the 12 lines, cost little in the whole map, where a worker meets each
beat rate on ~100 stiffness lines), the two maps bitwise equal; from the quiet measurement
above (64.2-72.8 s CPU per worker) that projects to 53-60 s CPU per worker, about 56-63 s
wall: at the goal, not reliably under it. Where the time now goes (perf, 12 lines): the
kernel's log det evaluations ~40 % (the widest strip's count of the truncations without a
tau <= tau_max, ~80 % of them, takes 54 % of the evaluations at ~20 nodes each, near the 17
of its starting path), Python ~40 % (assembly of D(s) from the tables, marginal_tau's
bookkeeping, the sweep's per-point work), numpy ~13 %.

Then fewer evaluations per truncation (issue 25, measured against the main branch as above):
the counting rectangle of 2 x 2 blocks starts on 4 top segments and one per side
(UPPER_RECTANGLE; the walk bisects them under the same MAX_BEND / MAX_TURN rule, in practice
each top segment once), the circle on 4 segments of its upper half; the real-axis points near
the hint and of the scan are evaluated only up to the lowest sign change, and the root reuses
log det at 0 and at the bracket's ends instead of evaluating them again. On 3 full lines
(sigma indices 2, 101, 198; 12128 truncations, every answer bitwise equal to main's kernel's,
counted with an instrumented build): 377k -> 245k log det evaluations (35 % fewer; an empty
truncation without hint 19.8 -> 11.9, one with tau_min and a hint 67.7 -> 44.9). With the
Python trims (the blocks passed to the kernel without a LogDet, _schur.conditioning taking each
block's moduli once and a run of equal coupling blocks once, the fluid table's cut-out check
on a Python complex), ``validation/bench_fig613.py --lines --against /work/main --rounds 4``
at load 8-10 on 2 cores: CPU s per round 4.75, 5.09, 5.24, 6.15 against main's 6.87, 6.72,
6.07, 7.07 (best rounds 21.8 % less, medians ~24 %), the maps bitwise equal; earlier 2-round
runs of intermediate states at load 8-15 gave 8-16 % (the CPU time of one code varies by up to
30 % between rounds at that load). The whole 200 x 200 map (validation/bench_fig613.py, 2
workers, run once at load ~10): workers' CPU 95.3 s (47.7 s per worker) against the 122.5 s
of the code before (measured at load 6-12) and 150.0 s of the one before that; scaled from the
quiet measurement above (64.2-72.8 s CPU per worker for the 150 s code) about 41-46 s CPU per
worker, so ~45-50 s wall on 2 idle cores (a projection: the wall time at load ~10 was 195 s).
The same run: the sampled cells equal to the dense path's to 2.5e-15 with the same has_tau
masks; one sphere truncation, N = 40..80, both kinds: 57x QZ (goal 30x).

Measured whole on a nearly idle machine (load 1.0-1.6, two consecutive runs of
``validation/bench_fig613.py --size 200 --sample 100`` on the code of these notes, with the
certified-empty marks of issue 23 in the sweep): 41.4 s and 38.5 s wall on 2 workers (40.2 and
37.7 s CPU per worker), against the dense path projected from 100 seeded cells at 621 s and
636 s (15.0x and 16.5x wall, 16.0x and 17.4x CPU); the sampled cells equal to 2.5e-15 with the
same has_tau masks; 2 of the 400,000 (cell, degree, kind) answers are empty without a proof and
marked uncertified. Issue 25's 60 s goal is met. One sphere truncation (N = 40, 60, 80, both
kinds, summed) in the same runs: 31.3x and 29.9x QZ, at the 30x goal, not reliably above it
(the 57x above was measured under load).

Then fewer and cheaper evaluations in the kernel (issue 25; the goal is >= 30x QZ at each N
and kind, and N = 40 was at 12-19x): STRIPS tried from 1e-4 (the 1e-2 strip, tried first
before, holds the sphere's near-axis complex eigenvalues at 50 bpm, and its count walked
52-142 nodes before the scan and the 1e-4 strip's 41-57 that answered: 143-242 evaluations
per empty truncation of the bench, now 41-57); a rectangle with g of opposite signs at its
real ends not walked (its count is odd); the real-axis points of the hint, the scan and the
root's brackets evaluated without the derivative (a third of a point); the log det compiled
apart for the sphere's scalar coupling and for the value alone (~10 % less per point).
Every answer bitwise equal to the main branch's kernel on the recorded calls of 8 full lines
of the 200 x 200 map (sigma indices 0, 2, 50, 100, 101, 150, 198, 199; 32,332 truncations)
and on the bench truncations. On lines 2, 101, 198 (12,128 truncations): 20.2 evaluations
per truncation -> 15.6 with the derivative and 3.7 without; the kernel's CPU time on their
calls, replayed alternately with main's kernel at load ~5: 0.79-0.90 s -> 0.61-0.63 s.
``validation/bench_fig613.py``'s truncation rows (CPU time, best of 7, main's kernel and this
one alternately in one process, load 4.5-6.5, three rounds): the sphere's lowest ratio (N = 40
subharmonic) 11.7-14.2x -> 36.7-38.1x, N = 40 harmonic 20-22x -> 47-86x, N = 60 29x ->
70-136x, N = 80 39-50x -> 167-278x. The fibre's lowest, N = 40 subharmonic: 49 evaluations
-> 28 with the derivative and 7 without, 0.375 -> 0.251 ms per truncation_taus call (CPU,
best of 15 rounds of 20 calls, the two kernels alternately; its QZ time varies too much under
load for the row's ratio, 26-40x -> 30-65x over those rounds, to show it).

Then the truncation without a hint whose first strip's count is odd by its ends' signs (one
real tau or an odd number below tau_max; issue 25): instead of the scan's points from 0 up to
the first sign change (all 49 where tau_min lies near tau_max, as the sphere's N = 40
subharmonic truncation of validation/bench_fig613.py, tau_min = 0.49991), the sign change of
g between 0 and tau_max^2 is bisected to the scan's spacing (6 evaluations of log g) and its
root certified in the first strip; only where that fails (another zero below, a complex one in
the strip) does the scan run, as before. Where both certify, the answers are bitwise equal
(the root is refined inside its dyadic cell; tests/test_contour.py, also on cells with 3-9
real tau below tau_max, where the bisection may find a higher one first). That truncation, one
BLAS thread, best of 300: 363 -> 275 us without a hint (240-263 us with tau_min as the hint).
The 12 lines of ``--lines``, against the code before (3 rounds each, alternately, load < 1):
5.20-5.27 -> 4.93-5.43 s CPU per round (within noise), the maps bitwise equal.
"""

from __future__ import annotations

import cmath
import math

import numpy as np
from scipy.linalg.lapack import zgetrf as _getrf, zgetri as _getri, zgetrs as _getrs

from .._threads import one_blas_thread
from ..discretise.hill import HillMatrices
from ._compiled import _schur
from .half_product import free_radius

#: Half-heights (and left margins) of the counting rectangle, relative to tau_max^2, tried in
#: turn until one holds no zero (:func:`_zeros_below`). A thinner rectangle lies inside a wider
#: one, so it holds no more zeros: 1e-4 first, 1e-6 where that holds some (complex eigenvalues
#: between the two), 1e-2 last, for a count of the others that failed. Issue 25: the 1e-2 strip
#: first (as before) holds the viscous sphere's complex eigenvalues near the axis at low beat
#: rates and its count walks 50-140 nodes there (Fig 6.13 at 50 bpm, m = 6, N = 40..80) against
#: 40-60 for the 1e-4 strip's zero count; on 3 lines of the map the 1e-4 strip's counts take
#: no more nodes than the 1e-2 strip's (11.6 against 11.9 per empty truncation).
STRIPS = (1e-4, 1e-6, 1e-2)
#: Radius of the disk around z* that must hold z* alone, relative to z*.
DISK = 1e-3
#: Nodes per contour before giving up (dense path instead).
MAX_NODES = 4000
#: The same for blocks larger than 2 x 2 (the cochlea's M x M), whose every node costs a block
#: LU sweep, O(K M^3) (0.04-0.12 s at M = 32, K = 81-283, under load): about twice the ~100
#: nodes a zero-free strip's upper half takes on the Fig 5.18 cells measured (gerbil, 116.9 Hz,
#: sigma = 1.16e9, M = 32, N = 141, tau_max = 1/2, 1e-4 strip: 106 harmonic, 92 subharmonic;
#: the whole closed rectangle took 211 and 183, and the budget was 500 then). Raised from 250
#: to 400 when the walk began to check log |g| too: the crowded cell (human, 63.62 Hz,
#: sigma = 1.85e9, M = 32, N = 51, subharmonic) then took 276 nodes (242 before; 270 from
#: UPPER_RECTANGLE's starting nodes), gave up at 250, and its refinement went on from the pair
#: (32, 64) to (64, 128): 141.6 -> 38.3 s CPU, tau_min moved by 2.8e-6
#: (tests/test_contour_blocks.py::test_crowded_cell_count_within_budget). On the seeded
#: 100-point sample of validation/bench_sweep.py no count fails at 400 (the largest took 342
#: nodes, 336 from UPPER_RECTANGLE's), so the higher budget costs nothing there (issue 25).
MAX_BLOCK_NODES = 400
#: The strips tried for such blocks: the viscous cochlea's truncations carry tens of complex
#: eigenvalues within 1 % of the axis (86 at the gerbil, 116.9 Hz, sigma = 1.16e9, M = 32,
#: N = 141), whose count in the 1e-2 strip took 1300 nodes against 210 for the zero count in
#: the 1e-4 one (both around the closed rectangle; the upper half takes about half).
BLOCK_STRIPS = (1e-4, 1e-6)
#: Blocks of fewer rows are inverted, not solved, in :func:`block_log_det`.
INVERSE_BELOW = 128
#: Largest mismatch between the change of log g read between neighbouring nodes and the one
#: predicted from g'/g, in the phase (radians) and in log |g|, and largest change of dz g'/g
#: along an edge (:func:`winding`).
MAX_TURN = math.pi / 4
MAX_BEND = 1.0
#: Relative offsets of the bracket tried around a hint, innermost first.
HINT_STEPS = (1e-7, 1e-5, 1e-3, 1e-2, 0.05)
#: Real-axis grid over [0, tau_max^2] when no hint brackets a zero and the count finds one.
SCAN_POINTS = 48
#: Margin on the bound of :func:`_free_disk`: its radius counts for FREE_MARGIN times itself
#: (the bound's rounding, relative <~ M eps COND_LIMIT <~ 1e-5, lies far inside).
FREE_MARGIN = 0.9
#: Relative step at which the first Newton solve of the root stops (the second one, inside
#: the root's dyadic cell, runs to rounding).
ROOT_RTOL = 1e-13


class LogDet:
    """z -> (log g(z), d log g / dz) of one bipartite pencil, g = det(A - sqrt(z) B) / det A
    (principal imaginary part); None where it meets a zero pivot. Blocks of 2 x 2 (the
    viscous sphere and fibre) by the compiled kernel; larger ones (the cochlea's M x M) by
    :func:`block_log_det`, one LAPACK LU per block and point."""

    def __init__(self, hill: HillMatrices):
        if not hill.bipartite:
            raise ValueError("LogDet needs a bipartite pencil (no self-coupling in B)")
        self.blocks = _kernel_blocks(hill)
        self.compiled = self.blocks[0].shape[1] == 2
        if not self.compiled:
            self.last = None  # (z, point(z)) of the last point evaluated
            lower, upper = self.blocks[1:]
            self.chained = bool(np.array_equal(upper[1:], -lower[:-1]))  # block_log_det
            self.rotated = rotated_coupling(*self.blocks)  # diagonal_log_det where not None
            # log det A, which the compiled kernel reads at z = 0 instead
            sign, modulus = np.linalg.slogdet(self.blocks[0] if self.rotated is None
                                              else self.rotated[0])
            self.offset = complex(modulus.sum(), np.angle(sign).sum())

    def __call__(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
        if self.compiled:  # log det A as the first point: g = det(A - tau B) / det A
            z = np.concatenate([[0.0], np.ravel(z)]).astype(complex)
            out, slope = np.empty_like(z), np.empty_like(z)
            if _schur.logdet(*self.blocks, z, out, slope):
                return None
            return out[1:] - out[0], slope[1:]
        z = np.ascontiguousarray(z, dtype=complex).ravel()
        out, slope = np.empty_like(z), np.empty_like(z)
        with one_blas_thread():
            for j, zj in enumerate(z):
                found = self.point(zj)
                if found is None:
                    return None
                out[j], slope[j] = found
        return out, slope

    def point(self, z: complex) -> tuple[complex, complex] | None:
        """(log g(z), d log g / dz) at one z (blocks larger than 2 x 2); the last point's
        answer is kept and returned again for the same z (:func:`_odd_below` evaluates the
        count's first node)."""
        if self.last is not None and self.last[0] == z:
            return self.last[1]
        found = (block_log_det(*self.blocks, z, self.chained) if self.rotated is None
                 else diagonal_log_det(*self.rotated, z))
        if found is not None:
            value = found[0] - self.offset
            found = complex(value.real, math.remainder(value.imag, 2 * math.pi)), found[1]
        self.last = z, found
        return found

    def turns(self, path: np.ndarray) -> float | None:
        """Zeros of g inside the contour symmetric about the real axis whose upper half is
        ``path`` (:func:`winding`), not rounded, by the compiled adaptive walk; None if it
        stops."""
        path = np.array(path, dtype=complex)
        if self.compiled:
            return _schur.winding(*self.blocks, path, MAX_BEND, MAX_TURN, MAX_NODES)
        with one_blas_thread():  # M x M blocks: BLAS threads only cost (_threads.py)
            return _schur.winding_of(self.point, path, MAX_BEND, MAX_TURN, MAX_BLOCK_NODES)


def _kernel_blocks(hill: HillMatrices) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(diag, lower, upper) of ``hill`` as C-contiguous complex128 arrays (the kernel's
    buffers): themselves when they are already (an assembled pencil and its cut-outs), else
    copies."""
    d, lower, upper = hill.diag, hill.lower, hill.upper
    if (d.dtype.char == lower.dtype.char == upper.dtype.char == "D" and d.flags.c_contiguous
            and lower.flags.c_contiguous and upper.flags.c_contiguous):
        return d, lower, upper
    return (np.ascontiguousarray(d, dtype=complex), np.ascontiguousarray(lower, dtype=complex),
            np.ascontiguousarray(upper, dtype=complex))


def block_log_det(diag: np.ndarray, lower: np.ndarray, upper: np.ndarray, z: complex,
                  chained: bool = False) -> tuple[complex, complex] | None:
    """(log det(A - tau B), its derivative in z) at z = tau^2 of a bipartite block-tridiagonal
    pencil with blocks of any size, by block elimination; None on an exactly singular pivot
    block or a non-finite value. ``chained``: upper[k] = -lower[k - 1] for every k >= 1 (the
    cochlea's pencils: one coupling matrix, upper = -lower), which saves a solve per block.

    The Schur complements S_0 = A_0, S_k = A_k - z L_{k-1} X_{k-1} (X_k = S_k^{-1} U_k,
    L = lower, U = upper) are factorised by LAPACK ?getrf (partial pivoting inside the block),
    so log det = sum_k log det S_k; their derivatives are S_0' = 0,
    S_k' = L_{k-1} V_{k-1} with V_k = z Y_k X_k - X_k and Y_k = S_k^{-1} S_k', and
    (log det)' = sum_k tr Y_k (the 2 x 2 kernel ``_schur.c`` carries the same recursion):
    O(K M^3). Chained, Y_k = -X_k V_{k-1} needs no solve of its own (S_k^{-1} L_{k-1} = -X_k).
    Blocks of fewer rows than INVERSE_BELOW are inverted from their LU (?getri) and solved by
    products, larger ones by ?getrs. Issue 25: OpenBLAS's triangular solves run 2-4x slower per
    flop than its products at M = 32..64 (one thread), where the inverse and products take
    half the solves' time; at M = 128 the two cost the same, at 256 the solves less."""
    K, M, _ = diag.shape
    S, V = diag[0].copy(), None  # V_{k-1} (S_k' = L_{k-1} V_{k-1}); S_0' = 0
    value, slope = 0.0j, 0.0j
    unmoved = np.arange(M)  # the pivots of an LU without row exchanges
    for k in range(K):
        factored = _log_lu(S, unmoved)
        if factored is None:
            return None
        lu, pivots, log_det = factored
        value += log_det
        last = k == K - 1
        if last and V is None:
            break
        solve = _solver(lu, pivots)
        if solve is None:
            return None
        X = None if last else solve(upper[k])
        if V is not None:
            Y = -(X @ V) if chained and not last else solve(lower[k - 1] @ V)
            slope += np.trace(Y)
        if last:
            break
        V = -X if V is None else z * (Y @ X) - X
        S = diag[k + 1] - z * (lower[k] @ X)
    if not (cmath.isfinite(value) and cmath.isfinite(slope)):
        return None
    return complex(value), complex(slope)


def _log_lu(S: np.ndarray, unmoved: np.ndarray) -> tuple[np.ndarray, np.ndarray, complex] | None:
    """(LU, pivots, log det S) of the block S (overwritten) by LAPACK ?getrf, the pivots' row
    exchanges counted against ``unmoved`` (np.arange(M)) as i pi each; None on an exactly
    singular S."""
    lu, pivots, info = _getrf(S, overwrite_a=1)
    if info != 0:
        return None
    swaps = np.count_nonzero(pivots != unmoved)
    return lu, pivots, np.log(lu.diagonal()).sum() + 1j * math.pi * swaps


def rotated_coupling(diag: np.ndarray, lower: np.ndarray,
                     upper: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """(U^H A_k U for every diagonal block A_k, the eigenvalues l of L) where every coupling
    block is one skew-Hermitian L (lower[k] = L, upper[k] = -L), L = U diag(l) U^H with U
    unitary; None for any other coupling. The cochlea's two-sided pencils have L = i kappa C,
    C real symmetric (thesis 5.2), so U is real orthogonal and l = i kappa eig(C).

    The similarity by the block diagonal diag(U, ..., U) leaves det(A - tau B) and det A, hence
    g, unchanged, keeps every block's LU as stable as before (U unitary), and makes every
    coupling block diagonal (:func:`diagonal_log_det`)."""
    if not len(lower):  # one block: no coupling to rotate
        return None
    coupling = lower[0]
    if not (np.array_equal(lower, np.broadcast_to(coupling, lower.shape))
            and np.array_equal(upper, np.broadcast_to(-coupling, upper.shape))
            and np.array_equal(coupling, -coupling.conj().T)):
        return None
    hermitian = 1j * coupling  # L = -i H: l = -i h
    if not hermitian.imag.any():
        h, U = np.linalg.eigh(hermitian.real)
        rotated = (U.T @ diag.real @ U) + 1j * (U.T @ diag.imag @ U)
    else:
        h, U = np.linalg.eigh(hermitian)
        rotated = U.conj().T @ diag @ U
    return np.ascontiguousarray(rotated, dtype=complex), -1j * h


def diagonal_log_det(diag: np.ndarray, coupling: np.ndarray,
                     z: complex) -> tuple[complex, complex] | None:
    """(log det(A - tau B), its derivative in z) at z = tau^2 of a bipartite block-tridiagonal
    pencil whose coupling blocks are one diagonal L = diag(``coupling``): lower L, upper -L (the
    cochlea's after :func:`rotated_coupling`); None as :func:`block_log_det`.

    The Schur complements of :func:`block_log_det` with U = -L become
    S_{k+1} = A_{k+1} + z L S_k^{-1} L, and their derivatives
    S_{k+1}' = L (S_k^{-1} - z Y_k S_k^{-1}) L with Y_k = S_k^{-1} S_k' (S_0' = 0), so
    (log det)' = sum_k tr Y_k: per block one LU, the inverse (?getri below INVERSE_BELOW rows,
    else ?getrs on the identity, the faster of the two there) and two products, where
    block_log_det's chained recursion takes the inverse (or a solve with M right-hand sides)
    and four products; the scalings by L cost O(M^2). The sweep runs in the compiled kernel
    (``_schur.rotated_logdet``, SciPy's ?getrf, ?getri, ?getrs and ?gemm): issue 25, from
    numpy it took 2-3x longer at M = 16..32 (the LAPACK and numpy calls' overhead, ~10 per
    block), see the module notes."""
    return _schur.rotated_logdet(diag, coupling, complex(z), INVERSE_BELOW)


def _solver(lu: np.ndarray, pivots: np.ndarray):
    """right -> S^{-1} right from the LU of S (:func:`block_log_det`): by S^{-1} (?getri)
    below INVERSE_BELOW rows, else by ?getrs; None if the inverse fails."""
    if lu.shape[0] < INVERSE_BELOW:
        inverse, info = _getri(lu, pivots, overwrite_lu=1)
        return None if info != 0 else (lambda right: inverse @ right)
    return lambda right: _getrs(lu, pivots, right)[0]


def winding(log_g: LogDet, path: np.ndarray) -> int | None:
    """Zeros of g inside the contour symmetric about the real axis whose upper half is ``path``
    (from a real point, counter-clockwise around the inside, to another), by the argument
    principle; None if it cannot be trusted (a zero pivot, MAX_NODES evaluations, a count
    farther than 0.05 from an integer).

    g takes conjugate values at conjugate points (its zeros are real or conjugate pairs), so the
    lower half turns the phase of g as much as the upper one: the kernel reads the upper half
    and doubles it (for blocks larger than 2 x 2 it calls back :meth:`LogDet.point` at each
    node; their g is real on the real axis too, see the module notes). Along each edge the
    phase change over a segment is predicted by the
    trapezoid rule on g'/g, Im (dz (g'/g(z_0) + g'/g(z_1)) / 2), and read modulo 2 pi from the
    two values of log g; a segment is bisected until dz g'/g changes along it by at most
    MAX_BEND (the prediction then errs by much less than pi) and the reading agrees with the
    prediction within MAX_TURN, which fixes the multiple of 2 pi, and so does the change of
    log |g| with the trapezoid's real part (a pair of zeros under one segment turns the phase
    by 2 pi, which the reading cannot see, but not log |g|). A zero close to an edge makes
    g'/g vary there like 1/distance and forces the nodes closer (a zero pair between two far
    nodes would otherwise turn the phase by 2 pi unseen); the many far-away zeros, which make
    |g'/g| large but smooth, do not."""
    total = log_g.turns(path)
    if total is None:
        return None
    count = round(total)
    return count if abs(total - count) <= 0.05 else None


def _upper_rectangle(top: int, side: int) -> np.ndarray:
    """The upper half of [0, 1] x [-1, 1] from (1, 0) counter-clockwise to (0, 0): ``top``
    segments along the top, ``side`` on each side."""
    sides = np.linspace(0.0, 1.0, side, endpoint=False)
    tops = np.linspace(1.0, 0.0, top, endpoint=False)
    return np.concatenate([1 + 1j * sides, tops + 1j, 1j * (1 - sides), [0.0]])


#: The starting nodes of the counting rectangle: 4 segments along the top, one on each side
#: (the rectangles are 50-10^6 times wider than high, so each side is short); the walk
#: (:func:`winding`) bisects them under the same rule as any others. Issue 25: against the 8
#: top segments and 4 per side before, on 3 lines of the Fig 6.13 grid (12128 truncations,
#: 2 x 2 blocks) the kernel's time fell by 24 %, and on the seeded 100-point Fig 5.18 sample
#: (validation/bench_sweep.py's sample_points; the cochlea's M x M blocks) the counts' nodes by
#: 12 % (11473 -> 10073; none failed, the largest took 336), every answer bitwise the same.
UPPER_RECTANGLE = _upper_rectangle(4, 1)


def rectangle(left: float, right: float, half_height: float,
              shape: np.ndarray = UPPER_RECTANGLE) -> np.ndarray:
    """The upper half (:func:`winding`) of the rectangle [left, right] x [-half_height,
    half_height], on the starting nodes ``shape`` (an upper rectangle of [0, 1] x [-1, 1];
    the kernel refines them)."""
    return left + (right - left) * shape.real + half_height * (1j * shape.imag)


def circle(centre: float, radius: float, count: int = 8) -> np.ndarray:
    """The upper half (:func:`winding`) of a circle, ``count // 2`` segments (around the lone
    zero at its centre, g'/g ~ 1 / (z - centre) turns by pi/4 per segment of the default 8:
    |dz (g'/g)| changes by (pi/4)^2 ~ 0.6 < MAX_BEND, no bisection needed)."""
    nodes = centre + radius * np.exp(1j * math.pi * np.arange(count // 2 + 1) / (count // 2))
    nodes[-1] = centre - radius  # on the real axis exactly
    return nodes


#: The unit circle's upper half (8 segments around), from which the kernel places the circle
#: around z* as :func:`circle` does: z* + rho u (the last node z* - rho).
UNIT_HALF_CIRCLE = circle(0.0, 1.0)


def _zeros_below(log_g: LogDet, right: float, z_max: float,
                 strips: tuple[float, ...] | None = None) -> int | None:
    """Zeros of g in the rectangle [-a, right] x [-a, a], a = s z_max for the first s of
    ``strips`` (by default STRIPS, BLOCK_STRIPS for blocks larger than 2 x 2) that finds none
    (else the count in the last; None if a count fails): complex eigenvalues close to the
    real axis are left outside a thinner strip."""
    if strips is None:
        strips = STRIPS if log_g.compiled else BLOCK_STRIPS
    count = None
    for strip in strips:
        side = strip * z_max
        count = winding(log_g, rectangle(-side, right, side))
        if count == 0:
            break
    return count


def none_up_to(hill: HillMatrices, tau_max: float, solves=None) -> bool:
    """Whether the count proves that one bipartite truncation has no real tau <= tau_max: no
    zero of g in a thin rectangle around [0, tau_max^2 (1 + 1e-6)] (:func:`_zeros_below`).
    False where it cannot (a complex eigenvalue within 1e-6 tau_max^2 of the real axis, a real
    one, a zero pivot, the node budget). For blocks larger than 2 x 2 a disk free of
    eigenvalues that holds every rectangle the count would walk (:func:`_free_disk`) proves it
    first, at a few per cent of a count's cost; else g < 0 at the rectangles' right corner
    (:func:`_odd_below`, one evaluation) declines it before the count. ``solves``: the disk
    bound's block solves (:func:`~spectralshell.solvers.half_product.free_radius`), e.g. kept
    from a larger truncation."""
    z_max = tau_max * tau_max
    right = z_max * (1 + 1e-6)
    if hill.diag.shape[1] > 2 and _free_disk(hill, math.hypot(right, max(BLOCK_STRIPS) * z_max),
                                             solves):
        return True
    log_g = LogDet(hill)
    if not log_g.compiled and _odd_below(log_g, right, z_max):
        return False
    return _zeros_below(log_g, right, z_max) == 0


def _odd_below(log_g: LogDet, right: float, z_max: float) -> bool:
    """Whether g < 0 at the real corner nearest 0 on the right of the rectangles that
    :func:`_zeros_below` would count (BLOCK_STRIPS): then, as g(0) = 1 and g is a real
    polynomial on the real axis, an odd number of real zeros lies between, inside every one of
    those rectangles, and none of their counts can be zero. One evaluation (the count's first
    node, kept by :meth:`LogDet.point`) instead of the tens to hundreds of nodes a count takes
    to find them. False where g there is not clearly real (its phase farther than pi/3 from
    0 or pi) or not evaluated (a zero pivot): the counts decide then. Issue 25."""
    corner = min(rectangle(-s * z_max, right, s * z_max)[0].real
                 for s in BLOCK_STRIPS)
    found = log_g.point(complex(corner))
    return found is not None and math.cos(found[0].imag) < -0.5


def _free_disk(hill: HillMatrices, reach: float, solves=None) -> bool:
    """Whether the disk |z| <= ``reach`` holds no zero of g, proved by the bound of
    :func:`~spectralshell.solvers.half_product.free_radius` (no eigenvalue with |tau| < r) with
    the margin FREE_MARGIN on r.

    Notes
    -----
    A zero-free disk holds every rectangle of :func:`_zeros_below` inside it, so the count
    there is zero in each strip: the same claim as the count's, and a stronger one (no
    eigenvalue at all, real or complex, with |tau|^2 <= reach). It succeeds where every
    eigenvalue lies well beyond tau_max (on the Fig 5.18 cells whose kind has nothing below the
    other kind's tau_min, the nearest |tau| is 4-14 tau_max and the bound 2-3 tau_max at
    M = 64..256), and costs about 3.7 K M^3 complex flops (one LU and one solve per block of
    A, two block products), against about 96 K M^3 for a count of 17 nodes; where it fails the
    count runs as before. Issue 25 (measured in the Cost notes of
    :mod:`spectralshell.solvers.marginal`)."""
    with one_blas_thread():  # M x M blocks: BLAS threads only cost (_threads.py)
        radius = free_radius(hill, solves)
    return (FREE_MARGIN * radius) ** 2 > reach


def smallest_real_tau(hill: HillMatrices, tau_max: float,
                      hint: float | None = None) -> tuple[float | None, float] | None:
    """(tau_min or None, complete_to) of one bipartite truncation, certified as in the module
    notes: no real tau below tau_min (none at all <= tau_max when None), and every real tau up
    to complete_to is tau_min. None when the certificate cannot be had (use the dense path).
    Blocks of 2 x 2 only; larger ones have the count alone, :func:`none_up_to`.

    The steps run in the compiled kernel (``_schur.smallest``), one call per truncation: the
    sign change near ``hint`` squared (HINT_STEPS), else the first strip's count and the
    real-axis scan (SCAN_POINTS; first, where that count is odd by the signs of g at its real
    ends, the sign change over [0, z_max] bisected to the scan's spacing, kept if its root's
    certificate holds in the first strip), then the other strips; the root by safeguarded Newton to
    1e-13 and again inside its dyadic cell of width 2^-30 |z| (so that the answer does not
    depend on the hint); the counts of :func:`rectangle` (STRIPS) below z* - rho / 2 and of
    :func:`circle` around z*, each as :func:`winding` takes them. Called from Python, these
    steps cost about as much as the counts themselves (issue 25)."""
    if not hill.bipartite:
        raise ValueError("smallest_real_tau needs a bipartite pencil (no self-coupling in B)")
    if hill.diag.shape[1] != 2:
        raise ValueError("smallest_real_tau needs 2 x 2 blocks (larger ones: none_up_to)")
    z_max = tau_max * tau_max
    z = _schur.smallest(*_kernel_blocks(hill), UPPER_RECTANGLE, UNIT_HALF_CIRCLE, HINT_STEPS,
                        STRIPS, z_max, -1.0 if hint is None else hint * hint, DISK,
                        SCAN_POINTS, MAX_BEND, MAX_TURN, MAX_NODES, ROOT_RTOL)
    if z is None:
        return None
    if math.isnan(z):
        return None, tau_max
    rho = DISK * z
    return math.sqrt(z), math.sqrt(z + rho / 2)
