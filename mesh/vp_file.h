/* vp_file — reading input files with a bound: every reader of a file named on the command line
 * or in a board file (meshes, session logs, .node point sets, INI files) goes through here, so
 * a device (/dev/zero, a terminal), a folder or a file larger than the format can hold is
 * refused at once with a clear message instead of being read until memory runs out. */
#ifndef VP_FILE_H
#define VP_FILE_H
#include <stddef.h>
#include <stdio.h>

/* Opens path for reading. Refuses (NULL, err set) anything but a regular file, and a regular
 * file of more than max bytes; what names the kind of file in messages ("mesh", "board file").
 * *size (may be NULL) gets the file's size. */
FILE *vp_file_open_read(const char *path, unsigned long long max, const char *what, unsigned long long *size,
                        char *err, size_t errlen);

/* Checks the first bytes of a file (n of them, fewer only when the file is that short): NULL
 * when they may start such a file, else why not (a constant text). */
typedef const char *(*vp_file_head_fn)(const unsigned char *p, size_t n);
#define VP_FILE_HEAD 4096

/* Reads a whole regular file of at most max bytes into a malloc'ed buffer (*data, with a NUL
 * after its *len bytes; the caller frees it). head (may be NULL) is asked about the first
 * VP_FILE_HEAD bytes before the rest is read, so a file that is not of the format fails fast.
 * VP_OK, VP_EIO (err says why; nothing allocated), VP_ECORRUPT (head refused), VP_ENOMEM. */
int vp_file_read(const char *path, unsigned long long max, const char *what, vp_file_head_fn head,
                 unsigned char **data, size_t *len, char *err, size_t errlen);

/* Where the first NUL byte of p[0..n) is: 1 and its 1-based line in *line, else 0. */
int vp_file_find_nul(const unsigned char *p, size_t n, unsigned long *line);

/* snprintf into err (NULL or errlen 0: nothing): the one way a reader above the core says why. */
void vp_seterr(char *err, size_t errlen, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

#endif
