/* vp_sort — spatial order for batch insertion: BRIO rounds, Hilbert curve inside each round.
 * Random rounds (Amenta, Choi, Rote: biased randomized insertion order) keep the expected cost
 * of incremental Delaunay low; the Hilbert order inside a round keeps consecutive points close
 * so that walks are short and memory stays in cache. Deterministic for a given seed.
 * Left out with VP_CORE_MCU (vp_status.h), as vp_dt_insert_batch, its only user. */
#ifndef VP_SORT_H
#define VP_SORT_H

#include <stddef.h>
#include <stdint.h>

#ifndef VP_CORE_MCU

/* Bytes of scratch vp_sort_brio needs for n points. */
size_t vp_sort_scratch_bytes(uint32_t n);

/* Writes to order[0..n) the insertion order of the points xyz[3*i..] (all finite).
 * scratch: vp_sort_scratch_bytes(n) bytes, 8-byte aligned. */
void vp_sort_brio(const double *xyz, uint32_t n, uint32_t seed, uint32_t *order, void *scratch);

/* Hilbert index of a point of the 2^16 grid (each coordinate < 65536): 48 bits. */
uint64_t vp_hilbert3(uint32_t x, uint32_t y, uint32_t z);

#endif /* VP_CORE_MCU */

#endif
