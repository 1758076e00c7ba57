/* vp_render — software rasteriser (z-buffer, flat shading) and PNG output. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "vp_note.h"
#include "vp_render.h"
#include "vp_status.h"
#ifdef VP_HAVE_PNG
#include <png.h>
#endif

static const double views[VP_RENDER_NVIEWS][2] = VP_RENDER_VIEWS;

typedef struct cam {
    double eye[3], f[3], r[3], u[3], light[3];
    double t, a;   /* 1 / tan(fov/2), aspect */
} cam_t;

static void unit(double *v)
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 0) { v[0] /= l; v[1] /= l; v[2] /= l; }
}

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void cross3(const double *a, const double *b, double *c)
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

static void camera(cam_t *c, const double *centre, double radius, double yaw, double pitch, int w, int h)
{
    const double fov = 40.0 * 3.14159265358979323846 / 180.0, up[3] = { 0, 0, 1 };
    double d = radius / sin(fov / 2) * 1.05;
    int k;
    c->eye[0] = centre[0] + d * cos(pitch) * cos(yaw);
    c->eye[1] = centre[1] + d * cos(pitch) * sin(yaw);
    c->eye[2] = centre[2] + d * sin(pitch);
    for (k = 0; k < 3; k++) c->f[k] = centre[k] - c->eye[k];
    unit(c->f);
    cross3(c->f, up, c->r);
    unit(c->r);
    cross3(c->r, c->f, c->u);
    for (k = 0; k < 3; k++) c->light[k] = -c->f[k] + 0.3 * c->r[k] + 0.5 * c->u[k];
    unit(c->light);
    c->t = 1.0 / tan(fov / 2);
    c->a = (double)w / h;
}

/* screen x, y and view depth z (> 0 in front) */
static void project(const cam_t *c, const double *p, int w, int h, double *s)
{
    double d[3];
    d[0] = p[0] - c->eye[0]; d[1] = p[1] - c->eye[1]; d[2] = p[2] - c->eye[2];
    s[2] = dot3(d, c->f);
    s[0] = w / 2.0 + dot3(d, c->r) / s[2] * c->t / c->a * w / 2.0;
    s[1] = h / 2.0 - dot3(d, c->u) / s[2] * c->t * h / 2.0;
}

void vp_render_size(const vp_render_opts_t *o, int *w, int *h)
{
    int tw = o->tile_w > 0 ? o->tile_w : 480, th = o->tile_h > 0 ? o->tile_h : 360;
    int nv = o->views > 0 && o->views <= VP_RENDER_NVIEWS ? o->views : VP_RENDER_NVIEWS;
    int cols = nv > 1 ? 2 : 1, rows = (nv + cols - 1) / cols;
    *w = tw * cols;
    *h = th * rows;
}

/* One view into the tile at (ox, oy) of an image w_img wide. */
static void draw_view(const vp_mesh_t *m, const vp_render_opts_t *o, const cam_t *c, int tw, int th,
                      unsigned char *rgb, int w_img, int ox, int oy, float *zbuf, double *scr)
{
    size_t i, f;
    int x, y;
    for (i = 0; i < (size_t)tw * th; i++) zbuf[i] = HUGE_VALF;
    for (i = 0; i < m->nv; i++) project(c, m->xyz + 3 * i, tw, th, scr + 3 * i);
    for (f = 0; f < m->nt; f++) {
        const uint32_t *t = m->tri + 3 * f;
        const double *A = scr + 3 * (size_t)t[0], *B = scr + 3 * (size_t)t[1], *C = scr + 3 * (size_t)t[2];
        const double *pa = m->xyz + 3 * (size_t)t[0], *pb = m->xyz + 3 * (size_t)t[1], *pc = m->xyz + 3 * (size_t)t[2];
        double e1[3], e2[3], n[3], shade, area, col[3];
        int x0, x1, y0, y1, k;
        if (A[2] <= 0 || B[2] <= 0 || C[2] <= 0) continue;
        area = (B[0] - A[0]) * (C[1] - A[1]) - (B[1] - A[1]) * (C[0] - A[0]);
        if (area == 0 || !isfinite(area)) continue;
        for (k = 0; k < 3; k++) { e1[k] = pb[k] - pa[k]; e2[k] = pc[k] - pa[k]; }
        cross3(e1, e2, n);
        unit(n);
        shade = 0.3 + 0.7 * fabs(dot3(n, c->light));
        if (o->facet_rgb) for (k = 0; k < 3; k++) col[k] = o->facet_rgb[3 * f + (size_t)k];
        else { col[0] = 168; col[1] = 189; col[2] = 214; }
        x0 = (int)floor(fmin(A[0], fmin(B[0], C[0])));
        x1 = (int)ceil(fmax(A[0], fmax(B[0], C[0])));
        y0 = (int)floor(fmin(A[1], fmin(B[1], C[1])));
        y1 = (int)ceil(fmax(A[1], fmax(B[1], C[1])));
        if (x0 < 0) x0 = 0;
        if (y0 < 0) y0 = 0;
        if (x1 > tw - 1) x1 = tw - 1;
        if (y1 > th - 1) y1 = th - 1;
        for (y = y0; y <= y1; y++) {
            double py = y + 0.5;
            for (x = x0; x <= x1; x++) {
                double px = x + 0.5, w0, w1, w2, z;
                float *zp;
                w0 = ((C[0] - B[0]) * (py - B[1]) - (C[1] - B[1]) * (px - B[0])) / area;
                w1 = ((A[0] - C[0]) * (py - C[1]) - (A[1] - C[1]) * (px - C[0])) / area;
                w2 = 1.0 - w0 - w1;
                if (w0 < 0 || w1 < 0 || w2 < 0) continue;
                /* perspective-correct depth: 1/z is linear on the screen */
                z = 1.0 / (w0 / A[2] + w1 / B[2] + w2 / C[2]);
                zp = &zbuf[(size_t)y * tw + x];
                if (z >= *zp) continue;
                *zp = (float)z;
                for (k = 0; k < 3; k++)
                    rgb[3 * ((size_t)(oy + y) * w_img + ox + x) + (size_t)k] = (unsigned char)(col[k] * shade + 0.5);
            }
        }
    }
}

int vp_render_rgb(const vp_mesh_t *m, const vp_render_opts_t *o, unsigned char *rgb)
{
    int tw = o->tile_w > 0 ? o->tile_w : 480, th = o->tile_h > 0 ? o->tile_h : 360;
    int nv = o->views > 0 && o->views <= VP_RENDER_NVIEWS ? o->views : VP_RENDER_NVIEWS;
    int w, h, v, k;
    double lo[3] = { HUGE_VAL, HUGE_VAL, HUGE_VAL }, hi[3] = { -HUGE_VAL, -HUGE_VAL, -HUGE_VAL }, centre[3], radius;
    float *zbuf;
    double *scr;
    size_t i;
    if (o->views < 0 || o->views > VP_RENDER_NVIEWS || tw > 8192 || th > 8192) return VP_EINVAL;
    vp_render_size(o, &w, &h);
    for (i = 0; i < (size_t)w * h; i++) {
        rgb[3 * i] = VP_RENDER_BG_R;
        rgb[3 * i + 1] = VP_RENDER_BG_G;
        rgb[3 * i + 2] = VP_RENDER_BG_B;
    }
    if (m->nv == 0) return VP_OK;
    for (i = 0; i < m->nv; i++)
        for (k = 0; k < 3; k++) {
            double x = m->xyz[3 * i + (size_t)k];
            if (x < lo[k]) lo[k] = x;
            if (x > hi[k]) hi[k] = x;
        }
    for (k = 0; k < 3; k++) centre[k] = 0.5 * (lo[k] + hi[k]);
    radius = 0.5 * sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
    if (!(radius > 0)) radius = 1e-9;
    zbuf = malloc((size_t)tw * th * sizeof *zbuf);
    scr = malloc((m->nv + 1) * 3 * sizeof *scr);
    if (!zbuf || !scr) { free(zbuf); free(scr); return VP_ENOMEM; }
    for (v = 0; v < nv; v++) {
        cam_t c;
        camera(&c, centre, radius, views[v][0], views[v][1], tw, th);
        draw_view(m, o, &c, tw, th, rgb, w, (v % 2) * tw, (v / 2) * th, zbuf, scr);
    }
    free(zbuf);
    free(scr);
    return VP_OK;
}

#ifdef VP_HAVE_PNG
static int write_png(const char *path, const unsigned char *rgb, int w, int h, char *err, size_t errlen)
{
    FILE *f = vp_mkdirs_for(path) == 0 ? fopen(path, "wb") : NULL; /* its folder made, as --out's */
    png_structp png;
    png_infop info;
    int y;
    if (!f) { snprintf(err, errlen, "cannot write %s: %s", path, strerror(errno)); return VP_EIO; }
    png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    info = png ? png_create_info_struct(png) : NULL;
    if (!png || !info) {
        png_destroy_write_struct(&png, NULL);
        fclose(f);
        snprintf(err, errlen, "out of memory");
        return VP_ENOMEM;
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        fclose(f);
        snprintf(err, errlen, "cannot write %s (libpng)", path);
        return VP_EIO;
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (y = 0; y < h; y++) png_write_row(png, rgb + (size_t)y * w * 3);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    if (fclose(f) != 0) { snprintf(err, errlen, "cannot write %s: %s", path, strerror(errno)); return VP_EIO; }
    return VP_OK;
}
#endif

int vp_render_png(const vp_mesh_t *m, const vp_render_opts_t *o, const char *path, char *err, size_t errlen)
{
#ifdef VP_HAVE_PNG
    int w, h, st;
    unsigned char *rgb;
    vp_render_opts_t defaults;
    if (!o) {
        memset(&defaults, 0, sizeof defaults);
        o = &defaults;
    }
    vp_render_size(o, &w, &h);
    rgb = malloc((size_t)w * h * 3);
    if (!rgb) { snprintf(err, errlen, "out of memory"); return VP_ENOMEM; }
    st = vp_render_rgb(m, o, rgb);
    if (st == VP_OK) st = write_png(path, rgb, w, h, err, errlen);
    else snprintf(err, errlen, "cannot draw the mesh: %s", vp_strerror(st));
    free(rgb);
    return st;
#else
    (void)m; (void)o; (void)path;
    snprintf(err, errlen, "this voroprobe was built without libpng (libpng-dev): no PNG output");
    return VP_ENODEV;
#endif
}
