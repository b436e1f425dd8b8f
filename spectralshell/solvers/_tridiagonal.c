/* Eigenvalues of a complex tridiagonal matrix in O(n^2) operations.
 *
 * The eigenvalues of a tridiagonal T depend only on its diagonal d and on the products
 * p_i = T[i, i+1] T[i+1, i]: T is diagonally similar to the complex symmetric tridiagonal with
 * off-diagonal sqrt(p_i). Its eigenvalues are found by the rational QL iteration with Wilkinson
 * shifts of EISPACK's TQLRAT (Reinsch, Comm. ACM 16 (1973) 689), which works on the squares
 * p_i directly, in complex arithmetic: the same rational recurrences, whose real derivation
 * uses only field operations (the complex symmetric QL of Cullum & Willoughby, "Lanczos
 * algorithms for large symmetric eigenvalue computations", vol. 1, ch. 6, in rational form).
 * Each sweep costs O(n) and keeps the matrix tridiagonal; LAPACK's Hessenberg QR on the same
 * matrix fills in its upper triangle and costs O(n^2) per sweep. The iteration runs on T scaled
 * to unit size, so that the squares it forms neither overflow nor underflow.
 *
 * The complex rotations behind it are not unitary, so digits can be lost (up to ~1e-11
 * relative on the Mathieu tests). Each eigenvalue then gets one Newton step on det(T - x)
 * through the pivots of Gaussian elimination (O(n)), taken only when the step is shorter than
 * a quarter of the distance to the nearest other eigenvalue. The result is checked against the
 * invariants trace(T) and trace(T^2); on any failure (a sweep count above MAX_ITER, a zero
 * pivot in a sweep, a non-finite value, a trace mismatch above TRACE_RTOL) the kernel returns a
 * nonzero status and the caller uses LAPACK instead.
 *
 * Python: eigenvalues(d, p) -> int status. d (n) and p (n - 1) are C-contiguous complex128
 * buffers; on success (status 0) d holds the eigenvalues (unordered); p is not changed.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <complex.h>
#include <float.h>
#include <math.h>

#define MAX_ITER 60
#define TRACE_RTOL 1e-11 /* relative mismatch of trace(T), trace(T^2) accepted */

static inline double norm1(double complex z) { return fabs(creal(z)) + fabs(cimag(z)); }

/* sqrt(f^2 + g^2), rescaled only when squaring could overflow or underflow;
 * t = |f|_1 + |g|_1 (|z|_1 = |Re z| + |Im z|) */
static inline double complex hypot_c(double complex f, double complex g, double t)
{
    if (t > 1e-150 && t < 1e150)
        return csqrt(f * f + g * g);
    if (t == 0.0)
        return 0.0;
    f /= t;
    g /= t;
    return t * csqrt(f * f + g * g);
}

/* Rational QL (EISPACK tqlrat) on the squared off-diagonal e2 = p: no square roots in the
 * sweep. d receives the eigenvalues. */
static int ql_rational(double complex *d, double complex *e2, Py_ssize_t n)
{
    const double eps = DBL_EPSILON;
    double t = 0.0, b = 0.0, c = 0.0;
    double complex f = 0.0;
    e2[n - 1] = 0.0;
    for (Py_ssize_t l = 0; l < n; l++) {
        int iter = 0;
        double h0 = norm1(d[l]) + sqrt(cabs(e2[l]));
        if (t < h0) {
            t = h0;
            b = eps * t;
            c = b * b;
        }
        for (;;) {
            Py_ssize_t m; /* the first negligible e2[m], m >= l (e2[n - 1] is 0 by definition) */
            for (m = l; m < n - 1; m++)
                if (norm1(e2[m]) <= c)
                    break;
            if (m == l)
                break;
            if (++iter > MAX_ITER)
                return 1;
            /* shift: the eigenvalue of the leading 2 x 2 block nearer d[l] */
            double complex s = csqrt(e2[l]), g = d[l];
            double complex pp = (d[l + 1] - g) / (2.0 * s);
            double complex r = hypot_c(pp, 1.0, norm1(pp) + 1.0);
            double complex den = norm1(pp + r) >= norm1(pp - r) ? pp + r : pp - r;
            d[l] = s / den;
            double complex h = g - d[l];
            for (Py_ssize_t i = l + 1; i < n; i++)
                d[i] -= h;
            f += h;
            g = d[m];
            if (g == 0.0)
                g = b;
            h = g;
            s = 0.0;
            for (Py_ssize_t i = m - 1; i >= l; i--) {
                double complex q = g * h;
                r = q + e2[i];
                if (r == 0.0)
                    return 2;
                double complex ir = 1.0 / r;
                e2[i + 1] = s * r;
                s = e2[i] * ir;
                d[i + 1] = h + s * (h + d[i]);
                g = d[i] - e2[i] / g;
                if (g == 0.0)
                    g = b;
                h = g * q * ir;
            }
            e2[l] = s * g;
            d[l] = h;
            if (!isfinite(norm1(h)) || !isfinite(norm1(e2[l])))
                return 4;
            if (h == 0.0 || norm1(e2[l]) <= c / norm1(h))
                break;
            e2[l] = h * e2[l];
            if (e2[l] == 0.0)
                break;
        }
        d[l] += f;
    }
    return 0;
}

/* Newton step for an eigenvalue x of the tridiagonal (d, p): det(T - x) = prod q_k with
 * q_0 = d_0 - x, q_k = d_k - x - p_{k-1} / q_{k-1} (Gaussian elimination without pivoting),
 * so that det'/det = sum q_k' / q_k, q_k' = -1 + p_{k-1} q_{k-1}' / q_{k-1}^2. Returns the
 * correction -det/det' (0 if a pivot vanishes: x is then an eigenvalue to rounding). */
static double complex newton_step(const double complex *d, const double complex *p,
                                  Py_ssize_t n, double complex x)
{
    double complex q = d[0] - x, dq = -1.0;
    if (q == 0.0)
        return 0.0;
    double complex iq = 1.0 / q, sum = dq * iq;
    for (Py_ssize_t k = 1; k < n; k++) {
        double complex ratio = p[k - 1] * iq;
        dq = -1.0 + ratio * dq * iq;
        q = d[k] - x - ratio;
        if (q == 0.0)
            return 0.0;
        iq = 1.0 / q;
        sum += dq * iq;
    }
    return sum == 0.0 ? 0.0 : -1.0 / sum;
}

static int tridiagonal_eigenvalues(double complex *d, const double complex *p, Py_ssize_t n)
{
    /* the iteration runs on T / sigma, sigma = max(|d_i|_1, |p_i|_1^(1/2)): unit scale, so
     * that squares neither overflow nor underflow */
    double sigma = 0.0, total = 0.0; /* total: NaN or inf if any input is */
    for (Py_ssize_t i = 0; i < n; i++) {
        sigma = fmax(sigma, norm1(d[i]));
        total += norm1(d[i]);
    }
    for (Py_ssize_t i = 0; i + 1 < n; i++) {
        sigma = fmax(sigma, sqrt(norm1(p[i])));
        total += norm1(p[i]);
    }
    if (!isfinite(total) || !isfinite(sigma))
        return 4;
    if (n < 2 || sigma == 0.0)
        return 0; /* 1 x 1, or the zero matrix */
    /* work: e2 (n entries: the sweep writes e2[i + 1] up to e2[n - 1]), the scaled d and p */
    double complex *e2 = PyMem_RawMalloc(3 * (size_t)n * sizeof(double complex));
    if (e2 == NULL)
        return -1;
    double complex *d0 = e2 + n, *p0 = e2 + 2 * n;
    double complex trace1 = 0.0, trace2 = 0.0; /* of the scaled matrix */
    double scale1 = 0.0, scale2 = 0.0;
    for (Py_ssize_t i = 0; i < n; i++) {
        d[i] = d0[i] = d[i] / sigma;
        trace1 += d0[i];
        trace2 += d0[i] * d0[i];
        scale1 += cabs(d0[i]);
        scale2 += cabs(d0[i]) * cabs(d0[i]);
    }
    for (Py_ssize_t i = 0; i + 1 < n; i++) {
        e2[i] = p0[i] = p[i] / sigma / sigma;
        trace2 += 2.0 * p0[i];
        scale2 += 2.0 * cabs(p0[i]);
    }
    int status = isfinite(scale1) && isfinite(scale2) ? ql_rational(d, e2, n) : 4;
    for (Py_ssize_t i = 0; i < n && status == 0; i++)
        if (!isfinite(creal(d[i])) || !isfinite(cimag(d[i])))
            status = 4;
    /* One Newton step on det(T - x) per eigenvalue (QL's complex rotations lose digits, up to
     * ~2e-11 relative on Mathieu tests; quadratic convergence restores them), taken only when
     * it is well inside the distance to the nearest other eigenvalue, so that it cannot jump
     * to a neighbour */
    for (Py_ssize_t i = 0; i < n && status == 0; i++) {
        double gap = INFINITY; /* |.|_1 distance to the nearest other eigenvalue */
        for (Py_ssize_t j = 0; j < n; j++)
            if (j != i)
                gap = fmin(gap, norm1(d[i] - d[j]));
        double complex delta = newton_step(d0, p0, n, d[i]);
        if (norm1(delta) <= 0.25 * gap)
            d[i] += delta;
    }
    double complex sum1 = 0.0, sum2 = 0.0;
    for (Py_ssize_t i = 0; i < n; i++) {
        sum1 += d[i];
        sum2 += d[i] * d[i];
    }
    if (status == 0 && (cabs(sum1 - trace1) > TRACE_RTOL * fmax(scale1, sqrt(scale2))
                        || cabs(sum2 - trace2) > TRACE_RTOL * scale2))
        status = 3;
    for (Py_ssize_t i = 0; i < n; i++)
        d[i] *= sigma;
    PyMem_RawFree(e2);
    return status;
}

static int complex_buffer(PyObject *obj, Py_buffer *view, const char *name, int writable)
{
    int flags = PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | (writable ? PyBUF_WRITABLE : 0);
    if (PyObject_GetBuffer(obj, view, flags) < 0)
        return -1;
    if (view->itemsize != (Py_ssize_t)sizeof(double complex) || view->format == NULL
        || strcmp(view->format, "Zd") != 0 || view->ndim != 1) {
        PyErr_Format(PyExc_TypeError, "%s must be a 1-d C-contiguous complex128 array", name);
        PyBuffer_Release(view);
        return -1;
    }
    return 0;
}

static PyObject *py_eigenvalues(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (nargs != 2) {
        PyErr_SetString(PyExc_TypeError, "eigenvalues(d, p) takes two arrays");
        return NULL;
    }
    Py_buffer dv, pv;
    if (complex_buffer(args[0], &dv, "d", 1) < 0)
        return NULL;
    if (complex_buffer(args[1], &pv, "p", 0) < 0) {
        PyBuffer_Release(&dv);
        return NULL;
    }
    Py_ssize_t n = dv.shape[0];
    if (pv.shape[0] != (n > 0 ? n - 1 : 0)) {
        PyBuffer_Release(&dv);
        PyBuffer_Release(&pv);
        PyErr_SetString(PyExc_ValueError, "p must have one entry fewer than d");
        return NULL;
    }
    int status;
    Py_BEGIN_ALLOW_THREADS
    status = tridiagonal_eigenvalues((double complex *)dv.buf, (const double complex *)pv.buf, n);
    Py_END_ALLOW_THREADS
    PyBuffer_Release(&dv);
    PyBuffer_Release(&pv);
    if (status < 0)
        return PyErr_NoMemory();
    return PyLong_FromLong(status);
}

static PyMethodDef methods[] = {
    {"eigenvalues", (PyCFunction)(void (*)(void))py_eigenvalues, METH_FASTCALL,
     "eigenvalues(d, p) -> status: eigenvalues of the tridiagonal with diagonal d and "
     "off-diagonal products p, written into d (status 0; otherwise not converged or "
     "inaccurate)."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_tridiagonal",
                                    "Compiled kernel: complex tridiagonal eigenvalues.", -1,
                                    methods, NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__tridiagonal(void) { return PyModule_Create(&module); }
