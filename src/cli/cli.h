/* cli.h - what the command files of the command line share (main.c). */
#ifndef ROCKFALL_CLI_H
#define ROCKFALL_CLI_H

enum { EXIT_OK = 0, EXIT_CHECK_FAILED = 1, EXIT_BAD_INPUT = 2 };

/* Prints "rockfall CMD: " fmt (with arg) and where help is; returns EXIT_BAD_INPUT. */
int usage_error(const char *cmd, const char *fmt, const char *arg);
/* A whole number in [lo, hi]; 0 on success. */
int parse_long(const char *s, long lo, long hi, long *out);
/* A finite plain decimal number; 0 on success. */
int parse_double(const char *s, double *out);

/* The worker threads of `run` and `calibrate` without --threads: the processors online
 * (sysconf(_SC_NPROCESSORS_ONLN)), at least 1 and at most 256 (threads.c). */
long rf_cli_default_threads(void);

/* rockfall calibrate (calibrate.c). */
extern const char CALIBRATE_HELP[];
int cmd_calibrate(int argc, char **argv);

#endif
