/* voroprobe report: one self-contained HTML page of a session log (a 3D viewer, the summary,
 * the certificate's verdicts and plots). */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_cli.h"
#include "vp_note.h"
#include "vp_outcome.h"
#include "vp_render.h"
#include "vp_report.h"
#include "vp_sim_opts.h"

/* the page (host/report/viewer.html), turned into an array by the Makefile */
extern const unsigned char vp_viewer_page[];
extern const size_t vp_viewer_page_len;

static void report_usage(FILE *f)
{
    fprintf(f,
        "usage: voroprobe report LOG [--out FILE.html] [--png FILE.png] [--mesh MESH.ply] [--max-rays N] [--json]\n"
        "Writes one self-contained HTML file (no network: its script and style are inside) that\n"
        "shows the session: an interactive 3D view of the mesh (drag to orbit, wheel to zoom,\n"
        "click a facet for its ball and verdict; a 2D canvas where WebGL is missing), toggles for\n"
        "the probe hits, misses, rays and the travel path (animated in order), facets coloured by\n"
        "ball radius or by the certificate (facets breaking H1 or H3 in red), holes and\n"
        "non-manifold edges marked, the summary sim and scan print, and plots (probes and\n"
        "vertices over the session, hit ratio, ball-radius histogram, travel per tenth).\n"
        "  --out FILE       the HTML file to write (LOG and at least one of --out, --png, --json)\n"
        "  --png FILE       also (or only) a picture of the mesh: four views (the viewer's, front,\n"
        "                   side, top), facets breaking H1 or H3 in red; drawn in software\n"
        "  --mesh MESH      show this mesh (PLY or OFF) instead of the session's; the summary\n"
        "                   stays the session's\n"
        "  --max-rays N     draw at most about N hits and N misses (every k-th; default 200000)\n"
        "  --json           print the summary as one JSON object\n"
        "  --quiet          no summary line\n"
        "Exit status: 0 written, 1 failure (the log cannot be read or replayed, I/O), 2 usage.\n");
}

/* The picture: facets that break H1 or H3 in red. 0 written, 1 failure (said). */
static int report_png(const vp_report_t *r, const char *path)
{
    vp_render_opts_t o;
    unsigned char *rgb = malloc(3 * (r->shown->nt + 1));
    char err[600];
    size_t i;
    int st;
    if (!rgb) { fprintf(stderr, "report: out of memory\n"); return 1; }
    for (i = 0; i < r->shown->nt; i++) {
        int bad = r->verdict[i] != 0;
        rgb[3 * i] = bad ? 220 : 168;
        rgb[3 * i + 1] = bad ? 40 : 189;
        rgb[3 * i + 2] = bad ? 40 : 214;
    }
    memset(&o, 0, sizeof o);
    o.facet_rgb = rgb;
    st = vp_render_png(r->shown, &o, path, err, sizeof err);
    free(rgb);
    if (st != VP_OK) { fprintf(stderr, "report: %s\n", err); return 1; }
    return 0;
}

int vp_cli_report(int argc, char **argv)
{
    const char *log = NULL, *out = NULL, *mesh = NULL, *png = NULL;
    size_t max_rays = 0;
    int i, json = 0, quiet = 0, st;
    vp_report_t r;
    char err[1400];
    FILE *f;
    for (i = 1; i < argc; i++) {
        const char *a = argv[i], *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) { report_usage(stdout); return 0; }
        if (!strcmp(a, "--json")) { json = 1; continue; }
        if (!strcmp(a, "--quiet")) { quiet = 1; continue; }
        if (!strcmp(a, "--out") || !strcmp(a, "--mesh") || !strcmp(a, "--max-rays") || !strcmp(a, "--png")) {
            if (!val) { fprintf(stderr, "report: %s needs a value\n", a); return 2; }
            i++;
            if (!strcmp(a, "--out")) out = val;
            else if (!strcmp(a, "--png")) png = val;
            else if (!strcmp(a, "--mesh")) mesh = val;
            else {
                unsigned long long n;
                if (vp_parse_count(val, 1000000000ull, &n) || n == 0) { fprintf(stderr, "report: --max-rays takes a positive count, not '%s'\n", val); return 2; }
                max_rays = (unsigned long)n;
            }
            continue;
        }
        if (a[0] == '-' && a[1]) { fprintf(stderr, "report: unknown option %s (see --help)\n", a); return 2; }
        if (log) { fprintf(stderr, "report: one log at a time ('%s' and '%s')\n", log, a); return 2; }
        log = a;
    }
    if (!log || (!out && !png && !json)) {
        fprintf(stderr, "report: give LOG and --out FILE.html, --png FILE.png or --json (see --help)\n");
        return 2;
    }
    st = vp_report_build(&r, log, mesh, err, sizeof err);
    if (st != VP_OK) {
        fprintf(stderr, "report: %s\n", err);
        vp_report_free(&r);
        return 1;
    }
    if (r.L.status != VP_OK) fprintf(stderr, "report: %s: %s\n", log, r.stop_text);
    if (png && report_png(&r, png)) { vp_report_free(&r); return 1; }
    if (!out) {
        if (png && !quiet && !json)
            printf("report: %s: %zu vertices, %zu facets, %llu probes (%llu hits), status %s; wrote %s\n", log,
                   r.mesh.nv, r.mesh.nt, (unsigned long long)r.st.probes, (unsigned long long)r.st.hits,
                   vp_outcome_name(r.exit_status), png);
        if (json) { vp_report_summary_json(&r, stdout); printf("\n"); }
        vp_report_free(&r);
        return 0;
    }
    f = vp_mkdirs_for(out) == 0 ? fopen(out, "wb") : NULL; /* its folder made, as sim's --out */
    if (!f) {
        fprintf(stderr, "report: cannot write %s: %s\n", out, strerror(errno));
        vp_report_free(&r);
        return 1;
    }
    st = vp_report_write_html(&r, f, (const char *)vp_viewer_page, vp_viewer_page_len, max_rays);
    if (fclose(f) != 0 && st == VP_OK) st = VP_EIO;
    if (st != VP_OK) {
        fprintf(stderr, "report: cannot write %s: %s\n", out, st == VP_EIO ? strerror(errno) : vp_strerror(st));
        vp_report_free(&r);
        return 1;
    }
    if (!quiet)
        printf("report: %s: %zu vertices, %zu facets, %llu probes (%llu hits), status %s; wrote %s\n", log,
               r.mesh.nv, r.mesh.nt, (unsigned long long)r.st.probes, (unsigned long long)r.st.hits,
               vp_outcome_name(r.exit_status), out);
    if (json) { vp_report_summary_json(&r, stdout); printf("\n"); }
    vp_report_free(&r);
    return 0;
}
