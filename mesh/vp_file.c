/* vp_file — see vp_file.h. */
#include <stdarg.h>
#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "vp_file.h"
#include "vp_status.h"

static const char *kind_of(mode_t m)
{
    if (S_ISDIR(m)) return "a folder";
    if (S_ISCHR(m)) return "a character device";
    if (S_ISBLK(m)) return "a block device";
    if (S_ISFIFO(m)) return "a pipe";
    if (S_ISSOCK(m)) return "a socket";
    return "not a plain file";
}

FILE *vp_file_open_read(const char *path, unsigned long long max, const char *what, unsigned long long *size,
                        char *err, size_t errlen)
{
    struct stat sb;
    FILE *f;
    int fd, fl;
    /* O_NONBLOCK: opening a pipe with no writer must not wait; cleared below */
    fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY);
    if (fd < 0) { snprintf(err, errlen, "%s: %s", path, strerror(errno)); return NULL; }
    if (fstat(fd, &sb) != 0) {
        snprintf(err, errlen, "%s: %s", path, strerror(errno));
        close(fd);
        return NULL;
    }
    if (!S_ISREG(sb.st_mode)) {
        snprintf(err, errlen, "%s is not a regular file (%s): give a %s", path, kind_of(sb.st_mode), what);
        close(fd);
        return NULL;
    }
    if ((unsigned long long)sb.st_size > max) {
        snprintf(err, errlen, "%s: %llu bytes, more than the %llu a %s may have", path,
                 (unsigned long long)sb.st_size, max, what);
        close(fd);
        return NULL;
    }
    fl = fcntl(fd, F_GETFL);
    if (fl < 0 || fcntl(fd, F_SETFL, fl & ~O_NONBLOCK) != 0 || !(f = fdopen(fd, "rb"))) {
        snprintf(err, errlen, "%s: %s", path, strerror(errno));
        close(fd);
        return NULL;
    }
    if (size) *size = (unsigned long long)sb.st_size;
    return f;
}

int vp_file_read(const char *path, unsigned long long max, const char *what, vp_file_head_fn head,
                 unsigned char **data, size_t *len, char *err, size_t errlen)
{
    unsigned long long size;
    unsigned char *p;
    size_t cap, n = 0;
    FILE *f;
    if (max >= (unsigned long long)((size_t)-1) - 1) max = (unsigned long long)((size_t)-1) - 2;
    f = vp_file_open_read(path, max, what, &size, err, errlen);
    if (!f) return VP_EIO;
    /* the file may grow while it is read: never more than max (+1 byte to notice) */
    cap = (size_t)(size < VP_FILE_HEAD ? VP_FILE_HEAD : size) + 1;
    if (!(p = malloc(cap + 1))) {
        fclose(f);
        snprintf(err, errlen, "%s: out of memory (%llu bytes)", path, size);
        return VP_ENOMEM;
    }
    for (;;) {
        size_t want = cap - n, got;
        if (n == 0 && want > VP_FILE_HEAD) want = VP_FILE_HEAD;
        got = fread(p + n, 1, want, f);
        if (n == 0 && head) {
            const char *why;
            if ((why = head(p, got)) != NULL) {
                fclose(f);
                free(p);
                snprintf(err, errlen, "%s is not a %s: %s", path, what, why);
                return VP_ECORRUPT;
            }
        }
        n += got;
        if (got < want) break;
        if (n == cap) {
            unsigned char *q;
            if ((unsigned long long)n > max) break;
            if (cap > ((size_t)-1) / 2 - 1) break;
            q = realloc(p, 2 * cap + 1);
            if (!q) {
                fclose(f);
                free(p);
                snprintf(err, errlen, "%s: out of memory", path);
                return VP_ENOMEM;
            }
            p = q;
            cap *= 2;
        }
    }
    if (ferror(f)) {
        fclose(f);
        free(p);
        snprintf(err, errlen, "%s: read error", path);
        return VP_EIO;
    }
    fclose(f);
    if ((unsigned long long)n > max) {
        free(p);
        snprintf(err, errlen, "%s: more than the %llu bytes a %s may have (it grew while read)", path, max, what);
        return VP_EIO;
    }
    p[n] = 0;
    *data = p;
    *len = n;
    return VP_OK;
}

int vp_file_find_nul(const unsigned char *p, size_t n, unsigned long *line)
{
    const unsigned char *z = memchr(p, 0, n), *q;
    unsigned long l = 1;
    if (!z) return 0;
    for (q = p; q < z; q++) l += *q == '\n';
    *line = l;
    return 1;
}

void vp_seterr(char *err, size_t errlen, const char *fmt, ...)
{
    va_list ap;
    if (!err || !errlen) return;
    va_start(ap, fmt);
    vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
}
