/* The continued fraction for I_{nu+1}(z)/I_nu(z), compiled.
 *
 * DLMF 10.33.1: I_nu(z)/I_{nu-1}(z) = 1/(b_1 + 1/(b_2 + ...)), b_k = 2(nu + k - 1)/z. With
 * nu = order + 1 the terms are b_k = 2(order + k)/z, evaluated by the modified Lentz method
 * (Numerical Recipes 5.2) to a relative change of one ulp, with at most 2|z| + 500 terms (the
 * tail converges once k exceeds about |z|). The Hill assembly of the sphere and the fibre needs
 * the ratio at a few points per truncation, where the vectorised numpy loop paid ~9 us of call
 * overhead per term; here a term costs nanoseconds.
 *
 * Python: ratio_i(order, z, out) -> int. order (float64), z and out (complex128) are 1-d
 * C-contiguous arrays of one length; z must be finite and nonzero (the caller's domain check).
 * Returns -1 when every point converged (out holds the ratios), else the index of the first
 * point that did not (out is then incomplete).
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <complex.h>
#include <float.h>
#include <math.h>

#define TINY 1e-300 /* replaces an exactly zero Lentz denominator */

/* I_{order+1}(z)/I_order(z); returns 0, or 1 if the cap of 2|z| + 500 terms is reached. */
static int ratio(double order, double complex z, double complex *out)
{
    double cap = 2.0 * cabs(z) + 500.0;
    if (!(cap < 1e9)) /* z not finite: the caller never passes it, but stay safe */
        return 1;
    double complex f = 2.0 * (order + 1.0) / z, c = f, d = 0.0;
    for (long k = 2;; k++) {
        double complex b = 2.0 * (order + (double)k) / z;
        d = b + d;
        if (d == 0.0)
            d = TINY;
        c = b + 1.0 / c;
        if (c == 0.0)
            c = TINY;
        d = 1.0 / d;
        double complex delta = c * d;
        f *= delta;
        if (cabs(delta - 1.0) <= DBL_EPSILON) {
            *out = 1.0 / f;
            return 0;
        }
        if ((double)k >= (double)(long)cap)
            return 1;
    }
}

static int typed_buffer(PyObject *obj, Py_buffer *view, const char *name, int writable,
                        const char *format, Py_ssize_t itemsize)
{
    int flags = PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | (writable ? PyBUF_WRITABLE : 0);
    if (PyObject_GetBuffer(obj, view, flags) < 0)
        return -1;
    if (view->itemsize != itemsize || view->format == NULL || strcmp(view->format, format) != 0
        || view->ndim != 1) {
        PyErr_Format(PyExc_TypeError, "%s must be a 1-d C-contiguous %s array", name,
                     itemsize == (Py_ssize_t)sizeof(double) ? "float64" : "complex128");
        PyBuffer_Release(view);
        return -1;
    }
    return 0;
}

static PyObject *py_ratio_i(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (nargs != 3) {
        PyErr_SetString(PyExc_TypeError, "ratio_i(order, z, out) takes three arrays");
        return NULL;
    }
    Py_buffer ov, zv, outv;
    if (typed_buffer(args[0], &ov, "order", 0, "d", sizeof(double)) < 0)
        return NULL;
    if (typed_buffer(args[1], &zv, "z", 0, "Zd", sizeof(double complex)) < 0) {
        PyBuffer_Release(&ov);
        return NULL;
    }
    if (typed_buffer(args[2], &outv, "out", 1, "Zd", sizeof(double complex)) < 0) {
        PyBuffer_Release(&ov);
        PyBuffer_Release(&zv);
        return NULL;
    }
    Py_ssize_t n = zv.shape[0], failed = -1;
    if (ov.shape[0] != n || outv.shape[0] != n) {
        PyBuffer_Release(&ov);
        PyBuffer_Release(&zv);
        PyBuffer_Release(&outv);
        PyErr_SetString(PyExc_ValueError, "order, z and out must have one length");
        return NULL;
    }
    const double *order = ov.buf;
    const double complex *z = zv.buf;
    double complex *out = outv.buf;
    Py_BEGIN_ALLOW_THREADS
    for (Py_ssize_t i = 0; i < n; i++)
        if (ratio(order[i], z[i], out + i)) {
            failed = i;
            break;
        }
    Py_END_ALLOW_THREADS
    PyBuffer_Release(&ov);
    PyBuffer_Release(&zv);
    PyBuffer_Release(&outv);
    return PyLong_FromSsize_t(failed);
}

static PyMethodDef methods[] = {
    {"ratio_i", (PyCFunction)(void (*)(void))py_ratio_i, METH_FASTCALL,
     "ratio_i(order, z, out) -> int: I_{order+1}(z)/I_order(z) into out by the continued "
     "fraction DLMF 10.33.1; -1 if every point converged, else the first index that did not."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "_lentz",
                                    "Compiled kernel: the Bessel-ratio continued fraction.", -1,
                                    methods, NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__lentz(void) { return PyModule_Create(&module); }
