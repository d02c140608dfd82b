/* qsum.c - the bounded quantile summary (qsum.h). */
#include "base/qsum.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/stats.h"

/* 2^(m/32) rounded to float, m = 0..31: the bin edges within an octave (exact
 * constants, so that a value's bin does not depend on a libm). */
static const float EDGE[RF_QSUM_PER_OCTAVE] = {
    0x1.000000p+0f, 0x1.059b0ep+0f, 0x1.0b5586p+0f, 0x1.11301ep+0f, 0x1.172b84p+0f,
    0x1.1d4874p+0f, 0x1.2387a6p+0f, 0x1.29e9e0p+0f, 0x1.306fe0p+0f, 0x1.371a74p+0f,
    0x1.3dea64p+0f, 0x1.44e086p+0f, 0x1.4bfdaep+0f, 0x1.5342b6p+0f, 0x1.5ab07ep+0f,
    0x1.6247ecp+0f, 0x1.6a09e6p+0f, 0x1.71f75ep+0f, 0x1.7a1148p+0f, 0x1.82589ap+0f,
    0x1.8ace54p+0f, 0x1.93737cp+0f, 0x1.9c4918p+0f, 0x1.a5503cp+0f, 0x1.ae89fap+0f,
    0x1.b7f770p+0f, 0x1.c199bep+0f, 0x1.cb720ep+0f, 0x1.d5818ep+0f, 0x1.dfc974p+0f,
    0x1.ea4afap+0f, 0x1.f50766p+0f};

/* 2^((m + 1/2)/32): the geometric middle of each bin, the value a bin stands for. */
static const double MID[RF_QSUM_PER_OCTAVE] = {
    1.0108892860517005, 1.0330248790212284, 1.0556451783605572, 1.0787607977571199,
    1.102382583307841,  1.1265216186082418, 1.1511892299529827, 1.1763969916502812,
    1.202156731452703,  1.22848053610687,   1.255380757024691,  1.2828700160787783,
    1.3109612115247644, 1.339667524053303,  1.3690024229745905, 1.3989796725383112,
    1.42961333839197,   1.460917794180647,  1.4929077282912648, 1.5255981507445384,
    1.559004400237837,  1.593142151342267,  1.6280274218573478, 1.6636765803267364,
    1.7001063537185235, 1.7373338352737062, 1.7753764925265212, 1.8142521755003989,
    1.8539791250833855, 1.8945759815869656, 1.9360617934922943, 1.978456026387951};

/* The IEEE-754 total order as an unsigned key. */
static uint32_t key(float v)
{
    uint32_t u;
    memcpy(&u, &v, sizeof u);
    return (u >> 31) ? ~u : (u | 0x80000000u);
}

static float maxf(float a, float b) { return key(b) > key(a) ? b : a; }

static int32_t scale_bins(const rf_qsum_scale *sc)
{
    return (sc->hi_exp - sc->lo_exp) * RF_QSUM_PER_OCTAVE;
}

/* The bin of v: 0 for zero and below (-0, negatives, -NaN), 1 between zero and the
 * scale, 2 + k on it, one past the scale's bins above it (and +inf, NaN). */
static int32_t bin_of(float v, const rf_qsum_scale *sc)
{
    if (key(v) <= key(0.0f))
        return 0;
    if (v < ldexpf(1.0f, sc->lo_exp))
        return 1;
    if (!(v < ldexpf(1.0f, sc->hi_exp)))
        return scale_bins(sc) + 2;
    int e;
    float mant = 2.0f * frexpf(v, &e); /* exact: v = mant 2^(e-1), mant in [1, 2) */
    int lo = 0, hi = RF_QSUM_PER_OCTAVE; /* the last edge <= mant */
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (EDGE[mid] <= mant)
            lo = mid;
        else
            hi = mid;
    }
    return 2 + (e - 1 - sc->lo_exp) * RF_QSUM_PER_OCTAVE + lo;
}

/* Widens the bins to hold bins lo .. hi-1 (their counts kept). */
static int cover(rf_qsum *s, int32_t lo, int32_t hi)
{
    if (s->bins) {
        if (lo >= s->b0 && hi <= s->b0 + (int32_t)s->nb)
            return 0;
        lo = lo < s->b0 ? lo : s->b0;
        hi = hi > s->b0 + (int32_t)s->nb ? hi : s->b0 + (int32_t)s->nb;
    }
    uint64_t *nb = calloc((size_t)(hi - lo), sizeof *nb);
    if (!nb)
        return -1;
    if (s->bins)
        memcpy(nb + (s->b0 - lo), s->bins, s->nb * sizeof *nb);
    free(s->bins);
    s->bins = nb;
    s->b0 = lo;
    s->nb = (uint32_t)(hi - lo);
    return 0;
}

/* Counts v in its bin (the bins cover it); the two bins below the scale keep their
 * largest values. */
static void bin_count(rf_qsum *s, int32_t b, float v)
{
    uint64_t *c = &s->bins[b - s->b0];
    if (b <= 1)
        s->low_max[b] = *c == 0 ? v : maxf(s->low_max[b], v);
    (*c)++;
}

/* From the values to the bins, which cover them already. */
static void to_bins(rf_qsum *s, const rf_qsum_scale *sc)
{
    s->low_max[0] = s->low_max[1] = -INFINITY;
    for (uint64_t i = 0; i < s->n; i++)
        bin_count(s, bin_of(s->v[i], sc), s->v[i]);
    free(s->v);
    s->v = NULL;
    s->cap = 0;
}

/* Inserts v among the sorted values (room for it made). */
static int exact_insert(rf_qsum *s, float v)
{
    if (s->n == s->cap) {
        uint32_t nc = s->cap ? 2 * s->cap : 4;
        if (nc > RF_QSUM_EXACT)
            nc = RF_QSUM_EXACT;
        float *nv = realloc(s->v, nc * sizeof *nv);
        if (!nv)
            return -1;
        s->v = nv;
        s->cap = nc;
    }
    uint32_t k = key(v), lo = 0, hi = (uint32_t)s->n; /* first value above v */
    while (lo < hi) {
        uint32_t mid = (lo + hi) / 2;
        if (key(s->v[mid]) <= k)
            lo = mid + 1;
        else
            hi = mid;
    }
    memmove(s->v + lo + 1, s->v + lo, (s->n - lo) * sizeof *s->v);
    s->v[lo] = v;
    s->n++;
    s->max = s->v[s->n - 1];
    return 0;
}

int rf_qsum_add(rf_qsum *s, const rf_qsum_scale *sc, float v)
{
    if (s->n < RF_QSUM_EXACT)
        return exact_insert(s, v);
    if (s->n == RF_QSUM_EXACT) {
        /* the first value past the exact ones: every value to the bins */
        int32_t b = bin_of(v, sc);
        int32_t lo = bin_of(s->v[0], sc), hi = bin_of(s->v[s->n - 1], sc) + 1;
        if (cover(s, lo < b ? lo : b, hi > b + 1 ? hi : b + 1))
            return -1;
        to_bins(s, sc);
    } else if (cover(s, bin_of(v, sc), bin_of(v, sc) + 1)) {
        return -1;
    }
    bin_count(s, bin_of(v, sc), v);
    s->max = maxf(s->max, v);
    s->n++;
    return 0;
}

/* Makes exact `s` binned (bins covering its values); 0 or -1 (unchanged). */
static int make_binned(rf_qsum *s, const rf_qsum_scale *sc)
{
    if (s->n > 0 &&
        cover(s, bin_of(s->v[0], sc), bin_of(s->v[s->n - 1], sc) + 1)) /* sorted */
        return -1;
    to_bins(s, sc);
    return 0;
}

int rf_qsum_merge(rf_qsum *into, const rf_qsum *from, const rf_qsum_scale *sc)
{
    if (from->n == 0)
        return 0;
    if (into->n + from->n <= RF_QSUM_EXACT) {
        for (uint64_t i = 0; i < from->n; i++)
            if (exact_insert(into, from->v[i]))
                return -1;
        return 0;
    }
    if (into->n <= RF_QSUM_EXACT && make_binned(into, sc))
        return -1;
    if (from->n > RF_QSUM_EXACT) {
        if (cover(into, from->b0, from->b0 + (int32_t)from->nb))
            return -1;
        for (int32_t b = from->b0; b <= 1 && b < from->b0 + (int32_t)from->nb; b++)
            if (from->bins[b - from->b0] > 0)
                into->low_max[b] = into->bins[b - into->b0] == 0
                                       ? from->low_max[b]
                                       : maxf(into->low_max[b], from->low_max[b]);
        for (uint32_t i = 0; i < from->nb; i++)
            into->bins[from->b0 - into->b0 + (int32_t)i] += from->bins[i];
    } else {
        for (uint64_t i = 0; i < from->n; i++) {
            int32_t b = bin_of(from->v[i], sc);
            if (cover(into, b, b + 1))
                return -1;
            bin_count(into, b, from->v[i]);
        }
    }
    into->max = into->n == 0 ? from->max : maxf(into->max, from->max);
    into->n += from->n;
    return 0;
}

double rf_qsum_quantile(const rf_qsum *s, const rf_qsum_scale *sc, double q)
{
    if (s->n <= RF_QSUM_EXACT)
        return rf_percentile_sorted(s->v, (size_t)s->n, q);
    double r = ceil(q * (double)s->n);
    uint64_t rank = r < 1.0 ? 1 : r > (double)s->n ? s->n : (uint64_t)r, cum = 0;
    uint32_t i = 0;
    while (i + 1 < s->nb && cum + s->bins[i] < rank)
        cum += s->bins[i++];
    int32_t b = s->b0 + (int32_t)i;
    if (b <= 1)
        return s->low_max[b];
    if (b > scale_bins(sc) + 1)
        return s->max;
    int32_t k = b - 2;
    double mid = ldexp(MID[k % RF_QSUM_PER_OCTAVE], sc->lo_exp + k / RF_QSUM_PER_OCTAVE);
    return mid > s->max ? s->max : mid;
}

static size_t put(unsigned char *buf, size_t cap, size_t at, uint64_t v, int bytes)
{
    for (int k = 0; k < bytes; k++, at++)
        if (at < cap)
            buf[at] = (unsigned char)(v >> (8 * k));
    return at;
}

static uint32_t bits(float v)
{
    uint32_t u;
    memcpy(&u, &v, sizeof u);
    return u;
}

size_t rf_qsum_encode(const rf_qsum *s, unsigned char *buf, size_t cap)
{
    size_t at = put(buf, cap, 0, s->n, 8);
    if (s->n == 0)
        return at;
    at = put(buf, cap, at, bits(s->max), 4);
    if (s->n <= RF_QSUM_EXACT) {
        for (uint64_t i = 0; i < s->n; i++)
            at = put(buf, cap, at, bits(s->v[i]), 4);
        return at;
    }
    at = put(buf, cap, at, bits(s->low_max[0]), 4);
    at = put(buf, cap, at, bits(s->low_max[1]), 4);
    at = put(buf, cap, at, (uint32_t)s->b0, 4);
    at = put(buf, cap, at, s->nb, 4);
    for (uint32_t i = 0; i < s->nb; i++)
        at = put(buf, cap, at, s->bins[i], 8);
    return at;
}

static int get(const unsigned char *buf, size_t len, size_t *at, int bytes, uint64_t *v)
{
    if (len - *at < (size_t)bytes || *at > len)
        return -1;
    *v = 0;
    for (int k = 0; k < bytes; k++)
        *v |= (uint64_t)buf[(*at)++] << (8 * k);
    return 0;
}

static float unbits(uint64_t u)
{
    uint32_t w = (uint32_t)u;
    float v;
    memcpy(&v, &w, sizeof v);
    return v;
}

int rf_qsum_decode(rf_qsum *s, const unsigned char *buf, size_t len, size_t *used)
{
    memset(s, 0, sizeof *s);
    size_t at = 0;
    uint64_t u, n;
    if (get(buf, len, &at, 8, &n))
        return -1;
    if (n == 0) {
        *used = at;
        return 0;
    }
    if (get(buf, len, &at, 4, &u))
        return -1;
    s->max = unbits(u);
    if (n <= RF_QSUM_EXACT) {
        s->v = malloc((size_t)n * sizeof *s->v);
        if (!s->v)
            return -1;
        s->cap = (uint32_t)n;
        for (s->n = 0; s->n < n; s->n++) {
            if (get(buf, len, &at, 4, &u) ||
                (s->n > 0 && key(unbits(u)) < key(s->v[s->n - 1]))) { /* not ascending */
                rf_qsum_free(s);
                return -1;
            }
            s->v[s->n] = unbits(u);
        }
        *used = at;
        return 0;
    }
    uint64_t lm0, lm1, b0, nb, sum = 0;
    if (get(buf, len, &at, 4, &lm0) || get(buf, len, &at, 4, &lm1) ||
        get(buf, len, &at, 4, &b0) || get(buf, len, &at, 4, &nb) || nb == 0 ||
        (int32_t)(uint32_t)b0 < 0 || nb > (len - at) / 8)
        return -1;
    s->bins = malloc((size_t)nb * sizeof *s->bins);
    if (!s->bins)
        return -1;
    s->low_max[0] = unbits(lm0);
    s->low_max[1] = unbits(lm1);
    s->b0 = (int32_t)(uint32_t)b0;
    s->nb = (uint32_t)nb;
    for (uint32_t i = 0; i < s->nb; i++) {
        get(buf, len, &at, 8, &s->bins[i]); /* within len: nb was bounded above */
        sum += s->bins[i];
    }
    s->n = n;
    if (sum != n) {
        rf_qsum_free(s);
        return -1;
    }
    *used = at;
    return 0;
}

size_t rf_qsum_bytes(const rf_qsum *s)
{
    return s->cap * sizeof *s->v + s->nb * sizeof *s->bins;
}

void rf_qsum_free(rf_qsum *s)
{
    free(s->v);
    free(s->bins);
    memset(s, 0, sizeof *s);
}
