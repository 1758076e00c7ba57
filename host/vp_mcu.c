/* vp_mcu — the host's end of the MCU link: framing (COBS between 0x00 bytes, CRC-32), the
 * links (qemu, a pipe, a serial device, a unix socket) and the session server. Written apart
 * from the firmware's end (boards/cortex-m4/mcu_link.c): the two meet only on the wire. */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <poll.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>
#include "vp_logfmt.h"
#include "vp_mcu.h"
#include "vp_status.h"

enum { T_HELLO = 0x01, T_MOVE = 0x02, T_PROBE = 0x03, T_LOG = 0x04, T_DONE = 0x06,
       T_START = 0x81, T_ACK = 0x82, T_RESULT = 0x83, T_STOP = 0x84, T_NAK = 0x85 };

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void put32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)v; p[1] = (unsigned char)(v >> 8);
    p[2] = (unsigned char)(v >> 16); p[3] = (unsigned char)(v >> 24);
}

static uint32_t get32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static void putd(unsigned char *p, double v)
{
    uint64_t u;
    memcpy(&u, &v, 8);
    put32(p, (uint32_t)u);
    put32(p + 4, (uint32_t)(u >> 32));
}

static double getd(const unsigned char *p)
{
    uint64_t u = (uint64_t)get32(p) | (uint64_t)get32(p + 4) << 32;
    double v;
    memcpy(&v, &u, 8);
    return v;
}

/* ---------- links ---------- */

static int in_path(const char *prog)
{
    const char *path = getenv("PATH");
    char buf[4096];
    if (strchr(prog, '/')) return access(prog, X_OK) == 0;
    while (path && *path) {
        const char *e = strchr(path, ':');
        size_t n = e ? (size_t)(e - path) : strlen(path);
        if (n > 0 && n + strlen(prog) + 2 < sizeof buf) {
            memcpy(buf, path, n);
            buf[n] = '/';
            strcpy(buf + n + 1, prog);
            if (access(buf, X_OK) == 0) return 1;
        }
        path = e ? e + 1 : NULL;
    }
    return 0;
}

static void link_init(vp_mcu_link_t *l)
{
    memset(l, 0, sizeof *l);
    l->fd = -1;
}

/* Runs argv with its stdin and stdout on one end of a socket pair. */
static int spawn(vp_mcu_link_t *l, char *const argv[], char *err, size_t errlen)
{
    int sv[2];
    pid_t pid;
    if (socketpair(AF_UNIX, SOCK_STREAM, 0, sv) != 0) {
        snprintf(err, errlen, "socketpair: %s", strerror(errno));
        return VP_EIO;
    }
    pid = fork();
    if (pid < 0) {
        snprintf(err, errlen, "fork: %s", strerror(errno));
        close(sv[0]); close(sv[1]);
        return VP_EIO;
    }
    if (pid == 0) {
        dup2(sv[1], 0);
        dup2(sv[1], 1);
        close(sv[0]); close(sv[1]);
        execvp(argv[0], argv);
        fprintf(stderr, "voroprobe mcu: cannot run %s: %s\n", argv[0], strerror(errno));
        _exit(127);
    }
    close(sv[1]);
    l->fd = sv[0];
    l->child = pid;
    return VP_OK;
}

int vp_mcu_open_qemu(vp_mcu_link_t *l, const char *qemu, const char *machine, const char *image, int icount,
                     char *err, size_t errlen)
{
    char shift[32];
    char *argv[16];
    int n = 0;
    struct stat st;
    link_init(l);
    if (!qemu) qemu = "qemu-system-arm";
    if (!in_path(qemu)) {
        snprintf(err, errlen, "%s is not installed (Debian: apt-get install qemu-system-arm, or make deps)", qemu);
        return VP_ENODEV;
    }
    if (stat(image, &st) != 0 || !S_ISREG(st.st_mode)) {
        snprintf(err, errlen, "the firmware image %s: %s (sh boards/cortex-m4/build.sh builds it)", image,
                 errno ? strerror(errno) : "not a file");
        return VP_EINVAL;
    }
    argv[n++] = (char *)qemu;
    argv[n++] = "-M"; argv[n++] = (char *)(machine ? machine : "mps2-an386");
    argv[n++] = "-nodefaults"; argv[n++] = "-display"; argv[n++] = "none"; argv[n++] = "-net"; argv[n++] = "none";
    argv[n++] = "-serial"; argv[n++] = "stdio";
    argv[n++] = "-kernel"; argv[n++] = (char *)image;
    if (icount >= 0) {
        snprintf(shift, sizeof shift, "shift=%d", icount);
        argv[n++] = "-icount"; argv[n++] = shift;
    }
    argv[n] = NULL;
    return spawn(l, argv, err, errlen);
}

int vp_mcu_open_exec(vp_mcu_link_t *l, const char *program, char *err, size_t errlen)
{
    char *argv[2];
    link_init(l);
    if (!in_path(program)) {
        snprintf(err, errlen, "%s: no such program", program);
        return VP_ENODEV;
    }
    argv[0] = (char *)program;
    argv[1] = NULL;
    return spawn(l, argv, err, errlen);
}

int vp_mcu_open_serial(vp_mcu_link_t *l, const char *device, long baud, char *err, size_t errlen)
{
    struct termios t;
    speed_t sp;
    link_init(l);
    switch (baud) {
    case 9600: sp = B9600; break;
    case 57600: sp = B57600; break;
    case 115200: sp = B115200; break;
    case 230400: sp = B230400; break;
    case 460800: sp = B460800; break;
    case 921600: sp = B921600; break;
    default:
        snprintf(err, errlen, "--baud %ld: use 9600, 57600, 115200, 230400, 460800 or 921600", baud);
        return VP_EINVAL;
    }
    l->fd = open(device, O_RDWR | O_NOCTTY);
    if (l->fd < 0) {
        snprintf(err, errlen, "cannot open %s: %s", device, strerror(errno));
        return VP_EIO;
    }
    if (tcgetattr(l->fd, &t) != 0) {
        snprintf(err, errlen, "%s is not a serial device: %s", device, strerror(errno));
        close(l->fd); l->fd = -1;
        return VP_EIO;
    }
    cfmakeraw(&t);
    cfsetispeed(&t, sp);
    cfsetospeed(&t, sp);
    t.c_cflag |= CLOCAL | CREAD;
    t.c_cc[VMIN] = 0;
    t.c_cc[VTIME] = 0;
    if (tcsetattr(l->fd, TCSANOW, &t) != 0) {
        snprintf(err, errlen, "cannot set %s to %ld baud: %s", device, baud, strerror(errno));
        close(l->fd); l->fd = -1;
        return VP_EIO;
    }
    tcflush(l->fd, TCIOFLUSH);
    return VP_OK;
}

int vp_mcu_open_socket(vp_mcu_link_t *l, const char *path, char *err, size_t errlen)
{
    struct sockaddr_un a;
    link_init(l);
    memset(&a, 0, sizeof a);
    a.sun_family = AF_UNIX;
    if (strlen(path) >= sizeof a.sun_path) {
        snprintf(err, errlen, "socket path too long: %s", path);
        return VP_EINVAL;
    }
    strcpy(a.sun_path, path);
    l->fd = socket(AF_UNIX, SOCK_STREAM, 0);
    if (l->fd < 0 || connect(l->fd, (struct sockaddr *)&a, sizeof a) != 0) {
        snprintf(err, errlen, "cannot connect to %s: %s", path, strerror(errno));
        if (l->fd >= 0) close(l->fd);
        l->fd = -1;
        return VP_EIO;
    }
    return VP_OK;
}

void vp_mcu_close(vp_mcu_link_t *l)
{
    if (l->fd >= 0) close(l->fd);
    if (l->child > 0) {
        int i, status;
        /* the --exec program ends at end of input; qemu is told to */
        for (i = 0; i < 50 && waitpid(l->child, &status, WNOHANG) == 0; i++) {
            struct timespec ts = { 0, 10000000L };
            if (i == 10) kill(l->child, SIGTERM);
            nanosleep(&ts, NULL);
        }
        if (i == 50) { kill(l->child, SIGKILL); waitpid(l->child, &status, 0); }
    }
    link_init(l);
}

/* ---------- frames ---------- */

static size_t cobs_stuff(const unsigned char *in, size_t n, unsigned char *out)
{
    size_t block = 0, o = 1, i;
    for (i = 0; i < n; i++) {
        if (in[i] != 0) out[o++] = in[i];
        if (in[i] == 0 || o - block == 0xFF) {
            out[block] = (unsigned char)(o - block);
            block = o++;
        }
    }
    out[block] = (unsigned char)(o - block);
    return o;
}

static long cobs_unstuff(const unsigned char *in, size_t n, unsigned char *out)
{
    size_t i = 0, o = 0;
    while (i < n) {
        size_t code = in[i], j;
        if (code == 0 || i + code > n) return -1;
        for (j = 1; j < code; j++) out[o++] = in[i + j];
        i += code;
        if (code < 0xFF && i < n) out[o++] = 0;
    }
    return (long)o;
}

/* flip >= 0: that bit of the frame (after its CRC) is inverted: damage on the line. */
static int send_frame(vp_mcu_link_t *l, int type, unsigned seq, const unsigned char *p, size_t n, long flip)
{
    unsigned char body[VP_MCU_MAX_PAYLOAD + 10], wire[sizeof body + sizeof body / 254 + 4];
    size_t w, off = 0;
    body[0] = VP_MCU_PROTO_VERSION;
    body[1] = (unsigned char)type;
    body[2] = (unsigned char)seq; body[3] = (unsigned char)(seq >> 8);
    body[4] = (unsigned char)n; body[5] = (unsigned char)(n >> 8);
    if (n) memcpy(body + 6, p, n);
    put32(body + 6 + n, vp_logfmt_crc32(0, body, 6 + n));
    if (flip >= 0) body[(size_t)flip / 8 % (n + 10)] ^= (unsigned char)(1u << (flip % 8));
    wire[0] = 0;
    w = 1 + cobs_stuff(body, n + 10, wire + 1);
    wire[w++] = 0;
    while (off < w) {
        ssize_t k = write(l->fd, wire + off, w - off);
        if (k < 0 && errno == EINTR) continue;
        if (k <= 0) return VP_EIO;
        off += (size_t)k;
    }
    return VP_OK;
}

typedef struct frame {
    int type;
    unsigned seq;
    size_t len;
    unsigned char payload[VP_MCU_MAX_PAYLOAD];
} frame_t;

/* The next frame: 1 good, VP_ECORRUPT damaged, 0 nothing within timeout_ms, VP_EIO closed.
 * flip >= 0: that bit is inverted before the check (damage on the line). */
static int recv_frame(vp_mcu_link_t *l, int timeout_ms, long flip, frame_t *f)
{
    double end = now_s() + timeout_ms / 1000.0;
    for (;;) {
        while (l->in_i < l->in_n) {
            unsigned char c = l->inbuf[l->in_i++];
            unsigned char body[sizeof l->rx];
            long n;
            size_t plen;
            if (c != 0) {
                if (l->rx_n < sizeof l->rx) l->rx[l->rx_n++] = c;
                else l->rx_overflow = 1;
                continue;
            }
            if (l->rx_n == 0 && !l->rx_overflow) continue;
            n = l->rx_overflow ? -1 : cobs_unstuff(l->rx, l->rx_n, body);
            l->rx_n = 0;
            l->rx_overflow = 0;
            if (n >= 10 && flip >= 0) body[(size_t)flip / 8 % (size_t)n] ^= (unsigned char)(1u << (flip % 8));
            if (n < 10) return VP_ECORRUPT;
            plen = (size_t)body[4] | (size_t)body[5] << 8;
            if (plen + 10 != (size_t)n || plen > VP_MCU_MAX_PAYLOAD) return VP_ECORRUPT;
            if (vp_logfmt_crc32(0, body, 6 + plen) != get32(body + 6 + plen)) return VP_ECORRUPT;
            if (body[0] != VP_MCU_PROTO_VERSION) return VP_EVERSION;
            f->type = body[1];
            f->seq = (unsigned)body[2] | (unsigned)body[3] << 8;
            f->len = plen;
            memcpy(f->payload, body + 6, plen);
            return 1;
        }
        {
            struct pollfd p;
            double left = end - now_s();
            ssize_t r;
            int pr;
            if (left <= 0) return 0;
            p.fd = l->fd;
            p.events = POLLIN;
            pr = poll(&p, 1, (int)(left * 1000.0) + 1);
            if (pr < 0 && errno == EINTR) continue;
            if (pr <= 0) return 0;
            r = read(l->fd, l->inbuf, sizeof l->inbuf);
            if (r < 0 && (errno == EINTR || errno == EAGAIN)) continue;
            if (r <= 0) return VP_EIO;
            l->in_n = (size_t)r;
            l->in_i = 0;
        }
    }
}

/* ---------- the step edges against the ideal profile ---------- */

double vp_mcu_trapezoid_seconds(uint32_t n, double max_rate, double accel)
{
    double n_acc = max_rate * max_rate / (2.0 * accel);
    if (n == 0) return 0.0;
    if (2.0 * n_acc >= (double)n) return 2.0 * sqrt((double)n / accel);
    return 2.0 * max_rate / accel + ((double)n - 2.0 * n_acc) / max_rate;
}

static void check_move(const vp_mcu_hello_t *h, const unsigned char *p, vp_mcu_result_t *r)
{
    uint32_t k, n = 0, edges[3];
    double ideal, dev, lat;
    for (k = 0; k < 3; k++) {
        double a = getd(p + 8 * k) * h->steps_per_unit, b = getd(p + 24 + 8 * k) * h->steps_per_unit;
        long long d = llround(b) - llround(a);
        uint32_t s = (uint32_t)(d < 0 ? -d : d);
        edges[k] = 2 * s;
        if (s > n) n = s;
    }
    r->moves_checked++;
    if (get32(p + 80) != 0) return;      /* stopped by an input: fewer edges on purpose */
    for (k = 0; k < 3; k++) r->edges += get32(p + 48 + 4 * k);
    for (k = 0; k < 3; k++) if (get32(p + 48 + 4 * k) != edges[k]) { r->edge_mismatches++; break; }
    if (n == 0) return;
    ideal = vp_mcu_trapezoid_seconds(n, h->max_rate, h->accel) * h->tick_hz + h->pulse_ticks;
    dev = fabs((double)get32(p + 64) - ideal);
    if (dev > r->max_schedule_dev_ticks) r->max_schedule_dev_ticks = dev;
    if (dev > 2.0 + 1e-6 * ideal) r->schedule_mismatches++;
    lat = ((double)get32(p + 68) - (double)get32(p + 64)) * 1e6 / h->tick_hz;
    if (lat > r->max_latency_us) r->max_latency_us = lat;
    r->mean_latency_us += lat;
    r->late_edges += get32(p + 72);
}

/* ---------- the session ---------- */

int vp_mcu_serve(vp_mcu_link_t *l, const vp_mcu_device_t *dev, const vp_mcu_options_t *o,
                 vp_mcu_result_t *res, char *err, size_t errlen)
{
    static frame_t f;
    unsigned char reply[64];
    int reply_type = 0, have_last = 0, started = 0, st = VP_OK;
    unsigned last_seq = 0;
    size_t reply_len = 0;
    double t0 = now_s(), last_good = t0, next_progress = t0 + 1.0;
    unsigned long timed_moves = 0, frame_no = 0, damaged = 0; /* damaged: frames since the last good one */
    unsigned corrupt_left = o->corrupt;
    vp_logfmt_reader_t *reader = malloc(sizeof *reader);
    FILE *log = NULL;
    memset(res, 0, sizeof *res);
    if (!reader) { snprintf(err, errlen, "out of memory"); return VP_ENOMEM; }
    vp_logfmt_reader_init(reader);
    for (;;) {
        long flip_in = -1, flip_out = -1;
        int r;
        /* every 5th frame from the 3rd on is damaged while some are left: in, out, in, ... */
        if (corrupt_left && frame_no % 5 == 2) {
            if ((res->injected_in + res->injected_out) % 2 == 0) flip_in = (long)(frame_no * 13 % 80);
            else flip_out = (long)(frame_no * 13 % 80);
        }
        r = recv_frame(l, 200, flip_in, &f);
        /* nothing, or only damaged frames (a wrong baud rate, a noisy line): both are silence */
        if (r != VP_EIO && r != VP_EVERSION && r <= 0 && now_s() - last_good > o->silent_seconds) {
            snprintf(err, errlen, "the board is silent: no valid frame for %.0f s%s%s", o->silent_seconds,
                     damaged ? " (damaged frames only: the link's speed, its wiring?)" : "",
                     started ? "" : " (no HELLO: is the image for this board, the link the right one?)");
            st = VP_ETIMEOUT;
            break;
        }
        if (r == 0) continue;
        if (r == VP_EIO) { snprintf(err, errlen, "the link closed (the board or qemu exited)"); st = VP_EIO; break; }
        frame_no++;
        if (flip_in >= 0) { res->injected_in++; corrupt_left--; }
        if (r == VP_EVERSION) {
            snprintf(err, errlen, "the board speaks another protocol version (this host: %u)", VP_MCU_PROTO_VERSION);
            st = VP_ECORRUPT;
            break;
        }
        if (r < 0) {                  /* damaged: never acted on, asked again */
            res->crc_errors++;
            damaged++;
            send_frame(l, T_NAK, 0, NULL, 0, -1);
            continue;
        }
        res->frames_in++;
        last_good = now_s();
        damaged = 0;
        if (have_last && f.seq == last_seq) {   /* our reply was lost: the same again */
            res->repeats++;
            if (flip_out >= 0) { res->injected_out++; corrupt_left--; }
            send_frame(l, reply_type, last_seq, reply_type == T_START ? o->header : reply,
                       reply_type == T_START ? o->header_len : reply_len, flip_out);
            res->frames_out++;
            continue;
        }
        reply_len = 0;
        reply_type = T_ACK;
        if (!started && f.type != T_HELLO) {
            snprintf(err, errlen, "the board is inside a session already (frame 0x%02x before HELLO): reset it", f.type);
            st = VP_ESTATE;
            goto out;
        }
        switch (f.type) {
        case T_HELLO:
            if (started) {
                snprintf(err, errlen, "the board restarted during the session (HELLO after START)");
                st = VP_EIO;
                goto out;
            }
            if (f.len < 28) goto bad;
            res->hello.version = f.payload[0];
            res->hello.arena_bytes = get32(f.payload + 4);
            res->hello.tick_hz = get32(f.payload + 8);
            res->hello.steps_per_unit = get32(f.payload + 12);
            res->hello.max_rate = get32(f.payload + 16);
            res->hello.accel = get32(f.payload + 20);
            res->hello.pulse_ticks = get32(f.payload + 24);
            memcpy(res->hello.board, f.payload + 28, f.len - 28 < 35 ? f.len - 28 : 35);
            if (!res->hello.tick_hz || !res->hello.steps_per_unit || !res->hello.max_rate || !res->hello.accel) goto bad;
            if (o->progress)
                fprintf(o->progress, "mcu: board %s, arena %u bytes, %u steps/unit, %u steps/s, %u steps/s^2\n",
                        res->hello.board, res->hello.arena_bytes, res->hello.steps_per_unit, res->hello.max_rate,
                        res->hello.accel);
            log = fopen(o->log_path, "wb");
            if (!log) {
                snprintf(err, errlen, "cannot write %s: %s", o->log_path, strerror(errno));
                st = VP_EIO;
                goto out;
            }
            started = 1;
            reply_type = T_START;
            break;
        case T_MOVE: {
            double from[3], to[3];
            int k, collided = 0;
            if (f.len != 84 || !started) goto bad;
            for (k = 0; k < 3; k++) { from[k] = getd(f.payload + 8 * k); to[k] = getd(f.payload + 24 + 8 * k); }
            check_move(&res->hello, f.payload, res);
            if (get32(f.payload + 60) > 0) timed_moves++;
            if ((st = dev->move(dev->ctx, from, to, &collided)) != VP_OK) {
                snprintf(err, errlen, "the device refused a move: %s", vp_strerror(st));
                goto out;
            }
            res->moves++;
            res->collisions += (unsigned long)collided;
            break;
        }
        case T_PROBE: {
            double from[3], dir[3], dist = 0, raw = NAN;
            int k, hit = 0;
            if (f.len != 56 || !started) goto bad;
            for (k = 0; k < 3; k++) { from[k] = getd(f.payload + 8 * k); dir[k] = getd(f.payload + 24 + 8 * k); }
            if ((st = dev->probe(dev->ctx, from, dir, getd(f.payload + 48), &hit, &dist, &raw)) != VP_OK) {
                snprintf(err, errlen, "the device refused a probe: %s", vp_strerror(st));
                goto out;
            }
            reply_type = T_RESULT;
            reply[0] = (unsigned char)hit;
            putd(reply + 1, dist);
            putd(reply + 9, raw);
            reply_len = 17;
            res->probes_answered++;
            break;
        }
        case T_LOG: {
            vp_logfmt_record_t rec;
            size_t used = 0;
            int got;
            if (!started) goto bad;
            got = vp_logfmt_reader_push(reader, f.payload, f.len, &used, &rec);
            if ((got != VP_LOGFMT_GOT_HEADER && got != VP_LOGFMT_GOT_RECORD) || used != f.len) {
                snprintf(err, errlen, "log record %lu from the board is refused: %s", res->log_records,
                         got < 0 ? vp_logfmt_reason_text(reader->reason) : "not one whole item");
                st = VP_ECORRUPT;
                goto out;
            }
            if (fwrite(f.payload, 1, f.len, log) != f.len) {
                snprintf(err, errlen, "cannot write %s: %s", o->log_path, strerror(errno));
                st = VP_EIO;
                goto out;
            }
            if (got == VP_LOGFMT_GOT_RECORD) res->log_records++;
            res->log_bytes += f.len;
            break;
        }
        case T_DONE:
            if (f.len != 40) goto bad;
            res->done = 1;
            res->status = (int32_t)get32(f.payload);
            res->commands = get32(f.payload + 4);
            res->probes = get32(f.payload + 8);
            res->vertices = get32(f.payload + 12);
            res->facets = get32(f.payload + 16);
            res->arena_peak = get32(f.payload + 20);
            res->mcu_crc_errors = get32(f.payload + 24);
            res->mcu_naks = get32(f.payload + 28);
            res->mcu_timeouts = get32(f.payload + 32);
            break;
        default:
        bad:
            snprintf(err, errlen, "unexpected frame type 0x%02x (%zu bytes) from the board", f.type, f.len);
            st = VP_ECORRUPT;
            goto out;
        }
        if (o->stop_flag && *o->stop_flag && started && (f.type == T_MOVE || f.type == T_PROBE)) {
            *o->stop_flag = 0;
            reply_type = T_STOP;
            reply_len = 0;
        }
        have_last = 1;
        last_seq = f.seq;
        if (flip_out >= 0) { res->injected_out++; corrupt_left--; }
        if (send_frame(l, reply_type, f.seq, reply_type == T_START ? o->header : reply,
                       reply_type == T_START ? o->header_len : reply_len, flip_out) != VP_OK) {
            snprintf(err, errlen, "the link closed while answering");
            st = VP_EIO;
            goto out;
        }
        res->frames_out++;
        if (res->done) break;
        if (o->progress && now_s() > next_progress) {
            next_progress = now_s() + 1.0;
            fprintf(o->progress, "mcu: %lu moves, %lu probes, %lu log records, %lu damaged frames, %.0f s\n",
                    res->moves, res->probes_answered, res->log_records, res->crc_errors, now_s() - t0);
        }
    }
out:
    if (timed_moves) res->mean_latency_us /= (double)timed_moves;
    if (log && fclose(log) != 0 && st == VP_OK) {
        snprintf(err, errlen, "cannot write %s: %s", o->log_path, strerror(errno));
        st = VP_EIO;
    }
    if (st == VP_OK && vp_logfmt_reader_finish(reader) != VP_OK) {
        snprintf(err, errlen, "the streamed log ends inside a record");
        st = VP_ECORRUPT;
    }
    free(reader);
    res->seconds = now_s() - t0;
    return st;
}
