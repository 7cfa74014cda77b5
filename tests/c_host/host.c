/* A minimal FMI 2.0 co-simulation host in C: loads the FMU's shared library, instantiates
 * it, steps it across impacts, reads outputs and frees it.
 *
 *   host <unzipped FMU dir> <GUID> <vr theta_dot_0> <theta_dot_0> <vr theta> <vr impacts> <steps> <step size>
 *
 * Prints "theta impacts" after the last step, and on stderr the libpython the process ended up
 * with.  The host knows nothing of Python: it opens the FMU's library with RTLD_NOW | RTLD_LOCAL,
 * as native system simulators do; the FMU finds a Python runtime by itself. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <link.h>
#include <string.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include "fmi2Functions.h"

static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                   fmi2String message, ...) {
    va_list args;
    (void)env;
    fprintf(stderr, "[%s] status %d %s: ", name, (int)status, category ? category : "");
    va_start(args, message);
    vfprintf(stderr, message, args);
    va_end(args);
    fputc('\n', stderr);
}

static int report_libpython(struct dl_phdr_info *info, size_t size, void *data) {
    (void)size; (void)data;
    const char *base = info->dlpi_name ? strrchr(info->dlpi_name, '/') : NULL;
    if (base && strncmp(base + 1, "libpython3", 10) == 0) fprintf(stderr, "libpython: %s\n", info->dlpi_name);
    return 0;
}

#define LOAD(name) name##TYPE *name = (name##TYPE *)dlsym(lib, #name); \
    if (!name) { fprintf(stderr, "missing %s\n", #name); return 2; }

int main(int argc, char **argv) {
    if (argc != 9) {
        fprintf(stderr, "usage: host dir guid vr_thetadot0 thetadot0 vr_theta vr_impacts steps h\n");
        return 2;
    }
    const char *dir = argv[1];
    char path[4096], resources[4096];
    snprintf(path, sizeof path, "%s/binaries/linux64/PendulumImpactDamper.so", dir);
    snprintf(resources, sizeof resources, "file://%s/resources", dir);
    void *lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!lib) { fprintf(stderr, "dlopen: %s\n", dlerror()); return 2; }
    LOAD(fmi2Instantiate) LOAD(fmi2SetupExperiment) LOAD(fmi2EnterInitializationMode)
    LOAD(fmi2ExitInitializationMode) LOAD(fmi2SetReal) LOAD(fmi2GetReal) LOAD(fmi2GetInteger)
    LOAD(fmi2DoStep) LOAD(fmi2Terminate) LOAD(fmi2FreeInstance)

    fmi2CallbackFunctions callbacks = {logger, calloc, free, NULL, NULL};
    fmi2Component c = fmi2Instantiate("c-host", fmi2CoSimulation, argv[2], resources, &callbacks, fmi2False,
                                      fmi2False);
    if (!c) { fprintf(stderr, "fmi2Instantiate failed\n"); return 3; }
    fmi2ValueReference vr_v0 = (fmi2ValueReference)atoi(argv[3]);
    fmi2Real v0 = strtod(argv[4], NULL);
    fmi2ValueReference vr_out[1] = {(fmi2ValueReference)atoi(argv[5])};
    fmi2ValueReference vr_imp[1] = {(fmi2ValueReference)atoi(argv[6])};
    int steps = atoi(argv[7]);
    double h = strtod(argv[8], NULL);
    if (fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0) > fmi2Warning) return 4;
    if (fmi2EnterInitializationMode(c) > fmi2Warning) return 4;
    if (fmi2SetReal(c, &vr_v0, 1, &v0) > fmi2Warning) return 4;
    if (fmi2ExitInitializationMode(c) > fmi2Warning) return 4;
    double t = 0.0;
    for (int k = 0; k < steps; k++) {
        if (fmi2DoStep(c, t, h, fmi2True) != fmi2OK) { fprintf(stderr, "doStep failed at %g\n", t); return 5; }
        t += h;
    }
    fmi2Real theta;
    fmi2Integer impacts;
    if (fmi2GetReal(c, vr_out, 1, &theta) > fmi2Warning || fmi2GetInteger(c, vr_imp, 1, &impacts) > fmi2Warning)
        return 6;
    printf("%.17g %d\n", theta, impacts);
    dl_iterate_phdr(report_libpython, NULL);
    fmi2Terminate(c);
    fmi2FreeInstance(c);
    dlclose(lib);
    return 0;
}
