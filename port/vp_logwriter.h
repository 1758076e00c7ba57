/* vp_logwriter — the session log as a POSIX file: header on create, records appended one
 * write() each, synced to the medium by a policy (every record, every N records, every T ms),
 * trading flash wear and speed against what a power cut can take.
 *
 * For power-loss tests the writer can "die" after a set number of bytes (littlefs's emubd
 * idea): the write in progress is torn exactly there and every later call fails with VP_EIO,
 * as if the power had gone.
 */
#ifndef VP_LOGWRITER_H
#define VP_LOGWRITER_H
#include <stdint.h>
#include "vp_logfmt.h"

typedef struct vp_logwriter_config {
    uint32_t sync_records;     /* fdatasync after this many unsynced records (0: not by count) */
    uint32_t sync_ms;          /* ... or when the oldest unsynced record is this old (0: not by time) */
    uint64_t die_after_bytes;  /* power-cut simulation: the file never grows past this (0: off) */
} vp_logwriter_config_t;         /* all zero: sync only on close; see vp_logwriter_config_default */

typedef struct vp_logwriter {
    int fd;
    vp_logwriter_config_t cfg;
    uint32_t seq;              /* the next record's sequence number */
    uint64_t bytes;            /* the file's length */
    uint32_t unsynced;         /* records written since the last sync */
    double first_unsynced;     /* monotonic seconds of the oldest unsynced record */
    unsigned long records, syncs;
    int dead;                  /* the simulated power cut happened */
    int busy;                  /* create/open failed: another process is writing this log */
    int changed;               /* open failed: the log is no longer the size it was read at */
} vp_logwriter_t;

/* Every record synced: nothing acknowledged is ever lost. */
void vp_logwriter_config_default(vp_logwriter_config_t *c);
/* Parses a policy: "record" (each record), "N" (every N records), "Tms" (every T ms), "N,Tms",
 * "close" (only on close). 0 or -1 (bad text). */
int vp_logwriter_parse_sync(const char *s, vp_logwriter_config_t *c);

/* A log being written is locked (flock, exclusive) from create or open until close: a second
 * writer of the same file, in this process or another, gets VP_EIO with f->busy set, and the
 * file is left exactly as it was. */

/* Creates (or replaces) path with the header; the header is synced at once. cfg may be NULL
 * (default). VP_OK, VP_EINVAL, VP_EIO (errno kept; f->busy: locked by another writer). */
int vp_logwriter_create(vp_logwriter_t *f, const char *path, const vp_logfmt_header_t *h,
                      const vp_logwriter_config_t *cfg);
/* Creates (or replaces) path with n bytes of another log (its header and valid records, as
 * read) to append to, continuing with sequence number next_seq. */
int vp_logwriter_create_copy(vp_logwriter_t *f, const char *path, const void *data, uint64_t n,
                           uint32_t next_seq, const vp_logwriter_config_t *cfg);
/* Opens an existing log to append: cuts it back to good_bytes (the end of its last valid
 * record, from the reader) and continues with sequence number next_seq. */
int vp_logwriter_open_append(vp_logwriter_t *f, const char *path, uint64_t good_bytes,
                           uint32_t next_seq, const vp_logwriter_config_t *cfg);
/* The same for a log read whole at read_size bytes: once the lock is ours the file must still
 * be that long (else VP_EIO, f->changed, nothing cut: another writer added records after it was
 * read). */
int vp_logwriter_open_append_read(vp_logwriter_t *f, const char *path, uint64_t good_bytes, uint32_t next_seq,
                                uint64_t read_size, const vp_logwriter_config_t *cfg);
/* Sets rec->seq, encodes and writes it, syncs when the policy says so. VP_EIO on a failed
 * write (or after the simulated power cut). */
int vp_logwriter_append(vp_logwriter_t *f, vp_logfmt_record_t *rec);
int vp_logwriter_event(vp_logwriter_t *f, uint32_t event, int32_t code, const char *text);
int vp_logwriter_sync(vp_logwriter_t *f);
/* Syncs and closes (also after a failure: then only closes). */
int vp_logwriter_close(vp_logwriter_t *f);

#endif
