/* A C host that restores a serialized FMU state into a variable it never initialised, as FMI 2.0
 * allows (fmi2DeSerializeFMUstate's FMUstate is an output: the host passes the address of a
 * variable that may hold anything, here 0xdeadbeef).
 *
 *   state_host <unzipped FMU dir> <GUID> <vr theta_dot_0> <theta_dot_0> <vr theta> <steps> <step size>
 *
 * Runs `steps` steps, saves and serializes the state, runs `steps` more and reads theta; then
 * de-serializes the bytes into the garbage variable, sets that state, runs the same `steps` again
 * and reads theta.  Prints "<status of fmi2DeSerializeFMUstate> <theta first> <theta again>". */
#include <dlfcn.h>
#include <stdarg.h>
#include <stdint.h>
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

#define LOAD(name) name##TYPE *name = (name##TYPE *)dlsym(lib, #name); \
    if (!name) { fprintf(stderr, "missing %s\n", #name); return 2; }
#define CHECK(call) if ((call) > fmi2Warning) { fprintf(stderr, "%s failed\n", #call); return 4; }

int main(int argc, char **argv) {
    if (argc != 8) {
        fprintf(stderr, "usage: state_host dir guid vr_thetadot0 thetadot0 vr_theta steps h\n");
        return 2;
    }
    char path[4096], resources[4096];
    snprintf(path, sizeof path, "%s/binaries/linux64/PendulumImpactDamper.so", argv[1]);
    snprintf(resources, sizeof resources, "file://%s/resources", argv[1]);
    void *lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!lib) { fprintf(stderr, "dlopen: %s\n", dlerror()); return 2; }
    LOAD(fmi2Instantiate) LOAD(fmi2SetupExperiment) LOAD(fmi2EnterInitializationMode)
    LOAD(fmi2ExitInitializationMode) LOAD(fmi2SetReal) LOAD(fmi2GetReal) LOAD(fmi2DoStep) LOAD(fmi2Terminate)
    LOAD(fmi2FreeInstance) LOAD(fmi2GetFMUstate) LOAD(fmi2SetFMUstate) LOAD(fmi2FreeFMUstate)
    LOAD(fmi2SerializedFMUstateSize) LOAD(fmi2SerializeFMUstate) LOAD(fmi2DeSerializeFMUstate)

    fmi2CallbackFunctions callbacks = {logger, calloc, free, NULL, NULL};
    fmi2Component c = fmi2Instantiate("state-host", fmi2CoSimulation, argv[2], resources, &callbacks, fmi2False,
                                      fmi2True);
    if (!c) { fprintf(stderr, "fmi2Instantiate failed\n"); return 3; }
    fmi2ValueReference vr_v0 = (fmi2ValueReference)atoi(argv[3]), vr_theta = (fmi2ValueReference)atoi(argv[5]);
    fmi2Real v0 = strtod(argv[4], NULL), first, again;
    int steps = atoi(argv[6]);
    double h = strtod(argv[7], NULL), t = 0.0;
    CHECK(fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0))
    CHECK(fmi2EnterInitializationMode(c))
    CHECK(fmi2SetReal(c, &vr_v0, 1, &v0))
    CHECK(fmi2ExitInitializationMode(c))
    for (int k = 0; k < steps; k++, t += h) CHECK(fmi2DoStep(c, t, h, fmi2False))
    double t_saved = t;
    fmi2FMUstate saved = NULL;
    size_t size = 0;
    CHECK(fmi2GetFMUstate(c, &saved))
    CHECK(fmi2SerializedFMUstateSize(c, saved, &size))
    fmi2Byte *bytes = malloc(size);
    if (!bytes) return 4;
    CHECK(fmi2SerializeFMUstate(c, saved, bytes, size))
    for (int k = 0; k < steps; k++, t += h) CHECK(fmi2DoStep(c, t, h, fmi2False))
    CHECK(fmi2GetReal(c, &vr_theta, 1, &first))

    fmi2FMUstate restored = (fmi2FMUstate)(uintptr_t)0xdeadbeef; /* never initialised by this host */
    fmi2Status status = fmi2DeSerializeFMUstate(c, bytes, size, &restored);
    if (status > fmi2Warning) { printf("%d\n", (int)status); return 5; }
    CHECK(fmi2SetFMUstate(c, restored))
    t = t_saved;
    for (int k = 0; k < steps; k++, t += h) CHECK(fmi2DoStep(c, t, h, fmi2False))
    CHECK(fmi2GetReal(c, &vr_theta, 1, &again))
    printf("%d %.17g %.17g\n", (int)status, first, again);
    CHECK(fmi2FreeFMUstate(c, &restored))
    CHECK(fmi2FreeFMUstate(c, &saved))
    free(bytes);
    fmi2Terminate(c);
    fmi2FreeInstance(c);
    dlclose(lib);
    return 0;
}
