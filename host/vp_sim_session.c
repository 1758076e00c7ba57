/* vp_sim_session — see vp_sim_session.h. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "vp_note.h"
#include "vp_sim_session.h"

void vp_sim_session_init(vp_sim_session_t *g)
{
    memset(g, 0, sizeof *g);
    /* a simulated device: sync ten times a second (--sync record for every record) */
    g->fcfg.sync_ms = 100;
    g->w.file.fd = -1;
}

void vp_sim_session_free(vp_sim_session_t *g)
{
    if (g->w.file.fd >= 0) vp_logwriter_close(&g->w.file);
    if (g->have_L) vp_sessionlog_free(&g->L);
    g->have_L = 0;
}

/* ---------- the options as text: the log's note ---------- */

void vp_sim_session_note(const vp_sim_options_t *o, char *buf, size_t n)
{
    size_t len = 0;
    buf[0] = 0;
    vp_note_put(buf, n, &len, "sim");
    vp_note_put_str(buf, n, &len, "--surface", o->surface ? o->surface : "");
    if (o->eps > 0) vp_note_put_num(buf, n, &len, "--eps", o->eps);
    else if (o->eps_rel > 0) vp_note_put_num(buf, n, &len, "--eps-rel", o->eps_rel);
    vp_note_put_num(buf, n, &len, "--noise", o->noise);
    vp_note_put_num(buf, n, &len, "--dropout", o->dropout);
    if (o->confirm >= 0) vp_note_put_opt(buf, n, &len, "--confirm", "%d", o->confirm);
    vp_note_put_num(buf, n, &len, "--clearance", o->clearance);
    if (o->min_feature > 0) vp_note_put_num(buf, n, &len, "--min-feature", o->min_feature);
    if (o->min_feature > 0 && o->feature_margin >= 0) vp_note_put_num(buf, n, &len, "--feature-margin", o->feature_margin);
    vp_note_put_num(buf, n, &len, "--max-range", o->max_range);
    if (o->min_range > 0) vp_note_put_num(buf, n, &len, "--min-range", o->min_range);
    if (o->min_angle > 0) vp_note_put_num(buf, n, &len, "--angle", o->min_angle);
    if (o->size_rel > 0) vp_note_put_num(buf, n, &len, "--size-rel", o->size_rel);
    if (o->accuracy > 0) vp_note_put_num(buf, n, &len, "--accuracy", o->accuracy);
    if (o->accuracy_rel > 0) vp_note_put_num(buf, n, &len, "--accuracy-rel", o->accuracy_rel);
    if (o->min_size > 0) vp_note_put_num(buf, n, &len, "--min-size", o->min_size);
    if (o->max_distance > 0) vp_note_put_num(buf, n, &len, "--max-distance", o->max_distance);
    vp_note_put_opt(buf, n, &len, "--arena", "%zu", o->arena);
    vp_note_put_str(buf, n, &len, "--omega", o->omega_ball ? "ball" : "box");
    vp_note_put_num(buf, n, &len, "--margin", o->omega_margin);
    vp_note_put_opt(buf, n, &len, "--seed", "%llu", o->seed);
    if ((o->flags & VP_PLAN_PAPER) != 0) vp_note_put(buf, n, &len, "--paper");
    if ((o->flags & VP_PLAN_LARGEST) != 0) vp_note_put(buf, n, &len, "--largest");
    if ((o->flags & VP_PLAN_FAR_READS) != 0) vp_note_put(buf, n, &len, "--far-reads");
    if ((o->flags & VP_PLAN_PREV_CHAINS) != 0) vp_note_put(buf, n, &len, "--prev-chains");
    if (o->newest_first) vp_note_put(buf, n, &len, "--newest-first");
    if (o->contact) vp_note_put(buf, n, &len, "--contact");
    if (o->proof_life > 0) vp_note_put_opt(buf, n, &len, "--proof-life", "%ld", o->proof_life);
    if (o->line_rays) {
        char v[64];
        snprintf(v, sizeof v, "%u,%.17g", o->line_rays, o->line_deg);
        vp_note_put_str(buf, n, &len, "--line-laser", v);
    }
    {
        int i;
        for (i = 0; i < o->ndark; i++) {
            char v[128];
            snprintf(v, sizeof v, "%.17g,%.17g,%.17g,%.17g", o->dark[i][0], o->dark[i][1], o->dark[i][2], o->dark[i][3]);
            vp_note_put_str(buf, n, &len, "--dark", v);
        }
    }
    if (o->motion) {
        vp_note_put_str(buf, n, &len, "--motion", o->motion);
        vp_note_put_num(buf, n, &len, "--speed", o->speed);
        vp_note_put_num(buf, n, &len, "--accel", o->accel);
        vp_note_put_num(buf, n, &len, "--probe-time", o->probe_time);
    }
}

/* ---------- begin / end ---------- */

int vp_sim_session_set_path(vp_sim_session_t *g, const vp_sim_options_t *o, char *err, size_t errlen)
{
    g->path[0] = 0;
    if (g->no_log && !g->resume) return VP_OK;
    if (g->log) return vp_path_cat(g->path, sizeof g->path, g->log, "", err, errlen);
    if (g->resume) return vp_path_cat(g->path, sizeof g->path, g->resume, "", err, errlen);
    if (o->out) return vp_path_cat(g->path, sizeof g->path, o->out, ".vplog", err, errlen);
    return VP_OK;
}

/* The log is open: every command goes to it (the session hooks). */
static void attach_log(vp_sim_session_t *g, vp_sim_t *s)
{
    g->active = 1;
    g->w.raw = &s->raw;
    g->w.stop_after = g->stop_after;
    g->hooks.ctx = &g->w;
    g->hooks.after = vp_sessionlog_after;
    s->hooks = &g->hooks;
}

/* The object of the last RESCAN event of the loaded log (its text: --surface SPEC). */
static int last_rescan_surface(vp_sim_session_t *g, char *err, size_t errlen)
{
    uint32_t i;
    for (i = g->L.n; i-- > 0;) {
        vp_logfmt_record_t rec;
        if (vp_sessionlog_record(&g->L, i, &rec) != VP_OK || rec.type != VP_LOGFMT_EVENT ||
            rec.event != VP_LOGFMT_EV_RESCAN || (rec.code & VP_RESCAN_HERE)) /* a tracking round: the object stays */
            continue;
        if (strncmp(rec.text, "--surface ", 10) != 0 || !rec.text[10]) break;
        memcpy(g->rescan_spec, rec.text + 10, strlen(rec.text + 10) + 1);
        g->rescan_surface = g->rescan_spec;
        return VP_OK;
    }
    if (i == (uint32_t)-1) return VP_OK; /* tracking rounds only: the logged object */
    snprintf(err, errlen, "the log's last RESCAN event does not name the object (--surface SPEC)");
    return VP_ECORRUPT;
}

/* --rescan OLD: OLD replayed into s->pl (with the object it was made on: the same planner
 * configuration), copied to the new log, a RESCAN event, the planner's re-scan, and the device
 * at the start facing the object now. */
static int rescan_begin(vp_sim_session_t *g, vp_sim_t *s, const vp_sim_options_t *o, FILE *msg, char *err,
                        size_t errlen)
{
    vp_replay_t R;
    char why[200], text[VP_LOGFMT_TEXT_MAX + 1];
    const char *now = g->rescan_surface ? g->rescan_surface : o->surface;
    int st;
    if (!vp_sessionlog_same_config(&g->L.header.cfg, g->L.header.arena_bytes, &s->cfg, (uint64_t)o->arena,
                                   why, sizeof why)) {
        snprintf(err, errlen, "%s: the scan configuration is not the logged one (%s)", g->rescan, why);
        return VP_EINVAL;
    }
    if (!g->no_log) {
        struct stat a, b;
        if (!g->path[0] || !strcmp(g->path, g->rescan) ||
            (stat(g->path, &a) == 0 && stat(g->rescan, &b) == 0 && a.st_dev == b.st_dev && a.st_ino == b.st_ino)) {
            snprintf(err, errlen, "a re-scan writes a new log: give --out or --log other than %s", g->rescan);
            return VP_EINVAL;
        }
    }
    if (strlen(now) + 10 > VP_LOGFMT_TEXT_MAX) {
        snprintf(err, errlen, "the object's name is too long for the log (%zu bytes at most)", (size_t)VP_LOGFMT_TEXT_MAX - 10);
        return VP_EINVAL;
    }
    vp_replay_init_state(&R, s->pl, &g->L);
    st = vp_replay_run(&R, &g->L, g->L.n, why, sizeof why);
    if (st != VP_OK) { snprintf(err, errlen, "%s: replay failed: %s", g->rescan, why); return st; }
    g->replayed = R.applied;
    if ((st = vp_planner_rescan_with(s->pl, g->sparse ? VP_RESCAN_SPARSE : 0u)) != VP_OK) {
        snprintf(err, errlen, "%s: the planner cannot re-scan this session: %s", g->rescan, vp_strerror(st));
        return st;
    }
    if ((st = vp_sim_swap_surface(s, now, err, errlen)) != VP_OK) return st;
    if (msg) fprintf(msg, "rescan %s: %u records replayed (%llu probes), %u samples to measure again on %s\n",
                     g->rescan, R.applied, (unsigned long long)R.probes, s->pl->dt.ninserted, now);
    if (g->no_log) return VP_OK;
    if (vp_mkdirs_for(g->path) != 0) {
        snprintf(err, errlen, "cannot create the folder of %s: %s", g->path, strerror(errno));
        return VP_EIO;
    }
    st = vp_logwriter_create_copy(&g->w.file, g->path, g->L.data, g->L.good_bytes, g->L.n, &g->fcfg);
    snprintf(text, sizeof text, "--surface %s", now);
    if (st == VP_OK) st = vp_logwriter_event(&g->w.file, VP_LOGFMT_EV_RESCAN, g->sparse ? VP_RESCAN_SPARSE : 0u, text);
    if (st != VP_OK) {
        snprintf(err, errlen, "cannot write the session log %s: %s", g->path, strerror(errno));
        return st;
    }
    attach_log(g, s);
    return VP_OK;
}

int vp_sim_session_begin(vp_sim_session_t *g, vp_sim_t *s, const vp_sim_options_t *o, FILE *msg,
                    char *err, size_t errlen)
{
    char why[200], stop[600];
    int st;
    s->raw = NAN;
    if (g->no_log && !g->resume && !g->rescan) return VP_OK;
    if ((st = vp_sim_session_set_path(g, o, err, errlen)) != VP_OK) return st;
    if (!g->path[0]) return VP_OK;
    if (vp_mkdirs_for(g->path) != 0) {
        snprintf(err, errlen, "cannot create the folder of %s: %s", g->path, strerror(errno));
        return VP_EIO;
    }
    if (g->rescan) return rescan_begin(g, s, o, msg, err, errlen);
    if (g->resume) {
        vp_replay_t R;
        if (!vp_sessionlog_same_config(&g->L.header.cfg, g->L.header.arena_bytes, &s->cfg, (uint64_t)o->arena,
                                 why, sizeof why)) {
            snprintf(err, errlen, "%s: the scan configuration is not the logged one (%s): resume with "
                     "the options the log was made with", g->resume, why);
            return VP_EINVAL;
        }
        vp_sessionlog_stop_text(&g->L, stop, sizeof stop);
        if (msg) fprintf(msg, "resume %s: %s\n", g->resume, stop);
        vp_replay_init_state(&R, s->pl, &g->L);
        st = vp_replay_run(&R, &g->L, g->L.n, why, sizeof why);
        if (st != VP_OK) { snprintf(err, errlen, "%s: replay failed: %s", g->resume, why); return st; }
        g->replayed = R.applied;
        g->complete = g->L.done;
        if (R.rescans > 0) {
            /* a paused re-scan: the object is the one its last RESCAN event names */
            if ((st = last_rescan_surface(g, err, errlen)) != VP_OK) return st;
            if (g->rescan_surface) {
                if ((st = vp_sim_swap_surface(s, g->rescan_surface, err, errlen)) != VP_OK) return st;
                s->before = R.at_rescan;
            }
        }
        /* the simulated device's probes so far (its noise): since the object was swapped */
        vp_simdev_restore(s->dev, R.pos, g->rescan_surface ? R.probes_since_rescan : R.probes);
        if (msg) fprintf(msg, "resume: %u records replayed (%llu probes, %llu moves), device at %.6g %.6g %.6g%s\n",
                         R.applied, (unsigned long long)R.probes, (unsigned long long)R.moves,
                         R.pos[0], R.pos[1], R.pos[2], g->complete ? "; the session is already complete" : "");
        if (g->no_log) return VP_OK;
        if (strcmp(g->path, g->resume) != 0) {
            /* --log elsewhere: the valid part of the resumed log, then the new records */
            st = vp_logwriter_create_copy(&g->w.file, g->path, g->L.data, g->L.good_bytes, g->L.n, &g->fcfg);
            if (st == VP_OK && g->complete) {  /* nothing to append */
                st = vp_logwriter_close(&g->w.file);
                if (st == VP_OK) return VP_OK;
            }
        } else if (g->complete)
            return VP_OK;   /* nothing to append */
        else
            st = vp_logwriter_open_append_read(&g->w.file, g->path, g->L.good_bytes, g->L.n, (uint64_t)g->L.size,
                                             &g->fcfg);
        if (st == VP_OK) {
            snprintf(why, sizeof why, "resumed after record %d", (int)g->L.n - 1);
            st = vp_logwriter_event(&g->w.file, VP_LOGFMT_EV_RESUME, 0, why);
        }
    } else {
        vp_logfmt_header_t h;
        char note[VP_LOGFMT_NOTE_MAX + 1];
        vp_sim_session_note(o, note, sizeof note);
        vp_logfmt_header_init(&h, &s->cfg, (uint64_t)o->arena, VP_LOGFMT_UNITS_NONE, "host-sim", note);
        st = vp_logwriter_create(&g->w.file, g->path, &h, &g->fcfg);
        if (st == VP_OK) st = vp_logwriter_event(&g->w.file, VP_LOGFMT_EV_START, 0, "voroprobe sim");
    }
    if (st != VP_OK) {
        if (g->w.file.dead) { g->active = 1; g->w.failed = 1; return VP_OK; } /* cut at once */
        if (g->w.file.busy)
            snprintf(err, errlen, "log %s is being written by another process: it is left as it is (wait for "
                     "that scan to end, or give another --out or --log)", g->path);
        else if (g->w.file.changed)
            snprintf(err, errlen, "log %s was written by another process while it was read: it is left as it "
                     "is (resume again)", g->path);
        else
            snprintf(err, errlen, "cannot write the session log %s: %s", g->path, strerror(errno));
        return st;
    }
    attach_log(g, s);
    return VP_OK;
}

int vp_sim_session_end(vp_sim_session_t *g, vp_sim_t *s, FILE *msg)
{
    int st = s->run.status;
    if (!g->active) return 0;
    if (g->w.file.dead) {
        if (msg) fprintf(msg, "sim: simulated power cut: the log %s stops at byte %llu; resume with --resume %s\n",
                         g->path, (unsigned long long)g->w.file.bytes, g->path);
        vp_logwriter_close(&g->w.file);
        return 1;
    }
    if (!g->w.failed) {
        if (st == VP_EABORT && g->w.stopped) {
            char t[80];
            snprintf(t, sizeof t, "paused after %lu commands (%s)", g->w.commands,
                     g->w.stop_flag && *g->w.stop_flag ? "a signal" : "--stop-after");
            vp_logwriter_event(&g->w.file, VP_LOGFMT_EV_PAUSE, 0, t);
            if (msg) fprintf(msg, "sim: %s; the mesh so far is written; resume with --resume %s\n", t, g->path);
        } else if (st != VP_OK) {
            vp_logwriter_event(&g->w.file, VP_LOGFMT_EV_FAULT, st, vp_strerror(st));
        }
    }
    if (vp_logwriter_close(&g->w.file) != VP_OK || g->w.failed) {
        if (msg) fprintf(msg, "sim: writing the session log %s failed: %s\n", g->path, strerror(errno));
    }
    return 0;
}

void vp_sim_session_report(const vp_sim_session_t *g, FILE *f)
{
    if (!g->path[0] || g->no_log) return;
    if (g->complete && !g->active)
        fprintf(f, "log: %s (complete; %u records replayed, nothing appended)\n", g->path, g->replayed);
    else
        fprintf(f, "log: %s (%u records replayed + %lu written, %lu syncs)\n", g->path, g->replayed,
                g->w.file.records, g->w.file.syncs);
}
