/* The FMI 2.0 logger of the C test hosts (fmu_host.c, lifecycle_host.c): every message to
 * stderr as "[instance][status N][category] message" (the message is a printf format, as the
 * FMI 2.0 standard says). Include after <stdarg.h>, <stdio.h> and "fmi2Functions.h". */
#ifndef AXIR_HOST_LOGGER_H
#define AXIR_HOST_LOGGER_H

static void logger(fmi2ComponentEnvironment env, fmi2String instance, fmi2Status status,
                   fmi2String category, fmi2String message, ...) {
    va_list args;
    (void)env;
    fprintf(stderr, "[%s][status %d][%s] ", instance ? instance : "?", (int)status,
            category ? category : "");
    va_start(args, message);
    vfprintf(stderr, message, args);
    va_end(args);
    fputc('\n', stderr);
}

#endif
