/* vp_sessionlog — see vp_sessionlog.h. */
#include <errno.h>
#include <stdio.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "vp_file.h"
#include "vp_sessionlog.h"
#include "vp_vec3.h"

const char *vp_sessionlog_event_name(uint32_t event)
{
    switch (event) {
    case VP_LOGFMT_EV_START: return "start";
    case VP_LOGFMT_EV_PAUSE: return "pause";
    case VP_LOGFMT_EV_RESUME: return "resume";
    case VP_LOGFMT_EV_FAULT: return "fault";
    case VP_LOGFMT_EV_DONE: return "done";
    case VP_LOGFMT_EV_CALIBRATION: return "calibration";
    case VP_LOGFMT_EV_STEPPING: return "stepping";
    case VP_LOGFMT_EV_CONTACT: return "contact";
    case VP_LOGFMT_EV_RESCAN: return "rescan";
    default: return "unknown";
    }
}

static int index_records(vp_sessionlog_t *L, char *err, size_t errlen)
{
    vp_logfmt_reader_t *r = malloc(sizeof *r);
    size_t pos = 0, cap = 1024;
    int st = VP_LOGFMT_NEED_MORE;
    if (!r || !(L->off = malloc(cap * sizeof *L->off))) {
        free(r);
        snprintf(err, errlen, "out of memory");
        return VP_ENOMEM;
    }
    vp_logfmt_reader_init(r);
    while (pos < L->size) {
        vp_logfmt_record_t rec;
        size_t used;
        uint64_t at = r->offset;
        st = vp_logfmt_reader_push(r, L->data + pos, L->size - pos, &used, &rec);
        pos += used;
        if (st < 0) break;
        if (st == VP_LOGFMT_GOT_HEADER) L->header = r->header;
        if (st != VP_LOGFMT_GOT_RECORD) continue;
        if (L->n == cap) {
            size_t *o = realloc(L->off, 2 * cap * sizeof *o);
            if (!o) { free(r); snprintf(err, errlen, "out of memory"); return VP_ENOMEM; }
            L->off = o;
            cap *= 2;
        }
        L->off[L->n++] = (size_t)at;
        if (rec.type == VP_LOGFMT_PROBE) { L->probes++; L->hits += rec.hit == 1; }
        else if (rec.type == VP_LOGFMT_RAY) { L->rays++; L->ray_hits += rec.hit == 1; }
        else if (rec.type == VP_LOGFMT_MOVE) L->moves++;
        else {
            L->events++;
            if (rec.event == VP_LOGFMT_EV_DONE) L->done = 1;
            if (rec.event == VP_LOGFMT_EV_RESCAN) L->done = 0; /* a re-scan goes on from there */
        }
    }
    if (st >= 0) st = vp_logfmt_reader_finish(r);
    L->good_bytes = r->offset;
    L->status = st < 0 ? st : VP_OK;
    L->reason = st < 0 ? r->reason : VP_LOGFMT_R_OK;
    if (!r->have_header) {
        int vst = r->status == VP_EVERSION ? VP_EVERSION : VP_ECORRUPT;
        if (r->reason == VP_LOGFMT_R_VERSION)
            snprintf(err, errlen, "the log was written by a newer format version (%u; this build reads up to %u): "
                     "use a newer voroprobe", (unsigned)(L->size >= 10 ? L->data[8] | L->data[9] << 8 : 0),
                     VP_LOGFMT_VERSION);
        else if (r->reason == VP_LOGFMT_R_HEADER_CRC || r->reason == VP_LOGFMT_R_HEADER) {
            /* the version field is believed only in an intact header */
            unsigned ver = (unsigned)(L->size >= 10 ? L->data[8] | L->data[9] << 8 : 0);
            unsigned long hl = L->size >= 16 ? (unsigned long)L->data[12] | (unsigned long)L->data[13] << 8 |
                                               (unsigned long)L->data[14] << 16 | (unsigned long)L->data[15] << 24 : 0;
            char why[200] = "";
            if (ver > VP_LOGFMT_VERSION && r->reason == VP_LOGFMT_R_HEADER_CRC)
                snprintf(why, sizeof why, "; its version field reads %u, not a newer format: a newer log's header "
                         "would be intact", ver);
            else if (ver > VP_LOGFMT_VERSION)
                snprintf(why, sizeof why, "; its version field reads %u (this build reads up to %u): damaged, or a "
                         "newer format whose header this build cannot check", ver, VP_LOGFMT_VERSION);
            if (r->reason == VP_LOGFMT_R_HEADER_CRC)
                snprintf(err, errlen, "unusable header: the header is damaged (header CRC mismatch over bytes 0..%lu)%s",
                         hl - 1, why);
            else
                snprintf(err, errlen, "unusable header: the header is damaged (an invalid length, version or field)%s",
                         why);
        } else
            snprintf(err, errlen, "unusable header: %s", vp_logfmt_reason_text(r->reason));
        free(r);
        return vst;
    }
    free(r);
    return VP_OK;
}

int vp_sessionlog_load_buf(vp_sessionlog_t *L, const void *buf, size_t len, char *err, size_t errlen)
{
    int st;
    memset(L, 0, sizeof *L);
    L->data = malloc(len ? len : 1);
    if (!L->data) { snprintf(err, errlen, "out of memory"); return VP_ENOMEM; }
    if (len) memcpy(L->data, buf, len);
    L->size = len;
    st = index_records(L, err, errlen);
    if (st != VP_OK) vp_sessionlog_free(L);
    return st;
}

/* The first bytes of a log: its magic (a shorter file is left to the reader: truncated). */
static const char *slog_head(const unsigned char *p, size_t n)
{
    if (n >= VP_LOGFMT_MAGIC_LEN && memcmp(p, vp_logfmt_magic, VP_LOGFMT_MAGIC_LEN) != 0)
        return "bad magic (a voroprobe session log starts with \"VPLOG\")";
    return NULL;
}

int vp_sessionlog_is_log(const char *path)
{
    unsigned char b[VP_LOGFMT_MAGIC_LEN];
    FILE *f = fopen(path, "rb");
    size_t n;
    if (!f) return 0;
    n = fread(b, 1, sizeof b, f);
    fclose(f);
    return n == sizeof b && memcmp(b, vp_logfmt_magic, sizeof b) == 0;
}

int vp_sessionlog_load(vp_sessionlog_t *L, const char *path, char *err, size_t errlen)
{
    unsigned char *p = NULL;
    size_t n = 0;
    char sub[400];
    int st;
    memset(L, 0, sizeof *L);
    /* a regular file of bounded size (a device would be read until memory runs out) */
    st = vp_file_read(path, VP_SESSIONLOG_MAX_FILE, "session log", slog_head, &p, &n, sub, sizeof sub);
    if (st != VP_OK) {
        snprintf(err, errlen, "%s", sub);
        return st == VP_ECORRUPT ? VP_ECORRUPT : VP_EIO;
    }
    L->data = p;
    L->size = n;
    st = index_records(L, sub, sizeof sub);
    if (st != VP_OK) {
        snprintf(err, errlen, "%s: %s", path, sub);
        vp_sessionlog_free(L);
    }
    return st;
}

void vp_sessionlog_free(vp_sessionlog_t *L)
{
    free(L->data);
    free(L->off);
    memset(L, 0, sizeof *L);
}

int vp_sessionlog_record(const vp_sessionlog_t *L, uint32_t i, vp_logfmt_record_t *rec)
{
    int st;
    if (i >= L->n) return VP_EINVAL;
    st = vp_logfmt_record_decode(L->data + L->off[i], L->size - L->off[i], rec, NULL);
    return st < 0 ? st : VP_OK;
}

void vp_sessionlog_stop_text(const vp_sessionlog_t *L, char *buf, size_t n)
{
    if (L->status == VP_OK) {
        snprintf(buf, n, "complete: %u records, %llu bytes, all CRCs and sequence numbers good",
                 L->n, (unsigned long long)L->size);
        return;
    }
    snprintf(buf, n, "reading stops at record %u (byte offset %llu): %s; records 0..%d "
             "(bytes 0..%llu) are valid and kept, %llu byte(s) after them are not used",
             L->n, (unsigned long long)L->good_bytes, vp_logfmt_reason_text(L->reason), (int)L->n - 1,
             (unsigned long long)L->good_bytes, (unsigned long long)(L->size - L->good_bytes));
}

/* ---------- replay ---------- */

void vp_replay_init_state(vp_replay_t *R, vp_planner_t *pl, const vp_sessionlog_t *L)
{
    memset(R, 0, sizeof *R);
    R->pl = pl;
    memcpy(R->pos, L->header.cfg.start, sizeof R->pos);
}

int vp_replay_open(vp_replay_t *R, const vp_sessionlog_t *L, size_t arena, char *err, size_t errlen)
{
    size_t bytes = arena ? arena : (size_t)L->header.arena_bytes;
    int st;
    vp_replay_init_state(R, NULL, L);
    if (bytes == 0 || (uint64_t)bytes != (arena ? (uint64_t)arena : L->header.arena_bytes)) {
        snprintf(err, errlen, "the header's arena size %llu cannot be used here",
                 (unsigned long long)L->header.arena_bytes);
        return VP_EINVAL;
    }
    R->pl = malloc(sizeof *R->pl);
    R->arena = malloc(bytes);
    if (!R->pl || !R->arena) {
        snprintf(err, errlen, "cannot allocate the planner's %zu-byte arena", bytes);
        return VP_ENOMEM;
    }
    st = vp_planner_init(R->pl, R->arena, bytes, &L->header.cfg);
    if (st != VP_OK) {
        snprintf(err, errlen, "the planner refuses the header's configuration: %s", vp_strerror(st));
        return st;
    }
    return VP_OK;
}

void vp_replay_close(vp_replay_t *R)
{
    free(R->pl);
    free(R->arena);
    memset(R, 0, sizeof *R);
}

static const char *cmd_name(int kind)
{
    return kind == VP_CMD_MOVE ? "MOVE" : kind == VP_CMD_PROBE ? "PROBE" : kind == VP_CMD_DONE ? "DONE" : kind == VP_CMD_RAY ? "RAY" : "?";
}

static const char *type_name(int type)
{
    return type == VP_LOGFMT_MOVE ? "MOVE" : type == VP_LOGFMT_PROBE ? "PROBE" : type == VP_LOGFMT_RAY ? "RAY" : "EVENT";
}

int vp_replay_run(vp_replay_t *R, const vp_sessionlog_t *L, uint32_t upto, char *err, size_t errlen)
{
    if (upto > L->n) upto = L->n;
    while (R->applied < upto) {
        vp_logfmt_record_t rec;
        vp_logfmt_mismatch_t mm;
        uint32_t i = R->applied;
        int st = vp_sessionlog_record(L, i, &rec);
        if (st != VP_OK) {
            snprintf(err, errlen, "record %u (byte offset %zu) cannot be decoded", i, L->off[i]);
            return st;
        }
        memset(&mm, 0, sizeof mm);
        if (rec.type == VP_LOGFMT_EVENT) {
            if (rec.event == VP_LOGFMT_EV_CONTACT) {
                /* the head touched during the MOVE before: the planner learns it again */
                double d[3], len;
                int k;
                st = vp_planner_touch(R->pl, rec.value[0]);
                if (st == VP_ERANGE && !R->touched_outside) {
                    /* outside Omega: the session stopped there (the object reaches out of it), as
                     * the planner does again; only events may follow */
                    R->touched_outside = 1;
                    R->contacts++;
                    R->applied++;
                    continue;
                }
                if (st != VP_OK) {
                    snprintf(err, errlen, "record %u (byte offset %zu): the planner refused the logged contact: %s",
                             i, L->off[i], vp_strerror(st));
                    return st;
                }
                vp_sub3(d, R->pos, R->from);
                len = sqrt(vp_dot3(d, d));
                for (k = 0; k < 3; k++) R->pos[k] = R->from[k] + rec.value[0] * (len > 0.0 ? d[k] / len : 0.0);
                R->contacts++;
            }
            if (rec.event == VP_LOGFMT_EV_RESCAN) {
                /* a re-scan: the planner measures its samples again from the start */
                st = vp_planner_rescan_with(R->pl, rec.code); /* the code: the re-scan's flags */
                if (st != VP_OK) {
                    snprintf(err, errlen, "record %u (byte offset %zu): the planner refused the re-scan: %s",
                             i, L->off[i], vp_strerror(st));
                    return st;
                }
                if (!(rec.code & VP_RESCAN_HERE)) memcpy(R->pos, L->header.cfg.start, sizeof R->pos);
                R->done = 0;
                R->rescans++;
                if (!(rec.code & VP_RESCAN_HERE)) { /* a re-scan of the object now (not a tracking round) */
                    R->probes_since_rescan = 0;
                    vp_planner_get_stats(R->pl, &R->at_rescan);
                }
            }
            if (rec.event == VP_LOGFMT_EV_DONE && !R->done) {
                /* the planner must agree that the session is complete */
                vp_cmd_t cmd;
                st = vp_planner_next(R->pl, &cmd);
                if (st != VP_OK || cmd.kind != VP_CMD_DONE) {
                    snprintf(err, errlen, "record %u (byte offset %zu): the log says DONE, the planner %s%s",
                             i, L->off[i], st != VP_OK ? "stopped: " : "issued ",
                             st != VP_OK ? vp_strerror(st) : cmd_name(cmd.kind));
                    return st != VP_OK ? st : VP_ECORRUPT;
                }
                R->done = 1;
            }
            R->applied++;
            continue;
        }
        st = vp_logfmt_replay(R->pl, &rec, &mm);
        if (st == VP_ECORRUPT && mm.field) {
            if (mm.got_kind != (rec.type == VP_LOGFMT_MOVE ? VP_CMD_MOVE : rec.type == VP_LOGFMT_RAY ? VP_CMD_RAY : VP_CMD_PROBE))
                snprintf(err, errlen, "record %u (byte offset %zu): the log has a %s, the planner issued %s: "
                         "this log was made by another planner build or configuration", i, L->off[i],
                         type_name(rec.type), cmd_name(mm.got_kind));
            else
                snprintf(err, errlen, "record %u (byte offset %zu): the planner's %s differs in its %s "
                         "(not bit for bit the logged one): another planner build or configuration",
                         i, L->off[i], type_name(rec.type), mm.field);
            return st;
        }
        if (st != VP_OK) {
            snprintf(err, errlen, "record %u (byte offset %zu): the planner stopped: %s", i, L->off[i],
                     vp_strerror(st));
            return st;
        }
        if (rec.type == VP_LOGFMT_MOVE) {
            memcpy(R->from, R->pos, sizeof R->from);
            memcpy(R->pos, rec.target, sizeof R->pos);
            R->moves++;
        }
        else if (rec.type == VP_LOGFMT_RAY) R->rays++;
        else { R->probes++; R->probes_since_rescan++; R->hits += rec.hit == 1; }
        R->applied++;
    }
    return VP_OK;
}

static int bits_eq(const double *a, const double *b, int n)
{
    return memcmp(a, b, (size_t)n * sizeof(double)) == 0;
}

int vp_sessionlog_same_config(const vp_planner_config_t *a, uint64_t arena_a,
                        const vp_planner_config_t *b, uint64_t arena_b, char *why, size_t n)
{
    const char *f = NULL;
    uint32_t i;
    if (a->omega_kind != b->omega_kind) f = "Omega kind";
    else if (!bits_eq(&a->eps, &b->eps, 1)) f = "eps";
    else if (a->omega_kind == VP_OMEGA_BOX && (!bits_eq(a->omega_lo, b->omega_lo, 3) || !bits_eq(a->omega_hi, b->omega_hi, 3))) f = "Omega box";
    else if (a->omega_kind == VP_OMEGA_BALL && (!bits_eq(a->omega_center, b->omega_center, 3) || !bits_eq(&a->omega_radius, &b->omega_radius, 1))) f = "Omega ball";
    else if (a->ninterior != b->ninterior) f = "number of interior points";
    else if (!bits_eq(a->start, b->start, 3)) f = "start position";
    else if (!bits_eq(&a->max_range, &b->max_range, 1)) f = "max range";
    else if (!bits_eq(&a->noise_tol, &b->noise_tol, 1)) f = "noise tolerance";
    else if (!bits_eq(&a->clearance, &b->clearance, 1)) f = "clearance";
    else if (!bits_eq(&a->min_angle, &b->min_angle, 1)) f = "angle bound";
    else if (!bits_eq(&a->size_rel, &b->size_rel, 1)) f = "sizing field (--size-rel)";
    else if (!bits_eq(&a->min_size, &b->min_size, 1)) f = "size floor (--min-size)";
    else if (!bits_eq(&a->max_distance, &b->max_distance, 1)) f = "distance bound (--max-distance)";
    else if (a->confirm_misses != b->confirm_misses) f = "confirm misses";
    else if (a->flags != b->flags) f = "planner flags";
    else if (a->line_rays != b->line_rays) f = "line laser rays (--line-laser)";
    else if (a->proof_life != b->proof_life) f = "proof life (--proof-life)";
    else if (!bits_eq(&a->min_feature, &b->min_feature, 1)) f = "tubes' feature size (--min-feature)";
    else if (!bits_eq(&a->feature_margin, &b->feature_margin, 1)) f = "tubes' feature margin (--feature-margin)";
    else if (!bits_eq(a->axis_time, b->axis_time, VP_PLANNER_AXES)) f = "axes' times per unit (the board's max_speed)";
    else if (!bits_eq(a->pan_travel, b->pan_travel, 2)) f = "pan's travel";
    else if (arena_a != arena_b) f = "arena size";
    for (i = 0; !f && i < a->ninterior && i < VP_PLANNER_MAX_SEEDS; i++)
        if (!bits_eq(a->interior[i], b->interior[i], 3)) f = "interior points";
    if (f && why) snprintf(why, n, "%s differs", f);
    return f == NULL;
}

/* ---------- writer hook ---------- */

int vp_sessionlog_after(void *ctx, const vp_cmd_t *cmd, const vp_probe_result_t *res)
{
    vp_sessionlog_writer_t *w = ctx;
    vp_logfmt_record_t rec;
    int st;
    /* a record lost to a failed write is never followed by the next one: the log would skip a
     * sequence number (a path's MOVEs are logged one after the other after it) */
    if (w->failed) return VP_EIO;
    if (cmd->kind == VP_CMD_DONE) {
        vp_logfmt_record_event(&rec, 0, VP_LOGFMT_EV_DONE, 0, "the planner says DONE");
    } else if (cmd->kind == VP_CMD_MOVE) {
        vp_logfmt_record_move(&rec, 0, cmd);
        if (res && res->hit == 1) {
            /* the contact switch stopped it: the MOVE, then where */
            double d[3], len;
            int k;
            st = vp_logwriter_append(&w->file, &rec);
            if (st != VP_OK) { w->failed = 1; return st; }
            vp_sub3(d, cmd->to, cmd->from);
            len = sqrt(vp_dot3(d, d));
            vp_logfmt_record_event(&rec, 0, VP_LOGFMT_EV_CONTACT, 0, "the contact switch stopped the move");
            rec.value[0] = res->dist;
            /* as the planner and the simulated device form it: the unit direction first */
            for (k = 0; k < 3; k++) rec.value[1 + k] = cmd->from[k] + res->dist * (len > 0.0 ? d[k] / len : 0.0);
        }
    } else {
        vp_logfmt_record_probe(&rec, 0, cmd, res, w->raw ? *w->raw : NAN);
    }
    st = vp_logwriter_append(&w->file, &rec);
    if (st != VP_OK) { w->failed = 1; return st; }
    if (cmd->kind == VP_CMD_RAY) return VP_OK; /* part of the PROBE's frame: a pause comes after it all */
    w->commands++;
    if (cmd->kind != VP_CMD_DONE &&
        ((w->stop_after && w->commands >= w->stop_after) || (w->stop_flag && *w->stop_flag))) {
        w->stopped = 1;
        return VP_EABORT;
    }
    return VP_OK;
}
