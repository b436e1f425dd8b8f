/* log det(A - tau B) of a block-tridiagonal bipartite Hill pencil at points z = tau^2, and the
 * zero count of det(A - tau B) inside a contour in z from its upper half, and a real zero
 * (spectralshell/solvers/contour.py).
 *
 * A is block diagonal (blocks A_k), B couples block k only to k - 1 (``lower`` L_k = B_{k,k-1})
 * and k + 1 (``upper`` U_k = B_{k,k+1}). Block elimination without pivoting across blocks gives
 * the Schur complements S_0 = A_0, S_k = A_k - z L_k S_{k-1}^{-1} U_{k-1}: only tau^2 = z
 * enters, and det(A - tau B) = prod_k det S_k. The blocks are 2 x 2 (the viscous sphere's and
 * fibre's pair of components), each S_{k-1}^{-1} taken by its adjugate, so one point costs O(K)
 * against O(K^3) for an eigenvalue solve.
 *
 * Python:
 * logdet(diag, lower, upper, z, out, slope) -> int status. diag (K, 2, 2), lower and upper
 *   (K - 1, 2, 2), z, out and slope (n) are C-contiguous complex128 buffers. On success
 *   (status 0) out[j] = log prod_k det S_k(z_j) (principal logarithm: the imaginary part is the
 *   phase modulo 2 pi) and slope[j] its derivative in z; the product is carried as a mantissa
 *   and a power of 2, so it neither overflows nor underflows. Status 1: a pivot of some S_k is
 *   exactly zero or a value is not finite.
 * winding(diag, lower, upper, nodes, max_bend, max_turn, max_nodes) -> float or None: the
 *   number of zeros of det(A - tau B) in z inside a contour symmetric about the real axis, given
 *   by its upper half ``nodes`` (complex128, at least 2), a path from one real point to another
 *   that runs counter-clockwise around the inside: twice the phase change along the path, in
 *   turns (det(A - tau B) is real on the real axis and takes conjugate values at conjugate
 *   points, so the lower half turns the phase as much as the upper), each edge bisected
 *   adaptively (see ``segment``); None on a zero pivot or after max_nodes evaluations.
 * winding_of(evaluate, nodes, max_bend, max_turn, max_nodes) -> float or None: the same count,
 *   by the same walk along the upper half ``nodes``, for any g real on the real axis with
 *   conjugate values at conjugate points: ``evaluate(z)`` (a Python callable, called with the
 *   GIL held) returns (log g(z), d log g / dz) as two complex numbers, or None where it cannot
 *   (a zero pivot); its exceptions propagate. Used for blocks larger than 2 x 2 (the
 *   cochlea's M x M), whose evaluation (block LU by LAPACK) costs far more than the call.
 *   Their g has the symmetry too, in both bipartite forms (real blocks in the real form; the
 *   reality condition in the two-sided one; tests/test_contour_blocks.py checks it on the
 *   cochlea), so no closed-polygon variant is kept.
 * root(diag, lower, upper, lo, hi, rtol) -> float, NaN or None: the zero of det(A - tau B) in
 *   the real interval [lo, hi] of z, where it changes sign, by Newton's method on d/dz log det
 *   safeguarded by bisection (each step keeps the sign change), started at the midpoint and
 *   stopped once a step is at most rtol |z|; NaN if the sign does not change between lo and hi,
 *   None on a zero pivot.
 * smallest(diag, lower, upper, rectangle, circle, hint_steps, strips, z_max, hint_z, disk,
 *   scan, max_bend, max_turn, max_nodes, root_rtol) -> float, NaN or None: every step of
 *   contour.smallest_real_tau for 2 x 2 blocks in one call (its module notes): a sign change
 *   of g on the real points hint_z (1 -+ hint_steps), else the count in the first strip's
 *   rectangle up to z_max (1 + 1e-6) (odd by its ends' signs: first the sign change over
 *   [0, z_max] bisected to z_max / scan, its root kept if certified in the first strip) and a
 *   scan of scan + 1 points over [0, z_max], else the
 *   other strips (a rectangle with g of opposite signs at its real ends is not walked: its
 *   count is odd, so not zero; the real points are evaluated without the derivative); the
 *   root (root() to root_rtol, then to 4 eps inside its dyadic cell of width 2^-30 |z|);
 *   the counts below z* - rho / 2 (strips in turn) and around the circle of radius rho =
 *   disk z*. rectangle: the upper half of [0, 1] x [-1, 1] (contour.UPPER_RECTANGLE),
 *   placed as left + (right - left) x + i a y; circle: the unit upper half circle, placed as
 *   z* + rho u (the last node z* - rho). Returns z* = tau_min^2, NaN where no real
 *   tau^2 <= z_max exists, None where the certificate cannot be had.
 * sweep(inv, coupling, g, start) -> None: one pass of the block-tridiagonal solve of
 *   solvers/shift_invert.py, in place on g (m, b) (complex128, C-contiguous like every buffer
 *   here): start None, the backward pass g_{m-1} <- inv_{m-1} g_{m-1},
 *   g_j <- inv_j (g_j - C_j g_{j+1}) for j = m-2..0; start a vector x (b), the forward pass
 *   g_j <- g_j - inv_j (C_j p), p = x for j = 0, else the new g_{j-1}. inv (m, b, b); coupling
 *   (c, b, b) with c = 1 (one block for every j: the forcing repeated) or one block C_j per j.
 *   Each block product is one BLAS zgemv (SciPy's: use_scipy()); the blocks are small
 *   (b = 16..128), and the per-call overhead of 4 m matrix-vector products from Python is what
 *   this saves.
 * rotated_logdet(diag, coupling, z, inverse_below) -> (value, slope) or None: log det(A - tau B)
 *   and its derivative in z at one z = tau^2 for M x M blocks coupled by one diagonal L
 *   (lower L, upper -L: the cochlea after contour.rotated_coupling), by the Schur recursion of
 *   contour.diagonal_log_det; diag (K, M, M), coupling (M). Per block one LAPACK ?getrf, the
 *   inverse (?getri below inverse_below rows, else ?getrs on the identity) and two ?gemm, the
 *   routines SciPy's own (use_scipy());
 *   None on an exactly singular block or a non-finite value. From Python the ~10 calls per
 *   block cost more than their flops at M = 16..32.
 * use_scipy(zgemv, zgetrf, zgetri, zgetrs, zgemm) -> None: hands over the BLAS and LAPACK
 *   routines of sweep() and rotated_logdet(), scipy.linalg.cython_blas's and cython_lapack's
 *   capsules (solvers/_compiled.py, once, at import).
 * conditioning(diag, lower, upper) -> (cond, coupled): the largest 1-norm condition number
 *   ||A_k||_1 ||A_k^{-1}||_1 of the blocks and the largest ||A_k^{-1}||_1 times
 *   max_k ||L_k||_1 + max_k ||U_k||_1 (the inverse by the adjugate: ||adj A_k||_1 is the largest
 *   row sum of |A_k|); both inf where a block is singular (solvers/half_product.py compares
 *   them with its limit).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <complex.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <string.h>

/* Evaluations allowed to one root(). */
#define ROOT_STEPS 200

static inline double norm1(double complex z) { return fabs(creal(z)) + fabs(cimag(z)); }

/* Whether the coupling blocks L, U (2 x 2) are l I and u I. */
static inline int scalar_pair(const double complex *L, const double complex *U)
{
    return L[1] == 0.0 && L[2] == 0.0 && L[0] == L[3] && U[1] == 0.0 && U[2] == 0.0 &&
           U[0] == U[3];
}

/* Whether every coupling block pair of a pencil of K blocks is (l I, u I) (the sphere's):
 * checked once per pencil rather than per block and point. */
static int scalar_coupling(const double complex *lower, const double complex *upper,
                           Py_ssize_t K)
{
    for (Py_ssize_t k = 0; k + 1 < K; k++)
        if (!scalar_pair(lower + 4 * k, upper + 4 * k))
            return 0;
    return 1;
}

#if defined(__GNUC__)
#define ALWAYS_INLINE static inline __attribute__((always_inline))
#else
#define ALWAYS_INLINE static inline
#endif

/* The body of schur_logdet(), compiled once for each constant (scalar, derivative) there. */
ALWAYS_INLINE int schur_steps(const double complex *diag, const double complex *lower,
                              const double complex *upper, Py_ssize_t K, const int scalar,
                              const int derivative, double complex z, double complex *out,
                              double complex *slope)
{
    double complex a = diag[0], b = diag[1], c = diag[2], d = diag[3];
    double complex da = 0.0, db = 0.0, dc = 0.0, dd = 0.0; /* S' */
    double complex det = 1.0, dlog = 0.0;
    long scale = 0;
    for (Py_ssize_t k = 1;; k++) {
        double complex dk = a * d - b * c;
        if (dk == 0.0)
            return 1;
        const double complex r = 1.0 / dk;
        if (derivative)
            dlog += r * (da * d + a * dd - db * c - b * dc);
        det *= dk;
        if ((k & 7) == 0 || k == K) {
            int e;
            frexp(norm1(det), &e);
            det = ldexp(creal(det), -e) + I * ldexp(cimag(det), -e);
            scale += e;
        }
        if (k == K)
            break;
        const double complex *L = lower + 4 * (k - 1), *U = upper + 4 * (k - 1);
        const double complex *Ak = diag + 4 * k;
        /* N = M U, T = z M S' X (T with the derivative only) */
        double complex n00, n01, n10, n11, t00 = 0.0, t01 = 0.0, t10 = 0.0, t11 = 0.0;
        if (scalar || scalar_pair(L, U)) {
            /* L = l I, U = u I (the sphere's coupling G = q I): with S^{-1} = r adj S,
             * N = l u r adj S and M S' X = l u r^2 (adj S) S' (adj S) */
            const double complex w = L[0] * U[0] * r;
            n00 = w * d;
            n01 = -w * b;
            n10 = -w * c;
            n11 = w * a;
            if (derivative) {
                const double complex v = z * w * r;
                double complex q00 = d * da - b * dc, q01 = d * db - b * dd; /* (adj S) S' */
                double complex q10 = a * dc - c * da, q11 = a * dd - c * db;
                t00 = v * (q00 * d - q01 * c);
                t01 = v * (q01 * a - q00 * b);
                t10 = v * (q10 * d - q11 * c);
                t11 = v * (q11 * a - q10 * b);
            }
        } else {
            /* S^{-1} = r [[d, -b], [-c, a]]; M = L S^{-1}, X = S^{-1} U */
            double complex m00 = r * (L[0] * d - L[1] * c), m01 = r * (L[1] * a - L[0] * b);
            double complex m10 = r * (L[2] * d - L[3] * c), m11 = r * (L[3] * a - L[2] * b);
            n00 = m00 * U[0] + m01 * U[2];
            n01 = m00 * U[1] + m01 * U[3];
            n10 = m10 * U[0] + m11 * U[2];
            n11 = m10 * U[1] + m11 * U[3];
            if (derivative) {
                double complex x00 = r * (d * U[0] - b * U[2]), x01 = r * (d * U[1] - b * U[3]);
                double complex x10 = r * (a * U[2] - c * U[0]), x11 = r * (a * U[3] - c * U[1]);
                /* P = M S' (2 x 2), then T = z P X */
                double complex p00 = m00 * da + m01 * dc, p01 = m00 * db + m01 * dd;
                double complex p10 = m10 * da + m11 * dc, p11 = m10 * db + m11 * dd;
                t00 = z * (p00 * x00 + p01 * x10);
                t01 = z * (p00 * x01 + p01 * x11);
                t10 = z * (p10 * x00 + p11 * x10);
                t11 = z * (p10 * x01 + p11 * x11);
            }
        }
        if (derivative) { /* S_k' = -N + T */
            da = -n00 + t00;
            db = -n01 + t01;
            dc = -n10 + t10;
            dd = -n11 + t11;
        }
        a = Ak[0] - z * n00;
        b = Ak[1] - z * n01;
        c = Ak[2] - z * n10;
        d = Ak[3] - z * n11;
    }
    if (!isfinite(creal(det)) || !isfinite(cimag(det)) || det == 0.0 || !isfinite(creal(dlog)) ||
        !isfinite(cimag(dlog)))
        return 1;
    *out = clog(det) + scale * M_LN2;
    if (derivative)
        *slope = dlog;
    return 0;
}

/* log det(A - tau B) at z = tau^2 into *out and its derivative in z into *slope (slope NULL:
 * the value alone, by the same arithmetic, for the real-axis points whose sign is all that is
 * read); 1 on a zero pivot or a non-finite value. The derivative is carried forward: with
 * M = L S^{-1} and X = S^{-1} U, S_k' = -M U + z M S' X, and (log det S)' = trace(S^{-1} S');
 * a coupling that is a multiple of the identity (checked per block, exactly, unless
 * ``scalar`` says that every one is: scalar_coupling) takes a shorter form. Issue 25: without
 * the derivative a point costs about a third; the four variants compiled apart (no per-block
 * test of the coupling or of the derivative), a point with it ~10 % less, same arithmetic. */
static int schur_logdet(const double complex *diag, const double complex *lower,
                        const double complex *upper, Py_ssize_t K, int scalar, double complex z,
                        double complex *out, double complex *slope)
{
    if (slope != NULL)
        return scalar ? schur_steps(diag, lower, upper, K, 1, 1, z, out, slope)
                      : schur_steps(diag, lower, upper, K, 0, 1, z, out, slope);
    return scalar ? schur_steps(diag, lower, upper, K, 1, 0, z, out, NULL)
                  : schur_steps(diag, lower, upper, K, 0, 0, z, out, NULL);
}

static int complex_buffer(PyObject *obj, Py_buffer *view, const char *name, int ndim)
{
    if (PyObject_GetBuffer(obj, view, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | PyBUF_WRITABLE) < 0)
        return -1;
    if (view->ndim != ndim || view->itemsize != 16 || strcmp(view->format, "Zd") != 0) {
        PyErr_Format(PyExc_TypeError, "%s must be a %d-d C-contiguous complex128 array", name,
                     ndim);
        PyBuffer_Release(view);
        return -1;
    }
    return 0;
}

static void release(Py_buffer *v, int count)
{
    for (int i = 0; i < count; i++)
        PyBuffer_Release(&v[i]);
}

/* The buffers of a pencil (diag, lower, upper) and of `count - 3` 1-d arrays of one length n
 * (at least `least`) from the first `count` args; -1 (exception set, nothing held) if any is of
 * the wrong type or of inconsistent shape. */
static int pencil_buffers(PyObject *const *args, const char *usage, const char **names,
                          int count, Py_ssize_t least, Py_buffer *v)
{
    for (int i = 0; i < count; i++)
        if (complex_buffer(args[i], &v[i], names[i], i < 3 ? 3 : 1) < 0) {
            release(v, i);
            return -1;
        }
    Py_ssize_t K = v[0].shape[0], n = count > 3 ? v[3].shape[0] : 0;
    int ok = v[0].shape[1] == 2 && v[0].shape[2] == 2 && K >= 1 && n >= least;
    for (int i = 1; i < 3; i++)
        ok = ok && v[i].shape[0] == K - 1 && v[i].shape[1] == 2 && v[i].shape[2] == 2;
    for (int i = 4; i < count; i++)
        ok = ok && v[i].shape[0] == n;
    if (!ok) {
        release(v, count);
        PyErr_Format(PyExc_ValueError, "%s: inconsistent shapes, or blocks not 2 x 2", usage);
        return -1;
    }
    return 0;
}

/* One log det (a 2 x 2 block pencil, or a Python callable when ``callback`` is set) and the
 * adaptive quadrature state of winding(). */
typedef struct {
    const double complex *diag, *lower, *upper;
    Py_ssize_t K;
    int scalar; /* scalar_coupling() of the pencil */
    PyObject *callback;
    double max_bend, max_turn;
    long budget; /* evaluations left */
} Contour;

/* (log g, slope) at z from the Python callable: 0, or 1 when it returns None or raises (then
 * the exception stays set for the caller). */
static int call_back(PyObject *callback, double complex z, double complex *value,
                     double complex *slope)
{
    PyObject *arg = PyComplex_FromDoubles(creal(z), cimag(z));
    if (arg == NULL)
        return 1;
    PyObject *got = PyObject_CallOneArg(callback, arg);
    Py_DECREF(arg);
    if (got == NULL)
        return 1;
    int failed = 1;
    if (got != Py_None) {
        PyObject *pair = PySequence_Fast(got, "evaluate must return (value, slope) or None");
        if (pair != NULL && PySequence_Fast_GET_SIZE(pair) == 2) {
            Py_complex v = PyComplex_AsCComplex(PySequence_Fast_GET_ITEM(pair, 0));
            Py_complex d = PyComplex_AsCComplex(PySequence_Fast_GET_ITEM(pair, 1));
            if (!PyErr_Occurred()) {
                *value = v.real + I * v.imag;
                *slope = d.real + I * d.imag;
                failed = !(isfinite(v.real) && isfinite(v.imag) && isfinite(d.real) &&
                           isfinite(d.imag));
            }
        } else if (pair != NULL)
            PyErr_SetString(PyExc_TypeError, "evaluate must return (value, slope) or None");
        Py_XDECREF(pair);
    }
    Py_DECREF(got);
    return failed;
}

/* The shared preamble of winding() and root(): exactly `want` args, of which the first `count`
 * are the pencil and 1-d arrays (see pencil_buffers), held in v, the pencil also in *c (no
 * budget yet, no callback); -1 (exception set, nothing held) otherwise. */
static int contour_args(PyObject *const *args, Py_ssize_t nargs, Py_ssize_t want,
                        const char *usage, const char **names, int count, Py_ssize_t least,
                        Py_buffer *v, Contour *c)
{
    if (nargs != want) {
        PyErr_Format(PyExc_TypeError, "%s takes %zd arguments", usage, want);
        return -1;
    }
    if (pencil_buffers(args, usage, names, count, least, v) < 0)
        return -1;
    *c = (Contour){.diag = (const double complex *)v[0].buf,
                   .lower = (const double complex *)v[1].buf,
                   .upper = (const double complex *)v[2].buf, .K = v[0].shape[0]};
    c->scalar = scalar_coupling(c->lower, c->upper, c->K);
    return 0;
}

/* (log g, slope) at z into *value, *slope (slope NULL: log g alone), one of the budget; 1 on
 * failure (the budget spent, a zero pivot, the callback's None or exception). */
static int evaluate(Contour *c, double complex z, double complex *value, double complex *slope)
{
    if (c->budget-- <= 0)
        return 1;
    if (c->callback != NULL) {
        double complex unused;
        return call_back(c->callback, z, value, slope != NULL ? slope : &unused);
    }
    return schur_logdet(c->diag, c->lower, c->upper, c->K, c->scalar, z, value, slope);
}

/* Phase change of g along the segment z0 -> z1 (values f, slopes s at the ends) into *turn:
 * the trapezoid prediction Im(dz (s0 + s1) / 2) corrected by the reading of Im(f1 - f0)
 * modulo 2 pi, the segment bisected until dz (s1 - s0) is at most max_bend and the reading
 * agrees with the prediction within max_turn, in the phase (modulo 2 pi) and in log |g|
 * (Re(f1 - f0), which has no multiple of 2 pi to hide in). The second check catches zeros
 * that the first cannot: two real zeros under one segment of a thin strip turn the phase by
 * 2 pi, invisible modulo 2 pi, and where the rest of g'/g happens to take the same value at
 * both ends the bend test passes too; log |g| then still differs from the trapezoid's
 * prediction by about the log of the distances (3 on the cochlea case of
 * tests/test_contour_blocks.py::test_count_sees_close_real_pair). Returns 1 on failure. */
static int segment(Contour *c, double complex z0, double complex f0, double complex s0,
                   double complex z1, double complex f1, double complex s1, int depth,
                   double *turn)
{
    double complex dz = z1 - z0, trapezoid = 0.5 * dz * (s0 + s1);
    double predicted = cimag(trapezoid);
    double miss = remainder(cimag(f1 - f0) - predicted, 2 * M_PI);
    if (cabs(dz * (s1 - s0)) <= c->max_bend && fabs(miss) <= c->max_turn &&
        fabs(creal(f1 - f0) - creal(trapezoid)) <= c->max_turn) {
        *turn += predicted + miss;
        return 0;
    }
    if (depth > 60)
        return 1;
    double complex zm = 0.5 * (z0 + z1), fm, sm;
    if (evaluate(c, zm, &fm, &sm))
        return 1;
    return segment(c, z0, f0, s0, zm, fm, sm, depth + 1, turn) ||
           segment(c, zm, fm, sm, z1, f1, s1, depth + 1, turn);
}

/* Phase change (radians) of g along the path z[0..n-1] into *turn, each edge refined by
 * segment(); 1 on failure. The one walk of winding() and winding_of(): the GIL is released
 * only for the compiled evaluator (the callback needs it held). ends: NULL, or (log g, slope)
 * at z[0] and at z[n-1] (four values), evaluated already and not again. */
static int contour_turns(Contour *c, const double complex *z, Py_ssize_t n,
                         const double complex *ends, double *turn)
{
    int failed = 0;
    PyThreadState *saved = c->callback == NULL ? PyEval_SaveThread() : NULL;
    double complex f0, s0, f1, s1;
    if (ends != NULL) {
        f0 = ends[0];
        s0 = ends[1];
    } else
        failed = evaluate(c, z[0], &f0, &s0);
    for (Py_ssize_t j = 0; j + 1 < n && !failed; j++) {
        if (ends != NULL && j + 2 == n) {
            f1 = ends[2];
            s1 = ends[3];
        } else
            failed = evaluate(c, z[j + 1], &f1, &s1);
        failed = failed || segment(c, z[j], f0, s0, z[j + 1], f1, s1, 0, turn);
        f0 = f1;
        s0 = s1;
    }
    if (saved != NULL)
        PyEval_RestoreThread(saved);
    return failed;
}

/* The count from the upper half's phase change: twice it, in turns (conjugate values at
 * conjugate points: the lower half turns the phase as much); NULL if the callback raised. */
static PyObject *turns_result(int failed, double turn)
{
    if (PyErr_Occurred())
        return NULL;
    if (failed)
        Py_RETURN_NONE;
    return PyFloat_FromDouble(turn / M_PI);
}

static PyObject *py_winding(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    static const char *names[4] = {"diag", "lower", "upper", "nodes"};
    Py_buffer v[4];
    Contour c;
    if (contour_args(args, nargs, 7, "winding(diag, lower, upper, nodes, max_bend, max_turn, "
                     "max_nodes)", names, 4, 2, v, &c) < 0)
        return NULL;
    c.max_bend = PyFloat_AsDouble(args[4]);
    c.max_turn = PyFloat_AsDouble(args[5]);
    c.budget = PyLong_AsLong(args[6]);
    if (PyErr_Occurred()) {
        release(v, 4);
        return NULL;
    }
    double turn = 0.0;
    int failed = contour_turns(&c, (const double complex *)v[3].buf, v[3].shape[0], NULL, &turn);
    release(v, 4);
    return turns_result(failed, turn);
}

static PyObject *py_winding_of(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (nargs != 5 || !PyCallable_Check(args[0])) {
        PyErr_SetString(PyExc_TypeError, "winding_of(evaluate, nodes, max_bend, max_turn, "
                                         "max_nodes) takes a callable and four arguments");
        return NULL;
    }
    Contour c = {.callback = args[0], .max_bend = PyFloat_AsDouble(args[2]),
                 .max_turn = PyFloat_AsDouble(args[3]), .budget = PyLong_AsLong(args[4])};
    Py_buffer v;
    if (PyErr_Occurred() || complex_buffer(args[1], &v, "nodes", 1) < 0)
        return NULL;
    if (v.shape[0] < 2) {
        PyBuffer_Release(&v);
        PyErr_SetString(PyExc_ValueError, "winding_of: at least 2 nodes");
        return NULL;
    }
    double turn = 0.0;
    int failed = contour_turns(&c, (const double complex *)v.buf, v.shape[0], NULL, &turn);
    PyBuffer_Release(&v);
    return turns_result(failed, turn);
}

/* The sign of the real function det(A - tau B) / det A at real z from its log det (``phase0``:
 * the phase of det A). */
static inline int real_sign(double complex log_det, double phase0)
{
    return cos(cimag(log_det) - phase0) > 0 ? 1 : -1;
}

/* The zero in [lo, hi] (see root() in the header) into *z; 1 on a zero pivot, 2 without a sign
 * change. Each step is Newton's, z - 1 / (d/dz log det), if that stays inside the bracket and,
 * after a Newton step, is at most half as long as it; else a bisection. The bracket keeps the
 * sign change, so it halves at least every other step. Done when a Newton step is at most
 * rtol |z| (its result returned) or the bracket at most rtol |z| wide (its midpoint).
 * ``known``: NULL, or log det at 0, lo and hi already evaluated (the first ``n_known`` of
 * them), which are not evaluated again (the same values: the evaluation is deterministic). */
static int real_root(Contour *c, double lo, double hi, double rtol, const double complex *known,
                     int n_known, double *z)
{
    double complex f, s;
    if (n_known > 0)
        f = known[0];
    else if (evaluate(c, 0.0, &f, NULL))
        return 1;
    double phase0 = cimag(f);
    if (n_known > 1)
        f = known[1];
    else if (evaluate(c, lo, &f, NULL))
        return 1;
    int sign_lo = real_sign(f, phase0);
    if (n_known > 2)
        f = known[2];
    else if (evaluate(c, hi, &f, NULL))
        return 1;
    if (real_sign(f, phase0) == sign_lo)
        return 2;
    double x = 0.5 * (lo + hi), last = 0.0;
    int newton_before = 0;
    for (;;) {
        if (evaluate(c, x, &f, &s))
            return 1;
        if (real_sign(f, phase0) == sign_lo)
            lo = x;
        else
            hi = x;
        double newton = -1.0 / creal(s), next = x + newton;
        if (next > lo && next < hi && !(newton_before && fabs(newton) > 0.5 * last)) {
            newton_before = 1;
            last = fabs(newton);
            x = next;
            if (last <= rtol * fabs(x))
                break;
        } else {
            newton_before = 0;
            x = 0.5 * (lo + hi);
            if (hi - lo <= rtol * fabs(x) || !(lo < x && x < hi))
                break;
        }
    }
    *z = x;
    return 0;
}

static PyObject *py_root(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    static const char *names[3] = {"diag", "lower", "upper"};
    Py_buffer v[3];
    Contour c;
    if (contour_args(args, nargs, 6, "root(diag, lower, upper, lo, hi, rtol)", names, 3, 0, v,
                     &c) < 0)
        return NULL;
    double lo = PyFloat_AsDouble(args[3]), hi = PyFloat_AsDouble(args[4]);
    double rtol = PyFloat_AsDouble(args[5]);
    if (PyErr_Occurred()) {
        release(v, 3);
        return NULL;
    }
    c.budget = ROOT_STEPS;
    double z = 0.0;
    int status;
    Py_BEGIN_ALLOW_THREADS
    status = real_root(&c, lo, hi, rtol, NULL, 0, &z);
    Py_END_ALLOW_THREADS
    release(v, 3);
    if (status == 1)
        Py_RETURN_NONE;
    return PyFloat_FromDouble(status == 2 ? NAN : z);
}

/* The rules of smallest() (contour.smallest_real_tau's module notes), whose tuning constants
 * come from Python (one owner: contour.py). */
typedef struct {
    const double complex *rect, *unit; /* upper rectangle of [0, 1] x [-1, 1]; unit half circle */
    Py_ssize_t n_rect, n_unit;
    double steps[8], strips[8];
    int n_steps, n_strips;
    double z_max, disk, root_rtol;
    long scan, max_nodes;
} Rules;

/* Zeros inside the contour whose upper half is z[0..n) (contour.winding): 0 with the count in
 * *count, 1 where it cannot be trusted (a zero pivot, the budget, a count farther than 0.05
 * from an integer). With ``nonzero_enough`` (the caller asks only whether the count is zero),
 * 2 without the walk where g has opposite signs at the two real ends of the path: the walk's
 * phase change is that between the ends modulo 2 pi (each step's reading is), here pi, so the
 * count would be odd, not zero. The ends are evaluated first either way and not again by the
 * walk, which thus spends the same evaluations of the same budget (issue 25). */
static int count_zeros(Contour *c, const Rules *r, const double complex *z, Py_ssize_t n,
                       int nonzero_enough, long *count)
{
    double turn = 0.0;
    double complex ends[4];
    c->budget = r->max_nodes;
    if (evaluate(c, z[0], &ends[0], &ends[1]) || evaluate(c, z[n - 1], &ends[2], &ends[3]))
        return 1;
    if (nonzero_enough && cos(cimag(ends[0] - ends[2])) < 0)
        return 2;
    if (contour_turns(c, z, n, ends, &turn))
        return 1;
    double total = turn / M_PI, nearest = round(total);
    if (!(fabs(total - nearest) <= 0.05))
        return 1;
    *count = (long)nearest;
    return 0;
}

/* contour._zeros_below: the zeros in [-a, right] x [-a, a], a = s z_max for the first strip s
 * of strips[first..last) that holds none; 0 when one does, else nonzero: 2 when the last
 * strip's g has opposite signs at its real ends (an odd count, not walked), 1 otherwise (each
 * holds some zeros, or its count failed). The nodes are those of contour.rectangle:
 * left + (right - left) x + i h y for x + i y of the rule's rectangle. */
static int none_below(Contour *c, const Rules *r, double right, int first, int last)
{
    double complex nodes[64];
    int status = 1;
    if (r->n_rect > 64)
        return 1;
    for (int j = first; j < last; j++) {
        double side = r->strips[j] * r->z_max, left = -side, width = right - left;
        for (Py_ssize_t i = 0; i < r->n_rect; i++)
            nodes[i] = CMPLX(left + width * creal(r->rect[i]), side * cimag(r->rect[i]));
        long count = -1;
        status = count_zeros(c, r, nodes, r->n_rect, 1, &count);
        if (!status && count == 0)
            return 0;
        status = status == 2 ? 2 : 1;
    }
    return status;
}

/* contour._first_change: the lowest sign change of g = det(A - tau B) / det A on the real
 * points p[0..n) into [*lo, *hi], the points evaluated in turn up to it (those above cannot
 * move it); known = {log det at 0, at *lo, at *hi} for real_root. 1 where there is none or a
 * pivot vanishes before it. */
static int first_change(Contour *c, const double *p, Py_ssize_t n, double *lo, double *hi,
                        double complex *known)
{
    double complex f0, f, before = 0.0;
    if (schur_logdet(c->diag, c->lower, c->upper, c->K, c->scalar, 0.0, &f0, NULL))
        return 1;
    double previous = 0.0;
    for (Py_ssize_t j = 0; j < n; j++) {
        if (schur_logdet(c->diag, c->lower, c->upper, c->K, c->scalar, p[j], &f, NULL))
            return 1;
        double cosine = cos(cimag(f - f0));
        double sign = cosine > 0 ? 1.0 : (cosine < 0 ? -1.0 : 0.0);
        if (j > 0 && previous * sign < 0) {
            *lo = p[j - 1];
            *hi = p[j];
            known[0] = f0;
            known[1] = before;
            known[2] = f;
            return 0;
        }
        previous = sign;
        before = f;
    }
    return 1;
}

/* The root's dyadic cell and certificate (contour.smallest_real_tau): x, a zero of g found to
 * root_rtol, refined to 4 eps inside its dyadic cell of width 2^-30 |x| (so that the answer does
 * not depend on the bracket it came from); then no zero in [-a, x - rho / 2] x [-a, a] (strips
 * [0, strips) in turn) and exactly one in the disk |z - x| <= rho = disk x. 0 with the value in
 * *z, 1 where any step fails. known[0]: log det at 0. */
static int certified_root(Contour *c, const Rules *r, double x, const double complex *known,
                          int strips, double *z)
{
    int e;
    frexp(x, &e);
    double cell = ldexp(1.0, e - 30), low = floor(x / cell) * cell, refined;
    c->budget = ROOT_STEPS;
    int status = real_root(c, low, low + cell, 4 * DBL_EPSILON, known, 1, &refined);
    if (status == 1)
        return 1;
    if (status == 0)
        x = refined;
    double rho = r->disk * x;
    if (none_below(c, r, x - rho / 2, 0, strips))
        return 1;
    double complex nodes[64];
    if (r->n_unit > 64 || r->n_unit < 2)
        return 1;
    for (Py_ssize_t i = 0; i + 1 < r->n_unit; i++)
        nodes[i] = CMPLX(x + rho * creal(r->unit[i]), rho * cimag(r->unit[i]));
    nodes[r->n_unit - 1] = CMPLX(x - rho, 0.0);
    long count;
    if (count_zeros(c, r, nodes, r->n_unit, 0, &count) || count != 1)
        return 1;
    *z = x;
    return 0;
}

/* The shortcut of contour.smallest_real_tau without a hint where g has opposite signs at the
 * ends of the first strip's rectangle: a sign change of g over [0, z_max] narrowed by
 * bisection (log det alone, as the scan's points) to at most z_max / scan, its root, certified
 * as any (certified_root, the first strip alone). 0 with the value in *z, 1 where any step
 * fails (no sign change in [0, z_max]; another zero below the root: then the scan decides). */
static int whole_interval_root(Contour *c, const Rules *r, double *z)
{
    double complex known[3], f;
    double lo = 0.0, hi = r->z_max, width = r->z_max / (double)r->scan;
    if (schur_logdet(c->diag, c->lower, c->upper, c->K, c->scalar, 0.0, &known[0], NULL) ||
        schur_logdet(c->diag, c->lower, c->upper, c->K, c->scalar, hi, &known[2], NULL))
        return 1;
    known[1] = known[0];
    if (!(cos(cimag(known[2] - known[0])) < 0))
        return 1;
    while (hi - lo > width) {
        double mid = 0.5 * (lo + hi);
        if (schur_logdet(c->diag, c->lower, c->upper, c->K, c->scalar, mid, &f, NULL))
            return 1;
        if (cos(cimag(f - known[0])) > 0) {
            lo = mid;
            known[1] = f;
        } else {
            hi = mid;
            known[2] = f;
        }
    }
    double x;
    c->budget = ROOT_STEPS;
    if (real_root(c, lo, hi, r->root_rtol, known, 3, &x))
        return 1;
    return certified_root(c, r, x, known, 1, z);
}

/* contour.smallest_real_tau on a 2 x 2 block pencil: 0 with z = tau_min^2 in *z (NaN: proved
 * that no real tau^2 <= z_max exists), 1 where the certificate cannot be had. hint_z: the
 * hint squared (outside (0, z_max]: none). Same steps, points and arithmetic as the Python
 * composition of winding, rectangle, circle and root in tests/test_contour.py. */
static int smallest_root(Contour *c, const Rules *r, double hint_z, double *z)
{
    double lo = NAN, hi = NAN, points[2 * 8 + 1];
    double complex known[3];
    if (0.0 < hint_z && hint_z <= r->z_max) {
        int n = 0;
        for (int j = r->n_steps - 1; j >= 0; j--)
            points[n++] = hint_z * (1.0 - r->steps[j]);
        points[n++] = hint_z;
        for (int j = 0; j < r->n_steps; j++)
            points[n++] = hint_z * (1.0 + r->steps[j]);
        for (int j = 0; j < n; j++)
            points[j] = fmin(fmax(points[j], 0.0), r->z_max);
        if (first_change(c, points, n, &lo, &hi, known))
            lo = hi = NAN;
    }
    if (lo != lo) {
        double right = r->z_max * (1 + 1e-6);
        int first = none_below(c, r, right, 0, 1);
        if (!first) {
            *z = NAN;
            return 0;
        }
        if (first == 2 && !whole_interval_root(c, r, z))
            return 0;
        double scan[1024];
        if (r->scan + 1 > 1024)
            return 1;
        double step = r->z_max / (double)r->scan;
        for (long j = 0; j < r->scan; j++)
            scan[j] = (double)j * step + 0.0;
        scan[r->scan] = r->z_max;
        if (first_change(c, scan, r->scan + 1, &lo, &hi, known)) {
            if (!none_below(c, r, right, 1, r->n_strips)) {
                *z = NAN;
                return 0;
            }
            return 1;
        }
    }
    double x;
    c->budget = ROOT_STEPS;
    if (real_root(c, lo, hi, r->root_rtol, known, 3, &x))
        return 1;
    return certified_root(c, r, x, known, r->n_strips, z);
}

/* Up to `most` floats of a sequence into out; their number, or -1 (exception set). */
static int float_list(PyObject *seq, double *out, int most, const char *name)
{
    PyObject *fast = PySequence_Fast(seq, name);
    if (fast == NULL)
        return -1;
    Py_ssize_t n = PySequence_Fast_GET_SIZE(fast);
    if (n > most) {
        Py_DECREF(fast);
        PyErr_Format(PyExc_ValueError, "%s: at most %d values", name, most);
        return -1;
    }
    for (Py_ssize_t i = 0; i < n; i++)
        out[i] = PyFloat_AsDouble(PySequence_Fast_GET_ITEM(fast, i));
    Py_DECREF(fast);
    return PyErr_Occurred() ? -1 : (int)n;
}

static PyObject *py_smallest(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    static const char *names[5] = {"diag", "lower", "upper", "rectangle", "circle"};
    const char *usage = "smallest(diag, lower, upper, rectangle, circle, hint_steps, strips, "
                        "z_max, hint_z, disk, scan, max_bend, max_turn, max_nodes, root_rtol)";
    Py_buffer v[5];
    Contour c;
    if (contour_args(args, nargs, 15, usage, names, 3, 0, v, &c) < 0)
        return NULL;
    for (int i = 3; i < 5; i++)
        if (complex_buffer(args[i], &v[i], names[i], 1) < 0) {
            release(v, i);
            return NULL;
        }
    Rules r = {.rect = (const double complex *)v[3].buf, .n_rect = v[3].shape[0],
               .unit = (const double complex *)v[4].buf, .n_unit = v[4].shape[0]};
    r.n_steps = float_list(args[5], r.steps, 8, "hint_steps");
    r.n_strips = r.n_steps < 0 ? -1 : float_list(args[6], r.strips, 8, "strips");
    r.z_max = PyFloat_AsDouble(args[7]);
    double hint_z = PyFloat_AsDouble(args[8]);
    r.disk = PyFloat_AsDouble(args[9]);
    r.scan = PyLong_AsLong(args[10]);
    c.max_bend = PyFloat_AsDouble(args[11]);
    c.max_turn = PyFloat_AsDouble(args[12]);
    r.max_nodes = PyLong_AsLong(args[13]);
    r.root_rtol = PyFloat_AsDouble(args[14]);
    if (PyErr_Occurred() || r.n_strips < 1 || r.scan < 1) {
        release(v, 5);
        if (!PyErr_Occurred())
            PyErr_Format(PyExc_ValueError, "%s: at least one strip and one scan step", usage);
        return NULL;
    }
    double z = 0.0;
    int status = smallest_root(&c, &r, hint_z, &z); /* the counts release the GIL themselves */
    release(v, 5);
    if (status)
        Py_RETURN_NONE;
    return PyFloat_FromDouble(z);
}

static PyObject *py_logdet(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    static const char *names[6] = {"diag", "lower", "upper", "z", "out", "slope"};
    Py_buffer v[6];
    if (nargs != 6) {
        PyErr_SetString(PyExc_TypeError,
                        "logdet(diag, lower, upper, z, out, slope) takes six arrays");
        return NULL;
    }
    if (pencil_buffers(args, "logdet", names, 6, 0, v) < 0)
        return NULL;
    Py_ssize_t K = v[0].shape[0], n = v[3].shape[0];
    int status = 0;
    Py_BEGIN_ALLOW_THREADS
    const double complex *z = (const double complex *)v[3].buf;
    const double complex *diag = v[0].buf, *lower = v[1].buf, *upper = v[2].buf;
    double complex *out = (double complex *)v[4].buf, *slope = (double complex *)v[5].buf;
    const int scalar = scalar_coupling(lower, upper, K);
    for (Py_ssize_t j = 0; j < n && !status; j++)
        status = schur_logdet(diag, lower, upper, K, scalar, z[j], out + j, slope + j);
    Py_END_ALLOW_THREADS
    release(v, 6);
    return PyLong_FromLong(status);
}

/* Largest 1-norm (column sum of moduli) of the 2 x 2 blocks m[0..count); a block equal to the
 * one before it (the sphere's coupling: every block) is not measured again. */
static double largest_norm1(const double complex *m, Py_ssize_t count)
{
    double out = 0.0;
    for (Py_ssize_t k = 0; k < count; k++, m += 4)
        if (k == 0 || memcmp(m, m - 4, 4 * sizeof *m) != 0)
            out = fmax(out, fmax(cabs(m[0]) + cabs(m[2]), cabs(m[1]) + cabs(m[3])));
    return out;
}

static PyObject *py_conditioning(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    static const char *names[3] = {"diag", "lower", "upper"};
    Py_buffer v[3];
    Contour c;
    if (contour_args(args, nargs, 3, "conditioning(diag, lower, upper)", names, 3, 0, v, &c) < 0)
        return NULL;
    double cond = 0.0, inverse = 0.0;
    for (Py_ssize_t k = 0; k < c.K; k++) {
        const double complex *a = c.diag + 4 * k;
        double det = cabs(a[0] * a[3] - a[1] * a[2]);
        double m0 = cabs(a[0]), m1 = cabs(a[1]), m2 = cabs(a[2]), m3 = cabs(a[3]);
        double rows = fmax(m0 + m1, m2 + m3), columns = fmax(m0 + m2, m1 + m3);
        double inv_norm = det > 0.0 ? rows / det : INFINITY;
        cond = fmax(cond, columns * inv_norm);
        inverse = fmax(inverse, inv_norm);
    }
    double coupling = largest_norm1(c.lower, c.K - 1) + largest_norm1(c.upper, c.K - 1);
    release(v, 3);
    return Py_BuildValue("(dd)", cond, inverse * coupling);
}

/* BLAS zgemv (Fortran interface), handed over by use_scipy() from SciPy's cython_blas. */
typedef void zgemv_fn(char *trans, int *m, int *n, double complex *alpha, double complex *a,
                      int *lda, double complex *x, int *incx, double complex *beta,
                      double complex *y, int *incy);
static zgemv_fn *zgemv = NULL;

/* y = alpha a x + beta y for the b x b row-major matrix a (column-major a^T, hence 'T'). */
static void block_times(const double complex *a, const double complex *x, double complex *y,
                        int b, double complex alpha, double complex beta)
{
    char trans = 'T';
    int one = 1;
    zgemv(&trans, &b, &b, &alpha, (double complex *)a, &b, (double complex *)x, &one, &beta, y,
          &one);
}

static PyObject *py_sweep(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    static const char *names[4] = {"inv", "coupling", "g", "start"};
    static const int dims[4] = {3, 3, 2, 1};
    Py_buffer v[4];
    if (nargs != 4) {
        PyErr_SetString(PyExc_TypeError, "sweep(inv, coupling, g, start) takes four arguments");
        return NULL;
    }
    int forward = args[3] != Py_None, count = 3 + forward;
    for (int i = 0; i < count; i++)
        if (complex_buffer(args[i], &v[i], names[i], dims[i]) < 0) {
            release(v, i);
            return NULL;
        }
    Py_ssize_t m = v[0].shape[0], b = v[0].shape[1], c = v[1].shape[0];
    int ok = m >= 1 && v[0].shape[2] == b && v[1].shape[1] == b && v[1].shape[2] == b &&
             (c == 1 || c >= m - 1 + forward) && v[2].shape[0] == m && v[2].shape[1] == b &&
             (!forward || v[3].shape[0] == b) && b <= INT_MAX;
    double complex *t = ok && zgemv ? malloc(b * sizeof *t) : NULL;
    if (!t) {
        release(v, count);
        if (ok && zgemv)
            return PyErr_NoMemory();
        PyErr_SetString(PyExc_ValueError, zgemv ? "sweep: inconsistent shapes"
                                                : "sweep: use_scipy() was not called");
        return NULL;
    }
    const double complex *inv = v[0].buf, *coupling = v[1].buf;
    double complex *g = v[2].buf;
    Py_ssize_t bb = b * b, step = c == 1 ? 0 : bb;
    Py_BEGIN_ALLOW_THREADS
    if (forward) {
        const double complex *p = v[3].buf;
        for (Py_ssize_t j = 0; j < m; p = g + j * b, j++) {
            block_times(coupling + j * step, p, t, (int)b, 1.0, 0.0);
            block_times(inv + j * bb, t, g + j * b, (int)b, -1.0, 1.0);
        }
    } else {
        memcpy(t, g + (m - 1) * b, b * sizeof *t);
        block_times(inv + (m - 1) * bb, t, g + (m - 1) * b, (int)b, 1.0, 0.0);
        for (Py_ssize_t j = m - 2; j >= 0; j--) {
            memcpy(t, g + j * b, b * sizeof *t);
            block_times(coupling + j * step, g + (j + 1) * b, t, (int)b, -1.0, 1.0);
            block_times(inv + j * bb, t, g + j * b, (int)b, 1.0, 0.0);
        }
    }
    Py_END_ALLOW_THREADS
    free(t);
    release(v, count);
    Py_RETURN_NONE;
}

/* LAPACK and BLAS (Fortran interface) for rotated_logdet(), handed over by use_scipy() from
 * SciPy's cython_lapack and cython_blas: the same routines scipy.linalg.lapack calls. */
typedef void zgetrf_fn(int *m, int *n, double complex *a, int *lda, int *ipiv, int *info);
typedef void zgetri_fn(int *n, double complex *a, int *lda, int *ipiv, double complex *work,
                       int *lwork, int *info);
typedef void zgetrs_fn(char *trans, int *n, int *nrhs, double complex *a, int *lda, int *ipiv,
                       double complex *b, int *ldb, int *info);
typedef void zgemm_fn(char *transa, char *transb, int *m, int *n, int *k, double complex *alpha,
                      double complex *a, int *lda, double complex *b, int *ldb,
                      double complex *beta, double complex *c, int *ldc);
static zgetrf_fn *zgetrf = NULL;
static zgetri_fn *zgetri = NULL;
static zgetrs_fn *zgetrs = NULL;
static zgemm_fn *zgemm = NULL;

static PyObject *py_use_scipy(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    void *f[5];
    if (nargs != 5) {
        PyErr_SetString(PyExc_TypeError, "use_scipy(zgemv, zgetrf, zgetri, zgetrs, zgemm) takes "
                                         "five capsules");
        return NULL;
    }
    for (int i = 0; i < 5; i++)
        if (!(f[i] = PyCapsule_GetPointer(args[i], PyCapsule_GetName(args[i]))))
            return NULL;
    zgemv = (zgemv_fn *)f[0];
    zgetrf = (zgetrf_fn *)f[1];
    zgetri = (zgetri_fn *)f[2];
    zgetrs = (zgetrs_fn *)f[3];
    zgemm = (zgemm_fn *)f[4];
    Py_RETURN_NONE;
}

/* row-major c = a b of m x m matrices (column-major: c^T = b^T a^T). */
static void square_product(double complex *a, double complex *b, double complex *c, int m)
{
    char n = 'N';
    double complex one = 1.0, zero = 0.0;
    zgemm(&n, &n, &m, &m, &m, &one, b, &m, a, &m, &zero, c, &m);
}

/* The rotated block sweep of contour.diagonal_log_det (its notes) at one z: S_0 = A_0,
 * S_{k+1} = A_{k+1} + z L S_k^{-1} L, S_{k+1}' = L (S_k^{-1} - z Y_k S_k^{-1}) L with
 * Y_k = S_k^{-1} S_k', S_0' = 0; value = sum_k log det S_k (the LU's diagonal logarithms, i pi
 * per row exchange), slope = sum_k tr Y_k. Row-major buffers are LAPACK's transposes: the LU
 * of S^T has det S, and ?getri / ?getrs on it give (S^{-1})^T, i.e. S^{-1} read row-major.
 * Returns 0, 1 on an exactly singular block, -1 when out of memory. */
static int rotated_steps(const double complex *diag, const double complex *coupling,
                         Py_ssize_t K, int m, double complex z, int inverse_below,
                         double complex *value, double complex *slope)
{
    size_t mm = (size_t)m * m;
    double complex *mem = malloc(6 * mm * sizeof *mem);
    int *pivots = malloc((size_t)m * sizeof *pivots);
    if (!mem || !pivots) {
        free(mem);
        free(pivots);
        return -1;
    }
    double complex *S = mem, *inv = mem + mm, *dS = mem + 2 * mm, *Y = mem + 3 * mm;
    double complex *T = mem + 4 * mm, *outer = mem + 5 * mm;
    for (int i = 0; i < m; i++)
        for (int j = 0; j < m; j++)
            outer[(size_t)i * m + j] = coupling[i] * coupling[j];
    memcpy(S, diag, mm * sizeof *S);
    double complex v = 0.0, s = 0.0;
    int has_slope = 0, status = 0, info = 0, lwork = (int)mm;
    long swaps = 0;
    for (Py_ssize_t k = 0; k < K; k++) {
        zgetrf(&m, &m, S, &m, pivots, &info);
        if (info != 0) {
            status = 1;
            break;
        }
        for (int i = 0; i < m; i++) {
            v += clog(S[(size_t)i * m + i]);
            swaps += pivots[i] != i + 1;
        }
        int last = k == K - 1;
        if (last && !has_slope)
            break;
        if (m < inverse_below) {
            memcpy(inv, S, mm * sizeof *inv);
            zgetri(&m, inv, &m, pivots, T, &lwork, &info);
        } else {
            char n = 'N';
            memset(inv, 0, mm * sizeof *inv);
            for (int i = 0; i < m; i++)
                inv[(size_t)i * m + i] = 1.0;
            zgetrs(&n, &m, &m, S, &m, pivots, inv, &m, &info);
        }
        if (info != 0) {
            status = 1;
            break;
        }
        if (last) { /* tr(S^{-1} S') without the product */
            for (int i = 0; i < m; i++)
                for (int j = 0; j < m; j++)
                    s += inv[(size_t)i * m + j] * dS[(size_t)j * m + i];
            break;
        }
        if (!has_slope) {
            for (size_t i = 0; i < mm; i++)
                dS[i] = outer[i] * inv[i];
            has_slope = 1;
        } else {
            square_product(inv, dS, Y, m);
            for (int i = 0; i < m; i++)
                s += Y[(size_t)i * m + i];
            square_product(Y, inv, T, m);
            for (size_t i = 0; i < mm; i++)
                dS[i] = outer[i] * (inv[i] - z * T[i]);
        }
        const double complex *next = diag + (size_t)(k + 1) * mm;
        for (size_t i = 0; i < mm; i++)
            S[i] = next[i] + z * (outer[i] * inv[i]);
    }
    free(mem);
    free(pivots);
    *value = v + I * (M_PI * (double)swaps);
    *slope = s;
    return status;
}

static PyObject *py_rotated_logdet(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    static const char *names[2] = {"diag", "coupling"};
    static const int dims[2] = {3, 1};
    Py_buffer v[2];
    if (nargs != 4) {
        PyErr_SetString(PyExc_TypeError,
                        "rotated_logdet(diag, coupling, z, inverse_below) takes four arguments");
        return NULL;
    }
    Py_complex zc = PyComplex_AsCComplex(args[2]);
    long inverse_below = PyLong_AsLong(args[3]);
    if (PyErr_Occurred())
        return NULL;
    for (int i = 0; i < 2; i++)
        if (complex_buffer(args[i], &v[i], names[i], dims[i]) < 0) {
            release(v, i);
            return NULL;
        }
    Py_ssize_t K = v[0].shape[0], m = v[0].shape[1];
    if (K < 1 || m < 1 || v[0].shape[2] != m || v[1].shape[0] != m || m > 46340 || !zgemm) {
        release(v, 2);
        PyErr_SetString(PyExc_ValueError, zgemm ? "rotated_logdet: inconsistent shapes"
                                                : "rotated_logdet: use_scipy() was not called");
        return NULL;
    }
    double complex value, slope, z = zc.real + I * zc.imag;
    int status;
    int below = inverse_below > INT_MAX ? INT_MAX : (int)inverse_below;
    Py_BEGIN_ALLOW_THREADS
    status = rotated_steps(v[0].buf, v[1].buf, K, (int)m, z, below, &value, &slope);
    Py_END_ALLOW_THREADS
    release(v, 2);
    if (status < 0)
        return PyErr_NoMemory();
    if (status > 0 || !isfinite(creal(value)) || !isfinite(cimag(value)) ||
        !isfinite(creal(slope)) || !isfinite(cimag(slope)))
        Py_RETURN_NONE;
    return Py_BuildValue("(DD)", &(Py_complex){creal(value), cimag(value)},
                         &(Py_complex){creal(slope), cimag(slope)});
}

static PyMethodDef methods[] = {
    {"logdet", (PyCFunction)(void (*)(void))py_logdet, METH_FASTCALL,
     "logdet(diag, lower, upper, z, out, slope) -> status: log det(A - tau B) at z = tau^2 "
     "and its derivative in z, written into out and slope (status 0; 1: a zero pivot)."},
    {"winding", (PyCFunction)(void (*)(void))py_winding, METH_FASTCALL,
     "winding(diag, lower, upper, nodes, max_bend, max_turn, max_nodes) -> zeros of "
     "det(A - tau B) in z = tau^2 inside the contour symmetric about the real axis whose upper "
     "half is the path nodes (float; None when "
     "a zero pivot or the node budget stops it)."},
    {"winding_of", (PyCFunction)(void (*)(void))py_winding_of, METH_FASTCALL,
     "winding_of(evaluate, nodes, max_bend, max_turn, max_nodes) -> zeros of g inside the "
     "contour symmetric about the real axis whose upper half is the path nodes, g real on the "
     "real axis, evaluate(z) giving (log g(z), d log g / dz) or None (float; None when "
     "evaluate declines or the node budget stops it)."},
    {"root", (PyCFunction)(void (*)(void))py_root, METH_FASTCALL,
     "root(diag, lower, upper, lo, hi, rtol) -> the real zero z of det(A - tau B) in [lo, hi] "
     "by safeguarded Newton (NaN: no sign change; None: a zero pivot)."},
    {"smallest", (PyCFunction)(void (*)(void))py_smallest, METH_FASTCALL,
     "smallest(diag, lower, upper, rectangle, circle, hint_steps, strips, z_max, hint_z, disk, "
     "scan, max_bend, max_turn, max_nodes, root_rtol) -> z = tau_min^2 of the smallest real "
     "tau, certified by zero counts (float; NaN: none up to z_max; None: not certified)."},
    {"conditioning", (PyCFunction)(void (*)(void))py_conditioning, METH_FASTCALL,
     "conditioning(diag, lower, upper) -> (largest 1-norm condition of the blocks of A, largest "
     "||A_k^{-1}||_1 times the coupling's 1-norm)."},
    {"sweep", (PyCFunction)(void (*)(void))py_sweep, METH_FASTCALL,
     "sweep(inv, coupling, g, start) -> None: the backward (start None) or forward pass of a "
     "block-tridiagonal solve, in place on g."},
    {"rotated_logdet", (PyCFunction)(void (*)(void))py_rotated_logdet, METH_FASTCALL,
     "rotated_logdet(diag, coupling, z, inverse_below) -> (log det(A - tau B), its derivative "
     "in z) at z = tau^2 of a pencil with one diagonal coupling (contour.diagonal_log_det), "
     "or None on an exactly singular block or a non-finite value."},
    {"use_scipy", (PyCFunction)(void (*)(void))py_use_scipy, METH_FASTCALL,
     "use_scipy(zgemv, zgetrf, zgetri, zgetrs, zgemm): the BLAS and LAPACK routines sweep() "
     "and rotated_logdet() call (scipy.linalg.cython_blas's and cython_lapack's capsules)."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_schur",
                                    "Compiled kernel: log det of a block-tridiagonal "
                                    "pencil, zero counts, a real zero, block conditioning.", -1,
                                    methods, NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__schur(void) { return PyModule_Create(&module); }
