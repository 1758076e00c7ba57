/* vp_sim_session — the session log of `sim`: its settings (--log, --no-log, --resume, --sync,
 * --stop-after, --power-cut; parsed by cli/vp_sim_opts), creating the log, resuming from one
 * (replay, device restored, append), and the closing event. cmd_sim.c calls these around vp_sim_open/run/finish. */
#ifndef VP_SIM_SESSION_H
#define VP_SIM_SESSION_H
#include <stdio.h>
#include "vp_note.h"
#include "vp_sim_setup.h"
#include "vp_sessionlog.h"

typedef struct vp_sim_session {
    const char *log;             /* --log FILE (NULL: PREFIX.vplog) */
    const char *resume;          /* --resume LOG */
    const char *rescan;          /* --rescan LOG: the session to scan again */
    const char *rescan_surface;  /* the object now (--surface with --rescan; NULL: the logged one;
                                    on --resume of a re-scan, the last RESCAN event's) */
    char rescan_spec[VP_LOGFMT_TEXT_MAX + 1];
    int no_log;                  /* --no-log */
    int sparse;                  /* --rescan-sparse: re-scans and tracking rounds measure part of
                                    the samples (VP_RESCAN_SPARSE) */
    vp_logwriter_config_t fcfg;    /* --sync, --power-cut */
    unsigned long stop_after;    /* --stop-after N */
    /* state */
    char path[VP_PATH_MAX], prefix[VP_PATH_MAX];
    char note[VP_LOGFMT_NOTE_MAX + 1];  /* the resumed log's options (o points into it) */
    vp_sessionlog_t L;                 /* the resumed log */
    int have_L, active, complete;
    uint32_t replayed;
    vp_sessionlog_writer_t w;
    vp_session_hooks_t hooks;
} vp_sim_session_t;

void vp_sim_session_init(vp_sim_session_t *g);
/* The log's path (--log, the resumed log, or PREFIX.vplog; none with --no-log) into g->path,
 * checked before anything is written: VP_EINVAL (err) when it is too long. */
int  vp_sim_session_set_path(vp_sim_session_t *g, const vp_sim_options_t *o, char *err, size_t errlen);
/* After vp_sim_open: creates the log, or replays the resumed one into s->pl (the configuration
 * must be the logged one bit for bit), puts the device where the log left it and reopens the
 * log to append. Sets s->hooks. msg: progress notes (may be NULL). */
int  vp_sim_session_begin(vp_sim_session_t *g, vp_sim_t *s, const vp_sim_options_t *o, FILE *msg,
                     char *err, size_t errlen);
/* After the run: FAULT or PAUSE event (DONE is written when the planner says so), sync, close.
 * Returns 1 when the simulated power cut stopped the run (nothing more may be written). */
int  vp_sim_session_end(vp_sim_session_t *g, vp_sim_t *s, FILE *msg);
/* One summary line (nothing without a log). */
void vp_sim_session_report(const vp_sim_session_t *g, FILE *f);
void vp_sim_session_free(vp_sim_session_t *g);
/* The sim options as a command line (the log's note); parsing it back gives the same
 * configuration bit for bit. */
void vp_sim_session_note(const vp_sim_options_t *o, char *buf, size_t n);

#endif
