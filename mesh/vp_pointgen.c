#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_file.h"
#include "vp_pointgen.h"
#include "vp_rng.h"
#include "vp_vec3.h"

static double *alloc_points(size_t n, char *err, size_t errlen)
{
    double *p = n ? malloc(n * 3 * sizeof(double)) : malloc(1);
    if (!p) snprintf(err, errlen, "cannot allocate %zu points", n);
    return p;
}

int vp_pointgen_uniform(size_t n, uint64_t seed, double **xyz, size_t *count, char *err, size_t errlen)
{
    uint64_t s = seed;
    size_t i;
    double *p = alloc_points(n, err, errlen);
    if (!p) return -1;
    for (i = 0; i < 3 * n; i++) p[i] = vp_splitmix_uniform(&s);
    *xyz = p; *count = n;
    return 0;
}

int vp_pointgen_grid(size_t k, uint64_t seed, double **xyz, size_t *count, char *err, size_t errlen)
{
    uint64_t s = seed;
    size_t n = k * k * k, i, x, y, z;
    double *p = alloc_points(n, err, errlen);
    if (!p) return -1;
    i = 0;
    for (x = 0; x < k; x++)
        for (y = 0; y < k; y++)
            for (z = 0; z < k; z++) {
                p[3 * i] = (double)x; p[3 * i + 1] = (double)y; p[3 * i + 2] = (double)z;
                i++;
            }
    for (i = n; i > 1; i--) { /* Fisher-Yates shuffle */
        size_t j = (size_t)(vp_splitmix_next(&s) % i), c;
        for (c = 0; c < 3; c++) {
            double t = p[3 * (i - 1) + c];
            p[3 * (i - 1) + c] = p[3 * j + c];
            p[3 * j + c] = t;
        }
    }
    *xyz = p; *count = n;
    return 0;
}

int vp_pointgen_sphere(size_t n, uint64_t seed, double **xyz, size_t *count, char *err, size_t errlen)
{
    uint64_t s = seed;
    size_t i;
    double *p = alloc_points(n, err, errlen);
    if (!p) return -1;
    for (i = 0; i < n; i++) {
        double v[3], r2;
        do {
            v[0] = 2.0 * vp_splitmix_uniform(&s) - 1.0;
            v[1] = 2.0 * vp_splitmix_uniform(&s) - 1.0;
            v[2] = 2.0 * vp_splitmix_uniform(&s) - 1.0;
            r2 = vp_dot3(v, v);
        } while (r2 > 1.0 || r2 < 1e-6);
        r2 = 1.0 / sqrt(r2);
        p[3 * i] = v[0] * r2; p[3 * i + 1] = v[1] * r2; p[3 * i + 2] = v[2] * r2;
    }
    *xyz = p; *count = n;
    return 0;
}

/* One line of f into line[cap] (without the newline): 1, 0 at the end of the file, -1 for a
 * line too long, -2 for a NUL byte in it (the rest of the line is consumed). */
static int node_line(FILE *f, char *line, size_t cap)
{
    size_t n = 0;
    int c = EOF, any = 0, nul = 0, longl = 0;
    while ((c = getc(f)) != EOF && c != '\n') {
        any = 1;
        if (c == 0) nul = 1;
        if (n + 1 < cap) line[n++] = (char)c;
        else longl = 1;
    }
    line[n] = 0;
    if (!any && c == EOF) return 0;
    return nul ? -2 : longl ? -1 : 1;
}

int vp_pointgen_read_node(const char *path, double **xyz, size_t *count, char *err, size_t errlen)
{
    unsigned long long size = 0;
    FILE *f = vp_file_open_read(path, VP_NODE_MAX_FILE, ".node file", &size, err, errlen);
    char line[512];
    long lineno = 0;
    size_t n = 0, i = 0;
    int dim = 0, header = 0, k;
    double *p = NULL;
    if (!f) return -1;
    while ((k = node_line(f, line, sizeof line)) != 0) {
        char *s = line, *e;
        double v[4];
        lineno++;
        if (k == -2) { snprintf(err, errlen, "%s:%ld: a NUL byte inside the line (a damaged or binary file)", path, lineno); goto fail; }
        if (k == -1) { snprintf(err, errlen, "%s:%ld: line longer than %d bytes", path, lineno, (int)sizeof line - 1); goto fail; }
        while (*s == ' ' || *s == '\t') s++;
        if (*s == '#' || *s == '\r' || !*s) continue;
        if (!header) {
            long ln = strtol(s, &e, 10);
            if (e == s || ln < 0) goto bad;
            dim = (int)strtol(e, &e, 10);
            if (dim != 3) { snprintf(err, errlen, "%s:%ld: dimension %d, expected 3", path, lineno, dim); goto fail; }
            n = (size_t)ln;
            /* each point takes a line of at least 8 bytes ("0 0 0 0\n") */
            if (n > ((size_t)1 << 31) || (unsigned long long)n > size / 8 + 1) {
                snprintf(err, errlen, "%s:%ld: %ld points: impossible for a file of %llu bytes", path, lineno, ln, size);
                goto fail;
            }
            p = alloc_points(n, err, errlen);
            if (!p) goto fail;
            header = 1;
            continue;
        }
        if (i >= n) { snprintf(err, errlen, "%s:%ld: more points than the header's %zu", path, lineno, n); goto fail; }
        for (k = 0; k < 4; k++) {
            v[k] = strtod(s, &e);
            if (e == s) goto bad;
            s = e;
        }
        for (k = 0; k < 3; k++) {
            if (!isfinite(v[k + 1])) { snprintf(err, errlen, "%s:%ld: non-finite coordinate", path, lineno); goto fail; }
            p[3 * i + (size_t)k] = v[k + 1];
        }
        i++;
    }
    if (ferror(f)) { snprintf(err, errlen, "%s: read error", path); goto fail; }
    if (!header) { snprintf(err, errlen, "%s: empty file", path); goto fail; }
    if (i != n) { snprintf(err, errlen, "%s: header says %zu points, file has %zu", path, n, i); goto fail; }
    fclose(f);
    *xyz = p; *count = n;
    return 0;
bad:
    snprintf(err, errlen, "%s:%ld: malformed line", path, lineno);
fail:
    free(p);
    fclose(f);
    return -1;
}

int vp_pointgen_write_node(const char *path, const double *xyz, size_t n, char *err, size_t errlen)
{
    FILE *f = fopen(path, "w");
    size_t i;
    if (!f) { snprintf(err, errlen, "%s: %s", path, strerror(errno)); return -1; }
    fprintf(f, "%zu 3 0 0\n", n);
    for (i = 0; i < n; i++)
        fprintf(f, "%zu %.17g %.17g %.17g\n", i, xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    if (fclose(f) != 0) { snprintf(err, errlen, "%s: write failed", path); return -1; }
    return 0;
}
