/* close.c — closing holes and H2. When no ball is bad, every edge of the mesh must have two
 * facets (a closed surface); edges with one are probed around until they do. H2 (every
 * component of S holds a sample): each interior point o_i must be enclosed by the mesh,
 * otherwise a component was missed and is reseeded from dOmega towards o_i. */
#include "vp_planner_priv.h"

/* ---------- closing: every edge of the mesh must have exactly two facets ---------- */

/* Queues forced probes around edge (x, y) of Del(E): from every active tet of the ring, each
 * unknown facet. Returns the number of probes queued, or a negative status. */
static int probe_around_edge(vp_planner_t *pl, uint32_t t0, uint32_t x, uint32_t y)
{
    ring_t r;
    uint32_t pushed = 0;
    int broken = 0;
    if (!ring_start(pl, &r, t0, x, y)) return 0;
    do {
        int f;
        if (tet_active(pl, r.cur))
            for (f = 0; f < 4; f++) {
                unsigned s = side_get(pl, r.cur, f);
#if VP_PL_TUBES
                if (pl->cfg.clearance > 0.0 && (pl->tube.on || !(pl->cfg.flags & VP_PLAN_NO_AIM)) &&
                    (s & (SIDE_BLOCKED | SIDE_DEGEN | SIDE_RETRIED | SIDE_QUEUED)) == SIDE_BLOCKED &&
                    (s & SIDE_MASK) == SIDE_UNKNOWN) {
                    /* unseen at a hole: once more, now that more tubes are proven (the line from
                     * past its occluder, or a survey), or from aside (aim.c) */
                    s = (s & ~SIDE_BLOCKED) | SIDE_RETRIED;
                    side_set(pl, r.cur, f, s);
                }
#endif
                if ((s & SIDE_MASK) != SIDE_UNKNOWN || (s & (SIDE_QUEUED | SIDE_BLOCKED)) ||
                    vp_pl_facet_has_ghost(pl, r.cur, f))
                    continue;
                VP_TRY(vp_pl_task_push(pl, r.cur, f, 1));
                pushed++;
            }
    } while (ring_step(pl, &r, &broken));
    return (int)pushed;
}

/* The manifold criterion (as CGAL's surface mesher refines non-manifold places): when probing
 * around the edges that do not have exactly two facets finds nothing more, the largest facet at
 * each such edge is refined like a bad ball, down to a floor on its radius so that it ends on
 * sharp edges and corners (inserted centres are farther than the floor from every sample). */
#define MANIFOLD_FLOOR_REL 0.01 /* of eps: the smallest ball refined for the manifold criterion */
/* 1 if a side of a tet around edge (x, y) of Del(E) is blocked as unseen: a Voronoi edge there
 * could not be probed (occluded from dOmega for a device with a body, or too close), so the hole
 * may be one the device cannot see, where refining would only add samples it cannot close (a
 * degenerate edge is no such reason: refinement is what removes it). In body mode such an edge
 * is refined all the same once no line is left to aim there (closing's last resort spent), while
 * each pass that does so finds fewer odd edges than the last one (refine_at_edges): at the rpi4's
 * 36 mm torus the unseen sides of the rings at its inner equator run along the axis through the
 * hole (S is not on them; a miss there cannot be read, the camera looking through the hole), and
 * refining closes the hole; where the device truly cannot see, the holes grow as they are
 * refined, and it stops. */
static int ring_blocked(const vp_planner_t *pl, uint32_t t0, uint32_t x, uint32_t y)
{
    ring_t r;
    int broken = 0;
    if (!ring_start(pl, &r, t0, x, y)) return 1;
    do {
        int f;
        for (f = 0; f < 4; f++) {
            unsigned s = side_get(pl, r.cur, f);
            if ((s & (SIDE_BLOCKED | SIDE_DEGEN)) == SIDE_BLOCKED && (s & SIDE_MASK) == SIDE_UNKNOWN) return 1;
        }
    } while (ring_step(pl, &r, &broken));
    return broken;
}

/* A facet record with edge (a, b): the first one, or with `largest` the largest ball among the
 * ones not stuck. NONE when there is none. */
static uint32_t edge_facet(const vp_planner_t *pl, uint32_t a, uint32_t b, int largest)
{
    uint32_t k, best = NONE;
    for (k = 0; k < pl->pool.nfrec; k++) {
        const vp_frec_t *f = &pl->pool.frec[k];
        if (f->v[0] == NONE || (largest && (f->flags & FREC_STUCK))) continue;
        if (!(f->v[0] == a || f->v[1] == a || f->v[2] == a) || !(f->v[0] == b || f->v[1] == b || f->v[2] == b))
            continue;
        if (!largest) return k;
        if (best == NONE || f->r > pl->pool.frec[best].r) best = k;
    }
    return best;
}

/* The edges of the edge table (3 words per slot: a, b, facets) without exactly two facets */
static uint32_t odd_edges(const uint32_t *tab, uint32_t slots)
{
    uint32_t i, odd = 0;
    for (i = 0; i < slots; i++) odd += tab[3 * i] != NONE && tab[3 * i + 2] != 2;
    return odd;
}

/* A tet to turn around edge (a, b) of the mesh from: one holding a facet record with that edge.
 * The search's scratch past the edge table (3 slots words) is left alone. NONE when none. */
static uint32_t edge_tet(vp_planner_t *pl, uint32_t a, uint32_t b, uint32_t slots)
{
    int fi;
    uint32_t k = edge_facet(pl, a, b, 0);
    return k == NONE ? NONE : vp_pl_find_facet(pl, pl->pool.frec[k].v, &fi, 3u * slots);
}

/* The smallest ball the manifold criterion refines. With a distance bound the features found
 * can be finer than eps / 100: the floor follows the bound's own floor. */
static double manifold_floor(const vp_planner_t *pl)
{
    double floor = MANIFOLD_FLOOR_REL * pl->cfg.eps;
    if (pl->cfg.max_distance > 0.0 && MANIFOLD_FLOOR_MIN * pl->cfg.min_size < floor)
        floor = MANIFOLD_FLOOR_MIN * pl->cfg.min_size;
    return floor;
}

static int refine_at_edges(vp_planner_t *pl, const uint32_t *tab, uint32_t slots)
{
    uint32_t i, refined = 0, odd = 0, unseen_used = 0;
    double floor = manifold_floor(pl);
    /* round an unseen side too: body mode, once closing's last resort has been taken and would
     * not be again (no line is left to aim: vp_pl_aim_far_vertices), and only while the odd
     * edges keep falling (so it ends) */
    int unseen_ok = 0;
#if VP_PL_TUBES
    if (pl->cfg.clearance > 0.0 && pl->close.far_lines) {
        odd = odd_edges(tab, slots);
        unseen_ok = 2u * odd > pl->close.resort_odd && (pl->close.unseen_odd == 0 || odd < pl->close.unseen_odd);
    }
#endif
    for (i = 0; i < slots; i++) {
        uint32_t a = tab[3 * i], b = tab[3 * i + 1], best;
        if (a == NONE || tab[3 * i + 2] == 2) continue;
        best = edge_facet(pl, a, b, 1);
        if (best == NONE || pl->pool.frec[best].heap != NONE || !(pl->pool.frec[best].r > floor))
            continue;
        {
            int fi;
            uint32_t t = vp_pl_find_facet(pl, pl->pool.frec[best].v, &fi, 3u * slots);
            if (t == NONE) continue;
            if (ring_blocked(pl, t, a, b)) {
                if (!unseen_ok) continue;
                unseen_used++;
            }
        }
        VP_TRY(vp_pl_heap_push(pl, best));
        refined++;
    }
    if (unseen_used) pl->close.unseen_odd = odd;
    pl->st.unseen_refinements += unseen_used;
    pl->st.manifold_refinements += refined;
    return (int)refined;
}

/* A fin thinner than the floor. The mesh is the boundary between the tets known outside (their
 * Voronoi vertex reached) and the rest, the inside. Where the manifold criterion has refined an
 * edge down to its floor and the edge still has four facets, the inside touches itself along
 * the edge (a wedge whose tip is thinner than the floor, as on an acute fold). The pinch is cut:
 * one inside tet of the ring is taken as outside (SIDE_CUT): its facets towards the outside go,
 * its facets towards the inside come in as facets without a probed ball (FREC_CUT: the facet's
 * circumcentre, never refined). Only a tet whose facets that go are hits with balls of at most
 * CUT_BALL floors (the surface moves by no more than those) and whose removal keeps the topology
 * of the inside (vp_pl_cut_keeps_topology). Counted (fins_cut). */
#define CUT_BALL 4.0
/* the refine-only round cuts at fins only when at most this many edges are still odd */
#define LAST_HOLES 4u
static int tet_outside(const vp_planner_t *pl, uint32_t t)
{
    return tet_active(pl, t) || (side_get(pl, t, 0) & SIDE_CUT);
}

#define STAR_MAX 128 /* tets of a vertex's star looked at, at most */

/* a tet of the inside: neither reached, nor cut, nor a ghost (the outside at infinity) */
static int tet_inside(const vp_planner_t *pl, uint32_t t)
{
    return !vp_dt_is_ghost(&pl->dt, t) && !tet_outside(pl, t);
}

/* 1 if taking inside tet t out keeps the topology of the inside: the part of t's boundary that
 * the rest of the inside holds (its facets, edges and vertices in another inside tet) is not
 * empty, is connected and has Euler characteristic 1 (a disk or a tree on the sphere that is
 * t's boundary: contractible, so the inside without t is a deformation retract of it). Taking
 * out a tet held along a loop would punch a tunnel (a handle too many), one held all round
 * would leave a cavity, one held at two places apart would cut the inside in two. */
VP_PL_API int vp_pl_cut_keeps_topology(const vp_planner_t *pl, uint32_t t)
{
    const uint32_t *w = vp_dt_tet(&pl->dt, t);
    uint32_t star[STAR_MAX], root[4];
    int held_v[4], nv = 0, ne = 0, nf = 0, i, j, k, n, broken = 0, comps = 0;
    for (i = 0; i < 4; i++) {
        root[i] = (uint32_t)i;
        held_v[i] = 0;
    }
    for (i = 0; i < 4; i++) {
        /* facet i (opposite vertex i) */
        if (tet_inside(pl, w[4 + i] >> 2)) nf++;
        n = vp_dt_incident_tets(&pl->dt, w[i], star, STAR_MAX);
        if (n <= 0 || n >= STAR_MAX) return 0; /* too large to look at: not cut */
        for (k = 0; k < n && !held_v[i]; k++) held_v[i] = star[k] != t && tet_inside(pl, star[k]);
        nv += held_v[i];
    }
    for (i = 0; i < 4; i++)
        for (j = i + 1; j < 4; j++) {
            ring_t r;
            int held = 0;
            if (!held_v[i] || !held_v[j] || !ring_start(pl, &r, t, w[i], w[j])) continue;
            while (!held && ring_step(pl, &r, &broken)) held = tet_inside(pl, r.cur);
            if (broken) return 0;
            if (held) {
                uint32_t a = root[i], b = root[j];
                while (root[a] != a) a = root[a];
                while (root[b] != b) b = root[b];
                root[a] = b;
                ne++;
            }
        }
    for (i = 0; i < 4; i++) comps += held_v[i] && root[i] == (uint32_t)i;
    return nv > 0 && comps == 1 && nv - ne + nf == 1;
}

static int cut_tet(vp_planner_t *pl, uint32_t t)
{
    const uint32_t *w = vp_dt_tet(&pl->dt, t);
    uint32_t recs[4], nr = 0, nin = 0, i;
    double lim = CUT_BALL * manifold_floor(pl);
    int f;
    for (f = 0; f < 4; f++) {
        uint32_t u = w[4 + f] >> 2, fv[3], r;
        if (w[f] == VP_DT_GHOST) return 0;
        if (!tet_outside(pl, u)) { nin++; continue; }
        vp_dt_facet(&pl->dt, t, f, fv);
        r = vp_pl_frec_lookup(pl, fv);
        if (r == NONE || (pl->pool.frec[r].flags & FREC_DOUBLE) || !(pl->pool.frec[r].r <= lim)) return 0;
        recs[nr++] = r;
    }
    if (!vp_pl_cut_keeps_topology(pl, t)) return 0;
    if (!(pl->pool.nfacets + nin < pl->pool.cap_frec)) return 0;
    for (i = 0; i < nr; i++) vp_pl_frec_delete(pl, recs[i]);
    for (f = 0; f < 4; f++) {
        uint32_t u = w[4 + f] >> 2, fv[3], r;
        if (tet_outside(pl, u)) continue;
        vp_dt_facet(&pl->dt, t, f, fv);
        VP_TRY(vp_pl_frec_add_cut(pl, fv, vp_dt_point(&pl->dt, w[f]), t, &r));
    }
    for (f = 0; f < 4; f++) side_set(pl, t, f, side_get(pl, t, f) | SIDE_CUT);
    pl->st.fins_cut++;
    return 1;
}

/* Tet t is reached (outside): its cut facets towards cut tets no longer lie between the outside
 * and the inside, and go. Nothing to do before the first cut. */
VP_PL_API void vp_pl_cut_reached(vp_planner_t *pl, uint32_t t)
{
    const uint32_t *w = vp_dt_tet(&pl->dt, t);
    int f;
    if (pl->st.fins_cut == 0) return;
    for (f = 0; f < 4; f++) {
        uint32_t fv[3], r;
        if (!(side_get(pl, w[4 + f] >> 2, 0) & SIDE_CUT) || vp_pl_facet_has_ghost(pl, t, f)) continue;
        vp_dt_facet(&pl->dt, t, f, fv);
        r = vp_pl_frec_lookup(pl, fv);
        if (r != NONE && (pl->pool.frec[r].flags & FREC_CUT)) vp_pl_frec_delete(pl, r);
    }
}

/* At every edge with four facets or more (the manifold criterion has nothing left to refine
 * there): one cut, the first tet of its ring that can be. Returns how many, or a status. */
static int cut_fins(vp_planner_t *pl, const uint32_t *tab, uint32_t slots)
{
    uint32_t i, cut = 0;
    for (i = 0; i < slots; i++) {
        uint32_t a = tab[3 * i], b = tab[3 * i + 1], t;
        int broken = 0, st = 0;
        ring_t r;
        if (a == NONE || tab[3 * i + 2] < 4) continue;
        t = edge_tet(pl, a, b, slots);
        if (t == NONE || !ring_start(pl, &r, t, a, b)) continue;
        do {
            if (!tet_outside(pl, r.cur) && (st = cut_tet(pl, r.cur)) != 0) break;
        } while (ring_step(pl, &r, &broken));
        if (st < 0) return st;
        cut += (uint32_t)st;
    }
    return (int)cut;
}

/* A vertex where the inside touches itself (two cones meeting at their tips, below the floor):
 * the smaller of the inside's parts in the vertex's star (tets joined by facets at the vertex)
 * is cut off, tet by tet (cut_tet). 1 if a tet was cut; 0 when none could be, the star is too
 * large to look at here, or it is the outside that is split there (left to certify). */
static int cut_star(vp_planner_t *pl, uint32_t v)
{
    uint32_t tets[STAR_MAX], comp[STAR_MAX], queue[STAR_MAX], ncomp = 0, best = NONE, bsize = 0, cut = 0, i, k;
    int n = vp_dt_incident_tets(&pl->dt, v, tets, STAR_MAX), st;
    if (n <= 0 || n >= STAR_MAX) return 0;
    for (i = 0; i < (uint32_t)n; i++) comp[i] = tet_outside(pl, tets[i]) ? NONE : NONE - 1;
    for (i = 0; i < (uint32_t)n; i++) {
        uint32_t qh = 0, qt = 0;
        if (comp[i] != NONE - 1) continue;
        comp[i] = ncomp;
        queue[qt++] = i;
        while (qh < qt) {
            const uint32_t *w = vp_dt_tet(&pl->dt, tets[queue[qh++]]);
            int f;
            for (f = 0; f < 4; f++) {
                uint32_t u = w[4 + f] >> 2;
                if (w[f] == v) continue; /* the facet across does not hold v */
                for (k = 0; k < (uint32_t)n && tets[k] != u; k++) {}
                if (k < (uint32_t)n && comp[k] == NONE - 1) { comp[k] = ncomp; queue[qt++] = k; }
            }
        }
        if (best == NONE || qt < bsize) { best = ncomp; bsize = qt; }
        ncomp++;
    }
    if (ncomp < 2) return 0;
    for (i = 0; i < (uint32_t)n; i++)
        if (comp[i] == best) {
            if ((st = cut_tet(pl, tets[i])) < 0) return st;
            if (st == 0) break; /* what was cut stays cut: the boundary is still one */
            cut++;
        }
    return cut > 0;
}

/* 1 if the facets fl[0..n) around vertex v form one cycle: walking from facet to facet across
 * the edges at v comes back to the first after all n (every edge has two facets here) */
static int one_cycle(const vp_planner_t *pl, uint32_t v, const uint32_t *fl, uint32_t n)
{
    uint32_t steps = 1, cur = fl[0], x = NONE, start = NONE, i;
    int k;
    /* the link edge of facet cur: its two vertices other than v */
    for (k = 0; k < 3; k++) {
        uint32_t w = pl->pool.frec[cur].v[k];
        if (w == v) continue;
        if (start == NONE) start = w; else x = w;
    }
    while (x != start) {
        uint32_t next = NONE, y = NONE;
        for (i = 0; i < n && next == NONE; i++) {
            const uint32_t *fv = pl->pool.frec[fl[i]].v;
            if (fl[i] == cur || !(fv[0] == x || fv[1] == x || fv[2] == x)) continue;
            next = fl[i];
            for (k = 0; k < 3; k++)
                if (fv[k] != v && fv[k] != x) y = fv[k];
        }
        if (next == NONE || y == NONE || ++steps > n) return 1; /* open: the edge test's case */
        cur = next;
        x = y;
    }
    return steps == n;
}

/* The manifold criterion at vertices: where every edge has its two facets but the facets
 * around a vertex form two or more cycles (cones meeting at a point, as where a fin or a gap
 * thinner than the samples' spacing is met), the largest facet at the vertex is refined, down
 * to the same floor. The facets of each vertex are listed by a counting sort in the scratch. */
static int refine_at_pinches(vp_planner_t *pl)
{
    uint32_t nv = pl->dt.nvert, *first = pl->pool.astar, *list, i, v, refined = 0;
    double floor = manifold_floor(pl);
    if ((size_t)nv + 1u + 3u * (size_t)pl->pool.nfrec > pl->pool.cap_astar) return 0; /* left to certify */
    list = first + nv + 1;
    memset(first, 0, ((size_t)nv + 1u) * sizeof *first);
    for (i = 0; i < pl->pool.nfrec; i++)
        if (frec_in_mesh(&pl->pool.frec[i])) {
            first[pl->pool.frec[i].v[0] + 1]++; first[pl->pool.frec[i].v[1] + 1]++; first[pl->pool.frec[i].v[2] + 1]++;
        }
    for (v = 0; v < nv; v++) first[v + 1] += first[v];
    /* fill: first[v] runs to the end of v's list, which is then where v + 1's begins */
    for (i = 0; i < pl->pool.nfrec; i++)
        if (frec_in_mesh(&pl->pool.frec[i])) {
            int k;
            for (k = 0; k < 3; k++) list[first[pl->pool.frec[i].v[k]]++] = i;
        }
    for (v = 0; v < nv; v++) {
        uint32_t b = v == 0 ? 0 : first[v - 1], n = first[v] - b, best = NONE;
        if (n < 3 || one_cycle(pl, v, list + b, n)) continue;
        for (i = b; i < first[v]; i++) {
            const vp_frec_t *f = &pl->pool.frec[list[i]];
            if (f->flags & FREC_STUCK) continue;
            if (best == NONE || f->r > pl->pool.frec[best].r) best = list[i];
        }
        if (best != NONE && pl->pool.frec[best].heap != NONE) continue;
        if (best == NONE || !(pl->pool.frec[best].r > floor)) {
            /* at the floor: cut (one vertex per pass, the lists above go stale) */
            int st;
            if (refined > 0 || (st = cut_star(pl, v)) == 0) continue;
            if (st > 0) pl->close.mark = 0;
            return st;
        }
        VP_TRY(vp_pl_heap_push(pl, best));
        refined++;
    }
    pl->st.manifold_refinements += refined;
    return (int)refined;
}

/* Parity for the facets hit once: a facet whose both tets are outside (reached, or cut) is not
 * on the boundary of the inside, like one hit from both ends; it is one whose other end was
 * reached another way (an edge between two known-free ends is not probed). Marked afresh at
 * every closing pass (FREC_OUTOUT), which is also where the mesh is read at the end. */
static void mark_outside_pairs(vp_planner_t *pl)
{
    uint32_t k;
    for (k = 0; k < pl->pool.nfrec; k++) {
        vp_frec_t *f = &pl->pool.frec[k];
        uint32_t t;
        int fi;
        if (f->v[0] == NONE) continue;
        f->flags &= ~FREC_OUTOUT;
        if (f->flags & FREC_DOUBLE) continue;
        t = vp_pl_find_facet(pl, f->v, &fi, 0);
        if (t != NONE && tet_outside(pl, t) && tet_outside(pl, vp_dt_tet(&pl->dt, t)[4 + fi] >> 2))
            f->flags |= FREC_OUTOUT;
    }
}

#if VP_PL_TUBES
/* The last resort before detect_access in full: with nothing left to probe at the holes, the
 * sides round the odd edges that aims from aside left unseen (or gave up on: the aims' budget)
 * are aimed at once more, now with lines through their far vertex alone too (close.far_lines,
 * aim.c): a torus's hole at its inner equator, whose Voronoi edges run from the inner side into
 * the hole and whose tilted lines all come through the tube. far_lines is set the first time;
 * every aim after it has those lines. Taken again only when at most half as many edges are odd
 * as the last time (close.resort_odd): a deep cavity, where each costs thousands of probes and
 * closes a few edges, is not taken through it again and again. Returns the number of sides
 * queued, or a negative status. */
VP_PL_API int vp_pl_aim_far_vertices(vp_planner_t *pl, const uint32_t *tab, uint32_t slots)
{
    uint32_t i, pushed = 0, odd;
    if (!(pl->cfg.clearance > 0.0) || pl->tube.on || (pl->cfg.flags & VP_PLAN_NO_AIM)) return 0;
    odd = odd_edges(tab, slots);
    if (pl->close.far_lines && 2u * odd > pl->close.resort_odd) return 0;
    pl->close.resort_odd = odd;
    pl->st.last_resorts++;
    for (i = 0; i < slots; i++) {
        uint32_t a = tab[3 * i], b = tab[3 * i + 1], t;
        ring_t r;
        int broken = 0;
        if (a == NONE || tab[3 * i + 2] == 2) continue;
        t = edge_tet(pl, a, b, slots);
        if (t == NONE || !ring_start(pl, &r, t, a, b)) continue;
        do {
            int f;
            if (!tet_active(pl, r.cur)) continue;
            for (f = 0; f < 4; f++) {
                unsigned s = side_get(pl, r.cur, f);
                edgegeom_t g;
                if ((s & (SIDE_BLOCKED | SIDE_DEGEN | SIDE_RETRIED | SIDE_QUEUED)) != (SIDE_BLOCKED | SIDE_RETRIED) ||
                    (s & SIDE_MASK) != SIDE_UNKNOWN || vp_pl_facet_has_ghost(pl, r.cur, f))
                    continue;
                /* only a side whose edge ends at its far vertex in Omega gets such lines */
                if (vp_pl_edge_geom(pl, r.cur, f, &g) != VP_OK || !g.a_inside || !(g.t1 > 0.0) || g.t1 < g.len)
                    continue;
                side_set(pl, r.cur, f, s & ~SIDE_BLOCKED);
                VP_TRY(vp_pl_task_push(pl, r.cur, f, 1));
                pushed++;
            }
        } while (ring_step(pl, &r, &broken));
    }
    vp_pl_aim_last_resort(pl, pushed);
    pl->st.far_line_sides += pushed;
    /* the next pass is a full one even if these resolve without a probe: detect_access in full
     * stays what follows them */
    if (pushed > 0) pl->close.mark = 0;
    return (int)pushed;
}
#endif

/* Body mode: detect_access in full from every active vertex found nothing at a hole in any scan
 * measured (the enclosed torus at eps 2: 7,596 probes; the bear at eps 2: 9,516; the rpi4's 36 mm
 * torus at eps 2: 5,872; genus5 in host-sim): away from the holes a line probed from dOmega
 * changes nothing there, and the rings round the odd edges have been probed already
 * (probe_around_edge). Only the tets with a vertex of an odd edge are explored then. The odd
 * edges' vertices, sorted, go past the edge table in the scratch; their number, or NONE when
 * they do not fit (then every active tet). */
#if VP_PL_TUBES
VP_PL_API uint32_t vp_pl_hole_vertices(const vp_planner_t *pl, const uint32_t *tab, uint32_t slots)
{
    uint32_t *vs = pl->pool.astar + 3u * slots, cap = pl->pool.cap_astar - 3u * slots, i, n = 0, k, j;
    if (cap > HOLE_VERTICES_MAX) cap = HOLE_VERTICES_MAX;
    for (i = 0; i < slots; i++) {
        if (tab[3 * i] == NONE || tab[3 * i + 2] == 2) continue;
        for (k = 0; k < 2; k++) {
            uint32_t v = tab[3 * i + k];
            /* insertion into the sorted list, once */
            for (j = n; j > 0 && vs[j - 1] > v; j--) {}
            if (j > 0 && vs[j - 1] == v) continue;
            if (n >= cap) return NONE;
            memmove(vs + j + 1, vs + j, (size_t)(n - j) * sizeof *vs);
            vs[j] = v;
            n++;
        }
    }
    return n;
}
#endif

VP_PL_API int vp_pl_has_vertex_in(const vp_planner_t *pl, uint32_t t, const uint32_t *vs, uint32_t n)
{
    const uint32_t *w = vp_dt_tet(&pl->dt, t);
    int k;
    for (k = 0; k < 4; k++) {
        uint32_t lo = 0, hi = n;
        while (lo < hi) {
            uint32_t mid = lo + (hi - lo) / 2;
            if (vs[mid] < w[k]) lo = mid + 1;
            else hi = mid;
        }
        if (lo < n && vs[lo] == w[k]) return 1;
    }
    return 0;
}

VP_PL_API int vp_pl_close_holes(vp_planner_t *pl, int refine_only)
{
    /* edge counts in a scratch hash: 3 words per slot (a, b, count) */
    uint32_t slots = 1, i, *tab = pl->pool.astar, pushed = 0, holes = 0;
    /* refine_only follows a full pass with nothing probed, inserted or cut since: the marks hold */
    if (!refine_only) mark_outside_pairs(pl);
    while (slots < 4u * pl->pool.nfacets + 16u) slots <<= 1;
    if (3u * slots > pl->pool.cap_astar) return 0; /* too big to check here: left to certify */
    for (i = 0; i < 3u * slots; i++) tab[i] = NONE;
    for (i = 0; i < pl->pool.nfrec; i++) {
        const vp_frec_t *f = &pl->pool.frec[i];
        int e;
        if (!frec_in_mesh(f)) continue;
        for (e = 0; e < 3; e++) {
            uint32_t a = f->v[e], b = f->v[(e + 1) % 3], h;
            if (a > b) { uint32_t t = a; a = b; b = t; }
            h = (uint32_t)(((uint64_t)a * 0x9E3779B97F4A7C15ull ^ b) * 0xBF58476D1CE4E5B9ull >> 40) & (slots - 1);
            while (tab[3 * h] != NONE && (tab[3 * h] != a || tab[3 * h + 1] != b)) h = (h + 1) & (slots - 1);
            if (tab[3 * h] == NONE) { tab[3 * h] = a; tab[3 * h + 1] = b; tab[3 * h + 2] = 0; }
            tab[3 * h + 2]++;
        }
    }
    if (refine_only) {
        /* the tasks the full pass pushed all resolved without a probe: refine at the open
         * edges; at the floor with the last few holes left, cut at the fins as a full pass
         * that pushed none would (with many left, cutting and refining feed each other on a
         * knife edge sharper than the floor resolves: measured at 20 degrees) */
        int r = refine_at_edges(pl, tab, slots);
        uint32_t odd;
        if (r != 0) return r;
        odd = odd_edges(tab, slots);
        if (odd <= LAST_HOLES && (r = cut_fins(pl, tab, slots)) > 0) pl->close.mark = 0;
#if VP_PL_TUBES
        /* nothing to probe at the holes either way: closing's last resort, as after a full
         * pass that pushed nothing */
        if (r == 0 && odd > 0) r = vp_pl_aim_far_vertices(pl, tab, slots);
#endif
        return r;
    }
    for (i = 0; i < slots; i++) {
        uint32_t a = tab[3 * i], b = tab[3 * i + 1], t;
        int n;
        if (a == NONE || tab[3 * i + 2] == 2) continue;
        t = edge_tet(pl, a, b, slots);
        if (t == NONE) continue;
        n = probe_around_edge(pl, t, a, b);
        if (n < 0) return n;
        pushed += (uint32_t)n;
        holes++;
    }
    if (holes == 0) return refine_at_pinches(pl);
    if (holes > 0 && pushed == 0) {
        /* the manifold criterion first: refining at the open edges is local; the exhaustive
         * detect_access below probes every edge of every active vertex */
        int r = refine_at_edges(pl, tab, slots);
        if (r != 0) return r;
        if ((r = cut_fins(pl, tab, slots)) != 0) {
            if (r < 0) return r;
            pl->close.mark = 0; /* count the edges again */
            return r;
        }
    }
#if VP_PL_TUBES
    if (holes > 0 && pushed == 0) {
        int r = vp_pl_aim_far_vertices(pl, tab, slots);
        if (r != 0) return r;
    }
#endif
    if (holes > 0 && pushed == 0 && !pl->close.exhaustive) {
        /* no active vertex next to the holes: detect_access in full from every active vertex
         * until the next insertion (in body mode from the holes' stars alone) */
        uint32_t tt, nv = NONE;
#if VP_PL_TUBES
        if (pl->cfg.clearance > 0.0 && !pl->tube.on) nv = vp_pl_hole_vertices(pl, tab, slots);
#endif
        pl->close.exhaustive = 1;
        pl->st.escalations++;
        for (tt = 0; tt < pl->dt.ntet_slots; tt++)
            if (vp_dt_alive(&pl->dt, tt) && tet_active(pl, tt) &&
                (nv == NONE || vp_pl_has_vertex_in(pl, tt, tab + 3u * slots, nv))) {
                VP_TRY(vp_pl_explore(pl, tt));
            }
        return (int)pl->pool.ntask;
    }
    return (int)pushed;
}


/* ---------- H2: a vertex on every component ---------- */

/* 1 if point o is enclosed by the mesh: odd number of facets crossed by a ray from o. The
 * ray's direction is fixed and irrational-looking so that it meets no edge in practice. */
static int mesh_encloses(const vp_planner_t *pl, const double *o)
{
    static const double dir[3] = { 0.4469983318002897, 0.5384104567341229, 0.7144217014264011 };
    uint32_t i, crossings = 0;
    for (i = 0; i < pl->pool.nfrec; i++) {
        const vp_frec_t *f = &pl->pool.frec[i];
        const double *a, *b, *c;
        double e1[3], e2[3], p[3], q[3], t[3], det, u, v, w;
        if (!frec_in_mesh(f)) continue;
        a = vp_dt_point(&pl->dt, f->v[0]);
        b = vp_dt_point(&pl->dt, f->v[1]);
        c = vp_dt_point(&pl->dt, f->v[2]);
        vp_sub3(e1, b, a);
        vp_sub3(e2, c, a);
        vp_cross3(p, dir, e2);
        det = vp_dot3(e1, p);
        if (det == 0.0) continue;
        vp_sub3(t, o, a);
        u = vp_dot3(t, p) / det;
        if (u < 0.0 || u > 1.0) continue;
        vp_cross3(q, t, e1);
        v = vp_dot3(dir, q) / det;
        if (v < 0.0 || u + v > 1.0) continue;
        w = vp_dot3(e2, q) / det;
        if (w > 0.0) crossings++;
    }
    return (int)(crossings & 1u);
}

/* Directions tried, one after the other, to find a component the seeds missed (and a seed
 * whose way in met a surface the rangefinder did not see: seed.c). */
VP_PL_API void vp_pl_reseed_dir(uint32_t attempt, double *d)
{
    static const signed char D[26][3] = {
        { 0, 0, 1 }, { 0, 0, -1 }, { 1, 0, 0 }, { -1, 0, 0 }, { 0, 1, 0 }, { 0, -1, 0 },
        { 1, 1, 1 }, { -1, -1, -1 }, { 1, -1, 1 }, { -1, 1, -1 }, { 1, 1, -1 }, { -1, -1, 1 },
        { -1, 1, 1 }, { 1, -1, -1 }, { 1, 1, 0 }, { -1, -1, 0 }, { 1, -1, 0 }, { -1, 1, 0 },
        { 1, 0, 1 }, { -1, 0, -1 }, { 1, 0, -1 }, { -1, 0, 1 }, { 0, 1, 1 }, { 0, -1, -1 },
        { 0, 1, -1 }, { 0, -1, 1 } };
    d[0] = D[attempt % 26][0]; d[1] = D[attempt % 26][1]; d[2] = D[attempt % 26][2];
    vp_normalize3(d);
}

#define RESEED_TRIES 26u

/* After the mesh closed: every o_i must be enclosed by it (H2). A missed component gets a new
 * sample: a probe towards o_i from another side of Omega, inserted like a ball centre. */
VP_PL_API int vp_pl_check_components(vp_planner_t *pl)
{
    uint32_t i;
    for (i = 0; i < pl->cfg.ninterior; i++) {
        const double *o = pl->cfg.interior[i];
        double d[3], q[3], te;
        int k;
        if (pl->close.h2_done & (1u << i)) continue;
        if (mesh_encloses(pl, o)) { pl->close.h2_done |= 1u << i; continue; }
        if (pl->close.h2_tries[i] >= RESEED_TRIES) continue; /* reported: not found */
        vp_pl_reseed_dir(pl->close.h2_tries[i]++, d);
        te = vp_pl_omega_exit(&pl->cfg, o, d);
        for (k = 0; k < 3; k++) q[k] = o[k] + te * d[k];
        k = vp_pl_plan_route(pl, NONE, q);
        if (k < 0) return k;
        if (VP_PL_CONTACTS && k == PL_UNREACHABLE) { pl->close.h2_tries[i] = RESEED_TRIES; continue; }
        for (k = 0; k < 3; k++) d[k] = -d[k];
        pl->phase = PH_RESEED;
        return vp_pl_seed_issue(pl, d, te);
    }
    pl->phase = PH_DONE;
    return VP_OK;
}

VP_PL_API int vp_pl_reseed_feed(vp_planner_t *pl, const vp_probe_result_t *res)
{
    double h[3];
    uint32_t v;
    int k, st;
    pl->phase = PH_COMPONENTS;
    if (res->hit != 1) {
        /* a dropout or the end of the rangefinder's reach: probe again, or walk on */
        int w = res->hit == VP_PROBE_TOO_CLOSE ? 0 : vp_pl_seed_miss_on(pl);
        if (w < 0) return w;
        if (w) pl->phase = PH_RESEED;
        return VP_OK;
    }
    for (k = 0; k < 3; k++) h[k] = pl->probe.origin[k] + res->dist * pl->probe.dir[k];
    if (!vp_pl_pools_have_room(pl)) return VP_ENOMEM;
    st = vp_dt_insert(&pl->dt, h, VP_DT_NONE, &v);
    if (st == VP_EDUP) return VP_OK;
    if (st != VP_OK) return st;
    pl->st.insertions++;
    pl->st.reseeds++;
    pl->close.exhaustive = 0;
    st = vp_pl_after_insert(pl, v);
    pl->phase = PH_RUN;
    return st;
}
