/* The driver kit's C example: Andrew's monotone chain in 2D, writing Qhull's Fx
 * (the extreme points, counter-clockwise).  Build: make -C drivers example
 * Run:   python -m hullstress run --exec 'mc[dim=2,output=Fx,mode=persistent]=drivers/build/monotone_chain' */
#include "../kit/hullstress_driver.h"

typedef struct { double x, y; long i; } point;

static int by_xy(const void *a, const void *b) {
    const point *p = (const point *)a, *q = (const point *)b;
    if (p->x != q->x) return p->x < q->x ? -1 : 1;
    if (p->y != q->y) return p->y < q->y ? -1 : 1;
    return 0;
}

static double cross(point o, point a, point b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

static int monotone_chain(const hs_case *c, hs_answer *a) {
    long n = c->n, k = 0;
    point *p = (point *)malloc(sizeof(point) * (n ? n : 1));
    long *h = (long *)malloc(sizeof(long) * (2 * n + 2));
    for (long i = 0; i < n; i++) { p[i].x = c->coords[2 * i]; p[i].y = c->coords[2 * i + 1]; p[i].i = i; }
    qsort(p, (size_t)n, sizeof(point), by_xy);
    for (long i = 0; i < n; i++) {                          /* lower hull */
        while (k >= 2 && cross(p[h[k - 2]], p[h[k - 1]], p[i]) <= 0) k--;
        h[k++] = i;
    }
    for (long i = n - 2, t = k + 1; i >= 0; i--) {          /* upper hull */
        while (k >= t && cross(p[h[k - 2]], p[h[k - 1]], p[i]) <= 0) k--;
        h[k++] = i;
    }
    if (k > 1) k--;                                         /* the last point is the first */
    hs_printf(a, "%ld\n", k);
    for (long i = 0; i < k; i++) hs_printf(a, "%ld\n", p[h[i]].i);
    free(p);
    free(h);
    return 0;
}

int main(int argc, char **argv) {
    hs_driver d = {2, "Fx", "monotone_chain example 1.0", "none"};
    return hs_main(&d, argc, argv, monotone_chain);
}
