/* names.h - an index of names: each name once, found in a time independent of how many
 * there are (an open-addressing hash table).  The loaders check that item names are
 * distinct and find items by name through it, so that loading n items takes time
 * growing with n, not n^2. */
#ifndef ROCKFALL_NAMES_H
#define ROCKFALL_NAMES_H

#include <stddef.h>

typedef struct rf_names {
    const char **key; /* the names, not copied: they must outlive the index */
    size_t *value;
    size_t cap, n;    /* slots (a power of two, at least twice n), names */
} rf_names;

#define RF_NAMES_ABSENT ((size_t)-1)

/* An empty index with room for `expected` names before it grows; 0, or -1 when memory
 * runs out. */
int rf_names_init(rf_names *h, size_t expected);
void rf_names_free(rf_names *h);
/* The value of name, or RF_NAMES_ABSENT. */
size_t rf_names_find(const rf_names *h, const char *name);
/* Adds name with value unless it is there: RF_NAMES_ABSENT when added, else the value it
 * has already (the index is unchanged); *oom is set when memory runs out. */
size_t rf_names_add(rf_names *h, const char *name, size_t value, int *oom);

/* For tests: the slots every index has looked at since the program started (a name's
 * lookup costs about one when the index works). */
unsigned long long rf_names_probes(void);

#endif
