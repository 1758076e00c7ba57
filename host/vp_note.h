/* vp_note — a session's options as one line of text, the note in a session log's header, so
 * that `--resume` and `replay` rebuild the same scan from the log alone.
 *
 * Tokens are separated by single spaces; a token with a space, quote, backslash, tab or
 * newline (or an empty one) is written in single quotes with ' and \ escaped by a backslash.
 * Numbers are written in the shortest of %.15g..%.17g that reads back as the same double.
 * Writers never overrun buf (n bytes, always terminated); *len is the length so far.
 */
#ifndef VP_NOTE_H
#define VP_NOTE_H
#include <limits.h>
#include <stddef.h>

void vp_note_put(char *buf, size_t n, size_t *len, const char *tok);
/* name, then the value (a path, a surface: any length that fits buf) */
void vp_note_put_str(char *buf, size_t n, size_t *len, const char *name, const char *value);
/* name, then the value formatted by fmt (printf-style, at most 63 characters) */
void vp_note_put_opt(char *buf, size_t n, size_t *len, const char *name, const char *fmt, ...);
/* name, then x in its shortest exact form */
void vp_note_put_num(char *buf, size_t n, size_t *len, const char *name, double x);
/* Splits a note back into at most cap tokens, in place in buf; returns the count, or -1 when
 * there are more than cap. */
int vp_note_split(char *buf, char **tok, int cap);

/* Creates the folders above a file's path (for PREFIX.ply, LOG); 0 or -1 (errno set, also for
 * a path of VP_PATH_MAX bytes or more). */
int vp_mkdirs_for(const char *path);

/* Paths of output files: any length the system takes (PATH_MAX bytes with the NUL). */
#ifdef PATH_MAX
#define VP_PATH_MAX PATH_MAX
#else
#define VP_PATH_MAX 4096
#endif
#define VP_NAME_MAX 255   /* bytes of one file or folder name */
/* buf[n] = prefix followed by ext (ext may be ""), checked: the whole path shorter than n and
 * every name in it at most VP_NAME_MAX bytes. VP_OK, or VP_EINVAL with a message in err
 * naming the path (nothing is cut short). */
int vp_path_cat(char *buf, size_t n, const char *prefix, const char *ext, char *err, size_t errlen);

#endif
