/* vp_sessionlog — session logs on the host: loading a log file (keeping every valid record before
 * the first bad one), replaying it through the planner, and the vp_session hook that writes
 * one record per executed command. */
#ifndef VP_SESSIONLOG_H
#define VP_SESSIONLOG_H
#include <stddef.h>
#include <signal.h>
#include <stdio.h>
#include "vp_logfmt.h"
#include "vp_logwriter.h"
#include "vp_planner.h"
#include "vp_session.h"

/* A loaded log: the file's bytes, the valid records' offsets, and where reading stopped. */
typedef struct vp_sessionlog {
    vp_logfmt_header_t header;
    unsigned char *data;
    size_t size;               /* file bytes */
    size_t *off;               /* offsets of the valid records */
    uint32_t n;                /* valid records */
    int status;                /* VP_OK: the file ends cleanly after record n-1 */
    int reason;                /* VP_LOGFMT_R_* when status != VP_OK */
    uint64_t good_bytes;       /* end of the last valid record */
    uint64_t probes, hits, moves, events;
    uint64_t rays, ray_hits;           /* RAY records: a line laser's more rays per frame */
    int done;                  /* a DONE event is among the records */
} vp_sessionlog_t;

/* Loads path. Fails (err set) only when the file cannot be read or its header is unusable
 * (not a regular file, not a log, newer version, damaged header); damage after the header is kept in
 * status/reason and the records before it are loaded. A failed load holds nothing (no
 * vp_sessionlog_free needed); a loaded one is freed with vp_sessionlog_free. */
#define VP_SESSIONLOG_MAX_FILE (1ULL << 33)   /* a larger file is refused (it is read whole) */
int  vp_sessionlog_load(vp_sessionlog_t *L, const char *path, char *err, size_t errlen);
/* 1 if the file at path begins with a session log's magic (what a command that takes a log or
 * another file looks at first), 0 otherwise or when it cannot be read. */
int  vp_sessionlog_is_log(const char *path);
int  vp_sessionlog_load_buf(vp_sessionlog_t *L, const void *buf, size_t len, char *err, size_t errlen);
void vp_sessionlog_free(vp_sessionlog_t *L);
/* Record i (< n), decoded again from the bytes. */
int  vp_sessionlog_record(const vp_sessionlog_t *L, uint32_t i, vp_logfmt_record_t *rec);
/* One line on where and why reading stopped ("complete" when it did not). */
void vp_sessionlog_stop_text(const vp_sessionlog_t *L, char *buf, size_t n);
const char *vp_sessionlog_event_name(uint32_t event);

/* Replay through a planner. */
typedef struct vp_replay {
    vp_planner_t *pl;
    void *arena;
    uint32_t applied;          /* records replayed */
    double pos[3];             /* device position after them */
    double from[3];            /* where the last MOVE started */
    uint64_t probes;           /* PROBE records replayed (the device's probe count) */
    uint64_t hits;             /* of which hits */
    uint64_t rays;             /* RAY records replayed (a line laser's more rays) */
    uint64_t moves;            /* MOVE records replayed */
    uint64_t contacts;         /* CONTACT events replayed (moves the contact switch stopped) */
    uint64_t rescans;          /* RESCAN events replayed (vp_planner_rescan) */
    uint64_t probes_since_rescan; /* PROBE records after the last RESCAN of code 0 */
    vp_planner_stats_t at_rescan; /* the planner's counters when that re-scan began */
    int done;                  /* the planner said DONE after the last record */
    int touched_outside;       /* the session stopped at a contact outside Omega (the object
                                  reaches out of it): the planner stays in that error, and no scan
                                  goes on from the log (a replay, a mesh, a report still do) */
} vp_replay_t;

/* Why no scan goes on from a log whose replay ended with touched_outside. */
#define VP_REPLAY_TOUCHED_OUTSIDE_TEXT "the session stopped where the head touched outside Omega (the object " \
    "reaches out of [omega]); no scan goes on from this log: move the part back inside Omega (or enlarge " \
    "[omega]) and start a new scan"

/* Creates the planner from the header (arena: the header's size unless arena != 0). */
int  vp_replay_open(vp_replay_t *R, const vp_sessionlog_t *L, size_t arena, char *err, size_t errlen);
/* Replays records [R->applied, upto) (upto > n: all) into R->pl (which may also be a planner
 * made elsewhere with the same configuration: set R->pl and call vp_replay_init_state). On a
 * mismatch err names the record, its offset and what differed. */
int  vp_replay_run(vp_replay_t *R, const vp_sessionlog_t *L, uint32_t upto, char *err, size_t errlen);
void vp_replay_init_state(vp_replay_t *R, vp_planner_t *pl, const vp_sessionlog_t *L);
void vp_replay_close(vp_replay_t *R);

/* 1 if the two configurations (and arenas) are the same bit for bit; else 0 and a line
 * naming the first field that differs. */
int  vp_sessionlog_same_config(const vp_planner_config_t *a, uint64_t arena_a,
                         const vp_planner_config_t *b, uint64_t arena_b, char *why, size_t n);

/* The writer hook: give vp_session_hooks_t { w, vp_sessionlog_after }. */
typedef struct vp_sessionlog_writer {
    vp_logwriter_t file;
    const double *raw;         /* the device's raw reading of its last probe (NULL: NaN) */
    unsigned long commands;    /* commands logged by this writer */
    unsigned long stop_after;  /* pause after this many commands (0: never): VP_EABORT */
    const volatile sig_atomic_t *stop_flag; /* set by a signal: pause after this command */
    int stopped;               /* paused (stop_after or stop_flag) */
    int failed;                /* a write failed (or the simulated power cut happened) */
} vp_sessionlog_writer_t;
int  vp_sessionlog_after(void *ctx, const vp_cmd_t *cmd, const vp_probe_result_t *res);

#endif
