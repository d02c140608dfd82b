/* threads.c - the default number of worker threads of the command line. */
#include <unistd.h>

#include "cli/cli.h"

long rf_cli_default_threads(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    if (n < 1)
        return 1; /* unknown: one thread */
    return n > 256 ? 256 : n;
}
