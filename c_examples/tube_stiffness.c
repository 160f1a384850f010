/*
 * Thin-tube coupling stiffness from C (physics.md 1.4).
 *
 * Usage: tube_stiffness [--values] [input.txt]
 *   (default input: c_examples/data/dna_tube.txt, from the repository root)
 * Reads "key = value" lines into a RodkitThinTubeSpec and prints a short
 * report: the stretch-twist law and how the tube twists when pulled. With
 * --values it also prints the inputs, the 3x3 coupling stiffness K, the
 * condensed stretch-twist law, the rod law and the free-tube response as
 * "name = value" lines (17 significant digits, so the test suite can compare
 * them with the Rust results).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
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

static int check(int32_t st, const char *what) {
    if (st < 0) {
        fprintf(stderr, "%s failed: %s (%d): %s\n", what, rodkit_status_string(st), (int)st,
                rodkit_last_error_message());
        return 1;
    }
    return 0;
}

static int set_field(RodkitThinTubeSpec *spec, const char *key, double v) {
    if (!strcmp(key, "mid_radius")) spec->mid_radius = v;
    else if (!strcmp(key, "thickness")) spec->thickness = v;
    else if (!strcmp(key, "intrinsic_twist")) spec->intrinsic_twist = v;
    else if (!strcmp(key, "e1")) spec->e1 = v;
    else if (!strcmp(key, "e2")) spec->e2 = v;
    else if (!strcmp(key, "nu12")) spec->nu12 = v;
    else if (!strcmp(key, "g12")) spec->g12 = v;
    else return 1;
    return 0;
}

static int read_spec(const char *path, RodkitThinTubeSpec *spec) {
    FILE *f = fopen(path, "r");
    if (!f) {
        perror(path);
        return 1;
    }
    char line[512];
    int lineno = 0;
    while (fgets(line, sizeof line, f)) {
        ++lineno;
        char *hash = strchr(line, '#');
        if (hash) *hash = '\0';
        char key[64];
        double v;
        if (sscanf(line, " %63[a-z0-9_] = %lf", key, &v) == 2) {
            if (set_field(spec, key, v)) {
                fprintf(stderr, "%s:%d: unknown key '%s'\n", path, lineno, key);
                fclose(f);
                return 1;
            }
        } else if (strspn(line, " \t\r\n") != strlen(line)) {
            fprintf(stderr, "%s:%d: expected 'key = value'\n", path, lineno);
            fclose(f);
            return 1;
        }
    }
    fclose(f);
    return 0;
}

int main(int argc, char **argv) {
    if (argc > 1 && strcmp(argv[1], "--values") == 0) {
        values = 1;
        ++argv;
        --argc;
    }
    const char *path = argc > 1 ? argv[1] : "c_examples/data/dna_tube.txt";
    int32_t major, minor, patch;
    if (check(rodkit_version(&major, &minor, &patch), "rodkit_version")) return 1;
    if (major != RODKIT_VERSION_MAJOR || rodkit_library_abi_version() != RODKIT_ABI_VERSION) {
        fprintf(stderr, "header/library mismatch: header %s ABI %d, library %d.%d.%d ABI %d\n",
                RODKIT_VERSION_STRING, RODKIT_ABI_VERSION, major, minor, patch, rodkit_library_abi_version());
        return 1;
    }
    DETAIL("# rodkit %d.%d.%d (ABI %d): thin-tube coupling stiffness from C, input %s\n", major, minor,
           patch, rodkit_library_abi_version(), path);

    RodkitThinTubeSpec spec;
    if (check(rodkit_thin_tube_spec_default(&spec), "spec_default") || read_spec(path, &spec)) return 1;
    DETAIL("mid_radius = %.17g\nthickness = %.17g\nintrinsic_twist = %.17g\n", spec.mid_radius,
           spec.thickness, spec.intrinsic_twist);
    DETAIL("e1 = %.17g\ne2 = %.17g\nnu12 = %.17g\ng12 = %.17g\n", spec.e1, spec.e2, spec.nu12, spec.g12);

    double alpha;
    if (check(rodkit_thin_tube_helix_angle(&spec, &alpha), "helix_angle")) return 1;
    DETAIL("helix_angle_deg = %.17g\n", alpha * 180.0 / acos(-1.0));

    double k[9];
    if (check(rodkit_thin_tube_coupling_stiffness(&spec, k, 3), "coupling_stiffness")) return 1;
    DETAIL("# K: (F, T, 2 pi R^2 p) = K (strain, twist per length, hoop strain)\n");
    static const char *names[3] = {"strain", "twist", "hoop"};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) DETAIL("K_%s_%s = %.17g\n", names[i], names[j], k[i + 3 * j]);

    double s[4];
    if (check(rodkit_thin_tube_stretch_twist(&spec, s, 2), "stretch_twist")) return 1;
    DETAIL("# condensed at p = 0: (F, T) = [[S, g], [g, C]] (strain, twist)\n");
    DETAIL("stretch_modulus_S = %.17g\ntwist_stretch_g = %.17g\ntwist_modulus_C = %.17g\n", s[0], s[2], s[3]);

    double rod[36];
    if (check(rodkit_thin_tube_rod_stiffness(&spec, rod, 6), "rod_stiffness")) return 1;
    DETAIL("# as a hemitropic rod: (m, n) = K6 (u, v - e3), strains (u1, u2, u3, v1, v2, v3)\n");
    DETAIL("rod_bending = %.17g\nrod_twist = %.17g\nrod_shear = %.17g\nrod_stretch = %.17g\n", rod[0], rod[2 + 6 * 2],
           rod[3 + 6 * 3], rod[5 + 6 * 5]);
    DETAIL("rod_twist_stretch = %.17g\nrod_bend_shear = %.17g\n", rod[2 + 6 * 5], rod[0 + 6 * 3]);

    RodkitFreeTubeResponse r;
    if (check(rodkit_thin_tube_free_response(&spec, &r), "free_response")) return 1;
    DETAIL("dstrain_dforce = %.17g\ndtwist_dforce = %.17g\ndhoop_dforce = %.17g\nwinding = %d\n",
           r.dstrain_dforce, r.dtwist_dforce, r.dhoop_dforce, (int)r.winding);
    DETAIL("# pulled with T = 0 the tube %s\n",
           r.winding == RODKIT_WINDING_OVERWINDS ? "OVERWINDS (twists further in the sense of tau0)"
           : r.winding == RODKIT_WINDING_UNWINDS ? "unwinds" : "does not twist");
    printf("Thin-walled tube (%s): R = %g, t = %g, helix angle %.1f deg, E1 = %g, E2 = %g, G12 = %g\n", path,
           spec.mid_radius, spec.thickness, alpha * 180.0 / acos(-1.0), spec.e1, spec.e2, spec.g12);
    printf("  stretch modulus S = %.6g, twist modulus C = %.6g, twist-stretch coupling g = %.6g; as a rod: bending %.6g\n",
           s[0], s[3], s[2], rod[0]);
    printf("  pulled at zero torque it %s (twist per force %.3g)\n",
           r.winding == RODKIT_WINDING_OVERWINDS ? "overwinds" : r.winding == RODKIT_WINDING_UNWINDS ? "unwinds" : "does not twist",
           r.dtwist_dforce);
    return 0;
}
