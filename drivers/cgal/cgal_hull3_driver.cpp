// hullstress driver for CGAL's convex_hull_3 with the Epick kernel (exact predicates,
// inexact constructions), into a Surface_mesh.  Writes Qhull's i layout: one face per line,
// input point indices, counter-clockwise seen from outside (CGAL's orientation).
// Build: make -C drivers cgal   (needs: apt-get install libcgal-dev)
#include "../kit/hullstress_driver.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>
#include <CGAL/version.h>

#include <exception>
#include <map>
#include <string>
#include <tuple>
#include <vector>

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef K::Point_3 Point;
typedef CGAL::Surface_mesh<Point> Mesh;

static int cgal_hull(const hs_case *c, hs_answer *a) {
    std::vector<Point> points;
    std::map<std::tuple<double, double, double>, long> index;  // the output's vertices are input points
    points.reserve(static_cast<size_t>(c->n));
    for (long i = 0; i < c->n; ++i) {
        const double *p = c->coords + 3 * i;
        points.emplace_back(p[0], p[1], p[2]);
        index.emplace(std::make_tuple(p[0], p[1], p[2]), i);
    }
    Mesh mesh;
    try {
        CGAL::convex_hull_3(points.begin(), points.end(), mesh);
    } catch (const std::exception &e) {
        return hs_reject(a, "CGAL: %s", e.what());
    }
    hs_printf(a, "%ld\n", static_cast<long>(mesh.number_of_faces()));
    for (Mesh::Face_index f : mesh.faces()) {
        bool first = true;
        for (Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
            const Point &p = mesh.point(v);
            auto found = index.find(std::make_tuple(p.x(), p.y(), p.z()));
            if (found == index.end()) return hs_reject(a, "CGAL returned a vertex that is not an input point");
            hs_printf(a, first ? "%ld" : " %ld", found->second);
            first = false;
        }
        hs_printf(a, "\n");
    }
    return 0;
}

int main(int argc, char **argv) {
    hs_driver d = {3, "i", "hullstress CGAL convex_hull_3 driver 1.0 (Epick, Surface_mesh)",
                   "CGAL " CGAL_VERSION_STR};
    return hs_main(&d, argc, argv, cgal_hull);
}
