/* test_store_maps.c - run --store maps (docs/scaling.md): the run keeps its releases,
 * interceptions, hazard cells and sampled paths, the trajectory rows those need and no
 * tree hits, all as a full run writes them; check refuses such a run. */
#include <sqlite3.h>
#include <stdio.h>
#include <string.h>

#include "db_test_util.h"
#include "test.h"

#include <limits.h>
#include <stdlib.h>

/* The Noto slope, two releases, trees, a barrier that only some rocks reach, 20 sampled
 * paths per release; its path in *path. */
static void write_project(char *path, size_t cap)
{
    char dem[PATH_MAX], text[PATH_MAX + 1024];
    ENSURE(realpath("projects/noto/terrain.asc", dem));
    snprintf(text, sizeof text,
             "name: maps\nseed: 77\nterrain:\n  dem: %s\n  surface:\n"
             "    restitution: {mean: 0.15, sd: 0.05}\n    friction: {mean: 0.3, sd: 0.05}\n"
             "vegetation:\n  - {name: f, polygon: [[0, 25], [300, 25], [300, 200], [0, 200]],"
             " density: 0.01, height: 5, diameter: 0.2}\n"
             "rocks:\n  - {name: r, mass: 3000}\n"
             "releases:\n  - {name: C, point: [110, 202], rock: r, count: 1, jitter: 5}\n"
             "  - {name: G, point: [230, 202], rock: r, count: 1, jitter: 5}\n"
             "measures:\n  - {name: B, kind: barrier, line: [[100, 150], [140, 150]], height: 4,"
             " mel: 3000}\n"
             "simulation: {model: sphere, paths: 20}\nhazard: {cell: 5}\n",
             dem);
    snprintf(path, cap, "%s", rf_test_write("maps.yaml", text));
}

static long long q1(const char *db, const char *sql)
{
    sqlite3 *h;
    ENSURE(sqlite3_open_v2(db, &h, SQLITE_OPEN_READONLY, NULL) == SQLITE_OK);
    long long v = dbt_int(h, "%s", sql);
    sqlite3_close(h);
    return v;
}

static unsigned long long hash_of(const char *db, const char *sql, long *n)
{
    sqlite3 *h;
    ENSURE(sqlite3_open_v2(db, &h, SQLITE_OPEN_READONLY, NULL) == SQLITE_OK);
    unsigned long long x = dbt_rows_hash(h, sql, n);
    sqlite3_close(h);
    return x;
}

TEST(run_store_maps_keeps_the_maps_and_the_rows_they_need)
{
    char all[600], maps[600], cmd[2048], out[16384], project[600];
    write_project(project, sizeof project);
    snprintf(all, sizeof all, "%s", rf_test_path("all.db"));
    snprintf(maps, sizeof maps, "%s", rf_test_path("maps.db"));
    /* 150 a release: the first 20 of each have their paths sampled */
    snprintf(cmd, sizeof cmd, "run %s --count 150 -q -o %s", project, all);
    int rc = rf_test_rockfall(cmd, out, sizeof out);
    ENSURE_MSG(rc == 0 || rc == 1, "%s", out);
    snprintf(cmd, sizeof cmd, "run %s --count 150 --store maps -o %s", project, maps);
    ENSURE_MSG(rf_test_rockfall(cmd, out, sizeof out) == 0, "%s", out);
    ENSURE_MSG(strstr(out, "maps kept") && !strstr(out, "verdict"), "%s", out);

    ENSURE(q1(maps, "SELECT count(*) FROM runs WHERE status = 'complete' AND store = 'maps'"
                    " AND n_trajectories = 300") == 1);
    ENSURE(q1(all, "SELECT count(*) FROM runs WHERE store = 'all'") == 1);
    ENSURE(q1(maps, "SELECT count(*) FROM tree_hits") == 0);
    ENSURE(q1(all, "SELECT count(*) FROM tree_hits") > 0);
    /* the trajectories kept: the sampled and those that crossed a measure, exactly */
    long long kept = q1(maps, "SELECT count(*) FROM trajectories");
    long long need = q1(all, "SELECT count(*) FROM trajectories t WHERE t.idx < 20 OR EXISTS"
                             " (SELECT 1 FROM interceptions i WHERE i.trajectory_id = t.id)");
    long long crossed = q1(all, "SELECT count(DISTINCT trajectory_id) FROM interceptions");
    ENSURE_MSG(kept == need && kept < 300 && crossed > 0 && kept > crossed,
               "%lld kept, %lld needed, %lld crossed", kept, need, crossed);
    /* the same rows as the full run, keyed by release and index */
    static const char *const same[] = {
        "SELECT * FROM hazard_cells ORDER BY ix, iy",
        "SELECT r.idx, t.idx, t.stop_x, t.stop_reason, t.max_energy_kj, t.mass_kg FROM"
        " trajectories t JOIN releases r ON r.id = t.release_id WHERE t.idx < 20 OR EXISTS"
        " (SELECT 1 FROM interceptions i WHERE i.trajectory_id = t.id) ORDER BY r.idx, t.idx",
        "SELECT r.idx, t.idx, i.measure_id, i.t_s, i.energy_kj, i.passing_height_m, i.outcome"
        " FROM interceptions i JOIN trajectories t ON t.id = i.trajectory_id JOIN releases r"
        " ON r.id = t.release_id ORDER BY r.idx, t.idx, i.id",
        "SELECT r.idx, t.idx, p.seq, p.x, p.y, p.z, p.energy_kj FROM path_points p JOIN"
        " trajectories t ON t.id = p.trajectory_id JOIN releases r ON r.id = t.release_id"
        " ORDER BY r.idx, t.idx, p.seq",
        "SELECT idx, name, count FROM releases ORDER BY idx"};
    for (size_t k = 0; k < sizeof same / sizeof *same; k++) {
        long na, nm;
        unsigned long long ha = hash_of(all, same[k], &na), hm = hash_of(maps, same[k], &nm);
        ENSURE_MSG(ha == hm && na == nm && na > 0, "%s: %ld and %ld rows", same[k], na, nm);
    }
    /* check refuses the maps run, and leaves it as it was */
    snprintf(cmd, sizeof cmd, "check %s --rules rules/table3.yaml", maps);
    ENSURE(rf_test_rockfall(cmd, out, sizeof out) == 2);
    ENSURE_MSG(strstr(out, "--store maps") && strstr(out, "run 1"), "%s", out);
    ENSURE(q1(maps, "SELECT count(*) FROM checks") == 0);
    /* a bad value */
    snprintf(cmd, sizeof cmd, "run %s --store paths -o %s", project, maps);
    ENSURE(rf_test_rockfall(cmd, out, sizeof out) == 2);
    ENSURE_MSG(strstr(out, "--store takes all or maps, got 'paths'"), "%s", out);
}
