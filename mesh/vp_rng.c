#include <math.h>
#include "vp_rng.h"
#include "vp_vec3.h"

uint64_t vp_splitmix_next(uint64_t *state)
{
    uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

double vp_splitmix_uniform(uint64_t *state)
{
    return (double)(vp_splitmix_next(state) >> 11) * (1.0 / 9007199254740992.0);
}

uint64_t vp_mix64(uint64_t x)
{
    return vp_splitmix_next(&x);
}

void vp_rng_seed(vp_rng_t *r, uint64_t seed)
{
    int i;
    for (i = 0; i < 4; i++) r->s[i] = vp_splitmix_next(&seed);
}

static uint64_t vp_rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

uint64_t vp_rng_u64(vp_rng_t *r)
{
    uint64_t *s = r->s;
    uint64_t out = vp_rotl(s[1] * 5, 7) * 9;
    uint64_t t = s[1] << 17;
    s[2] ^= s[0]; s[3] ^= s[1]; s[1] ^= s[2]; s[0] ^= s[3];
    s[2] ^= t;
    s[3] = vp_rotl(s[3], 45);
    return out;
}

double vp_rng_uniform(vp_rng_t *r)
{
    return (double)(vp_rng_u64(r) >> 11) * (1.0 / 9007199254740992.0);
}

double vp_rng_normal(vp_rng_t *r)
{
    double u1 = 1.0 - vp_rng_uniform(r);   /* (0,1] */
    double u2 = vp_rng_uniform(r);
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

uint64_t vp_rng_below(vp_rng_t *r, uint64_t n)
{
    uint64_t lim = UINT64_MAX - UINT64_MAX % n, x;
    do x = vp_rng_u64(r); while (x >= lim);
    return x % n;
}

void vp_rng_unit3(vp_rng_t *r, double v[3])
{
    double n2;
    do {
        v[0] = vp_rng_normal(r); v[1] = vp_rng_normal(r); v[2] = vp_rng_normal(r);
        n2 = vp_dot3(v, v);
    } while (n2 < 1e-20);
    n2 = 1.0 / sqrt(n2);
    v[0] *= n2; v[1] *= n2; v[2] *= n2;
}
