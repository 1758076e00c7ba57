// Anchors for `make bench` (bench/delaunay.sh): CGAL's 3D Delaunay triangulation of a TetGen
// .node file, timed the same way as `voroprobe bench-delaunay` (sort + insertion, file reading
// excluded); with REMOVE_FILE (one 0-based index into the .node file per line), the
// triangulation of all points is built untimed with the same spatial sort, keeping each point's
// handle, and Delaunay_triangulation_3::remove of the listed points, in that order, is timed.
// Prints one JSON line. Built by bench/delaunay.sh when libcgal-dev is installed.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/spatial_sort.h>
#include <CGAL/Spatial_sort_traits_adapter_3.h>
#include <CGAL/property_map.h>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <vector>

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Delaunay_triangulation_3<K> DT;
typedef DT::Vertex_handle VH;

static int removal(const std::vector<K::Point_3> &pts, const char *path)
{
    long n = (long)pts.size();
    std::ifstream rin(path);
    std::vector<long> rm;
    for (long r; rin >> r;) {
        if (r < 0 || r >= n) { std::fprintf(stderr, "bad index %ld\n", r); return 1; }
        rm.push_back(r);
    }
    DT dt;
    std::vector<VH> vh(n);
    {
        std::vector<std::size_t> order(n);
        for (long i = 0; i < n; i++) order[i] = (std::size_t)i;
        typedef CGAL::Pointer_property_map<K::Point_3>::const_type Pmap;
        typedef CGAL::Spatial_sort_traits_adapter_3<K, Pmap> Tr;
        CGAL::spatial_sort(order.begin(), order.end(), Tr(CGAL::make_property_map(pts)));
        VH hint;
        for (std::size_t i : order) hint = vh[i] = dt.insert(pts[i], hint);
    }
    if ((long)dt.number_of_vertices() != n) { std::fprintf(stderr, "duplicate points\n"); return 1; }
    auto t0 = std::chrono::steady_clock::now();
    for (long r : rm) dt.remove(vh[r]);
    auto t1 = std::chrono::steady_clock::now();
    double s = std::chrono::duration<double>(t1 - t0).count();
    std::printf("{\"points\":%ld,\"removed\":%zu,\"tets\":%zu,\"vertices\":%zu,\"seconds\":%.4f}\n",
                n, rm.size(), (size_t)dt.number_of_finite_cells(), (size_t)dt.number_of_vertices(), s);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc != 2 && argc != 3) { std::fprintf(stderr, "usage: cgal_delaunay FILE.node [REMOVE_FILE]\n"); return 2; }
    std::ifstream in(argv[1]);
    long n, dim, a, b;
    if (!(in >> n >> dim >> a >> b) || dim != 3) { std::fprintf(stderr, "bad .node header\n"); return 1; }
    std::vector<K::Point_3> pts;
    pts.reserve(n);
    for (long i = 0; i < n; i++) {
        long idx; double x, y, z;
        if (!(in >> idx >> x >> y >> z)) { std::fprintf(stderr, "bad .node line %ld\n", i + 2); return 1; }
        pts.push_back(K::Point_3(x, y, z));
    }
    if (argc == 3) return removal(pts, argv[2]);
    auto t0 = std::chrono::steady_clock::now();
    DT dt(pts.begin(), pts.end());
    auto t1 = std::chrono::steady_clock::now();
    double s = std::chrono::duration<double>(t1 - t0).count();
    std::printf("{\"points\":%ld,\"tets\":%zu,\"seconds\":%.4f,\"points_per_second\":%.0f}\n",
                n, (size_t)dt.number_of_finite_cells(), s, n / s);
    return 0;
}
