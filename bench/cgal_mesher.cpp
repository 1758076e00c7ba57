// Anchor for `make bench`: CGAL's surface mesher (Chew / Boissonnat-Oudot refinement, radius
// criterion only) on the anchor surfaces of ANCHORS.md, timed here in the same run as voroprobe.
// usage: cgal_mesher sphere|torus|genus2 RADIUS   -> one JSON line
#include <CGAL/Surface_mesh_default_triangulation_3.h>
#include <CGAL/Complex_2_in_triangulation_3.h>
#include <CGAL/make_surface_mesh.h>
#include <CGAL/Implicit_surface_3.h>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>

typedef CGAL::Surface_mesh_default_triangulation_3 Tr;
typedef CGAL::Complex_2_in_triangulation_3<Tr> C2t3;
typedef Tr::Geom_traits GT;
typedef GT::Sphere_3 Sphere_3;
typedef GT::Point_3 Point_3;
typedef GT::FT FT;
typedef FT (*Function)(Point_3);
typedef CGAL::Implicit_surface_3<GT, Function> Surface_3;

static FT sphere_f(Point_3 p) { return p.x() * p.x() + p.y() * p.y() + p.z() * p.z() - 1.0; }
static double torus_at(double x, double y, double z, double cx)
{
    double q = std::sqrt((x - cx) * (x - cx) + y * y) - 1.0;
    return q * q + z * z - 0.09;
}
static FT torus_f(Point_3 p) { return torus_at(p.x(), p.y(), p.z(), 0.0); }
static FT genus2_f(Point_3 p)
{
    double a = torus_at(p.x(), p.y(), p.z(), -1.0), b = torus_at(p.x(), p.y(), p.z(), 1.0);
    return std::min(a, b) - std::log(1.0 + std::exp(-50.0 * std::fabs(a - b))) / 50.0;
}

int main(int argc, char **argv)
{
    if (argc != 3) { std::fprintf(stderr, "usage: cgal_mesher sphere|torus|genus2 RADIUS\n"); return 2; }
    Function f = !std::strcmp(argv[1], "sphere") ? sphere_f : !std::strcmp(argv[1], "torus") ? torus_f
               : !std::strcmp(argv[1], "genus2") ? genus2_f : nullptr;
    if (!f) { std::fprintf(stderr, "unknown surface %s\n", argv[1]); return 2; }
    double r = std::atof(argv[2]), R = f == genus2_f ? 2.6 : 1.6;
    Tr tr;
    C2t3 c2t3(tr);
    auto t0 = std::chrono::steady_clock::now();
    Surface_3 surface(f, Sphere_3(CGAL::ORIGIN, R * R), 1e-6);
    CGAL::Surface_mesh_default_criteria_3<Tr> criteria(0.0, r, 1e6);
    CGAL::make_surface_mesh(c2t3, surface, criteria, CGAL::Non_manifold_tag());
    auto t1 = std::chrono::steady_clock::now();
    std::printf("{\"surface\":\"%s\",\"radius\":%g,\"vertices\":%zu,\"facets\":%zu,\"seconds\":%.4f}\n",
                argv[1], r, (size_t)tr.number_of_vertices(), (size_t)c2t3.number_of_facets(),
                std::chrono::duration<double>(t1 - t0).count());
    return 0;
}
