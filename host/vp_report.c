/* vp_report — a session log seen whole, written as one self-contained HTML page. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "vp_json.h"
#include "vp_outcome.h"
#include "vp_report.h"
#include "vp_session.h"

#define SERIES_MAX 400      /* checkpoints kept of the session over time */
#define HIST_BINS 24        /* ball-radius histogram */

/* ---------- building ---------- */

static double dist3(const double *a, const double *b)
{
    double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

static void take_point(vp_report_t *r, uint32_t record, double travel)
{
    vp_report_point_t *p = &r->series[r->nseries++];
    vp_planner_stats_t st;
    vp_planner_get_stats(r->R.pl, &st);
    p->record = record;
    p->probes = st.probes;
    p->hits = st.hits;
    p->moves = st.moves;
    p->vertices = vp_planner_dt(r->R.pl)->ninserted;
    p->facets = vp_planner_num_facets(r->R.pl);
    p->travel = travel;
}

/* Replays record by record: the series, travel per tenth and the seed's share. */
static int replay_all(vp_report_t *r, char *err, size_t errlen)
{
    uint32_t n = r->L.n, i, every = n / (SERIES_MAX - 2) + 1;
    double pos[3], travel = 0.0;
    int seeding = 1, st = VP_OK;
    memcpy(pos, r->L.header.cfg.start, sizeof pos);
    r->series = malloc(SERIES_MAX * sizeof *r->series);
    if (!r->series) { snprintf(err, errlen, "out of memory"); return VP_ENOMEM; }
    take_point(r, 0, 0.0);
    for (i = 0; i < n; i++) {
        vp_logfmt_record_t rec;
        if (vp_sessionlog_record(&r->L, i, &rec) != VP_OK) break;
        {
            struct timespec t0, t1;
            clock_gettime(CLOCK_MONOTONIC, &t0);
            st = vp_replay_run(&r->R, &r->L, i + 1, err, errlen);
            clock_gettime(CLOCK_MONOTONIC, &t1);
            r->planner_seconds += (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
        }
        if (st != VP_OK) break;
        if (rec.type == VP_LOGFMT_MOVE) {
            double d = dist3(pos, rec.target);
            travel += d;
            r->travel_tenth[(uint64_t)i * VP_REPORT_TENTHS / n] += d;
            if (seeding) r->seed_travel += d;
            r->travel_stage[vp_planner_stage(r->R.pl) & 3] += d;
            memcpy(pos, rec.target, sizeof pos);
            r->moves++;
        } else if (rec.type == VP_LOGFMT_PROBE) {
            r->probes++;
            if (rec.hit == 1) r->hits++;
            else if (rec.hit == 0) r->misses++;
            else r->too_close++;
        }
        if (seeding && vp_planner_dt(r->R.pl)->ninserted > 0) { seeding = 0; r->seed_records = i + 1; }
        if ((i + 1) % every == 0 && i + 1 < n) take_point(r, i + 1, travel);
    }
    if (seeding) r->seed_records = i;
    take_point(r, i, travel);
    r->travel = travel;
    return st;
}

/* Parses the certificate's offender lines: "H1 fails: facet N", "H3 fails: facet N", and
 * "H1 fails: edge (a b) is in k facet(s): f1 f2 ...". */
static int read_offenders(FILE *rep, vp_report_t *r, size_t nt)
{
    char line[4096];
    size_t cap_h = 0, cap_n = 0;
    rewind(rep);
    while (fgets(line, sizeof line, rep)) {
        unsigned long f, a, b, k;
        int used;
        if (sscanf(line, "H1 fails: facet %lu", &f) == 1 && f < nt) r->verdict[f] |= VP_REPORT_H1;
        else if (sscanf(line, "H3 fails: facet %lu", &f) == 1 && f < nt) r->verdict[f] |= VP_REPORT_H3;
        else if (sscanf(line, "H1 fails: edge (%lu %lu) is in %lu facet(s):%n", &a, &b, &k, &used) == 3) {
            const char *s = line + used;
            uint32_t **arr = k == 1 ? &r->hole_edges : &r->nm_edges;
            size_t *cnt = k == 1 ? &r->nhole_edges : &r->nnm_edges, *cap = k == 1 ? &cap_h : &cap_n;
            char *e;
            if (*cnt == *cap) {
                size_t nc = *cap ? 2 * *cap : 256;
                uint32_t *p = realloc(*arr, 2 * nc * sizeof *p);
                if (!p) return VP_ENOMEM;
                *arr = p;
                *cap = nc;
            }
            (*arr)[2 * *cnt] = (uint32_t)a;
            (*arr)[2 * *cnt + 1] = (uint32_t)b;
            (*cnt)++;
            for (;;) {
                f = strtoul(s, &e, 10);
                if (e == s) break;
                if (f < nt) r->verdict[f] |= VP_REPORT_H1;
                s = e;
            }
        }
    }
    return VP_OK;
}

/* Certifies m (centres: the balls, or NULL for a bare mesh) and, when verdicts are wanted,
 * marks every offending facet and edge of it. */
static int certify_mesh(vp_report_t *r, const vp_mesh_t *m, const double *centers, int verdicts, vp_cert_t *out)
{
    const vp_planner_config_t *pc = &r->L.header.cfg;
    const vp_dt_t *dt = vp_planner_dt(r->R.pl);
    vp_cert_config_t cfg;
    double *samples = NULL;
    size_t ns = 0;
    uint32_t s;
    FILE *rep = verdicts ? tmpfile() : NULL;
    int st;
    if (verdicts && !rep) return VP_EIO;
    memset(&cfg, 0, sizeof cfg);
    cfg.eps = pc->eps;
    cfg.interior = (const double (*)[3])pc->interior;
    cfg.ninterior = pc->ninterior;
    cfg.max_list = (size_t)-1;
    if (centers) {
        samples = malloc(((size_t)dt->nvert + 1) * 3 * sizeof *samples);
        if (!samples) { if (rep) fclose(rep); return VP_ENOMEM; }
        for (s = 0; s < dt->nvert; s++)
            if (vp_dt_vertex(dt, s)->tet != VP_DT_NONE) memcpy(samples + 3 * ns++, vp_dt_point(dt, s), 3 * sizeof(double));
        cfg.centers = centers;
        cfg.samples = samples;
        cfg.nsamples = ns;
    }
    st = vp_certify(m, &cfg, out, rep);
    if (st == VP_OK && rep) st = read_offenders(rep, r, m->nt);
    if (rep) fclose(rep);
    free(samples);
    return st;
}

static int outcome_of(const vp_report_t *r)
{
    vp_outcome_in_t in;
    uint32_t i;
    memset(&in, 0, sizeof in);
    in.run_status = r->R.done ? VP_OK : VP_EIO;
    /* the last PAUSE or FAULT says why an incomplete session stopped */
    for (i = r->R.applied; i-- > 0 && !r->R.done;) {
        vp_logfmt_record_t rec;
        if (vp_sessionlog_record(&r->L, i, &rec) != VP_OK || rec.type != VP_LOGFMT_EVENT) continue;
        if (rec.event == VP_LOGFMT_EV_PAUSE) { in.paused = 1; in.run_status = VP_EABORT; break; }
        if (rec.event == VP_LOGFMT_EV_FAULT) { in.run_status = rec.code ? rec.code : VP_EIO; break; }
    }
    in.closed_manifold = r->have_check && r->check.closed_manifold;
    in.missing_components = r->st.missing_components;
    return vp_outcome(&in);
}

int vp_report_build(vp_report_t *r, const char *log_path, const char *mesh_path, char *err, size_t errlen)
{
    double *centers = NULL;
    uint32_t s, nf = 0;
    int st;
    memset(r, 0, sizeof *r);
    vp_mesh_init(&r->mesh);
    vp_mesh_init(&r->other);
    r->log_path = log_path;
    r->mesh_path = mesh_path;
    st = vp_sessionlog_load(&r->L, log_path, err, errlen);
    if (st != VP_OK) return st;
    vp_sessionlog_stop_text(&r->L, r->stop_text, sizeof r->stop_text);
    st = vp_replay_open(&r->R, &r->L, 0, err, errlen);
    if (st == VP_OK) st = replay_all(r, err, errlen);
    if (st != VP_OK) return st;
    vp_planner_get_stats(r->R.pl, &r->st);
    st = vp_session_mesh(r->R.pl, &r->mesh);
    if (st != VP_OK) { snprintf(err, errlen, "mesh: %s", vp_strerror(st)); return st; }
    if (vp_meshcheck_analyze(&r->mesh, &r->check) == VP_OK) r->have_check = 1;
    r->exit_status = outcome_of(r);
    /* every facet's ball, in the mesh's facet order (the planner's slots) */
    centers = malloc((r->mesh.nt + 1) * 3 * sizeof *centers);
    r->radius = malloc((r->mesh.nt + 1) * sizeof *r->radius);
    if (!centers || !r->radius) { free(centers); snprintf(err, errlen, "out of memory"); return VP_ENOMEM; }
    for (s = 0; s < vp_planner_facet_slots(r->R.pl) && nf < r->mesh.nt; s++) {
        uint32_t v[3];
        if (vp_planner_facet(r->R.pl, s, v, &r->radius[nf], centers + 3 * (size_t)nf)) nf++;
    }
    r->shown = &r->mesh;
    if (mesh_path) {
        free(r->radius);
        r->radius = NULL;
        st = vp_mesh_read_file(mesh_path, &r->other, err, errlen);
        if (st != VP_OK) { free(centers); return st; }
        r->shown = &r->other;
        r->radius = malloc((r->other.nt + 1) * sizeof *r->radius);
        if (!r->radius) { free(centers); snprintf(err, errlen, "out of memory"); return VP_ENOMEM; }
        for (s = 0; s < r->other.nt; s++) r->radius[s] = NAN;
    }
    r->verdict = calloc(r->shown->nt + 1, 1);
    if (!r->verdict) { free(centers); snprintf(err, errlen, "out of memory"); return VP_ENOMEM; }
    /* a session stopped before its first facet has nothing to certify: the page says so */
    st = r->mesh.nt > 0 ? certify_mesh(r, &r->mesh, centers, !mesh_path, &r->cert) : VP_OK;
    if (st == VP_OK && r->mesh.nt > 0) r->have_cert = 1;
    if (st == VP_OK && mesh_path) {
        vp_cert_t bare;
        st = certify_mesh(r, &r->other, NULL, 1, &bare);
    }
    free(centers);
    if (st != VP_OK) { snprintf(err, errlen, "certify: %s", vp_strerror(st)); return st; }
    return VP_OK;
}

void vp_report_free(vp_report_t *r)
{
    if (r->have_check) vp_meshcheck_free(&r->check);
    vp_mesh_free(&r->mesh);
    vp_mesh_free(&r->other);
    vp_replay_close(&r->R);
    vp_sessionlog_free(&r->L);
    free(r->radius);
    free(r->verdict);
    free(r->hole_edges);
    free(r->nm_edges);
    free(r->series);
    memset(r, 0, sizeof *r);
}

/* ---------- JSON ---------- */

/* A JSON string that is also safe inside a <script> element (no '<', '>', '&'). */
static void json_num(FILE *f, double v)
{
    if (isfinite(v)) fprintf(f, "%.9g", v);
    else fprintf(f, "null");
}

static const char *verdict_word(int v) { return v > 0 ? "holds" : v == 0 ? "fails" : "unchecked"; }

void vp_report_summary_json(const vp_report_t *r, FILE *f)
{
    int closed = r->have_check && r->check.closed_manifold;
    fprintf(f, "{\"status\":\"%s\",\"exit\":%d,\"done\":%s,\"vertices\":%zu,\"facets\":%zu,",
            vp_outcome_name(r->exit_status), r->exit_status, r->R.done ? "true" : "false", r->mesh.nv, r->mesh.nt);
    /* the planner's counts, as sim prints them; the logged results beside them */
    fprintf(f, "\"probes\":%llu,\"hits\":%llu,\"misses\":%llu,\"too_close\":%llu,\"moves\":%llu,"
            "\"logged_hits\":%llu,\"logged_misses\":%llu,\"travel\":",
            (unsigned long long)r->st.probes, (unsigned long long)r->st.hits, (unsigned long long)r->st.misses,
            (unsigned long long)r->st.too_close, (unsigned long long)r->st.moves, (unsigned long long)r->hits,
            (unsigned long long)r->misses);
    json_num(f, r->st.travel);
    fprintf(f, ",\"travel_prev_chains\":");
    json_num(f, r->st.travel_prev_chains);
    fprintf(f, ",\"closed_manifold\":%s,\"components\":%d,\"genus\":", closed ? "true" : "false",
            r->have_check ? r->check.components : -1);
    if (closed) fprintf(f, "%d", r->check.genus);
    else fprintf(f, "null");
    fprintf(f, ",\"boundary_edges\":%zu,\"nonmanifold_edges\":%zu,\"max_ball_radius\":",
            r->have_check ? r->check.boundary_edges : 0, r->have_check ? r->check.nonmanifold_edges : 0);
    json_num(f, r->st.max_ball);
    fprintf(f, ",\"eps\":");
    json_num(f, r->L.header.cfg.eps);
    fprintf(f, ",\"bad_balls\":%u,\"insertions\":%llu,\"missing_components\":%u,\"unproven\":%llu,"
            "\"records\":%u,\"seed_records\":%u,\"seed_travel\":",
            r->st.bad_balls, (unsigned long long)r->st.insertions, r->st.missing_components,
            (unsigned long long)r->st.unproven, r->R.applied, r->seed_records);
    json_num(f, r->seed_travel);
    fprintf(f, ",\"planner_seconds_replayed\":");
    json_num(f, r->planner_seconds);
    fprintf(f, ",\"min_angle_deg\":");
    json_num(f, r->have_check ? r->check.min_angle_deg : NAN);
    fprintf(f, ",\"arena_bytes_peak\":%zu,\"log\":", r->st.arena_peak);
    vp_json_str(f, r->stop_text, 1);
    if (r->have_cert) {
        fprintf(f, ",\"h1\":\"%s\",\"h2\":\"%s\",\"h3\":\"%s\",\"big_balls\":%zu,\"open_balls\":%zu,\"eps_prime\":",
                verdict_word(r->cert.h1), verdict_word(r->cert.h2), verdict_word(r->cert.h3), r->cert.big_balls,
                r->cert.open_balls);
        json_num(f, r->cert.eps_prime >= 0 ? r->cert.eps_prime : NAN);
    }
    fprintf(f, "}");
}

/* ---------- quantised arrays in base64 ---------- */

typedef struct b64 {
    FILE *f;
    unsigned char in[3];
    int n;
} b64_t;

static const char b64_chars[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

static void b64_flush(b64_t *b, int final)
{
    char o[4];
    if (b->n == 0 || (b->n < 3 && !final)) return;
    if (b->n < 3) memset(b->in + b->n, 0, (size_t)(3 - b->n));
    o[0] = b64_chars[b->in[0] >> 2];
    o[1] = b64_chars[((b->in[0] & 3) << 4) | (b->in[1] >> 4)];
    o[2] = b->n > 1 ? b64_chars[((b->in[1] & 15) << 2) | (b->in[2] >> 6)] : '=';
    o[3] = b->n > 2 ? b64_chars[b->in[2] & 63] : '=';
    fwrite(o, 1, 4, b->f);
    b->n = 0;
}

static void b64_byte(b64_t *b, unsigned v)
{
    b->in[b->n++] = (unsigned char)v;
    if (b->n == 3) b64_flush(b, 0);
}

static void b64_u16(b64_t *b, unsigned v) { b64_byte(b, v & 255u); b64_byte(b, (v >> 8) & 255u); }
static void b64_u32(b64_t *b, uint32_t v)
{
    b64_byte(b, v & 255u); b64_byte(b, (v >> 8) & 255u); b64_byte(b, (v >> 16) & 255u); b64_byte(b, v >> 24);
}

/* Positions are 16-bit fractions of the box lo .. hi. */
typedef struct qbox { double lo[3], hi[3]; } qbox_t;

static void b64_point(b64_t *b, const qbox_t *q, const double *p)
{
    int k;
    for (k = 0; k < 3; k++) {
        double span = q->hi[k] - q->lo[k], t = span > 0 ? (p[k] - q->lo[k]) / span : 0.5;
        if (!(t > 0)) t = 0;
        if (t > 1) t = 1;
        b64_u16(b, (unsigned)floor(t * 65535.0 + 0.5));
    }
}

static void grow_box(qbox_t *q, const double *p)
{
    int k;
    for (k = 0; k < 3; k++) {
        if (!isfinite(p[k])) continue;
        if (p[k] < q->lo[k]) q->lo[k] = p[k];
        if (p[k] > q->hi[k]) q->hi[k] = p[k];
    }
}

/* Which probes are drawn: every stride-th hit and miss. */
static void probe_end(const vp_logfmt_record_t *rec, double *end)
{
    int k;
    double len = rec->hit == 1 ? rec->dist : rec->hit == 0 ? rec->range : 0.0;
    if (!isfinite(len)) len = 0.0;
    for (k = 0; k < 3; k++) end[k] = rec->origin[k] + len * rec->dir[k];
}

static void write_probes(const vp_report_t *r, FILE *f, const qbox_t *q, int want_hit, size_t stride)
{
    b64_t bo, be;
    uint32_t i;
    size_t seen = 0, kept = 0;
    for (i = 0; i < r->R.applied; i++) {
        vp_logfmt_record_t rec;
        if (vp_sessionlog_record(&r->L, i, &rec) != VP_OK || rec.type != VP_LOGFMT_PROBE) continue;
        if ((rec.hit == 1) != want_hit || rec.hit == 2) continue;
        if (seen++ % stride == 0) kept++;
    }
    fprintf(f, "{\"n\":%zu,\"stride\":%zu,\"o\":\"", kept, stride);
    memset(&bo, 0, sizeof bo);
    bo.f = f;
    seen = 0;
    for (i = 0; i < r->R.applied; i++) {
        vp_logfmt_record_t rec;
        if (vp_sessionlog_record(&r->L, i, &rec) != VP_OK || rec.type != VP_LOGFMT_PROBE) continue;
        if ((rec.hit == 1) != want_hit || rec.hit == 2) continue;
        if (seen++ % stride == 0) b64_point(&bo, q, rec.origin);
    }
    b64_flush(&bo, 1);
    fprintf(f, "\",\"e\":\"");
    memset(&be, 0, sizeof be);
    be.f = f;
    seen = 0;
    for (i = 0; i < r->R.applied; i++) {
        vp_logfmt_record_t rec;
        double end[3];
        if (vp_sessionlog_record(&r->L, i, &rec) != VP_OK || rec.type != VP_LOGFMT_PROBE) continue;
        if ((rec.hit == 1) != want_hit || rec.hit == 2) continue;
        if (seen++ % stride == 0) { probe_end(&rec, end); b64_point(&be, q, end); }
    }
    b64_flush(&be, 1);
    fprintf(f, "\"}");
}

static void write_edges(FILE *f, const uint32_t *e, size_t n)
{
    b64_t b;
    size_t i;
    memset(&b, 0, sizeof b);
    b.f = f;
    fputc('"', f);
    for (i = 0; i < 2 * n; i++) b64_u32(&b, e[i]);
    b64_flush(&b, 1);
    fputc('"', f);
}

static void write_series(const vp_report_t *r, FILE *f)
{
    size_t i;
    static const char *names[] = { "record", "probes", "hits", "moves", "vertices", "facets", "travel" };
    int k;
    fprintf(f, "{");
    for (k = 0; k < 7; k++) {
        fprintf(f, "%s\"%s\":[", k ? "," : "", names[k]);
        for (i = 0; i < r->nseries; i++) {
            const vp_report_point_t *p = &r->series[i];
            if (i) fputc(',', f);
            switch (k) {
            case 0: fprintf(f, "%u", p->record); break;
            case 1: fprintf(f, "%llu", (unsigned long long)p->probes); break;
            case 2: fprintf(f, "%llu", (unsigned long long)p->hits); break;
            case 3: fprintf(f, "%llu", (unsigned long long)p->moves); break;
            case 4: fprintf(f, "%u", p->vertices); break;
            case 5: fprintf(f, "%u", p->facets); break;
            default: fprintf(f, "%.6g", p->travel); break;
            }
        }
        fputc(']', f);
    }
    fprintf(f, "}");
}

static void write_data(const vp_report_t *r, FILE *f, size_t max_rays)
{
    const vp_mesh_t *m = r->shown;
    const vp_planner_config_t *pc = &r->L.header.cfg;
    qbox_t q;
    b64_t b;
    size_t i, hist[HIST_BINS], nhits = 0, nmiss = 0;
    double rmax = 0.0;
    uint32_t k;
    /* the quantisation box: Omega, the mesh and the path */
    for (k = 0; k < 3; k++) { q.lo[k] = HUGE_VAL; q.hi[k] = -HUGE_VAL; }
    if (pc->omega_kind == VP_OMEGA_BALL) {
        for (k = 0; k < 3; k++) {
            q.lo[k] = pc->omega_center[k] - pc->omega_radius;
            q.hi[k] = pc->omega_center[k] + pc->omega_radius;
        }
    } else {
        grow_box(&q, pc->omega_lo);
        grow_box(&q, pc->omega_hi);
    }
    grow_box(&q, pc->start);
    for (i = 0; i < m->nv; i++) grow_box(&q, m->xyz + 3 * i);
    for (k = 0; k < r->R.applied; k++) {
        vp_logfmt_record_t rec;
        if (vp_sessionlog_record(&r->L, k, &rec) != VP_OK) continue;
        if (rec.type == VP_LOGFMT_MOVE) grow_box(&q, rec.target);
        else if (rec.type == VP_LOGFMT_PROBE) {
            double end[3];
            probe_end(&rec, end);
            grow_box(&q, rec.origin);
            grow_box(&q, end);
            if (rec.hit == 1) nhits++;
            else if (rec.hit == 0) nmiss++;
        }
    }
    for (k = 0; k < 3; k++)
        if (!(q.lo[k] <= q.hi[k])) { q.lo[k] = -1; q.hi[k] = 1; }
    if (max_rays == 0) max_rays = 200000;

    fprintf(f, "{\"title\":");
    vp_json_str(f, r->log_path, 1);
    fprintf(f, ",\"note\":");
    vp_json_str(f, r->L.header.note, 1);
    fprintf(f, ",\"board\":");
    vp_json_str(f, r->L.header.board, 1);
    fprintf(f, ",\"mesh_source\":");
    vp_json_str(f, r->mesh_path ? r->mesh_path : "the session", 1);
    fprintf(f, ",\"summary\":");
    vp_report_summary_json(r, f);
    fprintf(f, ",\"box\":[%.17g,%.17g,%.17g,%.17g,%.17g,%.17g]", q.lo[0], q.lo[1], q.lo[2], q.hi[0], q.hi[1], q.hi[2]);

    /* the mesh: positions (u16 x3), triangles (u32 x3), radii (f32), verdicts (u8) */
    for (i = 0; i < m->nt; i++)
        if (isfinite(r->radius[i]) && r->radius[i] > rmax) rmax = r->radius[i];
    fprintf(f, ",\"mesh\":{\"nv\":%zu,\"nt\":%zu,\"rmax\":", m->nv, m->nt);
    json_num(f, rmax);
    fprintf(f, ",\"xyz\":\"");
    memset(&b, 0, sizeof b);
    b.f = f;
    for (i = 0; i < m->nv; i++) b64_point(&b, &q, m->xyz + 3 * i);
    b64_flush(&b, 1);
    fprintf(f, "\",\"tri\":\"");
    for (i = 0; i < 3 * m->nt; i++) b64_u32(&b, m->tri[i]);
    b64_flush(&b, 1);
    fprintf(f, "\",\"radius\":\"");   /* float32 (NaN: unknown) */
    for (i = 0; i < m->nt; i++) {
        float rf = (float)r->radius[i];
        uint32_t u;
        memcpy(&u, &rf, sizeof u);
        b64_u32(&b, u);
    }
    b64_flush(&b, 1);
    fprintf(f, "\",\"verdict\":\"");
    for (i = 0; i < m->nt; i++) b64_byte(&b, r->verdict[i]);
    b64_flush(&b, 1);
    fprintf(f, "\",\"holes\":{\"n\":%zu,\"e\":", r->nhole_edges);
    write_edges(f, r->hole_edges, r->nhole_edges);
    fprintf(f, "},\"nonmanifold\":{\"n\":%zu,\"e\":", r->nnm_edges);
    write_edges(f, r->nm_edges, r->nnm_edges);
    fprintf(f, "}}");

    /* the probes and the travel path in the order travelled */
    fprintf(f, ",\"hits\":");
    write_probes(r, f, &q, 1, nhits / max_rays + 1);
    fprintf(f, ",\"misses\":");
    write_probes(r, f, &q, 0, nmiss / max_rays + 1);
    fprintf(f, ",\"path\":{\"n\":%llu,\"p\":\"", (unsigned long long)r->moves + 1);
    b64_point(&b, &q, pc->start);
    for (k = 0; k < r->R.applied; k++) {
        vp_logfmt_record_t rec;
        if (vp_sessionlog_record(&r->L, k, &rec) == VP_OK && rec.type == VP_LOGFMT_MOVE) b64_point(&b, &q, rec.target);
    }
    b64_flush(&b, 1);
    fprintf(f, "\"}");

    /* the plots */
    fprintf(f, ",\"series\":");
    write_series(r, f);
    fprintf(f, ",\"travel_stages\":[");
    for (k = 0; k < 4; k++) fprintf(f, "%s%.6g", k ? "," : "", r->travel_stage[k]);
    fprintf(f, "]");
    fprintf(f, ",\"travel_tenths\":[");
    for (k = 0; k < VP_REPORT_TENTHS; k++) fprintf(f, "%s%.6g", k ? "," : "", r->travel_tenth[k]);
    fprintf(f, "],\"hist\":{\"max\":");
    json_num(f, rmax);
    memset(hist, 0, sizeof hist);
    for (i = 0; i < m->nt && rmax > 0; i++) {
        size_t bin;
        if (!isfinite(r->radius[i])) continue;
        bin = (size_t)(r->radius[i] / rmax * HIST_BINS);
        hist[bin < HIST_BINS ? bin : HIST_BINS - 1]++;
    }
    fprintf(f, ",\"counts\":[");
    for (i = 0; i < HIST_BINS; i++) fprintf(f, "%s%zu", i ? "," : "", hist[i]);
    fprintf(f, "]}}");
}

int vp_report_write_html(const vp_report_t *r, FILE *f, const char *page, size_t len, size_t max_rays)
{
    size_t ml = strlen(VP_REPORT_MARKER), at;
    for (at = 0; at + ml <= len; at++)
        if (!memcmp(page + at, VP_REPORT_MARKER, ml)) break;
    if (at + ml > len) return VP_EINVAL;
    fwrite(page, 1, at, f);
    write_data(r, f, max_rays);
    fwrite(page + at + ml, 1, len - at - ml, f);
    return ferror(f) ? VP_EIO : VP_OK;
}
