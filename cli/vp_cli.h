/* Sub-commands of build/voroprobe. Each returns the process exit status
 * (0 ok, 1 failure, 2 usage error) and prints its own --help. */
#ifndef VP_CLI_H
#define VP_CLI_H

typedef int (*vp_cli_fn)(int argc, char **argv);

struct vp_cli_cmd {
    const char *name;
    vp_cli_fn run;
    const char *summary;
};

int vp_cli_bench_delaunay(int argc, char **argv);
int vp_cli_sim(int argc, char **argv);
int vp_cli_track(int argc, char **argv);
int vp_cli_replay(int argc, char **argv);
int vp_cli_mesh(int argc, char **argv);
int vp_cli_log(int argc, char **argv);
int vp_cli_certify(int argc, char **argv);
int vp_cli_scan(int argc, char **argv);
int vp_cli_calibrate(int argc, char **argv);
int vp_cli_mcu(int argc, char **argv);
int vp_cli_reconstruct(int argc, char **argv);
int vp_cli_report(int argc, char **argv);

#endif
