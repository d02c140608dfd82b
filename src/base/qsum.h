/* qsum.h - a bounded summary of a multiset of values, for quantiles: the values
 * themselves up to RF_QSUM_EXACT of them (kept sorted), then counts in fixed
 * logarithmic bins (RF_QSUM_PER_OCTAVE per octave, edges 2^(k/32) that do not depend on
 * the data) over a scale [2^lo_exp, 2^hi_exp), with a bin for zero and below, one
 * between zero and the scale (each keeps its largest value) and one above the scale.
 * The largest value and the count are exact.
 *
 * The summary is a function of the multiset alone: adding the values in any order, or
 * merging summaries of any partition of them in any order, gives the same summary, to
 * the byte (rf_qsum_encode).  Values are ordered by their IEEE-754 total order (-0
 * before +0, NaN after +inf), so ties and signs cannot depend on the order either.
 *
 * Quantiles are nearest-rank: exact while the summary holds the values; from the bins,
 * within a relative 2^(1/64) - 1 (1.09 %) of the exact nearest-rank value on the scale,
 * within 2^lo_exp absolutely below it (exact for zero), and the largest value above it. */
#ifndef ROCKFALL_QSUM_H
#define ROCKFALL_QSUM_H

#include <stddef.h>
#include <stdint.h>

#define RF_QSUM_EXACT 128     /* values held exactly, sorted */
#define RF_QSUM_PER_OCTAVE 32 /* bins per octave: edges 2^(1/32) apart */

/* The bins' scale: [2^lo_exp, 2^hi_exp). */
typedef struct rf_qsum_scale {
    int lo_exp, hi_exp;
} rf_qsum_scale;

typedef struct rf_qsum {
    uint64_t n;       /* values in all */
    float max;        /* the largest (total order); meaningless while n == 0 */
    float low_max[2]; /* binned: the largest value <= 0, and in (0, 2^lo_exp) (-inf: none) */
    float *v;         /* exact (n <= RF_QSUM_EXACT): the values, ascending */
    uint32_t cap;     /* room in v */
    uint32_t nb;      /* binned: counts of the bins b0 .. b0 + nb - 1: 0 zero and below, */
    int32_t b0;       /* 1 below the scale, 2 .. the scale's bins, then the one above */
    uint64_t *bins;   /* NULL while exact */
} rf_qsum;

/* 0, or -1 when memory ran out (the summary is then unchanged). */
int rf_qsum_add(rf_qsum *s, const rf_qsum_scale *sc, float v);
/* Adds every value of `from` to `into`; 0 or -1 (out of memory: `into` may hold some of
 * them; free it). */
int rf_qsum_merge(rf_qsum *into, const rf_qsum *from, const rf_qsum_scale *sc);
/* The nearest-rank q-quantile (0 < q <= 1); NaN for no value. */
double rf_qsum_quantile(const rf_qsum *s, const rf_qsum_scale *sc, double q);
/* The summary's canonical bytes (writes at most cap, returns the length). */
size_t rf_qsum_encode(const rf_qsum *s, unsigned char *buf, size_t cap);
/* The summary whose canonical bytes begin buf (len of them there), into an empty s;
 * *used gets their length.  0, or -1 when they are not a summary's (or memory ran
 * out): s is then empty. */
int rf_qsum_decode(rf_qsum *s, const unsigned char *buf, size_t len, size_t *used);
/* Bytes of memory the summary holds (its arrays). */
size_t rf_qsum_bytes(const rf_qsum *s);
void rf_qsum_free(rf_qsum *s);

#endif
