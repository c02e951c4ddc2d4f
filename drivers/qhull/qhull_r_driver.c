/* hullstress driver for Qhull's reentrant C library (libqhull_r), 3D, with the options
 * scipy.spatial.ConvexHull uses by default ("i Qt": triangulated output).  Writes Qhull's
 * i layout (one triangle per line, vertex indices), counter-clockwise seen from outside.
 * Build: make -C drivers qhull   (needs: apt-get install libqhull-dev) */
#define _GNU_SOURCE
#include "../kit/hullstress_driver.h"
#include <libqhull_r/qhull_ra.h>

#define OPTIONS "qhull i Qt"

static int qhull_hull(const hs_case *c, hs_answer *a) {
    qhT qh_qh;
    qhT *qh = &qh_qh;
    char *errtext = NULL;
    size_t errlen = 0;
    FILE *err = open_memstream(&errtext, &errlen);
    int curlong, totlong, code;
    /* qh_new_qhull may keep the array: give it a copy it can own (ismalloc False: we free it). */
    coordT *pts = (coordT *)malloc(sizeof(coordT) * (size_t)(c->n * 3 + 1));
    memcpy(pts, c->coords, sizeof(coordT) * (size_t)(c->n * 3));
    qh_zero(qh, err);
    code = qh_new_qhull(qh, 3, (int)c->n, pts, False, (char *)OPTIONS, NULL, err);
    if (!code) {
        facetT *facet;
        vertexT *vertex, **vertexp;
        int count = 0;
        FORALLfacets { count++; }
        hs_printf(a, "%d\n", count);
        FORALLfacets {
            int ids[3], k = 0;
            double *p[3], u[3], v[3], nrm[3];
            FOREACHvertex_(facet->vertices) {
                if (k < 3) { ids[k] = qh_pointid(qh, vertex->point); p[k] = vertex->point; }
                k++;
            }
            if (k != 3) { hs_reject(a, "qhull gave a facet of %d vertices with Qt", k); break; }
            for (int j = 0; j < 3; j++) { u[j] = p[1][j] - p[0][j]; v[j] = p[2][j] - p[0][j]; }
            nrm[0] = u[1] * v[2] - u[2] * v[1];
            nrm[1] = u[2] * v[0] - u[0] * v[2];
            nrm[2] = u[0] * v[1] - u[1] * v[0];
            /* Qhull's vertex order is not its orientation: turn each triangle to its outward normal. */
            if (nrm[0] * facet->normal[0] + nrm[1] * facet->normal[1] + nrm[2] * facet->normal[2] < 0) {
                int t = ids[1]; ids[1] = ids[2]; ids[2] = t;
            }
            hs_printf(a, "%d %d %d\n", ids[0], ids[1], ids[2]);
        }
    }
    qh_freeqhull(qh, !qh_ALL);
    qh_memfreeshort(qh, &curlong, &totlong);
    fclose(err);
    free(pts);
    if (code) {
        char *line = errtext ? strtok(errtext, "\n") : NULL;
        hs_reject(a, "qhull error %d: %s", code, line ? line : "(no message)");
    }
    free(errtext);
    return a->rejected;
}

int main(int argc, char **argv) {
    char library[128];
    hs_driver d = {3, "i", "hullstress qhull_r driver 1.0 (" OPTIONS ")", library};
    snprintf(library, sizeof library, "libqhull_r %s", qh_version);
    return hs_main(&d, argc, argv, qhull_hull);
}
