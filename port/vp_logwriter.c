/* vp_logwriter — see vp_logwriter.h. */
#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>
#include "vp_logwriter.h"
#include "vp_rtclock.h"

void vp_logwriter_config_default(vp_logwriter_config_t *c)
{
    memset(c, 0, sizeof *c);
    c->sync_records = 1;
}

int vp_logwriter_parse_sync(const char *s, vp_logwriter_config_t *c)
{
    uint32_t rec = 0, ms = 0;
    if (!strcmp(s, "record")) { c->sync_records = 1; c->sync_ms = 0; return 0; }
    if (!strcmp(s, "close")) { c->sync_records = 0; c->sync_ms = 0; return 0; }
    while (*s) {
        char *e;
        unsigned long v;
        if (*s < '0' || *s > '9') return -1;
        v = strtoul(s, &e, 10);
        if (v == 0 || v > 100000000ul) return -1;
        if (!strncmp(e, "ms", 2)) { ms = (uint32_t)v; e += 2; }
        else rec = (uint32_t)v;
        if (*e == ',') e++;
        else if (*e) return -1;
        s = e;
    }
    if (!rec && !ms) return -1;
    c->sync_records = rec;
    c->sync_ms = ms;
    return 0;
}

static void start(vp_logwriter_t *f, int fd, const vp_logwriter_config_t *cfg)
{
    memset(f, 0, sizeof *f);
    f->fd = fd;
    if (cfg) f->cfg = *cfg;
    else vp_logwriter_config_default(&f->cfg);
}

/* Writes all of p (as far as the simulated power cut allows). */
static int write_all(vp_logwriter_t *f, const unsigned char *p, size_t n)
{
    size_t allowed = n;
    int cut = 0;
    if (f->dead) return VP_EIO;
    if (f->cfg.die_after_bytes && f->bytes + n > f->cfg.die_after_bytes) {
        allowed = f->bytes < f->cfg.die_after_bytes ? (size_t)(f->cfg.die_after_bytes - f->bytes) : 0;
        cut = 1;
    }
    while (allowed > 0) {
        ssize_t w = write(f->fd, p, allowed);
        if (w <= 0) {
            if (w < 0 && errno == EINTR) continue;
            if (w == 0) errno = EIO; /* nothing written and no reason given: never retried forever */
            return VP_EIO;
        }
        p += w;
        allowed -= (size_t)w;
        f->bytes += (uint64_t)w;
    }
    if (cut) {
        f->dead = 1;
        errno = EIO;
        return VP_EIO;
    }
    return VP_OK;
}

int vp_logwriter_sync(vp_logwriter_t *f)
{
    if (f->fd < 0 || f->dead) return VP_EIO;
    if (fdatasync(f->fd) != 0) return VP_EIO;
    f->unsynced = 0;
    f->syncs++;
    return VP_OK;
}

/* The folder entry of a new file must reach the medium too. */
static void sync_dir_of(const char *path)
{
    char dir[4096];
    const char *slash = strrchr(path, '/');
    size_t n = slash ? (size_t)(slash - path) : 0;
    int fd;
    if (!slash) { dir[0] = '.'; n = 1; }
    else if (n == 0) { dir[0] = '/'; n = 1; }
    else if (n >= sizeof dir) return;
    else memcpy(dir, path, n);
    dir[n] = 0;
    fd = open(dir, O_RDONLY);
    if (fd < 0) return;
    (void)fsync(fd);
    close(fd);
}

/* Opens path to write and takes an exclusive lock on it for as long as it stays open, without
 * changing a byte: a log another process is writing is left alone (f->busy, VP_EIO). */
static int open_locked(vp_logwriter_t *f, const char *path, int create)
{
    int fd = open(path, O_WRONLY | (create ? O_CREAT : 0), 0666), e;
    if (fd < 0) return VP_EIO;
    while (flock(fd, LOCK_EX | LOCK_NB) != 0) {
        if (errno == EINTR) continue;
        e = errno;
        if (e == EWOULDBLOCK) f->busy = 1;
        close(fd);
        errno = e;
        return VP_EIO;
    }
    f->fd = fd;
    return VP_OK;
}

int vp_logwriter_create(vp_logwriter_t *f, const char *path, const vp_logfmt_header_t *h,
                      const vp_logwriter_config_t *cfg)
{
    unsigned char buf[VP_LOGFMT_MAX_HEADER];
    int n = vp_logfmt_header_encode(h, buf, sizeof buf), st;
    start(f, -1, cfg);
    if (n < 0) return n;
    if ((st = open_locked(f, path, 1)) != VP_OK) return st;
    if (ftruncate(f->fd, 0) != 0) return VP_EIO;   /* replaced only once it is ours */
    st = write_all(f, buf, (size_t)n);
    if (st == VP_OK && !f->dead) st = vp_logwriter_sync(f);
    if (st == VP_OK) sync_dir_of(path);
    return st;
}

int vp_logwriter_create_copy(vp_logwriter_t *f, const char *path, const void *data, uint64_t n,
                           uint32_t next_seq, const vp_logwriter_config_t *cfg)
{
    const unsigned char *p = data;
    uint64_t left = n;
    int st;
    start(f, -1, cfg);
    if ((st = open_locked(f, path, 1)) != VP_OK) return st;
    if (ftruncate(f->fd, 0) != 0) return VP_EIO;
    /* the copied records are not part of the simulated power cut's count: appends are */
    while (left > 0) {
        ssize_t w = write(f->fd, p, left > (1u << 30) ? (size_t)1 << 30 : (size_t)left);
        if (w <= 0) {
            if (w < 0 && errno == EINTR) continue;
            if (w == 0) errno = EIO;
            return VP_EIO;
        }
        p += w;
        left -= (uint64_t)w;
    }
    if (fdatasync(f->fd) != 0) return VP_EIO;
    sync_dir_of(path);
    f->bytes = n;
    f->seq = next_seq;
    return VP_OK;
}

int vp_logwriter_open_append(vp_logwriter_t *f, const char *path, uint64_t good_bytes,
                           uint32_t next_seq, const vp_logwriter_config_t *cfg)
{
    return vp_logwriter_open_append_read(f, path, good_bytes, next_seq, UINT64_MAX, cfg);
}

int vp_logwriter_open_append_read(vp_logwriter_t *f, const char *path, uint64_t good_bytes, uint32_t next_seq,
                                uint64_t read_size, const vp_logwriter_config_t *cfg)
{
    struct stat sb;
    int st;
    start(f, -1, cfg);
    if ((st = open_locked(f, path, 0)) != VP_OK) return st;
    if (read_size != UINT64_MAX && (fstat(f->fd, &sb) != 0 || (uint64_t)sb.st_size != read_size)) {
        /* another writer added to it after it was read (and before the lock was ours) */
        f->changed = 1;
        close(f->fd);
        f->fd = -1;
        return VP_EIO;
    }
    /* drop a torn or damaged tail: new records must follow the last valid one */
    if (ftruncate(f->fd, (off_t)good_bytes) != 0 || lseek(f->fd, (off_t)good_bytes, SEEK_SET) < 0 ||
        fdatasync(f->fd) != 0)
        return VP_EIO;
    f->bytes = good_bytes;
    f->seq = next_seq;
    return VP_OK;
}

int vp_logwriter_append(vp_logwriter_t *f, vp_logfmt_record_t *rec)
{
    unsigned char buf[VP_LOGFMT_MAX_RECORD];
    int n, st;
    if (f->fd < 0 || f->dead) return VP_EIO;
    rec->seq = f->seq;
    n = vp_logfmt_record_encode(rec, buf, sizeof buf);
    if (n < 0) return n;
    st = write_all(f, buf, (size_t)n);
    if (st != VP_OK) return st;
    f->seq++;
    f->records++;
    if (f->unsynced++ == 0 && f->cfg.sync_ms) f->first_unsynced = vp_rt_seconds();
    if ((f->cfg.sync_records && f->unsynced >= f->cfg.sync_records) ||
        (f->cfg.sync_ms && (vp_rt_seconds() - f->first_unsynced) * 1000.0 >= (double)f->cfg.sync_ms))
        return vp_logwriter_sync(f);
    return VP_OK;
}

int vp_logwriter_event(vp_logwriter_t *f, uint32_t event, int32_t code, const char *text)
{
    vp_logfmt_record_t rec;
    vp_logfmt_record_event(&rec, 0, event, code, text);
    return vp_logwriter_append(f, &rec);
}

int vp_logwriter_close(vp_logwriter_t *f)
{
    int st = VP_OK;
    if (f->fd < 0) return VP_OK;
    if (!f->dead && f->unsynced) st = vp_logwriter_sync(f);
    if (close(f->fd) != 0 && st == VP_OK) st = VP_EIO;
    f->fd = -1;
    return st;
}
