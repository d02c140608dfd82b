/* bench_memory.c - peak memory of a run against its number of trajectories
 * (`make bench-memory`; a measurement, not a timing).
 *
 *   bench_memory [ROCKFALL [PROJECT [N1 N2 [THREADS]]]]
 *
 * Runs `ROCKFALL run PROJECT --count N -o TMP.db --threads THREADS` as a child process
 * for N1 and N2 trajectories per release (defaults: build/rockfall, the Noto project
 * without trees, 2 000 and 200 000, 2 threads) and reads each child's peak resident
 * set (wait4's ru_maxrss).  Prints both and their ratio; exits 1 when the larger run
 * needs more than 10 % over the smaller (memory that grows with the count). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#define FLAT_RATIO 1.10

/* The child's peak resident set (KiB) and its seconds; -1 when it failed. */
static long peak_kib(const char *bin, const char *project, const char *count,
                     const char *threads, const char *db, double *seconds)
{
    struct timeval t0, t1;
    fflush(stdout); /* not written twice by the child */
    gettimeofday(&t0, NULL);
    pid_t pid = fork();
    if (pid < 0)
        return -1;
    if (pid == 0) {
        if (!freopen("/dev/null", "w", stdout))
            _exit(127);
        execl(bin, bin, "run", project, "-o", db, "--count", count, "--threads", threads,
              (char *)NULL);
        _exit(127);
    }
    int status;
    struct rusage ru;
    if (wait4(pid, &status, 0, &ru) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
        return -1;
    gettimeofday(&t1, NULL);
    *seconds = (double)(t1.tv_sec - t0.tv_sec) + 1e-6 * (double)(t1.tv_usec - t0.tv_usec);
    return ru.ru_maxrss;
}

int main(int argc, char **argv)
{
    const char *bin = argc > 1 ? argv[1] : "build/rockfall";
    const char *project = argc > 2 ? argv[2] : "projects/noto/noto-3.1-no-trees.yaml";
    const char *counts[2] = {argc > 3 ? argv[3] : "2000", argc > 4 ? argv[4] : "200000"};
    const char *threads = argc > 5 ? argv[5] : "2";
    const char *tmp = getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp";
    char dir[512];
    snprintf(dir, sizeof dir, "%s/bench_memory.XXXXXX", tmp);
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 2;
    }
    long kib[2];
    printf("peak memory of `rockfall run %s --count N --threads %s`:\n", project, threads);
    for (int i = 0; i < 2; i++) {
        char db[600];
        snprintf(db, sizeof db, "%s/run%d.db", dir, i);
        double s = 0;
        kib[i] = peak_kib(bin, project, counts[i], threads, db, &s);
        if (kib[i] < 0) {
            fprintf(stderr, "bench_memory: the run of %s trajectories failed\n", counts[i]);
            return 2;
        }
        printf("  N = %-10s peak RSS %8.1f MiB  (%.1f s)\n", counts[i], (double)kib[i] / 1024.0,
               s);
        char side[640];
        for (int k = 0; k < 3; k++) {
            snprintf(side, sizeof side, "%s%s", db, k == 0 ? "" : k == 1 ? "-wal" : "-shm");
            remove(side);
        }
    }
    rmdir(dir);
    double ratio = (double)kib[1] / (double)kib[0];
    printf("ratio %.3f (at most %.2f: %s)\n", ratio, FLAT_RATIO,
           ratio <= FLAT_RATIO ? "flat" : "GROWS with the count");
    return ratio <= FLAT_RATIO ? 0 : 1;
}
