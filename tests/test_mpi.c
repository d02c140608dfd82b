/* test_mpi.c - runs shared among MPI ranks (src/run/mpi.c, docs/scaling.md): what the
 * ranks send each other (chunks, hazard cells, summaries) comes back the same, and
 * mpirun with build/mpi/rockfall ($ROCKFALL_MPI_BIN) writes exactly the rows of a
 * one-process run and survives a killed rank.  The cases that need mpirun are skipped,
 * with a note, where it or the MPI build is missing. */
#include <errno.h>
#include <dirent.h>
#include <signal.h>
#include <sqlite3.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "base/qsum.h"
#include "run/hazard.h"
#include "run/montecarlo_private.h"
#include "db_test_util.h"
#include "test.h"

#define MPI_PROJECT "projects/noto/noto-3.3.yaml" /* releases, trees, barrier, control line */

static uint64_t lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return *s >> 33;
}

/* ---- the bytes the ranks send ---------------------------------------------------- */

/* A summary decoded from its bytes encodes to the same bytes and merges as the original;
 * cut short, or with its values out of order, it is refused. */
TEST(mpi_qsum_decode_gives_back_the_same_summary)
{
    static unsigned char a[65536], b[65536];
    size_t sizes[] = {0, 1, 5, RF_QSUM_EXACT, RF_QSUM_EXACT + 1, 5000};
    uint64_t st = 777;
    for (size_t k = 0; k < sizeof sizes / sizeof *sizes; k++) {
        rf_qsum s = {0}, other = {0};
        for (size_t i = 0; i < sizes[k]; i++)
            ENSURE(rf_qsum_add(&s, &RF_HAZARD_ENERGY_SCALE,
                               (float)((double)(lcg(&st) % 100000) * 0.0731)) == 0);
        for (int i = 0; i < 40; i++)
            ENSURE(rf_qsum_add(&other, &RF_HAZARD_ENERGY_SCALE, 2.385f * (float)i) == 0);
        size_t la = rf_qsum_encode(&s, a, sizeof a), used = 0;
        ENSURE(la <= sizeof a);
        rf_qsum d;
        ENSURE(rf_qsum_decode(&d, a, la, &used) == 0 && used == la);
        ENSURE(rf_qsum_encode(&d, b, sizeof b) == la && memcmp(a, b, la) == 0);
        /* merged into another summary: the same as merging the original */
        rf_qsum m1 = {0}, m2 = {0};
        ENSURE(rf_qsum_merge(&m1, &other, &RF_HAZARD_ENERGY_SCALE) == 0);
        ENSURE(rf_qsum_merge(&m2, &other, &RF_HAZARD_ENERGY_SCALE) == 0);
        ENSURE(rf_qsum_merge(&m1, &s, &RF_HAZARD_ENERGY_SCALE) == 0);
        ENSURE(rf_qsum_merge(&m2, &d, &RF_HAZARD_ENERGY_SCALE) == 0);
        size_t l1 = rf_qsum_encode(&m1, a, sizeof a), l2 = rf_qsum_encode(&m2, b, sizeof b);
        ENSURE_MSG(l1 == l2 && memcmp(a, b, l1) == 0, "%zu values: merges differ", sizes[k]);
        /* every shorter prefix is refused */
        la = rf_qsum_encode(&s, a, sizeof a);
        for (size_t cut = 0; cut < la; cut += 1 + cut / 8) {
            rf_qsum bad;
            ENSURE_MSG(rf_qsum_decode(&bad, a, cut, &used) != 0, "%zu of %zu bytes accepted", cut,
                       la);
            ENSURE(bad.n == 0 && !bad.v && !bad.bins);
        }
        rf_qsum_free(&s), rf_qsum_free(&other), rf_qsum_free(&d);
        rf_qsum_free(&m1), rf_qsum_free(&m2);
    }
    /* exact values out of order */
    rf_qsum s = {0}, bad;
    ENSURE(rf_qsum_add(&s, &RF_HAZARD_ENERGY_SCALE, 1.5f) == 0);
    ENSURE(rf_qsum_add(&s, &RF_HAZARD_ENERGY_SCALE, 7.25f) == 0);
    size_t la = rf_qsum_encode(&s, a, sizeof a), used;
    unsigned char t[4];
    memcpy(t, a + 12, 4), memcpy(a + 12, a + 16, 4), memcpy(a + 16, t, 4);
    ENSURE(rf_qsum_decode(&bad, a, la, &used) != 0);
    rf_qsum_free(&s);
}

/* A grid of 2 m cells over [0, 40] x [0, 30]. */
static void grid(rf_hazard *h)
{
    rf_terrain t;
    memset(&t, 0, sizeof t);
    t.xmin = 0, t.xmax = 40, t.ymin = 0, t.ymax = 30;
    ENSURE(rf_hazard_init(h, &t, 2.0) == 0);
}

/* n trajectories of a few samples each, drawn from st. */
static void trajectories(rf_hazard *h, int n, uint64_t *st)
{
    for (int k = 0; k < n; k++) {
        rf_hazard_begin(h);
        double x = (double)(lcg(st) % 4000) * 0.01, y = 29.5;
        for (int i = 0; i < 12; i++, y -= 2.3)
            rf_hazard_sample(h, x + 0.37 * i, y, (double)(lcg(st) % 9000) * 0.173,
                             (double)(lcg(st) % 500) * 0.011);
        ENSURE(rf_hazard_end(h) == 0);
    }
}

/* Every cell of a, b as the same bytes. */
static void ensure_same_maps(const rf_hazard *a, const rf_hazard *b)
{
    static unsigned char ba[65536], bb[65536];
    ENSURE(a->ncells == b->ncells);
    for (size_t iy = 0; iy < a->ny; iy++)
        for (size_t ix = 0; ix < a->nx; ix++) {
            const rf_hazard_cell *ca = rf_hazard_at(a, ix, iy), *cb = rf_hazard_at(b, ix, iy);
            ENSURE((ca == NULL) == (cb == NULL));
            if (!ca)
                continue;
            size_t la = rf_qsum_encode(&ca->energy_kj, ba, sizeof ba);
            size_t lb = rf_qsum_encode(&cb->energy_kj, bb, sizeof bb);
            ENSURE_MSG(la == lb && memcmp(ba, bb, la) == 0, "cell %zu %zu energy", ix, iy);
            la = rf_qsum_encode(&ca->height_m, ba, sizeof ba);
            lb = rf_qsum_encode(&cb->height_m, bb, sizeof bb);
            ENSURE_MSG(la == lb && memcmp(ba, bb, la) == 0, "cell %zu %zu height", ix, iy);
        }
}

/* A rank's map sent in small batches and merged gives the cells of merging the map
 * itself; bytes that are not cells of this grid are refused. */
TEST(mpi_hazard_cells_sent_in_batches_merge_as_the_map)
{
    rf_hazard mine, theirs, direct, sent;
    grid(&mine), grid(&theirs), grid(&direct), grid(&sent);
    uint64_t st = 99;
    trajectories(&theirs, 300, &st); /* past the exact limit in the busy cells */
    uint64_t st2 = 5;
    trajectories(&mine, 40, &st2);
    st2 = 5;
    trajectories(&direct, 40, &st2);
    st2 = 5;
    trajectories(&sent, 40, &st2);
    ENSURE(rf_hazard_merge(&direct, &theirs) == 0);
    static unsigned char buf[16384];
    size_t next = 0;
    int batches = 0;
    while (next < theirs.ncells) {
        size_t n = rf_hazard_pack(&theirs, &next, buf, sizeof buf);
        ENSURE(n > 0 && n <= sizeof buf);
        ENSURE(rf_hazard_unpack_merge(&sent, buf, n) == 0);
        batches++;
    }
    ENSURE_MSG(batches > 1, "%d batch", batches);
    ensure_same_maps(&direct, &sent);
    /* a cut batch, and a cell beyond the grid */
    next = 0;
    size_t n = rf_hazard_pack(&theirs, &next, buf, sizeof buf);
    ENSURE(rf_hazard_unpack_merge(&mine, buf, n - 3) != 0);
    unsigned char far[12] = {0xff, 0xff, 0, 0}; /* cell 65535, then an empty summary */
    ENSURE(rf_hazard_unpack_merge(&mine, far, sizeof far) != 0);
    rf_hazard_free(&mine), rf_hazard_free(&theirs), rf_hazard_free(&direct);
    rf_hazard_free(&sent);
}

/* A chunk packed and unpacked holds the same rows; bytes cut short, or whose row ranges
 * leave the arrays, are refused. */
TEST(mpi_chunk_packed_and_unpacked_holds_the_same_rows)
{
    rf_chunk c;
    memset(&c, 0, sizeof c);
    c.first = 3 * RF_CHUNK_SIZE, c.n = 3;
    c.traj = calloc(3, sizeof *c.traj);
    c.npaths = 5, c.paths = calloc(5, sizeof *c.paths);
    c.nicpts = 2, c.icpts = calloc(2, sizeof *c.icpts);
    c.ntrees = 1, c.trees = calloc(1, sizeof *c.trees);
    ENSURE(c.traj && c.paths && c.icpts && c.trees);
    /* rows: 0 has paths 0-1, both crossings and the tree hit; 1 nothing; 2 paths 2-4 */
    static const size_t ranges[3][6] = {{0, 2, 0, 2, 0, 1}, {2, 2, 2, 2, 1, 1}, {2, 5, 2, 2, 1, 1}};
    for (int k = 0; k < 3; k++) {
        rf_traj_out *o = &c.traj[k];
        o->release = (size_t)k;
        o->idx = 17 + k;
        o->rec.reason = RF_END_STOPPED;
        o->rec.max_energy_kj = 2385.125 * k;
        o->path_begin = ranges[k][0], o->path_end = ranges[k][1];
        o->icpt_begin = ranges[k][2], o->icpt_end = ranges[k][3];
        o->tree_begin = ranges[k][4], o->tree_end = ranges[k][5];
    }
    for (int i = 0; i < 5; i++)
        c.paths[i].t_s = 0.125 * i, c.paths[i].p.z = 101.5 - i;
    c.icpts[1].energy_kj = 1867.25, c.icpts[1].measure = 2, c.icpts[1].outcome = RF_OUT_STOPPED;
    c.trees[0].energy_lost_kj = 12.5;
    size_t n = rf_chunk_packed_size(&c);
    unsigned char *buf = malloc(n);
    ENSURE(buf);
    rf_chunk_pack(&c, buf);
    rf_chunk d;
    ENSURE(rf_chunk_unpack(&d, buf, n) == 0);
    ENSURE(d.first == c.first && d.n == 3 && d.npaths == 5 && d.nicpts == 2 && d.ntrees == 1);
    ENSURE(d.oom == 0 && d.done == 0);
    ENSURE(memcmp(d.traj, c.traj, 3 * sizeof *c.traj) == 0);
    ENSURE(memcmp(d.paths, c.paths, 5 * sizeof *c.paths) == 0);
    ENSURE(memcmp(d.icpts, c.icpts, 2 * sizeof *c.icpts) == 0);
    ENSURE(memcmp(d.trees, c.trees, sizeof *c.trees) == 0);
    rf_chunk_clear(&d);
    for (size_t cut = 0; cut < n; cut += 1 + cut / 4)
        ENSURE_MSG(rf_chunk_unpack(&d, buf, cut) != 0 && d.traj == NULL, "%zu of %zu bytes", cut,
                   n);
    /* a row whose paths run past the chunk's */
    c.traj[2].path_end = 6;
    rf_chunk_pack(&c, buf);
    ENSURE(rf_chunk_unpack(&d, buf, n) != 0 && d.traj == NULL);
    free(buf);
    rf_chunk_clear(&c);
}

/* ---- mpirun ------------------------------------------------------------------------ */

/* The MPI build and mpirun, or NULL (after a note) when either is missing. */
static const char *mpi_bin(void)
{
    const char *bin = getenv("ROCKFALL_MPI_BIN");
    if (!bin || access(bin, X_OK) != 0 || system("command -v mpirun >/dev/null 2>&1") != 0) {
        printf("    skipped: needs mpirun and the MPI build (make mpi; $ROCKFALL_MPI_BIN)\n");
        return NULL;
    }
    /* CI runs as root, which OpenMPI refuses unless told */
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    return bin;
}

static void tables_of(const char *db, char *out, size_t cap)
{
    sqlite3 *h;
    ENSURE(sqlite3_open_v2(db, &h, SQLITE_OPEN_READONLY, NULL) == SQLITE_OK);
    dbt_tables_hash(h, out, cap);
    sqlite3_close(h);
}

/* The tables of `project` (run with `args`) by one process on one thread and by three
 * ranks of two threads each (all but when the run started and finished), into one.db
 * and three.db; both exit with `status`. */
static void one_and_three(const char *bin, const char *project, const char *args, int status,
                          char *h1, char *h3, size_t cap)
{
    char one[600], three[600], cmd[4096], out[65536];
    snprintf(one, sizeof one, "%s", rf_test_path("one.db"));
    snprintf(three, sizeof three, "%s", rf_test_path("three.db"));
    unlink(one), unlink(three);
    snprintf(cmd, sizeof cmd, "run %s %s --threads 1 -q -o %s", project, args, one);
    int rc1 = rf_test_rockfall(cmd, out, sizeof out);
    ENSURE_MSG(rc1 == status, "one process: %d: %s", rc1, out);
    snprintf(cmd, sizeof cmd,
             "mpirun --oversubscribe -n 3 %s run %s %s --threads 2 -q -o %s 2>&1", bin, project,
             args, three);
    FILE *f = popen(cmd, "r");
    ENSURE(f);
    size_t got = fread(out, 1, sizeof out - 1, f);
    out[got] = '\0';
    int st = pclose(f);
    /* mpirun passes rank 0's status on */
    ENSURE_MSG(WIFEXITED(st) && WEXITSTATUS(st) == status, "mpirun %d: %s", WEXITSTATUS(st), out);
    tables_of(one, h1, cap);
    tables_of(three, h3, cap);
    printf("%s", h3);
    ENSURE_MSG(strcmp(h1, h3) == 0, "one thread:\n%s\nthree ranks:\n%s", h1, h3);
}

/* Three ranks (two threads each) give every table the rows of one process on one
 * thread, but for when the run started and finished: trajectories, paths, interceptions,
 * tree hits, hazard cells, and the checks of the project's rules; and for a mask
 * release, each trajectory's source cell. */
TEST(mpi_three_ranks_write_the_rows_of_one_thread)
{
    const char *bin = mpi_bin();
    if (!bin)
        return;
    static char h1[16384], h3[16384];
    /* 5 releases of 300: 1 500 trajectories, 6 chunks handed out among the ranks; the
     * layout fails one check (exit status 1) */
    one_and_three(bin, MPI_PROJECT, "--count 300", 1, h1, h3, sizeof h1);
    /* what is compared holds the rows that could differ */
    ENSURE(strstr(h1, "trajectories 1500 ") && strstr(h1, "\nruns 1 "));
    /* and where each ran: one rank of one thread, three of two */
    sqlite3 *h;
    ENSURE(sqlite3_open_v2(rf_test_path("one.db"), &h, SQLITE_OPEN_READONLY, NULL) == SQLITE_OK);
    ENSURE(dbt_int(h, "SELECT count(*) FROM runs WHERE ranks = 1 AND threads = 1 AND"
                      " length(host) > 0") == 1);
    sqlite3_close(h);
    ENSURE(sqlite3_open_v2(rf_test_path("three.db"), &h, SQLITE_OPEN_READONLY, NULL) ==
           SQLITE_OK);
    ENSURE(dbt_int(h, "SELECT count(*) FROM runs WHERE ranks = 3 AND threads = 2") == 1);
    sqlite3_close(h);
    ENSURE(!strstr(h1, "hazard_cells 0 ") && !strstr(h1, "tree_hits 0 ") &&
           !strstr(h1, "interceptions 0 ") && !strstr(h1, "checks 0 "));
    /* 3 source cells of 100: 2 chunks */
    one_and_three(bin, "tests/data/project/release_cells.yaml", "--count 100", 0, h1, h3,
                  sizeof h1);
    ENSURE(strstr(h1, "trajectories 300 "));
    ENSURE(sqlite3_open_v2(rf_test_path("three.db"), &h, SQLITE_OPEN_READONLY, NULL) == SQLITE_OK);
    ENSURE(dbt_int(h, "SELECT count(*) FROM trajectories WHERE source_cell = idx / 100") == 300);
    sqlite3_close(h);
    /* keeping the maps only: the same rows too (no verdict: exit status 0) */
    one_and_three(bin, MPI_PROJECT, "--count 300 --store maps", 0, h1, h3, sizeof h1);
    ENSURE(strstr(h1, "tree_hits 0 ") && !strstr(h1, "hazard_cells 0 "));
}

/* The pid of the process of `rank` that mpirun (pid parent) started, or 0. */
static pid_t rank_pid(pid_t parent, int rank)
{
    char want[64];
    snprintf(want, sizeof want, "OMPI_COMM_WORLD_RANK=%d", rank);
    DIR *d = opendir("/proc");
    ENSURE(d);
    pid_t found = 0;
    struct dirent *e;
    while (!found && (e = readdir(d)) != NULL) {
        pid_t pid = (pid_t)atol(e->d_name);
        if (pid <= 0)
            continue;
        char path[64], stat[512];
        snprintf(path, sizeof path, "/proc/%d/stat", (int)pid);
        FILE *f = fopen(path, "r");
        if (!f)
            continue;
        size_t n = fread(stat, 1, sizeof stat - 1, f);
        fclose(f);
        stat[n] = '\0';
        const char *close = strrchr(stat, ')');
        int ppid = 0;
        if (!close || sscanf(close + 2, "%*c %d", &ppid) != 1 || ppid != (int)parent)
            continue;
        snprintf(path, sizeof path, "/proc/%d/environ", (int)pid);
        char *env = NULL;
        size_t cap = 0;
        f = fopen(path, "r");
        if (!f)
            continue;
        ssize_t len;
        while ((len = getdelim(&env, &cap, '\0', f)) > 0)
            if (strcmp(env, want) == 0)
                found = pid;
        free(env);
        fclose(f);
    }
    closedir(d);
    return found;
}

/* Trajectories of run `run` in the file (0 while it has none, or cannot be read). */
static long run_rows(const char *db, int run)
{
    sqlite3 *h;
    long n = 0;
    if (sqlite3_open_v2(db, &h, SQLITE_OPEN_READONLY, NULL) == SQLITE_OK) {
        sqlite3_busy_timeout(h, 2000);
        sqlite3_stmt *st;
        if (sqlite3_prepare_v2(h, "SELECT count(*) FROM trajectories WHERE run_id = ?1", -1,
                               &st, NULL) == SQLITE_OK &&
            sqlite3_bind_int(st, 1, run) == SQLITE_OK && sqlite3_step(st) == SQLITE_ROW)
            n = (long)sqlite3_column_int64(st, 0);
        sqlite3_finalize(st);
    }
    sqlite3_close(h);
    return n;
}

/* Run 1's rows in every table that has a run_id (and the path points of its
 * trajectories). */
static void run1_rows(const char *db, char *out, size_t cap)
{
    static const char *const q[] = {
        "SELECT id, project, seed, status, n_trajectories FROM runs WHERE id = 1",
        "SELECT * FROM releases WHERE run_id = 1", "SELECT * FROM measures WHERE run_id = 1",
        "SELECT * FROM trajectories WHERE run_id = 1 ORDER BY id",
        "SELECT * FROM interceptions WHERE run_id = 1 ORDER BY id",
        "SELECT * FROM tree_hits WHERE run_id = 1 ORDER BY id",
        "SELECT * FROM hazard_cells WHERE run_id = 1 ORDER BY ix, iy",
        "SELECT p.* FROM path_points p JOIN trajectories t ON t.id = p.trajectory_id "
        "WHERE t.run_id = 1 ORDER BY p.trajectory_id, p.seq"};
    sqlite3 *h;
    ENSURE(sqlite3_open_v2(db, &h, SQLITE_OPEN_READONLY, NULL) == SQLITE_OK);
    size_t at = 0;
    for (size_t k = 0; k < sizeof q / sizeof *q; k++) {
        long n;
        unsigned long long x = dbt_rows_hash(h, q[k], &n);
        at += (size_t)snprintf(out + at, cap - at, "%zu %ld %016llx\n", k, n, x);
        ENSURE(at < cap);
    }
    sqlite3_close(h);
}

/* mpirun of three ranks on a million trajectories (minutes) into db, started in the
 * background; returns mpirun's pid once that run (number `run` in the file) has at
 * least two chunks written (their number in *rows). */
static pid_t start_long_run(const char *bin, const char *db, int run, long *rows)
{
    pid_t mp = fork();
    ENSURE(mp >= 0);
    if (mp == 0) {
        /* mpirun's own report of the job's end is expected: not shown */
        if (!freopen("/dev/null", "w", stdout) || !freopen("/dev/null", "w", stderr))
            _exit(126);
        /* the grace mpirun gives the ranks between SIGTERM and SIGKILL: 1 s by default,
         * 5 here, so that a loaded machine cannot fail the test */
        execlp("mpirun", "mpirun", "--oversubscribe", "--mca", "odls_base_sigkill_timeout", "5",
               "-n", "3", bin, "run", MPI_PROJECT, "--count", "200000", "--threads", "1", "-q",
               "-o", db, (char *)NULL);
        _exit(127);
    }
    struct timespec tick = {0, 50 * 1000 * 1000};
    for (int i = 0; i < 1200 && (*rows = run_rows(db, run)) < 2 * RF_CHUNK_SIZE; i++)
        nanosleep(&tick, NULL);
    return mp;
}

/* mpirun's wait status, once it has ended (at most 60 s). */
static int wait_for(pid_t mp)
{
    struct timespec tick = {0, 50 * 1000 * 1000};
    int st = 0;
    pid_t w = 0;
    for (int i = 0; i < 1200 && (w = waitpid(mp, &st, WNOHANG)) == 0; i++)
        nanosleep(&tick, NULL);
    if (w == 0) {
        kill(mp, SIGKILL);
        waitpid(mp, &st, 0);
        ENSURE_MSG(0, "mpirun still running 60 s after the signal");
    }
    return st;
}

/* kill -9 of one rank in the middle of a run: the job ends, the file passes
 * integrity_check, the run is not complete and the run before it is intact. */
TEST(mpi_rank_killed_mid_run_leaves_the_file_whole)
{
    const char *bin = mpi_bin();
    if (!bin)
        return;
    char db[600], cmd[4096], out[16384];
    snprintf(db, sizeof db, "%s", rf_test_path("killed.db"));
    snprintf(cmd, sizeof cmd, "run " MPI_PROJECT " --count 40 -q -o %s", db);
    int rc1 = rf_test_rockfall(cmd, out, sizeof out);
    ENSURE_MSG(rc1 == 0 || rc1 == 1, "%s", out); /* run 1: complete (checked) */
    static char before[4096], after[4096];
    run1_rows(db, before, sizeof before);
    long rows = 0;
    pid_t mp = start_long_run(bin, db, 2, &rows);
    pid_t victim = rank_pid(mp, 1);
    ENSURE_MSG(rows >= 2 * RF_CHUNK_SIZE && victim > 0, "%ld rows, rank 1 pid %d", rows,
               (int)victim);
    ENSURE(kill(victim, SIGKILL) == 0);
    int st = wait_for(mp);
    ENSURE(!(WIFEXITED(st) && WEXITSTATUS(st) == 0));
    sqlite3 *h;
    ENSURE(sqlite3_open(db, &h) == SQLITE_OK); /* read-write: replays a WAL left behind */
    sqlite3_stmt *q;
    ENSURE(sqlite3_prepare_v2(h, "PRAGMA integrity_check", -1, &q, NULL) == SQLITE_OK);
    ENSURE(sqlite3_step(q) == SQLITE_ROW);
    ENSURE_MSG(strcmp((const char *)sqlite3_column_text(q, 0), "ok") == 0, "%s",
               sqlite3_column_text(q, 0));
    sqlite3_finalize(q);
    ENSURE(dbt_int(h, "SELECT count(*) FROM runs WHERE id = 2 AND status <> 'complete'") == 1);
    long n2 = (long)dbt_int(h, "SELECT count(*) FROM trajectories WHERE run_id = 2");
    ENSURE_MSG(n2 >= rows && n2 < 1000000 && n2 % RF_CHUNK_SIZE == 0, "%ld rows of run 2", n2);
    sqlite3_close(h);
    run1_rows(db, after, sizeof after);
    ENSURE_MSG(strcmp(before, after) == 0, "run 1 before:\n%s\nafter:\n%s", before, after);
}

/* A rank that cannot load the project (here: given another path, mpirun's MPMD form)
 * tells rank 0, which prints its error, marks the run failed and ends the job. */
TEST(mpi_rank_that_cannot_load_the_project_fails_the_run)
{
    const char *bin = mpi_bin();
    if (!bin)
        return;
    char db[600], cmd[4096], out[65536];
    snprintf(db, sizeof db, "%s", rf_test_path("lost.db"));
    snprintf(cmd, sizeof cmd,
             "mpirun --oversubscribe -n 2 %s run " MPI_PROJECT " --count 20000 -q -o %s :"
             " -n 1 %s run %s/missing.yaml -q -o %s 2>&1",
             bin, db, bin, rf_test_tmpdir(), db);
    FILE *f = popen(cmd, "r");
    ENSURE(f);
    size_t got = fread(out, 1, sizeof out - 1, f);
    out[got] = '\0';
    int st = pclose(f);
    ENSURE_MSG(WIFEXITED(st) && WEXITSTATUS(st) == 2, "mpirun %d: %s", WEXITSTATUS(st), out);
    ENSURE_MSG(strstr(out, "error: rank 2: cannot open"), "%s", out);
    sqlite3 *h;
    ENSURE(sqlite3_open(db, &h) == SQLITE_OK);
    ENSURE(dbt_int(h, "SELECT count(*) FROM runs WHERE status = 'failed'") == 1);
    ENSURE(dbt_int(h, "SELECT count(*) FROM runs") == 1);
    sqlite3_close(h);
}

/* Rank 0 prints the progress as lines (mpirun forwards its stderr, not a terminal): the
 * trajectories written of all, their rate and the time left; the other ranks print
 * nothing. */
TEST(mpi_progress_lines_come_from_rank_0)
{
    const char *bin = mpi_bin();
    if (!bin)
        return;
    char cmd[4096], out[65536];
    snprintf(cmd, sizeof cmd,
             "mpirun --oversubscribe -n 3 %s run " MPI_PROJECT " --count 60 -o %s 2>&1", bin,
             rf_test_path("progress.db"));
    FILE *f = popen(cmd, "r");
    ENSURE(f);
    size_t got = fread(out, 1, sizeof out - 1, f);
    out[got] = '\0';
    pclose(f);
    const char *line = strstr(out, "300 / 300 trajectories, ");
    ENSURE_MSG(line && strstr(line, " per second, 0:00 left\n"), "%s", out);
    ENSURE_MSG(strstr(line + 1, "300 / 300 trajectories") == NULL, "%s", out); /* once */
    const char *summary = strstr(out, "run 1 of 'noto-3.3' into");
    ENSURE_MSG(summary && !strstr(summary + 1, "run 1 of 'noto-3.3' into"), "%s", out);
}

/* Ctrl-C of mpirun (SIGINT, which it passes to every rank as SIGTERM, killing them after
 * its grace): rank 0 marks the run failed with the trajectories written and closes
 * the file, no -wal or -shm left beside it, as a one-process run interrupted does. */
TEST(mpi_interrupted_run_is_failed_and_closed)
{
    const char *bin = mpi_bin();
    if (!bin)
        return;
    char db[600], wal[700];
    snprintf(db, sizeof db, "%s", rf_test_path("interrupted.db"));
    snprintf(wal, sizeof wal, "%s-wal", db);
    long rows = 0;
    pid_t mp = start_long_run(bin, db, 1, &rows);
    ENSURE_MSG(rows >= 2 * RF_CHUNK_SIZE, "%ld rows", rows);
    ENSURE(kill(mp, SIGINT) == 0);
    int st = wait_for(mp);
    ENSURE(!(WIFEXITED(st) && WEXITSTATUS(st) == 0));
    ENSURE_MSG(access(wal, F_OK) != 0, "%s left behind", wal);
    sqlite3 *h;
    ENSURE(sqlite3_open(db, &h) == SQLITE_OK);
    ENSURE(dbt_int(h, "SELECT count(*) FROM runs WHERE status = 'failed'") == 1);
    long n = (long)dbt_int(h, "SELECT n_trajectories FROM runs");
    ENSURE_MSG(n == dbt_int(h, "SELECT count(*) FROM trajectories") && n >= rows &&
                   n % RF_CHUNK_SIZE == 0,
               "n_trajectories %ld", n);
    sqlite3_close(h);
}
