/* mpi.h - a run shared among MPI ranks (built only by `make mpi`, src/run/mpi.c;
 * docs/scaling.md).
 *
 * Rank 0 opens and writes the database, alone; it hands out chunks of trajectories
 * (montecarlo_private.h) on demand to every rank, its own worker threads included,
 * at most `ahead` chunks beyond the last one written, and writes the chunks in order as
 * they come back, so the rows are those of a one-process run.  Each other rank loads
 * the project (its terrain once, shared by its threads), asks for chunks while it has
 * fewer than twice its threads in hand, sends each filled chunk back, and at the end
 * sends its hazard map in batches of at most RF_MPI_BATCH bytes; rank 0 merges them
 * (the summaries depend only on the set of values: hazard.h).  Any failure ends the
 * whole job (MPI_Abort) after rank 0 has marked the run failed (a rank killed makes
 * mpirun send SIGTERM to the others, which rank 0 takes as an interrupt); rank 0 itself
 * killed leaves the run 'running' in a consistent file (the WAL journal). */
#ifndef ROCKFALL_MPI_H
#define ROCKFALL_MPI_H

#include "rockfall/error.h"
#include "rockfall/montecarlo.h"

struct rf_store;

#define RF_MPI_BATCH (1u << 20) /* bytes of hazard cells per message */

/* MPI_Init_thread (only the calling thread calls MPI); 0 or -1. */
int rf_mpi_init(int *argc, char ***argv);
int rf_mpi_rank(void);
int rf_mpi_size(void);
/* Ends this rank: after a failure, rank 0 (which has marked the run failed) aborts the
 * whole job with `status`, and any other rank tells rank 0 (unless it has already) and
 * waits to be ended; MPI_Finalize otherwise. */
void rf_mpi_end(int status);

/* Rank 0: the run (as rf_montecarlo_run). */
int rf_mpi_run(const rf_project *p, struct rf_store *s, const rf_run_options *o,
               rf_run_summary *sum, rf_error *err);
/* Ranks above 0: simulates the chunks rank 0 hands out on o->threads threads until
 * there are none left; 0, or -1 with err set (rank 0 was told). */
int rf_mpi_serve(const rf_project *p, const rf_run_options *o, rf_error *err);
/* Ranks above 0, when the project could not be loaded: tells rank 0 (which fails the
 * run with this message). */
void rf_mpi_report_failure(const rf_error *err);

#endif
