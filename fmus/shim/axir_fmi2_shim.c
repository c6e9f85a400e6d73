/*
 * axir FMI 2.0 co-simulation shim around pythonfmu's generic binary.
 *
 * Why (1): pythonfmu 0.7.0's binary can only return fmi2OK, fmi2Discard (do_step returned
 * False) or fmi2Fatal (a Python exception); a slave cannot answer fmi2Error. The axir adapter
 * (fmus/_base.py) reports every error as a log message with status fmi2Error instead.
 *
 * Why (2): pythonfmu's binary leaves the CPython symbols undefined (the host had to
 * LD_PRELOAD libpython and set PYTHONHOME/PYTHONPATH), and when it initializes the interpreter
 * itself it finalizes it again from the process's exit handlers, where it crashes (SIGSEGV in
 * PyState::Worker -> Py_FinalizeEx, after the static destructors of extension modules ran).
 *
 * What: this library is the FMU's binaries/linux64/<modelIdentifier>.so. At the first
 * fmi2Instantiate it
 *   1. makes sure a CPython is in the process and initialized (section "Python" below): the
 *      host's own if there is one (a Python host: nothing is loaded or initialized), else the
 *      Python recorded at build time in resources/axir_python.txt, or the python3 named by
 *      the environment variable AXIR_FMU_PYTHON: its libpython is dlopen'ed RTLD_GLOBAL and
 *      initialized here (home, program name, sys.path from the settings; the host's PYTHON*
 *      variables ignored), then the GIL is released. Python is never finalized (it lives until
 *      the process ends, the usual choice for an interpreter embedded by a plugin);
 *   2. checks that the modules the FMU's code imports (require= lines) import;
 *   3. loads pythonfmu's original binary, shipped next to it as <modelIdentifier>_pythonfmu.so
 *      (found with dladdr on a symbol of this library, dlopen RTLD_NOW | RTLD_LOCAL).
 * If any step fails, fmi2Instantiate returns NULL after a Fatal log message saying what to
 * install or set (always delivered, also with logging off; on stderr without a logger).
 *
 * pythonfmu creates a PyState per binary at fmi2Instantiate; as Python is initialized already,
 * its worker thread ends at once and it owns nothing. The shim calls pythonfmu's exported
 * finalizePythonInterpreter() right after each fmi2Instantiate: that drops the PyState then,
 * so neither the static shared_ptr's destructor nor pythonfmu's ELF destructor (which resets
 * the already destroyed shared_ptr: a use after free) has anything to do at exit.
 *
 * Forwarding: every FMI 2.0 co-simulation function is forwarded to the inner binary. At
 * fmi2Instantiate it gets its own logger: that logger notes that a message with status
 * fmi2Error or fmi2Fatal was logged during the current call, then forwards the message
 * unchanged to the host's logger (as the format argument, as pythonfmu does; the adapter
 * escapes '%'). When such a message was logged during a call whose inner status is fmi2OK,
 * fmi2Warning or fmi2Discard, the call returns fmi2Error instead. Fatal and Pending pass
 * through.
 *
 * Logging filter: pythonfmu drops every message while logging is off, which would hide the
 * errors from this shim. The inner instance therefore always runs with logging on (all
 * categories) and the shim applies the host's fmi2Instantiate loggingOn and
 * fmi2SetDebugLogging(loggingOn, categories) itself, with pythonfmu's rule: forward when
 * logging is on and (no categories were given or the message's category is one of them).
 * Error and Fatal messages of an fmi2Instantiate that fails are delivered in any case.
 *
 * Functions the inner binary does not export answer fmi2Error with a log message. See
 * docs/fmu_build.md ("fmi2Error from the C shim", "The Python of the FMU").
 */
#ifdef _WIN32
/* Windows (win64, built with mingw-w64): the forwarding and the error rules only. pythonfmu's
 * win64 binary imports python3.dll by name, so the host provides Python as before (the
 * directory of python3.dll on PATH, PYTHONHOME, PYTHONPATH; docs/other_tools.md); the shim
 * neither loads nor initializes Python there. Untested on Windows (built and checked for its
 * exports on Linux). */
#include <windows.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#define LIB_SUFFIX ".dll"
#define INNER_SUFFIX "_pythonfmu.dll"
typedef INIT_ONCE once_t;
#define ONCE_INIT INIT_ONCE_STATIC_INIT
typedef SRWLOCK lock_t;
#define LOCK_INIT SRWLOCK_INIT
#define LOCK(l) AcquireSRWLockExclusive(l)
#define UNLOCK(l) ReleaseSRWLockExclusive(l)
#else
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <link.h>
#include <pthread.h>
#include <spawn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>
#include <wchar.h>
#define LIB_SUFFIX ".so"
#define INNER_SUFFIX "_pythonfmu.so"
typedef pthread_once_t once_t;
#define ONCE_INIT PTHREAD_ONCE_INIT
typedef pthread_mutex_t lock_t;
#define LOCK_INIT PTHREAD_MUTEX_INITIALIZER
#define LOCK(l) pthread_mutex_lock(l)
#define UNLOCK(l) pthread_mutex_unlock(l)
#endif

#include <math.h> /* NAN (a constant: no libm needed) */
#include <stdint.h>

#include "fmi2Functions.h"

#define CONFIG_NAME "axir_python.txt"     /* resources/: the recorded Python (data only) */
#define PROBE_NAME "axir_python_probe.py" /* resources/: run by $AXIR_FMU_PYTHON -E */
#define ENV_VAR "AXIR_FMU_PYTHON"
#define MAX_LIST 256
#define MAX_TEXT (1 << 20)

static char setup_error[4096];     /* why the FMU cannot be instantiated in this process */
static int setup_ok;               /* 1 once Python is ready and the inner binary loaded */
static once_t setup_once = ONCE_INIT;
static lock_t instantiate_lock = LOCK_INIT;
static const char shim_anchor = 0; /* a symbol of this library for dladdr (never interposed) */

static void fail(const char *format, ...) {
    va_list args;
    va_start(args, format);
    vsnprintf(setup_error, sizeof setup_error, format, args);
    va_end(args);
}

static char *copy_string(const char *text) {
    size_t n = strlen(text) + 1;
    char *p = (char *)malloc(n);
    if (p != NULL) memcpy(p, text, n);
    return p;
}

/* The address of a library's function into a function pointer (POSIX dlsym returns an object
 * pointer, ISO C has no conversion between the two: copy the bits). */
static void sym(void *handle, void *function_pointer, const char *name) {
#ifdef _WIN32
    FARPROC p = GetProcAddress((HMODULE)handle, name);
#else
    void *p = dlsym(handle, name);
#endif
    memcpy(function_pointer, &p, sizeof p);
}

#ifndef _WIN32
extern char **environ;

/* ------------------------------------------------------------------ Python: settings */
/* resources/axir_python.txt, or the output of $AXIR_FMU_PYTHON -E axir_python_probe.py:
 * "key=value" lines (fmus/python_env.py writes both); '#' lines are comments. */
typedef struct {
    char origin[1200]; /* where the settings come from (for messages) */
    char *text;        /* the text, split in place */
    int format_ok;
    const char *implementation, *version, *executable, *libpython, *home, *stdlib;
    const char *paths[MAX_LIST];
    size_t n_paths;
    const char *requires[MAX_LIST];
    size_t n_requires;
} Settings;

static void parse_settings(Settings *st, char *text) {
    char *line, *next, *eq;
    st->text = text;
    for (line = text; line != NULL && *line != '\0'; line = next) {
        next = strchr(line, '\n');
        if (next != NULL) *next++ = '\0';
        if (line[0] == '#' || (eq = strchr(line, '=')) == NULL) continue;
        *eq++ = '\0';
        if (strcmp(line, "format") == 0) st->format_ok = strcmp(eq, "axir-python 1") == 0;
        else if (strcmp(line, "implementation") == 0) st->implementation = eq;
        else if (strcmp(line, "version") == 0) st->version = eq;
        else if (strcmp(line, "executable") == 0) st->executable = eq;
        else if (strcmp(line, "libpython") == 0) st->libpython = eq;
        else if (strcmp(line, "home") == 0) st->home = eq;
        else if (strcmp(line, "stdlib") == 0) st->stdlib = eq;
        else if (strcmp(line, "path") == 0 && st->n_paths < MAX_LIST)
            st->paths[st->n_paths++] = eq;
        else if (strcmp(line, "require") == 0 && st->n_requires < MAX_LIST)
            st->requires[st->n_requires++] = eq;
    }
}

/* Everything readable from fd (at most MAX_TEXT bytes), NUL-terminated; NULL on error. */
static char *read_all(int fd) {
    size_t n = 0, cap = 4096;
    char *buf = (char *)malloc(cap + 1), *bigger;
    ssize_t r;
    if (buf == NULL) return NULL;
    for (;;) {
        if (n == cap) {
            if (cap >= MAX_TEXT || (bigger = (char *)realloc(buf, 2 * cap + 1)) == NULL) break;
            buf = bigger;
            cap *= 2;
        }
        r = read(fd, buf + n, cap - n);
        if (r < 0 && errno == EINTR) continue;
        if (r <= 0) break;
        n += (size_t)r;
    }
    buf[n] = '\0';
    return buf;
}

static char *read_file(const char *path) {
    char *text;
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0) return NULL;
    text = read_all(fd);
    close(fd);
    return text;
}

/* Run "python -E probe" and parse its output into st; 0 (and setup_error) on failure. */
static int run_probe(Settings *st, const char *python, const char *probe) {
    int out[2] = {-1, -1}, err[2] = {-1, -1}, status = 0, rc;
    posix_spawn_file_actions_t fa;
    pid_t pid;
    char *argv[4], *text, *errtext;
    argv[0] = (char *)python;
    argv[1] = (char *)"-E";
    argv[2] = (char *)probe;
    argv[3] = NULL;
    snprintf(st->origin, sizeof st->origin, "%s=%.1000s", ENV_VAR, python);
    if (pipe2(out, O_CLOEXEC) != 0 || pipe2(err, O_CLOEXEC) != 0) {
        fail("axir shim: cannot run %s: pipe: %s", st->origin, strerror(errno));
        return 0;
    }
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_adddup2(&fa, out[1], 1);
    posix_spawn_file_actions_adddup2(&fa, err[1], 2);
    rc = posix_spawnp(&pid, python, &fa, NULL, argv, environ); /* a bare name: PATH */
    posix_spawn_file_actions_destroy(&fa);
    close(out[1]);
    close(err[1]);
    if (rc != 0) {
        close(out[0]);
        close(err[0]);
        fail("axir shim: cannot run %s: %s. Set %s to the path of a python3 executable "
             "(a CPython built with --enable-shared)", st->origin, strerror(rc), ENV_VAR);
        return 0;
    }
    text = read_all(out[0]);
    errtext = read_all(err[0]);
    close(out[0]);
    close(err[0]);
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (text == NULL || strncmp(text, "format=axir-python 1\n", 21) != 0) {
        size_t n = errtext ? strlen(errtext) : 0;
        fail("axir shim: %s -E %s did not answer (exit status %d): %s. Set %s to the path of "
             "a python3 executable (CPython >= 3.8)", st->origin, probe,
             WIFEXITED(status) ? WEXITSTATUS(status) : -1,
             n ? errtext + (n > 1500 ? n - 1500 : 0) : "no output", ENV_VAR);
        free(text);
        free(errtext);
        return 0;
    }
    free(errtext);
    parse_settings(st, text);
    return 1;
}

/* ------------------------------------------------------------------ Python: the C API */
/* Called through pointers (libpython is not linked; no Python header is needed). Objects
 * are opaque; PyGILState_STATE is an enum (int). */
typedef struct {
    int (*IsInitialized)(void);
    void (*InitializeEx)(int);
    const char *(*GetVersion)(void);
    void (*SetPythonHome)(const wchar_t *);
    void (*SetProgramName)(const wchar_t *);
    wchar_t *(*DecodeLocale)(const char *, size_t *);
    void *(*EvalSaveThread)(void);
    int (*GILStateEnsure)(void);
    void (*GILStateRelease)(int);
    void *(*ImportModule)(const char *);
    void (*ErrFetch)(void **, void **, void **);
    void *(*ObjectStr)(void *);
    const char *(*UnicodeAsUTF8)(void *);
    void *(*UnicodeDecodeFSDefault)(const char *);
    void (*DecRef)(void *);
    void *(*ListNew)(ssize_t);
    int (*ListAppend)(void *, void *);
    void *(*SysGetObject)(const char *);
    int (*SysSetObject)(const char *, void *);
    int *IgnoreEnvironmentFlag, *NoUserSiteDirectory, *UnbufferedStdioFlag; /* may be NULL */
    /* the shared value block (section "shared values"); optional: without them every get/set
     * goes through pythonfmu */
    unsigned long (*ThreadGetIdent)(void);
    void *(*LongFromUnsignedLong)(unsigned long);
    void *(*LongAsVoidPtr)(void *);
    void *(*DictGetItem)(void *, void *);
    int (*DictDelItem)(void *, void *);
    ssize_t (*TupleSize)(void *);
    void *(*TupleGetItem)(void *, ssize_t);
    void (*ErrClear)(void);
    void (*IncRef)(void *);
    /* the slave's fast step (section "fast step"); optional: without them every doStep goes
     * through pythonfmu */
    void *(*CallObject)(void *, void *);
    long (*LongAsLong)(void *);
    int (*CallableCheck)(void *);
    /* the fast step's gather and scatter made here (section "fast step I/O"); optional:
     * without them the slave's Python fast step gathers and scatters */
    void *(*DictNew)(void);
    int (*DictSetItem)(void *, void *, void *);
    void *(*FloatFromDouble)(double);
    void *(*LongFromLongLong)(long long);
    void *(*BoolFromLong)(long);
    double (*FloatAsDouble)(void *);
    long long (*LongAsLongLong)(void *);
    void *(*ErrOccurred)(void);
    int (*GetBuffer)(void *, void *, int);
    void (*BufferRelease)(void *);
    void *(*CallFunctionObjArgs)(void *, ...);
    void *(*ObjectType)(void *);
    void *LongType, *BoolType, *DictType; /* &PyLong_Type, &PyBool_Type, &PyDict_Type */
} PyApi;

static PyApi py;

static int resolve_python(void *h) {
    sym(h, &py.IsInitialized, "Py_IsInitialized");
    sym(h, &py.InitializeEx, "Py_InitializeEx");
    sym(h, &py.GetVersion, "Py_GetVersion");
    sym(h, &py.SetPythonHome, "Py_SetPythonHome");
    sym(h, &py.SetProgramName, "Py_SetProgramName");
    sym(h, &py.DecodeLocale, "Py_DecodeLocale");
    sym(h, &py.EvalSaveThread, "PyEval_SaveThread");
    sym(h, &py.GILStateEnsure, "PyGILState_Ensure");
    sym(h, &py.GILStateRelease, "PyGILState_Release");
    sym(h, &py.ImportModule, "PyImport_ImportModule");
    sym(h, &py.ErrFetch, "PyErr_Fetch");
    sym(h, &py.ObjectStr, "PyObject_Str");
    sym(h, &py.UnicodeAsUTF8, "PyUnicode_AsUTF8");
    sym(h, &py.UnicodeDecodeFSDefault, "PyUnicode_DecodeFSDefault");
    sym(h, &py.DecRef, "Py_DecRef");
    sym(h, &py.ListNew, "PyList_New");
    sym(h, &py.ListAppend, "PyList_Append");
    sym(h, &py.SysGetObject, "PySys_GetObject");
    sym(h, &py.SysSetObject, "PySys_SetObject");
    sym(h, &py.ThreadGetIdent, "PyThread_get_thread_ident");
    sym(h, &py.LongFromUnsignedLong, "PyLong_FromUnsignedLong");
    sym(h, &py.LongAsVoidPtr, "PyLong_AsVoidPtr");
    sym(h, &py.DictGetItem, "PyDict_GetItem");
    sym(h, &py.DictDelItem, "PyDict_DelItem");
    sym(h, &py.TupleSize, "PyTuple_Size");
    sym(h, &py.TupleGetItem, "PyTuple_GetItem");
    sym(h, &py.ErrClear, "PyErr_Clear");
    sym(h, &py.IncRef, "Py_IncRef");
    sym(h, &py.CallObject, "PyObject_CallObject");
    sym(h, &py.LongAsLong, "PyLong_AsLong");
    sym(h, &py.CallableCheck, "PyCallable_Check");
    sym(h, &py.DictNew, "PyDict_New");
    sym(h, &py.DictSetItem, "PyDict_SetItem");
    sym(h, &py.FloatFromDouble, "PyFloat_FromDouble");
    sym(h, &py.LongFromLongLong, "PyLong_FromLongLong");
    sym(h, &py.BoolFromLong, "PyBool_FromLong");
    sym(h, &py.FloatAsDouble, "PyFloat_AsDouble");
    sym(h, &py.LongAsLongLong, "PyLong_AsLongLong");
    sym(h, &py.ErrOccurred, "PyErr_Occurred");
    sym(h, &py.GetBuffer, "PyObject_GetBuffer");
    sym(h, &py.BufferRelease, "PyBuffer_Release");
    sym(h, &py.CallFunctionObjArgs, "PyObject_CallFunctionObjArgs");
    sym(h, &py.ObjectType, "PyObject_Type");
    sym(h, &py.LongType, "PyLong_Type");
    sym(h, &py.BoolType, "PyBool_Type");
    sym(h, &py.DictType, "PyDict_Type");
    py.IgnoreEnvironmentFlag = (int *)dlsym(h, "Py_IgnoreEnvironmentFlag");
    py.NoUserSiteDirectory = (int *)dlsym(h, "Py_NoUserSiteDirectory");
    py.UnbufferedStdioFlag = (int *)dlsym(h, "Py_UnbufferedStdioFlag");
    return py.IsInitialized && py.GetVersion && py.GILStateEnsure && py.GILStateRelease
           && py.ImportModule && py.ErrFetch && py.ObjectStr && py.UnicodeAsUTF8 && py.DecRef
           && py.SysGetObject;
}

static int find_libpython(struct dl_phdr_info *info, size_t size, void *data) {
    const char *name = info->dlpi_name, *base;
    (void)size;
    if (name == NULL || *name == '\0') return 0;
    base = strrchr(name, '/');
    base = base ? base + 1 : name;
    if (strncmp(base, "libpython3", 10) != 0 || strstr(base, ".so") == NULL) return 0;
    snprintf((char *)data, 1024, "%s", name);
    return 1;
}

/* A CPython already in the process (a Python host, a host linked with or preloading
 * libpython, another FMU's shim)? 1 and its handle in *h (RTLD_DEFAULT, which is NULL in
 * glibc, when its symbols are global), else 0. A libpython loaded RTLD_LOCAL is made global
 * (pythonfmu's binary needs its symbols). */
static int python_in_process(void **h) {
    char path[1024] = "";
    *h = RTLD_DEFAULT;
    if (dlsym(RTLD_DEFAULT, "Py_IsInitialized") != NULL) return 1;
    if (dl_iterate_phdr(find_libpython, path) && path[0] != '\0')
        *h = dlopen(path, RTLD_NOW | RTLD_NOLOAD | RTLD_GLOBAL);
    return *h != NULL;
}

/* "numpy, scipy" (sep ", ") or "numpy scipy" (sep " ") */
static void join_requires(const Settings *req, const char *sep, char *buf, size_t size) {
    size_t i, n = 0;
    buf[0] = '\0';
    for (i = 0; i < req->n_requires && n + 1 < size; i++)
        n += (size_t)snprintf(buf + n, size - n, "%s%s", i ? sep : "", req->requires[i]);
}

static int file_exists(const char *dir, const char *name) {
    char path[2200];
    struct stat st;
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return stat(path, &st) == 0;
}

/* Initialize the interpreter of libpython (already loaded) with the settings st; the caller
 * holds the GIL afterwards. 0 (and setup_error) if it cannot be done safely. */
static int init_python(const Settings *st, const char *fix) {
    static wchar_t *home, *program; /* Python keeps the pointers: never freed */
    const char *v = py.GetVersion();
    size_t i, nv = st->version ? strlen(st->version) : 0;
    void *list, *item;
    if (!py.InitializeEx || !py.SetPythonHome || !py.SetProgramName || !py.DecodeLocale
        || !py.EvalSaveThread || !py.UnicodeDecodeFSDefault || !py.ListNew || !py.ListAppend
        || !py.SysSetObject) {
        fail("axir shim: the libpython in this process (%.100s) lacks the initialization "
             "functions the shim uses (Py_SetPythonHome, ...). %s", v, fix);
        return 0;
    }
    if (nv == 0 || strncmp(v, st->version, nv) != 0 || v[nv] != '.') {
        fail("axir shim: the libpython in this process is Python %.20s, but %s names Python "
             "%s. %s", v, st->origin, st->version ? st->version : "(none)", fix);
        return 0;
    }
    /* Py_InitializeEx aborts the process when it cannot find the standard library: check. */
    if (!st->home || !st->stdlib || !st->executable || !file_exists(st->stdlib, "os.py")
        || !file_exists(st->stdlib, "encodings/__init__.py")) {
        fail("axir shim: the standard library of Python %s (%s, from %s) is missing. %s",
             st->version, st->stdlib ? st->stdlib : "no stdlib= entry", st->origin, fix);
        return 0;
    }
    home = py.DecodeLocale(st->home, NULL);
    program = py.DecodeLocale(st->executable, NULL);
    if (home == NULL || program == NULL) {
        fail("axir shim: cannot decode the paths of %s. %s", st->origin, fix);
        return 0;
    }
    /* isolated from the host's PYTHONHOME/PYTHONPATH/... (they may name another Python) */
    if (py.IgnoreEnvironmentFlag) *py.IgnoreEnvironmentFlag = 1;
    if (py.NoUserSiteDirectory) *py.NoUserSiteDirectory = 1;
    if (py.UnbufferedStdioFlag) *py.UnbufferedStdioFlag = 1; /* no Python output lost at exit */
    py.SetPythonHome(home);
    py.SetProgramName(program);
    py.InitializeEx(0); /* 0: the host's signal handlers stay */
    if (!py.IsInitialized()) {
        fail("axir shim: Py_InitializeEx failed for %s. %s", st->origin, fix);
        return 0;
    }
    /* sys.path = the recorded one (stdlib, lib-dynload, site-packages of the venv, ...) */
    list = py.ListNew(0);
    for (i = 0; list != NULL && i < st->n_paths; i++) {
        item = py.UnicodeDecodeFSDefault(st->paths[i]);
        if (item != NULL) {
            py.ListAppend(list, item);
            py.DecRef(item);
        }
    }
    if (list != NULL && st->n_paths > 0) py.SysSetObject("path", list);
    py.DecRef(list);
    return 1;
}

/* Import every required module (GIL held); 0 (and setup_error) on the first failure. */
static int check_requires(const Settings *req, const char *python, int own) {
    size_t i;
    char all[1024], pip[1024];
    void *m, *type, *value, *tb, *text;
    const char *why;
    for (i = 0; i < req->n_requires; i++) {
        m = py.ImportModule(req->requires[i]);
        if (m != NULL) {
            py.DecRef(m);
            continue;
        }
        type = value = tb = NULL;
        py.ErrFetch(&type, &value, &tb);
        text = value ? py.ObjectStr(value) : NULL;
        why = text ? py.UnicodeAsUTF8(text) : NULL;
        join_requires(req, ", ", all, sizeof all);
        join_requires(req, " ", pip, sizeof pip);
        fail("axir shim: the FMU's Python (%s) cannot import %s (%.300s). The FMU needs the "
             "packages %s: install them into that Python (%s -m pip install %s)%s",
             python, req->requires[i], why ? why : "unknown error", all, python, pip,
             own ? ", or set " ENV_VAR "=/path/to/python3 (a CPython built with "
                   "--enable-shared) that has them in the environment of the host process."
                 : ".");
        py.DecRef(text);
        py.DecRef(type);
        py.DecRef(value);
        py.DecRef(tb);
        return 0;
    }
    return 1;
}

/* sys.executable of the running interpreter (GIL held) */
static void python_name(char *buf, size_t size) {
    void *exe = py.SysGetObject("executable"); /* borrowed */
    const char *s = exe ? py.UnicodeAsUTF8(exe) : NULL;
    snprintf(buf, size, "%s", s && *s ? s : "the Python of this process");
}

/* Step 1 and 2 (see the top). resources: the FMU's resources folder. */
static int ensure_python(const char *resources) {
    static Settings recorded, probed;
    Settings *use = NULL;
    char path[1200], probe[1200], all[1024], fix[2048], python[1024];
    const char *env = getenv(ENV_VAR);
    void *h = NULL;
    int own = 0, present, initialized = 0, gil = 0, ok;

    snprintf(path, sizeof path, "%s/%s", resources, CONFIG_NAME);
    snprintf(recorded.origin, sizeof recorded.origin, "%s", path);
    {
        char *text = read_file(path);
        if (text != NULL) parse_settings(&recorded, text);
    }
    if (recorded.n_requires > 0)
        join_requires(&recorded, ", ", all, sizeof all);
    else
        snprintf(all, sizeof all, "the packages the FMU imports (numpy, ...)");
    snprintf(fix, sizeof fix, "Set %s=/path/to/python3 in the environment of the host "
             "process: a CPython %s built with --enable-shared (with a libpython%s.so) that "
             "has %s (see the FMU's documentation: axir docs/other_tools.md).", ENV_VAR,
             recorded.version ? recorded.version : "3", recorded.version ? recorded.version : "3",
             all);
    if (env != NULL && *env == '\0') env = NULL;

    present = python_in_process(&h);
    if (present) {
        if (!resolve_python(h)) {
            fail("axir shim: the CPython in this process lacks functions of the C API "
                 "(Py_IsInitialized, PyGILState_Ensure, ...). %s", fix);
            return 0;
        }
        initialized = py.IsInitialized();
    }
    if (!initialized) { /* the shim initializes Python: which one? */
        if (env != NULL) {
            snprintf(probe, sizeof probe, "%s/%s", resources, PROBE_NAME);
            if (!run_probe(&probed, env, probe)) return 0;
            use = &probed;
        } else {
            use = &recorded;
            if (recorded.text == NULL) {
                fail("axir shim: %s is missing (it names the Python this FMU runs on). %s",
                     path, fix);
                return 0;
            }
        }
        if (!use->format_ok) {
            fail("axir shim: %s is not in the axir-python 1 format. %s", use->origin, fix);
            return 0;
        }
        if (use->implementation && strcmp(use->implementation, "cpython") != 0) {
            fail("axir shim: %s is %s, not CPython. %s", use->origin, use->implementation, fix);
            return 0;
        }
        if (!present) {
            if (use->libpython == NULL || use->libpython[0] == '\0') {
                fail("axir shim: the Python of %s (%s) has no shared libpython (it was built "
                     "without --enable-shared). %s", use->origin,
                     use->executable ? use->executable : "?", fix);
                return 0;
            }
            h = dlopen(use->libpython, RTLD_NOW | RTLD_GLOBAL);
            if (h == NULL) {
                const char *e = dlerror();
                fail("axir shim: cannot load the libpython of %s: %.600s. %s", use->origin,
                     e ? e : use->libpython, fix);
                return 0;
            }
            if (!resolve_python(h)) {
                fail("axir shim: %s lacks functions of the CPython C API. %s", use->libpython,
                     fix);
                return 0;
            }
        }
        if (!py.IsInitialized()) { /* (another thread may have done it meanwhile) */
            if (!init_python(use, fix)) return 0;
            own = 1; /* this thread holds the GIL */
        }
    }
    if (!own) {
        gil = py.GILStateEnsure();
    }
    python_name(python, sizeof python);
    ok = check_requires(&recorded, python, own);
    if (own)
        py.EvalSaveThread(); /* release the GIL: pythonfmu takes it in every call */
    else
        py.GILStateRelease(gil);
    return ok;
}

#endif /* !_WIN32: Python */

/* ------------------------------------------------------------------ the inner binary */
typedef struct {
    fmi2SetDebugLoggingTYPE *SetDebugLogging;
    fmi2InstantiateTYPE *Instantiate;
    fmi2FreeInstanceTYPE *FreeInstance;
    fmi2SetupExperimentTYPE *SetupExperiment;
    fmi2EnterInitializationModeTYPE *EnterInitializationMode;
    fmi2ExitInitializationModeTYPE *ExitInitializationMode;
    fmi2TerminateTYPE *Terminate;
    fmi2ResetTYPE *Reset;
    fmi2GetRealTYPE *GetReal;
    fmi2GetIntegerTYPE *GetInteger;
    fmi2GetBooleanTYPE *GetBoolean;
    fmi2GetStringTYPE *GetString;
    fmi2SetRealTYPE *SetReal;
    fmi2SetIntegerTYPE *SetInteger;
    fmi2SetBooleanTYPE *SetBoolean;
    fmi2SetStringTYPE *SetString;
    fmi2GetFMUstateTYPE *GetFMUstate;
    fmi2SetFMUstateTYPE *SetFMUstate;
    fmi2FreeFMUstateTYPE *FreeFMUstate;
    fmi2SerializedFMUstateSizeTYPE *SerializedFMUstateSize;
    fmi2SerializeFMUstateTYPE *SerializeFMUstate;
    fmi2DeSerializeFMUstateTYPE *DeSerializeFMUstate;
    fmi2GetDirectionalDerivativeTYPE *GetDirectionalDerivative;
    fmi2SetRealInputDerivativesTYPE *SetRealInputDerivatives;
    fmi2GetRealOutputDerivativesTYPE *GetRealOutputDerivatives;
    fmi2DoStepTYPE *DoStep;
    fmi2CancelStepTYPE *CancelStep;
    fmi2GetStatusTYPE *GetStatus;
    fmi2GetRealStatusTYPE *GetRealStatus;
    fmi2GetIntegerStatusTYPE *GetIntegerStatus;
    fmi2GetBooleanStatusTYPE *GetBooleanStatus;
    fmi2GetStringStatusTYPE *GetStringStatus;
    void (*finalizePythonInterpreter)(void); /* pythonfmu's: drops its PyState */
} InnerApi;

static InnerApi api;
static void *inner_handle;

/* self: this library's path (UTF-8 on Windows) */
static int load_inner(const char *self) {
    char path[1100];
    size_t n = strlen(self), k = sizeof LIB_SUFFIX - 1;
    if (n < k || strcmp(self + n - k, LIB_SUFFIX) != 0
        || n - k + sizeof INNER_SUFFIX > sizeof path) {
        fail("axir shim: unexpected shim file name %.900s", self);
        return 0;
    }
    memcpy(path, self, n - k);
    memcpy(path + n - k, INNER_SUFFIX, sizeof INNER_SUFFIX);
#ifdef _WIN32
    {
        wchar_t wpath[1100];
        char err[512] = "";
        if (MultiByteToWideChar(CP_UTF8, 0, path, -1, wpath, 1100) > 0)
            inner_handle = (void *)LoadLibraryExW(wpath, NULL, LOAD_WITH_ALTERED_SEARCH_PATH);
        if (inner_handle == NULL) {
            FormatMessageA(FORMAT_MESSAGE_FROM_SYSTEM | FORMAT_MESSAGE_IGNORE_INSERTS, NULL,
                           GetLastError(), 0, err, sizeof err, NULL);
            fail("axir shim: cannot load %.500s: %.400s (is the folder of python3.dll on "
                 "PATH?)", path, err);
            return 0;
        }
    }
#else
    inner_handle = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (inner_handle == NULL) {
        const char *err = dlerror();
        fail("axir shim: cannot load %.500s: %.500s", path, err ? err : "unknown error");
        return 0;
    }
#endif
#define LOAD(f) sym(inner_handle, &api.f, "fmi2" #f)
    LOAD(SetDebugLogging);
    LOAD(Instantiate);
    LOAD(FreeInstance);
    LOAD(SetupExperiment);
    LOAD(EnterInitializationMode);
    LOAD(ExitInitializationMode);
    LOAD(Terminate);
    LOAD(Reset);
    LOAD(GetReal);
    LOAD(GetInteger);
    LOAD(GetBoolean);
    LOAD(GetString);
    LOAD(SetReal);
    LOAD(SetInteger);
    LOAD(SetBoolean);
    LOAD(SetString);
    LOAD(GetFMUstate);
    LOAD(SetFMUstate);
    LOAD(FreeFMUstate);
    LOAD(SerializedFMUstateSize);
    LOAD(SerializeFMUstate);
    LOAD(DeSerializeFMUstate);
    LOAD(GetDirectionalDerivative);
    LOAD(SetRealInputDerivatives);
    LOAD(GetRealOutputDerivatives);
    LOAD(DoStep);
    LOAD(CancelStep);
    LOAD(GetStatus);
    LOAD(GetRealStatus);
    LOAD(GetIntegerStatus);
    LOAD(GetBooleanStatus);
    LOAD(GetStringStatus);
#undef LOAD
    sym(inner_handle, &api.finalizePythonInterpreter, "finalizePythonInterpreter");
    if (api.Instantiate == NULL || api.FreeInstance == NULL || api.SetDebugLogging == NULL) {
        fail("axir shim: %.900s lacks fmi2Instantiate/fmi2FreeInstance/fmi2SetDebugLogging",
             path);
        return 0;
    }
    return 1;
}

/* once per library: Python, then the inner binary (see the top) */
#ifdef _WIN32
static BOOL CALLBACK setup(PINIT_ONCE once, PVOID parameter, PVOID *context) {
    HMODULE self = NULL;
    wchar_t wpath[1024];
    char path[1100];
    DWORD n;
    (void)once;
    (void)parameter;
    (void)context;
    if (!GetModuleHandleExW(GET_MODULE_HANDLE_EX_FLAG_FROM_ADDRESS
                                | GET_MODULE_HANDLE_EX_FLAG_UNCHANGED_REFCOUNT,
                            (LPCWSTR)(const void *)&shim_anchor, &self)
        || (n = GetModuleFileNameW(self, wpath, 1024)) == 0 || n >= 1024
        || WideCharToMultiByte(CP_UTF8, 0, wpath, -1, path, sizeof path, NULL, NULL) <= 0) {
        fail("axir shim: cannot locate the shim's own file");
        return TRUE;
    }
    setup_ok = load_inner(path);
    return TRUE;
}
#define RUN_SETUP() InitOnceExecuteOnce(&setup_once, setup, NULL, NULL)
#else
static void setup(void) {
    Dl_info info;
    char resources[1100], *slash;
    int i;
    if (!dladdr(&shim_anchor, &info) || info.dli_fname == NULL
        || strlen(info.dli_fname) >= sizeof resources - 16) {
        fail("axir shim: dladdr cannot locate the shim");
        return;
    }
    /* <fmu>/binaries/linux64/<id>.so -> <fmu>/resources */
    snprintf(resources, sizeof resources, "%s", info.dli_fname);
    for (i = 0; i < 3; i++) {
        slash = strrchr(resources, '/');
        if (slash == NULL) break;
        *slash = '\0';
    }
    if (i < 3) snprintf(resources, sizeof resources, ".");
    strcat(resources, "/resources");
    if (!ensure_python(resources)) return;
    setup_ok = load_inner(info.dli_fname);
}
#define RUN_SETUP() pthread_once(&setup_once, setup)
#endif

/* ------------------------------------------------------------------ shared values */
/* The Python slave (fmus/slave.py: SharedBlock) keeps every variable's value in ONE numpy
 * byte block with the layout below, and hands it over at construction (fmi2Instantiate,
 * fmi2Reset: pythonfmu builds a new slave object then) as
 *     sys._axir_shared[threading.get_ident()] = (address of the block, the block[, fast step
 *                                                 [, fast step I/O]])
 * The shim takes that entry out in the same thread right after the inner call (adopt_shared),
 * checks the header and keeps a strong reference to the block until fmi2FreeInstance, the
 * next fmi2Reset or an fmi2Fatal. Then fmi2Get{Real,Integer,Boolean} and
 * fmi2Set{Real,Integer,Boolean} are served here from the block without entering Python,
 * whenever every value reference of the call is valid for the call (right type; for a set:
 * settable in the current state, the slave's rule); anything else (a wrong value reference,
 * a fixed parameter after initialization, Strings, no block) is forwarded to pythonfmu,
 * whose slave logs the error as before. A set of a tunable parameter after initialization
 * raises the slave's "dirty" flag, as the slave's own set does.
 * Input screening fast path: just before forwarding fmi2DoStep the shim compares every
 * Real/Integer input with its domain bounds from the block (lo <= v <= hi; NaN fails), the
 * comparisons of the slave's _screen_inputs. When all pass it copies them to the block's
 * "held" (last valid) values and sets ctl[2] ("screened"): the slave then skips its own
 * check. Otherwise it leaves ctl[2] at 0 and the slave screens, replaces, logs the Warning.
 * Header: 27 little-endian 64-bit words (byte offsets from the block start):
 *   0 magic "AXIRSHM1", 1 version, 2 n_vars, 3 off kind[n_vars] (uint8: 0 Real, 1 Integer,
 *   2 Boolean, 3 String), 4 off index[n_vars] (int32: position in its type's array),
 *   5 off flags[n_vars] (uint8: 1 settable before/in initialization, 2 settable after,
 *   4 tunable), 6 off real[] (float64), 7 n_real, 8 off integer[] (int64), 9 n_integer,
 *   10 off boolean[] (uint8 0/1), 11 n_boolean, 12 off ctl[3] (int64: initialized, dirty,
 *   screened), 13 off name_offset[n_vars] (int32), 14 off names (NUL-terminated UTF-8),
 *   15 block size, 16-20 Real inputs: n, off pos[n] (int32, in real[]), off lo[n], off hi[n],
 *   off held[n] (float64), 21-25 the same for Integer inputs (int64 lo, hi, held),
 *   26 off step[2] (float64: t, h of the fast step, written by the shim).
 * Windows: no block (the shim does not use Python's C API there): everything is forwarded. */
#define SHM_MAGIC 0x314d485352495841ULL /* "AXIRSHM1" */
#define SHM_VERSION 3
#define SHM_WORDS 27
enum { K_REAL = 0, K_INTEGER = 1, K_BOOLEAN = 2, K_STRING = 3 };
enum { F_SETTABLE_INIT = 1, F_SETTABLE_RUN = 2, F_TUNABLE = 4 };

/* The fast step with its gather and scatter made here (section "fast step I/O"): the
 * slave's io tuple (strong reference) and what the shim reads from it (borrowed from it). */
#define IO_MAX_NDIM 4
#define IO_MAX_ARRAYS 8
typedef struct {
    void *tuple;                 /* (step, finish, forward, words address, words, input keys,
                                    array copies, output keys); NULL: no fast step I/O */
    void *step, *finish, *forward;
    int64_t n_in, n_in_arrays, n_out, n_out_arrays;
    const int64_t *in_desc, *out_desc, *array_desc; /* (kind, offset), (kind, offset),
                                                       (offset, bytes, ndim, shape[4]) */
    void **in_keys, **copies, **out_keys;           /* borrowed items of the tuple */
    int64_t *scratch;                               /* n_out converted scalar outputs */
} FastIO;

typedef struct {
    const unsigned char *kind, *flags;
    const int32_t *index, *name_offset;
    const char *names;
    double *real;
    int64_t *integer;
    unsigned char *boolean;
    int64_t *ctl; /* [0] initialized, [1] dirty (tunable parameters changed), [2] screened */
    uint64_t n_vars;
    uint64_t n_screen_real, n_screen_integer;
    const int32_t *pos_real, *pos_integer;
    const double *lo_real, *hi_real;
    const int64_t *lo_integer, *hi_integer;
    double *held_real;
    int64_t *held_integer;
    double *step; /* [0] t, [1] h: the arguments of the fast step */
    void *owner; /* the block (PyObject *, strong reference); NULL: no shared values */
    void *fast;  /* the slave's fast step (PyObject *, strong reference) or NULL */
    unsigned char *base; /* the block's first byte */
    uint64_t size;       /* the block's size [bytes] */
    FastIO io;           /* the fast step's gather and scatter made here (io.tuple != NULL) */
} Shared;

/* Fill m from the block at addr; 0 if the header or any index is inconsistent. */
static int parse_shared(Shared *m, const unsigned char *addr) {
    uint64_t h[SHM_WORDS], n, i, lim;
    const uint64_t counts[3] = {7, 9, 11};
    memcpy(h, addr, 16 * sizeof h[0]);
    if (h[0] != SHM_MAGIC || h[1] != SHM_VERSION || h[15] < sizeof h) return 0;
    memcpy(h, addr, sizeof h);
    n = h[2];
    lim = h[15];
    if (h[0] != SHM_MAGIC || h[1] != SHM_VERSION || n > (1u << 24) || lim < sizeof h
        || h[3] + n > lim || h[4] % 4 || h[4] + 4 * n > lim || h[5] + n > lim
        || h[6] % 8 || h[6] + 8 * h[7] > lim || h[8] % 8 || h[8] + 8 * h[9] > lim
        || h[10] + h[11] > lim || h[12] % 8 || h[12] + 24 > lim || h[13] % 4
        || h[13] + 4 * n > lim || h[14] >= lim || addr[lim - 1] != '\0' || h[16] > h[7]
        || h[17] % 4 || h[17] + 4 * h[16] > lim || h[18] % 8 || h[18] + 8 * h[16] > lim
        || h[19] % 8 || h[19] + 8 * h[16] > lim || h[20] % 8 || h[20] + 8 * h[16] > lim
        || h[21] > h[9] || h[22] % 4 || h[22] + 4 * h[21] > lim || h[23] % 8
        || h[23] + 8 * h[21] > lim || h[24] % 8 || h[24] + 8 * h[21] > lim || h[25] % 8
        || h[25] + 8 * h[21] > lim || h[26] % 8 || h[26] + 16 > lim)
        return 0;
    m->n_vars = n;
    m->kind = addr + h[3];
    m->index = (const int32_t *)(const void *)(addr + h[4]);
    m->flags = addr + h[5];
    m->real = (double *)(void *)(addr + h[6]);
    m->integer = (int64_t *)(void *)(addr + h[8]);
    m->boolean = (unsigned char *)(addr + h[10]);
    m->ctl = (int64_t *)(void *)(addr + h[12]);
    m->name_offset = (const int32_t *)(const void *)(addr + h[13]);
    m->names = (const char *)addr + h[14];
    m->n_screen_real = h[16];
    m->pos_real = (const int32_t *)(const void *)(addr + h[17]);
    m->lo_real = (const double *)(const void *)(addr + h[18]);
    m->hi_real = (const double *)(const void *)(addr + h[19]);
    m->held_real = (double *)(void *)(addr + h[20]);
    m->n_screen_integer = h[21];
    m->pos_integer = (const int32_t *)(const void *)(addr + h[22]);
    m->lo_integer = (const int64_t *)(const void *)(addr + h[23]);
    m->hi_integer = (const int64_t *)(const void *)(addr + h[24]);
    m->held_integer = (int64_t *)(void *)(addr + h[25]);
    m->step = (double *)(void *)(addr + h[26]);
    for (i = 0; i < m->n_screen_real; i++)
        if (m->pos_real[i] < 0 || (uint64_t)m->pos_real[i] >= h[7]) return 0;
    for (i = 0; i < m->n_screen_integer; i++)
        if (m->pos_integer[i] < 0 || (uint64_t)m->pos_integer[i] >= h[9]) return 0;
    for (i = 0; i < n; i++) {
        if (m->name_offset[i] < 0 || h[14] + (uint64_t)m->name_offset[i] >= lim) return 0;
        if (m->kind[i] == K_STRING) continue;
        if (m->kind[i] > K_STRING || m->index[i] < 0
            || (uint64_t)m->index[i] >= h[counts[m->kind[i]]])
            return 0;
    }
    return 1;
}

/* Before fmi2DoStep: every input in its domain? Then held := inputs and ctl[2] := 1 (the
 * slave skips its screening), else ctl[2] := 0 (the slave screens). */
static void shm_screen(Shared *m) {
    uint64_t i;
    m->ctl[2] = 0;
    for (i = 0; i < m->n_screen_real; i++) {
        double v = m->real[m->pos_real[i]];
        if (!(v >= m->lo_real[i] && v <= m->hi_real[i])) return;
    }
    for (i = 0; i < m->n_screen_integer; i++) {
        int64_t v = m->integer[m->pos_integer[i]];
        if (!(v >= m->lo_integer[i] && v <= m->hi_integer[i])) return;
    }
    for (i = 0; i < m->n_screen_real; i++) m->held_real[i] = m->real[m->pos_real[i]];
    for (i = 0; i < m->n_screen_integer; i++)
        m->held_integer[i] = m->integer[m->pos_integer[i]];
    m->ctl[2] = 1;
}

/* Every value reference of the call is of type kind (and, for a set, settable now: *tunable
 * tells whether a tunable parameter is among them). */
static int shm_covers(const Shared *m, int kind, const fmi2ValueReference vr[], size_t nvr,
                      int set, int *tunable) {
    size_t i;
    unsigned char bit;
    if (m->owner == NULL || (vr == NULL && nvr > 0)) return 0; /* no block: forward */
    bit = m->ctl[0] ? F_SETTABLE_RUN : F_SETTABLE_INIT;
    for (i = 0; i < nvr; i++) {
        fmi2ValueReference v = vr[i];
        if (v >= m->n_vars || m->kind[v] != kind) return 0;
        if (set) {
            if (!(m->flags[v] & bit)) return 0;
            if (m->flags[v] & F_TUNABLE) *tunable = 1;
        }
    }
    return 1;
}

/* ------------------------------------------------------------------ fast step I/O */
/* The slave may hand over, with its fast step, an io tuple (fmus/step_plan.py: make_fast_io):
 *   (step, finish, forward, words address, words, input keys, array copies, output keys)
 * words (int64): [n scalar inputs, n array inputs, n scalar outputs, n array outputs], then
 * (kind, byte offset) per scalar input, (kind, byte offset) per scalar output, (byte offset,
 * byte count, ndim, shape[4]) per array output; kinds 0 Real (float64), 1 Integer (int64),
 * 2 Boolean (one byte). The fast step then builds the input dict here (the scalars as
 * Python float/int/bool, then the arrays' fresh copies: the array copy callables), calls
 * step(inputs), which answers the model's output mapping or `forward`, and stores the outputs
 * here when every one has a plain value (io_scatter), else calls finish(out), the slave's
 * Python scatter. Windows: not used (no block). */
#ifndef _WIN32
typedef struct { /* Py_buffer (stable layout) */
    void *buf, *obj;
    ssize_t len, itemsize;
    int readonly, ndim;
    char *format;
    ssize_t *shape, *strides, *suboffsets;
    void *internal;
} PyBufferView;
#define BUF_C_CONTIGUOUS_FORMAT 0x3C        /* PyBUF_C_CONTIGUOUS | PyBUF_FORMAT */

static void io_release(FastIO *io) {
    if (io->tuple != NULL) py.DecRef(io->tuple);
    free(io->in_keys);
    free(io->copies);
    free(io->out_keys);
    free(io->scratch);
    memset(io, 0, sizeof *io);
}

static int io_api(void) {
    return py.DictNew && py.DictSetItem && py.FloatFromDouble && py.LongFromLongLong
           && py.BoolFromLong && py.FloatAsDouble && py.LongAsLongLong && py.ErrOccurred
           && py.GetBuffer && py.BufferRelease && py.CallFunctionObjArgs && py.ObjectType
           && py.LongType
           && py.BoolType && py.DictType && py.TupleSize && py.TupleGetItem && py.LongAsVoidPtr;
}

/* Take the io tuple t (GIL held) into m->io; 0 (nothing kept) when anything is inconsistent
 * with the block. */
static int io_adopt(Shared *m, void *t) {
    FastIO io;
    const int64_t *w;
    int64_t i, k, need, n_keys_in, n_keys_out;
    memset(&io, 0, sizeof io);
    if (!io_api() || py.TupleSize(t) != 8) return 0;
    io.step = py.TupleGetItem(t, 0);
    io.finish = py.TupleGetItem(t, 1);
    io.forward = py.TupleGetItem(t, 2);
    w = (const int64_t *)py.LongAsVoidPtr(py.TupleGetItem(t, 3));
    if (w == NULL || io.step == NULL || io.finish == NULL || io.forward == NULL
        || !py.CallableCheck(io.step) || !py.CallableCheck(io.finish)) {
        py.ErrClear();
        return 0;
    }
    io.n_in = w[0];
    io.n_in_arrays = w[1];
    io.n_out = w[2];
    io.n_out_arrays = w[3];
    if (io.n_in < 0 || io.n_in_arrays < 0 || io.n_out < 0 || io.n_out_arrays < 0
        || io.n_in > (1 << 24) || io.n_in_arrays > (1 << 24) || io.n_out > (1 << 24)
        || io.n_out_arrays > IO_MAX_ARRAYS)
        return 0;
    io.in_desc = w + 4;
    io.out_desc = io.in_desc + 2 * io.n_in;
    io.array_desc = io.out_desc + 2 * io.n_out;
    for (i = 0; i < io.n_in + io.n_out; i++) { /* scalars: kind, offset inside the block */
        k = io.in_desc[2 * i];
        need = k == K_BOOLEAN ? 1 : 8;
        if (k < K_REAL || k > K_BOOLEAN || io.in_desc[2 * i + 1] < 0
            || (uint64_t)(io.in_desc[2 * i + 1] + need) > m->size || (need == 8 && io.in_desc[2 * i + 1] % 8))
            return 0;
    }
    for (i = 0; i < io.n_out_arrays; i++) {
        const int64_t *a = io.array_desc + 7 * i;
        need = 8;
        if (a[2] < 1 || a[2] > IO_MAX_NDIM) return 0;
        for (k = 0; k < a[2]; k++) {
            if (a[3 + k] < 1 || a[3 + k] > (1 << 24)) return 0;
            need *= a[3 + k];
        }
        if (a[0] < 0 || a[0] % 8 || a[1] != need || (uint64_t)(a[0] + a[1]) > m->size) return 0;
    }
    n_keys_in = io.n_in + io.n_in_arrays;
    n_keys_out = io.n_out + io.n_out_arrays;
    if (py.TupleSize(py.TupleGetItem(t, 5)) != n_keys_in
        || py.TupleSize(py.TupleGetItem(t, 6)) != io.n_in_arrays
        || py.TupleSize(py.TupleGetItem(t, 7)) != n_keys_out) {
        py.ErrClear();
        return 0;
    }
    io.in_keys = calloc((size_t)n_keys_in + 1, sizeof(void *));
    io.copies = calloc((size_t)io.n_in_arrays + 1, sizeof(void *));
    io.out_keys = calloc((size_t)n_keys_out + 1, sizeof(void *));
    io.scratch = calloc((size_t)io.n_out + 1, sizeof(int64_t));
    if (io.in_keys == NULL || io.copies == NULL || io.out_keys == NULL || io.scratch == NULL) {
        io_release(&io);
        return 0;
    }
    for (i = 0; i < n_keys_in; i++) io.in_keys[i] = py.TupleGetItem(py.TupleGetItem(t, 5), i);
    for (i = 0; i < io.n_in_arrays; i++) {
        io.copies[i] = py.TupleGetItem(py.TupleGetItem(t, 6), i);
        if (io.copies[i] == NULL || !py.CallableCheck(io.copies[i])) {
            io_release(&io);
            py.ErrClear();
            return 0;
        }
    }
    for (i = 0; i < n_keys_out; i++) io.out_keys[i] = py.TupleGetItem(py.TupleGetItem(t, 7), i);
    py.IncRef(t);
    io.tuple = t;
    m->io = io;
    return 1;
}

/* The input mapping of the fast step (a new dict; NULL with a Python exception set). */
static void *io_gather(const Shared *m) {
    const FastIO *io = &m->io;
    void *d = py.DictNew(), *v;
    int64_t i;
    if (d == NULL) return NULL;
    for (i = 0; i < io->n_in; i++) {
        const unsigned char *at = m->base + io->in_desc[2 * i + 1];
        switch (io->in_desc[2 * i]) {
        case K_REAL: {
            double x;
            memcpy(&x, at, sizeof x);
            v = py.FloatFromDouble(x);
            break;
        }
        case K_INTEGER: {
            int64_t x;
            memcpy(&x, at, sizeof x);
            v = py.LongFromLongLong((long long)x);
            break;
        }
        default:
            v = py.BoolFromLong(*at != 0);
        }
        if (v == NULL || py.DictSetItem(d, io->in_keys[i], v) < 0) {
            if (v != NULL) py.DecRef(v);
            py.DecRef(d);
            return NULL;
        }
        py.DecRef(v);
    }
    for (i = 0; i < io->n_in_arrays; i++) {
        v = py.CallObject(io->copies[i], NULL);
        if (v == NULL || py.DictSetItem(d, io->in_keys[io->n_in + i], v) < 0) {
            if (v != NULL) py.DecRef(v);
            py.DecRef(d);
            return NULL;
        }
        py.DecRef(v);
    }
    return d;
}

/* The type of o, compared by identity (PyObject_Type: no assumption on the object layout). */
static void *type_of(void *o) {
    void *t = py.ObjectType(o);
    if (t != NULL) py.DecRef(t); /* a type outlives the object that has it */
    return t;
}

static int is_float64_format(const char *f) {
    if (f == NULL) return 0;
    if (*f == '<' || *f == '=' || *f == '@') f++;
    return f[0] == 'd' && f[1] == '\0';
}

/* Store the model's outputs `out` into the block when every one has a plain value (see
 * fmus/step_plan.py: make_fast_io): 1 when stored; 0 when not, with nothing stored and no
 * Python exception left set (the caller then runs the slave's Python scatter). */
static int io_scatter(Shared *m, void *out) {
    FastIO *io = &m->io;
    PyBufferView views[IO_MAX_ARRAYS];
    int64_t i, k, nv = 0, ok = 1;
    if (out == NULL || type_of(out) != py.DictType) return 0;
    for (i = 0; i < io->n_out && ok; i++) {
        void *v = py.DictGetItem(out, io->out_keys[i]), *tp; /* borrowed; NULL: missing */
        if (v == NULL) {
            ok = 0;
            break;
        }
        if (io->out_desc[2 * i] == K_REAL) {
            double x = py.FloatAsDouble(v); /* struct.pack('d')'s conversion */
            if (x == -1.0 && py.ErrOccurred() != NULL) ok = 0;
            memcpy(&io->scratch[i], &x, sizeof x);
            continue;
        }
        tp = type_of(v); /* Integer, Boolean: exact int or bool only */
        if (tp != py.LongType && tp != py.BoolType) {
            ok = 0;
            break;
        }
        io->scratch[i] = (int64_t)py.LongAsLongLong(v);
        if (io->scratch[i] == -1 && py.ErrOccurred() != NULL) ok = 0;
    }
    for (i = 0; i < io->n_out_arrays && ok; i++) {
        const int64_t *a = io->array_desc + 7 * i;
        void *v = py.DictGetItem(out, io->out_keys[io->n_out + i]);
        if (v == NULL || py.GetBuffer(v, &views[nv], BUF_C_CONTIGUOUS_FORMAT) != 0) {
            ok = 0;
            break;
        }
        nv++;
        if (views[nv - 1].itemsize != 8 || views[nv - 1].len != a[1]
            || views[nv - 1].ndim != a[2] || !is_float64_format(views[nv - 1].format)) {
            ok = 0;
            break;
        }
        for (k = 0; k < a[2]; k++)
            if (views[nv - 1].shape == NULL || views[nv - 1].shape[k] != a[3 + k]) ok = 0;
    }
    if (ok) {
        for (i = 0; i < io->n_out; i++) {
            unsigned char *at = m->base + io->out_desc[2 * i + 1];
            if (io->out_desc[2 * i] == K_BOOLEAN) *at = io->scratch[i] != 0;
            else memcpy(at, &io->scratch[i], 8);
        }
        for (i = 0; i < io->n_out_arrays; i++)
            memcpy(m->base + io->array_desc[7 * i], views[i].buf, (size_t)io->array_desc[7 * i + 1]);
    }
    for (i = 0; i < nv; i++) py.BufferRelease(&views[i]);
    if (!ok) py.ErrClear();
    return (int)ok;
}
#endif

/* ------------------------------------------------------------------ the shim's instance */
#define MAX_PENDING 8

typedef struct {
    fmi2Component inner;             /* pythonfmu's component */
    Shared shm;                      /* the slave's values (see "shared values") */
    int warning_logged;              /* a Warning message was logged during this call */
    fmi2CallbackFunctions host;      /* copy of the host's callbacks */
    fmi2CallbackFunctions wrapped;   /* handed to pythonfmu (it keeps the pointer) */
    char *instance_name;
    int error_logged;                /* an Error/Fatal message was logged during this call */
    fmi2Boolean logging_on;          /* the host's logging settings */
    size_t n_categories;
    char **categories;
    int instantiating;               /* inside fmi2Instantiate: keep filtered-out errors */
    int n_pending;
    fmi2Status pending_status[MAX_PENDING];
    char *pending_category[MAX_PENDING], *pending_message[MAX_PENDING];
    int fast_time_valid;             /* last_time is the fmi2LastSuccessfulTime (fast steps) */
    double last_time;
} Shim;

/* Let the slave's block and fast step go (GIL taken; nothing if Python is gone). */
static void release_shared(Shim *s) {
    void *owner = s->shm.owner, *fast = s->shm.fast;
    FastIO io = s->shm.io;
    memset(&s->shm, 0, sizeof s->shm);
#ifndef _WIN32
    if (owner != NULL && py.IsInitialized != NULL && py.IsInitialized()) {
        int gil = py.GILStateEnsure();
        py.DecRef(owner);
        if (fast != NULL) py.DecRef(fast);
        io_release(&io);
        py.GILStateRelease(gil);
    } else {
        io.tuple = NULL; /* Python is gone: free the C arrays only */
        io_release(&io);
    }
#else
    (void)owner;
    (void)fast;
#endif
}

/* Take the block the slave just handed over in this thread (see "shared values"); without
 * one (or a bad one) every get/set is forwarded. */
static void adopt_shared(Shim *s) {
#ifndef _WIN32
    void *d, *key, *t, *owner, *fast, *io;
    ssize_t n;
    const unsigned char *addr;
    int gil;
    release_shared(s);
    if (py.ThreadGetIdent == NULL || py.LongFromUnsignedLong == NULL || py.LongAsVoidPtr == NULL
        || py.DictGetItem == NULL || py.DictDelItem == NULL || py.TupleSize == NULL
        || py.TupleGetItem == NULL || py.ErrClear == NULL || py.IncRef == NULL)
        return;
    gil = py.GILStateEnsure();
    d = py.SysGetObject("_axir_shared"); /* borrowed */
    key = d != NULL ? py.LongFromUnsignedLong(py.ThreadGetIdent()) : NULL;
    if (key != NULL) {
        t = py.DictGetItem(d, key); /* borrowed */
        n = t != NULL ? py.TupleSize(t) : 0;
        if (n >= 2 && n <= 4) {
            addr = (const unsigned char *)py.LongAsVoidPtr(py.TupleGetItem(t, 0));
            owner = py.TupleGetItem(t, 1);
            fast = n >= 3 ? py.TupleGetItem(t, 2) : NULL;
            io = n == 4 ? py.TupleGetItem(t, 3) : NULL;
            if (addr != NULL && owner != NULL && parse_shared(&s->shm, addr)) {
                py.IncRef(owner);
                s->shm.owner = owner;
                s->shm.base = (unsigned char *)addr;
                memcpy(&s->shm.size, addr + 15 * 8, sizeof s->shm.size);
                if (fast != NULL && py.CallObject != NULL && py.LongAsLong != NULL
                    && py.CallableCheck != NULL && py.CallableCheck(fast)) {
                    py.IncRef(fast);
                    s->shm.fast = fast;
                    if (io != NULL) io_adopt(&s->shm, io); /* None or bad: no I/O here */
                }
            } else {
                memset(&s->shm, 0, sizeof s->shm);
            }
        }
        if (t != NULL) py.DictDelItem(d, key);
        py.DecRef(key);
    }
    py.ErrClear();
    py.GILStateRelease(gil);
#else
    (void)s;
#endif
}

static void free_categories(Shim *s) {
    size_t i;
    for (i = 0; i < s->n_categories; i++) free(s->categories[i]);
    free(s->categories);
    s->categories = NULL;
    s->n_categories = 0;
}

static int host_wants(const Shim *s, fmi2String category) {
    size_t i;
    const char *cat = category ? category : "";
    if (!s->logging_on) return 0;
    if (s->n_categories == 0) return 1;
    for (i = 0; i < s->n_categories; i++)
        if (strcmp(s->categories[i], cat) == 0) return 1;
    return 0;
}

static void shim_logger(fmi2ComponentEnvironment env, fmi2String instance_name,
                        fmi2Status status, fmi2String category, fmi2String message, ...) {
    Shim *s = (Shim *)env;
    int k;
    if (s == NULL) return;
    if (status == fmi2Error || status == fmi2Fatal) s->error_logged = 1;
    if (status == fmi2Warning) s->warning_logged = 1;
    if (s->host.logger != NULL && host_wants(s, category)) {
        /* pythonfmu passes the formatted message as the format: so do we */
        s->host.logger(s->host.componentEnvironment, instance_name, status, category, message);
    } else if (s->instantiating && (status == fmi2Error || status == fmi2Fatal)
               && s->n_pending < MAX_PENDING) {
        k = s->n_pending++;
        s->pending_status[k] = status;
        s->pending_category[k] = copy_string(category ? category : "");
        s->pending_message[k] = copy_string(message ? message : "");
    }
}

static void shim_step_finished(fmi2ComponentEnvironment env, fmi2Status status) {
    Shim *s = (Shim *)env;
    if (s != NULL && s->host.stepFinished != NULL)
        s->host.stepFinished(s->host.componentEnvironment, status);
}

static void release_shared(Shim *s);

/* The status of a forwarded call: fmi2Error if an Error was logged during it (unless it is
 * Fatal/Pending already), fmi2Warning if only a Warning was logged and the call said OK.
 * After fmi2Fatal pythonfmu dropped the slave: the shared values are let go, and so is
 * pythonfmu's component. pythonfmu 0.7.0 releases its Python objects (slave class, instance,
 * log list) when a Python exception reaches it (handle_py_exception -> cleanPyObject) without
 * forgetting them, and its destructor (fmi2FreeInstance) releases them a second time: the
 * slave class is freed while still in use and the process crashes later (in a garbage
 * collection or at exit); any other call would use the freed instance. So the shim never
 * calls into that component again: later calls answer fmi2Error (FMI 2.0 allows only
 * fmi2FreeInstance after fmi2Fatal), fmi2FreeInstance frees the shim only (pythonfmu's small
 * C++ component is leaked). */
static fmi2Status finish(Shim *s, fmi2Status status) {
    if (status == fmi2Fatal) {
        release_shared(s);
        s->inner = NULL;
    }
    if (s->error_logged && (status == fmi2OK || status == fmi2Warning || status == fmi2Discard))
        return fmi2Error;
    if (s->warning_logged && status == fmi2OK) return fmi2Warning;
    return status;
}

/* Log a message like pythonfmu does: already formatted, passed as the format with '%'
 * doubled (so that hosts which format and hosts which do not both show it). Without a
 * logger: on stderr. */
static void log_text(const fmi2CallbackFunctions *host, fmi2String instance_name,
                     fmi2Status status, fmi2String category, const char *text) {
    char buf[2 * sizeof setup_error + 1];
    size_t i = 0;
    if (host == NULL || host->logger == NULL) {
        fprintf(stderr, "[%s] %s\n", instance_name ? instance_name : "?", text);
        fflush(stderr);
        return;
    }
    for (; *text != '\0' && i + 2 < sizeof buf; text++) {
        if (*text == '%') buf[i++] = '%';
        buf[i++] = *text;
    }
    buf[i] = '\0';
    host->logger(host->componentEnvironment, instance_name, status, category, buf);
}

static fmi2Status unsupported(Shim *s, const char *function) {
    char text[200];
    if (s->host.logger != NULL && host_wants(s, "logStatusError")) {
        snprintf(text, sizeof text, "%s is not provided by the pythonfmu binary", function);
        log_text(&s->host, s->instance_name, fmi2Error, "logStatusError", text);
    }
    return fmi2Error;
}

/* Forward fmi2<f>(c, ...) to the inner binary and apply the Error rule. */
#define FORWARD(f, c, ...)                                   \
    do {                                                     \
        Shim *s_ = (Shim *)(c);                              \
        if (s_ == NULL || s_->inner == NULL) return fmi2Error; \
        if (api.f == NULL) return unsupported(s_, "fmi2" #f); \
        s_->error_logged = s_->warning_logged = 0;           \
        return finish(s_, api.f(s_->inner, __VA_ARGS__));    \
    } while (0)

#define FORWARD0(f, c)                                       \
    do {                                                     \
        Shim *s_ = (Shim *)(c);                              \
        if (s_ == NULL || s_->inner == NULL) return fmi2Error; \
        if (api.f == NULL) return unsupported(s_, "fmi2" #f); \
        s_->error_logged = s_->warning_logged = 0;           \
        return finish(s_, api.f(s_->inner));                 \
    } while (0)

/* ------------------------------------------------------------------ fast step */
/* fmi2DoStep without pythonfmu's bridge (issue 14): when the instance is initialized, no
 * tunable parameter changed and every input passed shm_screen, the shim writes t and h into
 * the block and calls the slave's fast step (fmus/step_plan.py, handed over with the block)
 * with the GIL taken, as pythonfmu takes it. It answers 0 (FAST_DONE): the step is made,
 * nothing was logged; the call returns fmi2OK and the shim remembers t + h as the
 * fmi2LastSuccessfulTime (pythonfmu's is not updated; fmi2GetRealStatus answers it here
 * until a forwarded doStep updates pythonfmu's). It answers 1 (FAST_FORWARD) having changed
 * nothing the regular path would not (the slave failed, or the model raised: the exception
 * is kept and raised again by the slave's do_step): the call is forwarded to pythonfmu as
 * before, with the same status, log and state. Returns FAST_DONE, FAST_FORWARD, or
 * FAST_FAILED: the fast step did not answer (cannot happen: it catches everything): an Error
 * is logged, the fast step is never used again and the call answers fmi2Error. */
enum { FAST_DONE = 0, FAST_FORWARD = 1, FAST_FAILED = 2 };

static int fast_step(Shim *s, double t, double h) {
#ifndef _WIN32
    int gil, done, answered = 0;
    long r = -1;
    void *res, *type, *value, *tb, *text;
    const char *why;
    char msg[700];
    s->shm.step[0] = t;
    s->shm.step[1] = h;
    gil = py.GILStateEnsure();
    if (s->shm.io.tuple != NULL) { /* gather and scatter here (section "fast step I/O") */
        void *inputs = io_gather(&s->shm), *out = NULL;
        if (inputs != NULL) {
            out = py.CallFunctionObjArgs(s->shm.io.step, inputs, NULL);
            py.DecRef(inputs);
        }
        if (out == s->shm.io.forward) {
            r = FAST_FORWARD;
            answered = 1;
        } else if (out != NULL && io_scatter(&s->shm, out)) {
            r = FAST_DONE;
            answered = 1;
        } else if (out != NULL) { /* the slave's Python scatter */
            res = py.CallFunctionObjArgs(s->shm.io.finish, out, NULL);
            if (res != NULL) {
                r = py.LongAsLong(res);
                answered = 1;
                py.DecRef(res);
            }
        }
        if (out != NULL) py.DecRef(out);
    } else {
        res = py.CallObject(s->shm.fast, NULL);
        if (res != NULL) {
            r = py.LongAsLong(res);
            answered = 1;
            py.DecRef(res);
        }
    }
    done = r == FAST_DONE ? FAST_DONE : FAST_FORWARD;
    if (!answered || (r != FAST_DONE && r != FAST_FORWARD)) {
        /* cannot happen (the fast step catches everything): say so, never use it again */
        type = value = tb = NULL;
        py.ErrFetch(&type, &value, &tb);
        text = value != NULL ? py.ObjectStr(value) : NULL;
        why = text != NULL ? py.UnicodeAsUTF8(text) : NULL;
        snprintf(msg, sizeof msg, "%s: fmi2DoStep: the slave's fast step failed (%.500s); the "
                 "model state is undefined, restore an FMU state or reset the instance",
                 s->instance_name, why ? why : "unexpected answer");
        py.ErrClear();
        if (text != NULL) py.DecRef(text);
        if (type != NULL) py.DecRef(type);
        if (value != NULL) py.DecRef(value);
        if (tb != NULL) py.DecRef(tb);
        py.DecRef(s->shm.fast);
        s->shm.fast = NULL;
        io_release(&s->shm.io);
        if (s->host.logger != NULL && host_wants(s, "logStatusError"))
            log_text(&s->host, s->instance_name, fmi2Error, "logStatusError", msg);
        done = FAST_FAILED;
    }
    py.GILStateRelease(gil);
    if (done == FAST_DONE) s->shm.ctl[2] = 0; /* screening used, as _screen_inputs does */
    return done;
#else
    (void)s;
    (void)t;
    (void)h;
    return FAST_FORWARD;
#endif
}

/* ------------------------------------------------------------------ common functions */
const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }

const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[]) {
    Shim *s = (Shim *)c;
    size_t i;
    if (s == NULL || s->inner == NULL) return fmi2Error;
    free_categories(s);
    s->logging_on = loggingOn;
    if (nCategories > 0 && categories != NULL) {
        s->categories = (char **)calloc(nCategories, sizeof(char *));
        if (s->categories == NULL) return fmi2Error;
        for (i = 0; i < nCategories; i++) {
            s->categories[i] = copy_string(categories[i] ? categories[i] : "");
            if (s->categories[i] == NULL) {
                s->n_categories = i;
                free_categories(s);
                return fmi2Error;
            }
        }
        s->n_categories = nCategories;
    }
    /* the inner instance keeps logging everything: the shim filters (see top) */
    s->error_logged = s->warning_logged = 0;
    return finish(s, api.SetDebugLogging(s->inner, fmi2True, 0, NULL));
}

static void free_shim(Shim *s) {
    int k;
    for (k = 0; k < s->n_pending; k++) {
        free(s->pending_category[k]);
        free(s->pending_message[k]);
    }
    free_categories(s);
    free(s->instance_name);
    free(s);
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation,
                              const fmi2CallbackFunctions *functions, fmi2Boolean visible,
                              fmi2Boolean loggingOn) {
    Shim *s;
    int k;
    RUN_SETUP();
    if (!setup_ok) {
        /* always delivered: the only diagnostic (FMI 2.0 allows error messages then) */
        log_text(functions, instanceName, fmi2Fatal, "logStatusFatal", setup_error);
        return NULL;
    }
    if (functions == NULL) return NULL;
    s = (Shim *)calloc(1, sizeof(Shim));
    if (s == NULL) return NULL;
    s->host = *functions;
    s->wrapped = *functions;
    s->wrapped.logger = shim_logger;
    s->wrapped.stepFinished = functions->stepFinished ? shim_step_finished : NULL;
    s->wrapped.componentEnvironment = s;
    s->logging_on = loggingOn;
    s->instance_name = copy_string(instanceName ? instanceName : "");
    if (s->instance_name == NULL) {
        free(s);
        return NULL;
    }
    s->instantiating = 1;
    LOCK(&instantiate_lock);
    s->inner = api.Instantiate(instanceName, fmuType, fmuGUID, fmuResourceLocation, &s->wrapped,
                               visible, fmi2True);
#ifndef _WIN32
    /* pythonfmu's PyState owns nothing (Python was initialized before): drop it now rather
     * than in the exit handlers (see the top). (Not on Windows: there pythonfmu may own the
     * interpreter.) */
    if (api.finalizePythonInterpreter != NULL) api.finalizePythonInterpreter();
#endif
    UNLOCK(&instantiate_lock);
    s->instantiating = 0;
    if (s->inner != NULL) adopt_shared(s);
    if (s->inner == NULL) {
        /* errors the host's logging settings held back: delivered now (as pythonfmu logs
         * them: the message is the format), on stderr without a logger */
        for (k = 0; k < s->n_pending; k++) {
            if (s->pending_message[k] == NULL) continue;
            if (s->host.logger != NULL)
                s->host.logger(s->host.componentEnvironment, s->instance_name,
                               s->pending_status[k], s->pending_category[k],
                               s->pending_message[k]);
            else
                fprintf(stderr, "[%s] %s\n", s->instance_name, s->pending_message[k]);
        }
        free_shim(s);
        return NULL;
    }
    for (k = 0; k < s->n_pending; k++) {
        free(s->pending_category[k]);
        free(s->pending_message[k]);
    }
    s->n_pending = 0;
    return s;
}

void fmi2FreeInstance(fmi2Component c) {
    Shim *s = (Shim *)c;
    if (s == NULL) return;
    if (s->inner != NULL) api.FreeInstance(s->inner);
    release_shared(s);
    free_shim(s);
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined,
                               fmi2Real tolerance, fmi2Real startTime,
                               fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
    FORWARD(SetupExperiment, c, toleranceDefined, tolerance, startTime, stopTimeDefined,
            stopTime);
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) { FORWARD0(EnterInitializationMode, c); }

fmi2Status fmi2ExitInitializationMode(fmi2Component c) { FORWARD0(ExitInitializationMode, c); }

fmi2Status fmi2Terminate(fmi2Component c) { FORWARD0(Terminate, c); }

fmi2Status fmi2Reset(fmi2Component c) {
    Shim *s = (Shim *)c;
    fmi2Status status;
    if (s == NULL || s->inner == NULL) return fmi2Error;
    if (api.Reset == NULL) return unsupported(s, "fmi2Reset");
    release_shared(s); /* pythonfmu builds a new slave object, with a new block */
    s->error_logged = s->warning_logged = 0;
    status = finish(s, api.Reset(s->inner));
    if (status == fmi2OK || status == fmi2Warning) {
        adopt_shared(s);
        /* back to the instantiated state, also for fmi2LastSuccessfulTime: cppfmu's Reset
         * leaves its lastSuccessfulTime as it was (the last forwarded doStep's), the shim's
         * own (fast steps) must not outlive the reset either; answered here as a fresh
         * instance answers it (cppfmu's initial quiet NaN, tests/test_fmu_fast_step.py)
         * until the next doStep. */
        s->last_time = NAN;
        s->fast_time_valid = 1;
    }
    return status;
}

/* ------------------------------------------------------------------ get / set values */
/* Served from the shared block when it covers the call (see "shared values"), else
 * forwarded to pythonfmu. */
fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                       fmi2Real value[]) {
    Shim *s = (Shim *)c;
    size_t i;
    if (s != NULL && value != NULL && shm_covers(&s->shm, K_REAL, vr, nvr, 0, NULL)) {
        for (i = 0; i < nvr; i++) value[i] = s->shm.real[s->shm.index[vr[i]]];
        return fmi2OK;
    }
    FORWARD(GetReal, c, vr, nvr, value);
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          fmi2Integer value[]) {
    Shim *s = (Shim *)c;
    size_t i;
    if (s != NULL && value != NULL && shm_covers(&s->shm, K_INTEGER, vr, nvr, 0, NULL)) {
        for (i = 0; i < nvr; i++) value[i] = (fmi2Integer)s->shm.integer[s->shm.index[vr[i]]];
        return fmi2OK;
    }
    FORWARD(GetInteger, c, vr, nvr, value);
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          fmi2Boolean value[]) {
    Shim *s = (Shim *)c;
    size_t i;
    if (s != NULL && value != NULL && shm_covers(&s->shm, K_BOOLEAN, vr, nvr, 0, NULL)) {
        for (i = 0; i < nvr; i++)
            value[i] = s->shm.boolean[s->shm.index[vr[i]]] ? fmi2True : fmi2False;
        return fmi2OK;
    }
    FORWARD(GetBoolean, c, vr, nvr, value);
}

fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                         fmi2String value[]) {
    FORWARD(GetString, c, vr, nvr, value);
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                       const fmi2Real value[]) {
    Shim *s = (Shim *)c;
    size_t i;
    int tunable = 0;
    if (s != NULL && value != NULL && shm_covers(&s->shm, K_REAL, vr, nvr, 1, &tunable)) {
        for (i = 0; i < nvr; i++) s->shm.real[s->shm.index[vr[i]]] = value[i];
        if (tunable && s->shm.ctl[0]) s->shm.ctl[1] = 1;
        return fmi2OK;
    }
    FORWARD(SetReal, c, vr, nvr, value);
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          const fmi2Integer value[]) {
    Shim *s = (Shim *)c;
    size_t i;
    int tunable = 0;
    if (s != NULL && value != NULL && shm_covers(&s->shm, K_INTEGER, vr, nvr, 1, &tunable)) {
        for (i = 0; i < nvr; i++) s->shm.integer[s->shm.index[vr[i]]] = value[i];
        if (tunable && s->shm.ctl[0]) s->shm.ctl[1] = 1;
        return fmi2OK;
    }
    FORWARD(SetInteger, c, vr, nvr, value);
}

/* fmi2Boolean is an int: only fmi2True (1) and fmi2False (0) are Booleans. pythonfmu would
 * take any other value as true; the shim refuses the whole call (nothing set) with an Error
 * naming the variable. */
fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          const fmi2Boolean value[]) {
    Shim *s = (Shim *)c;
    size_t i, bad = 0, first = 0;
    int tunable = 0;
    char text[600], name[400];
    if (s == NULL || s->inner == NULL) return fmi2Error;
    for (i = 0; value != NULL && i < nvr; i++)
        if (value[i] != fmi2True && value[i] != fmi2False && bad++ == 0) first = i;
    if (bad > 0) {
        if (s->shm.owner != NULL && vr != NULL && vr[first] < s->shm.n_vars)
            snprintf(name, sizeof name, "%s", s->shm.names + s->shm.name_offset[vr[first]]);
        else
            snprintf(name, sizeof name, "value reference %u", vr ? (unsigned)vr[first] : 0u);
        if (s->host.logger != NULL && host_wants(s, "logStatusError")) {
            snprintf(text, sizeof text, "%s: fmi2SetBoolean: %s = %d is not a Boolean "
                     "(fmi2True = 1 or fmi2False = 0)%s: nothing set", s->instance_name, name,
                     (int)value[first], bad > 1 ? " (and other values)" : "");
            log_text(&s->host, s->instance_name, fmi2Error, "logStatusError", text);
        }
        return fmi2Error;
    }
    if (value != NULL && shm_covers(&s->shm, K_BOOLEAN, vr, nvr, 1, &tunable)) {
        for (i = 0; i < nvr; i++) s->shm.boolean[s->shm.index[vr[i]]] = value[i] ? 1 : 0;
        if (tunable && s->shm.ctl[0]) s->shm.ctl[1] = 1;
        return fmi2OK;
    }
    FORWARD(SetBoolean, c, vr, nvr, value);
}

fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                         const fmi2String value[]) {
    FORWARD(SetString, c, vr, nvr, value);
}

/* ------------------------------------------------------------------ FMU state */
fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *FMUstate) {
    FORWARD(GetFMUstate, c, FMUstate);
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate FMUstate) {
    FORWARD(SetFMUstate, c, FMUstate);
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *FMUstate) {
    FORWARD(FreeFMUstate, c, FMUstate);
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate FMUstate, size_t *size) {
    FORWARD(SerializedFMUstateSize, c, FMUstate, size);
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate FMUstate,
                                 fmi2Byte serializedState[], size_t size) {
    FORWARD(SerializeFMUstate, c, FMUstate, serializedState, size);
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serializedState[],
                                   size_t size, fmi2FMUstate *FMUstate) {
    FORWARD(DeSerializeFMUstate, c, serializedState, size, FMUstate);
}

/* ------------------------------------------------------------------ derivatives */
fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown_ref[],
                                        size_t nUnknown, const fmi2ValueReference vKnown_ref[],
                                        size_t nKnown, const fmi2Real dvKnown[],
                                        fmi2Real dvUnknown[]) {
    FORWARD(GetDirectionalDerivative, c, vUnknown_ref, nUnknown, vKnown_ref, nKnown, dvKnown,
            dvUnknown);
}

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[],
                                       size_t nvr, const fmi2Integer order[],
                                       const fmi2Real value[]) {
    FORWARD(SetRealInputDerivatives, c, vr, nvr, order, value);
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[],
                                        size_t nvr, const fmi2Integer order[],
                                        fmi2Real value[]) {
    FORWARD(GetRealOutputDerivatives, c, vr, nvr, order, value);
}

/* ------------------------------------------------------------------ stepping, status */
fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint,
                      fmi2Real communicationStepSize,
                      fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
    Shim *s = (Shim *)c;
    fmi2Status status;
    if (s == NULL || s->inner == NULL) return fmi2Error;
    if (api.DoStep == NULL) return unsupported(s, "fmi2DoStep");
    if (s->shm.owner != NULL && s->shm.ctl[0]) {
        shm_screen(&s->shm);
        if (s->shm.fast != NULL && s->shm.ctl[2] && !s->shm.ctl[1]) {
            switch (fast_step(s, currentCommunicationPoint, communicationStepSize)) {
            case FAST_DONE:
                s->last_time = currentCommunicationPoint + communicationStepSize;
                s->fast_time_valid = 1;
                return fmi2OK;
            case FAST_FAILED:
                return fmi2Error;
            default:
                break; /* forward */
            }
        }
    }
    s->error_logged = s->warning_logged = 0;
    status = api.DoStep(s->inner, currentCommunicationPoint, communicationStepSize,
                        noSetFMUStatePriorToCurrentPoint);
    /* pythonfmu set its lastSuccessfulTime (t + h on OK, t on Discard) */
    if (status == fmi2OK || status == fmi2Discard) s->fast_time_valid = 0;
    return finish(s, status);
}

fmi2Status fmi2CancelStep(fmi2Component c) { FORWARD0(CancelStep, c); }

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value) {
    FORWARD(GetStatus, c, s, value);
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value) {
    Shim *sh = (Shim *)c;
    /* after fast steps pythonfmu's lastSuccessfulTime is stale: the shim's is the one */
    if (sh != NULL && sh->inner != NULL && sh->fast_time_valid && s == fmi2LastSuccessfulTime
        && value != NULL) {
        *value = sh->last_time;
        return fmi2OK;
    }
    FORWARD(GetRealStatus, c, s, value);
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value) {
    FORWARD(GetIntegerStatus, c, s, value);
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value) {
    FORWARD(GetBooleanStatus, c, s, value);
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value) {
    FORWARD(GetStringStatus, c, s, value);
}
