/* Status codes shared by every voroprobe module.
 * A fallible call returns int: >= 0 is success (some calls return a count), < 0 is a VP_E* code.
 * On any error the object the call worked on is unchanged and valid. */
#ifndef VP_STATUS_H
#define VP_STATUS_H

enum vp_status {
    VP_OK       = 0,
    VP_EINVAL   = -1,  /* bad argument: NaN/Inf coordinate, out of range, null pointer */
    VP_ENOMEM   = -2,  /* the caller's arena (or a fixed buffer in it) is full */
    VP_EDUP     = -3,  /* point already present (the existing vertex is reported) */
    VP_ESTATE   = -4,  /* call not allowed in the object's current state */
    VP_ECORRUPT = -5,  /* bytes failed a check (CRC, length, magic) */
    VP_EVERSION = -6,  /* data from a newer format version */
    VP_ERANGE   = -7,  /* a value outside Omega, travel limits or probe range */
    VP_EDEGEN   = -8,  /* internal consistency check failed (reported, never silent) */
    VP_EIO      = -9,  /* port: the device or file refused (errno kept by the port) */
    VP_ENODEV   = -10, /* port: hardware not present */
    VP_ETIMEOUT = -11, /* port: no answer in time */
    VP_EABORT   = -12, /* stopped by e-stop or user; the session stays resumable */
    VP_EUNSAFE  = -13, /* a move with no proof of free space: refused, nothing moved */
    VP_ESTALL   = -14  /* no progress within the planner's work bound: stopped */
};

/* Build option VP_CORE_MCU: define it when compiling the core (core/ and the planner) for a
 * microcontroller image, as tests/t_cortex_m4.sh does for boards/cortex-m4. Scans, commands
 * and logs stay the same bit for bit; the core is smaller (Cortex-M4 -Os: 49,114 bytes, 47.96 KiB, not 70,565).
 * It leaves out
 *   - what only host tools and tests call: vp_dt_check, vp_dt_remove, vp_dt_insert_batch (and
 *     vp_sort), vp_dt_locate, vp_dt_in_conflict;
 *   - vp_strerror and vp_logfmt_reason_text: texts for people, which the host shows (a device
 *     reports status codes);
 *   - the session log's incremental reader (vp_logfmt_reader_*): the host reads log files
 *     (host/vp_sessionlog.c); a device decodes whole headers and records from its link
 *     (vp_logfmt_header_decode, vp_logfmt_record_decode); and replay (vp_logfmt_replay): logs
 *     are replayed (resumed, checked) by the host or a Linux board's full build;
 *   - the exact predicates' floating-point stages after the filters (vp_pred.c: A', A, B, C,
 *     11 KB of software double arithmetic on a core without a double-precision FPU): what the
 *     filters leave undecided (near-degenerate input) goes to the exact integer stage X at
 *     once, 32-bit integer arithmetic that such a core has in hardware. Every stage is exact,
 *     so the signs are the same.
 * The declarations of what is left out are hidden too: a call fails to compile. */

#ifndef VP_CORE_MCU
/* Short constant text for a status, for messages. */
const char *vp_strerror(int status);
#endif

#define VP_TRY(expr) do { int vp_try_s_ = (expr); if (vp_try_s_ < 0) return vp_try_s_; } while (0)

#endif
