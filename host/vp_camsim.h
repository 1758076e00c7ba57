/* vp_camsim — renders what the rangefinder camera sees: the laser spot on a simulated object
 * (vp_surface) or a flat target, through the board's pinhole camera, with optical blur, the
 * beam's footprint stretched on slanted surfaces, Lambertian fall-off with distance and angle,
 * ambient light (level, gradient, smooth texture), an optional ghost spot (a reflection),
 * Gaussian noise, 8-bit quantisation and saturation; and a real world's faults: laser speckle, the
 * head still ringing after a move, mains flicker of the ambient light, a moving glint, a dark
 * band on the object; a backdrop (the walls round the machine) where a beam that meets no
 * object ends. The spot is hidden when the surface faces
 * away from the camera or the object occludes it. Truth (distance, image point) comes out with
 * each frame, so the detection and triangulation code can be measured against it.
 * As a vp_cam backend ("camsim") it renders at the head pose a callback gives. */
#ifndef VP_CAMSIM_H
#define VP_CAMSIM_H
#include <stdint.h>
#include "vp_cam.h"
#include "vp_laser.h"
#include "vp_rng.h"
#include "vp_surface.h"

typedef struct vp_camsim_config {
    vp_camera_model_t cam;       /* in the tilt frame (vp_kin); cam.dist: the lens' distortion,
                                    applied by the renderer's own code to the true points */
    double laser_offset[3];      /* laser origin in the tilt frame */
    double laser_dir[3];         /* the beam's direction in the tilt frame (0, 0, 0: +x) */
    double blur_px;              /* optical blur sigma, px (0: 1.2) */
    double beam_radius;          /* 1-sigma beam footprint on a facing surface, mm (0: 0.25) */
    double spot_energy;          /* grey levels x px^2 of a facing spot 300 mm from the camera (0: 3000) */
    double ambient;              /* mean background, grey levels */
    double gradient;             /* background change across the frame (left to right, top to bottom) */
    double texture;              /* amplitude of a smooth background pattern */
    double noise;                /* per-pixel sigma, grey levels */
    double ghost;                /* > 0: a second spot of this relative energy (a reflection) */
    double ghost_offset[2];      /* its image offset, px */
    double lamp_peak;            /* > 0: a broad bright blob (a lamp, a glare) of this peak */
    double lamp_uv[2], lamp_sigma;   /* its centre and width, px */
    int hot_pixels;              /* this many isolated pixels stuck at 255 */
    double highlight_peak;       /* > 0: an ambient highlight (a glint, a lamp's reflection) lit with
                                    the laser off too, of this peak, near the laser line: */
    double highlight_sigma;      /* its width, px (0: 1.5) */
    double highlight_dist;       /* where the beam's image would be for a surface this far, mm */
    double highlight_off_px;     /* and this far across the line, px */
    double max_range;            /* beam range, mm (0: 5000) */
    /* faults of a real world (0: off); each drawn from the renderer's seed */
    double speckle;              /* laser speckle contrast on the spot (1: fully developed): the spot's
                                    pixels times |complex Gaussian field|^2, grains of 2.44 lambda N */
    double fnumber;              /* the lens aperture N (0: 8) */
    double pixel_um, laser_nm;   /* pixel pitch (0: 3 um), laser wavelength (0: 650 nm) */
    uint64_t speckle_seed;       /* the surface's roughness: grains drawn from it and the lit point */
    double vib_px;               /* head vibration after a move: amplitude in the image at the move's
                                    end, px; decays as exp(-t / vib_ms), rings at vib_hz */
    double vib_hz, vib_ms;       /* (0: 150 Hz, 0: 40 ms) */
    double vib_deg;              /* its direction in the image, degrees from +u */
    double exposure_ms;          /* the exposure the spot moves during (0: 1 ms) */
    double flicker;              /* mains flicker of the ambient light: depth 0..1 */
    double flicker_hz;           /* (0: 100 Hz, 50 Hz mains) */
    double glint_peak;           /* > 0: a glint lit by the ambient light (no laser), moving: */
    double glint_sigma;          /* its width, px (0: 3, a lamp's image, wider than the spot) */
    double glint_dist;           /* at the beam's image for a surface this far, mm, */
    double glint_off_px;         /* this far across the line, px, */
    double glint_move_px;        /* swinging across the line this far either way, px, */
    double glint_period_ms;      /* with this period (0: 500 ms) */
    double dark_albedo;          /* > 0: the object between z = dark_z[0] and dark_z[1] (world, mm: a
                                    dark band) reflects this fraction of the spot's light */
    double dark_z[2];
    /* the laser's kind: a dot (a beam) or a line (a fan of light in a plane) */
    int laser_kind;              /* VP_CAMSIM_DOT (0) or VP_CAMSIM_LINE */
    /* the line: a fan in the plane through laser_offset with normal line_normal (tilt frame;
     * 0, 0, 0: +z), centred on laser_dir brought into that plane, fan_half_angle either side.
     * Drawn as line_rays rays cast against the scene, each hit the camera sees a small spot
     * (blur, the sheet's thickness stretched on slanted surfaces, fall-off, dark band, speckle,
     * ghost: ghost_offset moves a second line). The head's vibration is not drawn for a line.
     * highlight_off_px / glint_off_px / glint_move_px: along the image direction in which the
     * line moves with distance (across the line). */
    double fan_half_angle;       /* rad (0: 30 degrees) */
    double line_normal[3];
    double line_energy;          /* grey levels x px^2 per radian of fan on a facing surface 300 mm
                                    from the camera (0: 60000) */
    double line_width;           /* 1-sigma thickness of the light sheet, mm (0: beam_radius) */
    int line_rays;               /* rays cast across the fan (0: 4096) */
} vp_camsim_config_t;

enum { VP_CAMSIM_DOT = 0, VP_CAMSIM_LINE = 1 };

typedef struct vp_camsim_scene {
    const vp_surface_t *surf;    /* the object, or NULL for the plane */
    double plane_n[3], plane_d;  /* flat target n.x = d (world) when surf is NULL */
    double mark_peak;            /* > 0: a bright dot printed on the flat target, lit with the laser
                                    off too, of this peak (grey levels above the background) */
    double mark[3];              /* its centre (world, on the plane) */
    double mark_sigma;           /* its 1-sigma radius, mm (0: 0.4) */
    int backdrop;                /* 1: matte walls round the machine (a box, world mm): a beam that
                                    meets no object ends on them, where the camera may see its spot */
    double backdrop_lo[3], backdrop_hi[3];
} vp_camsim_scene_t;

typedef struct vp_camsim_truth {
    int hit;                     /* the beam met the object within max_range */
    int visible;                 /* and the camera sees the spot (in frame, lit side, not hidden) */
    int backdrop;                /* the beam met no object but the backdrop: the spot is on a wall */
    double dist;                 /* along the beam from the laser origin, mm */
    double uv[2];                /* where the spot's centre projects */
    double point[3];             /* world hit point */
    double energy;               /* rendered spot energy */
    double sigma_px;             /* spot size: (det of its covariance)^(1/4), px */
    double peak;                 /* spot peak above the background before clipping */
    int laser;                   /* the laser was on during the exposure (the spot is drawn) */
    double albedo;               /* of the surface at the spot (1, or dark_albedo) */
    double speckle_gain;         /* the spot's energy after speckle / before (1 without speckle) */
    double vib_px;               /* vibration amplitude during the exposure, px */
    double ambient_gain;         /* flicker: ambient light of this frame / its mean */
    int64_t seq, t_ns;           /* the frame's sequence number and time stamp (backend only) */
} vp_camsim_truth_t;

/* The line laser's truth, from the renderer's own ray casting: per image column x, the true
 * points of the fan whose image (through the lens) lies exactly on column x and that the camera
 * sees (lit side, in front, in frame, not hidden). */
#define VP_CAMSIM_MAX_W 4096
typedef struct vp_camsim_line_truth {
    int width;
    int rays, rays_visible;      /* rays cast, and hits the camera sees */
    uint8_t count[VP_CAMSIM_MAX_W];          /* crossings of column x (0: none; 2 or more: folds) */
    double v[VP_CAMSIM_MAX_W];               /* the first crossing: its image row */
    double p[VP_CAMSIM_MAX_W][3];            /* its point, tilt frame */
    double dist[VP_CAMSIM_MAX_W];            /* from the laser origin, mm */
    double albedo[VP_CAMSIM_MAX_W];          /* of the surface there (1, or dark_albedo) */
} vp_camsim_line_truth_t;

/* Renders one frame into img (cam.width x cam.height, stride bytes per row) for the head pose
 * (tilt frame -> world: rot row-major, pos). VP_EINVAL for a bad configuration. */
int vp_camsim_render(const vp_camsim_config_t *c, const vp_camsim_scene_t *sc, const double rot[9],
                     const double pos[3], vp_rng_t *rng, uint8_t *img, int stride, vp_camsim_truth_t *truth);

/* The same with the laser on or off and the exposure's start time t_ns (the glint's swing, the
 * flicker): a laser-on / laser-off pair is two calls (what the ambient light lights appears in
 * both). line (may be NULL): with laser_kind VP_CAMSIM_LINE the line's truth per column (computed
 * with the laser off too). */
int vp_camsim_render_ex(const vp_camsim_config_t *c, const vp_camsim_scene_t *sc, const double rot[9], const double pos[3],
                        vp_rng_t *rng, uint8_t *img, int stride, int laser, int64_t t_ns, vp_camsim_truth_t *truth,
                        vp_camsim_line_truth_t *line);

/* The camera backend: pose(ctx, rot, pos) gives the head pose at capture time; clock(ctx) the
 * time stamp (NULL: 0). Frames come from one buffer: one frame out at a time. The backend's
 * close destroys the renderer. */
typedef struct vp_camsim vp_camsim_t;
int     vp_camsim_create(const vp_camsim_config_t *c, const vp_camsim_scene_t *sc, uint64_t seed,
                         void (*pose)(void *ctx, double rot[9], double pos[3]),
                         int64_t (*clock)(void *ctx), void *ctx, vp_camsim_t **out);
vp_cam_t vp_camsim_cam(vp_camsim_t *cs);
/* Streaming like a real camera (default: off, each capture renders at once with the laser as it
 * is now, sequence numbers 0, 1, 2, ... and the clock's time stamp). With period_ns > 0 the
 * camera exposes frame s from s * period_ns (its time stamp) and delivers it (1 + latency)
 * frames later; up to `queue` delivered frames wait to be taken, oldest first (older ones are
 * dropped), so a capture can return a frame exposed long before; mark() drains them. The spot is
 * drawn when the laser was on at the frame's exposure start (the state seen at the last
 * mark/capture at or before it, or vp_camsim_laser_switched: the dry run calls it on each laser
 * write). */
typedef struct vp_camsim_stream {
    int64_t period_ns;           /* 0: no stream (as above) */
    int latency;                 /* frames of pipeline delay after the frame's own */
    int queue;                   /* frames waiting at most (0: 4) */
    int (*laser)(void *ctx);     /* the laser line now (NULL: always on); ctx: create's */
    int (*wait_until)(void *ctx, int64_t t_ns);   /* the clock's wait (needed with period_ns) */
    int64_t back_at;             /* fault (>= 1): the back_at-th frame handed out (counting from 1) */
    int back_kind;               /* comes stamped older than the one before (1) or numbered so (2) */
    int every_frame;             /* hand over every frame, ignoring the caller's lowest sequence
                                    number (as V4L2 does: the caller drops them) */
} vp_camsim_stream_t;
int     vp_camsim_set_stream(vp_camsim_t *cs, const vp_camsim_stream_t *s);
/* The stream settings in use (tests change them between frames). */
vp_camsim_stream_t *vp_camsim_stream(vp_camsim_t *cs);
/* A step was just written (the dry run's GPIO calls it): the head's vibration starts from now. */
void    vp_camsim_moved(vp_camsim_t *cs);
/* The laser line was just written (the dry run's GPIO calls it): its state is noted now. */
void    vp_camsim_laser_switched(vp_camsim_t *cs);
/* Fault injection (tests): the at-th frame handed out from now on comes stamped (kind 1) or
 * numbered (kind 2) older than the one before it. */
int     vp_camsim_fault(vp_camsim_t *cs, int64_t at, int kind);
/* The renderer's configuration, to change between frames (tests). */
vp_camsim_config_t *vp_camsim_config(vp_camsim_t *cs);
/* Restarts the noise generator (e.g. per probe, so a resumed dry run sees the same frames). */
void    vp_camsim_seed(vp_camsim_t *cs, uint64_t seed);
/* Truth of the last frame captured, and of the one before it. */
const vp_camsim_truth_t *vp_camsim_last(const vp_camsim_t *cs);
const vp_camsim_truth_t *vp_camsim_prev(const vp_camsim_t *cs);
/* Truth of the frame numbered seq among the last 32 handed out (NULL: not among them). */
const vp_camsim_truth_t *vp_camsim_truth_of(const vp_camsim_t *cs, int64_t seq);
void    vp_camsim_destroy(vp_camsim_t *cs);

#endif
