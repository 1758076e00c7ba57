/* vp_report — a session log seen whole: the mesh with every facet's surface Delaunay ball and
 * its certificate verdict, the probes (hits, misses, rays), the travel path, the counts that
 * sim and scan print, and the session over time; written as one self-contained HTML page
 * (the page's script and style come from the caller, the data goes in as JSON with the large
 * arrays quantised and base64-encoded). */
#ifndef VP_REPORT_H
#define VP_REPORT_H
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include "vp_certify.h"
#include "vp_meshcheck.h"
#include "vp_meshio.h"
#include "vp_sessionlog.h"

/* facet verdict bits (vp_report_t.verdict) */
#define VP_REPORT_H1 1u   /* the facet breaks H1: degenerate, or on an edge not in exactly 2 facets */
#define VP_REPORT_H3 2u   /* its ball is larger than eps or not empty of samples */

/* The session at one record. */
typedef struct vp_report_point {
    uint32_t record;
    uint64_t probes, hits, moves;
    uint32_t vertices, facets;
    double travel;
} vp_report_point_t;

#define VP_REPORT_TENTHS 10

typedef struct vp_report {
    const char *log_path, *mesh_path;
    vp_sessionlog_t L;
    vp_replay_t R;
    int replay_status;            /* VP_OK, or where the replay stopped (err of vp_report_build) */
    char stop_text[600];          /* vp_sessionlog_stop_text */
    /* the session's mesh, checked and certified */
    vp_mesh_t mesh;
    vp_meshcheck_t check;
    int have_check;
    vp_cert_t cert;
    int have_cert;
    vp_planner_stats_t st;
    int exit_status;              /* vp_outcome: what sim/scan would have said (no collision known) */
    uint64_t probes, hits, misses, too_close, moves;
    double travel;                /* sum of the logged MOVE lengths */
    /* the mesh shown: the session's, or --mesh (then radius is NaN) */
    const vp_mesh_t *shown;
    vp_mesh_t other;
    double *radius;               /* per shown facet: its ball radius */
    unsigned char *verdict;       /* per shown facet: VP_REPORT_H* bits */
    uint32_t *hole_edges, *nm_edges;   /* vertex index pairs of the shown mesh */
    size_t nhole_edges, nnm_edges;
    /* the session over time */
    vp_report_point_t *series;
    size_t nseries;
    double travel_tenth[VP_REPORT_TENTHS];  /* travel in each tenth of the records */
    double seed_travel;           /* travel before the first insertion (the seed probes) */
    double travel_stage[4];       /* travel per planner stage (vp_planner_stage: seed, refine, close, done) */
    double planner_seconds;       /* the planner's own time, replayed on this computer (the log holds no clock) */
    uint32_t seed_records;
} vp_report_t;

/* Loads and replays the log (a damaged tail: the records before it), meshes, checks and
 * certifies the session; mesh_path (may be NULL) is shown instead of the session's mesh.
 * VP_OK, or a VP_E* with err saying what failed. Free with vp_report_free either way. */
int  vp_report_build(vp_report_t *r, const char *log_path, const char *mesh_path, char *err, size_t errlen);
void vp_report_free(vp_report_t *r);

/* The summary as one JSON object (the same names as sim --json where they exist). */
void vp_report_summary_json(const vp_report_t *r, FILE *f);

/* Writes page[0..len) with its marker VP_REPORT_MARKER replaced by the report's data (JSON).
 * max_rays caps the hits and misses drawn (every k-th kept; 0: 200000). VP_OK, VP_EINVAL (no
 * marker in the page), VP_EIO. */
#define VP_REPORT_MARKER "/*VP_REPORT_DATA*/"
int vp_report_write_html(const vp_report_t *r, FILE *f, const char *page, size_t len, size_t max_rays);

#endif
