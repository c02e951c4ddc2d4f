/*
 * hullstress_driver.h: the C/C++ driver kit of hullstress (docs/executables.md).
 *
 * A driver wraps a hull library as a program hullstress runs with --exec.
 * Include this one header, write a function that hulls one case, and call
 * hs_main() from main():
 *
 *     static int my_hull(const hs_case *c, hs_answer *a) {
 *         // c->dim, c->n, c->coords[i * c->dim + k]
 *         hs_printf(a, "%d\n", count);             // the answer, in the announced format
 *         return 0;                                // or: return hs_reject(a, "why");
 *     }
 *     int main(int argc, char **argv) {
 *         hs_driver d = {2, "Fx", "my driver 1.0", "my library 2.3"};
 *         return hs_main(&d, argc, argv, my_hull);
 *     }
 *
 * hs_main() does the rest: with HULLSTRESS_EXEC_PROTOCOL set (persistent
 * mode) it writes the handshake and answers case after case ("case N", the
 * points; "hull N", the answer, "end N"; or "error N message") until end of
 * file; without it (spawn mode) it reads one case, writes the answer and
 * exits (status 1 with the message on stderr when the case is rejected).
 * "--version" prints the handshake line and exits.  Header only, C99 or C++.
 */
#ifndef HULLSTRESS_DRIVER_H
#define HULLSTRESS_DRIVER_H

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define HS_PROTOCOL_VERSION 1

/* What the driver is: its dimension, output format ("i", "Fx" or "off") and names with versions. */
typedef struct {
    int dim;
    const char *output;
    const char *driver;
    const char *library;
} hs_driver;

/* One case: n points of dim coordinates, point i at coords[i * dim .. i * dim + dim - 1]. */
typedef struct {
    int dim;
    long n;
    const double *coords;
} hs_case;

/* The answer being written (use hs_printf / hs_reject). */
typedef struct {
    char *text;
    size_t len, cap;
    char message[512];
    int rejected;
} hs_answer;

typedef int (*hs_hull_fn)(const hs_case *c, hs_answer *a);

/* Append formatted text to the answer. */
static void hs_printf(hs_answer *a, const char *fmt, ...) {
    for (;;) {
        va_list ap;
        size_t room = a->cap - a->len;
        int k;
        va_start(ap, fmt);
        k = vsnprintf(a->text ? a->text + a->len : NULL, a->text ? room : 0, fmt, ap);
        va_end(ap);
        if (k < 0) return;
        if (a->text && (size_t)k < room) { a->len += (size_t)k; return; }
        a->cap = (a->cap + (size_t)k + 1) * 2;
        a->text = (char *)realloc(a->text, a->cap);
        if (!a->text) { fputs("hullstress_driver: out of memory\n", stderr); exit(2); }
    }
}

/* Reject the case (degenerate input the library refuses): an error row, the driver goes on. */
static int hs_reject(hs_answer *a, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(a->message, sizeof a->message, fmt, ap);
    va_end(ap);
    for (char *p = a->message; *p; ++p) if (*p == '\n' || *p == '\r') *p = ' ';
    a->rejected = 1;
    return 1;
}

static void hs_handshake(const hs_driver *d) {
    printf("hullstress-exec/%d\tdim=%d\toutput=%s\tdriver=%s\tlibrary=%s\n", HS_PROTOCOL_VERSION, d->dim,
           d->output, d->driver ? d->driver : "", d->library ? d->library : "");
    fflush(stdout);
}

/* Read "dim\ncount\n" then count points; returns 0 at end of input, -1 on bad input, 1 on a case. */
static int hs_read_points(FILE *in, int want_dim, hs_case *c, double **buf, size_t *cap) {
    int dim;
    long n;
    if (fscanf(in, "%d", &dim) != 1) return 0;
    if (fscanf(in, "%ld", &n) != 1 || n < 0) return -1;
    if (dim != want_dim && n == want_dim) { long t = n; n = dim; dim = (int)t; } /* Qhull's either order */
    if (dim != want_dim) return -1;
    if ((size_t)(n * dim) > *cap) {
        *cap = (size_t)(n * dim) * 2;
        *buf = (double *)realloc(*buf, *cap * sizeof(double));
        if (!*buf) return -1;
    }
    for (long i = 0; i < n * dim; ++i)
        if (fscanf(in, "%lf", &(*buf)[i]) != 1) return -1;
    c->dim = dim;
    c->n = n;
    c->coords = *buf;
    return 1;
}

/* Run the driver: persistent when HULLSTRESS_EXEC_PROTOCOL is set, else one case (spawn mode). */
static int hs_main(const hs_driver *d, int argc, char **argv, hs_hull_fn hull) {
    double *buf = NULL;
    size_t cap = 0;
    hs_case c;
    hs_answer a;
    int persistent = getenv("HULLSTRESS_EXEC_PROTOCOL") != NULL;
    memset(&a, 0, sizeof a);
    if (argc > 1 && strcmp(argv[argc - 1], "--version") == 0) { hs_handshake(d); return 0; }
    if (!persistent) {
        int got = hs_read_points(stdin, d->dim, &c, &buf, &cap);
        if (got != 1) { fprintf(stderr, "%s: cannot read %dD points in Qhull's format\n", argv[0], d->dim); return 2; }
        if (hull(&c, &a) || a.rejected) {
            fprintf(stderr, "%s\n", a.message[0] ? a.message : "case rejected");
            return 1;
        }
        fwrite(a.text, 1, a.len, stdout);
        return 0;
    }
    hs_handshake(d);
    for (;;) {
        long number;
        int got;
        if (scanf(" case %ld", &number) != 1) return 0; /* end of file: stop */
        got = hs_read_points(stdin, d->dim, &c, &buf, &cap);
        a.len = 0;
        a.rejected = 0;
        a.message[0] = '\0';
        if (got != 1) {
            printf("error %ld cannot read %dD points in Qhull's format\n", number, d->dim);
        } else if (hull(&c, &a) || a.rejected) {
            printf("error %ld %s\n", number, a.message[0] ? a.message : "case rejected");
        } else {
            printf("hull %ld\n", number);
            fwrite(a.text, 1, a.len, stdout);
            if (a.len && a.text[a.len - 1] != '\n') putchar('\n');
            printf("end %ld\n", number);
        }
        fflush(stdout);
    }
}

#endif /* HULLSTRESS_DRIVER_H */
