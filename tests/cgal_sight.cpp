// An independent, exact check of vp_planner_spot_hidden (a miss must be seen): it shares no code
// with voroprobe (CGAL's exact predicates on the doubles as read, parsed with strtod).
//
// usage: cgal_sight CASES
//
// CASES (tests/core/test_sight --cases): a line `facets N`, N lines of an occluder's three corners
// (9 numbers), a line `queries`, then one line per sight triangle: its three corners (the camera,
// the beam's origin, the beam's end: 9 numbers) and the planner's answer (0 or 1).
// The answer must be 1 exactly when the sight triangle meets a facet (CGAL::do_intersect of two
// Triangle_3: any common point counts) or lies in one plane with it (every corner of one on the
// other's plane: the planner's documented rule, conservative), else 0.
// Prints a line per disagreement (at most 20) and a summary; exit 0 when all agree, 1 otherwise,
// 2 on a bad file.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/intersections.h>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <array>
#include <vector>

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef K::Point_3 P;
typedef K::Triangle_3 T;

static bool read_tri(FILE *f, P *p)
{
    double x[9];
    for (int i = 0; i < 9; i++)
        if (fscanf(f, "%lf", &x[i]) != 1) return false;
    for (int i = 0; i < 3; i++) p[i] = P(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
    return true;
}

static bool in_plane(const P *a, const P *b)
{
    for (int i = 0; i < 3; i++)
        if (CGAL::orientation(a[0], a[1], a[2], b[i]) != CGAL::COPLANAR) return false;
    return true;
}

int main(int argc, char **argv)
{
    if (argc != 2) { fprintf(stderr, "usage: cgal_sight CASES\n"); return 2; }
    FILE *f = fopen(argv[1], "r");
    if (!f) { perror(argv[1]); return 2; }
    unsigned n;
    char word[32];
    if (fscanf(f, "%31s %u", word, &n) != 2 || strcmp(word, "facets")) { fprintf(stderr, "bad header\n"); return 2; }
    std::vector<std::array<P, 3>> F(n);
    for (unsigned i = 0; i < n; i++)
        if (!read_tri(f, F[i].data()) || CGAL::collinear(F[i][0], F[i][1], F[i][2])) {
            fprintf(stderr, "facet %u: bad or flat\n", i);
            return 2;
        }
    if (fscanf(f, "%31s", word) != 1 || strcmp(word, "queries")) { fprintf(stderr, "no queries\n"); return 2; }
    unsigned q = 0, bad = 0, hidden = 0, flat = 0, coplanar = 0;
    P s[3];
    int ans;
    while (read_tri(f, s)) {
        if (fscanf(f, "%d", &ans) != 1 || (ans != 0 && ans != 1)) { fprintf(stderr, "query %u: no answer\n", q); return 2; }
        q++;
        if (CGAL::collinear(s[0], s[1], s[2])) { flat++; continue; } // no triangle to test
        T st(s[0], s[1], s[2]);
        int want = 0;
        for (unsigned i = 0; i < n && !want; i++) {
            if (in_plane(s, F[i].data()) || in_plane(F[i].data(), s)) { want = 1; coplanar++; break; }
            if (CGAL::do_intersect(st, T(F[i][0], F[i][1], F[i][2]))) want = 1;
        }
        hidden += want;
        if (want != ans) {
            if (++bad <= 20) printf("query %u: the planner says %d, CGAL %d\n", q, ans, want);
        }
    }
    fclose(f);
    printf("%u sight triangles against %u facets: %u meet one (%u in a facet's plane), %u flat skipped; "
           "%u disagree\n", q, n, hidden, coplanar, flat, bad);
    return bad || q == 0 ? 1 : 0;
}
