/* Fuzz target: the DNA wall fit (rodkit_dna_fit_thin_wall). See fuzz.h. */
#include "fuzz.h"

struct args {
    double stretch, twist, coupling, mid_radius, helix_angle, thickness, nu12;
};
static const struct fuzz_field fields[] = {
    FUZZ_F(struct args, stretch),    FUZZ_F(struct args, twist),       FUZZ_F(struct args, coupling),
    FUZZ_F(struct args, mid_radius), FUZZ_F(struct args, helix_angle), FUZZ_F(struct args, thickness),
    FUZZ_F(struct args, nu12),
};

static void fuzz_one(void) {
    struct args a = {1100.0, 440.0, -90.0, 1.0, 1.0471975511965976, 0.4, 0.3};
    fuzz_perturb(&a, sizeof a, fields, FUZZ_COUNT(fields));
    RodkitDnaFit f;
    const char *fn = "rodkit_dna_fit_thin_wall";
    if (fuzz_status(fn, rodkit_dna_fit_thin_wall(a.stretch, a.twist, a.coupling, a.mid_radius, a.helix_angle,
                                                 a.thickness, a.nu12, &f)) < 0)
        return;
    double v[] = {f.spec.mid_radius, f.spec.thickness, f.spec.intrinsic_twist, f.spec.e1, f.spec.e2, f.spec.nu12,
                  f.spec.g12, f.stretch, f.coupling, f.twist, f.twist_rate, f.turns_per_pn_per_10kbp,
                  f.thick_stretch, f.thick_coupling, f.thick_twist, f.thick_turns_per_pn_per_10kbp};
    fuzz_finite(fn, "fit", v, FUZZ_COUNT(v));
    fuzz_positive(fn, "e1", f.spec.e1);
    fuzz_positive(fn, "e2", f.spec.e2);
    fuzz_positive(fn, "g12", f.spec.g12);
    if (f.thick_status > 0 || f.thick_status < RODKIT_STATUS_ERR_IO)
        fuzz_violation(fn, "thick-status", "thick_status is not a status code");
}

int main(int argc, char **argv) { return fuzz_main("dna_fit", argc, argv); }
