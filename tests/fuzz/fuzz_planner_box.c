/* libFuzzer target: the planner's target (fuzz_planner.c) with a box for the object, or two:
 * flat faces, edges and corners, where samples are coplanar and Voronoi vertices far. */
#define FUZZ_OBJECT_BOXES 1
#include "fuzz_planner.c"
