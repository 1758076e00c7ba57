/* vp_render — a picture of a mesh without a GPU or a display: a software rasteriser (z-buffer,
 * flat shading) drawing several views side by side, written as PNG (libpng).
 *
 * The camera is the report viewer's: it looks at the centre of the mesh's bounding box from
 * (yaw, pitch) with z up, a 40 degree vertical field of view, at a distance of half the box
 * diagonal / sin(20 deg) x 1.05; pixel centres at +0.5. The views, tile by tile (left to
 * right, then down): VP_RENDER_VIEWS below. */
#ifndef VP_RENDER_H
#define VP_RENDER_H
#include <stddef.h>
#include "vp_meshio.h"

#define VP_RENDER_NVIEWS 4
/* (yaw, pitch) of each view in radians: the viewer's default, front (-y), side (+x), top */
#define VP_RENDER_VIEWS { { 0.6, 0.45 }, { -1.5707963267948966, 0.0 }, { 0.0, 0.0 }, { -1.5707963267948966, 1.5 } }
#define VP_RENDER_BG_R 238   /* the background, as in the report's viewer */
#define VP_RENDER_BG_G 241
#define VP_RENDER_BG_B 245

typedef struct vp_render_opts {
    int tile_w, tile_h;              /* pixels per view (0: 480 x 360) */
    int views;                       /* 1..VP_RENDER_NVIEWS (0: all), in a grid of 2 columns */
    const unsigned char *facet_rgb;  /* 3 bytes per facet (NULL: one colour for all) */
} vp_render_opts_t;

/* Draws m into rgb (w*h*3 bytes, w = tile_w * columns, h = tile_h * rows: vp_render_size). */
void vp_render_size(const vp_render_opts_t *o, int *w, int *h);
int  vp_render_rgb(const vp_mesh_t *m, const vp_render_opts_t *o, unsigned char *rgb);
/* Draws m and writes path as an 8-bit RGB PNG. VP_OK, VP_EINVAL (bad options), VP_ENOMEM,
 * VP_EIO (err says why), VP_ENODEV (built without libpng). o NULL: four views of 480 x 360. */
int  vp_render_png(const vp_mesh_t *m, const vp_render_opts_t *o, const char *path, char *err, size_t errlen);

#endif
