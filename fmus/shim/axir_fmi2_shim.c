/*
 * axir FMI 2.0 co-simulation shim around pythonfmu's generic binary.
 *
 * Why: pythonfmu 0.7.0's binary can only return fmi2OK, fmi2Discard (do_step returned False)
 * or fmi2Fatal (a Python exception); a slave cannot answer fmi2Error. The axir adapter
 * (fmus/_base.py) reports every error as a log message with status fmi2Error instead.
 *
 * What: this library is the FMU's binaries/linux64/<modelIdentifier>.so. It loads pythonfmu's
 * original binary, shipped next to it as <modelIdentifier>_pythonfmu.so (found with dladdr on
 * a symbol of this library, loaded with dlopen RTLD_NOW | RTLD_LOCAL on first fmi2Instantiate),
 * and forwards every FMI 2.0 co-simulation function to it. At fmi2Instantiate it hands the
 * inner binary its own logger: that logger notes that a message with status fmi2Error or
 * fmi2Fatal was logged during the current call, then forwards the message unchanged to the
 * host's logger (as the format argument, as pythonfmu does; the adapter escapes '%'). When
 * such a message was logged during a call whose inner status is fmi2OK, fmi2Warning or
 * fmi2Discard, the call returns fmi2Error instead. Fatal and Pending pass through.
 *
 * Logging filter: pythonfmu drops every message while logging is off, which would hide the
 * errors from this shim. The inner instance therefore always runs with logging on (all
 * categories) and the shim applies the host's fmi2Instantiate loggingOn and
 * fmi2SetDebugLogging(loggingOn, categories) itself, with pythonfmu's rule: forward when
 * logging is on and (no categories were given or the message's category is one of them).
 *
 * Functions the inner binary does not export answer fmi2Error with a log message. See
 * docs/fmu_build.md ("fmi2Error from the C shim").
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"

#define INNER_SUFFIX "_pythonfmu.so"

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
} InnerApi;

static InnerApi api;
static void *inner_handle;
static int inner_ok;              /* 1 once the inner binary is loaded with its core functions */
static char inner_error[1200];    /* why it could not be loaded */
static pthread_once_t inner_once = PTHREAD_ONCE_INIT;
static const char shim_anchor = 0; /* a symbol of this library for dladdr (never interposed) */

/* POSIX dlsym returns an object pointer; copy it into the function pointer (ISO C has no
 * conversion between the two). */
static void inner_sym(void *function_pointer, const char *name) {
    void *p = dlsym(inner_handle, name);
    memcpy(function_pointer, &p, sizeof p);
}

static void load_inner(void) {
    Dl_info info;
    char path[1024];
    const char *err;
    size_t n;
    if (!dladdr(&shim_anchor, &info) || info.dli_fname == NULL) {
        snprintf(inner_error, sizeof inner_error, "axir shim: dladdr cannot locate the shim");
        return;
    }
    n = strlen(info.dli_fname);
    if (n < 3 || strcmp(info.dli_fname + n - 3, ".so") != 0
        || n - 3 + sizeof INNER_SUFFIX > sizeof path) {
        snprintf(inner_error, sizeof inner_error,
                 "axir shim: unexpected shim file name %.900s", info.dli_fname);
        return;
    }
    memcpy(path, info.dli_fname, n - 3);
    memcpy(path + n - 3, INNER_SUFFIX, sizeof INNER_SUFFIX);
    inner_handle = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (inner_handle == NULL) {
        err = dlerror();
        snprintf(inner_error, sizeof inner_error, "axir shim: cannot load %.500s: %.500s", path,
                 err ? err : "unknown error");
        return;
    }
#define LOAD(f) inner_sym(&api.f, "fmi2" #f)
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
    if (api.Instantiate == NULL || api.FreeInstance == NULL || api.SetDebugLogging == NULL) {
        snprintf(inner_error, sizeof inner_error,
                 "axir shim: %.900s lacks fmi2Instantiate/fmi2FreeInstance/fmi2SetDebugLogging",
                 path);
        return;
    }
    inner_ok = 1;
}

/* ------------------------------------------------------------------ the shim's instance */
typedef struct {
    fmi2Component inner;             /* pythonfmu's component */
    fmi2CallbackFunctions host;      /* copy of the host's callbacks */
    fmi2CallbackFunctions wrapped;   /* handed to pythonfmu (it keeps the pointer) */
    char *instance_name;
    int error_logged;                /* an Error/Fatal message was logged during this call */
    fmi2Boolean logging_on;          /* the host's logging settings */
    size_t n_categories;
    char **categories;
} Shim;

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
    if (s == NULL) return;
    if (status == fmi2Error || status == fmi2Fatal) s->error_logged = 1;
    if (s->host.logger != NULL && host_wants(s, category))
        /* pythonfmu passes the formatted message as the format: so do we */
        s->host.logger(s->host.componentEnvironment, instance_name, status, category, message);
}

static void shim_step_finished(fmi2ComponentEnvironment env, fmi2Status status) {
    Shim *s = (Shim *)env;
    if (s != NULL && s->host.stepFinished != NULL)
        s->host.stepFinished(s->host.componentEnvironment, status);
}

static fmi2Status finish(Shim *s, fmi2Status status) {
    if (s->error_logged && (status == fmi2OK || status == fmi2Warning || status == fmi2Discard))
        return fmi2Error;
    return status;
}

/* Log the shim's own message like pythonfmu does: already formatted, passed as the format
 * with '%' doubled (so that hosts which format and hosts which do not both show it). */
static void log_text(const fmi2CallbackFunctions *host, fmi2String instance_name,
                     fmi2Status status, fmi2String category, const char *text) {
    char buf[2 * sizeof inner_error + 1];
    size_t i = 0;
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
        s_->error_logged = 0;                                \
        return finish(s_, api.f(s_->inner, __VA_ARGS__));    \
    } while (0)

#define FORWARD0(f, c)                                       \
    do {                                                     \
        Shim *s_ = (Shim *)(c);                              \
        if (s_ == NULL || s_->inner == NULL) return fmi2Error; \
        if (api.f == NULL) return unsupported(s_, "fmi2" #f); \
        s_->error_logged = 0;                                \
        return finish(s_, api.f(s_->inner));                 \
    } while (0)

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
            s->categories[i] = strdup(categories[i] ? categories[i] : "");
            if (s->categories[i] == NULL) {
                s->n_categories = i;
                free_categories(s);
                return fmi2Error;
            }
        }
        s->n_categories = nCategories;
    }
    /* the inner instance keeps logging everything: the shim filters (see top) */
    s->error_logged = 0;
    return finish(s, api.SetDebugLogging(s->inner, fmi2True, 0, NULL));
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation,
                              const fmi2CallbackFunctions *functions, fmi2Boolean visible,
                              fmi2Boolean loggingOn) {
    Shim *s;
    pthread_once(&inner_once, load_inner);
    if (!inner_ok) {
        if (functions != NULL && functions->logger != NULL)
            log_text(functions, instanceName, fmi2Fatal, "logStatusFatal", inner_error);
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
    s->instance_name = strdup(instanceName ? instanceName : "");
    if (s->instance_name == NULL) {
        free(s);
        return NULL;
    }
    s->inner = api.Instantiate(instanceName, fmuType, fmuGUID, fmuResourceLocation, &s->wrapped,
                               visible, fmi2True);
    if (s->inner == NULL) {
        free(s->instance_name);
        free(s);
        return NULL;
    }
    return s;
}

void fmi2FreeInstance(fmi2Component c) {
    Shim *s = (Shim *)c;
    if (s == NULL) return;
    if (s->inner != NULL) api.FreeInstance(s->inner);
    free_categories(s);
    free(s->instance_name);
    free(s);
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

fmi2Status fmi2Reset(fmi2Component c) { FORWARD0(Reset, c); }

/* ------------------------------------------------------------------ get / set values */
fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                       fmi2Real value[]) {
    FORWARD(GetReal, c, vr, nvr, value);
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          fmi2Integer value[]) {
    FORWARD(GetInteger, c, vr, nvr, value);
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          fmi2Boolean value[]) {
    FORWARD(GetBoolean, c, vr, nvr, value);
}

fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                         fmi2String value[]) {
    FORWARD(GetString, c, vr, nvr, value);
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                       const fmi2Real value[]) {
    FORWARD(SetReal, c, vr, nvr, value);
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          const fmi2Integer value[]) {
    FORWARD(SetInteger, c, vr, nvr, value);
}

fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          const fmi2Boolean value[]) {
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
    FORWARD(DoStep, c, currentCommunicationPoint, communicationStepSize,
            noSetFMUStatePriorToCurrentPoint);
}

fmi2Status fmi2CancelStep(fmi2Component c) { FORWARD0(CancelStep, c); }

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value) {
    FORWARD(GetStatus, c, s, value);
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value) {
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
