/* vp_sim_opts — the command line of `sim` (and of the sim options recorded in a session log's
 * note, read back by --resume): argv into vp_sim_options_t and vp_sim_session_t. The library
 * (host/vp_sim_setup, host/vp_sim_session) takes the parsed structs and parses no argv itself. */
#ifndef VP_SIM_OPTS_H
#define VP_SIM_OPTS_H
#include <stddef.h>
#include "vp_sim_setup.h"
#include "vp_sim_session.h"

/* Parses argv[*i] (and its value). 0: taken; 1: not a sim option; -1: bad value (err). */
int vp_sim_parse_option(vp_sim_options_t *o, int argc, char **argv, int *i, char *err, size_t errlen);
/* The moving object (sim only): --motion SPEC, --speed V, --accel A, --probe-time T; like
 * vp_sim_parse_option. The spec's syntax is checked here. */
int vp_sim_parse_motion_option(vp_sim_options_t *o, int argc, char **argv, int *i, char *err, size_t errlen);
/* Size with an optional K/M/G suffix; -1 on error. */
int vp_parse_size(const char *s, size_t *out);
/* A count: decimal digits only (no sign, no blanks), at most max; -1 on error. */
int vp_parse_count(const char *s, unsigned long long max, unsigned long long *out);
/* The log options (--log, --no-log, --resume, --sync, --stop-after, --power-cut), like
 * vp_sim_parse_option: 0 taken, 1 not ours, -1 bad value (err). */
int vp_sim_session_parse_option(vp_sim_session_t *g, int argc, char **argv, int *i, char *err, size_t errlen);
/* With --resume: loads the log and rebuilds o from the defaults, the sim options recorded in
 * the log, then the command line's (which win). Without: nothing. */
int vp_sim_session_options(vp_sim_session_t *g, vp_sim_options_t *o, int argc, char **argv, char *err,
                      size_t errlen);

#endif
