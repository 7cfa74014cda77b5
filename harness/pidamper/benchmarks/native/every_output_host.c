/* A native host as system simulators are: it opens the FMU's library with RTLD_NOW | RTLD_LOCAL,
 * steps it and reads every output at every step, one fmi2GetReal / fmi2GetInteger call per
 * variable.  Prints the process CPU time per step [us].
 *
 *   every_output_host <unzipped FMU> <model identifier> <GUID> <steps> <h> [P|Q:<vr>:<value> ...]
 *                     <R|I>:<vr> ... [U:<vr>:<A>:<w>[:<t_end>]]
 *
 * P / Q: a Real / Integer parameter set to value before initialization (tokens first).
 * U: before each step the Real input vr is set to A sin(w t) at the step's start t, or 0 from t_end
 * on (none: no input set).
 */
#include <dlfcn.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "fmi2Functions.h"

static void logger(fmi2ComponentEnvironment e, fmi2String n, fmi2Status s, fmi2String c, fmi2String m, ...) {
    (void)e; (void)c;
    if (s < fmi2Error) return;
    va_list args;  /* the message is a printf format (FMI 2.0, 2.1.5) */
    va_start(args, m);
    fprintf(stderr, "[%s] status %d: ", n, (int)s);
    vfprintf(stderr, m, args);
    fputc('\n', stderr);
    va_end(args);
}

#define LOAD(name) name##TYPE *name = (name##TYPE *)dlsym(lib, #name); \
    if (!name) { fprintf(stderr, "missing %s\n", #name); return 2; }

int main(int argc, char **argv) {
    if (argc < 7) { fprintf(stderr, "usage: every_output_host dir id guid steps h R:vr ...\n"); return 2; }
    char path[4096], resources[4096];
    snprintf(path, sizeof path, "%s/binaries/linux64/%s.so", argv[1], argv[2]);
    snprintf(resources, sizeof resources, "file://%s/resources", argv[1]);
    void *lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!lib) { fprintf(stderr, "dlopen: %s\n", dlerror()); return 2; }
    LOAD(fmi2Instantiate) LOAD(fmi2SetupExperiment) LOAD(fmi2EnterInitializationMode)
    LOAD(fmi2ExitInitializationMode) LOAD(fmi2GetReal) LOAD(fmi2GetInteger) LOAD(fmi2SetReal) LOAD(fmi2DoStep)
    LOAD(fmi2Terminate) LOAD(fmi2FreeInstance)
    int steps = atoi(argv[4]), n = argc - 6, first = 6;
    double h = strtod(argv[5], NULL);
    const char *guid = argv[3];
    while (n > 0 && (argv[first][0] == 'P' || argv[first][0] == 'Q')) { first++; n--; }  /* parameters */
    argv += first - 6;  /* the outputs and the input from argv[6] on, as without parameters */
    char *types = malloc(n);
    fmi2ValueReference *vrs = malloc(n * sizeof *vrs);
    for (int k = 0; k < n; k++) { types[k] = argv[6 + k][0]; vrs[k] = (fmi2ValueReference)atoi(argv[6 + k] + 2); }
    int driven = n > 0 && types[n - 1] == 'U';  /* the last token: the input and its harmonic */
    fmi2ValueReference input = 0;
    double amplitude = 0.0, omega = 0.0, t_end = INFINITY;
    if (driven) {
        unsigned vr;
        int got = sscanf(argv[5 + n] + 2, "%u:%lf:%lf:%lf", &vr, &amplitude, &omega, &t_end);
        if (got != 3 && got != 4) {
            fprintf(stderr, "bad input token %s (U:<vr>:<A>:<w>[:<t_end>])\n", argv[5 + n]); return 2;
        }
        input = (fmi2ValueReference)vr;
        n -= 1;
    }
    fmi2CallbackFunctions callbacks = {logger, calloc, free, NULL, NULL};
    fmi2Component c = fmi2Instantiate("host", fmi2CoSimulation, guid, resources, &callbacks, fmi2False, fmi2False);
    if (!c) { fprintf(stderr, "fmi2Instantiate failed\n"); return 3; }
    for (char **p = argv + 6 - (first - 6); p < argv + 6; p++) {  /* the parameters */
        unsigned vr;
        double value;
        if (sscanf(*p + 2, "%u:%lf", &vr, &value) != 2) { fprintf(stderr, "bad parameter token %s\n", *p); return 2; }
        fmi2ValueReference ref = (fmi2ValueReference)vr;
        fmi2Integer whole = (fmi2Integer)value;
        fmi2SetRealTYPE *setReal = fmi2SetReal;
        fmi2SetIntegerTYPE *setInteger = (fmi2SetIntegerTYPE *)dlsym(lib, "fmi2SetInteger");
        if (((*p)[0] == 'P' ? setReal(c, &ref, 1, &value) : setInteger(c, &ref, 1, &whole)) != fmi2OK) {
            fprintf(stderr, "set %s failed\n", *p); return 3;
        }
    }
    if (fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0) || fmi2EnterInitializationMode(c) ||
        fmi2ExitInitializationMode(c)) return 4;
    double r, sum = 0.0;
    fmi2Integer i;
    clock_t t0 = clock();
    for (int s = 0; s < steps; s++) {
        double a = s * h < t_end ? amplitude * sin(omega * (s * h)) : 0.0;
        if (driven && fmi2SetReal(c, &input, 1, &a) != fmi2OK) { fprintf(stderr, "set input failed\n"); return 5; }
        if (fmi2DoStep(c, s * h, h, fmi2True) != fmi2OK) { fprintf(stderr, "doStep failed\n"); return 5; }
        for (int k = 0; k < n; k++) {
            fmi2Status st = types[k] == 'R' ? fmi2GetReal(c, &vrs[k], 1, &r) : fmi2GetInteger(c, &vrs[k], 1, &i);
            if (st != fmi2OK) { fprintf(stderr, "get %c:%u failed\n", types[k], vrs[k]); return 6; }
            sum += types[k] == 'R' ? r : i;
        }
    }
    double cpu = (double)(clock() - t0) / CLOCKS_PER_SEC;
    fmi2Terminate(c);
    fmi2FreeInstance(c);
    printf("%.6f %.17g\n", cpu / steps * 1e6, sum);
    return 0;
}
