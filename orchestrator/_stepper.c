/*
 * axir.orchestrator._stepper: one macro step of the master as a list of FMI calls made in C
 * (issue 14). The plan is built in Python (orchestrator/stepper.py) from the master's transfer
 * plan, whose FMI function pointers, components, value references and buffers come from fmpy;
 * this module only walks it, so the FMI calls of a PRI step cost a C call each instead of a
 * ctypes call and the master's Python per call.
 *
 * A plan is one int64 buffer:
 *   header  [0] number of ops, [1] number of instances, [2] number of reads
 *   ops     8 int64 words each: kind, instance, read slot, n, function, component, a, b
 *   epochs  one per instance: incremented by every fmi2Set* and fmi2DoStep made here
 *   reads   one per read slot: the instance epoch at which the slot's buffer was last read
 * Op kinds:
 *   READ  (0): if reads[slot] != epochs[inst]: status = fn(comp, vr = a, n, buf = b);
 *              reads[slot] = epochs[inst]
 *   COPY  (1): memcpy(a, b, n bytes)
 *   WRITE (2): epochs[inst] += 1; status = fn(comp, vr = a, n, buf = b)
 *   STEP  (3): epochs[inst] += 1; status = fn(comp, t, h, no_set_prior = n)
 * Every read slot is stale when a step starts (the caller may have changed any instance since).
 * step(plan_address, t, h) returns -1 when every call answered fmi2OK or fmi2Warning, else
 * op index * 256 + status of the first call that answered worse (nothing after it is called);
 * a Python exception left set by a call is raised.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <stdint.h>
#include <string.h>

typedef int (*transfer_fn)(void *, const unsigned int *, size_t, void *);
typedef int (*do_step_fn)(void *, double, double, int);

enum { OP_READ = 0, OP_COPY = 1, OP_WRITE = 2, OP_STEP = 3 };
enum { OP_WORDS = 8, STATUS_WARNING = 1 };

static PyObject *stepper_step(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (nargs != 3) {
        PyErr_SetString(PyExc_TypeError, "step(plan_address, t, h)");
        return NULL;
    }
    int64_t *plan = (int64_t *)PyLong_AsVoidPtr(args[0]);
    double t = PyFloat_AsDouble(args[1]);
    double h = PyFloat_AsDouble(args[2]);
    if (PyErr_Occurred())
        return NULL;
    if (plan == NULL) {
        PyErr_SetString(PyExc_ValueError, "step: null plan");
        return NULL;
    }
    const int64_t nops = plan[0], ninst = plan[1], nreads = plan[2];
    int64_t *ops = plan + 3;
    int64_t *epochs = ops + OP_WORDS * nops;
    int64_t *reads = epochs + ninst;
    for (int64_t r = 0; r < nreads; ++r)
        reads[r] = -1;
    for (int64_t i = 0; i < nops; ++i) {
        const int64_t *op = ops + OP_WORDS * i;
        int status = 0;
        switch (op[0]) {
        case OP_READ:
            if (reads[op[2]] == epochs[op[1]])
                continue;
            status = ((transfer_fn)(intptr_t)op[4])((void *)(intptr_t)op[5],
                                                   (const unsigned int *)(intptr_t)op[6],
                                                   (size_t)op[3], (void *)(intptr_t)op[7]);
            reads[op[2]] = epochs[op[1]];
            break;
        case OP_COPY:
            memcpy((void *)(intptr_t)op[6], (const void *)(intptr_t)op[7], (size_t)op[3]);
            continue;
        case OP_WRITE:
            epochs[op[1]] += 1;
            status = ((transfer_fn)(intptr_t)op[4])((void *)(intptr_t)op[5],
                                                   (const unsigned int *)(intptr_t)op[6],
                                                   (size_t)op[3], (void *)(intptr_t)op[7]);
            break;
        case OP_STEP:
            epochs[op[1]] += 1;
            status = ((do_step_fn)(intptr_t)op[4])((void *)(intptr_t)op[5], t, h, (int)op[3]);
            break;
        default:
            PyErr_Format(PyExc_ValueError, "step: unknown op kind %lld at %lld",
                         (long long)op[0], (long long)i);
            return NULL;
        }
        if (PyErr_Occurred())
            return NULL;
        if (status > STATUS_WARNING || status < 0)
            return PyLong_FromLongLong(i * 256 + (status & 0xff));
    }
    return PyLong_FromLong(-1);
}

/* No-op FMI functions answering fmi2OK, for benchmarks/bench_loop.py --master-only (the
 * master's own cost: its FMI calls made, nothing done behind them). */
static int noop_transfer(void *c, const unsigned int *vr, size_t n, void *buf)
{
    (void)c;
    (void)vr;
    (void)n;
    (void)buf;
    return 0;
}

static int noop_do_step(void *c, double t, double h, int no_set_prior)
{
    (void)c;
    (void)t;
    (void)h;
    (void)no_set_prior;
    return 0;
}

static PyMethodDef stepper_methods[] = {
    {"step", (PyCFunction)(void (*)(void))stepper_step, METH_FASTCALL,
     "step(plan_address, t, h) -> -1, or op index * 256 + status of the first failed call"},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef stepper_module = {
    PyModuleDef_HEAD_INIT, "_stepper",
    "One master step as a list of FMI calls made in C (see orchestrator/stepper.py).", -1,
    stepper_methods, NULL, NULL, NULL, NULL,
};

PyMODINIT_FUNC PyInit__stepper(void)
{
    PyObject *m = PyModule_Create(&stepper_module);
    if (m == NULL)
        return NULL;
    if (PyModule_AddIntConstant(m, "OP_WORDS", OP_WORDS) < 0 ||
        PyModule_AddIntConstant(m, "OP_READ", OP_READ) < 0 ||
        PyModule_AddIntConstant(m, "OP_COPY", OP_COPY) < 0 ||
        PyModule_AddIntConstant(m, "OP_WRITE", OP_WRITE) < 0 ||
        PyModule_AddIntConstant(m, "OP_STEP", OP_STEP) < 0 ||
        PyModule_AddObject(m, "NOOP_TRANSFER", PyLong_FromVoidPtr((void *)noop_transfer)) < 0 ||
        PyModule_AddObject(m, "NOOP_DO_STEP", PyLong_FromVoidPtr((void *)noop_do_step)) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
