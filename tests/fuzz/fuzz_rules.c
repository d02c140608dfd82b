/* fuzz_rules.c - the rule file loader (rf_rules_load_text, in memory). */
#include "check/rules.h"
#include "fuzz_util.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    rf_rules r;
    rf_error err;
    if (rf_rules_load_text("fuzz-rules.yaml", (const char *)data, size, &r, &err) == 0)
        rf_rules_free(&r);
    return 0;
}
