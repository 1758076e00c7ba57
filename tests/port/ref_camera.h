/* The camera model of port/vp_laser.h written again for the tests, apart from the library: a
 * pinhole with Brown-Conrady distortion (OpenCV's, k3 = 0) in the tilt frame, and a camera turned
 * about an axis. tests/port/test_port_calib.c and tests/fuzz/fuzz_calib.c check the library's fits
 * against it. */
#ifndef REF_CAMERA_H
#define REF_CAMERA_H
#include <math.h>
#include <string.h>
#include "vp_laser.h"

/* camera frame, pinhole, distortion, pixels: 1 and uv when p lies in front of the camera */
static int ref_project(const vp_camera_model_t *c, const double p[3], double uv[2])
{
    double q[3], x, y, r2, rad;
    int i;
    for (i = 0; i < 3; i++)
        q[i] = c->rot[3 * i] * (p[0] - c->pos[0]) + c->rot[3 * i + 1] * (p[1] - c->pos[1]) + c->rot[3 * i + 2] * (p[2] - c->pos[2]);
    if (q[2] <= 0) return 0;
    x = q[0] / q[2];
    y = q[1] / q[2];
    r2 = x * x + y * y;
    rad = 1 + c->dist[0] * r2 + c->dist[1] * r2 * r2;
    uv[0] = c->fx * (x * rad + 2 * c->dist[2] * x * y + c->dist[3] * (r2 + 2 * x * x)) + c->cx;
    uv[1] = c->fy * (y * rad + c->dist[2] * (r2 + 2 * y * y) + 2 * c->dist[3] * x * y) + c->cy;
    return 1;
}

/* rotation by angle a about unit axis k, applied to the rows of rot (the camera turned) */
static void ref_turn(double rot[9], const double k[3], double a)
{
    double R[9], out[9], c = cos(a), s = sin(a), t = 1 - c;
    int i, j;
    R[0] = c + k[0] * k[0] * t;        R[1] = k[0] * k[1] * t - k[2] * s; R[2] = k[0] * k[2] * t + k[1] * s;
    R[3] = k[1] * k[0] * t + k[2] * s; R[4] = c + k[1] * k[1] * t;        R[5] = k[1] * k[2] * t - k[0] * s;
    R[6] = k[2] * k[0] * t - k[1] * s; R[7] = k[2] * k[1] * t + k[0] * s; R[8] = c + k[2] * k[2] * t;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) out[3 * i + j] = rot[3 * i] * R[j] + rot[3 * i + 1] * R[3 + j] + rot[3 * i + 2] * R[6 + j];
    memcpy(rot, out, sizeof out);
}

#endif
