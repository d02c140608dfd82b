/* bench_threads.c - the throughput of whole runs against their worker threads (`make
 * bench`).
 *
 * Runs PROJECT (default: the rolling bench slope at 1 m, projects/bench/roll.yaml) with
 * COUNT trajectories (default 4 000) through rf_montecarlo_run into a temporary
 * GeoPackage at 1, 2, 4, ... threads up to the machine's cores online (and at that
 * number), the best of ROUNDS interleaved rounds each, and prints the trajectories per
 * second, the speed-up over one thread and the efficiency (speed-up over threads).
 * The rows are the same at every thread count (tests/test_run.c); the time includes
 * the writer, as a user's run does.
 *
 *   bench_threads [PROJECT [COUNT]] */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "rockfall/montecarlo.h"
#include "rockfall/project.h"
#include "results/store.h"
#include "base/util.h"

#define ROUNDS 2
#define MAX_ROWS 16

/* Seconds of one run at `threads` threads into a new file `db`; -1 on an error. */
static double run_once(const rf_project *p, const char *db, int threads)
{
    rf_error err;
    rf_store *s;
    remove(db);
    if (rf_store_open(db, &s, &err)) {
        rf_error_print(&err, stderr);
        return -1;
    }
    rf_run_options o = {.threads = threads};
    rf_run_summary sum;
    double t0 = rf_now_s();
    int rc = rf_montecarlo_run(p, s, &o, &sum, &err);
    double t = rf_now_s() - t0;
    if (rc)
        rf_error_print(&err, stderr);
    rf_store_close(s);
    remove(db);
    return rc ? -1 : t;
}

int main(int argc, char **argv)
{
    const char *path = argc > 1 ? argv[1] : "projects/bench/roll.yaml";
    long count = argc > 2 ? atol(argv[2]) : 4000;
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    if (count < 1 || cores < 1) {
        fprintf(stderr, "usage: bench_threads [PROJECT [COUNT >= 1]]\n");
        return 2;
    }
    rf_project p;
    rf_error err;
    if (rf_project_load(path, &p, &err)) {
        rf_error_print(&err, stderr);
        return 2;
    }
    for (size_t i = 0; i < p.nreleases; i++)
        p.releases[i].count = count;
    int threads[MAX_ROWS], nrows = 0;
    for (long t = 1; t < cores && nrows < MAX_ROWS - 1; t *= 2)
        threads[nrows++] = (int)t;
    threads[nrows++] = (int)(cores < 256 ? cores : 256);
    double best[MAX_ROWS];
    char db[64];
    snprintf(db, sizeof db, "/tmp/rf-bench-threads-%ld.gpkg", (long)getpid());
    for (int r = 0; r < ROUNDS; r++)
        for (int i = 0; i < nrows; i++) {
            fprintf(stderr, "threads: %d, round %d of %d ...\n", threads[i], r + 1, ROUNDS);
            double t = run_once(&p, db, threads[i]);
            if (t < 0) {
                rf_project_free(&p);
                return 1;
            }
            best[i] = r == 0 || t < best[i] ? t : best[i];
        }
    double n = (double)count * (double)p.nreleases;
    printf("Threads: %s, %.0f trajectories per run into a GeoPackage, %ld cores online; the "
           "best of %d interleaved rounds.\n\n"
           "| threads | traj/s | speed-up | efficiency |\n|---:|---:|---:|---:|\n",
           path, n, cores, ROUNDS);
    for (int i = 0; i < nrows; i++)
        printf("| %d | %.0f | %.2fx | %.0f %% |\n", threads[i], n / best[i], best[0] / best[i],
               100.0 * best[0] / best[i] / threads[i]);
    printf("\n");
    rf_project_free(&p);
    return 0;
}
