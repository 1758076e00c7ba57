/* vp_machine — see vp_machine.h. */
#include <math.h>
#include <string.h>
#include "vp_machine.h"
#include "vp_device.h"
#include "vp_status.h"
#include "vp_vec3.h"

static void vp_machine_sync(vp_machine_t *m)
{
    double u[VP_STEP_MAX_AXES];
    vp_step_position(&m->step, u);
    memcpy(m->j, u, sizeof m->j);
}

int vp_machine_init(vp_machine_t *m, const vp_kin_config_t *kc, const vp_step_config_t *sc, const vp_io_t *io,
                    const vp_cam_t *cam, const vp_tri_model_t *tri, const vp_machine_config_t *mc)
{
    if (!m || !kc || !sc || !io || !cam || !tri || sc->naxes != VP_KIN_JOINTS) return VP_EINVAL;
    memset(m, 0, sizeof *m);
    VP_TRY(vp_kin_init(&m->kin, kc));
    VP_TRY(vp_step_init(&m->step, sc, io));
    m->io = *io;
    m->cam = *cam;
    m->tri = *tri;
    if (mc) m->cfg = *mc;
    if (m->cfg.timeout_ms <= 0) m->cfg.timeout_ms = 1000;
    if (m->cfg.latency_frames < 0) return VP_EINVAL;
    if (m->cfg.line) {
        /* a line laser: a laser-off / laser-on pair per probe, every column's point kept */
        int w = m->cfg.line_model.cam.width, step;
        if (!m->cfg.use_laser_line || m->cfg.single_frame || w < 1) return VP_EINVAL;
        if (m->cfg.line_cfg.column_step <= 0) m->cfg.line_cfg.column_step = (w + VP_MACHINE_MAX_LINE - 1) / VP_MACHINE_MAX_LINE;
        step = m->cfg.line_cfg.column_step;
        if ((w + step - 1) / step > VP_MACHINE_MAX_LINE) return VP_EINVAL;
        if (!(m->cfg.line_gap_cols > 0)) m->cfg.line_gap_cols = 3.0;
    }
    m->seen_seq = -1;
    m->last.seq = m->last.seq_off = m->last.seq_mark = m->last.seq_confirm = -1;
    vp_machine_sync(m);
    return VP_OK;
}

int vp_machine_home(vp_machine_t *m)
{
    int rc = vp_step_home(&m->step);
    m->touched = 0;
    vp_machine_sync(m);
    return rc;
}

void vp_machine_beam(const vp_machine_t *m, double origin[3], double dir[3])
{
    vp_kin_forward(&m->kin, m->j, origin, dir);
}

int vp_machine_goto(vp_machine_t *m, const double p[3])
{
    double t[VP_KIN_JOINTS], j0[VP_KIN_JOINTS], o0[3], o1[3], d[3];
    vp_step_contact_t c;
    int rc, k;
    VP_TRY(vp_kin_move(&m->kin, m->j, p, t));
    vp_machine_beam(m, o0, d);
    memcpy(j0, m->j, sizeof j0);
    m->touched = 0;                  /* the host's own move: the next MOVE starts from here */
    m->host_touched = 0;
    memset(&c, 0, sizeof c);
    rc = m->cfg.contact ? vp_step_move_watch(&m->step, t, 1, VP_STEP_WATCH_STOP, &c) : vp_step_move(&m->step, t);
    vp_machine_sync(m);
    vp_machine_beam(m, o1, d);
    m->st.travel += vp_dist3(o0, o1);
    if (rc != VP_OK || !m->cfg.contact || !c.hit) return rc;
    /* something where the host assumed free space: where the switch closed (latched joints), then
     * straight back to where the move began, the switch opening on the way */
    {
        double jl[VP_KIN_JOINTS], ol[3];
        for (k = 0; k < VP_KIN_JOINTS; k++) jl[k] = c.latch[k] / m->step.cfg.axis[k].steps_per_unit;
        vp_kin_forward(&m->kin, jl, ol, d);
        m->host_touched = 1;
        m->host_touch_at = c.at_start ? 0.0 : vp_dist3(o0, ol);
        m->host_overtravel = vp_dist3(ol, o1);
        memcpy(m->host_rest, m->j, sizeof m->host_rest);
    }
    rc = vp_step_move_watch(&m->step, j0, 1, VP_STEP_WATCH_RELEASE, &c);
    vp_machine_sync(m);
    vp_machine_beam(m, o0, d);
    m->st.travel += vp_dist3(o1, o0);
    return rc != VP_OK ? rc : VP_EABORT;
}

/* Joints j as the step generator will have them (rounded to its steps, as vp_machine_sync). */
static void vp_machine_as_stepped(const vp_machine_t *m, const double *j, double *q)
{
    int k;
    for (k = 0; k < VP_KIN_JOINTS; k++) q[k] = vp_step_to_steps(&m->step, k, j[k]) / m->step.cfg.axis[k].steps_per_unit;
}

/* The touch that stopped cmd (c), the head now at rest with its laser origin at o1: the
 * trigger is the latched joints through the forward kinematics, along the commanded line. A
 * watched path's (`way`, its pieces, the touched MOVE's from `first` on, from joints j0; NULL for
 * a MOVE alone) way back retraces what the head travelled: the waypoints its stop passed, the
 * latched joints, the touched MOVE's own waypoints before them, back to j0. */
static void vp_machine_take_touch(vp_machine_t *m, const vp_cmd_t *cmd, const vp_step_contact_t *c, const double *o1,
                                  const double (*way)[VP_KIN_JOINTS], int first, const double *j0)
{
    double jl[VP_KIN_JOINTS], d[3], seg[3], len, at = 0;
    int k;
    for (k = 0; k < VP_KIN_JOINTS; k++) jl[k] = c->latch[k] / m->step.cfg.axis[k].steps_per_unit;
    vp_kin_forward(&m->kin, jl, m->last.contact_point, d);
    for (k = 0; k < 3; k++) seg[k] = cmd->to[k] - cmd->from[k];
    len = vp_norm3(seg);
    if (len > 0 && !c->at_start) {
        for (k = 0; k < 3; k++) at += (m->last.contact_point[k] - cmd->from[k]) * seg[k] / len;
        if (at < 0) at = 0;
        if (at > len) at = len;
    }
    m->last.contact = 1;
    m->last.contact_at = at;
    m->last.overtravel = vp_dist3(m->last.contact_point, o1);
    m->touched = 1;
    m->back_n = 0;
    memcpy(m->touch_from, cmd->from, sizeof m->touch_from);
    if (way && c->rest_way - first < VP_MACHINE_BACK - 2) {
        int w;
        for (w = c->rest_way - 1; w >= c->way; w--) memcpy(m->back_way[m->back_n++], way[w], sizeof m->back_way[0]);
        m->back_latch = m->back_n;
        memcpy(m->back_way[m->back_n++], jl, sizeof jl);
        for (w = c->way - 1; w >= first; w--) memcpy(m->back_way[m->back_n++], way[w], sizeof m->back_way[0]);
        memcpy(m->back_way[m->back_n++], j0, sizeof m->back_way[0]);
    }
    memcpy(m->touch_point, m->last.contact_point, sizeof m->touch_point);
    for (k = 0; k < 3; k++) m->touch_dir[k] = len > 0 ? seg[k] / len : 0;
    m->contacts++;
}

/* How far the laser origin (where the contact switch is) can travel along a straight piece of
 * the joints from ja to jb, as stepped. Along it the origin O = gantry + arm(pan, tilt) moves at
 * O' = (O(jb) - O(ja)) + the change of the arm's derivative, which is at most its second
 * derivative's bound times the turn: the arm turns about the pan axis within |tilt_offset| +
 * |laser_offset| (rp) and about the tilt axis within |laser_offset| (rl), so |O'| <= |O(jb) -
 * O(ja)| + (rp |dpan| + rl |dtilt|) (|dpan| + |dtilt|), in radians. Exact for a MOVE (pan and
 * tilt stay put); a MOVE turning on the way keeps the origin near its line, and the bound sees
 * that. */
static double vp_machine_piece_len(const vp_machine_t *m, const double *ja, const double *jb)
{
    const double deg = 0.017453292519943295;
    double qa[VP_KIN_JOINTS], qb[VP_KIN_JOINTS], oa[3], ob[3], d[3], dp, dt;
    double rl = vp_norm3(m->kin.cfg.laser_offset), rp = vp_norm3(m->kin.cfg.tilt_offset) + rl;
    vp_machine_as_stepped(m, ja, qa);
    vp_machine_as_stepped(m, jb, qb);
    vp_kin_forward(&m->kin, qa, oa, d);
    vp_kin_forward(&m->kin, qb, ob, d);
    dp = fabs(qb[VP_J_PAN] - qa[VP_J_PAN]) * deg;
    dt = fabs(qb[VP_J_TILT] - qa[VP_J_TILT]) * deg;
    return vp_dist3(oa, ob) + (rp * dp + rl * dt) * (dp + dt);
}

/* The pieces' lengths (vp_machine_piece_len) of a path from joints j0 through way[0 .. n) */
static void vp_machine_piece_lens(const vp_machine_t *m, const double *j0, const double (*way)[VP_KIN_JOINTS], int n,
                                  double *lens)
{
    int w;
    for (w = 0; w < n; w++) lens[w] = vp_machine_piece_len(m, w ? way[w - 1] : j0, way[w]);
}

/* Pieces from the joints where the head stands, watched for a touch that passes their
 * waypoints where its stop stays within cfg.contact_stop (vp_step_move_touch). */
static int vp_machine_touch_pieces(vp_machine_t *m, const double (*way)[VP_KIN_JOINTS], int n, vp_step_contact_t *c)
{
    double lens[VP_MACHINE_PATH_WAY];
    if (n > VP_MACHINE_PATH_WAY) return VP_EINVAL;
    vp_machine_piece_lens(m, m->j, way, n, lens);
    return vp_step_move_touch(&m->step, &way[0][0], n, VP_STEP_WATCH_STOP, lens, m->cfg.contact_stop, c);
}

/* 1 when a touch's stop on every piece from j0 stays within cfg.contact_stop */
static int vp_machine_touch_fits(const vp_machine_t *m, const double *j0, const double (*way)[VP_KIN_JOINTS], int n)
{
    double lens[VP_MACHINE_PATH_WAY];
    if (n > VP_MACHINE_PATH_WAY) return 0;
    vp_machine_piece_lens(m, j0, way, n, lens);
    return vp_step_touch_fits(&m->step, j0, &way[0][0], n, lens, m->cfg.contact_stop);
}

/* A MOVE watching the contact switch (see vp_machine.h). */
static int vp_machine_touch_move(vp_machine_t *m, const vp_cmd_t *cmd)
{
    double way[VP_MACHINE_BACK + 1][VP_KIN_JOINTS], o0[3], o1[3], d[3];
    vp_step_contact_t c;
    int k, n = 1, watch = VP_STEP_WATCH_STOP, rc;
    for (k = 0; k < 3; k++) if (!isfinite(cmd->from[k]) || !isfinite(cmd->to[k])) return VP_EINVAL;
    if (m->touched) {
        /* backing off a contact: never further along the touching move's direction; after a
         * watched path's touch, back along its pieces */
        double adv = 0;
        for (k = 0; k < 3; k++) adv += (cmd->to[k] - m->touch_point[k]) * m->touch_dir[k];
        if (adv > 1e-6) return VP_ESTATE;
        watch = VP_STEP_WATCH_RELEASE;
        if (m->back_n > 0) {
            /* the pieces retraced to where the touched MOVE started: all of them when that is
             * where this MOVE goes (the planner's way back), else to the latch, then on */
            int to_start = 1;
            for (k = 0; k < 3; k++) if (fabs(cmd->to[k] - m->touch_from[k]) > 1e-9) to_start = 0;
            n = to_start ? m->back_n : m->back_latch + 2;
            memcpy(way, m->back_way, (size_t)(to_start ? n : n - 1) * sizeof way[0]);
            if (to_start) goto run;
        } else {
            VP_TRY(vp_kin_move(&m->kin, m->j, m->touch_point, way[0]));
            n = 2;
        }
    }
    VP_TRY(vp_kin_move(&m->kin, n >= 2 ? way[n - 2] : m->j, cmd->to, way[n - 1]));
run:
    m->st.moves++;
    vp_machine_beam(m, o0, d);
    rc = vp_step_move_watch(&m->step, &way[0][0], n, watch, &c);
    vp_machine_sync(m);
    vp_machine_beam(m, o1, d);
    m->st.travel += vp_dist3(o0, o1);
    if (rc < 0) return rc;
    m->touched = 0;
    m->back_n = 0;
    if (c.hit) vp_machine_take_touch(m, cmd, &c, o1, NULL, 0, NULL);
    return VP_OK;
}

/* A MOVE keeps the head's orientation, so the carriage sits at a fixed offset from the laser
 * origin all along the line. When that offset puts the carriage outside its travel at the
 * MOVE's end, the head first turns about the laser origin where it stands (the aim's path: the
 * origin stays put) to the orientation nearest in pan and tilt, of the 26 towards a cube's faces,
 * edges and corners, that keeps both ends within travel (the travel is a box: the line between
 * is too). VP_ERANGE when none does. */
static int vp_machine_turn_for(vp_machine_t *m, const double to[3])
{
    double o[3], d[3], jt[VP_KIN_JOINTS], best[VP_KIN_JOINTS], j1[VP_KIN_JOINTS], cost, bcost = HUGE_VAL;
    int i, k, n, rc;
    vp_machine_beam(m, o, d);
    for (i = 0; i < 27; i++) {
        double u[3] = { (double)(i % 3 - 1), (double)((i / 3) % 3 - 1), (double)(i / 9 - 1) };
        double l = vp_norm3(u);
        if (i == 13) continue;
        for (k = 0; k < 3; k++) u[k] /= l;
        if (vp_kin_aim(&m->kin, m->j, o, u, jt) != VP_OK || vp_kin_move(&m->kin, jt, to, j1) != VP_OK) continue;
        cost = fabs(jt[VP_J_PAN] - m->j[VP_J_PAN]) + fabs(jt[VP_J_TILT] - m->j[VP_J_TILT]);
        if (cost < bcost) { bcost = cost; memcpy(best, jt, sizeof best); }
    }
    if (!(bcost < HUGE_VAL)) return VP_ERANGE;
    n = vp_kin_aim_path(&m->kin, m->j, best, m->way, VP_MACHINE_MAX_WAY);
    if (n < 0) return n;
    rc = vp_step_move_path(&m->step, &m->way[0][0], n);
    vp_machine_sync(m);
    m->turn_n = n;
    if (rc >= 0) m->st.turns++;
    return rc < 0 ? rc : VP_OK;
}

/* A MOVE that names the PROBE it leads to (turn_on_move): the head turns on the way, by this
 * MOVE's share of the way left (its length over its own plus cmd->range), towards the
 * orientation the PROBE will aim from (vp_kin_aim at the route's end: the PROBE's origin is the
 * last MOVE's target). The path is vp_kin_aim_path's: the laser origin along the line, pan and
 * tilt in step, pieces short enough that the origin stays within origin_tol of the line, every
 * piece's end within travel (the travel is a box: the pieces between are too). Plans it from
 * joints j0 into way (VP_MACHINE_MAX_WAY): the pieces, or 0 when the MOVE is to be made straight
 * (no such PROBE named, or the turn does not fit). */
static int vp_machine_turning_plan(const vp_machine_t *m, const double *j0, const vp_cmd_t *cmd,
                                   double (*way)[VP_KIN_JOINTS])
{
    double tgt[VP_KIN_JOINTS], mid[VP_KIN_JOINTS], end[VP_KIN_JOINTS], len, f;
    int n, w;
    if (!m->cfg.turn_on_move || !vp_machine_paths_allowed(m) || m->touched || !isfinite(cmd->range) ||
        !(cmd->range >= 0) || !(fabs(vp_norm3(cmd->dir) - 1) <= 1e-9))
        return 0;
    if (vp_kin_aim(&m->kin, j0, cmd->to, cmd->dir, tgt) != VP_OK) return 0;
    len = vp_dist3(cmd->from, cmd->to);
    f = len + cmd->range > 0 ? len / (len + cmd->range) : 1.0;
    memcpy(mid, j0, sizeof mid);
    mid[VP_J_PAN] = j0[VP_J_PAN] + f * (tgt[VP_J_PAN] - j0[VP_J_PAN]);
    mid[VP_J_TILT] = j0[VP_J_TILT] + f * (tgt[VP_J_TILT] - j0[VP_J_TILT]);
    if (f >= 1.0) memcpy(mid, tgt, sizeof mid);
    if (mid[VP_J_PAN] == j0[VP_J_PAN] && mid[VP_J_TILT] == j0[VP_J_TILT]) return 0; /* nothing to turn */
    if (vp_kin_move(&m->kin, mid, cmd->to, end) != VP_OK) return 0;
    n = vp_kin_aim_path(&m->kin, j0, end, way, VP_MACHINE_MAX_WAY);
    if (n < 1) return 0;
    for (w = 0; w < n; w++)
        if (!vp_kin_in_travel(&m->kin, way[w])) return 0;
    /* a contact switch: only where a touch on every piece stops within its overtravel */
    if (m->cfg.contact && !vp_machine_touch_fits(m, j0, (const double (*)[VP_KIN_JOINTS])way, n)) return 0;
    return n;
}

/* The MOVE turning on its way (vp_machine_turning_plan): 1 when it moved so, 0 when it is to be
 * made straight. */
static int vp_machine_move_turning(vp_machine_t *m, const vp_cmd_t *cmd)
{
    double o0[3], o1[3], d[3], j0[VP_KIN_JOINTS];
    vp_step_contact_t c;
    int n = vp_machine_turning_plan(m, m->j, cmd, m->way), rc;
    if (n < 1) return 0;
    memcpy(j0, m->j, sizeof j0);
    m->st.moves++;
    vp_machine_beam(m, o0, d);
    c.hit = 0;
    rc = m->cfg.contact ? vp_machine_touch_pieces(m, (const double (*)[VP_KIN_JOINTS])m->way, n, &c)
                        : vp_step_move_path(&m->step, &m->way[0][0], n);
    vp_machine_sync(m);
    vp_machine_beam(m, o1, d);
    m->st.travel += vp_dist3(o0, o1);
    m->move_n = n;
    if (rc >= 0) m->st.moves_turning++;
    if (rc >= 0 && c.hit) {
        vp_machine_take_touch(m, cmd, &c, o1, (const double (*)[VP_KIN_JOINTS])m->way, 0, j0);
        /* the pieces it took: up to where the stop ended */
        memcpy(m->way[c.rest_way], m->j, sizeof m->j);
        m->move_n = c.rest_way + 1;
    }
    return rc < 0 ? rc : 1;
}

/* A MOVE made alone at the start of a path (it needs the head turned first): its record. */
static int vp_machine_path_alone(vp_machine_t *m, const vp_cmd_t *cmd)
{
    vp_machine_path_move_t *pm = &m->path[0];
    unsigned long turns = m->st.turns;
    int rc;
    memcpy(pm->j0, m->j, sizeof pm->j0);
    rc = vp_machine_move(m, cmd);
    if (rc < 0) return rc;
    pm->first = 0;
    pm->n = pm->turn_n = 0;
    pm->turning = m->move_n > 0;
    if (m->move_n > 0) {
        memcpy(m->path_way, m->way, (size_t)m->move_n * sizeof m->way[0]);
        pm->n = m->move_n;
    } else {
        if (m->st.turns != turns && m->turn_n > 0) {
            memcpy(m->path_way, m->way, (size_t)m->turn_n * sizeof m->way[0]);
            pm->n = pm->turn_n = m->turn_n;
        }
        memcpy(m->path_way[pm->n++], m->j, sizeof m->j);
    }
    memcpy(pm->j1, m->j, sizeof pm->j1);
    return VP_OK;
}

/* a path holds what the scan loop gives at once, and a MOVE made alone its turn and itself */
typedef char vp_machine_path_fits_loop[VP_MACHINE_PATH_MOVES >= VP_DEV_PATH ? 1 : -1];
typedef char vp_machine_path_fits_move[VP_MACHINE_PATH_WAY >= VP_MACHINE_MAX_WAY + 1 ? 1 : -1];

int vp_machine_paths_allowed(const vp_machine_t *m)
{
    return !m->cfg.contact || m->cfg.contact_stop > 0;
}

int vp_machine_move_path(vp_machine_t *m, const vp_cmd_t *cmds, int n, int *done)
{
    double jc[VP_KIN_JOINTS], o0[3], o1[3], d[3];
    int i, k, q, count, nw = 0, rc;
    int64_t t0;
    vp_step_contact_t c;
    if (done) *done = 0;
    if (!m || !cmds || !done || n < 1 || n > VP_MACHINE_PATH_MOVES || !vp_machine_paths_allowed(m))
        return VP_EINVAL;
    for (i = 0; i < n; i++) {
        if (cmds[i].kind != VP_CMD_MOVE) return VP_EINVAL;
        for (q = 0; q < 3; q++) if (!isfinite(cmds[i].from[q]) || !isfinite(cmds[i].to[q])) return VP_EINVAL;
    }
    m->last.contact = 0;
    m->last.contact_at = m->last.overtravel = 0;
    m->move_n = 0;
    t0 = m->io.now(m->io.ctx);
    memcpy(jc, m->j, sizeof jc);
    for (i = 0; i < n; i++) {
        vp_machine_path_move_t *pm = &m->path[i];
        int turning = 0;
        /* the pieces vp_machine_move would take from where the MOVE before ends */
        k = vp_machine_turning_plan(m, jc, &cmds[i], m->way);
        if (k >= 1) turning = 1;
        else k = vp_kin_move(&m->kin, jc, cmds[i].to, m->way[0]) == VP_OK;
        if (k >= 1 && i == 0 && m->touched) k = 0;          /* backing off a touch: alone */
        if (k == 0 && i == 0) {
            rc = vp_machine_path_alone(m, &cmds[0]);
            m->st.move_ns += m->io.now(m->io.ctx) - t0;
            if (rc < 0) return rc;
            *done = 1;
            return VP_OK;
        }
        if (k == 0 || nw + k > VP_MACHINE_PATH_WAY) break;    /* the rest given again */
        memcpy(pm->j0, jc, sizeof pm->j0);
        memcpy(m->path_way[nw], m->way, (size_t)k * sizeof m->way[0]);
        if (!turning) vp_machine_as_stepped(m, m->path_way[nw], m->path_way[nw]);
        vp_machine_as_stepped(m, m->path_way[nw + k - 1], jc);
        memcpy(pm->j1, jc, sizeof pm->j1);
        pm->first = nw;
        pm->n = k;
        pm->turn_n = 0;
        pm->turning = turning;
        nw += k;
    }
    count = i;
    c.hit = 0;
    if (m->cfg.contact) {
        /* watched: a touch ends the path in the MOVE whose pieces it fell in; a piece whose own
         * stop would go too far (fast, with the arm's turn) makes the first MOVE go alone */
        if (!vp_machine_touch_fits(m, m->j, (const double (*)[VP_KIN_JOINTS])m->path_way, nw)) {
            rc = vp_machine_path_alone(m, &cmds[0]);
            m->st.move_ns += m->io.now(m->io.ctx) - t0;
            if (rc < 0) return rc;
            *done = 1;
            return VP_OK;
        }
        rc = vp_machine_touch_pieces(m, (const double (*)[VP_KIN_JOINTS])m->path_way, nw, &c);
    } else
        rc = vp_step_move_path(&m->step, &m->path_way[0][0], nw);
    vp_machine_sync(m);
    m->st.move_ns += m->io.now(m->io.ctx) - t0;
    if (rc >= 0 && c.hit) {
        for (i = 0; i + 1 < count && m->path[i].first + m->path[i].n <= c.way; i++) {}
        count = i + 1;
        vp_kin_forward(&m->kin, m->j, o1, d);
        vp_machine_take_touch(m, &cmds[i], &c, o1, (const double (*)[VP_KIN_JOINTS])m->path_way, m->path[i].first,
                              m->path[i].j0);
        /* it ended where the stop did: its pieces up to there */
        memcpy(m->path[i].j1, m->j, sizeof m->j);
        memcpy(m->path_way[c.rest_way], m->j, sizeof m->j);
        m->path[i].n = c.rest_way - m->path[i].first + 1;
    }
    for (i = 0; i < count; i++) {
        const vp_machine_path_move_t *pm = &m->path[i];
        if (rc < 0 && pm->first + pm->n > m->step.path_done) break;
        m->st.moves++;
        if (pm->turning) m->st.moves_turning++;
        vp_kin_forward(&m->kin, pm->j0, o0, d);
        vp_kin_forward(&m->kin, pm->j1, o1, d);
        m->st.travel += vp_dist3(o0, o1);
    }
    *done = i;
    if (rc < 0) return rc;
    if (count > 1) {
        m->st.paths++;
        m->st.path_moves += (unsigned long)count;
    }
    return VP_OK;
}

int vp_machine_move(vp_machine_t *m, const vp_cmd_t *cmd)
{
    double j1[VP_KIN_JOINTS];
    int rc;
    if (!m || !cmd || cmd->kind != VP_CMD_MOVE) return VP_EINVAL;
    m->last.contact = 0;
    m->last.contact_at = m->last.overtravel = 0;
    m->move_n = 0;
    if ((rc = vp_machine_move_turning(m, cmd)) != 0) return rc < 0 ? rc : VP_OK;
    if (!m->touched && vp_kin_move(&m->kin, m->j, cmd->to, j1) == VP_ERANGE) VP_TRY(vp_machine_turn_for(m, cmd->to));
    if (m->cfg.contact) return vp_machine_touch_move(m, cmd);
    m->st.moves++;
    return vp_machine_goto(m, cmd->to);
}

int vp_machine_contact(const vp_machine_t *m, double *at)
{
    if (!m || !m->last.contact) return 0;
    if (at) *at = m->last.contact_at;
    return 1;
}

static void vp_machine_laser(vp_machine_t *m, int on)
{
    if (m->cfg.use_laser_line) m->io.write(m->io.ctx, VP_IO_LASER, on ? VP_IO_LASER : 0);
}

static int vp_machine_refuse(vp_machine_t *m, int fault, int rc)
{
    m->last.fault = fault;
    m->st.refused++;
    return rc;
}

/* One frame stamped at or after t0 and numbered at least want (-1: any). A frame numbered or
 * stamped older than one already taken is refused (VP_EIO), never passed over. */
static int vp_machine_frame(vp_machine_t *m, int64_t t0, int64_t want, vp_frame_t *f)
{
    int k, rc;
    for (k = 0;; k++) {
        memset(f, 0, sizeof *f);
        f->seq = want;
        rc = m->cam.capture(m->cam.ctx, t0, m->cfg.timeout_ms, f);
        if (rc < 0) { m->st.camera_errors++; return rc; }
        m->st.frames++;
        if (m->seen && ((f->seq >= 0 && f->seq <= m->seen_seq) || f->t_ns < m->seen_ts)) {
            m->cam.release(m->cam.ctx, f);
            return vp_machine_refuse(m, VP_FRAME_BACKWARDS, VP_EIO);
        }
        if (f->seq >= 0) m->seen_seq = f->seq;
        m->seen_ts = f->t_ns;
        m->seen = 1;
        if (want < 0 || f->seq < 0 || f->seq >= want) return VP_OK;
        /* from before the laser switch: dropped */
        m->st.stale++;
        m->cam.release(m->cam.ctx, f);
        if (k > m->cfg.latency_frames + 64) { m->st.camera_errors++; return VP_ETIMEOUT; }
    }
}

/* The laser was just switched: the camera's mark (taken now, after the switch), then a frame
 * numbered at least mark + latency_frames and stamped after now. *proven: the frame is known to
 * be from after the switch (a camera without sequence numbers or mark cannot show it). */
static int vp_machine_grab(vp_machine_t *m, vp_frame_t *f, int *proven)
{
    int64_t t0 = m->io.now(m->io.ctx), next = -1, want = -1;
    if (m->cam.mark) {
        int rc = m->cam.mark(m->cam.ctx, &next);
        if (rc < 0) { m->st.camera_errors++; return rc; }
        want = next + m->cfg.latency_frames;
    }
    m->last.seq_mark = next;
    VP_TRY(vp_machine_frame(m, t0, want, f));
    *proven = want >= 0 && f->seq >= want;
    return VP_OK;
}

/* The frame the spot is looked for in. With a laser line: a laser-off frame copied into diff_buf,
 * then a laser-on frame, and diff_buf = on - off (clamped at 0); *held = 0. Without (or with
 * single_frame): the camera's frame itself, *held = 1 (release it). The laser is off on return. */
static int vp_machine_expose(vp_machine_t *m, vp_frame_t *out, int *held, int keep_on, vp_spot_t *off_spot)
{
    vp_frame_t f;
    size_t n;
    int proven = 1, x, y, w, h, rc;
    uint8_t *b = m->cfg.diff_buf;
    *held = 0;
    if (off_spot) { memset(off_spot, 0, sizeof *off_spot); off_spot->result = VP_SPOT_NONE; }
    m->last.fault = VP_FRAME_OK;
    m->last.seq_off = m->last.seq_confirm = -1;
    if (!m->cfg.use_laser_line || m->cfg.single_frame) {
        vp_machine_laser(m, 1);
        if (m->cfg.use_laser_line) rc = vp_machine_grab(m, &f, &proven);
        else rc = vp_machine_frame(m, m->io.now(m->io.ctx), -1, &f);   /* the laser is always on */
        vp_machine_laser(m, 0);
        if (rc < 0) return rc;
        if (!proven) { m->cam.release(m->cam.ctx, &f); return vp_machine_refuse(m, VP_FRAME_UNPROVEN, VP_EIO); }
        *out = f;
        *held = 1;
        return VP_OK;
    }
    /* laser off: the scene's own light */
    vp_machine_laser(m, 0);
    VP_TRY(vp_machine_grab(m, &f, &proven));
    w = f.width;
    h = f.height;
    n = (size_t)w * (size_t)h;
    if (!proven || !b || m->cfg.diff_len < n || w < 1 || h < 1) {
        m->cam.release(m->cam.ctx, &f);
        return vp_machine_refuse(m, !proven ? VP_FRAME_UNPROVEN : VP_FRAME_NO_BUFFER, !proven ? VP_EIO : VP_ENOMEM);
    }
    if (keep_on && m->cfg.diff_len < 2 * n) {
        m->cam.release(m->cam.ctx, &f);
        return vp_machine_refuse(m, VP_FRAME_NO_BUFFER, VP_ENOMEM);
    }
    /* with a confirming frame to come, the laser-off frame is kept after the difference */
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) b[(size_t)y * w + x] = VP_FRAME_PIX(&f, x, y);
    if (keep_on) memcpy(b + n, b, n);
    m->last.seq_off = f.seq;
    m->cam.release(m->cam.ctx, &f);
    if (off_spot) {
        /* the scene with the laser off: the calibration mark */
        vp_frame_t view;
        memset(&view, 0, sizeof view);
        view.data = b; view.width = w; view.height = h; view.stride = w; view.step = 1;
        VP_TRY(vp_spot_find(&view, NULL, NULL, &m->ws, off_spot));
    }
    /* laser on */
    vp_machine_laser(m, 1);
    rc = vp_machine_grab(m, &f, &proven);
    if (!keep_on || rc < 0 || !proven || f.width != w || f.height != h) vp_machine_laser(m, 0);
    if (rc < 0) return rc;
    if (!proven || f.width != w || f.height != h) {
        m->cam.release(m->cam.ctx, &f);
        return vp_machine_refuse(m, !proven ? VP_FRAME_UNPROVEN : VP_FRAME_SIZE, VP_EIO);
    }
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            int d = (int)VP_FRAME_PIX(&f, x, y) - (int)b[(size_t)y * w + x];
            b[(size_t)y * w + x] = (uint8_t)(d > 0 ? d : 0);
        }
    memset(out, 0, sizeof *out);
    out->data = b;
    out->width = w;
    out->height = h;
    out->stride = w;
    out->step = 1;
    out->t_ns = f.t_ns;
    out->seq = f.seq;
    m->cam.release(m->cam.ctx, &f);
    return VP_OK;
}

/* The confirming frame: the laser still on, the next frame after the one read (*f), against the
 * same laser-off frame (kept after the difference); the spot must be found again within
 * confirm_px (or 0.4 of its radius, if more) of where it was, else the reading is VP_SPOT_MOVED:
 * light that moves between two laser-on frames (a glint, the head still ringing after a move) is
 * not the laser's spot. The laser is off on return. */
static int vp_machine_confirm(vp_machine_t *m, const vp_frame_t *f)
{
    vp_frame_t g;
    vp_spot_t s2;
    size_t n = (size_t)f->width * (size_t)f->height;
    uint8_t *b = m->cfg.diff_buf;
    double tol = m->cfg.confirm_px > 0 ? m->cfg.confirm_px : 1.0, r = sqrt(m->last.spot.area / 3.14159265358979);
    int x, y, rc, w = f->width, h = f->height;
    rc = vp_machine_frame(m, f->t_ns, f->seq >= 0 ? f->seq + 1 : -1, &g);
    vp_machine_laser(m, 0);
    if (rc < 0) return rc;
    if (g.width != w || g.height != h) {
        m->cam.release(m->cam.ctx, &g);
        return vp_machine_refuse(m, VP_FRAME_SIZE, VP_EIO);
    }
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            int d = (int)VP_FRAME_PIX(&g, x, y) - (int)b[n + (size_t)y * w + x];
            b[(size_t)y * w + x] = (uint8_t)(d > 0 ? d : 0);
        }
    m->last.seq_confirm = g.seq;
    m->cam.release(m->cam.ctx, &g);
    if (m->cfg.use_rf) {
        /* the full model looks for the spot anywhere (its beam's image is curved) */
        vp_spot_config_t sc = m->cfg.spot;
        sc.band = 0;
        VP_TRY(vp_spot_find(f, &sc, NULL, &m->ws, &s2));
    } else {
        VP_TRY(vp_spot_find(f, &m->cfg.spot, &m->tri, &m->ws, &s2));
    }
    if (tol < 0.4 * r) tol = 0.4 * r;      /* a large (saturated) spot's centroid wanders more */
    m->st.confirmed++;
    if (s2.result != VP_SPOT_FOUND || hypot(s2.u - m->last.spot.u, s2.v - m->last.spot.v) > tol) {
        m->last.spot.result = VP_SPOT_MOVED;
        m->st.moved++;
    }
    return VP_OK;
}

/* The laser-off frame where the spot is (kept at diff_buf + w h): a laser spot leaves it plain
 * (the scene's own light: smooth), light that was there without the laser (a glint that moved
 * between the frames and did not cancel) stands out: its 3x3 mean above the window's median by
 * more than max(8, a fifth of the spot's peak) grey levels within 3 spot radii + 6 px. 1: plain. */
static int vp_machine_off_plain(const vp_machine_t *m, int w, int h)
{
    const uint8_t *off = m->cfg.diff_buf + (size_t)w * (size_t)h;
    const vp_spot_t *sp = &m->last.spot;
    unsigned hist[256], n = 0, acc = 0;
    int R = (int)ceil(3 * sqrt(sp->area / 3.14159265358979) + 6), x0, x1, y0, y1, x, y, med;
    double best = 0, lim = sp->peak / 5 > 8 ? sp->peak / 5 : 8;
    x0 = (int)floor(sp->u) - R; x1 = (int)ceil(sp->u) + R;
    y0 = (int)floor(sp->v) - R; y1 = (int)ceil(sp->v) + R;
    if (x0 < 1) x0 = 1;
    if (y0 < 1) y0 = 1;
    if (x1 > w - 2) x1 = w - 2;
    if (y1 > h - 2) y1 = h - 2;
    if (x0 > x1 || y0 > y1) return 1;
    memset(hist, 0, sizeof hist);
    for (y = y0; y <= y1; y++)
        for (x = x0; x <= x1; x++) { hist[off[(size_t)y * w + x]]++; n++; }
    for (med = 0; med < 255; med++) { acc += hist[med]; if (2 * acc > n) break; }
    for (y = y0; y <= y1; y++)
        for (x = x0; x <= x1; x++) {
            int dx, dy, sum = 0;
            for (dy = -1; dy <= 1; dy++)
                for (dx = -1; dx <= 1; dx++) sum += off[(size_t)(y + dy) * w + x + dx];
            if (sum / 9.0 - med > best) best = sum / 9.0 - med;
        }
    return best <= lim;
}

/* A line laser's probe (vp_machine_line_read): two points of the line are one surface's when their
 * chord is at most LINE_CHORD_SLOPE times the arc between their rays (a surface up to 83 degrees
 * oblique) plus LINE_CHORD_MM; the axis is read on the chord only when the next points out lie
 * within LINE_FLAT_MM + LINE_FLAT_REL x distance of its line (no edge between them to cut) */
#define LINE_CHORD_SLOPE 8.0
#define LINE_CHORD_MM 0.2
#define LINE_FLAT_MM 0.2
#define LINE_FLAT_REL 0.002

/* A line laser's exposure: the laser-off frame into diff_buf, the laser-on frame after it (both
 * kept: the detector takes their difference itself and sees light in the laser-off frame). The
 * laser is off on return. */
static int vp_machine_expose_pair(vp_machine_t *m, vp_frame_t *on, vp_frame_t *off)
{
    vp_frame_t f;
    size_t n;
    int proven = 1, x, y, w, h, rc, k;
    uint8_t *b = m->cfg.diff_buf;
    m->last.fault = VP_FRAME_OK;
    m->last.seq_off = m->last.seq_confirm = -1;
    for (k = 0; k < 2; k++) {
        vp_machine_laser(m, k);
        rc = vp_machine_grab(m, &f, &proven);
        if (k) vp_machine_laser(m, 0);
        if (rc < 0) return rc;
        if (k == 0) { w = f.width; h = f.height; }
        n = (size_t)w * (size_t)h;
        if (!proven || !b || m->cfg.diff_len < 2 * n || w < 1 || h < 1 || f.width != w || f.height != h) {
            m->cam.release(m->cam.ctx, &f);
            if (k) vp_machine_laser(m, 0);
            return vp_machine_refuse(m, !proven ? VP_FRAME_UNPROVEN : f.width != w || f.height != h ? VP_FRAME_SIZE
                                                : VP_FRAME_NO_BUFFER, !proven ? VP_EIO : VP_ENOMEM);
        }
        for (y = 0; y < h; y++)
            for (x = 0; x < w; x++) b[(size_t)k * n + (size_t)y * w + x] = VP_FRAME_PIX(&f, x, y);
        if (k == 0) m->last.seq_off = f.seq;
        else { m->last.t_ns = f.t_ns; m->last.seq = f.seq; }
        m->cam.release(m->cam.ctx, &f);
    }
    memset(on, 0, sizeof *on);
    on->width = off->width = w;
    on->height = off->height = h;
    on->stride = w;
    on->step = 1;
    *off = *on;
    off->data = b;
    on->data = b + n;
    on->t_ns = m->last.t_ns;
    on->seq = m->last.seq;
    return VP_OK;
}

/* A point's angle from the fan's axis, in the plane (e2 = normal x axis). */
static double line_angle(const vp_line_point_t *p, const double *ax, const double *e2)
{
    return atan2(vp_dot3(p->dir, e2), vp_dot3(p->dir, ax));
}

/* 1 when two points of the line can be one surface's: their chord at most LINE_CHORD_SLOPE times
 * the arc between their rays plus LINE_CHORD_MM (longer: an edge, a step, a gap between them) */
static int line_continuous(const vp_line_point_t *p, const vp_line_point_t *q, const double *ax, const double *e2)
{
    double c[3], arc = fabs(line_angle(p, ax, e2) - line_angle(q, ax, e2)) * (p->dist < q->dist ? p->dist : q->dist);
    vp_sub3(c, p->p, q->p);
    return sqrt(vp_dot3(c, c)) <= LINE_CHORD_SLOPE * arc + LINE_CHORD_MM;
}

/* distance of point r from the line through p and q (all points of the plane) */
static double line_off_chord(const vp_line_point_t *p, const vp_line_point_t *q, const vp_line_point_t *r)
{
    double u[3], w[3], x[3], l2;
    vp_sub3(u, q->p, p->p);
    vp_sub3(w, r->p, p->p);
    l2 = vp_dot3(u, u);
    if (!(l2 > 0)) return sqrt(vp_dot3(w, w));
    vp_cross3(x, u, w);
    return sqrt(vp_dot3(x, x) / l2);
}

/* A line laser's probe: its frame pair's line (vp_line_detect, in the tilt frame), the points
 * either side of the fan's axis answer the PROBE (*hit, *dist along the beam; last.spot.result
 * FOUND, NONE without a line there, SEVERAL when it cannot be read: unreadable, never free), and
 * every point within the calibrated span that one surface carries on either side becomes a ray
 * from the PROBE's origin, in the world (vp_machine_ray). Read only when the two points are in
 * neighbouring columns (a column missing between them may hide an edge or a step), the line goes
 * on beyond both and lies straight there (no edge between them for the chord to cut), and their
 * chord is one surface's. Without a point on one side, the
 * axis is unreadable when any column where its hit could show (its image between the calibrated
 * span's ends, widened by line_gap_cols steps) was refused rather than empty, or lit with the
 * laser off: a doubled line, a reflection, a steep line is never read as free space. */
static int vp_machine_line_read(vp_machine_t *m, const vp_cmd_t *cmd, int *hit, double *dist)
{
    vp_line_model_t lm = m->cfg.line_model;
    const double *ax = lm.axis, *nn = lm.normal;
    const int step = m->cfg.line_cfg.column_step, gap = (int)m->cfg.line_gap_cols;
    double e2[3], rot[9], pos[3], best_lo = -1e300, best_hi = 1e300;
    vp_frame_t on, off;
    int i, lo = -1, hi = -1, n = 0, k, st, cols, readable = 1;
    *hit = 0;
    *dist = 0.0;
    m->nline = m->nrays = 0;
    memset(&m->last.spot, 0, sizeof m->last.spot);
    m->last.spot.result = VP_SPOT_NONE;
    m->last.rf_why = -1;
    m->last.rf_dist = 0.0;
    VP_TRY(vp_machine_expose_pair(m, &on, &off));
    /* every point the camera can place, near or far: the span is applied below */
    lm.min_range = 1e-6;
    lm.max_range = 1e9;
    st = vp_line_detect(&on, &off, &m->cfg.line_cfg, &lm, &m->lws, m->lpts, VP_MACHINE_MAX_LINE, &n, NULL);
    if (st != VP_OK) return st;
    m->nline = n;
    m->st.line_points += (unsigned long)n;
    cols = (on.width + step - 1) / step;
    for (k = 0; k < cols; k++) m->colmap[k] = -1;
    for (i = 0; i < n; i++) m->colmap[m->lpts[i].col / step] = (int16_t)i;
    /* the fan's axis: the points nearest it on either side (angle in the plane, from the axis) */
    vp_cross3(e2, nn, ax);
    for (i = 0; i < n; i++) {
        double a = line_angle(&m->lpts[i], ax, e2);
        if (a <= 0 && a > best_lo) { best_lo = a; lo = i; }
        if (a > 0 && a < best_hi) { best_hi = a; hi = i; }
    }
    if (lo >= 0 && hi >= 0) {
        const vp_line_point_t *p = &m->lpts[lo], *q = &m->lpts[hi], *p2 = NULL, *q2 = NULL;
        int kp = p->col / step, kq = q->col / step, away = kp > kq ? 1 : -1;
        if (kp + away >= 0 && kp + away < cols && m->colmap[kp + away] >= 0) p2 = &m->lpts[m->colmap[kp + away]];
        if (kq - away >= 0 && kq - away < cols && m->colmap[kq - away] >= 0) q2 = &m->lpts[m->colmap[kq - away]];
        if ((kp > kq ? kp - kq : kq - kp) != 1 || !p2 || !q2 || !line_continuous(p, q, ax, e2) || !line_continuous(p, p2, ax, e2) ||
            !line_continuous(q, q2, ax, e2) ||
            line_off_chord(p, q, p2) > LINE_FLAT_MM + LINE_FLAT_REL * p->dist ||
            line_off_chord(p, q, q2) > LINE_FLAT_MM + LINE_FLAT_REL * q->dist)
            readable = 0;
        if (readable) {
            /* the chord between them meets the axis (in the plane: x along it, y across) */
            double xp = p->dist * vp_dot3(p->dir, ax), yp = p->dist * vp_dot3(p->dir, e2);
            double xq = q->dist * vp_dot3(q->dir, ax), yq = q->dist * vp_dot3(q->dir, e2);
            double t = yp != yq ? yp / (yp - yq) : 0.0;
            m->last.spot.result = VP_SPOT_FOUND;
            m->last.spot.u = p->u + t * (q->u - p->u);
            m->last.spot.v = p->v + t * (q->v - p->v);
            *dist = xp + t * (xq - xp);
            *hit = *dist > 0.0;
        }
    } else {
        /* no point on one side: the columns the axis's hit could show in must be plainly empty */
        int ka = cols, kb = -1, j;
        for (j = 0; j <= 16; j++) {
            double d = m->cfg.line_model.min_range + (m->cfg.line_model.max_range - m->cfg.line_model.min_range) * j / 16.0;
            double pt[3], uv[2];
            for (k = 0; k < 3; k++) pt[k] = lm.origin[k] + d * ax[k];
            if (vp_camera_project(&lm.cam, pt, uv) && uv[0] >= -1e6 && uv[0] <= 1e6) {
                int kc = (int)floor(uv[0] / step);
                if (kc < ka) ka = kc;
                if (kc > kb) kb = kc;
            }
        }
        for (k = ka - gap; k <= kb + gap; k++)
            if (k >= 0 && k < cols && ((m->lws.why[k] != VP_LINE_NONE && m->lws.why[k] != VP_LINE_FOUND) || m->lws.off_lit[k]))
                readable = 0;
        if (readable && (lo >= 0 || hi >= 0)) {
            /* the line on one side only, reaching within a few column steps' angle of the axis:
             * unreadable (its end there is a limb, or its other side was hidden) */
            const vp_line_point_t *p = &m->lpts[lo >= 0 ? lo : hi];
            double ap = lo >= 0 ? best_lo : best_hi, dth = 0.0;
            int kp = p->col / step;
            for (j = -1; j <= 1; j += 2)
                if (kp + j >= 0 && kp + j < cols && m->colmap[kp + j] >= 0)
                    dth = fabs(line_angle(&m->lpts[m->colmap[kp + j]], ax, e2) - ap);
            if (dth > 0.0 && fabs(ap) <= m->cfg.line_gap_cols * dth) readable = 0;
        }
    }
    if (!readable) {
        m->last.spot.result = VP_SPOT_SEVERAL;
        m->st.line_gaps++;
    }
    /* the rays, in the world, from the PROBE's origin: points one surface carries on both sides */
    vp_kin_head(&m->kin, m->j, rot, pos);
    for (i = 0; i < n; i++) {
        const vp_line_point_t *p = &m->lpts[i];
        double w[3], v[3], len;
        int kp = p->col / step, ok = 1, j;
        if (!(p->dist >= m->cfg.line_model.min_range && p->dist <= m->cfg.line_model.max_range)) continue;
        if (m->cfg.line_ray_half > 0 && fabs(line_angle(p, ax, e2)) > m->cfg.line_ray_half) continue;
        for (j = -1; j <= 1 && ok; j += 2)
            ok = kp + j >= 0 && kp + j < cols && m->colmap[kp + j] >= 0 && line_continuous(p, &m->lpts[m->colmap[kp + j]], ax, e2);
        /* and lies straight between them (not a column mixing two surfaces at a corner) */
        if (!ok || line_off_chord(&m->lpts[m->colmap[kp - 1]], &m->lpts[m->colmap[kp + 1]], p) > LINE_FLAT_MM + LINE_FLAT_REL * p->dist)
            continue;
        vp_kin_mul(rot, p->p, w);
        for (k = 0; k < 3; k++) v[k] = pos[k] + w[k] - cmd->from[k];
        len = sqrt(vp_dot3(v, v));
        if (!(len > 0.0)) continue;
        for (k = 0; k < 3; k++) m->ray_dir[m->nrays][k] = v[k] / len;
        m->ray_dist[m->nrays++] = len;
    }
    m->st.line_rays += (unsigned long)m->nrays;
    return VP_OK;
}

int vp_machine_ray(const vp_machine_t *m, unsigned i, double dir[3], double *dist)
{
    if (!m || !dir || !dist || !m->cfg.line || i >= (unsigned)m->nrays) return 0;
    memcpy(dir, m->ray_dir[i], 3 * sizeof *dir);
    *dist = m->ray_dist[i];
    return 1;
}

static int vp_machine_probe_do(vp_machine_t *m, const vp_cmd_t *cmd, vp_probe_result_t *res)
{
    double target[VP_KIN_JOINTS], o0[3], d[3], dist = 0;
    vp_frame_t f;
    int n, rc, hit, held, confirm;
    int64_t t0;
    if (!m || !cmd || !res || cmd->kind != VP_CMD_PROBE) return VP_EINVAL;
    res->hit = 0;
    res->dist = 0;
    m->st.probes++;
    /* aim: turn about the laser origin, then wait for the head to settle */
    VP_TRY(vp_kin_aim(&m->kin, m->j, cmd->from, cmd->dir, target));
    n = vp_kin_aim_path(&m->kin, m->j, target, m->way, VP_MACHINE_MAX_WAY);
    if (n < 0) return n;
    vp_machine_beam(m, o0, d);
    t0 = m->io.now(m->io.ctx);
    rc = vp_step_move_path(&m->step, &m->way[0][0], n);
    vp_machine_sync(m);
    if (rc < 0) return rc;
    vp_machine_beam(m, m->last.origin, m->last.dir);
    m->st.travel += vp_dist3(o0, m->last.origin);
    m->st.aim_ns += m->io.now(m->io.ctx) - t0;
    t0 = m->io.now(m->io.ctx);
    if (m->cfg.settle_ns) m->io.wait_until(m->io.ctx, t0 + m->cfg.settle_ns);
    m->st.settle_ns += m->io.now(m->io.ctx) - t0;
    m->nline = m->nrays = 0;
    if (m->cfg.line) {
        /* a line laser: the distance along the beam as the full model gives it (span, near) */
        VP_TRY(vp_machine_line_read(m, cmd, &hit, &dist));
        if (hit) {
            m->last.rf_dist = dist;
            m->last.rf_why = dist > m->cfg.line_model.max_range ? VP_RF_OUT_OF_SPAN : VP_RF_OK;
            if (dist > m->cfg.line_model.max_range) hit = 0;
            else if (dist < m->cfg.line_model.min_range) m->st.near++;  /* too close: never free space */
        }
        goto judged;
    }
    /* expose: frames from after the laser switch only (vp_machine_expose) */
    confirm = m->cfg.confirm && m->cfg.use_laser_line && !m->cfg.single_frame;
    VP_TRY(vp_machine_expose(m, &f, &held, confirm, NULL));
    m->last.t_ns = f.t_ns;
    m->last.seq = f.seq;
    m->last.rf_why = -1;
    if (m->cfg.use_rf) {
        /* the full model: the spot anywhere in the frame, then the camera ray against the beam */
        vp_spot_config_t sc = m->cfg.spot;
        sc.band = 0;
        hit = vp_spot_find(&f, &sc, NULL, &m->ws, &m->last.spot);
        if (held) m->cam.release(m->cam.ctx, &f);
        if (hit >= 0) {
            hit = 0;
            if (m->last.spot.result == VP_SPOT_FOUND) {
                double uv[2];
                uv[0] = m->last.spot.u;
                uv[1] = m->last.spot.v;
                hit = vp_rf_distance(&m->cfg.rf, uv, &m->last.rf_dist, &m->last.rf_why, &m->last.rf_gap_px);
                if (hit >= 0) {
                    hit = 0;
                    if (m->last.rf_why == VP_RF_OFF_BEAM) m->last.spot.result = VP_SPOT_OFF_LINE;
                    else if (m->last.rf_why == VP_RF_OK) { hit = 1; dist = m->last.rf_dist; }
                    else if (m->last.rf_dist < m->cfg.rf.min_range && m->last.rf_dist > 0) {
                        /* nearer than the calibrated span: a surface too close, never free space */
                        hit = 1;
                        dist = m->last.rf_dist;
                        m->st.near++;
                    }
                }
            }
        }
    } else {
        hit = vp_laser_measure(&f, &m->cfg.spot, &m->tri, &m->ws, &m->last.spot, &dist);
        if (held) m->cam.release(m->cam.ctx, &f);
    }
    if (confirm) {
        /* the laser is still on: a second frame where the spot must be again */
        if (hit < 0 || m->last.spot.result != VP_SPOT_FOUND) vp_machine_laser(m, 0);
        else {
            VP_TRY(vp_machine_confirm(m, &f));
            if (m->last.spot.result == VP_SPOT_FOUND && !vp_machine_off_plain(m, f.width, f.height)) {
                m->last.spot.result = VP_SPOT_NOT_LASER;
                m->st.off_lit++;
            }
            if (m->last.spot.result != VP_SPOT_FOUND) hit = 0;
        }
    }
    if (hit < 0) return hit;
    if (!m->cfg.use_rf && !hit && m->last.spot.result == VP_SPOT_FOUND) {
        /* a spot nearer than min_range is a surface too close, never free space: report it
         * (extrapolated) rather than a miss */
        const vp_tri_model_t *t = &m->tri;
        double s = (m->last.spot.u - t->p0[0]) * t->e[0] + (m->last.spot.v - t->p0[1]) * t->e[1];
        double d0 = vp_tri_eval(t, s, NULL), smin = vp_tri_s(t, t->min_range);
        if ((1 + t->c * s) * (1 + t->c * smin) > 0 && d0 > 0 && d0 < t->min_range) {
            hit = 1;
            dist = d0;
            m->st.near++;
        }
    }
judged:
    /* a hit beyond the range asked for is a miss for the planner */
    if (hit && dist <= cmd->range) {
        int k;
        res->hit = 1;
        res->dist = dist;
        for (k = 0; k < 3; k++) m->last.point[k] = m->last.origin[k] + dist * m->last.dir[k];
        m->st.hits++;
    } else {
        int r = m->last.spot.result;
        m->st.misses++;
        m->st.miss_reason[hit || r == VP_SPOT_FOUND ? 5 : r < VP_SPOT_OFF_LINE ? 6 : r + 3]++;
    }
    return VP_OK;
}

vp_reading_t vp_machine_reading(const vp_machine_t *m, const vp_cmd_t *cmd, int was_near, int near_measure,
                                vp_probe_result_t *res, double *raw)
{
    const vp_tri_model_t *t = &m->tri;
    int r = m->last.spot.result, unreadable = 0;
    int full = m->cfg.use_rf || m->cfg.line;     /* the full model or a line laser: mm along the beam */
    vp_reading_t kind = VP_READING_PLAIN;
    double s = NAN;
    if (r == VP_SPOT_FOUND) s = (m->last.spot.u - t->p0[0]) * t->e[0] + (m->last.spot.v - t->p0[1]) * t->e[1];
    if (full) s = r == VP_SPOT_FOUND ? m->last.rf_dist : NAN;
    if (raw) *raw = s;
    if (full && r == VP_SPOT_FOUND && !res->hit && m->last.rf_why != VP_RF_OK) {
        /* beyond the calibrated span (or below it but not taken as near): refused, never free */
        unreadable = 1;
    } else if (full && r == VP_SPOT_FOUND && !res->hit) {
        /* measured within the span, beyond the range asked: free up to it */
    } else if (r == VP_SPOT_FOUND && res->hit && was_near) {
        kind = VP_READING_NEAR;
        if (!near_measure) res->hit = VP_PROBE_TOO_CLOSE;
    } else if (r == VP_SPOT_FOUND && !res->hit) {
        double dd = vp_tri_eval(t, s, NULL), sfar = vp_tri_s(t, t->max_range);
        int beyond = s >= sfar || (dd >= t->min_range && dd > cmd->range);
        /* with a backdrop every wall lies within the range: a spot past the model's far end is
         * no wall's, a reflection */
        if (!beyond || (m->cfg.backdrop && s >= sfar)) unreadable = 1;
    } else if (r != VP_SPOT_FOUND && r != VP_SPOT_NONE) unreadable = 1;
    else if (r == VP_SPOT_NONE && !res->hit && m->cfg.backdrop) {
        /* every beam ends on the backdrop within the range: no spot (for a line laser, no point
         * of the line on either side of the beam) means the camera did not see where it ended
         * (hidden behind the object, or a surface returning too little light) */
        unreadable = 1;
    }
    if (unreadable) {
        res->hit = VP_PROBE_TOO_CLOSE;
        kind = r == VP_SPOT_NONE ? VP_READING_NO_SPOT : r == VP_SPOT_OFF_LINE ? VP_READING_OFF_LINE
             : r == VP_SPOT_TOO_BIG ? VP_READING_TOO_BIG
             : r == VP_SPOT_SEVERAL ? VP_READING_SEVERAL : r == VP_SPOT_NOT_LASER || r == VP_SPOT_MOVED ? VP_READING_NOT_LASER
             : VP_READING_BELOW_MODEL;
    }
    if (res->hit == VP_PROBE_TOO_CLOSE) res->dist = 0;
    return kind;
}

/* A probe: what the aim and the settle took is counted inside, the rest is reading. */
int vp_machine_probe(vp_machine_t *m, const vp_cmd_t *cmd, vp_probe_result_t *res)
{
    int64_t t0, before;
    int rc;
    if (!m) return VP_EINVAL;
    t0 = m->io.now(m->io.ctx);
    before = m->st.aim_ns + m->st.settle_ns;
    rc = vp_machine_probe_do(m, cmd, res);
    m->st.read_ns += m->io.now(m->io.ctx) - t0 - (m->st.aim_ns + m->st.settle_ns - before);
    return rc;
}

int vp_machine_exec(vp_machine_t *m, const vp_cmd_t *cmd, vp_probe_result_t *res)
{
    int64_t t0;
    int rc;
    if (!m || !cmd) return VP_EINVAL;
    switch (cmd->kind) {
    case VP_CMD_MOVE:
        t0 = m->io.now(m->io.ctx);
        rc = vp_machine_move(m, cmd);
        m->st.move_ns += m->io.now(m->io.ctx) - t0;
        return rc;
    case VP_CMD_PROBE: return vp_machine_probe(m, cmd, res);
    case VP_CMD_DONE: return VP_OK;
    default: return VP_EINVAL;
    }
}

void vp_machine_close(vp_machine_t *m)
{
    if (!m) return;
    vp_step_enable(&m->step, 0);
    if (m->cam.close) m->cam.close(m->cam.ctx);
    m->cam.close = NULL;
}

/* The calibration's first station: the head at (x, y, z) looking along +x at the flat target. */
static int vp_machine_face_target(vp_machine_t *m, double x, double y, double z)
{
    static const double ex[3] = { 1, 0, 0 };
    double o[3], target[VP_KIN_JOINTS];
    int w;
    o[0] = x; o[1] = y; o[2] = z;
    VP_TRY(vp_kin_aim(&m->kin, m->j, o, ex, target));
    w = vp_kin_aim_path(&m->kin, m->j, target, m->way, VP_MACHINE_MAX_WAY);
    if (w < 0) return w;
    w = vp_step_move_path(&m->step, &m->way[0][0], w);
    vp_machine_sync(m);
    return w < 0 ? w : VP_OK;
}

/* The distance from the target of beam station i of n: even steps in 1/d from d_far to d_near
 * (the spot or line moves by about the same number of pixels each time) */
static double vp_machine_station(double d_near, double d_far, int n, int i)
{
    return 1 / (1 / d_far + (1 / d_near - 1 / d_far) * i / (n - 1));
}

int vp_machine_calibrate(vp_machine_t *m, const vp_calib_plan_t *p, vp_tri_model_t *out, vp_tri_fit_report_t *rep)
{
    double uv[VP_MACHINE_MAX_CALIB][2], dist[VP_MACHINE_MAX_CALIB], o[3], d[3];
    int i, k, n = 0, frames, w;
    if (!m || !p || !out || p->stations < 4 || !(p->d_near > 0) || !(p->d_far > p->d_near)) return VP_EINVAL;
    frames = p->frames > 0 ? p->frames : 3;
    if (p->stations * frames > VP_MACHINE_MAX_CALIB) return VP_EINVAL;
    VP_TRY(vp_machine_face_target(m, p->target_x - p->d_far, p->y, p->z));
    o[1] = p->y;
    o[2] = p->z;
    for (i = 0; i < p->stations; i++) {
        double dd = vp_machine_station(p->d_near, p->d_far, p->stations, i);
        o[0] = p->target_x - dd;
        VP_TRY(vp_machine_goto(m, o));
        vp_machine_beam(m, o, d);
        for (k = 0; k < frames; k++) {
            vp_frame_t f;
            vp_spot_t sp;
            int held;
            int64_t t0 = m->io.now(m->io.ctx);
            if (m->cfg.settle_ns) m->io.wait_until(m->io.ctx, t0 + m->cfg.settle_ns);
            VP_TRY(vp_machine_expose(m, &f, &held, 0, NULL));
            w = vp_spot_find(&f, NULL, NULL, &m->ws, &sp);
            if (held) m->cam.release(m->cam.ctx, &f);
            if (w < 0) return w;
            if (sp.result != VP_SPOT_FOUND) continue;
            uv[n][0] = sp.u;
            uv[n][1] = sp.v;
            dist[n] = (p->target_x - o[0]) / d[0];   /* along the beam as stepped */
            n++;
        }
    }
    if (n < 4) return VP_EDEGEN;
    return vp_tri_fit((const double (*)[2])uv, dist, n, 0, 0, out, rep);
}

int vp_machine_measure_latency(vp_machine_t *m, int trials, int max_frames, int *latency)
{
    vp_frame_t f, d;
    vp_spot_t sp;
    size_t n;
    int64_t next, want;
    int t, phase, x, y, w, h, worst = 0, rc;
    uint8_t *ref = m ? m->cfg.diff_buf : NULL, *dif;
    if (!m || !latency || trials < 1 || max_frames < 1) return VP_EINVAL;
    if (!m->cfg.use_laser_line || !m->cam.mark || !ref) return VP_ESTATE;
    for (t = 0; t < trials; t++) {
        /* a reference with the laser off long enough */
        vp_machine_laser(m, 0);
        VP_TRY(m->cam.mark(m->cam.ctx, &next));
        VP_TRY(vp_machine_frame(m, m->io.now(m->io.ctx), next + max_frames, &f));
        w = f.width;
        h = f.height;
        n = (size_t)w * (size_t)h;
        if (f.seq < 0 || m->cfg.diff_len < 2 * n) { m->cam.release(m->cam.ctx, &f); return VP_ESTATE; }
        for (y = 0; y < h; y++)
            for (x = 0; x < w; x++) ref[(size_t)y * w + x] = VP_FRAME_PIX(&f, x, y);
        m->cam.release(m->cam.ctx, &f);
        dif = ref + n;
        memset(&d, 0, sizeof d);
        d.data = dif; d.width = w; d.height = h; d.stride = w; d.step = 1;
        /* switch on, then off: frames from the mark until the spot shows (is gone) */
        for (phase = 1; phase >= 0; phase--) {
            int k, seen = -1;
            vp_machine_laser(m, phase);
            VP_TRY(m->cam.mark(m->cam.ctx, &next));
            for (k = 0, want = next; k <= max_frames; k++) {
                rc = vp_machine_frame(m, 0, want, &f);
                if (rc < 0) { vp_machine_laser(m, 0); return rc; }
                for (y = 0; y < h; y++)
                    for (x = 0; x < w; x++) {
                        int v = (int)VP_FRAME_PIX(&f, x, y) - (int)ref[(size_t)y * w + x];
                        dif[(size_t)y * w + x] = (uint8_t)(v > 0 ? v : 0);
                    }
                want = f.seq + 1;
                m->cam.release(m->cam.ctx, &f);
                rc = vp_spot_find(&d, &m->cfg.spot, &m->tri, &m->ws, &sp);
                if (rc < 0) { vp_machine_laser(m, 0); return rc; }
                if ((sp.result == VP_SPOT_FOUND) == phase) { seen = (int)(want - 1 - next); break; }
            }
            if (seen < 0) { vp_machine_laser(m, 0); return VP_ETIMEOUT; }
            if (seen > worst) worst = seen;
        }
    }
    vp_machine_laser(m, 0);
    *latency = worst;
    return VP_OK;
}

int vp_machine_observe(vp_machine_t *m, vp_spot_t *mark, vp_spot_t *spot)
{
    vp_frame_t f;
    int held, rc;
    int64_t t0;
    if (!m || !spot) return VP_EINVAL;
    t0 = m->io.now(m->io.ctx);
    if (m->cfg.settle_ns) m->io.wait_until(m->io.ctx, t0 + m->cfg.settle_ns);
    VP_TRY(vp_machine_expose(m, &f, &held, 0, mark));
    rc = vp_spot_find(&f, NULL, NULL, &m->ws, spot);
    if (held) m->cam.release(m->cam.ctx, &f);
    return rc;
}

/* The head pose now and the observations at it. */
/* The flat target x = target_x (world) in the tilt frame of the head pose R, T (vp_kin_head):
 * n.p = h with n = R^T ex */
static void vp_machine_target_plane(const double R[9], const double T[3], double target_x, double n[3], double *h)
{
    int i;
    for (i = 0; i < 3; i++) n[i] = R[i];
    *h = target_x - T[0];
}

static int vp_machine_calib_obs(vp_machine_t *m, const vp_calib_full_plan_t *p, vp_calib_obs_t *obs, int cap, int *n,
                                double spot_uv[2])
{
    double R[9], T[3], w[3];
    vp_spot_t mark, spot;
    int i, k;
    VP_TRY(vp_machine_observe(m, &mark, &spot));
    vp_kin_head(&m->kin, m->j, R, T);
    spot_uv[0] = spot_uv[1] = NAN;
    if (mark.result == VP_SPOT_FOUND) {
        if (*n >= cap) return VP_ENOMEM;
        memset(&obs[*n], 0, sizeof obs[*n]);
        obs[*n].kind = VP_OBS_MARK;
        obs[*n].uv[0] = mark.u;
        obs[*n].uv[1] = mark.v;
        for (k = 0; k < 3; k++) w[k] = p->mark[k] - T[k];
        for (i = 0; i < 3; i++) obs[*n].p[i] = R[i] * w[0] + R[3 + i] * w[1] + R[6 + i] * w[2];   /* R^T w */
        (*n)++;
    }
    if (spot.result == VP_SPOT_FOUND && !m->cfg.line) {   /* a line laser has no spot: its plane is fitted apart */
        if (*n >= cap) return VP_ENOMEM;
        memset(&obs[*n], 0, sizeof obs[*n]);
        obs[*n].kind = VP_OBS_SPOT;
        obs[*n].uv[0] = spot_uv[0] = spot.u;
        obs[*n].uv[1] = spot_uv[1] = spot.v;
        vp_machine_target_plane(R, T, p->target_x, obs[*n].n, &obs[*n].h);
        (*n)++;
    }
    return VP_OK;
}

int vp_machine_calibrate_full(vp_machine_t *m, const vp_calib_full_plan_t *p, vp_calib_obs_t *obs, int cap, int *n,
                              double (*beam_uv)[2], double *beam_d, int *nbeam)
{
    const vp_rf_model_t *nom;
    double o[3], d[3], uv[2];
    int i, k, dz, row, col;
    if (!m || !p || !obs || !n || !beam_uv || !beam_d || !nbeam || !p->nominal || p->stations < 4 || p->depths < 1 ||
        p->cols < 2 || p->rows < 2 || !(p->d_near > 0) || !(p->d_far > p->d_near) || !(p->mark_near > 0) ||
        !(p->mark_far >= p->mark_near))
        return VP_EINVAL;
    if (!m->cfg.use_laser_line || m->cfg.single_frame) return VP_ESTATE;
    nom = p->nominal;
    *n = *nbeam = 0;
    VP_TRY(vp_machine_face_target(m, p->target_x - p->d_far, p->y, p->z));
    /* beam stations */
    for (i = 0; i < p->stations; i++) {
        double dd = vp_machine_station(p->d_near, p->d_far, p->stations, i);
        o[0] = p->target_x - dd; o[1] = p->y; o[2] = p->z;
        VP_TRY(vp_machine_goto(m, o));
        vp_machine_beam(m, o, d);
        VP_TRY(vp_machine_calib_obs(m, p, obs, cap, n, uv));
        if (isfinite(uv[0])) {
            beam_uv[*nbeam][0] = uv[0];
            beam_uv[*nbeam][1] = uv[1];
            beam_d[*nbeam] = (p->target_x - o[0]) / d[0];
            (*nbeam)++;
        }
    }
    /* mark stations: the mark over the image at each depth (serpentine rows) */
    for (dz = 0; dz < p->depths; dz++) {
        double z = p->depths < 2 ? p->mark_near
                 : 1 / (1 / p->mark_far + (1 / p->mark_near - 1 / p->mark_far) * dz / (p->depths - 1));
        for (row = 0; row < p->rows; row++)
            for (col = 0; col < p->cols; col++) {
                int c = row % 2 ? p->cols - 1 - col : col, rc;
                double want[2], r[3], pt[3], lo[3], sp[2];
                want[0] = p->margin_px + (nom->cam.width - 1 - 2 * p->margin_px) * c / (p->cols - 1);
                want[1] = p->margin_px + (nom->cam.height - 1 - 2 * p->margin_px) * row / (p->rows - 1);
                if (vp_camera_ray(&nom->cam, want, r) != VP_OK) continue;
                /* tilt frame at pan = tilt = 0 is the machine's axes: the head's origin T = mark - pt */
                for (k = 0; k < 3; k++) pt[k] = nom->cam.pos[k] + z * r[k];
                for (k = 0; k < 3; k++) lo[k] = p->mark[k] - pt[k] + m->kin.cfg.laser_offset[k];
                if (lo[0] > p->target_x - 2) continue;
                if (vp_rf_spot(nom, p->target_x - lo[0], sp) &&
                    (sp[0] - want[0]) * (sp[0] - want[0]) + (sp[1] - want[1]) * (sp[1] - want[1]) < 30 * 30)
                    continue;   /* the laser spot would sit on the mark */
                rc = vp_machine_goto(m, lo);
                if (rc == VP_ERANGE) continue;   /* out of travel: nothing moved */
                if (rc != VP_OK) return rc;
                VP_TRY(vp_machine_calib_obs(m, p, obs, cap, n, uv));
            }
    }
    return VP_OK;
}

int vp_machine_line_obs(vp_machine_t *m, double target_x, vp_calib_obs_t *obs, int cap, int *n)
{
    double R[9], T[3], nt[3], h;
    vp_frame_t on, off;
    int i, k, np = 0;
    int64_t t0;
    if (!m || !obs || !n || cap < 0 || *n < 0 || !isfinite(target_x)) return VP_EINVAL;
    if (!m->cfg.line) return VP_ESTATE;
    t0 = m->io.now(m->io.ctx);
    if (m->cfg.settle_ns) m->io.wait_until(m->io.ctx, t0 + m->cfg.settle_ns);
    VP_TRY(vp_machine_expose_pair(m, &on, &off));
    /* image points only: the plane is what is being measured */
    VP_TRY(vp_line_detect(&on, &off, &m->cfg.line_cfg, NULL, &m->lws, m->lpts, VP_MACHINE_MAX_LINE, &np, NULL));
    m->nline = m->nrays = 0;
    vp_kin_head(&m->kin, m->j, R, T);
    vp_machine_target_plane(R, T, target_x, nt, &h);
    if (*n + np > cap) return VP_ENOMEM;
    for (i = 0; i < np; i++) {
        vp_calib_obs_t *o = &obs[*n + i];
        memset(o, 0, sizeof *o);
        o->kind = VP_OBS_SPOT;
        o->uv[0] = m->lpts[i].u;
        o->uv[1] = m->lpts[i].v;
        for (k = 0; k < 3; k++) o->n[k] = nt[k];
        o->h = h;
    }
    *n += np;
    return VP_OK;
}

int vp_machine_calibrate_line(vp_machine_t *m, const vp_calib_full_plan_t *p, vp_calib_obs_t *obs, int cap, int *n,
                              int *poses)
{
    double o[3];
    int i, before;
    if (!m || !p || !obs || !n || !poses || p->stations < 2 || !(p->d_near > 0) || !(p->d_far > p->d_near)) return VP_EINVAL;
    if (!m->cfg.line) return VP_ESTATE;
    *n = *poses = 0;
    VP_TRY(vp_machine_face_target(m, p->target_x - p->d_far, p->y, p->z));
    for (i = 0; i < p->stations; i++) {
        double dd = vp_machine_station(p->d_near, p->d_far, p->stations, i);
        o[0] = p->target_x - dd; o[1] = p->y; o[2] = p->z;
        VP_TRY(vp_machine_goto(m, o));
        before = *n;
        VP_TRY(vp_machine_line_obs(m, p->target_x, obs, cap, n));
        if (*n > before) (*poses)++;
    }
    return VP_OK;
}
