/* vp_logfmt — the session log's format, encoded and decoded: every command a scan executed,
 * with every probe's result, so a session can be replayed bit for bit, resumed after a power
 * cut and meshed on a PC.
 *
 * Binary, little-endian, versioned; doubles are stored as their IEEE-754 bits (never text).
 * A header (the exact planner configuration, units, arena size, board name, a note), then
 * append-only records (PROBE, MOVE, EVENT), each with its length, a sequence number and a
 * CRC-32. The byte layout is in doc/session-log.md (enough to write another reader).
 *
 * The core only encodes into caller buffers and decodes from them: no heap, no stdio. The
 * reader is incremental (feed any chunks) and stops at the first bad item, reporting which
 * record and at which byte offset; everything before it stays usable.
 */
#ifndef VP_LOGFMT_H
#define VP_LOGFMT_H

#include <stddef.h>
#include <stdint.h>
#include "vp_planner.h"
#include "vp_status.h"

#ifndef VP_CORE_MCU
#define VP_LOGFMT_VERSION     8u  /* 2 adds the sizing field (size_rel, min_size) after the note,
                                     3 the distance bound too, 4 a line laser's rays per frame
                                     (and RAY records) and the proofs' life, 5 the tubes' feature
                                     size and margin, 6 the axes' times and the pan's travel
                                     (moves weighed by machine time), 7 the spots read past
                                     the edge (VP_PLAN_FAR_READS; no more bytes: a build
                                     before it refuses such a log rather than replay it
                                     otherwise), 8 the smallest ball first
                                     (VP_PLAN_SMALL_FIRST; no more bytes, the same); a header
                                     is written in the oldest version that holds its
                                     configuration */
#else
#define VP_LOGFMT_VERSION     3u  /* a microcontroller core has no line laser */
#endif
#define VP_LOGFMT_MAGIC_LEN   8
#define VP_LOGFMT_BOARD_MAX   63     /* bytes of the board name */
#define VP_LOGFMT_NOTE_MAX    1023   /* bytes of the free-form note */
#define VP_LOGFMT_TEXT_MAX    255    /* bytes of an event's text */
#define VP_LOGFMT_MAX_HEADER  2048   /* no valid header is longer */
#define VP_LOGFMT_MAX_RECORD  320    /* no valid record is longer */
#define VP_LOGFMT_PROBE_SIZE  92     /* record sizes, framing included */
#define VP_LOGFMT_MOVE_SIZE   40
#define VP_LOGFMT_EVENT_BASE  58     /* + text length */

extern const unsigned char vp_logfmt_magic[VP_LOGFMT_MAGIC_LEN]; /* "VPLOG\r\n\x1a" */

enum vp_logfmt_units { VP_LOGFMT_UNITS_NONE = 0, VP_LOGFMT_UNITS_M = 1, VP_LOGFMT_UNITS_MM = 2,
                    VP_LOGFMT_UNITS_INCH = 3 };

typedef struct vp_logfmt_header {
    uint32_t version;              /* of the data read; the encoder writes VP_LOGFMT_VERSION */
    uint32_t units;                /* VP_LOGFMT_UNITS_* */
    vp_planner_config_t cfg;       /* exactly what vp_planner_init was given */
    uint64_t arena_bytes;          /* the planner's arena (its pools depend on it) */
    char board[VP_LOGFMT_BOARD_MAX + 1];  /* NUL-terminated */
    char note[VP_LOGFMT_NOTE_MAX + 1];    /* NUL-terminated */
} vp_logfmt_header_t;

/* RAY: one more ray of the PROBE before it (a line laser's frame), the PROBE's layout: its origin
 * is the PROBE's, range and raw as the device gave them. */
enum vp_logfmt_type { VP_LOGFMT_PROBE = 1, VP_LOGFMT_MOVE = 2, VP_LOGFMT_EVENT = 3, VP_LOGFMT_RAY = 4 };

enum vp_logfmt_event {
    VP_LOGFMT_EV_START = 1,       /* a session starts (text: what started it) */
    VP_LOGFMT_EV_PAUSE = 2,       /* stopped on purpose; resumable */
    VP_LOGFMT_EV_RESUME = 3,      /* the log was replayed and the scan goes on */
    VP_LOGFMT_EV_FAULT = 4,       /* the scan stopped on an error (code: VP_E*) */
    VP_LOGFMT_EV_DONE = 5,        /* the planner said DONE: the session is complete */
    VP_LOGFMT_EV_CALIBRATION = 6, /* device calibration (value[]: device-specific, text says) */
    VP_LOGFMT_EV_STEPPING = 7,    /* the step timing of the scan: retimes, faults, lateness */
    VP_LOGFMT_EV_CONTACT = 8,     /* right after a MOVE: the head's contact switch stopped it;
                                     value[0] the distance along the move, value[1..3] the point */
    VP_LOGFMT_EV_RESCAN = 9       /* a re-scan starts (vp_planner_rescan): the object may have
                                     changed; every free part logged before is stale; the code
                                     holds vp_planner_rescan_with's flags: bit 0 clear, the device
                                     is at the start again (text: the object now, e.g. "--surface
                                     SPEC"), set, it stays where it stands (a round of tracking);
                                     bit 1, a sparse re-scan */
};

typedef struct vp_logfmt_record {
    uint32_t seq;              /* sequence number: 0, 1, 2, ... after the header */
    int type;                  /* VP_LOGFMT_PROBE / MOVE / EVENT */
    /* PROBE (and RAY): the command and its result exactly as fed to the planner */
    double origin[3], dir[3], range;
    int hit;                   /* 1: hit at dist; 0: miss (dist as fed, normally 0); 2: too close */
    double dist;
    double raw;                /* the sensor's own reading before conversion (NaN: none) */
    /* MOVE */
    double target[3];
    /* EVENT */
    uint32_t event;            /* VP_LOGFMT_EV_* (other values are kept, for newer writers) */
    int32_t code;              /* a VP_E* status for FAULT, else free */
    double value[4];
    uint32_t text_len;
    char text[VP_LOGFMT_TEXT_MAX + 1]; /* NUL-terminated */
} vp_logfmt_record_t;

/* CRC-32 (IEEE 802.3, reflected 0xEDB88320, as zlib's crc32): start with crc = 0. */
uint32_t vp_logfmt_crc32(uint32_t crc, const void *data, size_t len);

/* Header: fills version, copies cfg, arena, and the board name and note (truncated to their
 * limits, at a byte boundary). */
void vp_logfmt_header_init(vp_logfmt_header_t *h, const vp_planner_config_t *cfg, uint64_t arena_bytes,
                        uint32_t units, const char *board, const char *note);
/* Bytes the header will take; VP_EINVAL for a header that cannot be written. */
int vp_logfmt_header_size(const vp_logfmt_header_t *h);
/* Encodes into buf[cap]: the byte count, VP_EINVAL (bad header), VP_ENOMEM (cap too small). */
int vp_logfmt_header_encode(const vp_logfmt_header_t *h, void *buf, size_t cap);

/* Record builders (every other field zeroed); record_probe makes a RAY for a VP_CMD_RAY. */
void vp_logfmt_record_probe(vp_logfmt_record_t *r, uint32_t seq, const vp_cmd_t *cmd,
                         const vp_probe_result_t *res, double raw);
void vp_logfmt_record_move(vp_logfmt_record_t *r, uint32_t seq, const vp_cmd_t *cmd);
void vp_logfmt_record_event(vp_logfmt_record_t *r, uint32_t seq, uint32_t event, int32_t code,
                         const char *text);
int vp_logfmt_record_size(const vp_logfmt_record_t *r);
/* Its size in buf; VP_ENOMEM when cap is too small; VP_EINVAL for a record the reader would
 * refuse (a PROBE's or RAY's non-finite origin, direction, range or distance or a hit outside
 * 0..2, a MOVE's non-finite target, an event's text too long): nothing is written. */
int vp_logfmt_record_encode(const vp_logfmt_record_t *r, void *buf, size_t cap);
/* Decodes one record from buf[len] (frame, CRC and fields checked; not the sequence): its size,
 * or VP_ECORRUPT with *reason (VP_LOGFMT_R_*; may be NULL). */
int vp_logfmt_record_decode(const void *buf, size_t len, vp_logfmt_record_t *rec, int *reason);

/* Why reading stopped. */
enum vp_logfmt_reason {
    VP_LOGFMT_R_OK = 0,
    VP_LOGFMT_R_TRUNCATED,    /* the data ends inside the header or a record (a torn write) */
    VP_LOGFMT_R_MAGIC,        /* not a voroprobe session log */
    VP_LOGFMT_R_VERSION,      /* written by a newer format version (header CRC good): refused */
    VP_LOGFMT_R_HEADER,       /* header length or a header field is invalid */
    VP_LOGFMT_R_HEADER_CRC,   /* header CRC mismatch */
    VP_LOGFMT_R_LENGTH,       /* record length impossible for its type */
    VP_LOGFMT_R_CRC,          /* record CRC mismatch */
    VP_LOGFMT_R_SEQUENCE,     /* sequence number is not the next one */
    VP_LOGFMT_R_TYPE,         /* unknown record type */
    VP_LOGFMT_R_FIELD         /* a field value is invalid (NaN coordinate, hit not 0/1, ...) */
};
#ifndef VP_CORE_MCU /* texts for people: host only (vp_status.h) */
const char *vp_logfmt_reason_text(int reason);
#endif

/* A whole header in buf (len bytes, a record or more may follow): its size, with *h; or
 * VP_ECORRUPT / VP_EVERSION (a newer format) with *reason (may be NULL), VP_EINVAL. */
int vp_logfmt_header_decode(const void *buf, size_t len, vp_logfmt_header_t *h, int *reason);

#ifndef VP_CORE_MCU /* the incremental reader: host only (vp_status.h) */
/* Incremental reader: push bytes in any chunks. Allocation-free (buffers inside). */
typedef struct vp_logfmt_reader {
    vp_logfmt_header_t header;    /* valid once have_header */
    int have_header;
    uint64_t offset;           /* end of the last complete item: everything before is good */
    uint32_t records;          /* complete records read (also the next expected sequence) */
    int status;                /* VP_OK while reading; the VP_E* that stopped it */
    int reason;                /* VP_LOGFMT_R_* */
    uint32_t bad_record;       /* the record that failed (== records); meaningless for header */
    int bad_in_header;         /* 1: the header failed */
    uint64_t bad_offset;       /* byte offset where the failing item starts */
    uint32_t need, have;       /* bytes the current item needs / has in buf */
    unsigned char buf[VP_LOGFMT_MAX_HEADER];
} vp_logfmt_reader_t;

#define VP_LOGFMT_NEED_MORE  0
#define VP_LOGFMT_GOT_HEADER 1
#define VP_LOGFMT_GOT_RECORD 2

void vp_logfmt_reader_init(vp_logfmt_reader_t *r);
/* Consumes data[0..len) until one item is complete. Returns VP_LOGFMT_NEED_MORE (all of data
 * used), VP_LOGFMT_GOT_HEADER (r->header), VP_LOGFMT_GOT_RECORD (*rec), or the VP_E* status that
 * stopped reading (VP_ECORRUPT, VP_EVERSION; then r->reason, bad_record, bad_offset say
 * where; every later call returns it again). *used gets the bytes consumed. */
int vp_logfmt_reader_push(vp_logfmt_reader_t *r, const void *data, size_t len, size_t *used,
                       vp_logfmt_record_t *rec);
/* The data ended: VP_OK when it ended between records, else VP_ECORRUPT with reason
 * VP_LOGFMT_R_TRUNCATED (or the earlier error). */
int vp_logfmt_reader_finish(vp_logfmt_reader_t *r);
#endif

#ifndef VP_CORE_MCU /* replay: host only (vp_status.h) */
/* Replay of one record through the planner: EVENT records are skipped; for MOVE and PROBE
 * the planner's next command must equal the logged one bit for bit (a PROBE's result is then
 * fed). VP_OK; VP_ECORRUPT when the planner issued something else (*mismatch says what; a
 * different planner build or configuration); a planner error as returned. */
typedef struct vp_logfmt_mismatch {
    int expected_type, got_kind;   /* VP_LOGFMT_* logged, VP_CMD_* issued */
    const char *field;             /* "kind", "target", "origin", "dir", "range" */
    vp_cmd_t got;
} vp_logfmt_mismatch_t;
int vp_logfmt_replay(vp_planner_t *pl, const vp_logfmt_record_t *rec, vp_logfmt_mismatch_t *mismatch);
#endif

#endif
