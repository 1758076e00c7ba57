# tests/cgal_moves.sh — sourced by the safety scripts: `cgal_moves_build BUILD` builds the
# independent move checker tests/cgal_moves.cpp (CGAL, exact) into BUILD/safety/cgal_moves when
# it is missing or older than its source, and sets CG to it. Returns 1 with CG_WHY set when it
# cannot: without libcgal-dev (tools/install-deps.sh installs it for make check) the safety checks
# would grade themselves, so the callers fail, never skip.
cgal_moves_build() {
  CG="$1/safety/cgal_moves"
  CG_WHY=""
  mkdir -p "$1/safety"
  if [ ! -f /usr/include/CGAL/Side_of_triangle_mesh.h ] || ! command -v g++ >/dev/null 2>&1; then
    CG_WHY="no CGAL (libcgal-dev): the independent move check cannot run"
    rm -f "$CG"
    return 1
  fi
  if [ ! -x "$CG" ] || [ tests/cgal_moves.cpp -nt "$CG" ]; then
    # CGAL's own assertions are kept (no -DNDEBUG): a misuse aborts instead of answering
    g++ -O2 -o "$CG.tmp" tests/cgal_moves.cpp -lgmp -lmpfr >"$1/safety/cgal_moves-build.log" 2>&1 && mv "$CG.tmp" "$CG" || {
      CG_WHY="tests/cgal_moves.cpp does not build (log: $1/safety/cgal_moves-build.log)"
      tail -5 "$1/safety/cgal_moves-build.log"
      rm -f "$CG" "$CG.tmp"
      return 1
    }
  fi
  return 0
}
