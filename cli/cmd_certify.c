/* voroprobe certify: which of the papers' guarantees hold for a scanned mesh. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_certify.h"
#include "vp_cli.h"
#include "vp_meshio.h"
#include "vp_session.h"
#include "vp_sim_opts.h"
#include "vp_sim_setup.h"
#include "vp_sessionlog.h"

static void certify_usage(FILE *f)
{
    fprintf(f,
        "usage: voroprobe certify LOG|MESH [--eps E] [--reach R] [--interior X,Y,Z]... [--list N]\n"
        "Checks, facet by facet, the hypotheses under which the papers guarantee the mesh\n"
        "(Boissonnat-Guibas-Oudot Thm 2.1; Boissonnat-Oudot loose eps-samples):\n"
        "  H1  the mesh is a 2-manifold without boundary\n"
        "  H2  a vertex on every component of S (each interior point o_i enclosed by the mesh)\n"
        "  H3  every facet has a surface Delaunay ball of radius <= eps\n"
        "  and eps < 0.091 reach(S) when a reach bound is given.\n"
        "From a session LOG the planner is replayed: every facet's ball (centre on a probed\n"
        "surface point) is checked exactly (radius <= eps, empty of samples), and the o_i come\n"
        "from the log. For a bare MESH (PLY/OFF) only necessary conditions of H3 can be checked\n"
        "(circumradius <= eps, Delaunay facet), so H3 is never established; H2 needs --interior.\n"
        "Prints which guarantees hold (ambient isotopy, Hausdorff <= 4.5 diam/reach^2 eps^2,\n"
        "E a 2eps-sample) or exactly which facets, edges or vertices break which hypothesis.\n"
        "  --eps E            the eps to certify (required for a mesh; default for a log: its eps)\n"
        "  --reach R          a lower bound on the reach of the object\n"
        "  --interior X,Y,Z   a point inside a component (repeat per component; mesh only)\n"
        "  --diam D           an upper bound on diam(S) (default: Omega's diameter for a log,\n"
        "                     the bounding-box diagonal for a mesh)\n"
        "  --list N           offenders listed per kind (default 20)\n"
        "Exit status: 0 no hypothesis broken, 1 a hypothesis broken (or an error), 2 usage.\n");
}

static const char *verdict(int v) { return v > 0 ? "holds" : v == 0 ? "FAILS" : "cannot be checked"; }

/* The command line of certify. */
typedef struct certify_args {
    const char *path;
    double eps, reach, diam, interior[VP_PLANNER_MAX_SEEDS][3];
    uint32_t ninterior;
    unsigned long list;
} certify_args_t;

/* -1: parsed; else the exit status (0 after --help, 2 on bad usage). */
static int certify_parse(int argc, char **argv, certify_args_t *o)
{
    int i;
    memset(o, 0, sizeof *o);
    o->list = 20;
    for (i = 1; i < argc; i++) {
        const char *a = argv[i], *val = i + 1 < argc ? argv[i + 1] : NULL;
        char *e;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) { certify_usage(stdout); return 0; }
        if (a[0] != '-') {
            if (o->path) { fprintf(stderr, "certify: one input at a time\n"); return 2; }
            o->path = a;
            continue;
        }
        if (strcmp(a, "--eps") && strcmp(a, "--reach") && strcmp(a, "--interior") && strcmp(a, "--list") &&
            strcmp(a, "--diam")) {
            fprintf(stderr, "certify: unknown option %s (see --help)\n", a);
            return 2;
        }
        if (!val) { fprintf(stderr, "certify: %s needs a value\n", a); return 2; }
        i++;
        if (!strcmp(a, "--interior")) {
            double *p;
            if (o->ninterior == VP_PLANNER_MAX_SEEDS) { fprintf(stderr, "certify: at most %d interior points\n", VP_PLANNER_MAX_SEEDS); return 2; }
            p = o->interior[o->ninterior];
            if (sscanf(val, "%lf,%lf,%lf", &p[0], &p[1], &p[2]) != 3 || !isfinite(p[0] + p[1] + p[2])) {
                fprintf(stderr, "certify: --interior takes X,Y,Z, not '%s'\n", val);
                return 2;
            }
            o->ninterior++;
            continue;
        }
        if (!strcmp(a, "--list")) {
            unsigned long long n;
            if (vp_parse_count(val, 1000000000ull, &n)) { fprintf(stderr, "certify: --list takes a count, not '%s'\n", val); return 2; }
            o->list = (unsigned long)n;
            continue;
        }
        {
            double v = strtod(val, &e);
            if (e == val || *e || !(v > 0) || !isfinite(v)) { fprintf(stderr, "certify: %s takes a positive number, not '%s'\n", a, val); return 2; }
            if (!strcmp(a, "--eps")) o->eps = v;
            else if (!strcmp(a, "--reach")) o->reach = v;
            else o->diam = v;
        }
    }
    if (!o->path) { fprintf(stderr, "certify: give a LOG or MESH file (see --help)\n"); return 2; }
    return -1;
}

/* What certify checks, and what it holds while it does. */
typedef struct certify_input {
    vp_mesh_t m;
    vp_sessionlog_t L;
    vp_replay_t R;
    double *centers, *samples;
    size_t nsamples, ncut; /* samples; facets of cut tets (vp_planner_facet returns 2) */
    int complete;
} certify_input_t;

/* A session log: replayed; the mesh, every facet's ball and the samples from the planner.
 * -1: ready; else the exit status. */
static int certify_from_log(certify_args_t *o, certify_input_t *in, vp_cert_config_t *cfg)
{
    const vp_dt_t *dt;
    uint32_t s, nf = 0;
    const vp_planner_config_t *pc;
    char err[1400];
    int st;
    if (o->ninterior) { fprintf(stderr, "certify: --interior is for meshes; a log has its own\n"); return 2; }
    st = vp_sessionlog_load(&in->L, o->path, err, sizeof err);
    if (st == VP_OK) st = vp_replay_open(&in->R, &in->L, 0, err, sizeof err);
    if (st == VP_OK) st = vp_replay_run(&in->R, &in->L, in->L.n, err, sizeof err);
    if (st == VP_OK && (st = vp_session_mesh(in->R.pl, &in->m)) != VP_OK) snprintf(err, sizeof err, "mesh: %s", vp_strerror(st));
    if (st != VP_OK) { fprintf(stderr, "certify: %s\n", err); return 1; }
    if (in->L.status != VP_OK) {
        char stop[600];
        vp_sessionlog_stop_text(&in->L, stop, sizeof stop);
        fprintf(stderr, "certify: %s: %s\n", o->path, stop);
    }
    in->complete = in->R.done;
    pc = &in->L.header.cfg;
    if (o->eps <= 0) o->eps = pc->eps;
    if (o->diam <= 0) {
        if (pc->omega_kind == VP_OMEGA_BALL) o->diam = 2.0 * pc->omega_radius;
        else o->diam = sqrt((pc->omega_hi[0] - pc->omega_lo[0]) * (pc->omega_hi[0] - pc->omega_lo[0]) +
                            (pc->omega_hi[1] - pc->omega_lo[1]) * (pc->omega_hi[1] - pc->omega_lo[1]) +
                            (pc->omega_hi[2] - pc->omega_lo[2]) * (pc->omega_hi[2] - pc->omega_lo[2]));
    }
    /* the facets' balls, in the mesh's facet order (the planner's slots) */
    in->centers = malloc((in->m.nt + 1) * 3 * sizeof *in->centers);
    dt = vp_planner_dt(in->R.pl);
    in->samples = malloc(((size_t)dt->nvert + 1) * 3 * sizeof *in->samples);
    if (!in->centers || !in->samples) { fprintf(stderr, "certify: out of memory\n"); return 1; }
    for (s = 0; s < vp_planner_facet_slots(in->R.pl); s++) {
        uint32_t v[3];
        int k = vp_planner_facet(in->R.pl, s, v, NULL, in->centers + 3 * (size_t)nf);
        if (k) nf++;
        if (k == 2) in->ncut++;
    }
    for (s = 0; s < dt->nvert; s++)
        if (vp_dt_vertex(dt, s)->tet != VP_DT_NONE) memcpy(in->samples + 3 * in->nsamples++, vp_dt_point(dt, s), 3 * sizeof(double));
    if (nf != in->m.nt) { fprintf(stderr, "certify: internal error: %u balls for %zu facets\n", nf, in->m.nt); return 1; }
    cfg->interior = (const double (*)[3])pc->interior;
    cfg->ninterior = pc->ninterior;
    cfg->centers = in->centers;
    cfg->samples = in->samples;
    cfg->nsamples = in->nsamples;
    return -1;
}

/* A bare mesh (PLY/OFF): diam from its bounding box unless given. -1: ready; else the exit status. */
static int certify_from_mesh(certify_args_t *o, certify_input_t *in, vp_cert_config_t *cfg)
{
    vp_mesh_t *m = &in->m;
    size_t v;
    double lo[3] = { HUGE_VAL, HUGE_VAL, HUGE_VAL }, hi[3] = { -HUGE_VAL, -HUGE_VAL, -HUGE_VAL };
    char err[1400];
    if (o->eps <= 0) { fprintf(stderr, "certify: --eps is required for a mesh (see --help)\n"); return 2; }
    if (vp_mesh_read_file(o->path, m, err, sizeof err) != VP_OK) { fprintf(stderr, "certify: %s\n", err); return 1; }
    for (v = 0; v < m->nv; v++) {
        int k;
        for (k = 0; k < 3; k++) {
            if (m->xyz[3 * v + (size_t)k] < lo[k]) lo[k] = m->xyz[3 * v + (size_t)k];
            if (m->xyz[3 * v + (size_t)k] > hi[k]) hi[k] = m->xyz[3 * v + (size_t)k];
        }
    }
    if (o->diam <= 0 && m->nv)
        o->diam = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
    cfg->interior = o->ninterior ? (const double (*)[3])o->interior : NULL;
    cfg->ninterior = o->ninterior;
    return -1;
}

/* The verdict on each hypothesis and the guarantees that follow. Returns the exit status. */
static int certify_report(const certify_args_t *o, const certify_input_t *in, const vp_cert_config_t *cfg,
                          const vp_cert_t *cp, int fromlog)
{
    const vp_cert_t c = *cp;
    double eps = o->eps, reach = o->reach, diam = o->diam;
    printf("H1  2-manifold without boundary: %s", verdict(c.h1));
    if (c.h1 > 0) printf(" (%zu edges, each in exactly 2 facets; every vertex link one cycle; %d component(s))\n", c.edges, c.components);
    else printf(" (%zu boundary edges, %zu non-manifold edges, %zu non-manifold vertices, %zu degenerate facets)\n",
                c.boundary_edges, c.nonmanifold_edges, c.bad_vertices, c.degenerate_facets);
    printf("H2  a vertex on every component: %s", verdict(c.h2));
    if (c.h2 > 0) printf(" (all %u interior point(s) enclosed by the mesh)\n", cfg->ninterior);
    else if (c.h2 == 0) printf(" (%u of %u interior point(s) not enclosed)\n", c.h2_missing, cfg->ninterior);
    else printf(" (no interior points: give --interior X,Y,Z per component; the mesh has %d component(s))\n", c.components);
    printf("H3  a surface Delaunay ball of radius <= eps on every facet: %s", verdict(c.h3));
    if (fromlog) {
        if (c.h3 > 0) printf(" (all %zu balls, exactly: largest radius %.9g at facet %zu; each ball empty of the %zu samples)\n",
                             in->m.nt, c.max_radius, c.max_radius_facet, in->nsamples);
        else printf(" (%zu ball(s) larger than eps, %zu not empty; largest radius %.9g at facet %zu)\n",
                    c.big_balls, c.open_balls, c.max_radius, c.max_radius_facet);
        printf("    ball centres are probed surface points on the facets' Voronoi edges (largest radius spread %.2g)\n",
               c.max_spread);
        if (in->ncut)
            printf("    except %zu facet(s) of tets cut off where the inside touched itself below the manifold floor: "
                   "their balls are their circumballs\n", in->ncut);
    } else {
        if (c.h3 < 0)
            printf(": the ball centres on S are unknown for a bare mesh; necessary conditions hold: every circumradius "
                   "<= eps (largest %.9g, %zu within rounding) and every facet Delaunay for the mesh vertices (exact)\n",
                   c.max_radius, c.undecided);
        else
            printf(" (%zu facet(s) with circumradius > eps, %zu not Delaunay)\n", c.big_circumradius, c.not_delaunay);
    }
    if (c.reach_ok > 0) printf("    eps < 0.091 reach: holds (%.9g < %.9g)\n", eps, 0.091 * reach);
    else if (c.reach_ok == 0) printf("    eps < 0.091 reach: FAILS (%.9g >= 0.091 * %.9g = %.9g)\n", eps, reach, 0.091 * reach);
    else printf("    eps < 0.091 reach: not checked (no --reach): it needs reach(S) > %.9g\n", eps / 0.091);
    if (c.eps_prime >= 0.0)
        printf("    non-uniform (paper 002): every ball has r <= eps' dM(c) with eps' = %.4g (largest at facet %zu; dM "
               "estimated from the samples' poles, an estimate, not a bound; 0.091 is the paper's limit)\n",
               c.eps_prime, c.eps_prime_facet);
    if (c.h1 > 0 && c.h2 > 0 && c.h3 > 0) {
        if (c.reach_ok > 0) {
            printf("guarantees (000 Theorem 2.1): the mesh is ambient isotopic to S; Hausdorff distance <= 4.5 diam/reach^2 "
                   "eps^2 = %.6g (diam <= %.6g); the samples are a 2eps-sample of S (every point of S within %.6g of one)\n",
                   c.hausdorff_bound, diam, 2 * eps);
        } else if (c.reach_ok == 0) {
            printf("guarantees: none: H1-H3 hold but eps is too large for the given reach (the papers need "
                   "eps < 0.091 reach)\n");
        } else {
            printf("guarantees: conditional: IF reach(S) > %.9g then the mesh is ambient isotopic to S, the Hausdorff "
                   "distance is <= 4.5 diam/reach^2 eps^2 (diam <= %.6g), and the samples are a 2eps-sample of S\n",
                   eps / 0.091, diam);
        }
    } else if (c.h1 == 0 || c.h2 == 0 || c.h3 == 0 || c.reach_ok == 0) {
        printf("guarantees: none (a hypothesis fails: see above)\n");
    } else {
        printf("guarantees: not established (some hypotheses cannot be checked on this input)\n");
    }
    return (c.h1 == 0 || c.h2 == 0 || c.h3 == 0 || c.reach_ok == 0) ? 1 : 0;
}

int vp_cli_certify(int argc, char **argv)
{
    certify_args_t o;
    certify_input_t in;
    vp_cert_config_t cfg;
    vp_cert_t c;
    int st, fromlog, rc;
    if ((rc = certify_parse(argc, argv, &o)) >= 0) return rc;
    fromlog = vp_sessionlog_is_log(o.path);
    memset(&in, 0, sizeof in);
    vp_mesh_init(&in.m);
    in.complete = 1;
    memset(&cfg, 0, sizeof cfg);
    rc = fromlog ? certify_from_log(&o, &in, &cfg) : certify_from_mesh(&o, &in, &cfg);
    if (rc < 0) {
        cfg.eps = o.eps;
        cfg.reach = o.reach;
        cfg.diam = o.diam;
        cfg.max_list = o.list;
        printf("certify %s: %s; %zu facets, %zu vertices; eps %.9g%s\n", o.path,
               fromlog ? (in.complete ? "session log, complete (DONE)" : "session log, INCOMPLETE session") : "bare mesh",
               in.m.nt, in.m.nv, o.eps, fromlog ? "" : "");
        fflush(stdout);
        if (in.m.nt == 0) {
            /* a session stopped before its first facet (or an empty mesh file) */
            printf("certify: nothing to certify: %s\n", fromlog ? "the session has no facet yet" : "the mesh has no facet");
            rc = 1;
        } else {
            st = vp_certify(&in.m, &cfg, &c, stdout);
            if (st != VP_OK) { fprintf(stderr, "certify: %s\n", vp_strerror(st)); rc = 1; }
            else rc = certify_report(&o, &in, &cfg, &c, fromlog);
        }
    }
    free(in.centers);
    free(in.samples);
    vp_mesh_free(&in.m);
    vp_replay_close(&in.R);
    vp_sessionlog_free(&in.L);
    return rc;
}
