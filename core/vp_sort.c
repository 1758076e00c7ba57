#include <string.h>
#include "vp_sort.h"

#ifndef VP_CORE_MCU /* only vp_dt_insert_batch sorts: left out with it (vp_status.h) */

#define HBITS 16u
#define BRIO_MIN_ROUND 64u /* the first round holds about this many points */

/* Spreads the low 16 bits of v so that bit k lands on bit 3k. */
static uint64_t spread3(uint64_t v)
{
    v &= 0xFFFFu;
    v = (v | (v << 16)) & 0x0000FF0000FFull;
    v = (v | (v << 8)) & 0x00F00F00F00Full;
    v = (v | (v << 4)) & 0x0C30C30C30C3ull;
    v = (v | (v << 2)) & 0x249249249249ull;
    return v;
}

/* Hilbert index of the 2^bits grid by Skilling's transposition ("Programming the Hilbert
 * curve", 2004): undo the rotations and reflections level by level, Gray-code the result,
 * then interleave the bits. Branch-free: the data-dependent choices are masks. */
static uint64_t hilbert_bits(uint32_t x, uint32_t y, uint32_t z, unsigned bits)
{
    uint32_t c0 = x, c1 = y, c2 = z, t, low, m;
    unsigned lev;
    for (lev = bits - 1; lev > 0; lev--) {
        low = (1u << lev) - 1u;
        /* axis 0: invert the low bits of c0 when its bit is set */
        c0 ^= low & (0u - ((c0 >> lev) & 1u));
        /* axes 1, 2: bit set -> invert c0's low bits; clear -> exchange low bits with c0 */
        m = 0u - ((c1 >> lev) & 1u);
        t = (c0 ^ c1) & low & ~m;
        c0 ^= (low & m) | t;
        c1 ^= t;
        m = 0u - ((c2 >> lev) & 1u);
        t = (c0 ^ c2) & low & ~m;
        c0 ^= (low & m) | t;
        c2 ^= t;
    }
    c1 ^= c0;
    c2 ^= c1;
    t = 0;
    for (lev = bits - 1; lev > 0; lev--) t ^= ((1u << lev) - 1u) & (0u - ((c2 >> lev) & 1u));
    c0 ^= t; c1 ^= t; c2 ^= t;
    return (spread3(c0) << 2) | (spread3(c1) << 1) | spread3(c2);
}

uint64_t vp_hilbert3(uint32_t x, uint32_t y, uint32_t z)
{
    return hilbert_bits(x & 0xFFFFu, y & 0xFFFFu, z & 0xFFFFu, HBITS);
}

size_t vp_sort_scratch_bytes(uint32_t n)
{
    /* two key arrays, one index array, histograms */
    return (size_t)n * (2 * sizeof(uint64_t) + sizeof(uint32_t)) + 8 * 256 * sizeof(uint32_t) + 16;
}

static uint32_t mix32(uint32_t h)
{
    h ^= h >> 16; h *= 0x7FEB352Du;
    h ^= h >> 15; h *= 0x846CA68Bu;
    h ^= h >> 16;
    return h;
}

static uint32_t quantize(double v, double lo, double scale, double top)
{
    double q = (v - lo) * scale;
    if (!(q > 0.0)) return 0;
    if (q >= top) return (uint32_t)top;
    return (uint32_t)q;
}

void vp_sort_brio(const double *xyz, uint32_t n, uint32_t seed, uint32_t *order, void *scratch)
{
    uint64_t *key = (uint64_t *)scratch, *key2 = key + n;
    uint32_t *idx2 = (uint32_t *)(key2 + n);
    uint32_t *hist = idx2 + n;
    double lo[3], hi[3], scale[3], top;
    uint32_t i, rounds = 1, pass, npass, *src_i, *dst_i;
    unsigned bits = 2;
    uint64_t *src_k, *dst_k;
    int k;

    if (n == 0) return;
    for (k = 0; k < 3; k++) lo[k] = hi[k] = xyz[k];
    for (i = 1; i < n; i++)
        for (k = 0; k < 3; k++) {
            double v = xyz[3 * (size_t)i + k];
            if (v < lo[k]) lo[k] = v;
            if (v > hi[k]) hi[k] = v;
        }
    /* Hilbert grid: about 8^2 cells per point (ties keep the input order), at most 2^16 a side */
    while (bits < HBITS && ((uint64_t)1 << (3 * (bits - 2))) < n) bits++;
    top = (double)((1u << bits) - 1u);
    for (k = 0; k < 3; k++) {
        double ext = hi[k] - lo[k];
        scale[k] = ext > 0.0 ? top / ext : 0.0;
    }
    /* BRIO: round r (0 = first) keeps each point with probability ~8^-(rounds-1-r) */
    while (rounds < 12 && ((uint64_t)BRIO_MIN_ROUND << (3 * rounds)) < n) rounds++;
    for (i = 0; i < n; i++) {
        const double *p = xyz + 3 * (size_t)i;
        uint32_t h = mix32(i * 0x9E3779B9u ^ mix32(seed + 0x632BE5ABu));
        uint32_t lz = 0, r;
        while (lz < 31 && !(h & (0x80000000u >> lz))) lz++;
        r = lz / 3 >= rounds - 1 ? 0 : rounds - 1 - lz / 3;
        key[i] = ((uint64_t)r << (3 * bits)) |
                 hilbert_bits(quantize(p[0], lo[0], scale[0], top),
                              quantize(p[1], lo[1], scale[1], top),
                              quantize(p[2], lo[2], scale[2], top), bits);
        order[i] = i;
    }
    /* LSD radix sort, one byte per pass, stable; passes where every key agrees are skipped */
    npass = (3 * bits + 4 + 7) / 8; /* the round fits in 4 bits (rounds <= 12) */
    memset(hist, 0, 7 * 256 * sizeof(uint32_t));
    for (i = 0; i < n; i++)
        for (pass = 0; pass < npass; pass++) hist[pass * 256 + ((key[i] >> (8 * pass)) & 0xFF)]++;
    src_k = key; dst_k = key2; src_i = order; dst_i = idx2;
    for (pass = 0; pass < npass; pass++) {
        uint32_t *h = hist + pass * 256, sum = 0, b, *ti;
        uint64_t *tk;
        if (h[(src_k[0] >> (8 * pass)) & 0xFF] == n) continue;
        for (b = 0; b < 256; b++) { uint32_t c = h[b]; h[b] = sum; sum += c; }
        for (i = 0; i < n; i++) {
            uint32_t dst = h[(src_k[i] >> (8 * pass)) & 0xFF]++;
            dst_k[dst] = src_k[i];
            dst_i[dst] = src_i[i];
        }
        tk = src_k; src_k = dst_k; dst_k = tk;
        ti = src_i; src_i = dst_i; dst_i = ti;
    }
    if (src_i != order) memcpy(order, src_i, (size_t)n * sizeof(uint32_t));
}

#endif /* VP_CORE_MCU */
