/* records.c - the names of the enumerated values of a simulation's rows, as they
 * appear in the results database. */
#include "rockfall/records.h"

#include <assert.h>
#include <string.h>

const char *rf_stop_reason_name(rf_stop_reason r)
{
    switch (r) {
    case RF_END_REST: return "rest";
    case RF_END_EXITED: return "exited";
    case RF_END_STOPPED: return "stopped";
    case RF_END_MAX_TIME: return "max_time";
    }
    assert(!"unknown stop reason");
    return "?";
}

const char *rf_outcome_name(rf_outcome o)
{
    switch (o) {
    case RF_OUT_STOPPED: return "stopped";
    case RF_OUT_OVERTOPPED: return "overtopped";
    case RF_OUT_BROKE_THROUGH: return "broke_through";
    case RF_OUT_PASSED: return "passed";
    }
    assert(!"unknown outcome");
    return "?";
}

rf_outcome rf_outcome_from_name(const char *text)
{
    for (int o = RF_OUT_STOPPED; text && o <= RF_OUT_PASSED; o++)
        if (!strcmp(text, rf_outcome_name((rf_outcome)o)))
            return (rf_outcome)o;
    return RF_OUT_PASSED;
}
