/* The compiled floor: the smallest FMI 2.0 co-simulation FMU in C with the trivial pythonfmu
 * FMU's variables (Real input u = vr 0; Real outputs y1, y2 = vr 1, 2: copies of u; Integer
 * output n = vr 3: steps taken).  Built by pidamper.benchmarks.floor from fmpy's FMI headers. */
#include <stdlib.h>
#include <string.h>
#include "fmi2Functions.h"

typedef struct { double u, y1, y2; int n; } Model;

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }
fmi2Component fmi2Instantiate(fmi2String n, fmi2Type t, fmi2String g, fmi2String r, const fmi2CallbackFunctions *f,
                              fmi2Boolean v, fmi2Boolean l) {
    (void)n; (void)t; (void)g; (void)r; (void)f; (void)v; (void)l;
    return calloc(1, sizeof(Model));
}
void fmi2FreeInstance(fmi2Component c) { free(c); }
fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean l, size_t n, const fmi2String s[]) {
    (void)c; (void)l; (void)n; (void)s; return fmi2OK;
}
fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean a, fmi2Real b, fmi2Real d, fmi2Boolean e, fmi2Real f) {
    (void)c; (void)a; (void)b; (void)d; (void)e; (void)f; return fmi2OK;
}
fmi2Status fmi2EnterInitializationMode(fmi2Component c) { (void)c; return fmi2OK; }
fmi2Status fmi2ExitInitializationMode(fmi2Component c) { (void)c; return fmi2OK; }
fmi2Status fmi2Terminate(fmi2Component c) { (void)c; return fmi2OK; }
fmi2Status fmi2Reset(fmi2Component c) { memset(c, 0, sizeof(Model)); return fmi2OK; }
fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[]) {
    Model *m = c;
    for (size_t k = 0; k < nvr; k++) {
        if (vr[k] > 2) return fmi2Error;
        value[k] = vr[k] == 0 ? m->u : vr[k] == 1 ? m->y1 : m->y2;
    }
    return fmi2OK;
}
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[]) {
    for (size_t k = 0; k < nvr; k++) {
        if (vr[k] != 3) return fmi2Error;
        value[k] = ((Model *)c)->n;
    }
    return fmi2OK;
}
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[]) {
    for (size_t k = 0; k < nvr; k++) {
        if (vr[k] != 0) return fmi2Error;
        ((Model *)c)->u = value[k];
    }
    return fmi2OK;
}
#define REFUSED(name, ...) fmi2Status name(__VA_ARGS__) { return fmi2Error; }
REFUSED(fmi2GetBoolean, fmi2Component c, const fmi2ValueReference v[], size_t n, fmi2Boolean x[])
REFUSED(fmi2GetString, fmi2Component c, const fmi2ValueReference v[], size_t n, fmi2String x[])
REFUSED(fmi2SetInteger, fmi2Component c, const fmi2ValueReference v[], size_t n, const fmi2Integer x[])
REFUSED(fmi2SetBoolean, fmi2Component c, const fmi2ValueReference v[], size_t n, const fmi2Boolean x[])
REFUSED(fmi2SetString, fmi2Component c, const fmi2ValueReference v[], size_t n, const fmi2String x[])
REFUSED(fmi2GetFMUstate, fmi2Component c, fmi2FMUstate *s)
REFUSED(fmi2SetFMUstate, fmi2Component c, fmi2FMUstate s)
REFUSED(fmi2FreeFMUstate, fmi2Component c, fmi2FMUstate *s)
REFUSED(fmi2SerializedFMUstateSize, fmi2Component c, fmi2FMUstate s, size_t *n)
REFUSED(fmi2SerializeFMUstate, fmi2Component c, fmi2FMUstate s, fmi2Byte b[], size_t n)
REFUSED(fmi2DeSerializeFMUstate, fmi2Component c, const fmi2Byte b[], size_t n, fmi2FMUstate *s)
REFUSED(fmi2GetDirectionalDerivative, fmi2Component c, const fmi2ValueReference a[], size_t n,
        const fmi2ValueReference b[], size_t m, const fmi2Real x[], fmi2Real y[])
REFUSED(fmi2SetRealInputDerivatives, fmi2Component c, const fmi2ValueReference v[], size_t n,
        const fmi2Integer o[], const fmi2Real x[])
REFUSED(fmi2GetRealOutputDerivatives, fmi2Component c, const fmi2ValueReference v[], size_t n,
        const fmi2Integer o[], fmi2Real x[])
REFUSED(fmi2CancelStep, fmi2Component c)
REFUSED(fmi2GetStatus, fmi2Component c, const fmi2StatusKind s, fmi2Status *v)
REFUSED(fmi2GetRealStatus, fmi2Component c, const fmi2StatusKind s, fmi2Real *v)
REFUSED(fmi2GetIntegerStatus, fmi2Component c, const fmi2StatusKind s, fmi2Integer *v)
REFUSED(fmi2GetBooleanStatus, fmi2Component c, const fmi2StatusKind s, fmi2Boolean *v)
REFUSED(fmi2GetStringStatus, fmi2Component c, const fmi2StatusKind s, fmi2String *v)
fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean no) {
    Model *m = c;
    (void)t; (void)h; (void)no;
    m->y1 = m->y2 = m->u;
    m->n++;
    return fmi2OK;
}
