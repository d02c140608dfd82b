/* names.c - an index of names (see names.h). */
#include "base/names.h"

#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static atomic_ullong probes;

unsigned long long rf_names_probes(void)
{
    return atomic_load_explicit(&probes, memory_order_relaxed);
}

/* FNV-1a, 64 bits. */
static uint64_t hash(const char *s)
{
    uint64_t h = 0xcbf29ce484222325u;
    for (const unsigned char *p = (const unsigned char *)s; *p; p++)
        h = (h ^ *p) * 0x100000001b3u;
    return h;
}

static int alloc_slots(rf_names *h, size_t cap)
{
    h->key = calloc(cap, sizeof *h->key);
    h->value = malloc(cap * sizeof *h->value);
    if (!h->key || !h->value) {
        free(h->key);
        free(h->value);
        h->key = NULL;
        h->value = NULL;
        return -1;
    }
    h->cap = cap;
    return 0;
}

int rf_names_init(rf_names *h, size_t expected)
{
    memset(h, 0, sizeof *h);
    size_t cap = 16;
    while (cap < 2 * expected && cap < SIZE_MAX / 4)
        cap *= 2;
    return alloc_slots(h, cap);
}

void rf_names_free(rf_names *h)
{
    free(h->key);
    free(h->value);
    memset(h, 0, sizeof *h);
}

/* The slot of name, or of the empty slot where it would go. */
static size_t slot_of(const rf_names *h, const char *name)
{
    size_t mask = h->cap - 1, i = (size_t)hash(name) & mask, n = 0;
    while (h->key[i] && strcmp(h->key[i], name)) {
        i = (i + 1) & mask;
        n++;
    }
    atomic_fetch_add_explicit(&probes, n + 1, memory_order_relaxed);
    return i;
}

size_t rf_names_find(const rf_names *h, const char *name)
{
    if (!h->cap)
        return RF_NAMES_ABSENT;
    size_t i = slot_of(h, name);
    return h->key[i] ? h->value[i] : RF_NAMES_ABSENT;
}

static int grow(rf_names *h)
{
    rf_names bigger;
    if (h->cap > SIZE_MAX / 4 || alloc_slots(&bigger, 2 * h->cap))
        return -1;
    bigger.n = h->n;
    for (size_t k = 0; k < h->cap; k++) {
        if (!h->key[k])
            continue;
        size_t i = slot_of(&bigger, h->key[k]);
        bigger.key[i] = h->key[k];
        bigger.value[i] = h->value[k];
    }
    rf_names_free(h);
    *h = bigger;
    return 0;
}

size_t rf_names_add(rf_names *h, const char *name, size_t value, int *oom)
{
    *oom = 0;
    if ((!h->cap || 2 * (h->n + 1) > h->cap) && (h->cap ? grow(h) : alloc_slots(h, 16))) {
        *oom = 1;
        return RF_NAMES_ABSENT;
    }
    size_t i = slot_of(h, name);
    if (h->key[i])
        return h->value[i];
    h->key[i] = name;
    h->value[i] = value;
    h->n++;
    return RF_NAMES_ABSENT;
}
