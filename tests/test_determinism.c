/* test_determinism.c - the results of a fixed run, pinned: a Monte Carlo run of the
 * Noto hazard-map project (trees, a control line, random coefficients) with 1 and with
 * 4 threads, its rows hashed and compared with each other and with a stored constant.
 *
 * The hash is 64-bit FNV-1a (offset basis 14695981039346656037, prime 1099511628211)
 * over every column of every row, in id order: an INTEGER as its 8 bytes of int64 in
 * little-endian order, a REAL as the 8 bytes of its IEEE-754 bits in little-endian
 * order, TEXT as its UTF-8 bytes, NULL as nothing; each value is followed by a type
 * byte (1 integer, 2 real, 3 text, 5 null; SQLite's type codes), each row by 0xff.
 * A difference in the last bit of any double changes it. */
#include <sqlite3.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "rockfall/montecarlo.h"
#include "rockfall/project.h"
#include "motion_test_util.h"
#include "replay_test_util.h"
#include "results/store.h"
#include "test.h"

#define DET_PROJECT "projects/noto/noto-3.2.yaml"
#define DET_PER_RELEASE 60 /* 5 releases: 300 trajectories */

/* The hashes of the run above (its project's seed 2009, 60 per release), on x86-64 with
 * -O2 -ffp-contract=off (gcc and clang alike).
 * These change only in a commit of their own that says which change moved the results
 * and why; a commit that changes them as a side effect of something else is wrong. */
#define DET_TRAJECTORIES_HASH 0x184799a0efcc57caull
#define DET_INTERCEPTIONS_HASH 0xe4ad0aba29c3a325ull

/* The columns the hash pins, named: a column a later schema version adds (source_cell
 * of version 5, NULL for this project's point releases) leaves the pinned rows as they
 * were. */
static const char *const TRAJECTORIES_SQL =
    "SELECT id, run_id, release_id, idx, stop_x, stop_y, stop_z, stop_reason, duration_s,"
    " path_length_m, max_energy_kj, n_impacts, n_tree_hits, rest_steep, mass_kg, start_x,"
    " start_y, start_z FROM trajectories ORDER BY id";
static const char *const INTERCEPTIONS_SQL = "SELECT * FROM interceptions ORDER BY id";

static uint64_t fnv1a(uint64_t h, const unsigned char *b, size_t n)
{
    for (size_t k = 0; k < n; k++)
        h = (h ^ b[k]) * 1099511628211ull;
    return h;
}

static uint64_t fnv1a_u64(uint64_t h, uint64_t v)
{
    unsigned char b[8];
    for (int k = 0; k < 8; k++)
        b[k] = (unsigned char)(v >> (8 * k));
    return fnv1a(h, b, sizeof b);
}

/* The hash of a query's rows (above), and their number. */
static uint64_t rows_hash(const char *db, const char *sql, long *nrows)
{
    sqlite3 *h;
    ENSURE(sqlite3_open_v2(db, &h, SQLITE_OPEN_READONLY, NULL) == SQLITE_OK);
    sqlite3_stmt *st;
    ENSURE_MSG(sqlite3_prepare_v2(h, sql, -1, &st, NULL) == SQLITE_OK, "%s", sqlite3_errmsg(h));
    uint64_t hash = 14695981039346656037ull;
    *nrows = 0;
    int rc;
    while ((rc = sqlite3_step(st)) == SQLITE_ROW) {
        (*nrows)++;
        for (int c = 0; c < sqlite3_column_count(st); c++) {
            int type = sqlite3_column_type(st, c);
            if (type == SQLITE_INTEGER) {
                hash = fnv1a_u64(hash, (uint64_t)sqlite3_column_int64(st, c));
            } else if (type == SQLITE_FLOAT) {
                double v = sqlite3_column_double(st, c);
                uint64_t bits;
                memcpy(&bits, &v, sizeof bits);
                hash = fnv1a_u64(hash, bits);
            } else if (type == SQLITE_TEXT) {
                const unsigned char *s = sqlite3_column_text(st, c);
                hash = fnv1a(hash, s, (size_t)sqlite3_column_bytes(st, c));
            } else {
                ENSURE_MSG(type == SQLITE_NULL, "column %d: a blob", c);
            }
            unsigned char tb = (unsigned char)type;
            hash = fnv1a(hash, &tb, 1);
        }
        unsigned char end = 0xff;
        hash = fnv1a(hash, &end, 1);
    }
    ENSURE_MSG(rc == SQLITE_DONE, "%s", sqlite3_errmsg(h));
    sqlite3_finalize(st);
    sqlite3_close(h);
    return hash;
}

/* The project's run with `threads` workers into a fresh database `name`; its path.  With
 * `derive` its grid derives its triangles from its heights (rf_terrain_spec.grid_derive)
 * instead of keeping them. */
static const char *run_derived_into(const char *name, int threads, int derive)
{
    const char *db = rf_test_path(name);
    rf_project p;
    rf_error err;
    ENSURE_MSG(rf_project_load(DET_PROJECT, &p, &err) == 0, "%s:%d:%d: %s", err.file, err.line,
               err.column, err.message);
    ENSURE(p.terrain.is_grid && p.terrain.tri != NULL);
    if (derive) {
        rf_terrain_free(&p.terrain);
        p.terrain_spec.grid_derive = 1;
        ENSURE_MSG(rf_terrain_build(&p.terrain_spec, &p.terrain, &err) == 0, "%s", err.message);
        ENSURE(p.terrain.tri == NULL);
    }
    for (size_t i = 0; i < p.nreleases; i++)
        p.releases[i].count = DET_PER_RELEASE;
    rf_store *s;
    ENSURE_MSG(rf_store_open(db, &s, &err) == 0, "%s", err.message);
    rf_run_options o = {.threads = threads};
    rf_run_summary sum;
    ENSURE_MSG(rf_montecarlo_run(&p, s, &o, &sum, &err) == 0, "%s", err.message);
    ENSURE(sum.n_trajectories == DET_PER_RELEASE * (long)p.nreleases);
    rf_store_close(s);
    rf_project_free(&p);
    return db;
}

static const char *run_into(const char *name, int threads)
{
    return run_derived_into(name, threads, 0);
}

TEST(determinism_noto_rows_hash_same_any_threads_and_stored)
{
    char one[600], four[600];
    snprintf(one, sizeof one, "%s", run_into("one.db", 1));
    snprintf(four, sizeof four, "%s", run_into("four.db", 4));
    long n1, n4;
    uint64_t t1 = rows_hash(one, TRAJECTORIES_SQL, &n1);
    uint64_t t4 = rows_hash(four, TRAJECTORIES_SQL, &n4);
    ENSURE(n1 == 5 * DET_PER_RELEASE && n4 == n1);
    uint64_t i1 = rows_hash(one, INTERCEPTIONS_SQL, &n1);
    uint64_t i4 = rows_hash(four, INTERCEPTIONS_SQL, &n4);
    /* most rocks reach the road's control line; some stay in the forest above it */
    ENSURE_MSG(n1 > 4 * DET_PER_RELEASE && n4 == n1, "%ld and %ld interceptions", n1, n4);
    printf("    trajectories 0x%016llxull, interceptions 0x%016llxull\n", (unsigned long long)t1,
           (unsigned long long)i1);
    ENSURE_MSG(t1 == t4, "trajectories: 1 thread 0x%016llx, 4 threads 0x%016llx",
               (unsigned long long)t1, (unsigned long long)t4);
    ENSURE_MSG(i1 == i4, "interceptions: 1 thread 0x%016llx, 4 threads 0x%016llx",
               (unsigned long long)i1, (unsigned long long)i4);
    ENSURE_MSG(t1 == DET_TRAJECTORIES_HASH, "trajectories 0x%016llx, stored 0x%016llx",
               (unsigned long long)t1, DET_TRAJECTORIES_HASH);
    ENSURE_MSG(i1 == DET_INTERCEPTIONS_HASH, "interceptions 0x%016llx, stored 0x%016llx",
               (unsigned long long)i1, DET_INTERCEPTIONS_HASH);
}

/* The grid that derives its triangles from its heights gives the rows of the one that
 * keeps them, bit for bit, on 1 and on 3 threads. */
TEST(determinism_noto_rows_hash_same_with_derived_triangles)
{
    const int threads[2] = {1, 3};
    for (int k = 0; k < 2; k++) {
        const char *db = run_derived_into(k ? "derived3.db" : "derived1.db", threads[k], 1);
        long n;
        uint64_t t = rows_hash(db, TRAJECTORIES_SQL, &n);
        uint64_t i = rows_hash(db, INTERCEPTIONS_SQL, &n);
        ENSURE_MSG(t == DET_TRAJECTORIES_HASH, "%d threads: trajectories 0x%016llx, stored 0x%016llx",
                   threads[k], (unsigned long long)t, DET_TRAJECTORIES_HASH);
        ENSURE_MSG(i == DET_INTERCEPTIONS_HASH, "%d threads: interceptions 0x%016llx, stored 0x%016llx",
                   threads[k], (unsigned long long)i, DET_INTERCEPTIONS_HASH);
    }
}

/* ---- the same trajectory twice ------------------------------------------------------ */

/* One process, the same rock and seed twice on a rough slope: the record and every path
 * point are the same bytes. */
TEST(hard_same_seed_bit_identical_records)
{
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, 99);
    rf_terrain t;
    rough_terrain(&t, "det.asc", rng);
    for (int k = 0; k < 20; k++) {
        rf_state s = mt_state(rf_v3(3.0 + k, 5.0 + k, 50.0), rf_v3(1.0, 0.5, 0.0));
        mt_run a, b;
        mt_simulate(&t, k % 2 ? RF_MODEL_POINT : RF_MODEL_SPHERE, 2385.0, RF_CONTACT_FULL, &s,
                    1000 + (unsigned long)k, &a);
        mt_simulate(&t, k % 2 ? RF_MODEL_POINT : RF_MODEL_SPHERE, 2385.0, RF_CONTACT_FULL, &s,
                    1000 + (unsigned long)k, &b);
        ENSURE(memcmp(&a.rec, &b.rec, sizeof a.rec) == 0);
        ENSURE(a.npoints == b.npoints);
        ENSURE(memcmp(a.points, b.points, a.npoints * sizeof *a.points) == 0);
        mt_run_free(&a);
        mt_run_free(&b);
    }
    gsl_rng_free(rng);
    rf_terrain_free(&t);
}
