// Anchor for `make bench` (bench/delaunay.sh): CGAL's Delaunay_triangulation_3::remove on a TetGen
// .node file. Builds the triangulation of all points (not timed), then removes the points listed
// in REMOVE_FILE (one 0-based index into the .node file per line) in that order, timed.
// Prints one JSON line: points, removed, finite tets and vertices after, seconds.
// Built by bench/delaunay.sh when libcgal-dev is installed.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Delaunay_triangulation_3.h>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <vector>

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Delaunay_triangulation_3<K> DT;
typedef DT::Vertex_handle VH;

int main(int argc, char **argv)
{
    if (argc != 3) { std::fprintf(stderr, "usage: cgal_remove FILE.node REMOVE_FILE\n"); return 2; }
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
    std::ifstream rin(argv[2]);
    std::vector<long> rm;
    for (long r; rin >> r;) {
        if (r < 0 || r >= n) { std::fprintf(stderr, "bad index %ld\n", r); return 1; }
        rm.push_back(r);
    }
    // the same spatial sort as DT's range constructor, keeping each point's handle
    DT dt;
    std::vector<VH> vh(n);
    {
        std::vector<std::size_t> order(n);
        for (long i = 0; i < n; i++) order[i] = (std::size_t)i;
        typedef CGAL::Pointer_property_map<K::Point_3>::type Pmap;
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
