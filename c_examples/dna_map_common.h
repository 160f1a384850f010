/*
 * What the DNA map drivers share (c_examples/dna_map.c, the serial force x
 * salt map, and c_examples/mpi_dna_map.c, the same map over MPI ranks):
 * running one supercoiling curve and summarising it - with the full
 * zero-temperature charged rod (rodkit_dna_supercoil_*) or with the
 * thermal two-phase model (rodkit_tweezers_*) - its CSV, the summary CSV
 * (a `model` column says which model made each row; dna_map.c's header
 * comment says which column means what for each model), the SVG families,
 * the printed table, the plateau torque vs force against tweezers data,
 * and files written atomically (a temporary name, then rename(2): a reader
 * sees the old file, no file, or the complete new one - never a partial
 * one).
 */
#ifndef RODKIT_DNA_MAP_COMMON_H
#define RODKIT_DNA_MAP_COMMON_H

#include <stdint.h>
#include <stdio.h>

#include "rodkit.h"

#define DM_MAX_VALUES 16

typedef struct {
    int64_t bp;
    double force, salt;
    /* RODKIT_SUPERCOIL_MODEL_*: FULL_ROD (or 0: a zeroed curve is a full
     * rod's), THERMAL_TWO_PHASE, ZERO_TEMPERATURE_TWO_PHASE (the thermal
     * model at kT = 0); kT (pN nm) of the two-phase models. */
    int32_t model;
    double kT;
    int32_t status;
    int64_t points;
    double seconds, curve_seconds; /* the whole curve, and of it the energies and summary */
    RodkitSupercoilInfo info;
    RodkitSupercoilCurveInfo sum;
    RodkitSupercoilPoint *pts;
    RodkitSupercoilCurvePoint *cpts; /* NULL when the curve failed */
    /* The two-phase models: their points (pts is NULL then) and summary,
     * the points outside the model's range (in_range 0, skipped by the
     * summary), and why a curve failed. */
    RodkitTweezersPoint *tpts;
    RodkitTweezersInfo tsum;
    int64_t out_of_range;
    char msg[512];
} DnaCurve;

/* 1 for the two-phase (thermal or zero-temperature) models. */
int dm_two_phase(const DnaCurve *c);
/* A model's name in summary.csv: thermal_two_phase,
 * zero_temperature_two_phase or full_rod. */
const char *dm_model_name(int32_t model);

/* Monotonic seconds. */
double dm_now(void);
/* A comma-separated list of numbers into out[DM_MAX_VALUES]: their count, -1 when malformed. */
int dm_parse_list(const char *s, double *out);
/* mkdir -p. */
int dm_make_dirs(const char *path);
/* The names of a RodkitSummaryFinding and a RodkitStabilityKind. */
const char *dm_finding(int32_t f);
const char *dm_stability(int32_t k);
/* 1 when the finding carries a number (found, unverified). */
int dm_has_value(int32_t f);

/* Run one curve into c (c->force, c->salt, c->bp set by the caller);
 * its failure is recorded in c->status (and told on stderr), not fatal.
 * progress may be NULL. */
void dm_run_curve(const RodkitDnaSupercoilSpec *spec, DnaCurve *c, RodkitBranchCallback progress, void *user_data);
/* The two-phase model's curve into c (c->force, c->salt, c->bp, c->kT
 * set by the caller): points turns evenly from 0 to max_turns, or
 * (max_turns <= 0) rodkit_tweezers_default_turns (0 to twice the buckling
 * turns); summarised by rodkit_tweezers_summary. A failure is recorded in
 * c->status and c->msg (and told on stderr), not fatal. */
void dm_run_two_phase_curve(DnaCurve *c, double max_turns, int64_t points);
void dm_curve_free(DnaCurve *c);

/* Atomic writes: dm_open_tmp opens `<path>.tmp.<pid>` (its name into tmp),
 * dm_commit flushes, fsyncs and closes it and renames it to path (removing
 * it on any failure). Both return NULL / non-zero on failure, told on
 * stderr. */
FILE *dm_open_tmp(const char *path, char *tmp, size_t tmp_size);
int dm_commit(FILE *f, const char *tmp, const char *path);

/* The per-curve CSV (every point of the path with its energy, stability
 * and negative modes), written atomically to path. */
int dm_write_curve_csv(const char *path, const DnaCurve *c);
/* summary.csv: one row per curve, the summary with findings (empty cells
 * where nothing was determined); with_seconds adds the run time column
 * (the serial driver's; the MPI driver leaves timings out of it so that
 * the file is the same whatever the ranks). Atomic. */
int dm_write_summary_csv(const char *path, const DnaCurve *cs, int n, int with_seconds);
/* A family plot of y (which 0: extension, 1: torque) vs turns: colour
 * salt, dash force; o coexistence, x instability. Atomic. */
int dm_write_svg(const char *path, int which, const DnaCurve *cs, int n, const double *forces, int nf,
                 const double *salts, int ns);
/* The map's table on stdout. */
void dm_print_table(const DnaCurve *cs, int n);

/* The plateau torque vs force of the two-phase curves cs (one polyline per
 * salt) beside published tweezers data (tests/data/tweezers/
 * buckling_torque.csv: points with error bars, legend naming the
 * sources; rows of kind spec_unverified labelled as such), written to
 * svg_path (atomic; NULL: no plot), and the table "model vs data" on
 * stdout (each data row against the model at its force and at each salt;
 * the model is interpolated linearly in force between the map's forces,
 * never extrapolated). 0, or -1 when the data cannot be read. */
int dm_plateau_vs_data(const char *svg_path, const char *data_path, const DnaCurve *cs, int n);

#endif
