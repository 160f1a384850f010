/*
 * Feeds bad input to the C ABI and checks that each call returns its own
 * negative status and a message naming the argument. Exit code 0 only if all
 * checks pass; prints a one-line report (--values: one line per check and
 * "N passed, M failed" at the end).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "rodkit.h"

/* --values (first argument): also print the details, every result as a
 * "name = value" line (the channel rodkit's tests read) and the tables;
 * without it, a short report. */
static int values;
#define DETAIL(...)                      \
    do {                                 \
        if (values) printf(__VA_ARGS__); \
    } while (0)

static int passed = 0, failed = 0;

static void expect(const char *what, int32_t st, int32_t want, const char *needle) {
    const char *msg = rodkit_last_error_message();
    int ok = st == want && strstr(msg, needle) != NULL;
    DETAIL("%s %-34s status %3d (%s) message: %s\n", ok ? "PASS" : "FAIL", what, (int)st,
           rodkit_status_string(st), msg);
    if (ok) ++passed; else ++failed;
}

static RodkitThinTubeSpec good(void) {
    RodkitThinTubeSpec s;
    rodkit_thin_tube_spec_default(&s);
    s.mid_radius = 1.0;
    s.thickness = 0.4;
    s.intrinsic_twist = 1.7320508075688772;
    s.e1 = 300.0;
    s.e2 = 900.0;
    s.nu12 = 0.3;
    s.g12 = 100.0;
    return s;
}

int main(int argc, char **argv) {
    if (argc > 1 && strcmp(argv[1], "--values") == 0) values = 1;
    double k[9];
    int32_t a, b;
    RodkitThinTubeSpec s;

    expect("NULL spec", rodkit_thin_tube_coupling_stiffness(NULL, k, 3), RODKIT_STATUS_ERR_NULL_POINTER, "`spec`");
    s = good();
    expect("NULL output array", rodkit_thin_tube_coupling_stiffness(&s, NULL, 3), RODKIT_STATUS_ERR_NULL_POINTER, "`k`");
    expect("NULL version pointer", rodkit_version(&a, &b, NULL), RODKIT_STATUS_ERR_NULL_POINTER, "`patch`");
    s = good(); s.e1 = NAN;
    expect("NaN e1", rodkit_thin_tube_coupling_stiffness(&s, k, 3), RODKIT_STATUS_ERR_NOT_FINITE, "`spec.e1` must be finite (got NaN)");
    rodkit_thin_tube_spec_default(&s);
    expect("unset spec", rodkit_thin_tube_coupling_stiffness(&s, k, 3), RODKIT_STATUS_ERR_NOT_FINITE, "(got NaN)");
    s = good(); s.thickness = -0.1;
    expect("negative thickness", rodkit_thin_tube_coupling_stiffness(&s, k, 3), RODKIT_STATUS_ERR_NOT_POSITIVE, "`spec.thickness` must be positive (got -1e-1)");
    s = good(); s.e2 = 0.0;
    expect("E2 = 0", rodkit_thin_tube_coupling_stiffness(&s, k, 3), RODKIT_STATUS_ERR_NOT_POSITIVE, "`spec.e2`");
    s = good(); s.e2 = -900.0;
    expect("E2 < 0", rodkit_thin_tube_free_response(&s, &(RodkitFreeTubeResponse){0}), RODKIT_STATUS_ERR_NOT_POSITIVE, "`spec.e2` must be positive (got -9e2)");
    s = good(); s.thickness = 3.0;
    expect("wall thicker than the tube", rodkit_thin_tube_coupling_stiffness(&s, k, 3), RODKIT_STATUS_ERR_INVALID_GEOMETRY, "thickness 3e0");
    s = good(); s.nu12 = 0.7;
    expect("non-positive-definite material", rodkit_thin_tube_stretch_twist(&s, k, 2), RODKIT_STATUS_ERR_NOT_POSITIVE_DEFINITE, "nu12 = 7e-1");
    s = good();
    expect("leading dimension too small", rodkit_thin_tube_coupling_stiffness(&s, k, 2), RODKIT_STATUS_ERR_INVALID_DIMENSION, "`ldk`");
    expect("NULL error buffer", rodkit_last_error_copy(NULL, 8, NULL), RODKIT_STATUS_ERR_NULL_POINTER, "`buffer`");
    expect("panic inside rodkit", rodkit_diagnostic_panic(), RODKIT_STATUS_ERR_INTERNAL, "deliberate panic");

    /* A good call after all that succeeds and clears the message. */
    s = good();
    int32_t st = rodkit_thin_tube_coupling_stiffness(&s, k, 3);
    int ok = st == 0 && rodkit_last_error_message()[0] == '\0' && k[0] > 0.0;
    DETAIL("%s %-34s status %3d\n", ok ? "PASS" : "FAIL", "good call after failures", (int)st);
    if (ok) ++passed; else ++failed;

    DETAIL("%d passed, %d failed\n", passed, failed);
    printf("Error handling: %d of %d bad calls returned their own status and a message naming the argument%s;\n"
           "  a panic inside rodkit came back as RODKIT_STATUS_ERR_INTERNAL with a message, nothing printed\n",
           passed, passed + failed, failed ? " (FAILURES: run with --values)" : "");
    return failed != 0;
}
