/*
 * fmu_host.c -- a minimal FMI 2.0 co-simulation host in C (no Python, no FMI library).
 *
 * Loads an extracted FMU's shared library with dlopen, resolves the FMI 2.0 C API with dlsym,
 * instantiates one slave, sets parameters, initializes, then for every row of an input CSV
 * sets the inputs, calls fmi2DoStep and writes the chosen outputs to an output CSV.
 * It is the "non-Python host" of issue 5: see tests/test_c_host.py and docs/other_tools.md.
 *
 * Usage:
 *   fmu_host FMU_DIR MODEL_IDENTIFIER GUID PARAMS INPUTS_CSV OUTPUTS STOP_TIME OUT_CSV
 *
 *   FMU_DIR      the extracted FMU (modelDescription.xml, binaries/linux64/, resources/)
 *   PARAMS       text file, one parameter per line: "<R|I|B|S> <valueReference> <value>"
 *                (lines starting with '#' are comments)
 *   INPUTS_CSV   header "time,<T><vr>,..." with T in R/I/B (e.g. "time,R22,I217,B230"),
 *                then one row per step: row i holds the communication point t_i and the input
 *                values applied during the step from t_i to t_{i+1} (t_{i+1} is the next
 *                row's time, STOP_TIME for the last row)
 *   OUTPUTS      text file, one output per line: "<R|I|B> <valueReference> <name>"
 *   OUT_CSV      written: quoted header "time","<name>",... (names may hold commas:
 *                sum[1,2]), one row per step (time = t_{i+1}), Reals with %.17g (exact)
 *
 * Exit status: 0 on success, 1 on a usage/file error, 2 on an FMI error (the FMU's log
 * messages are printed on stderr).
 *
 * The axir FMUs find their Python themselves (the one they were built with, or
 * AXIR_FMU_PYTHON=/path/to/python3; docs/other_tools.md): no environment is needed.
 *
 * Build: gcc -std=c99 -O2 -I fmus/shim -o fmu_host tests/c_host/fmu_host.c -ldl
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "host_logger.h"

#define MAX_VARS 4096
#define MAX_LINE 1048576

typedef struct {
    char kind; /* 'R', 'I', 'B', 'S' */
    fmi2ValueReference vr;
    char name[256];
} Var;


static void *load(void *lib, const char *name) {
    void *f = dlsym(lib, name);
    if (!f) {
        fprintf(stderr, "error: %s not found in the FMU library: %s\n", name, dlerror());
        exit(1);
    }
    return f;
}

#define CHECK(call, what)                                                      \
    do {                                                                       \
        fmi2Status s_ = (call);                                                \
        if (s_ > fmi2Warning) {                                                \
            fprintf(stderr, "error: %s returned status %d\n", what, (int)s_); \
            return 2;                                                    \
        }                                                                      \
    } while (0)

/* "R22" -> kind 'R', vr 22 */
static int parse_ref(const char *tok, Var *v) {
    char *end;
    if (!tok[0] || !strchr("RIB", tok[0])) return 0;
    v->kind = tok[0];
    v->vr = (fmi2ValueReference)strtoul(tok + 1, &end, 10);
    return end != tok + 1 && (*end == '\0' || *end == '\n' || *end == '\r');
}

int main(int argc, char **argv) {
    if (argc != 9) {
        fprintf(stderr, "usage: %s FMU_DIR MODEL_IDENTIFIER GUID PARAMS INPUTS_CSV OUTPUTS "
                        "STOP_TIME OUT_CSV\n", argv[0]);
        return 1;
    }
    const char *fmu_dir = argv[1], *model = argv[2], *guid = argv[3];
    double stop = strtod(argv[7], NULL);
    static char line[MAX_LINE], next_line[MAX_LINE], path[4096], uri[4200];

    /* --- the library and the FMI functions -------------------------------------------- */
    snprintf(path, sizeof path, "%s/binaries/linux64/%s.so", fmu_dir, model);
    void *lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        fprintf(stderr, "error: dlopen(%s): %s\n", path, dlerror());
        return 1;
    }
    fmi2InstantiateTYPE *instantiate = load(lib, "fmi2Instantiate");
    fmi2SetupExperimentTYPE *setup = load(lib, "fmi2SetupExperiment");
    fmi2EnterInitializationModeTYPE *enter_init = load(lib, "fmi2EnterInitializationMode");
    fmi2ExitInitializationModeTYPE *exit_init = load(lib, "fmi2ExitInitializationMode");
    fmi2SetRealTYPE *set_real = load(lib, "fmi2SetReal");
    fmi2SetIntegerTYPE *set_int = load(lib, "fmi2SetInteger");
    fmi2SetBooleanTYPE *set_bool = load(lib, "fmi2SetBoolean");
    fmi2SetStringTYPE *set_string = load(lib, "fmi2SetString");
    fmi2GetRealTYPE *get_real = load(lib, "fmi2GetReal");
    fmi2GetIntegerTYPE *get_int = load(lib, "fmi2GetInteger");
    fmi2GetBooleanTYPE *get_bool = load(lib, "fmi2GetBoolean");
    fmi2DoStepTYPE *do_step = load(lib, "fmi2DoStep");
    fmi2TerminateTYPE *terminate = load(lib, "fmi2Terminate");
    fmi2FreeInstanceTYPE *free_instance = load(lib, "fmi2FreeInstance");

    /* --- instantiate -------------------------------------------------------------------- */
    fmi2CallbackFunctions callbacks = {logger, calloc, free, NULL, NULL};
    snprintf(uri, sizeof uri, "file://%s/resources", fmu_dir);
    fmi2Component c = instantiate("instance", fmi2CoSimulation, guid, uri, &callbacks,
                                  fmi2False, fmi2True);
    if (!c) {
        fprintf(stderr, "error: fmi2Instantiate failed\n");
        return 2;
    }

    /* --- parameters, initialization ----------------------------------------------------- */
    FILE *pf = fopen(argv[4], "r");
    if (!pf) {
        fprintf(stderr, "error: cannot open %s\n", argv[4]);
        return 1;
    }
    CHECK(setup(c, fmi2False, 0.0, 0.0, fmi2True, stop), "fmi2SetupExperiment");
    while (fgets(line, sizeof line, pf)) {
        char kind, value[1024];
        unsigned vr;
        if (line[0] == '#' || line[0] == '\n') continue;
        if (sscanf(line, " %c %u %1023[^\n]", &kind, &vr, value) != 3) {
            fprintf(stderr, "error: %s: bad line: %s", argv[4], line);
            return 1;
        }
        fmi2ValueReference r = vr;
        if (kind == 'R') {
            fmi2Real x = strtod(value, NULL);
            CHECK(set_real(c, &r, 1, &x), "fmi2SetReal (parameter)");
        } else if (kind == 'I') {
            fmi2Integer x = (fmi2Integer)strtol(value, NULL, 10);
            CHECK(set_int(c, &r, 1, &x), "fmi2SetInteger (parameter)");
        } else if (kind == 'B') {
            fmi2Boolean x = strtol(value, NULL, 10) != 0;
            CHECK(set_bool(c, &r, 1, &x), "fmi2SetBoolean (parameter)");
        } else if (kind == 'S') {
            fmi2String x = value;
            CHECK(set_string(c, &r, 1, &x), "fmi2SetString (parameter)");
        } else {
            fprintf(stderr, "error: %s: unknown type %c\n", argv[4], kind);
            return 1;
        }
    }
    fclose(pf);
    CHECK(enter_init(c), "fmi2EnterInitializationMode");
    CHECK(exit_init(c), "fmi2ExitInitializationMode");

    /* --- outputs ------------------------------------------------------------------------ */
    static Var outs[MAX_VARS], ins[MAX_VARS];
    static fmi2ValueReference vr_r[MAX_VARS], vr_i[MAX_VARS], vr_b[MAX_VARS];
    static fmi2Real val_r[MAX_VARS];
    static fmi2Integer val_i[MAX_VARS];
    static fmi2Boolean val_b[MAX_VARS];
    int n_out = 0, n_in = 0;
    FILE *of = fopen(argv[6], "r");
    if (!of) {
        fprintf(stderr, "error: cannot open %s\n", argv[6]);
        return 1;
    }
    while (n_out < MAX_VARS && fgets(line, sizeof line, of)) {
        unsigned vr;
        Var *v = &outs[n_out];
        if (line[0] == '#' || line[0] == '\n') continue;
        if (sscanf(line, " %c %u %255s", &v->kind, &vr, v->name) != 3 || !strchr("RIB", v->kind)) {
            fprintf(stderr, "error: %s: bad line: %s", argv[6], line);
            return 1;
        }
        v->vr = vr;
        n_out++;
    }
    fclose(of);

    /* --- inputs: header ----------------------------------------------------------------- */
    FILE *in = fopen(argv[5], "r");
    if (!in || !fgets(line, sizeof line, in)) {
        fprintf(stderr, "error: cannot read %s\n", argv[5]);
        return 1;
    }
    char *save = NULL, *tok = strtok_r(line, ",\r\n", &save);
    if (!tok || strcmp(tok, "time") != 0) {
        fprintf(stderr, "error: %s: the first column must be 'time'\n", argv[5]);
        return 1;
    }
    while ((tok = strtok_r(NULL, ",\r\n", &save)) && n_in < MAX_VARS) {
        if (!parse_ref(tok, &ins[n_in])) {
            fprintf(stderr, "error: %s: bad column %s (want R<vr>, I<vr> or B<vr>)\n", argv[5],
                    tok);
            return 1;
        }
        n_in++;
    }

    FILE *out = fopen(argv[8], "w");
    if (!out) {
        fprintf(stderr, "error: cannot write %s\n", argv[8]);
        return 1;
    }
    fprintf(out, "\"time\"");
    for (int j = 0; j < n_out; j++) fprintf(out, ",\"%s\"", outs[j].name);
    fputc('\n', out);

    /* --- the steps ---------------------------------------------------------------------- */
    int have = fgets(line, sizeof line, in) != NULL, steps = 0;
    while (have) {
        int more = fgets(next_line, sizeof next_line, in) != NULL;
        char *p = line, *end;
        double t = strtod(p, &end), t_next = more ? strtod(next_line, NULL) : stop;
        size_t nr = 0, ni = 0, nb = 0;
        for (int j = 0; j < n_in; j++) {
            if (*end != ',') {
                fprintf(stderr, "error: %s: row %d has too few values\n", argv[5], steps + 1);
                return 1;
            }
            p = end + 1;
            double x = strtod(p, &end);
            if (ins[j].kind == 'R') {
                vr_r[nr] = ins[j].vr;
                val_r[nr++] = x;
            } else if (ins[j].kind == 'I') {
                vr_i[ni] = ins[j].vr;
                val_i[ni++] = (fmi2Integer)x;
            } else {
                vr_b[nb] = ins[j].vr;
                val_b[nb++] = x != 0.0;
            }
        }
        /* one call per type, as an FMI master would */
        if (nr) CHECK(set_real(c, vr_r, nr, val_r), "fmi2SetReal");
        if (ni) CHECK(set_int(c, vr_i, ni, val_i), "fmi2SetInteger");
        if (nb) CHECK(set_bool(c, vr_b, nb, val_b), "fmi2SetBoolean");
        CHECK(do_step(c, t, t_next - t, fmi2True), "fmi2DoStep");
        fprintf(out, "%.17g", t_next);
        for (int j = 0; j < n_out; j++) {
            fmi2ValueReference r = outs[j].vr;
            if (outs[j].kind == 'R') {
                fmi2Real x;
                CHECK(get_real(c, &r, 1, &x), "fmi2GetReal");
                fprintf(out, ",%.17g", x);
            } else if (outs[j].kind == 'I') {
                fmi2Integer x;
                CHECK(get_int(c, &r, 1, &x), "fmi2GetInteger");
                fprintf(out, ",%d", x);
            } else {
                fmi2Boolean x;
                CHECK(get_bool(c, &r, 1, &x), "fmi2GetBoolean");
                fprintf(out, ",%d", x ? 1 : 0);
            }
        }
        fputc('\n', out);
        steps++;
        if (more) memcpy(line, next_line, strlen(next_line) + 1);
        have = more;
    }
    fclose(in);
    fclose(out);
    CHECK(terminate(c), "fmi2Terminate");
    free_instance(c);
    fprintf(stderr, "fmu_host: %d steps\n", steps);
    /* A plain return: the exit handlers run (the FMU's shim never finalizes Python, so they
       have nothing of pythonfmu's to do; docs/other_tools.md section 1.4). */
    return 0;
}
