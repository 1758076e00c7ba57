/* planner.c — init, the arena, the phase machine and the public calls (vp_planner.h).
 * The phase machine is drawn in vp_planner_priv.h. */
#include "vp_planner_priv.h"

/* Limits of vp_planner_init. A configured length beyond CFG_MAX is refused: its square, formed
 * in the geometry, would overflow. The arena: below ARENA_MIN or a pool below POOL_MIN entries
 * (SCRATCH_MIN words of scratch) no object can be scanned. A route holds ROUTE_CAP_MAX points
 * at most: a path search expands SEARCH_FULL records, so longer routes never occur. */
#define CFG_MAX 1e150
#define PAN_TRAVEL_MAX 1e3 /* radians: the ends of the pan's travel (a board's wider travel turns freely) */
#define MIN_ANGLE_MAX 30.0 /* degrees: above it Delaunay refinement need not terminate */
#define ARENA_MIN (64u * 1024u)
#define POOL_MIN 64u
#define ROUTE_MIN 32u
#define SCRATCH_MIN 1024u
#define ROUTE_CAP_MAX 4096u
/* the slack of a proof check, relative to Omega's size (1 + its circumradius): the rounding of
 * constructed points (Voronoi vertices, hits), far below any physical size */
#define PROOF_TOL_REL 1e-10
/* Omega's circumradius, in the caller's units: at least 1e-4 (the proofs' slack of 1e-10 then
 * at most 1e-6 of it; at 1e-13 a scan ended DONE with no facet), at most 1e50 */
#define OMEGA_R_MIN 1e-4
#define OMEGA_R_MAX 1e50
#define DEG_TO_RAD 0.017453292519943295
/* body mode: the task slots keep their starts only where the task share holds this many times
 * an update's headroom with them (vp_pl_pools_have_room) */
#define NEAR_ROOM 8u
/* ---------- arena ---------- */

/* Shares of the arena per 100 units (vp_planner_init): records, facets, free edges, scratch,
 * tasks, route (in 24-byte points), proofs, the triangulation's least; [1] below SMALL_ARENA. */
static const unsigned char split[2][8] = {{20, 7, 6, 8, 7, 1, PROOF_SHARE, 28}, {23, 14, 6, 4, 5, 2, 15, 24}};

/* the bytes a task slot's kept start takes (none on a microcontroller core: it keeps none) */
#ifndef VP_CORE_MCU
#define TASK_NEAR_BYTES(pl) ((pl)->pool.near ? sizeof(vp_task_near_t) + ((pl)->pool.near_dir ? 3 * sizeof(float) : 0u) : 0u)
#else
#define TASK_NEAR_BYTES(pl) 0u
#endif

static void *carve(unsigned char **cur, unsigned char *end, size_t bytes)
{
    uintptr_t p = ((uintptr_t)*cur + 7u) & ~(uintptr_t)7u;
    if (p + bytes > (uintptr_t)end || p + bytes < p) return NULL;
    *cur = (unsigned char *)(p + bytes);
    return (void *)p;
}

/* Arena in use at most: the triangulation's high-water mark plus every pool's. The planner's
 * split of the arena is fixed, so a session needs each pool's peak to fit its share. */
VP_PL_API void vp_pl_note_peak(vp_planner_t *pl)
{
    size_t used;
    uint32_t hash_need = 1;
    if (pl->pool.ntask > pl->peak.task) pl->peak.task = pl->pool.ntask;
    if (pl->pool.nheap > pl->peak.heap) pl->peak.heap = pl->pool.nheap;
    if (pl->route.n > pl->peak.route) pl->peak.route = pl->route.n;
    while (hash_need < 2u * pl->pool.nfacets + 16u) hash_need <<= 1;
    used = vp_dt_bytes_used(&pl->dt) + (size_t)pl->pool.nvrec * sizeof(vp_vrec_t) +
           (size_t)pl->pool.nfedge * 4u * FEDGE_WORDS + (size_t)pl->pool.nproof * sizeof(vp_proof_t) + (size_t)pl->pool.nfrec * sizeof(vp_frec_t) + (size_t)hash_need * 4u +
           (size_t)pl->peak.heap * 4u + (size_t)pl->peak.task * (sizeof(vp_task_t) + TASK_NEAR_BYTES(pl)) +
           (size_t)pl->peak.route * 24u + (size_t)pl->peak.astar * 4u + (size_t)pl->peak.path * 4u;
    if (used > pl->st.arena_peak) pl->st.arena_peak = used;
}

/* ---------- public ---------- */

/* vp_planner_init's work; *made = 1 once pl has been cleared (a failure after that leaves pl
 * half made: vp_planner_init clears it and keeps the error) */
static int planner_init(vp_planner_t *pl, void *arena, size_t bytes, const vp_planner_config_t *cfg, int *made)
{
    unsigned char *cur, *end;
    size_t dtb, unit;
    const unsigned char *sh;
    uint32_t i, hwords;
    int k, st, keep_starts = 0, keep_small = 0;
    if (!pl || !arena || !cfg) return VP_EINVAL;
    if (cfg->omega_kind == VP_OMEGA_BALL) {
        if (!vp_finite3(cfg->omega_center) || !(cfg->omega_radius > 0.0) || !(cfg->omega_radius < CFG_MAX))
            return VP_EINVAL;
    } else if (cfg->omega_kind == VP_OMEGA_BOX) {
        if (!vp_finite3(cfg->omega_lo) || !vp_finite3(cfg->omega_hi)) return VP_EINVAL;
        for (k = 0; k < 3; k++)
            if (!(cfg->omega_lo[k] < cfg->omega_hi[k])) return VP_EINVAL;
    } else {
        return VP_EINVAL;
    }
    /* Omega's size in the units the caller chose: the proofs' slack holds an absolute part
     * (PROOF_TOL_REL) and the predicates' products grow as its cube and more */
    if (!(vp_pl_omega_circumradius(cfg) >= OMEGA_R_MIN) || !(vp_pl_omega_circumradius(cfg) <= OMEGA_R_MAX))
        return VP_EINVAL;
    if (!(cfg->eps > 0.0) || !(cfg->eps < CFG_MAX)) return VP_EINVAL;
    if (cfg->ninterior < 1 || cfg->ninterior > VP_PLANNER_MAX_SEEDS) return VP_EINVAL;
    for (i = 0; i < cfg->ninterior; i++)
        if (!vp_finite3(cfg->interior[i]) || !vp_pl_omega_inside(cfg, cfg->interior[i])) return VP_EINVAL;
    if (!vp_finite3(cfg->start) || vp_pl_omega_inside(cfg, cfg->start)) return VP_EINVAL;
    if (!(cfg->min_angle >= 0.0) || cfg->min_angle > MIN_ANGLE_MAX) return VP_EINVAL;
    /* the sizing field needs a floor to end on sharp edges (dM -> 0 there) */
    if (!(cfg->size_rel >= 0.0) || !(cfg->size_rel < 1.0) || !(cfg->min_size >= 0.0) ||
        (cfg->size_rel > 0.0 && !(cfg->min_size > 0.0 && cfg->min_size <= cfg->eps)))
        return VP_EINVAL;
    if (!(cfg->max_distance >= 0.0) || cfg->max_distance > CFG_MAX || cfg->min_size > cfg->eps) return VP_EINVAL;
    if (!(cfg->max_range >= 0.0) || !(cfg->noise_tol >= 0.0) || !(cfg->clearance >= 0.0) ||
        cfg->max_range > CFG_MAX || cfg->noise_tol > CFG_MAX || cfg->clearance > CFG_MAX)
        return VP_EINVAL;
#if VP_PL_LINE_LASER /* a microcontroller core takes no rays: line_rays is not read there */
    if (cfg->line_rays > VP_PLANNER_MAX_LINE_RAYS) return VP_EINVAL;
#endif
#if VP_PL_TUBES /* nor tubes: min_feature is not read there */
    /* tubes need a body, proofs that last (an object that moves makes marks stale) and a
     * feature size Omega can hold */
    if (!(cfg->min_feature >= 0.0) || !(cfg->feature_margin >= 0.0) || cfg->min_feature > CFG_MAX ||
        cfg->feature_margin > CFG_MAX ||
        (cfg->min_feature > 0.0 && (!(cfg->clearance > 0.0) || cfg->proof_life > 0u ||
                                    cfg->min_feature > vp_pl_omega_circumradius(cfg))))
        return VP_EINVAL;
#endif
#if VP_PL_TIMED
    for (k = 0; k < VP_PLANNER_AXES; k++)
        if (!(cfg->axis_time[k] >= 0.0) || cfg->axis_time[k] > CFG_MAX) return VP_EINVAL;
    if (!(fabs(cfg->pan_travel[0]) <= PAN_TRAVEL_MAX) || !(fabs(cfg->pan_travel[1]) <= PAN_TRAVEL_MAX) ||
        ((cfg->pan_travel[0] != 0.0 || cfg->pan_travel[1] != 0.0) && !(cfg->pan_travel[0] < cfg->pan_travel[1])))
        return VP_EINVAL;
#endif
    if (bytes < ARENA_MIN) return VP_ENOMEM;
    *made = 1;
    memset(pl, 0, sizeof *pl);
    pl->cfg = *cfg;
    /* the slack of a proof: rounding of constructed points, far below any physical size */
    pl->ptol = PROOF_TOL_REL * (1.0 + vp_pl_omega_circumradius(cfg));
    pl->close.size_epoch = 1;
    cur = (unsigned char *)arena;
    end = cur + bytes;
    /* the split, per 100 units, from the peaks measured per output vertex (README): the
     * triangulation at least 28, records 20, proofs 16, free edges 6, facets 7, tasks 7, hash
     * 2-4, path search and hole scratch 8, paths 1, heap 1, route 1. Below SMALL_ARENA (a
     * microcontroller's RAM, some 100 vertices) the split of a small mesh, whose facets and
     * proofs weigh more and whose scratch needs less (split[1]): the triangulation at least
     * 24, records 23, proofs 15, free edges 6, facets 14, tasks 5, scratch 4, route 2. */
    unit = bytes / 100;
    sh = split[bytes < SMALL_ARENA];
    pl->pool.room = bytes < SMALL_ARENA ? (uint32_t)(bytes / ROOM_BYTES) : ROOM_SMALL;
    pl->pool.cap_vrec = (uint32_t)(sh[0] * unit / sizeof(vp_vrec_t));
    pl->pool.cap_frec = (uint32_t)(sh[1] * unit / sizeof(vp_frec_t));
    pl->pool.cap_fedge = (uint32_t)(sh[2] * unit / (4 * FEDGE_WORDS));
    for (hwords = 1; (size_t)hwords * 2 * 4 <= 4 * unit; hwords <<= 1) {}
    pl->pool.cap_astar = (uint32_t)(sh[3] * unit / 4);
    pl->route.cap_path = (uint32_t)(unit / 4);
    /* body mode: each task slot has its start kept beside it (the nearest task, tasks.c), where
     * the task share then still holds NEAR_ROOM times an update's headroom (from about 2.6 MB;
     * timed, with each start's direction, 3 MB): in a smaller arena the starts are worked out
     * at each pick */
    pl->pool.cap_task = (uint32_t)(sh[4] * unit / sizeof(vp_task_t));
#ifndef VP_CORE_MCU /* a microcontroller core keeps the newest-first order (its flash budget) */
    if (cfg->clearance > 0.0) {
        size_t slot = sizeof(vp_task_t) + sizeof(vp_task_near_t) + (vp_planner_timed(cfg) ? 3 * sizeof(float) : 0u);
        uint32_t cap_near = (uint32_t)(sh[4] * unit / slot);
        if (cap_near >= NEAR_ROOM * pl->pool.room) { keep_starts = 1; pl->pool.cap_task = cap_near; }
    } else if (cfg->flags & VP_PLAN_SMALL_FIRST) {
        /* the smallest ball first: each slot's smallest ball kept beside it (tasks.c) */
        uint32_t cap_small = (uint32_t)(sh[4] * unit / (sizeof(vp_task_t) + sizeof(vp_task_small_t)));
        if (cap_small >= NEAR_ROOM * pl->pool.room) { keep_small = 1; pl->pool.cap_task = cap_small; }
    }
#endif
    pl->pool.cap_heap = (uint32_t)(unit / 4);
    pl->route.cap = (uint32_t)(sh[5] * unit / 24);
    if (pl->route.cap > ROUTE_CAP_MAX) pl->route.cap = ROUTE_CAP_MAX;
    pl->pool.vrec = carve(&cur, end, (size_t)pl->pool.cap_vrec * sizeof(vp_vrec_t));
    pl->pool.frec = carve(&cur, end, (size_t)pl->pool.cap_frec * sizeof(vp_frec_t));
    pl->pool.fedge = carve(&cur, end, (size_t)pl->pool.cap_fedge * 4 * FEDGE_WORDS);
    pl->pool.fhash = carve(&cur, end, (size_t)hwords * 4);
    pl->pool.astar = carve(&cur, end, (size_t)pl->pool.cap_astar * 4);
    pl->route.path = carve(&cur, end, (size_t)pl->route.cap_path * 4);
    pl->pool.task = carve(&cur, end, (size_t)pl->pool.cap_task * sizeof(vp_task_t));
    if (keep_small) {
        pl->pool.small = carve(&cur, end, (size_t)pl->pool.cap_task * sizeof(vp_task_small_t));
        if (!pl->pool.small) return VP_ENOMEM;
        memset(pl->pool.small, 0, (size_t)pl->pool.cap_task * sizeof(vp_task_small_t)); /* none kept */
    }
    if (keep_starts) {
        pl->pool.near = carve(&cur, end, (size_t)pl->pool.cap_task * sizeof(vp_task_near_t));
        if (!pl->pool.near) return VP_ENOMEM;
        memset(pl->pool.near, 0, (size_t)pl->pool.cap_task * sizeof(vp_task_near_t)); /* no key is all 0 */
#if VP_PL_TIMED
        if (vp_planner_timed(cfg)) {
            pl->pool.near_dir = carve(&cur, end, (size_t)pl->pool.cap_task * 3 * sizeof(float));
            if (!pl->pool.near_dir) return VP_ENOMEM;
        }
#endif
    }
    pl->pool.heap = carve(&cur, end, (size_t)pl->pool.cap_heap * 4);
    pl->route.pts = carve(&cur, end, (size_t)pl->route.cap * 24);
    pl->route.proof = carve(&cur, end, (size_t)pl->route.cap * 4);
    pl->pool.cap_proof = (uint32_t)(sh[6] * unit / sizeof(vp_proof_t));
    pl->pool.proof = carve(&cur, end, (size_t)pl->pool.cap_proof * sizeof(vp_proof_t));
    if (!pl->route.proof || !pl->pool.proof || pl->pool.cap_proof < POOL_MIN) return VP_ENOMEM;
    if (!pl->pool.vrec || !pl->pool.frec || !pl->pool.fedge || !pl->pool.fhash || !pl->pool.astar || !pl->route.path ||
        !pl->pool.task || !pl->pool.heap || !pl->route.pts || pl->pool.cap_vrec < POOL_MIN || pl->pool.cap_frec < POOL_MIN ||
        pl->pool.cap_task < POOL_MIN || pl->route.cap < ROUTE_MIN || pl->pool.cap_astar < SCRATCH_MIN)
        return VP_ENOMEM;
    dtb = (size_t)(end - cur);
    /* the other shares take at most 71.2 units (the hash up to 4): the triangulation gets the
     * rest, never less than 28 (it needs 23-27 at 2.5 KB per output vertex); with a distance
     * bound the samples' normal cache takes a 16th of it where that leaves 28 (some 400 bytes
     * of triangulation per sample: the cache has room for nearly every one) */
    if (dtb < sh[7] * unit) return VP_ENOMEM;
    if (cfg->max_distance > 0.0) {
        size_t nb = dtb / 16;
        if (dtb - nb < sh[7] * unit) nb = dtb - sh[7] * unit;
        size_t per = 3 * sizeof(double) + sizeof(uint32_t); /* a normal and a change stamp */
        pl->pool.cap_nrm = (uint32_t)(nb / per < 0xFFFFFFF0u ? nb / per : 0xFFFFFFF0u);
        pl->pool.nrm = pl->pool.cap_nrm > 0 ? carve(&cur, end, (size_t)pl->pool.cap_nrm * 3 * sizeof(double)) : NULL;
        pl->pool.vstamp = pl->pool.nrm ? carve(&cur, end, (size_t)pl->pool.cap_nrm * sizeof(uint32_t)) : NULL;
        if (!pl->pool.nrm || !pl->pool.vstamp) { pl->pool.cap_nrm = 0; pl->pool.nrm = NULL; pl->pool.vstamp = NULL; }
        else memset(pl->pool.vstamp, 0xFF, (size_t)pl->pool.cap_nrm * sizeof(uint32_t)); /* unknown: changed */
        dtb = (size_t)(end - cur);
    }
#if VP_PL_TUBES
    if (cfg->min_feature > 0.0) {
        /* the grid of tube marks: at most an eighth of what is left, the triangulation keeping
         * its least share */
        size_t budget = dtb / 8, nb;
        if (dtb - budget < sh[7] * unit) budget = dtb - sh[7] * unit;
        nb = vp_pl_tube_plan(cfg, pl->ptol, budget, &pl->tube);
        if (nb == 0 || !(pl->tube.bits = carve(&cur, end, nb))) return VP_ENOMEM;
        memset(pl->tube.bits, 0, nb);
        pl->tube.on = 1;
        dtb = (size_t)(end - cur);
    }
#endif
    st = vp_dt_init(&pl->dt, cur, dtb, KPAY * 4);
    if (st != VP_OK) return st == VP_EINVAL ? VP_ENOMEM : st;
    pl->pool.hash_mask = hwords - 1;
    for (i = 0; i < hwords; i++) pl->pool.fhash[i] = HASH_EMPTY;
    pl->pool.frec_free = NONE;
    pl->probe.cur_proof = pl->probe.chain_proof = PROOF_NONE;
    pl->phase = PH_SEED;
    {
        /* sin of the angle bound by its Taylor series (|x| <= pi/6: error below 1e-9) */
        double x = cfg->min_angle * DEG_TO_RAD, x2 = x * x;
        pl->sin_angle = x * (1.0 - x2 / 6.0 * (1.0 - x2 / 20.0 * (1.0 - x2 / 42.0 * (1.0 - x2 / 72.0))));
    }
    memcpy(pl->dev.pos, cfg->start, sizeof pl->dev.pos);
#if VP_PL_TIMED
    /* the pan before the first probe: 0, or the nearest end of its travel */
    if (cfg->pan_travel[0] > 0.0) pl->dev.pan = cfg->pan_travel[0];
    if (cfg->pan_travel[1] < 0.0) pl->dev.pan = cfg->pan_travel[1];
#endif
#if VP_PL_CONTACTS
    pl->rescan.drop = pl->rescan.cur = NONE; /* no re-scan yet */
#endif
    st = vp_pl_rec_new(pl, cfg->start, NONE, REC_OUT, &pl->dev.at);
    if (st != VP_OK) return st;
    vp_pl_note_peak(pl);
    return VP_OK;
}

int vp_planner_init(vp_planner_t *pl, void *arena, size_t bytes, const vp_planner_config_t *cfg)
{
    int made = 0, st = planner_init(pl, arena, bytes, cfg, &made);
    if (st != VP_OK && made) {
        /* the arena held too little once the pools were laid out: nothing half made is left to
         * run, every call but vp_planner_init answers this error */
        memset(pl, 0, sizeof *pl);
        pl->error = st;
    }
    return st;
}

/* A PROBE goes out: what its result will prove is measured from this ray. */
static void issue_probe(vp_planner_t *pl, vp_cmd_t *cmd, const double *from, const double *dir,
                        double range)
{
    cmd->kind = VP_CMD_PROBE;
    memcpy(cmd->from, from, sizeof cmd->from);
    memcpy(cmd->dir, dir, sizeof cmd->dir);
    cmd->range = range;
    pl->dev.awaiting = 1;
    memcpy(pl->dev.iss_o, cmd->from, sizeof pl->dev.iss_o);
    memcpy(pl->dev.iss_d, cmd->dir, sizeof pl->dev.iss_d);
    pl->dev.iss_range = cmd->range;
#if VP_PL_TIMED
    if (vp_pl_timed(pl)) vp_pl_pan_aim(pl, dir);
#endif
    pl->probe.cur_proof = PROOF_NONE;
#if VP_PL_CONTACTS
    pl->contact.moved = 0;
#endif
    pl->st.probes++;
}

/* Issue step 1: MOVE to the next route point. The one promise: a MOVE only along a segment
 * with a proof of freedom, checked again here. */
static int issue_move(vp_planner_t *pl, vp_cmd_t *cmd)
{
    const double *to = pl->route.pts + 3 * (size_t)pl->route.i;
    if (!vp_pl_proof_covers(pl, pl->route.proof[pl->route.i], pl->dev.pos, to)) return VP_EUNSAFE;
    if (pl->route.proof[pl->route.i] == PROOF_TUBE) pl->st.tube_moves++;
    pl->route.i++;
    cmd->kind = VP_CMD_MOVE;
    memcpy(cmd->from, pl->dev.pos, sizeof cmd->from);
    memcpy(cmd->to, to, sizeof cmd->to);
#if VP_PL_CONTACTS
    if (pl->cfg.clearance > 0.0 && pl->probe.ready && !pl->sc.pending) {
        /* the route leads to a PROBE: its direction, and the way left after this MOVE, so that
         * a machine may turn the head towards it on the way (a hint: the PROBE aims anyway) */
        uint32_t q;
        const double *prev = to;
        memcpy(cmd->dir, pl->probe.dir, sizeof cmd->dir);
        for (q = pl->route.i; q < pl->route.n; q++) {
            cmd->range += vp_dist3(prev, pl->route.pts + 3 * (size_t)q);
            prev = pl->route.pts + 3 * (size_t)q;
        }
    }
#endif
    pl->st.travel += vp_dist3(pl->dev.pos, to);
    pl->st.moves++;
#if VP_PL_CONTACTS
    pl->contact.moved = 1;
    memcpy(pl->contact.move_from, pl->dev.pos, sizeof pl->contact.move_from);
#endif
    memcpy(pl->dev.pos, to, sizeof pl->dev.pos);
    return VP_OK;
}

/* Issue step 2: PROBE the straight way of a shortcut, from sc.from towards sc.to. */
static int issue_shortcut(vp_planner_t *pl, vp_cmd_t *cmd)
{
    const vp_vrec_t *a = &pl->pool.vrec[pl->sc.from], *b = &pl->pool.vrec[pl->sc.to];
    double d[3], len;
    vp_sub3(d, b->p, a->p);
    len = sqrt(vp_dot3(d, d));
    if (!vp_normalize3(d)) return VP_EDEGEN; /* two records at one point: never proposed */
    pl->sc.pending = 2;
    pl->probe.chain_proof = PROOF_NONE;
    issue_probe(pl, cmd, a->p, d, len);
    pl->st.shortcut_probes++;
    return VP_OK;
}

/* A range-limited probe is being walked on: the device stands at the end of its free part and
 * the next task continues it, so nothing is inserted before it goes on. */
static int walk_in_progress(const vp_planner_t *pl)
{
    return pl->pool.ntask > 0 && pl->pool.task[pl->pool.ntask - 1].off > 0.0;
}

/* Issue step 4: one step of the phase machine (VP_PL_PHASES); *done = 1 at the end. */
static int phase_step(vp_planner_t *pl, int *done)
{
    int st = VP_OK;
    switch (pl->phase) {
    case PH_SEED:
        st = vp_pl_seed_next(pl);
        if (st == 1) {
            st = vp_pl_start_run(pl);
            pl->phase = PH_RUN;
        }
        return st;
    case PH_RUN:
#if VP_PL_CONTACTS
        if (pl->rescan.ndoomed > 0 && pl->dt.ninserted > 5 && !walk_in_progress(pl)) {
            /* a re-scan's samples that had to wait for new ones to be removed */
            st = vp_pl_remove_doomed(pl);
            if (st < 0) return st;
        }
#endif
#if VP_PL_LINE_LASER
        if (pl->rays.n > 0 && !walk_in_progress(pl)) {
            /* a line laser's hit becomes a sample first (where no sample is within eps): the
             * refinement then needs fewer centres probed one by one */
            st = vp_pl_ray_sample(pl);
            return st < 0 ? st : VP_OK;
        }
#endif
        if (pl->pool.nheap > 0 && !vp_pl_exhaustive(pl) &&
            !walk_in_progress(pl)) {
            /* a known bad ball is refined at once: the probes still queued around it would
             * mostly test facets that its insertion kills (the published rule finishes
             * detect_access first). A range-limited probe in progress goes on first: the
             * device stands at the end of its free part. */
            return vp_pl_refine(pl);
        }
        if (pl->pool.ntask > 0) {
            vp_task_t k;
#ifndef VP_CORE_MCU
            /* body mode: the task whose probe starts nearest the head (timed: soonest) goes first;
             * point mode, asked: the one that can find the smallest ball */
            if (pl->cfg.clearance > 0.0 && pl->pool.ntask > 1) vp_pl_task_nearest_on_top(pl);
            else if ((pl->cfg.flags & VP_PLAN_SMALL_FIRST) && pl->pool.ntask > 1) vp_pl_task_small_on_top(pl);
            if (pl->pool.ntask == 0) return pl->error; /* every task had gone */
#endif
            k = pl->pool.task[--pl->pool.ntask];
            if (vp_pl_task_start(pl, &k)) pl->probe.ready = 1;
            if (pl->sc.pending) pl->route.i = pl->route.n; /* hold the route: shortcut first */
            return pl->error;
        }
        if (pl->pool.nheap > 0) return vp_pl_refine(pl);
        if ((pl->cfg.size_rel > 0.0 || pl->cfg.max_distance > 0.0) && pl->close.size_mark != pl->st.insertions + 1) {
            /* the sizing field's dM estimates shrank with the samples since the balls were
             * rated: rate them all again before closing */
            pl->close.size_mark = pl->st.insertions + 1;
            st = vp_pl_size_pass(pl);
            if (st != 0) return st < 0 ? st : VP_OK;
        }
        pl->phase = PH_CLOSE;
        return VP_OK;
    case PH_CLOSE:
        /* closing again with nothing probed or inserted since the last try cannot do better:
         * the holes stay (certify names them) */
        if (pl->close.mark == pl->st.probes + pl->st.insertions + 1) {
            /* the probes queued around the holes all resolved without probing: refining at
             * the open edges (the manifold criterion) is what is left, else the holes stay */
            st = vp_pl_close_holes(pl, 1);
            if (st > 0) { pl->phase = PH_RUN; return VP_OK; }
            pl->st.stalls++;
            pl->phase = PH_COMPONENTS;
            return st;
        }
        pl->close.mark = pl->st.probes + pl->st.insertions + 1;
        st = vp_pl_close_holes(pl, 0);
        pl->phase = st > 0 ? PH_RUN : PH_COMPONENTS;
        return st > 0 ? VP_OK : st;
    case PH_COMPONENTS:
        return vp_pl_check_components(pl);
#if VP_PL_CONTACTS
    case PH_VERIFY:
        return vp_pl_verify_next(pl);
#endif
    default: /* PH_DONE */
        *done = 1;
        return VP_OK;
    }
}

/* internal steps one vp_planner_next call may take without a command (plus 4 per task slot):
 * far above any real need, so hitting it means a rule loops */
#define STEP_BUDGET (1u << 20)

/* The issue order of VP_PL_PHASES: a route step, the shortcut probe, the prepared probe, else
 * a step of the phase machine, until one gives a command. */
int vp_planner_next(vp_planner_t *pl, vp_cmd_t *cmd)
{
    int st;
    uint64_t budget;
    if (!pl || !cmd) return VP_EINVAL;
    if (pl->dev.awaiting) return VP_ESTATE;
    if (pl->error) return pl->error;
    memset(cmd, 0, sizeof *cmd);
#if VP_PL_LINE_LASER
    pl->rays.left = 0;          /* the last PROBE's frame is over */
#endif
#if VP_PL_CONTACTS
    if (pl->rescan.blocked || pl->rescan.drop != NONE) {
        /* a re-scan's last PROBE found a route step blocked or a sample moved */
        st = vp_pl_rescan_pending(pl);
        if (st < 0) { pl->error = st; return st; }
    }
#endif
    for (budget = STEP_BUDGET + 4u * (uint64_t)pl->pool.cap_task;; budget--) {
        if (budget == 0) {
            /* bounded work per call: a loop that issues nothing is reported, never spun */
            pl->st.stalls++;
            pl->error = VP_ESTALL;
            return VP_ESTALL;
        }
        if (pl->route.i < pl->route.n) {
#if VP_PL_CONTACTS
            double d[3], range;
            if (vp_pl_step_stale(pl) && vp_pl_reprove_dir(pl, d, &range)) {
                /* a re-scan: the step's proof is from before it; probe the step first */
                issue_probe(pl, cmd, pl->dev.pos, d, range);
                return VP_OK;
            }
#endif
            st = issue_move(pl, cmd);
        } else if (pl->sc.pending == 1) {
            st = issue_shortcut(pl, cmd);
        } else if (pl->probe.ready) {
            pl->probe.ready = 0;
            issue_probe(pl, cmd, pl->probe.origin, pl->probe.dir,
                        pl->probe.reach > pl->probe.range ? pl->probe.reach : pl->probe.range);
            return VP_OK;
#if VP_PL_TUBES
        } else if (pl->tube.survey_ready) {
            /* a survey ray, from where its route ended, back along the tube */
            double d[3];
            pl->tube.survey_ready = 0;
            pl->tube.survey_wait = 1;
            d[0] = -pl->tube.su[0]; d[1] = -pl->tube.su[1]; d[2] = -pl->tube.su[2];
            issue_probe(pl, cmd, pl->dev.pos, d, vp_pl_clamp_range(pl, pl->tube.ray_range));
            return VP_OK;
        } else if (pl->tube.survey_i < pl->tube.survey_n) {
            st = vp_pl_survey_next(pl);
            if (st >= 0) continue;
#endif
        } else {
            int done = 0;
            st = phase_step(pl, &done);
            if (done) {
                cmd->kind = VP_CMD_DONE;
#if VP_PL_CONTACTS
                pl->contact.moved = 0;
#endif
                vp_pl_note_peak(pl);
                return VP_OK;
            }
            if (st >= 0) continue;
        }
        if (st < 0) pl->error = st;
        return st;
    }
}

/* The straight way is not free: the searched route stands (searched now if it was deferred).
 * When no way is known any more (a contact withdrew them), the prepared probe is dropped. */
static int shortcut_search(vp_planner_t *pl)
{
    if (pl->route.deferred) {
        int st;
        pl->route.deferred = 0;
        st = vp_pl_route_full(pl, pl->sc.from, pl->sc.to);
        if (st < 0) return st;
#if VP_PL_CONTACTS
        if (st == PL_UNREACHABLE) {
            pl->route.n = 0;
            pl->dev.at = pl->sc.from;
            if (pl->phase == PH_VERIFY) pl->probe.ready = 0; /* a measuring probe: the next line */
            else vp_pl_probe_drop(pl);
        }
#endif
    }
    pl->route.i = 0;
    return VP_OK;
}

/* The answer to a shortcut probe: a hit keeps the searched route (searching it now if it was
 * deferred); a miss, confirmed, makes the straight way a free edge and the route. */
static int shortcut_feed(vp_planner_t *pl, const vp_probe_result_t *res)
{
    uint32_t pf;
    pl->sc.pending = 0;
    if (res->hit) return shortcut_search(pl);
    if (pl->sc.tries < pl->cfg.confirm_misses) {
        pl->sc.tries++;
        pl->st.reprobes++;
        pl->sc.pending = 1;
        return VP_OK;
    }
    VP_TRY(vp_pl_probe_proof(pl, res, &pf));
    if (VP_PL_CONTACTS && pf == PROOF_NONE && pl->contact.n > 0) return shortcut_search(pl); /* a miss near a contact proves nothing */
    /* the straight way is free: take it */
    pl->route.deferred = 0;
    VP_TRY(vp_pl_edge_add(pl, pl->sc.from, pl->sc.to, pf));
    pl->route.n = pl->route.i = 0;
    return vp_pl_route_push(pl, pl->pool.vrec[pl->sc.to].p, pf);
}

/* A probe's (or a ray's) result as the device may give it: hit 0, 1 or too close, its distance
 * finite (a miss's too: the session log holds it), a hit's not negative either. */
int vp_probe_result_valid(const vp_probe_result_t *res)
{
    if (!res || res->hit < 0 || res->hit > VP_PROBE_TOO_CLOSE) return 0;
    if (!vp_finite(res->dist)) return 0;
    return res->hit != 1 || (res->dist >= 0.0 && res->dist < VP_PL_HUGE);
}

int vp_planner_feed(vp_planner_t *pl, const vp_probe_result_t *res)
{
    int st;
    if (!pl || !res) return VP_EINVAL;
    if (!pl->dev.awaiting) return VP_ESTATE;
    if (!vp_probe_result_valid(res)) return VP_EINVAL;
    pl->dev.awaiting = 0;
    /* counted as the device answered, whatever the answer is used for */
    if (res->hit == 1) pl->st.hits++;
    else if (res->hit == 0) pl->st.misses++;
    else pl->st.too_close++;
#if VP_PL_LINE_LASER
    pl->rays.left = pl->cfg.line_rays;
#endif
#if VP_PL_TUBES
    if (pl->tube.survey_wait) st = vp_pl_survey_feed(pl, res);
    else
#endif
#if VP_PL_CONTACTS
    if (pl->rescan.reprove) st = vp_pl_reprove_feed(pl, res);
    else if (pl->sc.pending == 2) st = shortcut_feed(pl, res);
    else if (pl->phase == PH_VERIFY) st = vp_pl_verify_feed(pl, res);
#else
    if (pl->sc.pending == 2) st = shortcut_feed(pl, res);
#endif
    else if (pl->phase == PH_SEED) st = vp_pl_seed_feed(pl, res);
    else if (pl->phase == PH_RESEED) st = vp_pl_reseed_feed(pl, res);
    else st = vp_pl_task_finish(pl, res);
    if (st < 0) pl->error = st;
    return st;
}

#if VP_PL_LINE_LASER
int vp_planner_feed_ray(vp_planner_t *pl, const double dir[3], const vp_probe_result_t *res)
{
    double h[3];
    uint32_t i;
    int q;
    if (!pl || !dir || !res) return VP_EINVAL;
    if (!vp_finite3(dir) || fabs(vp_dot3(dir, dir) - 1.0) > 1e-9) return VP_EINVAL;
    if (!vp_probe_result_valid(res)) return VP_EINVAL;
    if (pl->error) return pl->error;
    if (pl->dev.awaiting || pl->rays.left == 0) return VP_ESTATE;
    pl->rays.left--;
    pl->st.rays++;
    if (res->hit != 1) return VP_OK;
    pl->st.ray_hits++;
    /* only while refining (the seeds and the closing rounds keep their own samples), and only
     * as many as the queue holds: the rest of a frame is left unused */
    if (pl->phase != PH_RUN || pl->rays.n >= VP_PLANNER_RAY_QUEUE) return VP_OK;
    for (q = 0; q < 3; q++) h[q] = pl->dev.iss_o[q] + res->dist * dir[q];
    /* a hit within eps of one already queued could not become a sample beside it */
    for (i = 0; i < pl->rays.n; i++)
        if (vp_dist3(h, pl->rays.pts[i]) <= pl->cfg.eps) return VP_OK;
    memcpy(pl->rays.pts[pl->rays.n++], h, sizeof h);
    return VP_OK;
}
#endif

uint32_t vp_planner_facet_slots(const vp_planner_t *pl) { return pl->pool.nfrec; }
uint32_t vp_planner_num_facets(const vp_planner_t *pl) { return pl->pool.nfacets; }

vp_planner_stage_t vp_planner_stage(const vp_planner_t *pl)
{
    switch (pl->phase) {
    case PH_SEED: case PH_VERIFY: return VP_STAGE_SEED;
    case PH_RUN: case PH_RESEED: return VP_STAGE_REFINE;
    case PH_CLOSE: case PH_COMPONENTS: return VP_STAGE_CLOSE;
    default: return VP_STAGE_DONE;
    }
}
const vp_dt_t *vp_planner_dt(const vp_planner_t *pl) { return &pl->dt; }

int vp_planner_facet(const vp_planner_t *pl, uint32_t i, uint32_t v[3], double *radius, double center[3])
{
    const vp_frec_t *f;
    if (i >= pl->pool.nfrec) return 0;
    f = &pl->pool.frec[i];
    if (!frec_in_mesh(f)) return 0;
    v[0] = f->v[0];
    v[1] = (f->flags & FREC_FLIP) ? f->v[2] : f->v[1];
    v[2] = (f->flags & FREC_FLIP) ? f->v[1] : f->v[2];
    if (radius) *radius = f->r;
    if (center) memcpy(center, f->c, sizeof f->c);
    return (f->flags & FREC_CUT) ? 2 : 1;
}

void vp_planner_get_stats(const vp_planner_t *pl, vp_planner_stats_t *st)
{
    uint32_t i;
    *st = pl->st;
    st->bad_balls = pl->pool.nheap;
    st->missing_components = 0;
    for (i = 0; i < pl->cfg.ninterior; i++)
        st->missing_components += !(pl->close.h2_done & (1u << i));
    st->records = pl->pool.nvrec;
    st->free_edges = pl->pool.nfedge;
    st->facet_records = pl->pool.nfacets;
    st->max_ball = 0.0;
    for (i = 0; i < pl->pool.nfrec; i++)
        if (pl->pool.frec[i].v[0] != NONE && pl->pool.frec[i].r > st->max_ball) st->max_ball = pl->pool.frec[i].r;
}
