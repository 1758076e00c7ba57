/* vp_audit — keeps a copy of every session log a command wrote, for a later independent proof
 * check (`voroprobe log verify`). Off unless the environment names a folder:
 *   VP_AUDIT_DIR=DIR   each sim or scan copies its log to DIR/<pid>-<n>-<name> when it ends
 * `make check` sets it, then verifies every copy (tests/verify_sessions.sh). */
#ifndef VP_AUDIT_H
#define VP_AUDIT_H

/* Copies the log at path into $VP_AUDIT_DIR (nothing when unset). 0, or -1 with a message on
 * stderr (the scan's own result is not changed by a failed copy). */
int vp_audit_keep(const char *path);

#endif
