// CGAL on triangle-mesh objects, for the accuracy test and the `make bench` anchors:
//   cgal_object mesh OBJECT.off H RADIUS OUT.off  CGAL's surface mesher (make_surface_mesh, angle
//       30 degrees, distance bound H, radius bound RADIUS, manifold tag) on the object seen
//       through an inside/outside oracle (Side_of_triangle_mesh); writes OUT.off; one JSON line
//   cgal_object hausdorff A.off B.off             two-sided Hausdorff distance of two triangle
//       meshes (PMP::approximate_symmetric_Hausdorff_distance, 20 points per unit of area
//       relative to the diagonal); one JSON line. Used to measure every mesher's output the
//       same way, independently of voroprobe's own measure.
//   cgal_object distance A.off POINTS             each point's distance to the triangle mesh A
//       (an AABB tree of A's faces), one line each; POINTS: "x y z" lines
//   cgal_object topology A.off                    whether A's triangles make a closed 2-manifold
//       (PMP::is_polygon_soup_a_polygon_mesh on the soup as read, then CGAL::is_closed on the
//       Surface_mesh it becomes), its components and genus (Euler characteristic); one JSON line
//   cgal_object edges A.off                       the edges of the 3D Delaunay triangulation of
//       A's vertices (CGAL's Delaunay_triangulation_3), one "i j" line each (vertex indices, i < j)
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh_default_triangulation_3.h>
#include <CGAL/Complex_2_in_triangulation_3.h>
#include <CGAL/make_surface_mesh.h>
#include <CGAL/Implicit_surface_3.h>
#include <CGAL/IO/facets_in_complex_2_to_triangle_mesh.h>
#include <CGAL/Polygon_mesh_processing/IO/polygon_mesh_io.h>
#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/Random.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/IO/polygon_soup_io.h>
#include <algorithm>
#include <chrono>
#include <utility>
#include <vector>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Surface_mesh<K::Point_3> Mesh;
typedef CGAL::Surface_mesh_default_triangulation_3 Tr;
typedef CGAL::Complex_2_in_triangulation_3<Tr> C2t3;
typedef Tr::Geom_traits GT;
namespace PMP = CGAL::Polygon_mesh_processing;

static bool read_mesh(const char *path, Mesh &m)
{
    if (!CGAL::IO::read_polygon_mesh(path, m) || m.number_of_faces() == 0) {
        std::fprintf(stderr, "cgal_object: cannot read %s as a triangle mesh\n", path);
        return false;
    }
    return true;
}

static double diagonal(const Mesh &m)
{
    CGAL::Bbox_3 b = PMP::bbox(m);
    double dx = b.xmax() - b.xmin(), dy = b.ymax() - b.ymin(), dz = b.zmax() - b.zmin();
    return std::sqrt(dx * dx + dy * dy + dz * dz);
}

// -1 inside the object, +1 outside (the parity of a ray: the mesh's orientation does not matter)
struct Inside_fn {
    const CGAL::Side_of_triangle_mesh<Mesh, K> *side;
    GT::FT operator()(const GT::Point_3 &p) const
    {
        return (*side)(K::Point_3(p.x(), p.y(), p.z())) == CGAL::ON_BOUNDED_SIDE ? -1.0 : 1.0;
    }
};

static int mesh_cmd(const char *in, double h, double radius, const char *out)
{
    Mesh m;
    if (!read_mesh(in, m)) return 1;
    CGAL::Side_of_triangle_mesh<Mesh, K> side(m);
    CGAL::Bbox_3 b = PMP::bbox(m);
    // a point inside: CGAL's oracle needs the bounding sphere's centre inside the object
    CGAL::Random rnd(1);
    K::Point_3 c;
    int tries = 0;
    do {
        c = K::Point_3(rnd.get_double(b.xmin(), b.xmax()), rnd.get_double(b.ymin(), b.ymax()),
                       rnd.get_double(b.zmin(), b.zmax()));
    } while (side(c) != CGAL::ON_BOUNDED_SIDE && ++tries < 1000000);
    if (tries >= 1000000) { std::fprintf(stderr, "cgal_object: no inside point found\n"); return 1; }
    double r2 = 0;
    for (int i = 0; i < 8; i++) {
        double x = (i & 1 ? b.xmax() : b.xmin()) - c.x(), y = (i & 2 ? b.ymax() : b.ymin()) - c.y(),
               z = (i & 4 ? b.zmax() : b.zmin()) - c.z();
        r2 = std::max(r2, 1.0201 * (x * x + y * y + z * z));
    }
    Inside_fn f{&side};
    Tr tr;
    C2t3 c2t3(tr);
    auto t0 = std::chrono::steady_clock::now();
    CGAL::Implicit_surface_3<GT, Inside_fn> surface(f, GT::Sphere_3(GT::Point_3(c.x(), c.y(), c.z()), r2),
                                                    1e-7 / std::sqrt(r2));
    CGAL::Surface_mesh_default_criteria_3<Tr> criteria(30.0, radius, h);
    CGAL::make_surface_mesh(c2t3, surface, criteria, CGAL::Manifold_tag(), 20);
    auto t1 = std::chrono::steady_clock::now();
    Mesh outm;
    CGAL::facets_in_complex_2_to_triangle_mesh(c2t3, outm);
    if (!CGAL::IO::write_polygon_mesh(out, outm, CGAL::parameters::stream_precision(17))) {
        std::fprintf(stderr, "cgal_object: cannot write %s\n", out);
        return 1;
    }
    std::printf("{\"object\":\"%s\",\"distance_bound\":%.6g,\"radius_bound\":%.6g,\"vertices\":%zu,"
                "\"facets\":%zu,\"seconds\":%.4f}\n",
                in, h, radius, (size_t)outm.number_of_vertices(), (size_t)outm.number_of_faces(),
                std::chrono::duration<double>(t1 - t0).count());
    return 0;
}

static int hausdorff_cmd(const char *a, const char *b)
{
    Mesh ma, mb;
    if (!read_mesh(a, ma) || !read_mesh(b, mb)) return 1;
    double d = diagonal(ma);
    // points per unit of area: about 4e5 over a mesh of the size of its bounding box
    double ppa = 4e5 / (d * d);
    double h1 = PMP::approximate_Hausdorff_distance<CGAL::Sequential_tag>(
        ma, mb, CGAL::parameters::number_of_points_per_area_unit(ppa).random_seed(1), CGAL::parameters::default_values());
    double h2 = PMP::approximate_Hausdorff_distance<CGAL::Sequential_tag>(
        mb, ma, CGAL::parameters::number_of_points_per_area_unit(ppa).random_seed(1), CGAL::parameters::default_values());
    // where the object is farthest from the mesh (A's sample point, for a look at the place)
    typedef CGAL::AABB_face_graph_triangle_primitive<Mesh> Prim;
    typedef CGAL::AABB_tree<CGAL::AABB_traits<K, Prim>> Tree;
    std::vector<K::Point_3> pts;
    PMP::sample_triangle_mesh(ma, std::back_inserter(pts),
                              CGAL::parameters::number_of_points_per_area_unit(ppa).random_seed(2));
    Tree tree(faces(mb).first, faces(mb).second, mb);
    tree.accelerate_distance_queries();
    double worst = -1;
    K::Point_3 wp;
    for (const K::Point_3 &p : pts) {
        double q = tree.squared_distance(p);
        if (q > worst) { worst = q; wp = p; }
    }
    std::printf("{\"a\":\"%s\",\"b\":\"%s\",\"a_to_b\":%.9g,\"b_to_a\":%.9g,\"hausdorff\":%.9g,\"diagonal\":%.9g,"
                "\"worst_a\":[%.6g,%.6g,%.6g]}\n",
                a, b, h1, h2, std::max(h1, h2), d, wp.x(), wp.y(), wp.z());
    return 0;
}

static int distance_cmd(const char *a, const char *pts)
{
    typedef CGAL::AABB_face_graph_triangle_primitive<Mesh> Prim;
    typedef CGAL::AABB_tree<CGAL::AABB_traits<K, Prim>> Tree;
    Mesh m;
    if (!read_mesh(a, m)) return 1;
    std::ifstream in(pts);
    if (!in) { std::fprintf(stderr, "cannot read %s\n", pts); return 1; }
    Tree tree(faces(m).first, faces(m).second, m);
    tree.accelerate_distance_queries();
    double x, y, z;
    while (in >> x >> y >> z) std::printf("%.9g\n", std::sqrt(tree.squared_distance(K::Point_3(x, y, z))));
    return 0;
}

static int edges_cmd(const char *a)
{
    typedef CGAL::Triangulation_vertex_base_with_info_3<unsigned, K> Vb;
    typedef CGAL::Triangulation_data_structure_3<Vb> Tds;
    typedef CGAL::Delaunay_triangulation_3<K, Tds> Dt;
    Mesh m;
    if (!read_mesh(a, m)) return 1;
    std::vector<std::pair<K::Point_3, unsigned>> pts;
    for (Mesh::Vertex_index v : m.vertices()) pts.push_back(std::make_pair(m.point(v), (unsigned)v.idx()));
    Dt dt(pts.begin(), pts.end());
    std::vector<std::pair<unsigned, unsigned>> out;
    for (Dt::Finite_edges_iterator e = dt.finite_edges_begin(); e != dt.finite_edges_end(); ++e) {
        unsigned i = e->first->vertex(e->second)->info(), j = e->first->vertex(e->third)->info();
        out.push_back(std::make_pair(std::min(i, j), std::max(i, j)));
    }
    std::sort(out.begin(), out.end());
    for (const std::pair<unsigned, unsigned> &e : out) std::printf("%u %u\n", e.first, e.second);
    return 0;
}

static int topology_cmd(const char *a)
{
    std::vector<K::Point_3> pts;
    std::vector<std::vector<std::size_t>> tris;
    if (!CGAL::IO::read_polygon_soup(a, pts, tris)) { std::fprintf(stderr, "cannot read %s\n", a); return 1; }
    bool manifold = PMP::is_polygon_soup_a_polygon_mesh(tris), closed = false;
    long comps = -1, genus = -1;
    if (manifold) {
        Mesh m;
        PMP::polygon_soup_to_polygon_mesh(pts, tris, m);
        closed = CGAL::is_closed(m);
        comps = (long)PMP::connected_components(m, m.add_property_map<Mesh::Face_index, std::size_t>("f:cc").first);
        long chi = (long)m.number_of_vertices() - (long)m.number_of_edges() + (long)m.number_of_faces();
        if (closed) genus = (2 * comps - chi) / 2;
    }
    std::printf("{\"mesh\":\"%s\",\"manifold\":%s,\"closed\":%s,\"components\":%ld,\"genus\":%ld}\n", a,
                manifold ? "true" : "false", closed ? "true" : "false", comps, genus);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc == 3 && !std::strcmp(argv[1], "topology")) return topology_cmd(argv[2]);
    if (argc == 3 && !std::strcmp(argv[1], "edges")) return edges_cmd(argv[2]);
    if (argc == 4 && !std::strcmp(argv[1], "distance")) return distance_cmd(argv[2], argv[3]);
    if (argc == 6 && !std::strcmp(argv[1], "mesh"))
        return mesh_cmd(argv[2], std::atof(argv[3]), std::atof(argv[4]), argv[5]);
    if (argc == 4 && !std::strcmp(argv[1], "hausdorff")) return hausdorff_cmd(argv[2], argv[3]);
    std::fprintf(stderr, "usage: cgal_object mesh OBJECT.off H RADIUS OUT.off\n"
                         "       cgal_object hausdorff A.off B.off\n"
                         "       cgal_object topology A.off\n"
                         "       cgal_object edges A.off\n"
                         "       cgal_object distance A.off POINTS\n");
    return 2;
}
