/* Point sets for benchmarks and tests: the anchor sets (uniform, grid, sphere) and TetGen
 * .node files. Each returns 0 or -1 with a message in err; *xyz is malloc'ed (free it). */
#ifndef VP_POINTGEN_H
#define VP_POINTGEN_H
#include <stddef.h>
#include <stdint.h>

/* The generator of the anchor point sets is splitmix64 (vp_rng.h): same seed, same points as the anchors. */

int vp_pointgen_uniform(size_t n, uint64_t seed, double **xyz, size_t *count, char *err, size_t errlen);
int vp_pointgen_grid(size_t k, uint64_t seed, double **xyz, size_t *count, char *err, size_t errlen);
int vp_pointgen_sphere(size_t n, uint64_t seed, double **xyz, size_t *count, char *err, size_t errlen);
/* A regular file of at most VP_NODE_MAX_FILE bytes ("N 3 0 0", then "index x y z" lines; '#'
 * comments); a device, a NUL byte or a count the file cannot hold is refused, naming the line. */
#define VP_NODE_MAX_FILE (1ULL << 36)
int vp_pointgen_read_node(const char *path, double **xyz, size_t *count, char *err, size_t errlen);
int vp_pointgen_write_node(const char *path, const double *xyz, size_t n, char *err, size_t errlen);
#endif
