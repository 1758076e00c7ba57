/* Sub-commands of build/voroprobe. Each returns the process exit status
 * (0 ok, 1 failure, 2 usage error) and prints its own --help. */
#ifndef VP_CLI_H
#define VP_CLI_H

typedef int (*vp_cmd_fn)(int argc, char **argv);

struct vp_cli_cmd {
    const char *name;
    vp_cmd_fn run;
    const char *summary;
};

int vp_cmd_bench_delaunay(int argc, char **argv);
int vp_cmd_sim(int argc, char **argv);
int vp_cmd_replay(int argc, char **argv);
int vp_cmd_mesh(int argc, char **argv);
int vp_cmd_log(int argc, char **argv);
int vp_cmd_certify(int argc, char **argv);
int vp_cmd_scan(int argc, char **argv);
int vp_cmd_calibrate(int argc, char **argv);

#endif
