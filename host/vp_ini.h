/* vp_ini — a small INI reader: [section], key = value, comments from '#' or ';' (at the line
 * start, or after a blank inside a value), blanks trimmed. The caller's function sees every
 * key with its section and line; its complaint (or the parser's) becomes one message naming
 * the file, the line, the section and the key. No allocation; lines up to VP_INI_LINE bytes,
 * without NUL bytes. */
#ifndef VP_INI_H
#define VP_INI_H
#include <stddef.h>

#define VP_INI_LINE 512

/* Return 0, or < 0 after writing a reason into msg. */
typedef int (*vp_ini_fn)(void *user, const char *section, const char *key, const char *value, int line,
                         char *msg, size_t msglen);

/* VP_OK; VP_EIO (cannot read the file, or it is not a regular file of at most VP_INI_MAX_FILE
 * bytes); VP_EINVAL (syntax, a NUL byte in a line, or the function refused). */
#define VP_INI_MAX_FILE (1u << 20)
int vp_ini_parse_file(const char *path, vp_ini_fn fn, void *user, char *err, size_t errlen);
/* The same on text in memory; name is used in messages. */
int vp_ini_parse_text(const char *text, const char *name, vp_ini_fn fn, void *user, char *err, size_t errlen);

#endif
