#include "vp_status.h"

#ifndef VP_CORE_MCU /* texts for people: host only (vp_status.h) */

const char *vp_strerror(int status)
{
    switch (status) {
    case VP_OK:       return "ok";
    case VP_EINVAL:   return "invalid argument";
    case VP_ENOMEM:   return "arena exhausted";
    case VP_EDUP:     return "duplicate point";
    case VP_ESTATE:   return "not allowed in this state";
    case VP_ECORRUPT: return "corrupt data";
    case VP_EVERSION: return "unsupported format version";
    case VP_ERANGE:   return "out of range";
    case VP_EDEGEN:   return "internal consistency check failed";
    case VP_EIO:      return "input/output error";
    case VP_ENODEV:   return "no such device";
    case VP_ETIMEOUT: return "timed out";
    case VP_EABORT:   return "aborted";
    case VP_EUNSAFE:  return "move refused: no proof that its segment is free";
    case VP_ESTALL:   return "no progress: the scan cannot go on";
    default:          return status >= 0 ? "ok" : "unknown error";
    }
}
#endif
