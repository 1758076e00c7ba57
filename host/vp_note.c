/* vp_note — see vp_note.h. */
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "vp_note.h"
#include "vp_status.h"

void vp_note_put(char *buf, size_t n, size_t *len, const char *tok)
{
    size_t k;
    int quote = *tok == 0;
    for (k = 0; tok[k]; k++)
        if (tok[k] == ' ' || tok[k] == '\'' || tok[k] == '\\' || tok[k] == '\t' || tok[k] == '\n') quote = 1;
    if (*len && *len + 1 < n) buf[(*len)++] = ' ';
    if (quote && *len + 1 < n) buf[(*len)++] = '\'';
    for (k = 0; tok[k] && *len + 2 < n; k++) {
        if (tok[k] == '\'' || tok[k] == '\\') buf[(*len)++] = '\\';
        buf[(*len)++] = tok[k];
    }
    if (quote && *len + 1 < n) buf[(*len)++] = '\'';
    buf[*len < n ? *len : n - 1] = 0;
}

void vp_note_put_str(char *buf, size_t n, size_t *len, const char *name, const char *value)
{
    vp_note_put(buf, n, len, name);
    vp_note_put(buf, n, len, value);
}

void vp_note_put_opt(char *buf, size_t n, size_t *len, const char *name, const char *fmt, ...)
{
    char v[64];
    va_list ap;
    vp_note_put(buf, n, len, name);
    va_start(ap, fmt);
    vsnprintf(v, sizeof v, fmt, ap);
    va_end(ap);
    vp_note_put(buf, n, len, v);
}

void vp_note_put_num(char *buf, size_t n, size_t *len, const char *name, double x)
{
    char v[40];
    int p;
    for (p = 15; p <= 17; p++) {
        snprintf(v, sizeof v, "%.*g", p, x);
        if (strtod(v, NULL) == x) break;
    }
    vp_note_put(buf, n, len, name);
    vp_note_put(buf, n, len, v);
}

int vp_note_split(char *buf, char **tok, int cap)
{
    char *r = buf, *w = buf;
    int n = 0;
    while (*r) {
        int quoted = 0;
        while (*r == ' ') r++;
        if (!*r) break;
        if (n == cap) return -1;
        tok[n++] = w;
        while (*r && (quoted || *r != ' ')) {
            if (*r == '\'') { quoted = !quoted; r++; continue; }
            if (*r == '\\' && r[1]) r++;
            *w++ = *r++;
        }
        if (*r) r++;
        *w++ = 0;
    }
    return n;
}

int vp_path_cat(char *buf, size_t n, const char *prefix, const char *ext, char *err, size_t errlen)
{
    size_t lp = strlen(prefix), le = strlen(ext), i, start = 0;
    if (lp + le >= n) {
        snprintf(err, errlen, "the path %.48s...%s is too long: %lu bytes, at most %lu", prefix, ext,
                 (unsigned long)(lp + le), (unsigned long)n - 1);
        return VP_EINVAL;
    }
    memcpy(buf, prefix, lp);
    memcpy(buf + lp, ext, le + 1);
    for (i = 0; i <= lp + le; i++)
        if (buf[i] == '/' || buf[i] == 0) {
            if (i - start > VP_NAME_MAX) {
                snprintf(err, errlen, "the name %.32s... in the path %.48s... is too long: %lu bytes, at most %d",
                         buf + start, buf, (unsigned long)(i - start), VP_NAME_MAX);
                buf[0] = 0;
                return VP_EINVAL;
            }
            start = i + 1;
        }
    return VP_OK;
}

int vp_mkdirs_for(const char *path)
{
    char dir[VP_PATH_MAX];
    size_t i, n = strlen(path);
    if (n >= sizeof dir) { errno = ENAMETOOLONG; return -1; }
    memcpy(dir, path, n + 1);
    for (i = 1; i < n; i++)
        if (dir[i] == '/') {
            dir[i] = 0;
            if (mkdir(dir, 0777) != 0 && errno != EEXIST) return -1;
            dir[i] = '/';
        }
    return 0;
}
