/*
 * The DNA map over MPI ranks (issue 21): the supercoiling curves of
 * c_examples/dna_map.c (a charged Kirchhoff rod, Debye-Hueckel screening;
 * see that file for the model and the summary's findings) for every
 * length x force x salt, spread over the ranks of an MPI job, each curve
 * summarised by rodkit_supercoil_curve_summary.
 *
 * Usage: mpirun -np R mpi_dna_map [options] <output folder>
 *   --model full-rod  the only model here: the full zero-temperature rod
 *                     (summary.csv's `model` column says full_rod). Unlike
 *                     the serial map (dna_map.c, whose default is the
 *                     thermal two-phase model), --model thermal is refused
 *                     with a message: a thermal curve takes milliseconds,
 *                     so the serial map is the place for it
 *   --lengths a,b,..  base pairs (default 1000; --bp N is one length)
 *   --forces a,b,..   pN      (default 0.5,1,2)
 *   --salts a,b,..    mol/L   (default 0.01,0.05,0.1,0.2)
 *   --turns T         the buckled branch stops past T turns (default 12)
 *   --elements N      0 (default): the automatic 2 nm mesh (see dna_map.c)
 *   --steps N         continuation steps per branch (default 1000)
 *   --threads T       threads per rank for each curve's pair forces
 *                     (RodkitDnaSupercoilSpec.threads, default 1)
 * Scenes are numbered length-major, then force, then salt (scene order).
 *
 * Outputs, all in the one folder given (shared by the ranks: on a cluster
 * a shared file system), each file written atomically (temporary name,
 * fsync, rename):
 *   curve_bp<L>_F<force>_S<salt>.csv  per curve, written by the rank that
 *                     ran it: the CSV of dna_map.c (every point with its
 *                     energy, stability and negative modes)
 *   scenes/bp<L>_F<force>_S<salt>.rec  the scene's checkpoint record: its
 *                     parameters, status, summary and the (turns, extension,
 *                     torque) of its points, in exact hexadecimal floats;
 *                     written after the curve file - a scene is finished
 *                     when its record exists
 *   summary.csv       rank 0: one row per scene in scene order (the columns
 *                     of dna_map.c's summary.csv without its run time)
 *   extension_vs_turns.svg, torque_vs_turns.svg
 *                     rank 0: the families (one pair per length, suffixed
 *                     _bp<L>, when there are several lengths)
 *   timings.csv       rank 0: seconds and rank of each scene run by this
 *                     job (the only output that changes from run to run)
 *
 * Load balancing: a work counter (one int64) in an MPI window at rank 0;
 * every rank, rank 0 included, takes the next unfinished scene with
 * MPI_Fetch_and_op(+1) under a shared passive-target lock, until the
 * counter passes the list. Scenes are handed out longest first (the cost
 * grows with the length), then in scene order, so no rank is left with a
 * long curve at the end when others could have shared it. With -np 1 the
 * one rank takes every scene. On networks without hardware atomics the
 * target must enter MPI for the others' fetch to progress: rank 0 calls
 * MPI_Iprobe from its progress callback after each converged point.
 *
 * Gathering: after the last scene every rank sends its records (the same
 * bytes it wrote to scenes/) to rank 0 (MPI_Gatherv); rank 0 builds
 * summary.csv and the plots only from records - gathered, or read back from
 * scenes/ for the scenes a previous run finished - so the outputs do not
 * depend on which rank ran a scene, in which order, or in which job.
 *
 * Checkpoint and restart: run the same command again (same folder, same
 * lists) after a kill: rank 0 skips every scene whose record exists and
 * holds the same parameters (a record of other parameters is recomputed,
 * and said so), removes stale temporary files, and prints "skipped K
 * finished scenes". Failed scenes are recorded too (their failure is the
 * result); delete their records to retry them.
 *
 * Determinism: every curve is computed by one rank alone, from its spec
 * only, so summary.csv, the plots and the curve files are bitwise the same
 * for any number of ranks (tests/mpi.rs: 1, 2 and 4) and any --threads
 * (rodkit.h, RodkitDnaSupercoilSpec.threads: results bitwise the same for
 * any thread count; tests/mpi.rs: 1 and 2). So a record is reused whatever
 * --threads wrote it: its identity holds what the curve depends on only.
 *
 * Threads and MPI: MPI_THREAD_FUNNELED is requested, and it suffices: only
 * the main thread calls MPI (the progress callback runs on the thread that
 * called rodkit, rodkit.h), and rodkit never calls MPI; the threads it
 * starts for --threads are its own and do no MPI.
 */
#define _XOPEN_SOURCE 700
#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <mpi.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "dna_map_common.h"
#include "rodkit.h"

typedef struct {
    double lengths[DM_MAX_VALUES], forces[DM_MAX_VALUES], salts[DM_MAX_VALUES];
    int nl, nf, ns;
    double turns;
    long long elements, steps, threads;
    const char *dir;
} Map;

/* One scene's record as text (malloc'd), its length, and where it came from. */
typedef struct {
    char *text;
    size_t len;
} Record;

static int rank_ = 0;

static void scene_values(const Map *m, int k, int64_t *bp, double *force, double *salt) {
    int si = k % m->ns, fi = (k / m->ns) % m->nf, li = k / (m->ns * m->nf);
    *bp = (int64_t)m->lengths[li];
    *force = m->forces[fi];
    *salt = m->salts[si];
}

static void scene_paths(const Map *m, int k, char *curve, char *record, size_t size) {
    int64_t bp;
    double f, s;
    scene_values(m, k, &bp, &f, &s);
    snprintf(curve, size, "%s/curve_bp%lld_F%g_S%g.csv", m->dir, (long long)bp, f, s);
    snprintf(record, size, "%s/scenes/bp%lld_F%g_S%g.rec", m->dir, (long long)bp, f, s);
}

/* The record's identity line: every parameter the curve depends on, exact. */
static void identity(const Map *m, int k, char *out, size_t size) {
    int64_t bp;
    double f, s;
    scene_values(m, k, &bp, &f, &s);
    snprintf(out, size, "rodkit-dna-map-scene 2 bp %lld force %a salt %a turns %a elements %lld steps %lld\n", (long long)bp,
             f, s, m->turns, m->elements, m->steps);
}

/* The summary's fields in the record's order. */
enum { I32, I64, F64 };
#define SF(name, type) {offsetof(RodkitSupercoilCurveInfo, name), type}
static const struct {
    size_t off;
    int type;
} SUM_FIELDS[] = {
    SF(instability_finding, I32), SF(instability_turns, F64), SF(instability_torque, F64),
    SF(coexistence_finding, I32), SF(coexistence_turns, F64), SF(coexistence_torque_straight, F64),
    SF(coexistence_torque_plectoneme, F64), SF(coexistence_extension_straight, F64),
    SF(coexistence_extension_plectoneme, F64), SF(coexistence_extension_jump, F64), SF(plateau_finding, I32),
    SF(plateau_torque, F64), SF(plateau_torque_min, F64), SF(plateau_torque_max, F64), SF(slope, F64),
    SF(plateau_turns_from, F64), SF(plateau_turns_to, F64), SF(plateau_nodes, I64), SF(superhelix_finding, I32),
    SF(superhelix_radius, F64), SF(strand_distance, F64), SF(strand_s1, F64), SF(strand_s2, F64),
    SF(superhelix_turns, F64),
};
#undef SF
#define N_SUM_FIELDS (sizeof SUM_FIELDS / sizeof SUM_FIELDS[0])

/* The record of a computed curve (NULL when out of memory). */
static char *make_record(const Map *m, int k, const DnaCurve *c, size_t *len) {
    char *buf = NULL;
    FILE *f = open_memstream(&buf, len);
    if (!f) return NULL;
    char id[512];
    identity(m, k, id, sizeof id);
    fputs(id, f);
    int ok = c->status >= 0;
    fprintf(f, "status %d points %lld hard_core_switched %d\nsummary", (int)c->status, ok ? (long long)c->points : 0LL,
            ok ? (int)c->info.hard_core_switched : 0);
    for (size_t i = 0; i < N_SUM_FIELDS; ++i) {
        const char *p = (const char *)&c->sum + SUM_FIELDS[i].off;
        switch (SUM_FIELDS[i].type) {
        case I32: fprintf(f, " %d", (int)*(const int32_t *)(const void *)p); break;
        case I64: fprintf(f, " %lld", (long long)*(const int64_t *)(const void *)p); break;
        default: fprintf(f, " %a", *(const double *)(const void *)p);
        }
    }
    fputc('\n', f);
    for (int64_t i = 0; ok && i < c->points; ++i)
        fprintf(f, "%a %a %a\n", c->pts[i].turns, c->pts[i].extension, c->pts[i].torque);
    fputs("end\n", f);
    if (fclose(f) != 0) {
        free(buf);
        return NULL;
    }
    return buf;
}

/* A record back into a curve (its scene's values, status, summary and the
 * points' turns, extension and torque). 0, or -1 when it is malformed or
 * of other parameters. */
static int parse_record(const Map *m, int k, const char *text, DnaCurve *c) {
    char id[512];
    identity(m, k, id, sizeof id);
    size_t idn = strlen(id);
    if (strncmp(text, id, idn) != 0) return -1;
    const char *s = text + idn;
    int status, hcs, used = 0;
    long long points;
    if (sscanf(s, "status %d points %lld hard_core_switched %d\nsummary%n", &status, &points, &hcs, &used) != 3 || used == 0 ||
        points < 0 || points > 100000000)
        return -1;
    s += used;
    memset(c, 0, sizeof *c);
    scene_values(m, k, &c->bp, &c->force, &c->salt);
    c->status = status;
    c->points = points;
    c->info.points = points;
    c->info.hard_core_switched = hcs;
    char *end;
    for (size_t i = 0; i < N_SUM_FIELDS; ++i) {
        char *p = (char *)&c->sum + SUM_FIELDS[i].off;
        if (SUM_FIELDS[i].type == F64) *(double *)(void *)p = strtod(s, &end);
        else {
            long long v = strtoll(s, &end, 10);
            if (SUM_FIELDS[i].type == I32) *(int32_t *)(void *)p = (int32_t)v;
            else *(int64_t *)(void *)p = (int64_t)v;
        }
        if (end == s) return -1;
        s = end;
    }
    if (*s++ != '\n') return -1;
    if (points > 0 && !(c->pts = calloc((size_t)points, sizeof *c->pts))) return -1;
    for (long long i = 0; i < points; ++i) {
        double v[3];
        for (int j = 0; j < 3; ++j) {
            v[j] = strtod(s, &end);
            if (end == s) return -1;
            s = end;
        }
        if (*s++ != '\n') return -1;
        c->pts[i].turns = v[0];
        c->pts[i].extension = v[1];
        c->pts[i].torque = v[2];
    }
    return strcmp(s, "end\n") == 0 ? 0 : -1;
}

/* A whole file (NULL when it cannot be read). */
static char *read_file(const char *path, size_t *len) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    char *buf = NULL;
    size_t cap = 0, n = 0;
    for (;;) {
        if (n + 65536 + 1 > cap) {
            cap = 2 * cap + 65536 + 1;
            char *b = realloc(buf, cap);
            if (!b) break;
            buf = b;
        }
        size_t got = fread(buf + n, 1, cap - n - 1, f);
        n += got;
        if (got == 0) {
            fclose(f);
            buf[n] = '\0';
            *len = n;
            return buf;
        }
    }
    fclose(f);
    free(buf);
    return NULL;
}

static int write_text(const char *path, const char *text, size_t len) {
    char tmp[4300];
    FILE *f = dm_open_tmp(path, tmp, sizeof tmp);
    if (!f) return -1;
    fwrite(text, 1, len, f);
    return dm_commit(f, tmp, path);
}

/* Remove the temporary files (".tmp.<pid>") a killed run left in dir. */
static int remove_stale(const char *dir) {
    DIR *d = opendir(dir);
    int n = 0;
    if (!d) return 0;
    struct dirent *e;
    char path[4300];
    while ((e = readdir(d))) {
        if (!strstr(e->d_name, ".tmp.")) continue;
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        n += remove(path) == 0;
    }
    closedir(d);
    return n;
}

/* Rank 0 keeps MPI's progress engine turning while it computes (for the
 * others' fetch on networks without hardware atomics). Main thread only. */
static int32_t nudge(const RodkitBranchProgress *p, void *user_data) {
    (void)p;
    (void)user_data;
    int flag;
    MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, MPI_STATUS_IGNORE);
    return 0;
}

/* Longest first, then scene order. */
static const Map *sort_map;
static int by_cost(const void *a, const void *b) {
    int i = *(const int *)a, j = *(const int *)b;
    int64_t bi, bj;
    double f, s;
    scene_values(sort_map, i, &bi, &f, &s);
    scene_values(sort_map, j, &bj, &f, &s);
    if (bi != bj) return bi > bj ? -1 : 1;
    return (i > j) - (i < j);
}

static int usage(const char *msg, const char *arg) {
    if (rank_ == 0) fprintf(stderr, "%s%s (see the comment at the top of mpi_dna_map.c)\n", msg, arg);
    return 2;
}

static int parse_args(int argc, char **argv, Map *m) {
    static const double F[] = {0.5, 1.0, 2.0}, S[] = {0.01, 0.05, 0.1, 0.2};
    memcpy(m->forces, F, sizeof F);
    memcpy(m->salts, S, sizeof S);
    m->lengths[0] = 1000;
    m->nl = 1, m->nf = 3, m->ns = 4;
    m->turns = 12.0;
    m->elements = 0, m->steps = 1000, m->threads = 1;
    m->dir = NULL;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        int takes = a[0] == '-' && a[1] == '-';
        if (takes && !v) return usage("a value is needed after ", a);
        if (!strcmp(a, "--model")) {
            if (!strcmp(v, "thermal"))
                return usage("--model thermal is not offered over MPI (a thermal map takes milliseconds a curve: run c_dna_map "
                             "--model thermal, the serial map's default); this map is the full rod's", "");
            if (strcmp(v, "full-rod")) return usage("--model: full-rod (the only model of the MPI map), not ", v);
        } else if (!strcmp(a, "--forces")) m->nf = dm_parse_list(v, m->forces);
        else if (!strcmp(a, "--salts")) m->ns = dm_parse_list(v, m->salts);
        else if (!strcmp(a, "--lengths")) m->nl = dm_parse_list(v, m->lengths);
        else if (!strcmp(a, "--bp")) m->nl = 1, m->lengths[0] = atof(v);
        else if (!strcmp(a, "--turns")) m->turns = atof(v);
        else if (!strcmp(a, "--elements")) m->elements = atoll(v);
        else if (!strcmp(a, "--steps")) m->steps = atoll(v);
        else if (!strcmp(a, "--threads")) m->threads = atoll(v);
        else if (takes) return usage("unknown option ", a);
        else if (m->dir) return usage("one output folder, not two: ", a);
        else { m->dir = a; continue; }
        ++i;
        if (m->nf <= 0 || m->ns <= 0 || m->nl <= 0) return usage("bad list after ", a);
    }
    if (!m->dir) return usage("the output folder is missing", "");
    for (int i = 0; i < m->nl; ++i)
        if (m->lengths[i] < 1 || m->lengths[i] != (double)(int64_t)m->lengths[i]) return usage("a length is not a whole number of base pairs", "");
    if (m->elements < 0 || m->threads < 1) return usage("--elements must be >= 0 and --threads >= 1", "");
    return 0;
}

int main(int argc, char **argv) {
    int provided, nranks;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &nranks);
    double t_start = MPI_Wtime();
    Map m;
    int bad = parse_args(argc, argv, &m);
    if (bad) {
        MPI_Finalize();
        return bad;
    }
    const int n = m.nl * m.nf * m.ns;
    if (rank_ == 0 && provided < MPI_THREAD_FUNNELED && m.threads > 1)
        fprintf(stderr, "# warning: the MPI library gives no MPI_THREAD_FUNNELED (level %d): rodkit's own threads "
                        "(--threads) are outside what it promises\n", provided);

    /* Rank 0: the folder, stale temporaries, and the finished scenes. */
    Record *recs = calloc((size_t)n, sizeof *recs);
    int *todo = malloc(sizeof *todo * (size_t)n);
    int ntodo = 0;
    if (!recs || !todo) MPI_Abort(MPI_COMM_WORLD, 1);
    if (rank_ == 0) {
        char sub[4200];
        snprintf(sub, sizeof sub, "%s/scenes", m.dir);
        if (dm_make_dirs(sub) != 0) {
            perror(sub);
            ntodo = -1;
        } else {
            int stale = remove_stale(m.dir) + remove_stale(sub);
            if (stale) printf("# removed %d temporary files of an interrupted run\n", stale);
            for (int k = 0; k < n; ++k) {
                char curve[4200], record[4200];
                scene_paths(&m, k, curve, record, sizeof curve);
                size_t len = 0;
                char *text = read_file(record, &len);
                DnaCurve c;
                memset(&c, 0, sizeof c);
                int ok = text && parse_record(&m, k, text, &c) == 0;
                struct stat st;
                if (ok && c.status >= 0 && stat(curve, &st) != 0) ok = 0;
                dm_curve_free(&c);
                if (text && !ok)
                    printf("# %s: not a record of this map's scene (other parameters, or no curve file): recomputed\n", record);
                if (ok) recs[k] = (Record){text, len};
                else {
                    free(text);
                    todo[ntodo++] = k;
                }
            }
            sort_map = &m;
            qsort(todo, (size_t)ntodo, sizeof *todo, by_cost);
            printf("# DNA map over %d MPI ranks x %lld threads: %d lengths x %d forces x %d salts = %d scenes, to %g turns, "
                   "%lld elements%s, up to %lld steps a branch\n", nranks, m.threads, m.nl, m.nf, m.ns, n, m.turns, m.elements,
                   m.elements ? "" : " (the automatic mesh)", m.steps);
            printf("skipped %d finished scenes\n", n - ntodo);
            fflush(stdout);
        }
    }
    MPI_Bcast(&ntodo, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (ntodo < 0) {
        MPI_Finalize();
        return 1;
    }
    MPI_Bcast(todo, ntodo, MPI_INT, 0, MPI_COMM_WORLD);

    /* The work counter at rank 0. */
    int64_t *counter = NULL;
    MPI_Win win;
    MPI_Win_allocate(rank_ == 0 ? (MPI_Aint)sizeof(int64_t) : 0, sizeof(int64_t), MPI_INFO_NULL, MPI_COMM_WORLD, &counter, &win);
    if (rank_ == 0) {
        MPI_Win_lock(MPI_LOCK_EXCLUSIVE, 0, 0, win);
        *counter = 0;
        MPI_Win_unlock(0, win);
    }
    MPI_Barrier(MPI_COMM_WORLD);

    /* Take scenes until none is left; keep their records for rank 0. */
    int nmine = 0;
    int *mine = malloc(sizeof *mine * (size_t)(ntodo + 1));
    double *secs = malloc(sizeof *secs * (size_t)(ntodo + 1));
    Record *mrec = calloc((size_t)ntodo + 1, sizeof *mrec);
    if (!mine || !secs || !mrec) MPI_Abort(MPI_COMM_WORLD, 1);
    for (;;) {
        int64_t one = 1, got = 0;
        MPI_Win_lock(MPI_LOCK_SHARED, 0, 0, win);
        MPI_Fetch_and_op(&one, &got, MPI_INT64_T, 0, 0, MPI_SUM, win);
        MPI_Win_unlock(0, win);
        if (got >= ntodo) break;
        int k = todo[got];
        DnaCurve c;
        memset(&c, 0, sizeof c);
        scene_values(&m, k, &c.bp, &c.force, &c.salt);
        RodkitDnaSupercoilSpec spec;
        if (rodkit_dna_supercoil_spec_default(&spec) < 0) MPI_Abort(MPI_COMM_WORLD, 1);
        spec.base_pairs = c.bp;
        spec.tension = c.force;
        spec.salt = c.salt;
        spec.max_turns = m.turns;
        spec.elements = m.elements;
        spec.max_steps = m.steps;
        spec.threads = m.threads;
        dm_run_curve(&spec, &c, rank_ == 0 && nranks > 1 ? nudge : NULL, NULL);
        char curve[4200], record[4200];
        scene_paths(&m, k, curve, record, sizeof curve);
        size_t len = 0;
        char *text = make_record(&m, k, &c, &len);
        /* The curve file first, its record last: a record means both are complete. */
        if (!text || (c.status >= 0 && dm_write_curve_csv(curve, &c) != 0) || write_text(record, text, len) != 0) {
            fprintf(stderr, "rank %d: cannot write scene %d's files\n", rank_, k + 1);
            MPI_Abort(MPI_COMM_WORLD, 1);
        }
        printf("# rank %d: scene %d/%d (%lld bp, %g pN, %g M): %lld points to %.3f turns in %.2f s (%s)\n", rank_, k + 1, n,
               (long long)c.bp, c.force, c.salt, (long long)c.points, c.points ? c.pts[c.points - 1].turns : 0.0, c.seconds,
               rodkit_status_string(c.status));
        fflush(stdout);
        mine[nmine] = k;
        secs[nmine] = c.seconds;
        mrec[nmine++] = (Record){text, len};
        dm_curve_free(&c);
    }
    MPI_Win_free(&win);

    /* Gather the records at rank 0 (MPI_Gatherv: counts and displacements are int). */
    long long mybytes = 0;
    for (int i = 0; i < nmine; ++i) mybytes += (long long)mrec[i].len;
    int *counts = NULL, *bcounts = NULL, *displs = NULL, *bdispls = NULL, *all_k = NULL;
    long long *all_len = NULL, *bytes_of = NULL;
    double *all_s = NULL;
    if (rank_ == 0) {
        counts = calloc((size_t)nranks, sizeof *counts);
        bcounts = calloc((size_t)nranks, sizeof *bcounts);
        displs = calloc((size_t)nranks, sizeof *displs);
        bdispls = calloc((size_t)nranks, sizeof *bdispls);
        bytes_of = calloc((size_t)nranks, sizeof *bytes_of);
        all_k = malloc(sizeof *all_k * (size_t)(ntodo + 1));
        all_len = malloc(sizeof *all_len * (size_t)(ntodo + 1));
        all_s = malloc(sizeof *all_s * (size_t)(ntodo + 1));
        if (!counts || !bcounts || !displs || !bdispls || !bytes_of || !all_k || !all_len || !all_s) MPI_Abort(MPI_COMM_WORLD, 1);
    }
    MPI_Gather(&nmine, 1, MPI_INT, counts, 1, MPI_INT, 0, MPI_COMM_WORLD);
    MPI_Gather(&mybytes, 1, MPI_LONG_LONG, bytes_of, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
    int too_big = 0;
    if (rank_ == 0) {
        long long total = 0;
        for (int r = 0; r < nranks; ++r) {
            displs[r] = r ? displs[r - 1] + counts[r - 1] : 0;
            bdispls[r] = (int)total;
            bcounts[r] = (int)bytes_of[r];
            total += bytes_of[r];
            if (total > INT_MAX) too_big = 1;
        }
    }
    long long *lens = malloc(sizeof *lens * (size_t)(nmine + 1));
    if (!lens) MPI_Abort(MPI_COMM_WORLD, 1);
    for (int i = 0; i < nmine; ++i) lens[i] = (long long)mrec[i].len;
    MPI_Gatherv(mine, nmine, MPI_INT, all_k, counts, displs, MPI_INT, 0, MPI_COMM_WORLD);
    MPI_Gatherv(secs, nmine, MPI_DOUBLE, all_s, counts, displs, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    MPI_Gatherv(lens, nmine, MPI_LONG_LONG, all_len, counts, displs, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
    MPI_Bcast(&too_big, 1, MPI_INT, 0, MPI_COMM_WORLD);
    char *bytes = NULL;
    if (!too_big) {
        /* The records, one after another. */
        char *myb = malloc((size_t)mybytes + 1);
        if (!myb) MPI_Abort(MPI_COMM_WORLD, 1);
        size_t at = 0;
        for (int i = 0; i < nmine; ++i) {
            memcpy(myb + at, mrec[i].text, mrec[i].len);
            at += mrec[i].len;
        }
        long long total = 0;
        if (rank_ == 0)
            for (int r = 0; r < nranks; ++r) total += bytes_of[r];
        if (rank_ == 0 && !(bytes = malloc((size_t)total + 1))) MPI_Abort(MPI_COMM_WORLD, 1);
        MPI_Gatherv(myb, (int)mybytes, MPI_CHAR, bytes, bcounts, bdispls, MPI_CHAR, 0, MPI_COMM_WORLD);
        free(myb);
    }

    int status = 0;
    if (rank_ == 0) {
        /* Every scene's record: gathered, or (too many bytes for one
         * Gatherv) read back from scenes/ like a finished scene's. */
        int *ran_on = malloc(sizeof *ran_on * (size_t)n);
        double *ran_s = malloc(sizeof *ran_s * (size_t)n);
        if (!ran_on || !ran_s) MPI_Abort(MPI_COMM_WORLD, 1);
        for (int k = 0; k < n; ++k) ran_on[k] = -1, ran_s[k] = 0.0;
        size_t at = 0;
        for (int r = 0, i = 0; r < nranks; ++r)
            for (int j = 0; j < counts[r]; ++j, ++i) {
                int k = all_k[i];
                ran_on[k] = r;
                ran_s[k] = all_s[i];
                if (too_big) {
                    char curve[4200], record[4200];
                    scene_paths(&m, k, curve, record, sizeof curve);
                    recs[k].text = read_file(record, &recs[k].len);
                } else {
                    recs[k].text = malloc((size_t)all_len[i] + 1);
                    if (recs[k].text) {
                        memcpy(recs[k].text, bytes + at, (size_t)all_len[i]);
                        recs[k].text[all_len[i]] = '\0';
                        recs[k].len = (size_t)all_len[i];
                    }
                    at += (size_t)all_len[i];
                }
            }
        DnaCurve *cs = calloc((size_t)n, sizeof *cs);
        if (!cs) MPI_Abort(MPI_COMM_WORLD, 1);
        int failed = 0;
        double sum_s = 0.0, max_s = 0.0;
        for (int k = 0; k < n; ++k) {
            if (!recs[k].text || parse_record(&m, k, recs[k].text, &cs[k]) != 0) {
                fprintf(stderr, "scene %d: its record is missing or malformed\n", k + 1);
                MPI_Abort(MPI_COMM_WORLD, 1);
            }
            cs[k].seconds = ran_s[k];
            failed += cs[k].status < 0;
            sum_s += ran_s[k];
            if (ran_s[k] > max_s) max_s = ran_s[k];
        }
        char path[4200];
        snprintf(path, sizeof path, "%s/summary.csv", m.dir);
        if (dm_write_summary_csv(path, cs, n, 0) != 0) status = 1;
        for (int li = 0; li < m.nl && !status; ++li) {
            const DnaCurve *part = cs + li * m.nf * m.ns;
            for (int which = 0; which < 2; ++which) {
                const char *name = which ? "torque_vs_turns" : "extension_vs_turns";
                if (m.nl == 1) snprintf(path, sizeof path, "%s/%s.svg", m.dir, name);
                else snprintf(path, sizeof path, "%s/%s_bp%lld.svg", m.dir, name, (long long)m.lengths[li]);
                if (dm_write_svg(path, which, part, m.nf * m.ns, m.forces, m.nf, m.salts, m.ns) != 0) status = 1;
            }
        }
        char tmp[4300];
        snprintf(path, sizeof path, "%s/timings.csv", m.dir);
        FILE *f = dm_open_tmp(path, tmp, sizeof tmp);
        if (f) {
            fprintf(f, "scene,base_pairs,force_pN,salt_M,rank,seconds,points\n");
            for (int k = 0; k < n; ++k) {
                fprintf(f, "%d,%lld,%g,%g,", k + 1, (long long)cs[k].bp, cs[k].force, cs[k].salt);
                if (ran_on[k] < 0) fprintf(f, "skipped,,%lld\n", (long long)cs[k].points);
                else fprintf(f, "%d,%.4f,%lld\n", ran_on[k], ran_s[k], (long long)cs[k].points);
            }
            if (dm_commit(f, tmp, path) != 0) status = 1;
        } else status = 1;
        dm_print_table(cs, n);
        printf("# (s: this job's run time; 0 for a skipped scene)\n");
        printf("scenes = %d\nskipped_scenes = %d\ncomputed_scenes = %d\nfailed_scenes = %d\nranks = %d\nthreads = %lld\n", n,
               n - ntodo, ntodo, failed, nranks, m.threads);
        printf("scene_seconds_sum = %.2f\nscene_seconds_max = %.2f\nwall_seconds = %.2f\n", sum_s, max_s, MPI_Wtime() - t_start);
        char *abs = realpath(m.dir, NULL);
        printf("# files in %s/: summary.csv, curve_bp<L>_F<force>_S<salt>.csv (%d), the .svg plots, timings.csv, scenes/\n",
               abs ? abs : m.dir, n - failed);
        free(abs);
        if (failed) status = 1;
        for (int k = 0; k < n; ++k) dm_curve_free(&cs[k]);
        free(cs);
        free(ran_on);
        free(ran_s);
    }
    MPI_Bcast(&status, 1, MPI_INT, 0, MPI_COMM_WORLD);
    for (int k = 0; k < n; ++k) free(recs[k].text);
    for (int i = 0; i < nmine; ++i) free(mrec[i].text);
    free(recs);
    free(todo);
    free(mine);
    free(secs);
    free(mrec);
    free(lens);
    free(bytes);
    free(counts);
    free(bcounts);
    free(displs);
    free(bdispls);
    free(bytes_of);
    free(all_k);
    free(all_len);
    free(all_s);
    MPI_Finalize();
    return status;
}
