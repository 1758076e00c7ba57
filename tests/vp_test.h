/* Minimal test harness: CHECK counts failures and keeps going; the program's exit status is the
 * verdict (0 pass, 1 fail, 77 skipped). Each program prints one summary line last. */
#ifndef VP_TEST_H
#define VP_TEST_H
#include <stdio.h>
#include <stdlib.h>

static int vp_test_failures;
static long vp_test_checks;

#define CHECK(cond) do { vp_test_checks++; if (!(cond)) { vp_test_failures++; \
    if (vp_test_failures <= 20) fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond); } } while (0)
#define CHECKF(cond, ...) do { vp_test_checks++; if (!(cond)) { vp_test_failures++; \
    if (vp_test_failures <= 20) { fprintf(stderr, "%s:%d: CHECK failed: %s: ", __FILE__, __LINE__, #cond); \
    fprintf(stderr, __VA_ARGS__); fputc('\n', stderr); } } } while (0)
#define TEST_SKIP(...) do { printf("skipped: "); printf(__VA_ARGS__); printf("\n"); exit(77); } while (0)

static int vp_test_done(const char *what)
{
    printf("%s: %ld checks, %d failed\n", what, vp_test_checks, vp_test_failures);
    return vp_test_failures ? 1 : 0;
}
#endif
