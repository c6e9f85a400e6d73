/*
 * lifecycle_host.c -- load, run and unload FMI 2.0 co-simulation FMUs in the ways a
 * non-Python host does, then end main with a plain `return 0` (the exit handlers run).
 * See tests/test_host_lifecycle.py and docs/other_tools.md section 1.4.
 *
 * Usage:
 *   lifecycle_host MODE STEPS FMU_DIR [FMU_DIR2]
 *
 *   MODE     once    one lifecycle: dlopen, instantiate, setup, initialize, STEPS steps,
 *                    terminate, free (the library stays loaded until exit)
 *            twice   two lifecycles with one dlopen
 *            reload  one lifecycle, dlclose, dlopen again, a second lifecycle
 *            pair    FMU_DIR and FMU_DIR2 loaded and instantiated at once, stepped in turn
 *   FMU_DIR  an extracted FMU (modelDescription.xml, binaries/linux64/<id>.so, resources/)
 *
 * Every lifecycle instantiates with loggingOn = fmi2False (messages that reach the logger
 * anyway are printed on stderr), sets no parameter, steps with the DefaultExperiment step
 * (1e-4 s without one) and reads every Real output after each step. It prints on stdout one
 * line per lifecycle, "<id> lifecycle <k>: <steps> steps, checksum <sum of all outputs read>",
 * then "lifecycle_host: <MODE> done" as the last line (stdout is buffered when it is a pipe:
 * that line shows that the process flushed it at exit).
 *
 * Exit status: 0 on success, 1 on a usage/file error, 2 on an FMI error.
 *
 * Build: gcc -std=c99 -O2 -I fmus/shim -o lifecycle_host tests/c_host/lifecycle_host.c -ldl
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "host_logger.h"

#define MAX_OUT 1024

typedef struct {
    const char *dir;
    char id[256], guid[256], so[4096], uri[4200];
    double step;
    fmi2ValueReference out[MAX_OUT];
    size_t n_out;
    void *lib;
    fmi2InstantiateTYPE *instantiate;
    fmi2SetupExperimentTYPE *setup;
    fmi2EnterInitializationModeTYPE *enter_init;
    fmi2ExitInitializationModeTYPE *exit_init;
    fmi2DoStepTYPE *do_step;
    fmi2GetRealTYPE *get_real;
    fmi2TerminateTYPE *terminate;
    fmi2FreeInstanceTYPE *free_instance;
    fmi2Component c;
    double checksum;
    fmi2Real values[MAX_OUT];
} Fmu;


static const fmi2CallbackFunctions callbacks = {logger, calloc, free, NULL, NULL};

/* the value of attr="..." in [from, to) (to NULL: anywhere after from) */
static int attribute(const char *from, const char *to, const char *attr, char *out, size_t n) {
    char key[64];
    const char *p, *q;
    snprintf(key, sizeof key, " %s=\"", attr);
    p = strstr(from, key);
    if (p == NULL || (to != NULL && p >= to)) return 0;
    p += strlen(key);
    q = strchr(p, '"');
    if (q == NULL || (size_t)(q - p) >= n) return 0;
    memcpy(out, p, (size_t)(q - p));
    out[q - p] = '\0';
    return 1;
}

/* modelIdentifier, guid, DefaultExperiment stepSize, the Real outputs (a minimal reader for
 * the modelDescription.xml files axir writes) */
static int read_model_description(Fmu *f) {
    char path[4200], value[64], *xml;
    const char *p, *end, *cs;
    long size;
    FILE *fp;
    snprintf(path, sizeof path, "%s/modelDescription.xml", f->dir);
    fp = fopen(path, "rb");
    if (fp == NULL || fseek(fp, 0, SEEK_END) != 0 || (size = ftell(fp)) <= 0) {
        fprintf(stderr, "error: cannot read %s\n", path);
        if (fp) fclose(fp);
        return 0;
    }
    rewind(fp);
    xml = (char *)malloc((size_t)size + 1);
    if (xml == NULL || fread(xml, 1, (size_t)size, fp) != (size_t)size) {
        fclose(fp);
        free(xml);
        return 0;
    }
    fclose(fp);
    xml[size] = '\0';
    cs = strstr(xml, "<CoSimulation");
    if (!attribute(xml, NULL, "guid", f->guid, sizeof f->guid) || cs == NULL
        || !attribute(cs, NULL, "modelIdentifier", f->id, sizeof f->id)) {
        fprintf(stderr, "error: %s: no guid or CoSimulation modelIdentifier\n", path);
        free(xml);
        return 0;
    }
    p = strstr(xml, "<DefaultExperiment");
    f->step = p && attribute(p, strchr(p, '>'), "stepSize", value, sizeof value)
                  ? strtod(value, NULL) : 1e-4;
    for (p = strstr(xml, "<ScalarVariable"); p != NULL && f->n_out < MAX_OUT;
         p = strstr(end, "<ScalarVariable")) {
        end = strstr(p, "</ScalarVariable>");
        if (end == NULL) end = p + strlen(p);
        if (attribute(p, end, "causality", value, sizeof value) && strcmp(value, "output") == 0
            && strstr(p, "<Real") != NULL && strstr(p, "<Real") < end
            && attribute(p, end, "valueReference", value, sizeof value))
            f->out[f->n_out++] = (fmi2ValueReference)strtoul(value, NULL, 10);
    }
    free(xml);
    snprintf(f->so, sizeof f->so, "%s/binaries/linux64/%s.so", f->dir, f->id);
    snprintf(f->uri, sizeof f->uri, "file://%s/resources", f->dir);
    return 1;
}

static void *function(Fmu *f, const char *name) {
    void *p = dlsym(f->lib, name);
    if (p == NULL) fprintf(stderr, "error: %s not found in %s\n", name, f->so);
    return p;
}

static int load(Fmu *f) {
    f->lib = dlopen(f->so, RTLD_NOW | RTLD_LOCAL);
    if (f->lib == NULL) {
        fprintf(stderr, "error: dlopen(%s): %s\n", f->so, dlerror());
        return 0;
    }
    /* (function pointers from dlsym: POSIX guarantees the conversion) */
    *(void **)&f->instantiate = function(f, "fmi2Instantiate");
    *(void **)&f->setup = function(f, "fmi2SetupExperiment");
    *(void **)&f->enter_init = function(f, "fmi2EnterInitializationMode");
    *(void **)&f->exit_init = function(f, "fmi2ExitInitializationMode");
    *(void **)&f->do_step = function(f, "fmi2DoStep");
    *(void **)&f->get_real = function(f, "fmi2GetReal");
    *(void **)&f->terminate = function(f, "fmi2Terminate");
    *(void **)&f->free_instance = function(f, "fmi2FreeInstance");
    return f->instantiate && f->setup && f->enter_init && f->exit_init && f->do_step
           && f->get_real && f->terminate && f->free_instance;
}

#define CHECK(f, call, what)                                                             \
    do {                                                                                 \
        fmi2Status s_ = (call);                                                          \
        if (s_ > fmi2Warning) {                                                          \
            fprintf(stderr, "error: %s: %s returned status %d\n", (f)->id, what, (int)s_); \
            return 0;                                                                    \
        }                                                                                \
    } while (0)

static int start(Fmu *f, const char *instance) {
    f->checksum = 0.0;
    f->c = f->instantiate(instance, fmi2CoSimulation, f->guid, f->uri, &callbacks, fmi2False,
                          fmi2False);
    if (f->c == NULL) {
        fprintf(stderr, "error: %s: fmi2Instantiate failed\n", f->id);
        return 0;
    }
    CHECK(f, f->setup(f->c, fmi2False, 0.0, 0.0, fmi2False, 0.0), "fmi2SetupExperiment");
    CHECK(f, f->enter_init(f->c), "fmi2EnterInitializationMode");
    CHECK(f, f->exit_init(f->c), "fmi2ExitInitializationMode");
    return 1;
}

static int step(Fmu *f, int k) {
    size_t j;
    CHECK(f, f->do_step(f->c, k * f->step, f->step, fmi2True), "fmi2DoStep");
    CHECK(f, f->get_real(f->c, f->out, f->n_out, f->values), "fmi2GetReal");
    for (j = 0; j < f->n_out; j++) f->checksum += f->values[j];
    return 1;
}

static int stop(Fmu *f, int lifecycle, int steps) {
    CHECK(f, f->terminate(f->c), "fmi2Terminate");
    f->free_instance(f->c);
    f->c = NULL;
    printf("%s lifecycle %d: %d steps, checksum %.17g\n", f->id, lifecycle, steps, f->checksum);
    return 1;
}

static int lifecycle(Fmu *f, int k, int steps) {
    int i;
    if (!start(f, "lifecycle")) return 0;
    for (i = 0; i < steps; i++)
        if (!step(f, i)) return 0;
    return stop(f, k, steps);
}

int main(int argc, char **argv) {
    static Fmu a, b;
    const char *mode;
    int steps, i;
    if (argc < 4 || argc > 5) {
        fprintf(stderr, "usage: %s once|twice|reload|pair STEPS FMU_DIR [FMU_DIR2]\n", argv[0]);
        return 1;
    }
    mode = argv[1];
    steps = atoi(argv[2]);
    a.dir = argv[3];
    b.dir = argc == 5 ? argv[4] : NULL;
    if ((strcmp(mode, "pair") == 0) != (b.dir != NULL) || steps < 0) {
        fprintf(stderr, "error: mode pair takes two FMU folders, the others one\n");
        return 1;
    }
    if (!read_model_description(&a) || (b.dir && !read_model_description(&b))) return 1;
    if (!load(&a)) return 1;
    if (strcmp(mode, "once") == 0) {
        if (!lifecycle(&a, 1, steps)) return 2;
    } else if (strcmp(mode, "twice") == 0) {
        if (!lifecycle(&a, 1, steps) || !lifecycle(&a, 2, steps)) return 2;
    } else if (strcmp(mode, "reload") == 0) {
        if (!lifecycle(&a, 1, steps)) return 2;
        if (dlclose(a.lib) != 0) {
            fprintf(stderr, "error: dlclose: %s\n", dlerror());
            return 1;
        }
        if (!load(&a) || !lifecycle(&a, 2, steps)) return 2;
    } else if (strcmp(mode, "pair") == 0) {
        if (!load(&b) || !start(&a, "first") || !start(&b, "second")) return 2;
        for (i = 0; i < steps; i++)
            if (!step(&a, i) || !step(&b, i)) return 2;
        if (!stop(&a, 1, steps) || !stop(&b, 1, steps)) return 2;
    } else {
        fprintf(stderr, "error: unknown mode %s\n", mode);
        return 1;
    }
    printf("lifecycle_host: %s done\n", mode);
    return 0;
}
