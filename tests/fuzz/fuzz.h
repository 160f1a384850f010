/*
 * rodkit fuzz targets (issue 17, "no silent wrong answers"): shared driver.
 *
 * Each target starts from valid inputs, perturbs fields at random (NaN,
 * ±Inf, 0, −0, −1, ±1e308, denormals, random scale factors, out-of-range
 * integers, garbage bytes), calls the entry points and checks the
 * invariants of the C ABI:
 *
 *   - no crash and no sanitizer report (built with -fsanitize=address,undefined);
 *   - the status is one of the documented codes (RODKIT_STATUS_*);
 *   - on success (>= 0) the last-error message is empty and every output
 *     double is finite (radii and stiffness diagonals positive);
 *   - on failure (< 0) the message is non-empty and short (< 1 kB);
 *   - caller buffers are not written past their size (sentinels).
 *
 * Usage: fuzz_<group> [iterations [seed [first]]] (defaults 2000, 1, 0; or
 * FUZZ_ITERS, FUZZ_SEED); each iteration draws from (seed, iteration) only,
 * so `fuzz_<group> 1 SEED ITERATION` replays one. A violation is identified as "<function>:<check>"; those
 * listed in the file named by RODKIT_FUZZ_KNOWN (tests/fuzz/known.txt: one
 * id a line, `#` comments; findings owned by other branches, emptied at
 * merge) are reported but do not fail the run. Exit status 1 on any other
 * violation. Reproduce one with the seed and iteration printed.
 */
#ifndef RODKIT_FUZZ_H
#define RODKIT_FUZZ_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "rodkit.h"

/* ------------------------------------------------------------ random */

static uint64_t fuzz_state = 1;

static uint64_t fuzz_next(void) { /* splitmix64 */
    uint64_t z = (fuzz_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static int fuzz_below(int n) { return (int)(fuzz_next() % (uint64_t)n); }

static double fuzz_unit(void) { return (double)(fuzz_next() >> 11) * 0x1.0p-53; }

/* A hostile double, or `v` scaled, shifted or flipped. */
static double fuzz_double(double v) {
    switch (fuzz_below(16)) {
    case 0: return NAN;
    case 1: return INFINITY;
    case 2: return -INFINITY;
    case 3: return 0.0;
    case 4: return -0.0;
    case 5: return -1.0;
    case 6: return 1e308;
    case 7: return -1e308;
    case 8: return 4.9e-324; /* smallest denormal */
    case 9: return -2.2e-310;
    case 10: return v * pow(10.0, 40.0 * fuzz_unit() - 20.0);
    case 11: return -v;
    case 12: return v * (1.0 + 1e-3 * (fuzz_unit() - 0.5));
    case 13: return v + (fuzz_unit() - 0.5) * 10.0;
    case 14: {
        double d;
        uint64_t bits = fuzz_next();
        memcpy(&d, &bits, sizeof d);
        return d;
    }
    default: return v * 2.0 * fuzz_unit();
    }
}

/* A hostile integer for a count, index or enum of valid value `v`. */
static int64_t fuzz_int(int64_t v) {
    switch (fuzz_below(10)) {
    case 0: return -1;
    case 1: return 0;
    case 2: return v == INT64_MAX ? v : v + 1;
    case 3: return v == INT64_MIN ? v : v - 1;
    case 4: return INT64_MAX;
    case 5: return INT64_MIN;
    case 6: return INT32_MAX;
    case 7: return (int64_t)(fuzz_next() % 100) - 10;
    case 8: return 1ll << 40;
    default: return (int64_t)((uint64_t)v * 2u);
    }
}

/* Field tables: offsets and kinds of the fields of a C struct. */
enum fuzz_kind { FUZZ_F64, FUZZ_I32, FUZZ_I64 };
struct fuzz_field {
    size_t offset;
    enum fuzz_kind kind;
};
#define FUZZ_F(T, f) {offsetof(T, f), FUZZ_F64}
#define FUZZ_I(T, f) {offsetof(T, f), FUZZ_I32}
#define FUZZ_L(T, f) {offsetof(T, f), FUZZ_I64}
#define FUZZ_COUNT(a) (sizeof(a) / sizeof((a)[0]))

/* Perturb 0…3 fields of `s` (and with probability 1/16 one garbage byte).
 * Returns the number of changes. */
static int fuzz_perturb(void *s, size_t size, const struct fuzz_field *fields, size_t nfields) {
    int k = fuzz_below(4), changes = 0;
    unsigned char *b = (unsigned char *)s;
    for (int i = 0; i < k; i++) {
        const struct fuzz_field *f = &fields[fuzz_below((int)nfields)];
        if (f->kind == FUZZ_F64) {
            double v;
            memcpy(&v, b + f->offset, sizeof v);
            v = fuzz_double(v);
            memcpy(b + f->offset, &v, sizeof v);
        } else if (f->kind == FUZZ_I32) {
            int32_t v;
            memcpy(&v, b + f->offset, sizeof v);
            v = (int32_t)fuzz_int(v);
            memcpy(b + f->offset, &v, sizeof v);
        } else {
            int64_t v;
            memcpy(&v, b + f->offset, sizeof v);
            v = fuzz_int(v);
            memcpy(b + f->offset, &v, sizeof v);
        }
        changes++;
    }
    if (fuzz_below(16) == 0) {
        b[fuzz_below((int)size)] = (unsigned char)fuzz_next();
        changes++;
    }
    return changes;
}

/* ------------------------------------------------------------ checks */

static const char *fuzz_group = "?";
static long fuzz_iter = 0;
static uint64_t fuzz_seed = 1;
static long fuzz_violations = 0, fuzz_known_hits = 0, fuzz_calls = 0, fuzz_ok = 0;
static char fuzz_known[8192];
static char fuzz_reported[16384];

static void fuzz_load_known(void) {
    const char *path = getenv("RODKIT_FUZZ_KNOWN");
    fuzz_known[0] = '\n';
    fuzz_known[1] = 0;
    if (!path || !*path) return;
    FILE *f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "fuzz: cannot read RODKIT_FUZZ_KNOWN=%s\n", path);
        exit(2);
    }
    char line[512];
    size_t used = 1;
    while (fgets(line, sizeof line, f)) {
        char *hash = strchr(line, '#');
        if (hash) *hash = 0;
        char *end = line + strlen(line);
        while (end > line && (end[-1] == '\n' || end[-1] == ' ' || end[-1] == '\t')) *--end = 0;
        if (!*line || used + strlen(line) + 2 >= sizeof fuzz_known) continue;
        memcpy(fuzz_known + used, line, strlen(line));
        used += strlen(line);
        fuzz_known[used++] = '\n';
        fuzz_known[used] = 0;
    }
    fclose(f);
}

static int fuzz_in_list(const char *list, const char *id) {
    char key[300];
    snprintf(key, sizeof key, "\n%s\n", id);
    return strstr(list, key) != NULL;
}

/* Record a violation `func:check` with a detail line. */
static void fuzz_violation(const char *func, const char *check, const char *detail_in) {
    char id[256], detail[400];
    snprintf(detail, sizeof detail, "%s", detail_in);
    for (char *c = detail; *c; c++)
        if (*c == '\n') *c = ' ';
    for (char *c = strstr(detail, "  "); c; c = strstr(detail, "  ")) memmove(c, c + 1, strlen(c)); /* squeeze */
    snprintf(id, sizeof id, "%s:%s", func, check);
    int known = fuzz_in_list(fuzz_known, id);
    if (known)
        fuzz_known_hits++;
    else
        fuzz_violations++;
    if (!fuzz_in_list(fuzz_reported, id) && strlen(fuzz_reported) + strlen(id) + 3 < sizeof fuzz_reported) {
        if (!fuzz_reported[0]) strcpy(fuzz_reported, "\n");
        strcat(fuzz_reported, id);
        strcat(fuzz_reported, "\n");
        fprintf(stderr, "%s %s (seed %llu, iteration %ld): %s\n", known ? "KNOWN" : "VIOLATION", id,
                (unsigned long long)fuzz_seed, fuzz_iter, detail);
    }
}

/* The status and message invariants of one call; returns `st`. */
static int32_t fuzz_status(const char *func, int32_t st) {
    char detail[700];
    const char *msg = rodkit_last_error_message();
    fuzz_calls++;
    if (!((st >= RODKIT_STATUS_ERR_IO && st <= RODKIT_STATUS_ERR_INTERNAL) ||
          (st >= RODKIT_STATUS_OK && st <= RODKIT_STATUS_INFO_STRAND_CROSSING))) {
        snprintf(detail, sizeof detail, "undocumented status %d", (int)st);
        fuzz_violation(func, "status", detail);
    }
    if (st == RODKIT_STATUS_ERR_INTERNAL) {
        snprintf(detail, sizeof detail, "internal error: %.500s", msg);
        fuzz_violation(func, "internal", detail);
    }
    if (st >= 0) {
        fuzz_ok++;
        if (msg[0]) {
            snprintf(detail, sizeof detail, "status %d with message \"%.500s\"", (int)st, msg);
            fuzz_violation(func, "message-after-success", detail);
        }
    } else if (!msg[0]) {
        snprintf(detail, sizeof detail, "status %d with an empty message", (int)st);
        fuzz_violation(func, "empty-message", detail);
    } else if (strlen(msg) >= 1024) {
        snprintf(detail, sizeof detail, "status %d, message of %zu bytes: %.300s", (int)st, strlen(msg), msg);
        fuzz_violation(func, "long-message", detail);
    }
    return st;
}

/* After a success: `n` outputs finite. */
static void fuzz_finite(const char *func, const char *what, const double *v, size_t n) {
    for (size_t i = 0; i < n; i++)
        if (!isfinite(v[i])) {
            char detail[300];
            snprintf(detail, sizeof detail, "OK with %s[%zu] = %g", what, i, v[i]);
            fuzz_violation(func, "non-finite-output", detail);
            return;
        }
}

static __attribute__((unused)) void fuzz_positive(const char *func, const char *what, double v) {
    if (!(v > 0.0)) {
        char detail[300];
        snprintf(detail, sizeof detail, "OK with %s = %g (must be > 0)", what, v);
        fuzz_violation(func, "not-positive-output", detail);
    }
}

/* Sentinel-guarded output buffers: `n` usable doubles followed by guard
 * doubles that must come back untouched. */
#define FUZZ_GUARD 8
static const double fuzz_sentinel = -1.2345678901234567e-77;

static __attribute__((unused)) double *fuzz_buffer(size_t n) {
    double *b = (double *)malloc((n + FUZZ_GUARD) * sizeof(double));
    if (!b) abort();
    for (size_t i = 0; i < n + FUZZ_GUARD; i++) b[i] = fuzz_sentinel;
    return b;
}

static __attribute__((unused)) void fuzz_guard(const char *func, const char *what, double *b, size_t n) {
    for (size_t i = n; i < n + FUZZ_GUARD; i++)
        if (memcmp(&b[i], &fuzz_sentinel, sizeof(double)) != 0) {
            char detail[300];
            snprintf(detail, sizeof detail, "%s written past its %zu entries (at %zu)", what, n, i);
            fuzz_violation(func, "overflow", detail);
            break;
        }
    free(b);
}

/* Padding rows of a leading dimension (rows < ld) must be untouched. */
static __attribute__((unused)) void fuzz_padding(const char *func, const double *m, int64_t ld, int64_t rows, int64_t cols) {
    for (int64_t j = 0; j < cols; j++)
        for (int64_t i = rows; i < ld; i++)
            if (memcmp(&m[i + ld * j], &fuzz_sentinel, sizeof(double)) != 0) {
                fuzz_violation(func, "padding-written", "an entry between rows and ld was written");
                return;
            }
}

/* ------------------------------------------------------------ main */

static void fuzz_one(void); /* each target defines it: one iteration */

static int fuzz_main(const char *group, int argc, char **argv) {
    long iters = 2000, first = 0;
    fuzz_group = group;
    if (getenv("FUZZ_ITERS")) iters = atol(getenv("FUZZ_ITERS"));
    if (getenv("FUZZ_SEED")) fuzz_seed = strtoull(getenv("FUZZ_SEED"), NULL, 10);
    if (argc > 1) iters = atol(argv[1]);
    if (argc > 2) fuzz_seed = strtoull(argv[2], NULL, 10);
    if (argc > 3) first = atol(argv[3]);
    fuzz_load_known();
    for (fuzz_iter = first; fuzz_iter < first + iters; fuzz_iter++) {
        fuzz_state = fuzz_seed * 0x2545F4914F6CDD1Dull + (uint64_t)fuzz_iter;
        clock_t t0 = clock();
        if (getenv("FUZZ_TRACE")) fprintf(stderr, "iteration %ld\n", fuzz_iter);
        fuzz_one();
        /* FUZZ_SLOW=s: report iterations taking more CPU seconds (a hint
         * where the work bounds are loose; never a failure). */
        if (getenv("FUZZ_SLOW") && (double)(clock() - t0) / CLOCKS_PER_SEC > atof(getenv("FUZZ_SLOW")))
            fprintf(stderr, "slow: iteration %ld took %.2f s\n", fuzz_iter, (double)(clock() - t0) / CLOCKS_PER_SEC);
    }
    printf("fuzz %-12s seed %llu: %ld iterations, %ld calls (%ld succeeded), %ld violations, %ld known\n", group,
           (unsigned long long)fuzz_seed, iters, fuzz_calls, fuzz_ok, fuzz_violations, fuzz_known_hits);
    return fuzz_violations ? 1 : 0;
}

#endif
