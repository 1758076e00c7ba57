/* vp_simdev: probes (hits, misses, range, noise statistics, dropouts, minimum range,
 * reproducibility from the seed) and moves (collision checks with a clearance, travel,
 * refused moves outside the travel box or on collision). */
#include <math.h>
#include <string.h>
#include "vp_simdev.h"
#include "vp_status.h"
#include "vp_surface.h"
#include "vp_test.h"

int main(void)
{
    vp_surface_t *s;
    vp_simdev_t *d, *d2;
    vp_simdev_config_t cfg;
    vp_simdev_stats_t st;
    vp_simdev_probe_t pr, pr2;
    vp_simdev_move_t mr;
    char err[256];
    double start[3] = { 3, 0, 0 }, mx[3] = { -1, 0, 0 }, px[3] = { 1, 0, 0 }, p[3], bad[3] = { 1, 1, 0 };
    int i;
    CHECK(vp_surface_open("sphere", &s, err, sizeof err) == VP_OK);
    memset(&cfg, 0, sizeof cfg);
    CHECK(vp_simdev_create(s, &cfg, start, &d) == VP_OK);
    CHECK(vp_simdev_probe(d, mx, 10, &pr) == VP_OK && pr.hit && fabs(pr.t - 2) < 1e-15 && fabs(pr.point[0] - 1) < 1e-15 && pr.true_t == pr.t);
    CHECK(vp_simdev_probe(d, px, 10, &pr) == VP_OK && !pr.hit && pr.true_t == -1);
    CHECK(vp_simdev_probe(d, mx, 1.5, &pr) == VP_OK && !pr.hit);
    CHECK(vp_simdev_probe(d, bad, 10, &pr) == VP_EINVAL && !pr.hit);
    CHECK(vp_simdev_probe(d, mx, -1, &pr) == VP_EINVAL);
    vp_simdev_stats(d, &st);
    CHECK(st.probes == 3 && st.hits == 1 && st.misses == 2);
    /* moves */
    CHECK(vp_simdev_move(d, (double[3]){ -3, 0, 0 }, &mr) == VP_OK && mr.collided && mr.length == 6);
    CHECK(vp_simdev_move(d, (double[3]){ -3, 3, 0 }, &mr) == VP_OK && !mr.collided);
    vp_simdev_position(d, p);
    CHECK(p[0] == -3 && p[1] == 3 && p[2] == 0);
    vp_simdev_stats(d, &st);
    CHECK(st.moves == 2 && st.collisions == 1 && st.travel == 9);
    CHECK(vp_simdev_move(d, (double[3]){ NAN, 0, 0 }, &mr) == VP_EINVAL);
    vp_simdev_destroy(d);

    /* clearance, refusal on collision, travel box */
    cfg.clearance = 0.5;
    cfg.stop_on_collision = 1;
    cfg.has_limits = 1;
    cfg.limit_lo[0] = cfg.limit_lo[1] = cfg.limit_lo[2] = -4;
    cfg.limit_hi[0] = cfg.limit_hi[1] = cfg.limit_hi[2] = 4;
    CHECK(vp_simdev_create(s, &cfg, (double[3]){ 3, 1.4, 0 }, &d) == VP_OK);
    CHECK(vp_simdev_move(d, (double[3]){ -3, 1.4, 0 }, &mr) == VP_EABORT && mr.collided && mr.length == 0);
    CHECK(vp_simdev_move(d, (double[3]){ 3, 1.6, 0 }, &mr) == VP_OK && !mr.collided);
    CHECK(vp_simdev_move(d, (double[3]){ -3, 1.6, 0 }, &mr) == VP_OK && !mr.collided);   /* 0.6 from the sphere */
    CHECK(vp_simdev_move(d, (double[3]){ -5, 1.6, 0 }, &mr) == VP_ERANGE);
    vp_simdev_position(d, p);
    CHECK(p[0] == -3 && p[1] == 1.6);
    vp_simdev_stats(d, &st);
    CHECK(st.refused_moves == 2 && st.collisions == 1 && st.moves == 2 && fabs(st.travel - 6.2) < 1e-12);
    vp_simdev_destroy(d);

    /* noise and dropouts: statistics and reproducibility */
    memset(&cfg, 0, sizeof cfg);
    cfg.noise_sigma = 0.01;
    cfg.dropout = 0.3;
    cfg.seed = 42;
    CHECK(vp_simdev_create(s, &cfg, start, &d) == VP_OK);
    CHECK(vp_simdev_create(s, &cfg, start, &d2) == VP_OK);
    {
        double sum = 0, sum2 = 0;
        int hits = 0, n = 40000, same = 1;
        for (i = 0; i < n; i++) {
            vp_simdev_probe(d, mx, 10, &pr);
            vp_simdev_probe(d2, mx, 10, &pr2);
            if (pr.hit != pr2.hit || pr.t != pr2.t) same = 0;
            if (pr.hit) { hits++; sum += pr.t; sum2 += pr.t * pr.t; CHECK(pr.true_t == 2); }
        }
        sum /= hits;
        sum2 = sqrt(sum2 / hits - sum * sum);
        CHECK(same);
        CHECKF(fabs((double)hits / n - 0.7) < 0.01, "hit rate %g", (double)hits / n);
        CHECKF(fabs(sum - 2) < 4 * 0.01 / sqrt(hits), "mean %g", sum);
        CHECKF(fabs(sum2 - 0.01) < 0.0005, "sigma %g", sum2);
        vp_simdev_stats(d, &st);
        CHECK(st.dropouts == (unsigned long)(n - hits) && st.misses == st.dropouts && st.hits == (unsigned long)hits);
    }
    vp_simdev_destroy(d2);
    cfg.seed = 43;
    CHECK(vp_simdev_create(s, &cfg, start, &d2) == VP_OK);
    {
        int differ = 0;
        for (i = 0; i < 100; i++) {
            vp_simdev_probe(d, mx, 10, &pr);
            vp_simdev_probe(d2, mx, 10, &pr2);
            differ += pr.hit != pr2.hit || pr.t != pr2.t;
        }
        CHECK(differ > 50);
    }
    vp_simdev_destroy(d); vp_simdev_destroy(d2);

    /* minimum and maximum range */
    memset(&cfg, 0, sizeof cfg);
    cfg.min_range = 0.1;
    cfg.max_range = 1.0;
    CHECK(vp_simdev_create(s, &cfg, (double[3]){ 1.05, 0, 0 }, &d) == VP_OK);
    CHECK(vp_simdev_probe(d, mx, 10, &pr) == VP_OK && !pr.hit && pr.too_close && fabs(pr.true_t - 0.05) < 1e-12);
    CHECK(vp_simdev_move(d, (double[3]){ 1.5, 0, 0 }, &mr) == VP_OK);
    CHECK(vp_simdev_probe(d, mx, 10, &pr) == VP_OK && pr.hit && fabs(pr.t - 0.5) < 1e-12);
    CHECK(vp_simdev_move(d, (double[3]){ 2.5, 0, 0 }, &mr) == VP_OK);
    CHECK(vp_simdev_probe(d, mx, 10, &pr) == VP_OK && !pr.hit);   /* 1.5 away, range capped at 1 */
    vp_simdev_stats(d, &st);
    CHECK(st.too_close == 1 && st.hits == 1 && st.misses == 1);
    vp_simdev_destroy(d);
    CHECK(vp_simdev_create(s, &(vp_simdev_config_t){ .dropout = 2 }, start, &d) == VP_EINVAL);
    vp_surface_close(s);

    /* a genus-2 object: the device reports exactly what the surface ray says */
    CHECK(vp_surface_open("genus2", &s, err, sizeof err) == VP_OK);
    memset(&cfg, 0, sizeof cfg);
    CHECK(vp_simdev_create(s, &cfg, (double[3]){ 0, 0, 2 }, &d) == VP_OK);
    for (i = 0; i < 200; i++) {
        double dir[3] = { cos(i * 0.1) * 0.6, sin(i * 0.1) * 0.6, -0.8 }, t;
        int h = vp_surface_ray(s, (double[3]){ 0, 0, 2 }, dir, 5, &t);
        CHECK(vp_simdev_probe(d, dir, 5, &pr) == VP_OK && pr.hit == h && (!h || pr.t == t));
    }
    vp_simdev_destroy(d);
    vp_surface_close(s);
    return vp_test_done("test_simdev");
}
