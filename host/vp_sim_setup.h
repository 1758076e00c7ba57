/* vp_sim_setup — a simulated scan from options to figures: the object (host-sim), the planner
 * configuration derived from it (Omega, interior points, start), the simulated device, the run,
 * the mesh files and the measurements. Shared by `sim`, `scan --dry-run` and the tests. */
#ifndef VP_SIM_SETUP_H
#define VP_SIM_SETUP_H
#include <stdio.h>
#include "vp_planner.h"
#include "vp_session.h"
#include "vp_simdev.h"
#include "vp_surface.h"
#include "vp_hausdorff.h"
#include "vp_motion.h"
#include "vp_meshcheck.h"

typedef struct vp_sim_options {
    const char *surface;
    double eps, eps_rel;
    const char *out;          /* PREFIX; NULL: do not write */
    double noise, dropout, clearance, max_range, min_range, min_angle;
    double min_feature, feature_margin; /* with a clearance: tubes inside Omega (0: never inside) */
    double size_rel, min_size;  /* the sizing field (0: off); its floor (0: eps / 10) */
    double max_distance;      /* the distance bound (0: off) */
    double accuracy, accuracy_rel; /* the Hausdorff target (absolute, or of the diagonal; 0: none):
                                      chooses eps, the sizing field and its floor */
    int confirm;              /* -1: default */
    size_t arena;
    int omega_ball;
    double omega_margin;      /* fraction of the bbox diagonal */
    unsigned flags;           /* VP_PLAN_* */
    int newest_first;         /* --newest-first: no VP_PLAN_SMALL_FIRST with a distance bound */
    unsigned long long seed;
    size_t hausdorff;
    int json, quiet;
    int ndark;                /* dark patches: the rangefinder sees no spot there (--dark) */
    double dark[VP_SIMDEV_MAX_DARK][4];
    int contact;              /* the head has a contact switch (--contact) */
    unsigned line_rays;       /* a line laser: more rays per probe (--line-laser N[,DEG]; 0: a dot) */
    double line_deg;          /* the fan's full angle, degrees */
    long proof_life;          /* --proof-life N: proofs older than N commands are proven again
                                 (-1: unset: with --motion from the speed bound, else never) */
    const char *motion;       /* a moving object (vp_motion.h spec); NULL: static */
    double speed, accel, probe_time; /* the device's clock: travel speed, acceleration, one probe's time */
} vp_sim_options_t;

typedef struct vp_sim {
    vp_surface_t *surf;
    vp_simdev_t *dev;
    vp_planner_t *pl;
    void *arena;
    vp_planner_config_t cfg;
    int components;
    double diag;
    vp_session_result_t run;
    vp_mesh_t mesh;
    vp_meshcheck_t check;
    int have_check;
    vp_hausdorff_t haus;
    int have_haus;
    double min_angle;
    const vp_session_hooks_t *hooks; /* passed to vp_session_run (the session log); may be NULL */
    double raw;                      /* the last probe's raw reading (NaN: no return) */
    double target;                   /* the accuracy target in object units (0: none) */
    int paused;                      /* stopped on purpose (resumable) */
    int written;                     /* vp_sim_finish wrote PREFIX.ply and PREFIX.off */
    int contact;                     /* the device has a contact switch */
    double line_half;                /* a line laser's half fan angle, rad */
    int touched;                     /* the last move stopped on contact ... */
    double touch_at;                 /* ... this far along it */
    vp_motion_t *motion;             /* the object's motion (NULL: static) */
    vp_hausdorff_t haus_end;         /* with a motion: the mesh against the object at the end time */
    int have_haus_end;
    vp_simdev_config_t dc;           /* the simulated device's settings (kept for a re-scan) */
    struct vp_sim_round *rounds;     /* --track: the first scan, then one per round */
    int nrounds;
    int rescan;                      /* a re-scan: the object was swapped after the replay */
    const char *rescan_spec;         /* ... for this one (the caller's string) */
    vp_planner_stats_t before;       /* the planner's counters when the re-scan began */
} vp_sim_t;

void vp_sim_options_default(vp_sim_options_t *o);
/* The clock's defaults: boards/sim.ini's x axis (speed, accel) and one probe = the board's
 * default settle (20 ms) + one 30 fps frame. */
#define VP_SIM_SPEED      300.0
#define VP_SIM_ACCEL      3000.0
#define VP_SIM_PROBE_TIME 0.053

/* What the planner supports (checked by vp_sim_open): eps at least VP_SIM_EPS_MIN_OMEGA of
 * Omega's diagonal and VP_SIM_EPS_MIN_COORD of its largest coordinate (double precision), noise
 * at most eps * VP_SIM_NOISE_MAX_REL, dropout at most VP_SIM_DROPOUT_MAX. */
#define VP_SIM_EPS_MIN_OMEGA 1e-9
#define VP_SIM_EPS_MIN_COORD 1e-12
#define VP_SIM_NOISE_MAX_REL (1.0 / 16.0)
#define VP_SIM_DROPOUT_MAX   0.5
/* An accuracy target H (the mesh within H of the object): the distance bound H / 3 and its
 * floor min(H / 4, eps) in the planner's configuration (measured: README, the accuracy table). */
void vp_accuracy_config(vp_planner_config_t *cfg, double target);
/* VP_OK, or VP_EINVAL with a message naming the option, its range and the smallest or largest
 * accepted value (diag: the object's bounding-box diagonal, for --eps-rel). */
int vp_sim_check_ranges(const vp_planner_config_t *cfg, double diag, const vp_sim_options_t *o, char *err,
                        size_t errlen);
/* PREFIX.ply and PREFIX.off fit a path (VP_EINVAL and a message when they do not). */
int vp_sim_check_out(const vp_sim_options_t *o, char *err, size_t errlen);

/* Opens the object, derives the planner configuration, creates device and planner (after
 * vp_sim_check_ranges). */
int vp_sim_open(vp_sim_t *s, const vp_sim_options_t *o, char *err, size_t errlen);
/* The scan (until DONE or an error); s->run gets the figures. */
int vp_sim_run(vp_sim_t *s, FILE *progress);
/* Builds the mesh, analyses it, measures Hausdorff and writes PREFIX.ply / PREFIX.off. */
int vp_sim_finish(vp_sim_t *s, const vp_sim_options_t *o, char *err, size_t errlen);
/* The exit status of the scan (vp_outcome.h): closed, error, stopped, not_closed, collision,
 * not_within_target, wrong_topology. */
int vp_sim_exit(const vp_sim_t *s);
/* 1 if a closed mesh (mc) has another genus (summed over its components) or number of
 * components than the object, where the object's is known (a mesh file that is no closed
 * oriented manifold has none): sim and a dry run say so (exit 7). */
int vp_topology_differs(const vp_meshcheck_t *mc, const vp_surface_t *surf);
/* The same for the scan's mesh against its object (a moving object: never). */
int vp_sim_wrong_topology(const vp_sim_t *s);
/* Human summary, and with o->json one JSON object as the last line. */
void vp_sim_report(const vp_sim_t *s, const vp_sim_options_t *o, FILE *f);
void vp_sim_close(vp_sim_t *s);

/* Tracking a moving object (--track N): after each round (the first scan, then re-scans from
 * where the device stands, vp_planner_rescan_here), what it took and what it left. */
typedef struct vp_sim_round {
    double t0, t1;                   /* the simulated clock at its start and end (s) */
    uint64_t probes, moves, kept, skipped, dropped, moved, unseen, normal, reproved, blocked;
    unsigned long collisions;        /* moves that touched the moving object in this round */
    int status, closed, genus, components;
    unsigned vertices;
    double hausdorff;                /* the mesh against the object at t1 (-1: not measured) */
    double min_spacing;              /* the closest two vertices of the mesh */
} vp_sim_round_t;
/* Runs rounds 1..n after the first scan (each: rescan_event(ctx, k), the re-scan, its figures in
 * s->rounds[k]; s->rounds[0] is the first scan); stops early when a round does not end DONE. */
int vp_sim_track(vp_sim_t *s, const vp_sim_options_t *o, int n, unsigned flags, int (*rescan_event)(void *ctx, int round),
                 void *ctx, FILE *progress);
/* A re-scan: the simulated object becomes `spec` (the device back at the start, its counters from
 * zero), after the session so far was replayed into s->pl with the old one. The planner's
 * configuration stays the logged one, so the new object must lie in its Omega (assumption A2;
 * with a body, the clearance inside it): VP_EINVAL (err) otherwise. */
int vp_sim_swap_surface(vp_sim_t *s, const char *spec, char *err, size_t errlen);

/* The planner configuration for an object: Omega = bbox grown by margin * diagonal (box or
 * ball), one interior point per component, start outside Omega. */
int vp_sim_config(const vp_surface_t *surf, double eps, int ball, double margin,
                  vp_planner_config_t *cfg, char *err, size_t errlen);

#endif
