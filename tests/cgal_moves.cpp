// An independent, exact check of a session's moves against the true object (issue 12): it
// shares no code with voroprobe (its own OFF reader, CGAL's exact predicates).
//
// usage: cgal_moves MESH.off MOVES [--start X,Y,Z] [--list N] [--lag MM]
//
// MESH.off: a plain OFF file (no scale or position: the object as `sim --surface off:MESH.off`
//   sees it). '#' starts a comment; polygons are fanned from their first corner, as voroprobe's
//   reader does.
// MOVES: either
//   - the CSV of `voroprobe log dump LOG --csv` (columns found by name: seq, type, target_x,
//     target_y, target_z); the CSV has no start position, so --start gives the header's start
//     (the `# start X Y Z` line of `voroprobe log dump LOG`), or
//   - a move list: '#' comments, one line `start X Y Z`, then one line per move,
//     `move X Y Z` or `move SEQ X Y Z` (SEQ: the log record, for the report).
//   A MOVE goes from the previous MOVE's target (the start position before the first one).
//
// For every move, the closed segment [from, to] is tested against every closed triangle of the
// mesh with CGAL::Exact_predicates_inexact_constructions_kernel (exact predicates on the doubles
// as read: every number is parsed with strtod, so the 17 digits of the dump are the same doubles
// the planner used) through an AABB tree:
//   through: the segment meets a triangle (crossing, touching an edge or a vertex, lying in a
//            face: any common point counts);
//   inside:  the segment meets no triangle and both ends are inside the closed mesh
//            (CGAL::Side_of_triangle_mesh, ray parity: the mesh's orientation does not matter).
// A zero-area triangle (collinear corners) has no plane for the triangle tests; its point set
// is the union of its edges, tested exactly as segments (and left out of the ray parity, where
// it has no area to cross).
// A move the contact switch stopped ends at the touch (a `contact` line or event after it): its
// last 1e-9 is left out, and the next move's first 1e-9 (the way back from the touch). A machine
// logs where its switch read closed, which lies past the surface by the switch's lag and the
// carriages' backlash: --lag MM leaves out the last MM of such a move (and the first MM of the
// next) instead, at most all but 1e-9 of it.
// Prints "moves N, through M, inside K, first R (record S)" as its last line (R: the 1-based
// number of the first offending move, "none" if there is none). Exit status: 0 no offending
// move, 1 some, 2 bad input.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef K::Point_3 Point;
typedef K::Segment_3 Segment;
typedef CGAL::Surface_mesh<Point> Mesh;
typedef CGAL::Side_of_triangle_mesh<Mesh, K> Side;
typedef Side::AABB_tree Tree;   // AABB_face_graph_triangle_primitive<Mesh>
typedef std::vector<Segment>::const_iterator Seg_iterator;
typedef CGAL::AABB_segment_primitive<K, Seg_iterator> Seg_primitive;
typedef CGAL::AABB_tree<CGAL::AABB_traits<K, Seg_primitive> > Seg_tree;

static void die(const std::string &msg)
{
    std::fprintf(stderr, "cgal_moves: %s\n", msg.c_str());
    std::exit(2);
}

static bool parse_double(const std::string &tok, double *v)
{
    char *end;
    errno = 0;
    *v = std::strtod(tok.c_str(), &end);
    return end != tok.c_str() && *end == 0 && std::isfinite(*v);
}

static bool parse_long(const std::string &tok, long long *v)
{
    char *end;
    errno = 0;
    *v = std::strtoll(tok.c_str(), &end, 10);
    return end != tok.c_str() && *end == 0 && errno != ERANGE;
}

// ---------- OFF: tokens with '#' comments; extra values after a vertex or face are skipped ----------

struct Lexer {
    std::string s;
    size_t pos = 0;
    bool at_line_end() {   // only blanks (or a comment) before the next newline
        size_t p = pos;
        while (p < s.size() && (s[p] == ' ' || s[p] == '\t' || s[p] == '\r')) p++;
        return p >= s.size() || s[p] == '\n' || s[p] == '#';
    }
    void skip_line() { while (pos < s.size() && s[pos] != '\n') pos++; }
    bool token(std::string *t) {
        for (;;) {
            while (pos < s.size() && std::isspace((unsigned char)s[pos])) pos++;
            if (pos < s.size() && s[pos] == '#') { skip_line(); continue; }
            break;
        }
        if (pos >= s.size()) return false;
        size_t b = pos;
        while (pos < s.size() && !std::isspace((unsigned char)s[pos]) && s[pos] != '#') pos++;
        *t = s.substr(b, pos - b);
        return true;
    }
};

static void read_off(const char *path, std::vector<Point> *pts, std::vector<std::array<size_t, 3> > *tris)
{
    std::ifstream f(path, std::ios::binary);
    if (!f) die(std::string(path) + ": cannot open");
    std::stringstream ss;
    ss << f.rdbuf();
    Lexer lx;
    lx.s = ss.str();
    if (lx.s.find('\0') != std::string::npos) die(std::string(path) + ": NUL byte in the file");
    std::string t;
    long long nv, nf, ne;
    if (!lx.token(&t) || (t != "OFF" && t != "COFF" && t != "NOFF" && t != "CNOFF")) die(std::string(path) + ": not an OFF file");
    if (!lx.token(&t) || !parse_long(t, &nv) || !lx.token(&t) || !parse_long(t, &nf) ||
        !lx.token(&t) || !parse_long(t, &ne) || nv < 0 || nf < 0 || nv > 100000000 || nf > 100000000)
        die(std::string(path) + ": bad counts");
    lx.skip_line();
    for (long long i = 0; i < nv; i++) {
        double c[3];
        for (int k = 0; k < 3; k++)
            if (!lx.token(&t) || !parse_double(t, &c[k])) die(std::string(path) + ": bad vertex " + std::to_string(i));
        lx.skip_line();
        pts->push_back(Point(c[0], c[1], c[2]));
    }
    for (long long i = 0; i < nf; i++) {
        long long n, first = -1, prev = -1, cur;
        if (!lx.token(&t) || !parse_long(t, &n) || n < 3 || n > 1000000) die(std::string(path) + ": bad face " + std::to_string(i));
        for (long long j = 0; j < n; j++) {
            if (!lx.token(&t) || !parse_long(t, &cur) || cur < 0 || cur >= nv) die(std::string(path) + ": bad index in face " + std::to_string(i));
            if (j == 0) first = cur;
            else if (j >= 2) tris->push_back({ (size_t)first, (size_t)prev, (size_t)cur });
            prev = cur;
        }
        lx.skip_line();
    }
}

// ---------- moves ----------

// contact: the head's contact switch stopped the move at `to` (a point of the surface)
struct Move { Point to; long long seq; bool contact; };

// the share of a move at a contact point left out of the check (the touch itself)
static const double CONTACT_SHARE = 1e-9;

static std::vector<std::string> split_csv(const std::string &line)
{
    std::vector<std::string> out;
    std::string cur;
    bool q = false;
    for (size_t i = 0; i < line.size(); i++) {
        char c = line[i];
        if (q) {
            if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') { cur += '"'; i++; }
            else if (c == '"') q = false;
            else cur += c;
        } else if (c == '"') q = true;
        else if (c == ',') { out.push_back(cur); cur.clear(); }
        else if (c != '\r') cur += c;
    }
    out.push_back(cur);
    return out;
}

static bool parse_point(const std::string &a, const std::string &b, const std::string &c, Point *p)
{
    double x, y, z;
    if (!parse_double(a, &x) || !parse_double(b, &y) || !parse_double(c, &z)) return false;
    *p = Point(x, y, z);
    return true;
}

static void read_moves(const char *path, bool *have_start, Point *start, std::vector<Move> *moves)
{
    std::ifstream f(path);
    if (!f) die(std::string(path) + ": cannot open");
    std::string line;
    int col_seq = -1, col_type = -1, col_x = -1, col_y = -1, col_z = -1, col_ev = -1, col_px = -1;
    bool csv = false;
    long long lineno = 0;
    while (std::getline(f, line)) {
        lineno++;
        std::string where = std::string(path) + ":" + std::to_string(lineno);
        if (!csv && line.compare(0, 4, "seq,") == 0) {   // the CSV header row of `log dump --csv`
            std::vector<std::string> h = split_csv(line);
            for (size_t i = 0; i < h.size(); i++) {
                if (h[i] == "seq") col_seq = (int)i;
                else if (h[i] == "type") col_type = (int)i;
                else if (h[i] == "target_x") col_x = (int)i;
                else if (h[i] == "target_y") col_y = (int)i;
                else if (h[i] == "target_z") col_z = (int)i;
                else if (h[i] == "event") col_ev = (int)i;
                else if (h[i] == "point_x") col_px = (int)i;
            }
            if (col_seq < 0 || col_type < 0 || col_x < 0 || col_y < 0 || col_z < 0)
                die(where + ": CSV header lacks seq, type or target_x/y/z");
            csv = true;
            continue;
        }
        if (csv) {
            std::vector<std::string> c = split_csv(line);
            if (line.empty()) continue;
            int need = std::max(std::max(col_seq, col_type), std::max(col_x, std::max(col_y, col_z)));
            if ((int)c.size() <= need) die(where + ": short CSV row");
            if (c[col_type] == "event" && col_ev >= 0 && col_px >= 0 && (int)c.size() > col_px + 2 &&
                c[col_ev] == "contact") {
                // the move before stopped where the head touched: it ends there
                if (moves->empty() || !parse_point(c[col_px], c[col_px + 1], c[col_px + 2], &moves->back().to))
                    die(where + ": bad contact row");
                moves->back().contact = true;
                continue;
            }
            if (c[col_type] != "move") continue;
            Move m;
            m.contact = false;
            if (!parse_long(c[col_seq], &m.seq) || !parse_point(c[col_x], c[col_y], c[col_z], &m.to)) die(where + ": bad move row");
            moves->push_back(m);
            continue;
        }
        size_t h = line.find('#');
        if (h != std::string::npos) line.erase(h);
        std::istringstream is(line);
        std::vector<std::string> w;
        std::string tok;
        while (is >> tok) w.push_back(tok);
        if (w.empty()) continue;
        if (w[0] == "start" && w.size() == 4) {
            if (!parse_point(w[1], w[2], w[3], start)) die(where + ": bad start");
            *have_start = true;
        } else if (w[0] == "contact" && w.size() == 4) {
            if (moves->empty() || !parse_point(w[1], w[2], w[3], &moves->back().to)) die(where + ": bad contact");
            moves->back().contact = true;
        } else if (w[0] == "move" && (w.size() == 4 || w.size() == 5)) {
            Move m;
            m.seq = -1;
            m.contact = false;
            size_t o = w.size() == 5 ? 2 : 1;
            if (w.size() == 5 && !parse_long(w[1], &m.seq)) die(where + ": bad move number");
            if (!parse_point(w[o], w[o + 1], w[o + 2], &m.to)) die(where + ": bad move");
            moves->push_back(m);
        } else die(where + ": expected `start X Y Z`, `move [SEQ] X Y Z` or `contact X Y Z`");
    }
}

int main(int argc, char **argv)
{
    const char *mesh_path = nullptr, *moves_path = nullptr;
    bool have_start = false;
    Point start(0, 0, 0);
    long list = 0;
    double lag = 0.0;
    for (int i = 1; i < argc; i++) {
        std::string a = argv[i];
        if (a == "--start" && i + 1 < argc) {
            std::string s = argv[++i];
            for (char &c : s) if (c == ',') c = ' ';
            std::istringstream is(s);
            std::string x, y, z, extra;
            if (!(is >> x >> y >> z) || (is >> extra) || !parse_point(x, y, z, &start)) die("bad --start (X,Y,Z)");
            have_start = true;
        } else if (a == "--list" && i + 1 < argc) list = std::atol(argv[++i]);
        else if (a == "--lag" && i + 1 < argc) {
            char *e;
            lag = std::strtod(argv[++i], &e);
            if (*e || !(lag >= 0.0) || !std::isfinite(lag)) die("bad --lag (MM >= 0)");
        }
        else if (a[0] == '-' && a.size() > 1) die("unknown option " + a);
        else if (!mesh_path) mesh_path = argv[i];
        else if (!moves_path) moves_path = argv[i];
        else die("too many arguments");
    }
    if (!mesh_path || !moves_path) {
        std::fprintf(stderr, "usage: cgal_moves MESH.off MOVES [--start X,Y,Z] [--list N] [--lag MM]\n");
        return 2;
    }
    std::vector<Point> pts;
    std::vector<std::array<size_t, 3> > tris;
    read_off(mesh_path, &pts, &tris);
    if (tris.empty()) die(std::string(mesh_path) + ": no faces");

    // Each proper triangle as its own face (a triangle soup: the geometry is all that counts, so
    // non-manifold edges or vertices need no repair); zero-area triangles as segments.
    Mesh mesh;
    std::vector<Mesh::Face_index> faces;
    std::vector<Segment> flat_segs;
    std::vector<Point> flat_points;
    size_t degenerate = 0;
    for (const auto &t : tris) {
        const Point &a = pts[t[0]], &b = pts[t[1]], &c = pts[t[2]];
        if (CGAL::collinear(a, b, c)) {
            degenerate++;
            if (a != b) flat_segs.push_back(Segment(a, b));
            if (b != c) flat_segs.push_back(Segment(b, c));
            if (c != a) flat_segs.push_back(Segment(c, a));
            if (a == b && b == c) flat_points.push_back(a);
            continue;
        }
        Mesh::Vertex_index va = mesh.add_vertex(a), vb = mesh.add_vertex(b), vc = mesh.add_vertex(c);
        Mesh::Face_index fi = mesh.add_face(va, vb, vc);
        if (fi == Mesh::null_face()) die("internal: add_face failed");
        faces.push_back(fi);
    }
    if (faces.empty()) die(std::string(mesh_path) + ": only zero-area faces");
    Tree tree(faces.begin(), faces.end(), mesh);
    tree.build();
    tree.accelerate_distance_queries();
    Seg_tree seg_tree(flat_segs.begin(), flat_segs.end());
    if (!flat_segs.empty()) seg_tree.build();
    // The ray parity over the triangles' tree (the constructor that takes a built tree: the
    // mesh's faces are not connected, which only this check of a closed surface's geometry uses).
    Side side(tree);

    std::vector<Move> moves;
    read_moves(moves_path, &have_start, &start, &moves);
    if (!have_start) die("no start position (a `start X Y Z` line or --start X,Y,Z)");

    auto touches = [&](const Point &p, const Point &q) -> bool {
        if (p == q) {
            if (tree.do_intersect(p)) return true;
            for (const Segment &s : flat_segs) if (s.has_on(p)) return true;
        } else {
            Segment s(p, q);
            if (tree.do_intersect(s)) return true;
            if (!flat_segs.empty() && seg_tree.do_intersect(s)) return true;
            for (const Point &x : flat_points) if (s.has_on(x)) return true;
        }
        return false;
    };

    size_t through = 0, inside = 0, listed = 0, odd = 0, contacts = 0;
    long long first = -1, first_seq = -1;
    Point from = start;
    bool on_contact = false;
    for (size_t i = 0; i < moves.size(); i++) {
        const Move &m = moves[i];
        const char *what = nullptr;
        // a move the contact switch stopped touches the surface at its end, and the next one
        // leaves from there: those touches (the last or first 1e-9 of the move) are allowed
        Point p = from, q = m.to;
        double len = std::sqrt(CGAL::to_double(CGAL::squared_distance(from, m.to)));
        double share = len > 0.0 ? std::min(1.0 - CONTACT_SHARE, std::max(CONTACT_SHARE, lag / len)) : 0.0;
        if (on_contact && from != m.to) p = from + share * (m.to - from);
        if (m.contact && from != m.to) { q = from + (1.0 - share) * (m.to - from); contacts++; }
        if (touches(p, q)) { through++; what = "through"; }
        else {
            CGAL::Bounded_side s0 = side(p), s1 = side(q);
            if (s0 == CGAL::ON_BOUNDED_SIDE && s1 == CGAL::ON_BOUNDED_SIDE) { inside++; what = "inside"; }
            else if (s0 != s1) odd++;   // cannot be: the segment meets no triangle
        }
        if (what) {
            if (first < 0) { first = (long long)i + 1; first_seq = m.seq; }
            if (listed < (size_t)list) {
                listed++;
                std::printf("%s: move %zu (record %lld) from %.17g %.17g %.17g to %.17g %.17g %.17g\n", what, i + 1, m.seq,
                            from.x(), from.y(), from.z(), m.to.x(), m.to.y(), m.to.z());
            }
        }
        from = m.to;
        on_contact = m.contact;
    }
    if (contacts) std::printf("contacts %zu (moves ending where the head touched)\n", contacts);
    std::printf("mesh %s: %zu vertices, %zu triangles (%zu zero-area)\n", mesh_path, pts.size(), tris.size(), degenerate);
    if (odd) std::printf("warning: %zu move(s) with ends on both sides and no triangle met (inconsistent mesh)\n", odd);
    if (first < 0) std::printf("moves %zu, through %zu, inside %zu, first none\n", moves.size(), through, inside);
    else if (first_seq >= 0) std::printf("moves %zu, through %zu, inside %zu, first %lld (record %lld)\n", moves.size(), through, inside, first, first_seq);
    else std::printf("moves %zu, through %zu, inside %zu, first %lld\n", moves.size(), through, inside, first);
    return through + inside ? 1 : 0;
}
