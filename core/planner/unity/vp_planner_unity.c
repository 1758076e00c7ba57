/* The planner as one compilation unit, for a size-constrained target (boards/cortex-m4 via
 * tests/t_cortex_m4.sh). Same sources as the files of core/planner/, which the host build
 * compiles one by one (each testable alone); here the functions they share (VP_PL_API) become
 * static, so the compiler may inline a function into its only caller as it did when the planner
 * was one file: the image is no larger for the split. The pattern of SQLite's amalgamation
 * (SQLITE_PRIVATE). Never compiled together with the separate files: one or the other. */
#define VP_PL_API static
#include "../proof.c"
#include "../route.c"
#include "../facets.c"
#include "../tasks.c"
#include "../update.c"
#include "../close.c"
#ifndef VP_CORE_MCU /* the contact safety net: not on a microcontroller (VP_PL_CONTACTS) */
#include "../contact.c"
#include "../rescan.c"
#include "../tube.c"
#include "../aim.c"
#endif
#include "../seed.c"
#include "../planner.c"
