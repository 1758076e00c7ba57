# tests/cgal_object.sh — sourced by the scripts that measure meshes against their objects:
# `cgal_object_build BUILD` builds the independent measure tests/cgal_object.cpp (CGAL's
# Polygon_mesh_processing: Hausdorff distance, point distances, Delaunay edges) into
# BUILD/accuracy/cgal_object when it is missing or older than its source, and sets CO to it.
# Returns 1 with CG_WHY set when it cannot: without libcgal-dev (tools/install-deps.sh installs
# it for make check) the accuracy would be measured by voroprobe alone, so the callers fail,
# never skip. `chaus A B` prints CGAL's two-sided Hausdorff distance between meshes A and B.
cgal_object_build() {
  CO="$1/accuracy/cgal_object"
  CG_WHY=""
  mkdir -p "$1/accuracy"
  if [ ! -f /usr/include/CGAL/Polygon_mesh_processing/distance.h ] || ! command -v g++ >/dev/null 2>&1; then
    CG_WHY="no CGAL (libcgal-dev): the accuracy would be measured by voroprobe alone"
    rm -f "$CO"
    return 1
  fi
  if [ ! -x "$CO" ] || [ tests/cgal_object.cpp -nt "$CO" ]; then
    g++ -O2 -o "$CO.tmp" tests/cgal_object.cpp -lgmp -lmpfr >"$1/accuracy/build.log" 2>&1 && mv "$CO.tmp" "$CO" || {
      CG_WHY="tests/cgal_object.cpp does not build (log: $1/accuracy/build.log)"
      rm -f "$CO" "$CO.tmp"
      return 1
    }
  fi
  return 0
}
chaus() { "$CO" hausdorff "$1" "$2" | sed -n 's/.*"hausdorff":\([^,}]*\).*/\1/p'; }
