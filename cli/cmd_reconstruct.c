/* voroprobe reconstruct: the tangential Delaunay complex of a point set (paper 004), and the
 * seeded manifold samples it is tested and measured on. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include "vp_cli.h"
#include "vp_file.h"
#include "vp_manifoldgen.h"
#include "vp_meshio.h"
#include "vp_mfcheck.h"
#include "vp_sessionlog.h"
#include "vp_status.h"
#include "vp_tdc.h"

#define MAX_TEXT_FILE (1ULL << 32)

static void reconstruct_usage(FILE *f)
{
    size_t i;
    fprintf(f,
        "usage: voroprobe reconstruct POINTS --dim K --out PREFIX [options]\n"
        "       voroprobe reconstruct --generate NAME --n N [--seed S] [--noise S] [--nonuniform]\n"
        "                             [--out-points FILE] [--out PREFIX [options]]\n"
        "Reconstructs a K-manifold (K = 1, 2, 3) from points in R^d with the tangential Delaunay\n"
        "complex (A. Ghosh's thesis, ch. 3): per point a tangent space by local PCA, its star (the\n"
        "K-simplices whose weighted Voronoi face meets the tangent space, a K-dimensional power\n"
        "cell certified against every farther point), then inconsistent simplices (in one vertex's\n"
        "star, not in another's) removed by perturbing their points within a bound, recomputing\n"
        "only the stars that can change and undoing a move that adds inconsistencies. The result\n"
        "is checked by a manifold check that sees only the simplices.\n"
        "POINTS: a PLY file (its vertices), a session log (its hits), or a text file with one point\n"
        "per line, d numbers separated by blanks or commas (any d; '#' starts a comment line).\n"
        "Output: PREFIX.simplices (doc/simplex-file.md); for K = 2 in R^3 also PREFIX.ply and\n"
        "PREFIX.off, consistently oriented (outward) when orientable.\n"
        "  --dim K            intrinsic dimension (default with --generate: the manifold's)\n"
        "  --out PREFIX       where the output goes\n"
        "  --json             end with one JSON object (points, dim, ambient_dim, simplices per\n"
        "                     dimension, inconsistent_before, inconsistent, euler, manifold,\n"
        "                     orientable, components, rounds, moves, max_shift, seconds,\n"
        "                     peak_rss_kb, ...)\n"
        "  --fix MODE         position (default): move points within the bound in their tangent\n"
        "                     space; weight: random weights up to (bound)^2; none: no fixing\n"
        "  --perturb-rel R    the bound, times each point's nearest-neighbour distance (0.25)\n"
        "  --rounds N         at most N fixing sweeps over the points with an inconsistency (1000)\n"
        "  --time-limit S     at most S seconds of fixing (120)\n"
        "  --pca N            neighbours in each PCA (8, 25, 60 for K = 1, 2, 3)\n"
        "  --seed S           seed of the perturbations (and of --generate) (1)\n"
        "  --quiet            no summary lines (the JSON still printed with --json)\n"
        "Generating (--generate NAME, seeded and the same on every machine):\n");
    for (i = 0; vp_manifold_info(i); i++) {
        const vp_manifold_info_t *m = vp_manifold_info(i);
        fprintf(f, "  %-9s k=%d d=%-2d Euler %2ld %-13s %s\n", m->name, m->k, m->d, m->euler,
                m->orientable ? "orientable" : "non-orientable", m->what);
    }
    fprintf(f,
        "  --n N              points (required)\n"
        "  --noise S          Gaussian noise of standard deviation S on every coordinate\n"
        "  --nonuniform       density growing fivefold along the first coordinate\n"
        "  --out-points FILE  write the points as text (one per line) and, without --out, stop\n"
        "Exit status: 0 a closed manifold with no inconsistent simplex (or points written),\n"
        "1 an error, or a result that is not (written all the same), 2 usage.\n"
        "Example: voroprobe reconstruct --generate torus --n 10000 --out out/torus --json\n");
}

typedef struct rec_args {
    const char *in, *out, *out_points, *generate;
    int k, json, quiet, fix_mode, no_fix, nonuniform;
    long rounds, pca;
    double perturb_rel, time_limit, noise;
    unsigned long long seed, n;
} rec_args_t;

static int parse_num(const char *opt, const char *v, double *out, double lo)
{
    char *e;
    double x = strtod(v, &e);
    if (e == v || *e || !isfinite(x) || x < lo) {
        fprintf(stderr, "reconstruct: %s: bad value '%s'\n", opt, v);
        return 0;
    }
    *out = x;
    return 1;
}

/* -1: parsed; else the exit status. */
static int rec_parse(int argc, char **argv, rec_args_t *o)
{
    int i;
    memset(o, 0, sizeof *o);
    o->seed = 1;
    for (i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        double x;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) { reconstruct_usage(stdout); return 0; }
        if (a[0] != '-') {
            if (o->in) { fprintf(stderr, "reconstruct: one input at a time\n"); return 2; }
            o->in = a;
            continue;
        }
        if (!strcmp(a, "--json")) { o->json = 1; continue; }
        if (!strcmp(a, "--quiet")) { o->quiet = 1; continue; }
        if (!strcmp(a, "--nonuniform")) { o->nonuniform = 1; continue; }
        {
            static const char *const valued[] = {"--out", "--out-points", "--generate", "--fix", "--dim", "--perturb-rel",
                                                 "--time-limit", "--noise", "--rounds", "--pca", "--seed", "--n"};
            size_t k;
            for (k = 0; k < sizeof valued / sizeof valued[0] && strcmp(a, valued[k]); k++)
                ;
            if (k == sizeof valued / sizeof valued[0]) { fprintf(stderr, "reconstruct: unknown option %s (see --help)\n", a); return 2; }
        }
        if (!v) { fprintf(stderr, "reconstruct: %s needs a value (see --help)\n", a); return 2; }
        i++;
        if (!strcmp(a, "--out")) o->out = v;
        else if (!strcmp(a, "--out-points")) o->out_points = v;
        else if (!strcmp(a, "--generate")) {
            if (!vp_manifold_find(v)) { fprintf(stderr, "reconstruct: --generate: unknown manifold '%s' (see --help)\n", v); return 2; }
            o->generate = v;
        } else if (!strcmp(a, "--fix")) {
            if (!strcmp(v, "position")) o->fix_mode = VP_TDC_FIX_POSITION;
            else if (!strcmp(v, "weight")) o->fix_mode = VP_TDC_FIX_WEIGHT;
            else if (!strcmp(v, "none")) o->no_fix = 1;
            else { fprintf(stderr, "reconstruct: --fix: position, weight or none\n"); return 2; }
        } else if (!strcmp(a, "--dim")) {
            if (!parse_num(a, v, &x, 1) || x > VP_TDC_KMAX || x != floor(x)) {
                fprintf(stderr, "reconstruct: --dim: 1 to %d\n", VP_TDC_KMAX);
                return 2;
            }
            o->k = (int)x;
        } else if (!strcmp(a, "--perturb-rel")) { if (!parse_num(a, v, &o->perturb_rel, 1e-9)) return 2; }
        else if (!strcmp(a, "--time-limit")) { if (!parse_num(a, v, &o->time_limit, 1e-9)) return 2; }
        else if (!strcmp(a, "--noise")) { if (!parse_num(a, v, &o->noise, 0)) return 2; }
        else if (!strcmp(a, "--rounds")) { if (!parse_num(a, v, &x, 1) || x > 1e9) return 2; o->rounds = (long)x; }
        else if (!strcmp(a, "--pca")) { if (!parse_num(a, v, &x, 2) || x > 100000) return 2; o->pca = (long)x; }
        else if (!strcmp(a, "--seed")) { if (!parse_num(a, v, &x, 0) || x > 9e15) return 2; o->seed = (unsigned long long)x; }
        else if (!strcmp(a, "--n")) { if (!parse_num(a, v, &x, 1) || x > 5e7) return 2; o->n = (unsigned long long)x; }
        else { fprintf(stderr, "reconstruct: unknown option %s (see --help)\n", a); return 2; }
    }
    if (o->generate && o->in) { fprintf(stderr, "reconstruct: POINTS or --generate, not both\n"); return 2; }
    if (!o->generate && !o->in) { fprintf(stderr, "reconstruct: no POINTS (see --help)\n"); return 2; }
    if (o->generate && !o->n) { fprintf(stderr, "reconstruct: --generate needs --n\n"); return 2; }
    if (!o->generate && (o->n || o->out_points || o->nonuniform || o->noise > 0)) {
        fprintf(stderr, "reconstruct: --n, --noise, --nonuniform, --out-points go with --generate\n");
        return 2;
    }
    if (!o->out && !o->out_points) { fprintf(stderr, "reconstruct: --out PREFIX is required\n"); return 2; }
    if (o->out && !o->generate && !o->k) { fprintf(stderr, "reconstruct: --dim K is required\n"); return 2; }
    return -1;
}

/* Text points: one per line, d numbers (blanks or commas); blank and '#' lines skipped. */
static int read_text_points(const char *path, double **pts, size_t *n, int *d, char *err, size_t errlen)
{
    unsigned char *data;
    size_t len, cap = 0, m = 0;
    unsigned long line = 0;
    double *v = NULL, row[VP_TDC_DMAX];
    char *s, *next;
    int dim = 0, st = vp_file_read(path, MAX_TEXT_FILE, "point file", NULL, &data, &len, err, errlen);
    if (st < 0) return st;
    if (vp_file_find_nul(data, len, &line)) {
        vp_seterr(err, errlen, "%s: line %lu: a NUL byte (not a text point file)", path, line);
        free(data);
        return VP_ECORRUPT;
    }
    line = 0;
    for (s = (char *)data; s && *s; s = next) {
        int c = 0;
        char *p;
        next = strchr(s, '\n');
        if (next) *next++ = 0;
        line++;
        for (p = s; *p == ' ' || *p == '\t' || *p == '\r'; p++) {}
        if (!*p || *p == '#') continue;
        for (;;) {   /* the line's numbers into row[] */
            char *e;
            double x;
            while (*p == ' ' || *p == '\t' || *p == ',' || *p == '\r') p++;
            if (!*p) break;
            x = strtod(p, &e);
            if (e == p || !isfinite(x)) {
                vp_seterr(err, errlen, "%s: line %lu: '%.20s' is not a finite number", path, line, p);
                st = VP_ECORRUPT;
                goto fail;
            }
            if (c >= VP_TDC_DMAX) {
                vp_seterr(err, errlen, "%s: line %lu: more than %d coordinates", path, line, VP_TDC_DMAX);
                st = VP_ECORRUPT;
                goto fail;
            }
            row[c++] = x;
            p = e;
        }
        if (!dim) dim = c;
        if (c != dim) {
            vp_seterr(err, errlen, "%s: line %lu: %d coordinates, the first point has %d", path, line, c, dim);
            st = VP_ECORRUPT;
            goto fail;
        }
        if ((m + 1) * dim > cap) {
            size_t nc = cap ? 2 * cap : 4096 * (size_t)dim;
            double *nv = realloc(v, nc * sizeof *nv);
            if (!nv) { st = VP_ENOMEM; goto fail; }
            v = nv; cap = nc;
        }
        memcpy(v + m * dim, row, (size_t)dim * sizeof *row);
        m++;
    }
    if (!m) { vp_seterr(err, errlen, "%s: no points", path); st = VP_ECORRUPT; goto fail; }
    free(data);
    *pts = v; *n = m; *d = dim;
    return VP_OK;
fail:
    free(data);
    free(v);
    return st;
}

static int is_ply(const char *path)
{
    char b[3];
    FILE *f = fopen(path, "rb");
    size_t n;
    if (!f) return 0;
    n = fread(b, 1, 3, f);
    fclose(f);
    return n == 3 && !memcmp(b, "ply", 3);
}

static int read_points(const char *path, double **pts, size_t *n, int *d, char *err, size_t errlen)
{
    if (vp_sessionlog_is_log(path)) {
        vp_sessionlog_t L;
        uint32_t i;
        size_t m = 0;
        double *v;
        int st = vp_sessionlog_load(&L, path, err, errlen);
        if (st < 0) return st;
        v = malloc(((size_t)L.hits + 1) * 3 * sizeof *v);
        if (!v) { vp_sessionlog_free(&L); return VP_ENOMEM; }
        for (i = 0; i < L.n; i++) {
            vp_logfmt_record_t r;
            int c;
            if (vp_sessionlog_record(&L, i, &r) != VP_OK || r.type != VP_LOGFMT_PROBE || r.hit != 1) continue;
            if (m >= L.hits) break;
            for (c = 0; c < 3; c++) v[m * 3 + c] = r.origin[c] + r.dist * r.dir[c];
            m++;
        }
        vp_sessionlog_free(&L);
        if (!m) { free(v); vp_seterr(err, errlen, "%s: the session log holds no hit", path); return VP_ECORRUPT; }
        *pts = v; *n = m; *d = 3;
        return VP_OK;
    }
    if (is_ply(path)) {
        vp_mesh_t mesh;
        int st;
        vp_mesh_init(&mesh);
        st = vp_mesh_read_file(path, &mesh, err, errlen);
        if (st < 0) return st;
        if (!mesh.nv) { vp_mesh_free(&mesh); vp_seterr(err, errlen, "%s: no vertices", path); return VP_ECORRUPT; }
        *pts = mesh.xyz; *n = mesh.nv; *d = 3;
        mesh.xyz = NULL;
        vp_mesh_free(&mesh);
        return VP_OK;
    }
    return read_text_points(path, pts, n, d, err, errlen);
}

static int write_text_points(const char *path, const double *p, size_t n, int d)
{
    FILE *f = fopen(path, "w");
    size_t i;
    int c;
    if (!f) return VP_EIO;
    for (i = 0; i < n; i++)
        for (c = 0; c < d; c++) fprintf(f, "%.17g%c", p[i * d + c], c + 1 < d ? ' ' : '\n');
    return fclose(f) ? VP_EIO : VP_OK;
}

/* doc/simplex-file.md */
static int write_simplices(const char *path, const double *p, size_t n, int d, const uint32_t *s, size_t ns, int k)
{
    FILE *f = fopen(path, "w");
    size_t i;
    int c;
    if (!f) return VP_EIO;
    fprintf(f, "# voroprobe simplicial complex\npoints %zu %d\n", n, d);
    for (i = 0; i < n; i++)
        for (c = 0; c < d; c++) fprintf(f, "%.17g%c", p[i * d + c], c + 1 < d ? ' ' : '\n');
    fprintf(f, "simplices %zu %d\n", ns, k);
    for (i = 0; i < ns; i++)
        for (c = 0; c <= k; c++) fprintf(f, "%u%c", s[i * (k + 1) + c], c < k ? ' ' : '\n');
    return fclose(f) ? VP_EIO : VP_OK;
}

static int write_surface(const char *prefix, const double *p, size_t n, uint32_t *tri, size_t nt, int flip_out)
{
    vp_mesh_t m;
    char path[4096];
    size_t i;
    double vol = 0;
    int st;
    for (i = 0; i < nt; i++) {   /* signed volume: make the orientation outward */
        const double *a = p + 3 * tri[3 * i], *b = p + 3 * tri[3 * i + 1], *c = p + 3 * tri[3 * i + 2];
        vol += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
    }
    if (flip_out && vol < 0)
        for (i = 0; i < nt; i++) { uint32_t t = tri[3 * i]; tri[3 * i] = tri[3 * i + 1]; tri[3 * i + 1] = t; }
    m.xyz = (double *)p; m.tri = tri; m.nv = n; m.nt = nt;
    snprintf(path, sizeof path, "%s.ply", prefix);
    if ((st = vp_mesh_write_file(&m, path, VP_MESH_PLY_BIN)) < 0) return st;
    snprintf(path, sizeof path, "%s.off", prefix);
    return vp_mesh_write_file(&m, path, VP_MESH_OFF);
}

static double wall_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int vp_cli_reconstruct(int argc, char **argv)
{
    rec_args_t o;
    double *pts = NULL, t0, t_check;
    size_t n = 0, ns = 0;
    int d = 0, k, st, rc = 1, j;
    char err[512] = "";
    vp_tdc_params_t prm;
    vp_tdc_t *tdc = NULL;
    vp_tdc_stats_t S;
    vp_mfcheck_t mc;
    uint32_t *simp = NULL, *oriented = NULL;
    char path[4096];
    struct rusage ru;

    if ((st = rec_parse(argc, argv, &o)) >= 0) return st;
    t0 = wall_seconds();
    if (o.generate) {
        const vp_manifold_info_t *m = vp_manifold_find(o.generate);
        n = (size_t)o.n; d = m->d;
        pts = malloc(n * d * sizeof *pts);
        if (!pts) { fprintf(stderr, "reconstruct: out of memory\n"); return 1; }
        vp_manifold_sample(o.generate, n, o.seed, o.noise, o.nonuniform, pts);
        if (!o.k) o.k = m->k;
        if (o.out_points) {
            if (write_text_points(o.out_points, pts, n, d) < 0) {
                fprintf(stderr, "reconstruct: cannot write %s\n", o.out_points);
                free(pts);
                return 1;
            }
            if (!o.quiet) printf("wrote %zu points of %s (k=%d, R^%d, seed %llu) to %s\n", n, o.generate, m->k, d, o.seed, o.out_points);
            if (!o.out) { free(pts); return 0; }
        }
    } else if ((st = read_points(o.in, &pts, &n, &d, err, sizeof err)) < 0) {
        fprintf(stderr, "reconstruct: %s\n", err[0] ? err : vp_strerror(st));
        return 1;
    }
    k = o.k;
    memset(&prm, 0, sizeof prm);
    prm.k = k;
    prm.pca_neighbours = (int)o.pca;
    prm.perturb_rel = o.perturb_rel;
    prm.fix_mode = o.fix_mode;
    prm.max_rounds = o.no_fix ? -1 : (int)o.rounds;
    prm.time_limit = o.time_limit;
    prm.seed = o.seed;
    if ((st = vp_tdc_create(&tdc, pts, n, d, &prm, err, sizeof err)) < 0) {
        fprintf(stderr, "reconstruct: %s\n", err[0] ? err : vp_strerror(st));
        free(pts);
        return 1;
    }
    if ((st = vp_tdc_build(tdc)) < 0 || (st = vp_tdc_fix(tdc)) < 0 || (st = vp_tdc_simplices(tdc, &simp, &ns)) < 0) {
        fprintf(stderr, "reconstruct: %s\n", vp_strerror(st));
        goto out;
    }
    vp_tdc_get_stats(tdc, &S);
    t_check = wall_seconds();
    oriented = malloc((ns + 1) * (k + 1) * sizeof *oriented);
    if (!oriented || (st = vp_mfcheck_run(simp, ns, k, n, &mc, oriented)) < 0) {
        fprintf(stderr, "reconstruct: manifold check: %s\n", vp_strerror(oriented ? st : VP_ENOMEM));
        goto out;
    }
    t_check = wall_seconds() - t_check;
    snprintf(path, sizeof path, "%s.simplices", o.out);
    if (write_simplices(path, vp_tdc_points(tdc), n, d, oriented, ns, k) < 0) {
        fprintf(stderr, "reconstruct: cannot write %s\n", path);
        goto out;
    }
    if (k == 2 && d == 3 && write_surface(o.out, vp_tdc_points(tdc), n, oriented, ns, mc.orientable == 1) < 0) {
        fprintf(stderr, "reconstruct: cannot write %s.ply / %s.off\n", o.out, o.out);
        goto out;
    }
    rc = (mc.manifold && !S.inconsistent) ? 0 : 1;
    getrusage(RUSAGE_SELF, &ru);
    if (!o.quiet) {
        printf("reconstruct: %zu points in R^%d, k = %d: %zu %d-simplices; tangents %.3f s, stars %.3f s\n",
               n, d, k, ns, k, S.seconds_tangents, S.seconds_stars);
        printf("inconsistent: %zu before, %zu after %zu sweeps (%zu moves, %.3f s; largest shift %.3g = %.2f x nearest-neighbour distance)\n",
               S.inconsistent_before, S.inconsistent, S.rounds, S.moves, S.seconds_fix, S.max_shift, S.max_shift_rel);
        printf("complex: faces");
        for (j = 0; j <= k; j++) printf(" %zu", mc.faces[j]);
        printf(", Euler %ld, %s, %s, %zu component(s); bad facets %zu, bad links %zu; uncertified stars %zu\n",
               mc.euler, mc.manifold ? "closed manifold" : "NOT a closed manifold",
               mc.orientable == 1 ? "orientable" : mc.orientable == 0 ? "non-orientable" : "orientability undecided",
               mc.components, mc.bad_facets, mc.bad_links, S.uncertified);
        printf("wrote %s.simplices%s; %.3f s in all, peak RSS %ld KB\n", o.out,
               k == 2 && d == 3 ? ", .ply and .off" : "", wall_seconds() - t0, ru.ru_maxrss);
        printf("result: %s (exit %d)\n", rc ? "not a closed manifold without inconsistency" : "closed manifold, no inconsistent simplex", rc);
    }
    if (o.json) {
        printf("{\"points\":%zu,\"dim\":%d,\"ambient_dim\":%d,\"simplices\":[", n, k, d);
        for (j = 0; j <= k; j++) printf("%s%zu", j ? "," : "", mc.faces[j]);
        printf("],\"inconsistent_before\":%zu,\"inconsistent\":%zu,\"euler\":%ld,\"manifold\":%s,\"orientable\":%s,"
               "\"components\":%zu,\"bad_facets\":%zu,\"bad_links\":%zu,\"uncertified\":%zu,\"rounds\":%zu,\"moves\":%zu,"
               "\"max_shift\":%.6g,\"max_shift_rel\":%.4f,\"nn_mean\":%.6g,\"star_builds\":%zu,\"seconds_tangents\":%.4f,\"seconds_stars\":%.4f,"
               "\"seconds_fix\":%.4f,\"seconds_check\":%.4f,\"seconds\":%.4f,\"peak_rss_kb\":%ld}\n",
               S.inconsistent_before, S.inconsistent, mc.euler, mc.manifold ? "true" : "false",
               mc.orientable == 1 ? "true" : mc.orientable == 0 ? "false" : "null", mc.components, mc.bad_facets,
               mc.bad_links, S.uncertified, S.rounds, S.moves, S.max_shift, S.max_shift_rel, S.nn_mean, S.star_builds, S.seconds_tangents,
               S.seconds_stars, S.seconds_fix, t_check, S.seconds_tangents + S.seconds_stars + S.seconds_fix,
               ru.ru_maxrss);
    }
out:
    free(simp);
    free(oriented);
    vp_tdc_free(tdc);
    free(pts);
    return rc;
}
