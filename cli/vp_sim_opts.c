/* vp_sim_opts — see vp_sim_opts.h. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_note.h"
#include "vp_sim_opts.h"

int vp_parse_size(const char *s, size_t *out)
{
    char *e;
    double v = strtod(s, &e);
    if (e == s || !(v >= 0)) return -1;
    if (*e == 'k' || *e == 'K') { v *= 1024.0; e++; }
    else if (*e == 'm' || *e == 'M') { v *= 1048576.0; e++; }
    else if (*e == 'g' || *e == 'G') { v *= 1073741824.0; e++; }
    if (*e || v > 1e15) return -1;
    *out = (size_t)v;
    return 0;
}

int vp_parse_count(const char *s, unsigned long long max, unsigned long long *out)
{
    unsigned long long v = 0;
    const char *c = s;
    if (!*c) return -1;
    for (; *c; c++) {
        unsigned d = (unsigned)(*c - '0');
        if (d > 9u || v > (max - d) / 10u) return -1; /* strtoul would take "-3" as a huge count */
        v = 10u * v + d;
    }
    *out = v;
    return 0;
}

static int num(const char *s, double *v)
{
    char *e;
    *v = strtod(s, &e);
    return e != s && !*e && isfinite(*v);
}

int vp_sim_parse_option(vp_sim_options_t *o, int argc, char **argv, int *i, char *err, size_t errlen)
{
    const char *a = argv[*i], *val = *i + 1 < argc ? argv[*i + 1] : NULL;
    double v;
    if (!strcmp(a, "--json")) { o->json = 1; return 0; }
    if (!strcmp(a, "--quiet")) { o->quiet = 1; return 0; }
    if (!strcmp(a, "--paper")) { o->flags |= VP_PLAN_PAPER | VP_PLAN_PREV_CHAINS | VP_PLAN_LARGEST; return 0; }
    if (!strcmp(a, "--largest")) { o->flags |= VP_PLAN_LARGEST; return 0; }
    if (!strcmp(a, "--far-reads")) { o->flags |= VP_PLAN_FAR_READS; return 0; }
    if (!strcmp(a, "--newest-first")) { o->newest_first = 1; return 0; }
    if (!strcmp(a, "--prev-chains")) { o->flags |= VP_PLAN_PREV_CHAINS; return 0; }
    if (!strcmp(a, "--contact")) { o->contact = 1; return 0; }
    if (!strcmp(a, "--dark")) {
        double *d;
        char *e;
        const char *q = val;
        int k;
        if (!val) { snprintf(err, errlen, "--dark needs X,Y,Z,R"); return -1; }
        if (o->ndark >= VP_SIMDEV_MAX_DARK) { snprintf(err, errlen, "--dark: at most %d patches", VP_SIMDEV_MAX_DARK); return -1; }
        d = o->dark[o->ndark];
        for (k = 0; k < 4; k++) {
            d[k] = strtod(q, &e);
            if (e == q || !isfinite(d[k]) || (k < 3 && *e != ',') || (k == 3 && *e)) {
                snprintf(err, errlen, "--dark takes X,Y,Z,R (a ball: the surface inside it returns no spot), not '%s'", val);
                return -1;
            }
            q = e + 1;
        }
        if (!(d[3] > 0)) { snprintf(err, errlen, "--dark: the radius must be > 0"); return -1; }
        o->ndark++;
        (*i)++;
        return 0;
    }
    if (!strcmp(a, "--proof-life")) {
        char *e;
        long n;
        if (!val) { snprintf(err, errlen, "--proof-life needs N (commands)"); return -1; }
        n = strtol(val, &e, 10);
        if (e == val || *e || n < 0 || n > 1000000000L) {
            snprintf(err, errlen, "--proof-life takes a number of commands, 0 (never) to 1e9, not '%s'", val);
            return -1;
        }
        o->proof_life = n;
        (*i)++;
        return 0;
    }
    if (!strcmp(a, "--line-laser")) {
        char *e;
        long n;
        if (!val) { snprintf(err, errlen, "--line-laser needs N[,DEG]"); return -1; }
        n = strtol(val, &e, 10);
        o->line_deg = 30.0;
        if (e == val || n < 1 || n > VP_PLANNER_MAX_LINE_RAYS || (*e && *e != ',') ||
            (*e == ',' && (!num(e + 1, &o->line_deg) || !(o->line_deg > 0.0) || o->line_deg > 120.0))) {
            snprintf(err, errlen, "--line-laser takes N[,DEG]: N more rays per probe (1 to %d) over a fan of DEG "
                     "degrees (above 0, at most 120; default 30), not '%s'", VP_PLANNER_MAX_LINE_RAYS, val);
            return -1;
        }
        o->line_rays = (unsigned)n;
        (*i)++;
        return 0;
    }
    if (strncmp(a, "--", 2) != 0) return 1;
    if (strcmp(a, "--surface") && strcmp(a, "--eps") && strcmp(a, "--eps-rel") && strcmp(a, "--out") &&
        strcmp(a, "--noise") && strcmp(a, "--dropout") && strcmp(a, "--clearance") &&
        strcmp(a, "--min-feature") && strcmp(a, "--feature-margin") &&
        strcmp(a, "--max-range") && strcmp(a, "--min-range") && strcmp(a, "--arena") && strcmp(a, "--omega") &&
        strcmp(a, "--seed") && strcmp(a, "--hausdorff") && strcmp(a, "--confirm") && strcmp(a, "--margin") &&
        strcmp(a, "--angle") && strcmp(a, "--size-rel") && strcmp(a, "--min-size") && strcmp(a, "--max-distance") &&
        strcmp(a, "--accuracy") && strcmp(a, "--accuracy-rel"))
        return 1;
    if (!val) { snprintf(err, errlen, "%s needs a value", a); return -1; }
    (*i)++;
    if (!strcmp(a, "--surface")) { o->surface = val; return 0; }
    if (!strcmp(a, "--out")) { o->out = val; return 0; }
    if (!strcmp(a, "--omega")) {
        if (!strcmp(val, "box")) o->omega_ball = 0;
        else if (!strcmp(val, "ball")) o->omega_ball = 1;
        else { snprintf(err, errlen, "--omega takes box or ball, not '%s'", val); return -1; }
        return 0;
    }
    if (!strcmp(a, "--arena")) {
        if (vp_parse_size(val, &o->arena)) { snprintf(err, errlen, "--arena: bad size '%s'", val); return -1; }
        return 0;
    }
    if (!num(val, &v)) { snprintf(err, errlen, "%s: not a number: '%s'", a, val); return -1; }
    if (!strcmp(a, "--eps")) {
        if (!(v > 0)) { snprintf(err, errlen, "--eps must be > 0"); return -1; }
        if (o->eps_rel > 0) { snprintf(err, errlen, "--eps and --eps-rel both set eps: give one of them"); return -1; }
        o->eps = v;
    } else if (!strcmp(a, "--eps-rel")) {
        if (!(v > 0 && v < 1)) { snprintf(err, errlen, "--eps-rel must be in (0, 1)"); return -1; }
        if (o->eps > 0) { snprintf(err, errlen, "--eps and --eps-rel both set eps: give one of them"); return -1; }
        o->eps_rel = v;
    } else if (!strcmp(a, "--noise")) {
        if (!(v >= 0)) { snprintf(err, errlen, "--noise must be >= 0"); return -1; }
        o->noise = v;
    } else if (!strcmp(a, "--dropout")) {
        if (!(v >= 0 && v < 1)) { snprintf(err, errlen, "--dropout must be in [0, 1)"); return -1; }
        o->dropout = v;
    } else if (!strcmp(a, "--clearance")) {
        if (!(v >= 0)) { snprintf(err, errlen, "--clearance must be >= 0"); return -1; }
        o->clearance = v;
    } else if (!strcmp(a, "--min-feature")) {
        if (!(v >= 0)) { snprintf(err, errlen, "--min-feature must be >= 0"); return -1; }
        o->min_feature = v;
    } else if (!strcmp(a, "--feature-margin")) {
        if (!(v >= 0)) { snprintf(err, errlen, "--feature-margin must be >= 0"); return -1; }
        o->feature_margin = v;
    } else if (!strcmp(a, "--min-range")) {
        if (!(v >= 0)) { snprintf(err, errlen, "--min-range must be >= 0"); return -1; }
        o->min_range = v;
    } else if (!strcmp(a, "--max-range")) {
        if (!(v >= 0)) { snprintf(err, errlen, "--max-range must be >= 0"); return -1; }
        o->max_range = v;
    } else if (!strcmp(a, "--margin")) {
        if (!(v > 0 && v < 10)) { snprintf(err, errlen, "--margin must be in (0, 10)"); return -1; }
        o->omega_margin = v;
    } else if (!strcmp(a, "--seed")) {
        if (!(v >= 0)) { snprintf(err, errlen, "--seed must be >= 0"); return -1; }
        o->seed = (unsigned long long)v;
    } else if (!strcmp(a, "--hausdorff")) {
        if (!(v >= 0)) { snprintf(err, errlen, "--hausdorff must be >= 0"); return -1; }
        o->hausdorff = (size_t)v;
    } else if (!strcmp(a, "--angle")) {
        if (!(v >= 0 && v <= 30)) { snprintf(err, errlen, "--angle must be in [0, 30] degrees"); return -1; }
        o->min_angle = v;
    } else if (!strcmp(a, "--size-rel")) {
        if (!(v > 0 && v < 1)) { snprintf(err, errlen, "--size-rel must be in (0, 1) (the sizing field's eps; 0.1-0.5 is usual)"); return -1; }
        o->size_rel = v;
    } else if (!strcmp(a, "--accuracy") || !strcmp(a, "--accuracy-rel")) {
        int rel = !strcmp(a, "--accuracy-rel");
        if (!(v > 0 && (rel ? v < 0.5 : v < 1e150))) {
            snprintf(err, errlen, "%s must be > 0%s", a, rel ? " and below 0.5 (of the bounding-box diagonal)" : " (object units)");
            return -1;
        }
        if (o->accuracy > 0 || o->accuracy_rel > 0) { snprintf(err, errlen, "give one of --accuracy and --accuracy-rel"); return -1; }
        if (rel) o->accuracy_rel = v; else o->accuracy = v;
    } else if (!strcmp(a, "--max-distance")) {
        if (!(v > 0 && v < 1e150)) { snprintf(err, errlen, "--max-distance must be > 0 (object units)"); return -1; }
        o->max_distance = v;
    } else if (!strcmp(a, "--min-size")) {
        if (!(v > 0 && v < 1e150)) { snprintf(err, errlen, "--min-size must be > 0 (object units)"); return -1; }
        o->min_size = v;
    } else if (!strcmp(a, "--confirm")) {
        if (!(v >= 0 && v <= 16)) { snprintf(err, errlen, "--confirm must be in 0..16"); return -1; }
        o->confirm = (int)v;
    }
    return 0;
}

int vp_sim_parse_motion_option(vp_sim_options_t *o, int argc, char **argv, int *i, char *err, size_t errlen)
{
    const char *a = argv[*i], *val = *i + 1 < argc ? argv[*i + 1] : NULL;
    double v;
    if (strcmp(a, "--motion") && strcmp(a, "--speed") && strcmp(a, "--accel") && strcmp(a, "--probe-time")) return 1;
    if (!val) { snprintf(err, errlen, "%s needs a value", a); return -1; }
    (*i)++;
    if (!strcmp(a, "--motion")) {
        char sub[256];
        if (vp_motion_check_spec(val, sub, sizeof sub) != VP_OK) { snprintf(err, errlen, "--motion: %s", sub); return -1; }
        o->motion = val;
        return 0;
    }
    if (!num(val, &v) || !(v >= 0) || v > 1e150 || (!strcmp(a, "--speed") && !(v > 0))) {
        snprintf(err, errlen, "%s takes a number %s, not '%s'", a, !strcmp(a, "--speed") ? "> 0" : ">= 0", val);
        return -1;
    }
    if (!strcmp(a, "--speed")) o->speed = v;
    else if (!strcmp(a, "--accel")) o->accel = v;
    else o->probe_time = v;
    return 0;
}

int vp_sim_session_parse_option(vp_sim_session_t *g, int argc, char **argv, int *i, char *err, size_t errlen)
{
    const char *a = argv[*i], *val = *i + 1 < argc ? argv[*i + 1] : NULL;
    if (!strcmp(a, "--no-log")) { g->no_log = 1; return 0; }
    if (!strcmp(a, "--rescan-sparse")) { g->sparse = 1; return 0; }
    if (strcmp(a, "--log") && strcmp(a, "--resume") && strcmp(a, "--rescan") && strcmp(a, "--sync") &&
        strcmp(a, "--stop-after") && strcmp(a, "--power-cut"))
        return 1;
    if (!val) { snprintf(err, errlen, "%s needs a value", a); return -1; }
    (*i)++;
    if (!strcmp(a, "--log")) g->log = val;
    else if (!strcmp(a, "--resume")) g->resume = val;
    else if (!strcmp(a, "--rescan")) g->rescan = val;
    else if (!strcmp(a, "--sync")) {
        if (vp_logwriter_parse_sync(val, &g->fcfg)) {
            snprintf(err, errlen, "--sync takes record, close, N (records), Tms or N,Tms; not '%s'", val);
            return -1;
        }
    } else {
        unsigned long long v;
        if (vp_parse_count(val, ~0ull, &v) || v == 0) { snprintf(err, errlen, "%s takes a positive integer, not '%s'", a, val); return -1; }
        if (!strcmp(a, "--stop-after")) g->stop_after = (unsigned long)v;
        else g->fcfg.die_after_bytes = v;
    }
    return 0;
}

int vp_sim_session_options(vp_sim_session_t *g, vp_sim_options_t *o, int argc, char **argv, char *err,
                      size_t errlen)
{
    char *note = g->note, *tok[128], sub[512];
    const char *src = g->resume ? g->resume : g->rescan;
    int n, i, st, has_out = 0;
    if (!src) return VP_OK;
    if (g->resume && g->rescan) {
        snprintf(err, errlen, "--resume and --rescan cannot go together (resume a paused re-scan with --resume alone)");
        return VP_EINVAL;
    }
    st = vp_sessionlog_load(&g->L, src, err, errlen);
    if (st != VP_OK) return st;
    g->have_L = 1;
    memcpy(note, g->L.header.note, sizeof g->note);
    n = vp_note_split(note, tok, 128);
    if (n < 1 || strcmp(tok[0], "sim") != 0) {
        snprintf(err, errlen, "%s was not written by `sim` (its note does not start with 'sim'): "
                 "resume it with the program that wrote it", src);
        return VP_EINVAL;
    }
    vp_sim_options_default(o);
    for (i = 1; i < n; i++) {
        st = vp_sim_parse_option(o, n, tok, &i, sub, sizeof sub);
        if (st != 0 && !strcmp(tok[i], "--motion")) {
            snprintf(err, errlen, "%s: a session with a moving object (--motion) cannot be resumed: its log holds "
                     "no clock", src);
            return VP_EINVAL;
        }
        if (st != 0) {
            snprintf(err, errlen, "%s: the options recorded in the log are not understood ('%s'%s%s)",
                     src, tok[i], st < 0 ? ": " : "", st < 0 ? sub : "");
            return VP_EINVAL;
        }
    }
    /* a session logged without the smallest ball first (a log format before 8) ran with the
     * newest task first */
    if (!(g->L.header.cfg.flags & VP_PLAN_SMALL_FIRST)) o->newest_first = 1;
    for (i = 1; i < argc; i++) {
        vp_sim_session_t scratch;
        vp_sim_session_init(&scratch);
        if (!strcmp(argv[i], "--out")) has_out = 1;
        if (vp_sim_session_parse_option(&scratch, argc, argv, &i, sub, sizeof sub) == 0) continue;
        if (g->rescan && !strcmp(argv[i], "--surface") && i + 1 < argc) {
            g->rescan_surface = argv[++i]; /* the object now; the session's own builds its Omega */
            continue;
        }
        if (g->rescan && (!strcmp(argv[i], "--png") || !strcmp(argv[i], "--track") || !strncmp(argv[i], "--serve", 7))) {
            i++; /* taken by cmd_sim */
            continue;
        }
        if (g->rescan && strcmp(argv[i], "--out") && strcmp(argv[i], "--json") && strcmp(argv[i], "--quiet") &&
            strcmp(argv[i], "--hausdorff")) {
            snprintf(err, errlen, "%s: a re-scan keeps the options of the session it re-scans (its log's); give only "
                     "--surface (the object now) and the outputs (--out, --log, --json, --quiet, --hausdorff, --png)", argv[i]);
            return VP_EINVAL;
        }
        {
            int at = i, bad = vp_sim_parse_option(o, argc, argv, &i, sub, sizeof sub);
            if (bad < 0) {
                snprintf(err, errlen, "%s (the options given with --resume add to those in the log)", sub);
                return VP_EINVAL;
            }
            if (bad > 0) {
                snprintf(err, errlen, "unknown option %s", argv[at]);
                return VP_EINVAL;
            }
        }
    }
    if (!has_out) {
        /* the mesh goes beside the log: LOG minus .vplog */
        size_t len = strlen(src);
        if (len > 6 && !strcmp(src + len - 6, ".vplog")) {
            st = vp_path_cat(g->prefix, sizeof g->prefix, src, "", err, errlen);
            if (st == VP_OK) g->prefix[len - 6] = 0;
            if (st == VP_OK && g->rescan) {
                char base[VP_PATH_MAX];
                memcpy(base, g->prefix, sizeof base);
                st = vp_path_cat(g->prefix, sizeof g->prefix, base, ".rescan", err, errlen);
            }
        } else
            st = vp_path_cat(g->prefix, sizeof g->prefix, src, g->rescan ? ".rescan" : ".resumed", err, errlen);
        if (st != VP_OK) return st;
        o->out = g->prefix;
    }
    return VP_OK;
}
