/* vp_rng — small deterministic PRNGs above the core (splitmix64; xoshiro256** seeded by it) (splitmix64 seeding, xoshiro256**).
 * Same seed, same sequence on every machine; no global state. */
#ifndef VP_RNG_H
#define VP_RNG_H
#include <stdint.h>

typedef struct vp_rng { uint64_t s[4]; } vp_rng_t;

/* splitmix64: the next value of the sequence at *state (which advances), the same as a
 * uniform double in [0,1) (53 bits), and one value mixed from x alone (a hash of x). */
uint64_t vp_splitmix_next(uint64_t *state);
double   vp_splitmix_uniform(uint64_t *state);
uint64_t vp_mix64(uint64_t x);

void     vp_rng_seed(vp_rng_t *r, uint64_t seed);
uint64_t vp_rng_u64(vp_rng_t *r);
double   vp_rng_uniform(vp_rng_t *r);               /* [0,1), 53 random bits */
double   vp_rng_normal(vp_rng_t *r);                /* standard normal (Box-Muller) */
uint64_t vp_rng_below(vp_rng_t *r, uint64_t n);     /* uniform in [0,n), n > 0 */
void     vp_rng_unit3(vp_rng_t *r, double v[3]);    /* uniform direction on the unit sphere */

#endif
