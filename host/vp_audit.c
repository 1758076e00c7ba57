/* vp_audit — see vp_audit.h. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "vp_audit.h"
#include "vp_note.h"

int vp_audit_keep(const char *path)
{
    static unsigned n;
    const char *dir = getenv("VP_AUDIT_DIR"), *base;
    char *to;
    FILE *in, *out;
    char buf[65536];
    size_t k, len;
    int rc = 0;
    if (!dir || !*dir || !path || !*path) return 0;
    base = strrchr(path, '/');
    base = base ? base + 1 : path;
    len = strlen(dir) + strlen(base) + 48;
    if (!(to = malloc(len))) return -1;
    snprintf(to, len, "%s/%ld-%u-%s", dir, (long)getpid(), n++, base);
    if (vp_mkdirs_for(to) != 0 || !(in = fopen(path, "rb"))) {
        fprintf(stderr, "audit: cannot keep %s in %s: %s\n", path, dir, strerror(errno));
        free(to);
        return -1;
    }
    if (!(out = fopen(to, "wb"))) {
        fprintf(stderr, "audit: cannot write %s: %s\n", to, strerror(errno));
        fclose(in);
        free(to);
        return -1;
    }
    while ((k = fread(buf, 1, sizeof buf, in)) > 0)
        if (fwrite(buf, 1, k, out) != k) { rc = -1; break; }
    if (ferror(in)) rc = -1;
    fclose(in);
    if (fclose(out) != 0) rc = -1;
    if (rc) fprintf(stderr, "audit: copying %s to %s failed\n", path, to);
    free(to);
    return rc;
}
