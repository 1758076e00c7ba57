/* vp_ini — see vp_ini.h. */
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include "vp_file.h"
#include "vp_ini.h"
#include "vp_status.h"

static char *vp_trim(char *s)
{
    char *e;
    while (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\n') s++;
    e = s + strlen(s);
    while (e > s && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\r' || e[-1] == '\n')) *--e = 0;
    return s;
}

typedef struct vp_ini_state {
    const char *name;
    vp_ini_fn fn;
    void *user;
    char section[96];
    int line;
} vp_ini_state_t;

static int vp_ini_line(vp_ini_state_t *st, char *buf, char *err, size_t errlen)
{
    char *s = vp_trim(buf), *eq, *key, *val, *c, msg[300];
    if (!*s || *s == '#' || *s == ';') return VP_OK;
    if (*s == '[') {
        char *e = strchr(s, ']');
        if (!e) { snprintf(err, errlen, "%s:%d: section header without ']'", st->name, st->line); return VP_EINVAL; }
        *e = 0;
        if (*vp_trim(e + 1) && *vp_trim(e + 1) != '#' && *vp_trim(e + 1) != ';') {
            snprintf(err, errlen, "%s:%d: text after the section header", st->name, st->line);
            return VP_EINVAL;
        }
        s = vp_trim(s + 1);
        if (!*s || strlen(s) >= sizeof st->section) { snprintf(err, errlen, "%s:%d: bad section name", st->name, st->line); return VP_EINVAL; }
        strcpy(st->section, s);
        msg[0] = 0;
        /* sections are announced with an empty key */
        if (st->fn(st->user, st->section, "", "", st->line, msg, sizeof msg) < 0) {
            snprintf(err, errlen, "%s:%d: [%s]: %s", st->name, st->line, st->section, msg);
            return VP_EINVAL;
        }
        return VP_OK;
    }
    eq = strchr(s, '=');
    if (!eq) { snprintf(err, errlen, "%s:%d: expected 'key = value' or '[section]', got '%.60s'", st->name, st->line, s); return VP_EINVAL; }
    *eq = 0;
    key = vp_trim(s);
    val = eq + 1;
    /* an inline comment starts with a blank then '#' or ';' */
    for (c = val; *c; c++)
        if ((*c == '#' || *c == ';') && (c == val || c[-1] == ' ' || c[-1] == '\t')) { *c = 0; break; }
    val = vp_trim(val);
    if (!*key) { snprintf(err, errlen, "%s:%d: empty key", st->name, st->line); return VP_EINVAL; }
    msg[0] = 0;
    if (st->fn(st->user, st->section, key, val, st->line, msg, sizeof msg) < 0) {
        if (st->section[0]) snprintf(err, errlen, "%s:%d: [%s] %s: %s", st->name, st->line, st->section, key, msg);
        else snprintf(err, errlen, "%s:%d: %s: %s", st->name, st->line, key, msg);
        return VP_EINVAL;
    }
    return VP_OK;
}

int vp_ini_parse_file(const char *path, vp_ini_fn fn, void *user, char *err, size_t errlen)
{
    vp_ini_state_t st;
    char buf[VP_INI_LINE + 2];
    FILE *f;
    int rc = VP_OK;
    if (!path || !fn) return VP_EINVAL;
    /* a regular file of bounded size: /dev/zero or a pipe would be read for ever */
    f = vp_file_open_read(path, VP_INI_MAX_FILE, "board or calibration file", NULL, err, errlen);
    if (!f) return VP_EIO;
    memset(&st, 0, sizeof st);
    st.name = path;
    st.fn = fn;
    st.user = user;
    while (rc == VP_OK) {
        size_t n = 0;
        int c = EOF, nul = 0, any = 0;
        while ((c = getc(f)) != EOF && c != '\n') {
            any = 1;
            if (c == 0) nul = 1;
            if (n <= VP_INI_LINE) buf[n++] = (char)c;
        }
        if (!any && c == EOF) break;
        st.line++;
        if (nul) {
            /* the value would end at the NUL: "steps_per_unit = 8<NUL>0" read as 8 */
            snprintf(err, errlen, "%s:%d: a NUL byte inside the line (a damaged or binary file)", path, st.line);
            rc = VP_EINVAL;
            break;
        }
        if (n > VP_INI_LINE) {
            snprintf(err, errlen, "%s:%d: line longer than %d bytes", path, st.line, VP_INI_LINE);
            rc = VP_EINVAL;
            break;
        }
        buf[n] = 0;
        rc = vp_ini_line(&st, buf, err, errlen);
        if (c == EOF) break;
    }
    if (rc == VP_OK && ferror(f)) { snprintf(err, errlen, "%s: read error", path); rc = VP_EIO; }
    fclose(f);
    return rc;
}

int vp_ini_parse_text(const char *text, const char *name, vp_ini_fn fn, void *user, char *err, size_t errlen)
{
    vp_ini_state_t st;
    char buf[VP_INI_LINE + 2];
    const char *p = text;
    int rc = VP_OK;
    if (!text || !fn) return VP_EINVAL;
    memset(&st, 0, sizeof st);
    st.name = name ? name : "(text)";
    st.fn = fn;
    st.user = user;
    while (rc == VP_OK && *p) {
        const char *e = strchr(p, '\n');
        size_t n = e ? (size_t)(e - p) : strlen(p);
        st.line++;
        if (n > VP_INI_LINE) { snprintf(err, errlen, "%s:%d: line longer than %d bytes", st.name, st.line, VP_INI_LINE); return VP_EINVAL; }
        memcpy(buf, p, n);
        buf[n] = 0;
        rc = vp_ini_line(&st, buf, err, errlen);
        p = e ? e + 1 : p + n;
    }
    return rc;
}
