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

/* Short constant text for a status, for messages. */
const char *vp_strerror(int status);

#define VP_TRY(expr) do { int vp_try_s_ = (expr); if (vp_try_s_ < 0) return vp_try_s_; } while (0)

#endif
