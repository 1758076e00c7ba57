// Anchor for `make bench`: CGAL's 3D Delaunay triangulation of a TetGen .node file, timed the
// same way as `voroprobe bench-delaunay` (sort + insertion, file reading excluded).
// Prints one JSON line. Built only by bench/run.sh when libcgal-dev is installed.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Delaunay_triangulation_3.h>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <vector>

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Delaunay_triangulation_3<K> DT;

int main(int argc, char **argv)
{
    if (argc != 2) { std::fprintf(stderr, "usage: cgal_delaunay FILE.node\n"); return 2; }
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
    auto t0 = std::chrono::steady_clock::now();
    DT dt(pts.begin(), pts.end());
    auto t1 = std::chrono::steady_clock::now();
    double s = std::chrono::duration<double>(t1 - t0).count();
    std::printf("{\"points\":%ld,\"tets\":%zu,\"seconds\":%.4f,\"points_per_second\":%.0f}\n",
                n, (size_t)dt.number_of_finite_cells(), s, n / s);
    return 0;
}
