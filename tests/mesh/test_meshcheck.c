/* vp_meshcheck on meshes with known answers: icosphere, torus grid, a hole, two components,
 * a non-manifold edge and vertex, a flipped face, inward orientation, degenerate faces; and the
 * Hausdorff distance of an icosphere to the unit sphere against its analytic value. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "vp_hausdorff.h"
#include "vp_meshcheck.h"
#include "vp_meshgen.h"
#include "vp_status.h"
#include "vp_surface.h"
#include "vp_test.h"

static vp_meshcheck_t analyze(const vp_mesh_t *m)
{
    vp_meshcheck_t r;
    int st = vp_meshcheck_analyze(m, &r);
    CHECK(st == VP_OK);
    return r;
}

/* m without its last k faces */
static void drop_faces(vp_mesh_t *m, size_t k) { m->nt -= k; }

static void topology(void)
{
    vp_mesh_t ico, tor, two, tmp;
    vp_meshcheck_t r;
    double off[3] = { 4, 0, 0 };
    vp_mesh_init(&ico); vp_mesh_init(&tor); vp_mesh_init(&two); vp_mesh_init(&tmp);
    CHECK(vp_meshgen_icosphere(3, &ico) == VP_OK);
    CHECK(vp_meshgen_torus(1.0, 0.3, 40, 16, &tor) == VP_OK);

    r = analyze(&ico);
    CHECK(r.closed_manifold && r.oriented && r.outward && r.components == 1 && r.euler == 2 && r.genus == 0);
    CHECK(r.edges == 1920 && r.boundary_edges == 0 && r.nonmanifold_edges == 0 && r.nonmanifold_vertices == 0);
    CHECK(r.comp[0].closed && fabs(r.comp[0].volume - 4.18879) < 0.05 && r.min_angle_deg > 50 && r.min_angle_deg < 60);
    vp_meshcheck_free(&r);

    r = analyze(&tor);
    CHECK(r.closed_manifold && r.outward && r.components == 1 && r.euler == 0 && r.genus == 1);
    CHECK(fabs(r.comp[0].volume - 2 * 3.14159265 * 3.14159265 * 0.09) < 0.08);   /* inscribed polygons lose ~3% */
    vp_meshcheck_free(&r);

    /* a hole: one face removed from the sphere, and three adjacent faces from the torus */
    drop_faces(&ico, 1);
    r = analyze(&ico);
    CHECK(!r.closed_manifold && r.boundary_edges == 3 && r.comp[0].boundary_loops == 1 && r.genus == 0 && r.euler == 1);
    CHECK(r.nonmanifold_vertices == 0 && r.oriented && !r.outward);
    vp_meshcheck_free(&r);
    ico.nt += 1;
    drop_faces(&tor, 2);   /* one grid quad */
    r = analyze(&tor);
    CHECK(r.boundary_edges == 4 && r.comp[0].boundary_loops == 1 && r.genus == 1 && r.euler == -1);
    vp_meshcheck_free(&r);
    tor.nt += 2;

    /* two components */
    CHECK(vp_meshgen_icosphere(1, &two) == VP_OK);
    CHECK(vp_meshgen_append(&two, &tor, off) == VP_OK);
    r = analyze(&two);
    CHECK(r.components == 2 && r.closed_manifold && r.outward && r.genus == 1 && r.euler == 2);
    CHECK(r.comp[0].genus == 0 && r.comp[1].genus == 1 && r.comp[0].faces == 80 && r.comp[1].faces == tor.nt);
    CHECK(r.comp_of_face[0] == 0 && r.comp_of_face[two.nt - 1] == 1);
    vp_meshcheck_free(&r);

    /* non-manifold edge: a fin on edge (t0, t1) of the sphere */
    CHECK(vp_mesh_alloc(&tmp, ico.nv + 1, ico.nt + 1) == VP_OK);
    memcpy(tmp.xyz, ico.xyz, ico.nv * 3 * sizeof(double));
    memcpy(tmp.tri, ico.tri, ico.nt * 3 * sizeof(uint32_t));
    tmp.xyz[3 * ico.nv] = 3; tmp.xyz[3 * ico.nv + 1] = 3; tmp.xyz[3 * ico.nv + 2] = 3;
    tmp.tri[3 * ico.nt] = ico.tri[0]; tmp.tri[3 * ico.nt + 1] = ico.tri[1]; tmp.tri[3 * ico.nt + 2] = (uint32_t)ico.nv;
    r = analyze(&tmp);
    CHECK(r.nonmanifold_edges == 1 && !r.closed_manifold && r.genus == -1 && r.boundary_edges == 2 && r.components == 1);
    vp_meshcheck_free(&r);

    /* non-manifold vertex: two spheres sharing one vertex */
    {
        vp_mesh_t a;
        size_t i;
        double o2[3] = { 2, 0, 0 };
        vp_mesh_init(&a);
        CHECK(vp_meshgen_icosphere(1, &a) == VP_OK);
        CHECK(vp_meshgen_append(&a, &a, o2) == VP_OK);
        /* glue: vertex 0 of the second copy becomes vertex 0 of the first */
        for (i = 80 * 3; i < a.nt * 3; i++) if (a.tri[i] == 42) a.tri[i] = 0;
        r = analyze(&a);
        CHECK(r.components == 2 && r.nonmanifold_vertices == 1 && !r.closed_manifold && r.unused_vertices == 1);
        CHECK(r.euler == 3);   /* 83 used vertices - 240 edges + 160 faces */
        vp_meshcheck_free(&r);
        vp_mesh_free(&a);
    }

    /* one flipped face, then all flipped */
    {
        uint32_t s = ico.tri[1];
        size_t f;
        ico.tri[1] = ico.tri[2]; ico.tri[2] = s;
        r = analyze(&ico);
        CHECK(r.misoriented_edges == 3 && !r.oriented && !r.outward && r.genus == -1);
        vp_meshcheck_free(&r);
        for (f = 1; f < ico.nt; f++) { s = ico.tri[3 * f + 1]; ico.tri[3 * f + 1] = ico.tri[3 * f + 2]; ico.tri[3 * f + 2] = s; }
        r = analyze(&ico);
        CHECK(r.oriented && r.closed_manifold && !r.outward && r.comp[0].volume < 0 && r.genus == 0);
        vp_meshcheck_free(&r);
    }

    /* degenerate face and a bad index */
    tmp.tri[3 * ico.nt + 2] = tmp.tri[3 * ico.nt];
    r = analyze(&tmp);
    CHECK(r.degenerate_faces == 1 && !r.closed_manifold);
    vp_meshcheck_free(&r);
    tmp.tri[0] = (uint32_t)tmp.nv;
    CHECK(vp_meshcheck_analyze(&tmp, &r) == VP_EINVAL);
    vp_mesh_free(&ico); vp_mesh_free(&tor); vp_mesh_free(&two); vp_mesh_free(&tmp);
}

static void hausdorff(void)
{
    vp_mesh_t ico;
    vp_surface_t *s;
    vp_hausdorff_t h;
    char err[256];
    double expect = 0;
    size_t f;
    vp_mesh_init(&ico);
    CHECK(vp_meshgen_icosphere(3, &ico) == VP_OK);
    CHECK(vp_surface_open("sphere", &s, err, sizeof err) == VP_OK);
    /* Analytic: every face's plane is at distance sqrt(1 - Rc^2) from the centre (Rc: the
     * circumradius); the worst point is the circumcentre, on both sides. */
    for (f = 0; f < ico.nt; f++) {
        const double *a = ico.xyz + 3 * ico.tri[3 * f], *b = ico.xyz + 3 * ico.tri[3 * f + 1], *c = ico.xyz + 3 * ico.tri[3 * f + 2];
        double la = sqrt(pow(b[0] - c[0], 2) + pow(b[1] - c[1], 2) + pow(b[2] - c[2], 2));
        double lb = sqrt(pow(a[0] - c[0], 2) + pow(a[1] - c[1], 2) + pow(a[2] - c[2], 2));
        double lc = sqrt(pow(a[0] - b[0], 2) + pow(a[1] - b[1], 2) + pow(a[2] - b[2], 2));
        double sp = 0.5 * (la + lb + lc), area = sqrt(sp * (sp - la) * (sp - lb) * (sp - lc));
        double rc = la * lb * lc / (4 * area), e = 1 - sqrt(1 - rc * rc);
        if (e > expect) expect = e;
    }
    CHECK(vp_hausdorff(&ico, s, 20000, 1, &h) == VP_OK);
    printf("icosphere(3) vs unit sphere: Hausdorff %.12g (mesh->surface %.12g, surface->mesh %.12g), analytic %.12g\n",
           h.hausdorff, h.mesh_to_surface, h.surface_to_mesh, expect);
    CHECKF(fabs(h.mesh_to_surface - expect) <= 1e-7 * expect, "mesh->surface %.12g vs %.12g", h.mesh_to_surface, expect);
    CHECKF(fabs(h.surface_to_mesh - expect) <= 1e-7 * expect, "surface->mesh %.12g vs %.12g", h.surface_to_mesh, expect);
    CHECK(h.mean_mesh_to_surface > 0 && h.mean_mesh_to_surface < expect && h.mean_surface_to_mesh < expect);
    /* a shifted copy: the distance grows by the shift (to first order) */
    for (f = 0; f < ico.nv; f++) ico.xyz[3 * f] += 0.1;
    CHECK(vp_hausdorff(&ico, s, 5000, 2, &h) == VP_OK);
    CHECKF(h.hausdorff > 0.1 && h.hausdorff < 0.1 + 2 * expect, "shifted: %g", h.hausdorff);
    vp_surface_close(s);
    vp_mesh_free(&ico);
    /* a torus grid against the torus: vertices are on the surface, the error is in the faces */
    {
        vp_mesh_t tor;
        vp_mesh_init(&tor);
        CHECK(vp_meshgen_torus(1.0, 0.3, 96, 32, &tor) == VP_OK);
        CHECK(vp_surface_open("torus", &s, err, sizeof err) == VP_OK);
        CHECK(vp_hausdorff(&tor, s, 20000, 3, &h) == VP_OK);
        printf("torus grid 96x32 vs torus: Hausdorff %.6g\n", h.hausdorff);
        /* chord sagitta bounds: tube 0.3*(1-cos(pi/32)), ring 1.3*(1-cos(pi/96)) */
        CHECK(h.hausdorff > 0.3 * (1 - cos(3.14159265 / 32)) * 0.9 && h.hausdorff < 0.3 * (1 - cos(3.14159265 / 32)) + 1.3 * (1 - cos(3.14159265 / 96)) + 1e-9);
        vp_surface_close(s);
        vp_mesh_free(&tor);
    }
}

int main(void)
{
    topology();
    hausdorff();
    return vp_test_done("test_meshcheck");
}
