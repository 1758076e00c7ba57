/* voroprobe replay / log / mesh: session logs on the PC. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_cli.h"
#include "vp_json.h"
#include "vp_logverify.h"
#include "vp_meshcheck.h"
#include "vp_meshio.h"
#include "vp_note.h"
#include "vp_render.h"
#include "vp_session.h"
#include "vp_sim_opts.h"
#include "vp_sim_setup.h"
#include "vp_sessionlog.h"

/* ---------- shared ---------- */

typedef struct logjob {
    const char *log, *out;
    const char *png;       /* --png: a picture of the mesh (host/vp_render) */
    size_t arena;          /* 0: the header's */
    unsigned long upto;    /* replay only the first N records (0: all) */
    int quiet;
    int samples;           /* replay --samples: round by round, PREFIX.samples.csv */
    unsigned kept_old, removed_old, nsamples; /* ... its figures */
    vp_sessionlog_t L;
    vp_replay_t R;
    vp_mesh_t mesh;
} logjob_t;

static int replay_samples(logjob_t *j, const char *cmd);

/* Loads and replays (with --samples, round by round); prints the load problem (if any) to
 * stderr. 0 ok, 1 failure. */
static int load_and_replay(logjob_t *j, const char *cmd)
{
    char err[1400], stop[600];
    int st = vp_sessionlog_load(&j->L, j->log, err, sizeof err);
    if (st != VP_OK) { fprintf(stderr, "%s: %s\n", cmd, err); return 1; }
    if (j->L.status != VP_OK) {
        vp_sessionlog_stop_text(&j->L, stop, sizeof stop);
        fprintf(stderr, "%s: %s: %s\n", cmd, j->log, stop);
    }
    st = vp_replay_open(&j->R, &j->L, j->arena, err, sizeof err);
    if (st == VP_OK && j->samples) {
        if (replay_samples(j, cmd)) return 1;
    } else if (st == VP_OK)
        st = vp_replay_run(&j->R, &j->L, j->upto ? (uint32_t)j->upto : j->L.n, err, sizeof err);
    if (st != VP_OK) { fprintf(stderr, "%s: %s: %s\n", cmd, j->log, err); return 1; }
    vp_mesh_init(&j->mesh);
    st = vp_session_mesh(j->R.pl, &j->mesh);
    if (st != VP_OK) { fprintf(stderr, "%s: mesh: %s\n", cmd, vp_strerror(st)); return 1; }
    return 0;
}

/* --png: four views of the mesh; 0 written (or not asked), 1 failure (said) */
static int job_png(const logjob_t *j, const char *cmd)
{
    char err[600];
    if (!j->png || vp_render_png(&j->mesh, NULL, j->png, err, sizeof err) == VP_OK) return 0;
    fprintf(stderr, "%s: %s\n", cmd, err);
    return 1;
}

static void job_free(logjob_t *j)
{
    vp_mesh_free(&j->mesh);
    vp_replay_close(&j->R);
    vp_sessionlog_free(&j->L);
}

/* Common options; 0 taken, 1 not ours, -1 bad. */
static int job_option(logjob_t *j, int argc, char **argv, int *i, const char *cmd)
{
    const char *a = argv[*i], *val = *i + 1 < argc ? argv[*i + 1] : NULL;
    if (!strcmp(a, "--quiet")) { j->quiet = 1; return 0; }
    if (strcmp(a, "--out") && strcmp(a, "--arena") && strcmp(a, "--upto") && strcmp(a, "--png")) {
        if (a[0] == '-' && a[1]) return 1;
        if (j->log) { fprintf(stderr, "%s: one log at a time ('%s' and '%s')\n", cmd, j->log, a); return -1; }
        j->log = a;
        return 0;
    }
    if (!val) { fprintf(stderr, "%s: %s needs a value\n", cmd, a); return -1; }
    (*i)++;
    if (!strcmp(a, "--out")) j->out = val;
    else if (!strcmp(a, "--png")) j->png = val;
    else if (!strcmp(a, "--arena")) {
        if (vp_parse_size(val, &j->arena) || j->arena == 0) { fprintf(stderr, "%s: --arena: bad size '%s'\n", cmd, val); return -1; }
    } else {
        unsigned long long n;
        if (vp_parse_count(val, 0xffffffffull, &n) || n == 0) {
            fprintf(stderr, "%s: --upto takes a count of records (at least 1), not '%s'\n", cmd, val);
            return -1;
        }
        j->upto = (unsigned long)n;
    }
    return 0;
}

/* PREFIX + the longest extension fits a path: 0, or 2 (usage) after saying why. */
static int check_out(const char *prefix, const char *ext, const char *cmd)
{
    char path[VP_PATH_MAX], err[300];
    if (vp_path_cat(path, sizeof path, prefix, ext, err, sizeof err) == VP_OK) return 0;
    fprintf(stderr, "%s: %s\n", cmd, err);
    return 2;
}

static int write_mesh(const vp_mesh_t *m, const char *prefix, const char *ext, int format, const char *cmd)
{
    char path[VP_PATH_MAX], err[300];
    if (vp_path_cat(path, sizeof path, prefix, ext, err, sizeof err) != VP_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err);
        return 1;
    }
    if (vp_mesh_write_file(m, path, format) != VP_OK) {
        fprintf(stderr, "%s: cannot write %s: %s\n", cmd, path, strerror(errno));
        return 1;
    }
    return 0;
}

/* ---------- replay ---------- */

static void replay_usage(FILE *f)
{
    fprintf(f,
        "usage: voroprobe replay LOG --out PREFIX [--arena BYTES] [--upto N] [--quiet]\n"
        "Feeds the logged probe results back through the planner the header describes, checks\n"
        "that every command it issues equals the logged one bit for bit, and writes the mesh it\n"
        "has at the end of the log: PREFIX.ply (binary) and PREFIX.off, byte-identical to what the\n"
        "device or `sim` wrote. A damaged or torn tail is reported (record number, byte offset)\n"
        "and the valid records before it are replayed.\n"
        "  --out PREFIX   output files (required)\n"
        "  --arena BYTES  planner arena (default: the size in the log header)\n"
        "  --upto N       replay only the first N records\n"
        "  --png FILE     also a picture of the mesh (four views, drawn in software)\n"
        "  --samples      also PREFIX.samples.csv: every sample the session had, with the round it\n"
        "                 came in and the one a re-scan removed it in (0: the first scan; K: after\n"
        "                 the K-th RESCAN event, a re-scan or a tracking round; removed empty: a\n"
        "                 sample at the end). A sample that moved is one removed and one added.\n"
        "  --quiet        no summary\n");
}

/* --samples: the log replayed round by round (up to each RESCAN event, then to the end); each
 * sample's first round and the first round it is missing from. 0 ok, 1 failure (said). */
static int replay_samples(logjob_t *j, const char *cmd)
{
    char err[1400], path[VP_PATH_MAX];
    uint32_t i, cap = 0, *added = NULL, *removed = NULL, round = 0;
    const vp_dt_t *dt;
    FILE *f;
    int st = VP_OK;
    if (vp_path_cat(path, sizeof path, j->out, ".samples.csv", err, sizeof err) != VP_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err);
        return 1;
    }
    for (i = 0; i <= j->L.n && st == VP_OK; i++) {
        vp_logfmt_record_t rec;
        uint32_t v, n;
        int last = i == j->L.n;
        if (!last && (vp_sessionlog_record(&j->L, i, &rec) != VP_OK || rec.type != VP_LOGFMT_EVENT ||
                      rec.event != VP_LOGFMT_EV_RESCAN))
            continue;
        /* the session up to this RESCAN event (or to the end): round `round` ends */
        st = vp_replay_run(&j->R, &j->L, i, err, sizeof err);
        if (st != VP_OK) break;
        dt = vp_planner_dt(j->R.pl);
        n = dt->nvert;
        if (n > cap) {
            uint32_t *a = realloc(added, n * sizeof *a), *b;
            if (a) added = a;
            b = a ? realloc(removed, n * sizeof *b) : NULL;
            if (!a || !b) { st = VP_ENOMEM; break; }
            removed = b;
            for (v = cap; v < n; v++) { added[v] = round; removed[v] = UINT32_MAX; }
            cap = n;
        }
        for (v = 0; v < n; v++)
            if (removed[v] == UINT32_MAX && vp_dt_vertex(dt, v)->tet == VP_DT_NONE) removed[v] = round;
        round++;
    }
    if (st != VP_OK) {
        fprintf(stderr, "%s: %s: %s\n", cmd, j->log, st != VP_ENOMEM ? err : vp_strerror(st));
        free(added); free(removed);
        return 1;
    }
    f = fopen(path, "w");
    if (!f) { fprintf(stderr, "%s: cannot write %s: %s\n", cmd, path, strerror(errno)); free(added); free(removed); return 1; }
    fprintf(f, "sample,x,y,z,added,removed\n");
    j->kept_old = j->removed_old = j->nsamples = 0;
    dt = vp_planner_dt(j->R.pl);
    for (i = 0; i < cap; i++) {
        const double *p = vp_dt_point(dt, i);
        fprintf(f, "%u,%.17g,%.17g,%.17g,%u,", i, p[0], p[1], p[2], added[i]);
        if (removed[i] != UINT32_MAX) fprintf(f, "%u\n", removed[i]);
        else fprintf(f, "\n");
        if (removed[i] == UINT32_MAX) j->nsamples++;
        if (round > 1 && added[i] < round - 1) {
            if (removed[i] == UINT32_MAX) j->kept_old++;
            else if (removed[i] == round - 1) j->removed_old++;
        }
    }
    free(added);
    free(removed);
    if (fclose(f) != 0) { fprintf(stderr, "%s: cannot write %s: %s\n", cmd, path, strerror(errno)); return 1; }
    return 0;
}

int vp_cli_replay(int argc, char **argv)
{
    logjob_t j;
    int i, rc;
    memset(&j, 0, sizeof j);
    vp_mesh_init(&j.mesh);
    for (i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) { replay_usage(stdout); return 0; }
        if (!strcmp(argv[i], "--samples")) { j.samples = 1; continue; }
        rc = job_option(&j, argc, argv, &i, "replay");
        if (rc < 0) return 2;
        if (rc > 0) { fprintf(stderr, "replay: unknown option %s (see --help)\n", argv[i]); return 2; }
    }
    if (!j.log || !j.out) { fprintf(stderr, "replay: give LOG and --out PREFIX (see --help)\n"); return 2; }
    if (check_out(j.out, j.samples ? ".samples.csv" : ".ply", "replay")) return 2;
    if (j.samples && j.upto) { fprintf(stderr, "replay: --samples replays the whole log (not with --upto)\n"); return 2; }
    rc = load_and_replay(&j, "replay");
    if (rc == 0) rc = write_mesh(&j.mesh, j.out, ".ply", VP_MESH_PLY_BIN, "replay") ||
                      write_mesh(&j.mesh, j.out, ".off", VP_MESH_OFF, "replay") || job_png(&j, "replay");
    if (rc == 0 && !j.quiet) {
        printf("replayed %u records of %s (%llu probes, %llu hits, %llu moves): every command equal to the logged one\n",
               j.R.applied, j.log, (unsigned long long)j.R.probes, (unsigned long long)j.R.hits,
               (unsigned long long)j.R.moves);
        printf("session %s; mesh: %zu vertices, %zu facets\n",
               j.R.done ? "complete (DONE)" : "incomplete (no DONE): the mesh is the one at the end of the log",
               j.mesh.nv, j.mesh.nt);
        if (j.samples && j.R.rescans > 0)
            printf("samples: %u at the end; of those before the last RESCAN event, %u still samples, %u removed "
                   "(a sample that moved: removed, and added in the last round)\n", j.nsamples, j.kept_old, j.removed_old);
        printf("wrote %s.ply and %s.off%s%s%s\n", j.out, j.out, j.samples ? " and " : "", j.samples ? j.out : "",
               j.samples ? ".samples.csv" : "");
    }
    job_free(&j);
    return rc;
}

/* ---------- mesh ---------- */

static void mesh_usage(FILE *f)
{
    fprintf(f,
        "usage: voroprobe mesh LOG --out PREFIX [--ascii] [--off] [--points] [--upto N]\n"
        "The mesh of a logged session. Complete session: the final mesh. Incomplete one (the\n"
        "device stopped early): the visible restricted Delaunay triangulation so far, with the\n"
        "parts not yet closed reported as holes (boundary edges and loops), never patched.\n"
        "  --out PREFIX   write PREFIX.ply (binary little-endian PLY; required)\n"
        "  --ascii        ASCII PLY instead of binary\n"
        "  --off          also write PREFIX.off\n"
        "  --points       also write PREFIX.points.ply: every probed surface point, with a unit\n"
        "                 normal pointing back to the probe's origin (binary or --ascii)\n"
        "  --upto N       only the first N records (the session as it was then)\n"
        "  --png FILE     also a picture of the mesh (four views, drawn in software)\n"
        "  --arena BYTES  planner arena (default: the size in the log header)\n"
        "  --quiet        no summary\n");
}

/* Every hit as a point with the unit normal towards its probe origin. */
/* A record that carries a reading (a PROBE, or a RAY of its frame): origin, direction, result. */
static int is_reading(int type) { return type == VP_LOGFMT_PROBE || type == VP_LOGFMT_RAY; }

static int write_points(const vp_sessionlog_t *L, uint32_t upto, const char *path, int ascii, size_t *count)
{
    FILE *f = fopen(path, "wb");
    uint32_t i;
    size_t n = 0;
    int k;
    if (!f) return VP_EIO;
    for (i = 0; i < upto; i++) {
        vp_logfmt_record_t r;
        if (vp_sessionlog_record(L, i, &r) == VP_OK && is_reading(r.type) && r.hit == 1) n++;
    }
    fprintf(f, "ply\nformat %s 1.0\ncomment voroprobe probed points; normals point to the probe origins\n"
            "element vertex %zu\nproperty double x\nproperty double y\nproperty double z\n"
            "property double nx\nproperty double ny\nproperty double nz\nend_header\n",
            ascii ? "ascii" : "binary_little_endian", n);
    for (i = 0; i < upto; i++) {
        vp_logfmt_record_t r;
        double v[6], len;
        if (vp_sessionlog_record(L, i, &r) != VP_OK || !is_reading(r.type) || r.hit != 1) continue;
        len = sqrt(r.dir[0] * r.dir[0] + r.dir[1] * r.dir[1] + r.dir[2] * r.dir[2]);
        for (k = 0; k < 3; k++) {
            v[k] = r.origin[k] + r.dist * r.dir[k];
            v[3 + k] = len > 0 ? -r.dir[k] / len : 0.0;
        }
        if (ascii) {
            fprintf(f, "%.17g %.17g %.17g %.17g %.17g %.17g\n", v[0], v[1], v[2], v[3], v[4], v[5]);
        } else {
            unsigned char b[48];
            for (k = 0; k < 6; k++) {
                uint64_t u;
                int q;
                memcpy(&u, &v[k], 8);
                for (q = 0; q < 8; q++) b[8 * k + q] = (unsigned char)(u >> (8 * q));
            }
            fwrite(b, 1, sizeof b, f);
        }
    }
    *count = n;
    k = ferror(f);
    return fclose(f) == 0 && !k ? VP_OK : VP_EIO;
}

int vp_cli_mesh(int argc, char **argv)
{
    logjob_t j;
    int i, rc, ascii = 0, off = 0, points = 0;
    memset(&j, 0, sizeof j);
    vp_mesh_init(&j.mesh);
    for (i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) { mesh_usage(stdout); return 0; }
        if (!strcmp(a, "--ascii")) { ascii = 1; continue; }
        if (!strcmp(a, "--off")) { off = 1; continue; }
        if (!strcmp(a, "--points")) { points = 1; continue; }
        rc = job_option(&j, argc, argv, &i, "mesh");
        if (rc < 0) return 2;
        if (rc > 0) { fprintf(stderr, "mesh: unknown option %s (see --help)\n", a); return 2; }
    }
    if (!j.log || !j.out) { fprintf(stderr, "mesh: give LOG and --out PREFIX (see --help)\n"); return 2; }
    if (check_out(j.out, points ? ".points.ply" : ".ply", "mesh")) return 2;
    rc = load_and_replay(&j, "mesh");
    if (rc == 0) rc = write_mesh(&j.mesh, j.out, ".ply", ascii ? VP_MESH_PLY_ASCII : VP_MESH_PLY_BIN, "mesh");
    if (rc == 0 && off) rc = write_mesh(&j.mesh, j.out, ".off", VP_MESH_OFF, "mesh");
    if (rc == 0) rc = job_png(&j, "mesh");
    if (rc == 0) {
        vp_meshcheck_t c;
        size_t npts = 0;
        char path[VP_PATH_MAX], perr[300];
        if (points) {
            vp_path_cat(path, sizeof path, j.out, ".points.ply", perr, sizeof perr);   /* checked above */
            if (write_points(&j.L, j.R.applied, path, ascii, &npts) != VP_OK) {
                fprintf(stderr, "mesh: cannot write %s: %s\n", path, strerror(errno));
                rc = 1;
            }
        }
        if (rc == 0 && !j.quiet && vp_meshcheck_analyze(&j.mesh, &c) == VP_OK) {
            vp_planner_stats_t st;
            size_t loops = 0;
            int k;
            for (k = 0; k < c.components; k++) loops += c.comp[k].boundary_loops;
            vp_planner_get_stats(j.R.pl, &st);
            printf("%s: %u records replayed (%llu probes, %llu hits), session %s\n", j.log, j.R.applied,
                   (unsigned long long)j.R.probes, (unsigned long long)j.R.hits,
                   j.R.done ? "complete (DONE)" : "INCOMPLETE (no DONE)");
            printf("mesh: %zu vertices, %zu facets, %d component(s); ", j.mesh.nv, j.mesh.nt, c.components);
            if (c.closed_manifold)
                printf("closed 2-manifold, genus %d, no holes\n", c.genus);
            else
                printf("%zu hole(s): %zu boundary edges in %zu boundary loop(s)%s (not patched)\n",
                       loops, c.boundary_edges, loops,
                       c.nonmanifold_edges ? ", and non-manifold edges" : "");
            printf("largest surface Delaunay ball %.6g (eps %.6g), %u bad ball(s) left%s\n", st.max_ball,
                   j.L.header.cfg.eps, st.bad_balls, j.R.done ? "" : " (`certify` names every open edge and large ball)");
            printf("wrote %s.ply%s%s%s\n", j.out, off ? " and " : "", off ? j.out : "", off ? ".off" : "");
            if (points) printf("wrote %s (%zu points with normals)\n", path, npts);
            vp_meshcheck_free(&c);
        }
    }
    job_free(&j);
    return rc;
}

/* ---------- log dump / check ---------- */

static void log_usage(FILE *f)
{
    fprintf(f,
        "usage: voroprobe log dump LOG [--jsonl | --csv]\n"
        "       voroprobe log check LOG [--no-replay]\n"
        "       voroprobe log verify LOG [--json]\n"
        "dump   prints the header and every valid record: text (default), JSON lines (one\n"
        "       object per line: the header first), or CSV (one row per record). Numbers are\n"
        "       printed with 17 significant digits (exact doubles).\n"
        "check  verifies the header, every record's length, CRC and sequence number, replays\n"
        "       the planner over the valid records (unless --no-replay), and says what is\n"
        "       recoverable. Exit status 0: intact; 1: damaged (the valid part is named).\n"
        "verify checks from the log alone, without the planner, that the device moved only\n"
        "       through space proven free before each move: outside Omega (dOmega included),\n"
        "       or on the free part of an earlier probe fired from where the device stood (a\n"
        "       hit frees origin .. dist - noise_tol, a miss origin .. range, too close nothing).\n"
        "       The device starts at the header's start; events do not move it. Names each\n"
        "       move not proven free (record number, seq, from, to, the unproven part; the first\n"
        "       20) and each probe fired from elsewhere; a damaged or torn log is verified up to\n"
        "       its last good record. Tolerance: 1e-9 x Omega's diameter. --json ends with\n"
        "       {moves, probes, unproven_moves, first_unproven_record, probes_off_position,\n"
        "       records, ok, ...}. Exit status 0: every move proven free and every probe from\n"
        "       the device's position; 1: not (a violation named); 3: the log cannot be read\n"
        "       (no file, not a session log, damaged header, newer version).\n");
}

static void json_num(FILE *f, double v)
{
    if (isfinite(v)) fprintf(f, "%.17g", v);
    else fprintf(f, "null");
}

static void json_vec(FILE *f, const double *v)
{
    fputc('[', f); json_num(f, v[0]); fputc(',', f); json_num(f, v[1]); fputc(',', f); json_num(f, v[2]); fputc(']', f);
}

static const char *units_name(uint32_t u)
{
    return u == VP_LOGFMT_UNITS_M ? "m" : u == VP_LOGFMT_UNITS_MM ? "mm" : u == VP_LOGFMT_UNITS_INCH ? "inch" : "none";
}

static const char *type_str(int t)
{
    return t == VP_LOGFMT_PROBE ? "probe" : t == VP_LOGFMT_RAY ? "ray" : t == VP_LOGFMT_MOVE ? "move" : "event";
}

static void dump_header_text(const vp_logfmt_header_t *h, FILE *f)
{
    const vp_planner_config_t *c = &h->cfg;
    uint32_t i;
    fprintf(f, "# voroprobe session log, format version %u, units %s, board '%s'\n", h->version,
            units_name(h->units), h->board);
    fprintf(f, "# note: %s\n", h->note);
    fprintf(f, "# eps %.17g, ", c->eps);
    if (c->omega_kind == VP_OMEGA_BALL)
        fprintf(f, "Omega ball centre %.17g %.17g %.17g radius %.17g\n", c->omega_center[0], c->omega_center[1],
                c->omega_center[2], c->omega_radius);
    else
        fprintf(f, "Omega box %.17g %.17g %.17g .. %.17g %.17g %.17g\n", c->omega_lo[0], c->omega_lo[1],
                c->omega_lo[2], c->omega_hi[0], c->omega_hi[1], c->omega_hi[2]);
    for (i = 0; i < c->ninterior; i++)
        fprintf(f, "# interior point o_%u: %.17g %.17g %.17g\n", i, c->interior[i][0], c->interior[i][1], c->interior[i][2]);
    fprintf(f, "# start %.17g %.17g %.17g, max range %.17g, noise tolerance %.17g, clearance %.17g\n",
            c->start[0], c->start[1], c->start[2], c->max_range, c->noise_tol, c->clearance);
    fprintf(f, "# angle bound %.17g, confirm misses %u, planner flags 0x%x, arena %llu bytes\n", c->min_angle,
            c->confirm_misses, c->flags, (unsigned long long)h->arena_bytes);
    if (c->line_rays) fprintf(f, "# line laser: up to %u more rays per probe\n", c->line_rays);
    if (c->proof_life) fprintf(f, "# proofs' life: %u commands (older proofs are probed again before a move)\n", c->proof_life);
    if (c->min_feature > 0)
        fprintf(f, "# tubes: min feature %.17g, feature margin %.17g (the device with a body may move inside Omega)\n",
                c->min_feature, c->feature_margin);
    if (h->version >= 6u)
        fprintf(f, "# moves weighed by machine time: s per unit x %.17g y %.17g z %.17g, per radian pan %.17g tilt "
                   "%.17g; pan travel %.17g..%.17g rad\n", c->axis_time[0], c->axis_time[1], c->axis_time[2],
                c->axis_time[3], c->axis_time[4], c->pan_travel[0], c->pan_travel[1]);
}

static void dump_header_json(const vp_logfmt_header_t *h, FILE *f)
{
    const vp_planner_config_t *c = &h->cfg;
    uint32_t i;
    fprintf(f, "{\"header\":{\"version\":%u,\"units\":\"%s\",\"board\":", h->version, units_name(h->units));
    vp_json_str(f, h->board, 0);
    fprintf(f, ",\"note\":");
    vp_json_str(f, h->note, 0);
    fprintf(f, ",\"eps\":"); json_num(f, c->eps);
    fprintf(f, ",\"omega\":\"%s\"", c->omega_kind == VP_OMEGA_BALL ? "ball" : "box");
    fprintf(f, ",\"omega_lo\":"); json_vec(f, c->omega_lo);
    fprintf(f, ",\"omega_hi\":"); json_vec(f, c->omega_hi);
    fprintf(f, ",\"omega_center\":"); json_vec(f, c->omega_center);
    fprintf(f, ",\"omega_radius\":"); json_num(f, c->omega_radius);
    fprintf(f, ",\"interior\":[");
    for (i = 0; i < c->ninterior; i++) { if (i) fputc(',', f); json_vec(f, c->interior[i]); }
    fprintf(f, "],\"start\":"); json_vec(f, c->start);
    fprintf(f, ",\"max_range\":"); json_num(f, c->max_range);
    fprintf(f, ",\"noise_tol\":"); json_num(f, c->noise_tol);
    fprintf(f, ",\"clearance\":"); json_num(f, c->clearance);
    fprintf(f, ",\"min_angle\":"); json_num(f, c->min_angle);
    if (c->line_rays) fprintf(f, ",\"line_rays\":%u", c->line_rays);
    if (c->proof_life) fprintf(f, ",\"proof_life\":%u", c->proof_life);
    if (c->min_feature > 0) {
        fprintf(f, ",\"min_feature\":"); json_num(f, c->min_feature);
        fprintf(f, ",\"feature_margin\":"); json_num(f, c->feature_margin);
    }
    if (h->version >= 6u) {
        fprintf(f, ",\"axis_time\":[");
        for (i = 0; i < VP_PLANNER_AXES; i++) { if (i) fputc(',', f); json_num(f, c->axis_time[i]); }
        fprintf(f, "],\"pan_travel\":["); json_num(f, c->pan_travel[0]);
        fputc(',', f); json_num(f, c->pan_travel[1]);
        fputc(']', f);
    }
    fprintf(f, ",\"confirm_misses\":%u,\"flags\":%u,\"arena_bytes\":%llu}}\n", c->confirm_misses, c->flags,
            (unsigned long long)h->arena_bytes);
}

static int log_dump(const char *path, int mode)
{
    vp_sessionlog_t L;
    char err[1400], stop[600];
    uint32_t i;
    int st = vp_sessionlog_load(&L, path, err, sizeof err);
    if (st != VP_OK) { fprintf(stderr, "log dump: %s\n", err); return 1; }
    if (mode == 0) dump_header_text(&L.header, stdout);
    else if (mode == 1) dump_header_json(&L.header, stdout);
    else printf("seq,offset,type,origin_x,origin_y,origin_z,dir_x,dir_y,dir_z,range,hit,dist,raw,"
                "point_x,point_y,point_z,target_x,target_y,target_z,event,code,text\n");
    for (i = 0; i < L.n; i++) {
        vp_logfmt_record_t r;
        double p[3];
        int k;
        if (vp_sessionlog_record(&L, i, &r) != VP_OK) break;
        for (k = 0; k < 3; k++) p[k] = r.origin[k] + r.dist * r.dir[k];
        if (mode == 0) {
            printf("%u @%zu ", r.seq, L.off[i]);
            if (is_reading(r.type)) {
                printf("%s from %.17g %.17g %.17g dir %.17g %.17g %.17g range %.17g: ", r.type == VP_LOGFMT_RAY ? "RAY" : "PROBE", r.origin[0], r.origin[1],
                       r.origin[2], r.dir[0], r.dir[1], r.dir[2], r.range);
                if (r.hit == VP_PROBE_TOO_CLOSE) printf("too close (nothing measured, nothing free) raw %.17g\n", r.raw);
                else if (r.hit) printf("hit at %.17g (point %.17g %.17g %.17g) raw %.17g\n", r.dist, p[0], p[1], p[2], r.raw);
                else printf("miss (dist %.17g, raw %.17g)\n", r.dist, r.raw);
            } else if (r.type == VP_LOGFMT_MOVE) {
                printf("MOVE to %.17g %.17g %.17g\n", r.target[0], r.target[1], r.target[2]);
            } else {
                printf("EVENT %s code %d", vp_sessionlog_event_name(r.event), (int)r.code);
                if (r.event == VP_LOGFMT_EV_CALIBRATION || r.event == VP_LOGFMT_EV_CONTACT)
                    printf(" values %.17g %.17g %.17g %.17g", r.value[0], r.value[1], r.value[2], r.value[3]);
                printf(" '%s'\n", r.text);
            }
        } else if (mode == 1) {
            printf("{\"seq\":%u,\"offset\":%zu,\"type\":\"%s\"", r.seq, L.off[i], type_str(r.type));
            if (is_reading(r.type)) {
                printf(",\"origin\":"); json_vec(stdout, r.origin);
                printf(",\"dir\":"); json_vec(stdout, r.dir);
                printf(",\"range\":"); json_num(stdout, r.range);
                printf(",\"hit\":%s,%s\"dist\":", r.hit == 1 ? "true" : "false",
                       r.hit == VP_PROBE_TOO_CLOSE ? "\"too_close\":true," : ""); json_num(stdout, r.dist);
                printf(",\"raw\":"); json_num(stdout, r.raw);
                if (r.hit == 1) { printf(",\"point\":"); json_vec(stdout, p); }
            } else if (r.type == VP_LOGFMT_MOVE) {
                printf(",\"target\":"); json_vec(stdout, r.target);
            } else {
                printf(",\"event\":\"%s\",\"event_code\":%u,\"code\":%d,\"values\":[", vp_sessionlog_event_name(r.event),
                       r.event, (int)r.code);
                for (k = 0; k < 4; k++) { if (k) putchar(','); json_num(stdout, r.value[k]); }
                printf("],\"text\":"); vp_json_str(stdout, r.text, 0);
            }
            printf("}\n");
        } else {
            printf("%u,%zu,%s,", r.seq, L.off[i], type_str(r.type));
            if (is_reading(r.type))
                printf("%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%d,%.17g,%.17g,", r.origin[0], r.origin[1],
                       r.origin[2], r.dir[0], r.dir[1], r.dir[2], r.range, r.hit, r.dist, r.raw);
            else
                printf(",,,,,,,,,,");
            if (is_reading(r.type) && r.hit == 1) printf("%.17g,%.17g,%.17g,", p[0], p[1], p[2]);
            else if (r.type == VP_LOGFMT_EVENT && r.event == VP_LOGFMT_EV_CONTACT)
                printf("%.17g,%.17g,%.17g,", r.value[1], r.value[2], r.value[3]);
            else printf(",,,");
            if (r.type == VP_LOGFMT_MOVE) printf("%.17g,%.17g,%.17g,", r.target[0], r.target[1], r.target[2]);
            else printf(",,,");
            if (r.type == VP_LOGFMT_EVENT) {
                printf("%s,%d,\"", vp_sessionlog_event_name(r.event), (int)r.code);
                for (k = 0; r.text[k]; k++) { if (r.text[k] == '"') putchar('"'); putchar(r.text[k]); }
                printf("\"\n");
            } else {
                printf(",,\n");
            }
        }
    }
    if (L.status != VP_OK) {
        vp_sessionlog_stop_text(&L, stop, sizeof stop);
        fprintf(stderr, "log dump: %s: %s\n", path, stop);
    }
    st = L.status == VP_OK ? 0 : 1;
    vp_sessionlog_free(&L);
    return st;
}

static int log_check(const char *path, int replay)
{
    vp_sessionlog_t L;
    char err[1400], stop[600];
    int st = vp_sessionlog_load(&L, path, err, sizeof err), rc;
    uint32_t i, last_event = 0;
    int32_t last_code = 0;
    if (st != VP_OK) {
        printf("%s: NOT usable: %s\n", path, err);
        return 1;
    }
    for (i = 0; i < L.n; i++) {
        vp_logfmt_record_t r;
        if (vp_sessionlog_record(&L, i, &r) == VP_OK && r.type == VP_LOGFMT_EVENT) { last_event = r.event; last_code = r.code; }
    }
    vp_sessionlog_stop_text(&L, stop, sizeof stop);
    printf("%s: format version %u, board '%s', %llu bytes\n", path, L.header.version, L.header.board,
           (unsigned long long)L.size);
    printf("header: ok (CRC good), eps %.6g, %u interior point(s)\n", L.header.cfg.eps, L.header.cfg.ninterior);
    printf("records: %u valid (%llu probes, %llu hits, %llu moves, %llu events)\n", L.n,
           (unsigned long long)L.probes, (unsigned long long)L.hits, (unsigned long long)L.moves,
           (unsigned long long)L.events);
    if (L.rays)
        printf("line laser: %llu more rays in the probes' frames (%llu hits)\n", (unsigned long long)L.rays,
               (unsigned long long)L.ray_hits);
    printf("%s\n", stop);
    rc = L.status == VP_OK ? 0 : 1;
    if (replay) {
        vp_replay_t R;
        st = vp_replay_open(&R, &L, 0, err, sizeof err);
        if (st == VP_OK) st = vp_replay_run(&R, &L, L.n, err, sizeof err);
        if (st == VP_OK)
            printf("replay: the planner reissues all %u commands bit for bit\n", (unsigned)(L.probes + L.moves));
        else if (st != VP_ECORRUPT && last_event == VP_LOGFMT_EV_FAULT && last_code == st)
            printf("replay: the planner reissues every command bit for bit and stops where the session stopped: %s\n",
                   err);
        else {
            printf("replay: FAILED: %s\n", err);
            rc = 1;
        }
        vp_replay_close(&R);
    }
    if (L.done)
        printf("session: complete (DONE)%s\n", rc ? "; the mesh can be rebuilt from the valid records" : "");
    else
        printf("session: incomplete (last event: %s): `%s %s%s` continues it from record %u; "
               "`mesh` gives the mesh so far%s\n", last_event ? vp_sessionlog_event_name(last_event) : "none",
               strncmp(L.header.note, "scan ", 5) ? "sim --resume" : "scan --log", path,
               strncmp(L.header.note, "scan ", 5) ? "" : " --resume", L.n,
               L.status != VP_OK ? " (resume first cuts the damaged tail)" : "");
    vp_sessionlog_free(&L);
    return rc;
}

static void vec_text(const double *v)
{
    printf("%.9g %.9g %.9g", v[0], v[1], v[2]);
}

static int log_verify(const char *path, int json)
{
    vp_sessionlog_t L;
    vp_logverify_t *v;
    vp_logverify_result_t *res;
    char err[1400], stop[600];
    uint32_t i;
    int st = vp_sessionlog_load(&L, path, err, sizeof err);
    if (st != VP_OK) {
        fprintf(stderr, "log verify: %s\n", err);
        if (json) printf("{\"ok\":false,\"error\":\"unreadable\"}\n");
        return 3;
    }
    v = malloc(sizeof *v);
    res = malloc(sizeof *res);
    if (!v || !res) { free(v); free(res); vp_sessionlog_free(&L); fprintf(stderr, "log verify: out of memory\n"); return 3; }
    st = vp_logverify_begin(v, &L.header);
    if (st != VP_OK) {
        fprintf(stderr, "log verify: %s: the header's Omega is not usable (not finite or empty)\n", path);
        free(v); free(res); vp_sessionlog_free(&L);
        if (json) printf("{\"ok\":false,\"error\":\"bad omega\"}\n");
        return 3;
    }
    for (i = 0; i < L.n && st == VP_OK; i++) {
        vp_logfmt_record_t r;
        st = vp_sessionlog_record(&L, i, &r);
        if (st == VP_OK) st = vp_logverify_add(v, &r);
    }
    vp_logverify_end(v, res);
    free(v);
    if (st != VP_OK) {
        fprintf(stderr, "log verify: %s: record %u: %s\n", path, i - 1, vp_strerror(st));
        free(res); vp_sessionlog_free(&L);
        if (json) printf("{\"ok\":false,\"error\":\"%s\"}\n", vp_strerror(st));
        return 3;
    }
    for (i = 0; i < res->nmoves_listed; i++) {
        const vp_logverify_move_t *m = &res->move[i];
        printf("record %u (seq %u, move %llu): MOVE from ", m->record, m->seq, (unsigned long long)m->move);
        vec_text(m->from);
        printf(" to ");
        vec_text(m->to);
        printf(": %.6g of its length %.6g NOT proven free", m->unproven, m->length);
        printf("; first unproven part s %.6g..%.6g (", m->gap_s0, m->gap_s1);
        vec_text(m->gap_from);
        printf(" .. ");
        vec_text(m->gap_to);
        printf(")");
        if (m->gaps > 1) printf(", %u unproven parts", m->gaps);
        printf("; %u earlier probe(s) on its line\n", m->probes_on_line);
    }
    if (res->unproven_moves > res->nmoves_listed)
        printf("... %llu more unproven moves\n", (unsigned long long)(res->unproven_moves - res->nmoves_listed));
    for (i = 0; i < res->nprobes_listed; i++) {
        const vp_logverify_probe_t *p = &res->probe[i];
        printf("record %u (seq %u): PROBE from ", p->record, p->seq);
        vec_text(p->origin);
        printf(", but the device was at ");
        vec_text(p->pos);
        printf(" (%.6g away): fired from a position never moved to; it proves nothing\n", p->off);
    }
    if (res->probes_off_position > res->nprobes_listed)
        printf("... %llu more probes off the device's position\n",
               (unsigned long long)(res->probes_off_position - res->nprobes_listed));
    if (L.status != VP_OK) {
        vp_sessionlog_stop_text(&L, stop, sizeof stop);
        if (L.n) printf("verify: %s: %s; verified records 0..%u only\n", path, stop, L.n - 1);
        else printf("verify: %s: %s; no record to verify\n", path, stop);
    }
    if (res->unproven_moves == 0)
        printf("verify: %llu moves, %llu probes: all moves proven free", (unsigned long long)res->moves,
               (unsigned long long)res->probes);
    else
        printf("verify: %llu of %llu moves NOT proven free (first: record %u, seq %u, move %llu; %.6g unproven in all)",
               (unsigned long long)res->unproven_moves, (unsigned long long)res->moves, res->move[0].record,
               res->move[0].seq, (unsigned long long)res->move[0].move, res->unproven_length);
    if (res->probes_off_position)
        printf("; %llu of %llu probes NOT from the device's position (first: record %u)",
               (unsigned long long)res->probes_off_position, (unsigned long long)res->probes, res->probe[0].record);
    if (res->probes_bad) printf("; %llu probe(s) with a zero direction (prove nothing)", (unsigned long long)res->probes_bad);
    if (res->probes_far)
        printf("; %llu probe(s) fired from farther than %g diameters of Omega (prove nothing)",
               (unsigned long long)res->probes_far, VP_LOGVERIFY_FAR);
    if (res->contacts_misplaced)
        printf("; %llu CONTACT event(s) NOT right after a MOVE (a log voroprobe does not write)",
               (unsigned long long)res->contacts_misplaced);
    if (res->probes_near_contact)
        printf("; %llu probe(s) within the contact reach of a contact (prove nothing)",
               (unsigned long long)res->probes_near_contact);
    if (res->tube_too_large)
        printf("; %llu tube move(s) too long for the lattice (unproven)", (unsigned long long)res->tube_too_large);
    if (res->contacts)
        printf("; %llu contact(s) withdrew %llu free part(s)", (unsigned long long)res->contacts,
               (unsigned long long)res->withdrawn);
    if (res->rescans)
        printf("; %llu re-scan(s): no free part logged before one proves a move after it",
               (unsigned long long)res->rescans);
    if (res->tube_moves)
        printf("; %llu move(s) inside Omega checked by the tube rule (%llu cubes of their capsules)",
               (unsigned long long)res->tube_moves, (unsigned long long)res->tube_points);
    printf("\n");
    if (json) {
        printf("{\"moves\":%llu,\"probes\":%llu,\"unproven_moves\":%llu,\"first_unproven_record\":",
               (unsigned long long)res->moves, (unsigned long long)res->probes, (unsigned long long)res->unproven_moves);
        if (res->unproven_moves) printf("%u", res->move[0].record); else printf("null");
        printf(",\"probes_off_position\":%llu,\"first_off_position_record\":", (unsigned long long)res->probes_off_position);
        if (res->probes_off_position) printf("%u", res->probe[0].record); else printf("null");
        if (res->rays) printf(",\"rays\":%llu", (unsigned long long)res->rays);
        printf(",\"records\":%llu,\"events\":%llu,\"moves_outside_omega\":%llu,\"unproven_length\":",
               (unsigned long long)res->records, (unsigned long long)res->events, (unsigned long long)res->moves_outside);
        json_num(stdout, res->unproven_length);
        printf(",\"tol\":");
        json_num(stdout, res->tol);
        printf(",\"index_fallbacks\":%llu,\"contacts\":%llu,\"withdrawn\":%llu", (unsigned long long)res->scans,
               (unsigned long long)res->contacts, (unsigned long long)res->withdrawn);
        if (res->rescans) printf(",\"rescans\":%llu", (unsigned long long)res->rescans);
        printf(",\"contacts_misplaced\":%llu,\"probes_near_contact\":%llu,\"probes_far\":%llu",
               (unsigned long long)res->contacts_misplaced, (unsigned long long)res->probes_near_contact,
               (unsigned long long)res->probes_far);
        if (res->tube_too_large) printf(",\"tube_too_large\":%llu", (unsigned long long)res->tube_too_large);
        if (res->tube_moves)
            printf(",\"tube_moves\":%llu,\"tube_points\":%llu", (unsigned long long)res->tube_moves,
                   (unsigned long long)res->tube_points);
        printf(",\"log_complete\":%s,\"ok\":%s}\n", L.status == VP_OK ? "true" : "false", res->ok ? "true" : "false");
    }
    st = res->ok ? 0 : 1;
    free(res);
    vp_sessionlog_free(&L);
    return st;
}

int vp_cli_log(int argc, char **argv)
{
    const char *sub, *path = NULL;
    int i, mode = 0, replay = 1;
    if (argc < 2 || !strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) {
        log_usage(argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    sub = argv[1];
    if (strcmp(sub, "dump") && strcmp(sub, "check") && strcmp(sub, "verify")) {
        fprintf(stderr, "log: unknown sub-command '%s' (dump, check or verify; see --help)\n", sub);
        return 2;
    }
    for (i = 2; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) { log_usage(stdout); return 0; }
        if (!strcmp(sub, "dump") && !strcmp(a, "--jsonl")) mode = 1;
        else if (!strcmp(sub, "dump") && !strcmp(a, "--csv")) mode = 2;
        else if (!strcmp(sub, "check") && !strcmp(a, "--no-replay")) replay = 0;
        else if (!strcmp(sub, "verify") && !strcmp(a, "--json")) mode = 1;
        else if (a[0] == '-' && a[1]) { fprintf(stderr, "log %s: unknown option %s (see --help)\n", sub, a); return 2; }
        else if (path) { fprintf(stderr, "log %s: one log at a time\n", sub); return 2; }
        else path = a;
    }
    if (!path) { fprintf(stderr, "log %s: give a LOG file (see --help)\n", sub); return 2; }
    if (!strcmp(sub, "verify")) return log_verify(path, mode);
    return !strcmp(sub, "dump") ? log_dump(path, mode) : log_check(path, replay);
}
