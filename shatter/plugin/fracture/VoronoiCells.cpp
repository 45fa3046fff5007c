#include <shatter/plugin/fracture/VoronoiCells.h>

#include <shatter/plugin/common/InputError.h>

#include <voro++/voro++.hh>

#include <algorithm>
#include <cmath>
#include <optional>

namespace shatter::fracture {

namespace {

// voro++ gives vertices and faces as flat lists; a face lists its vertex count first.
geometry::ConvexPolyhedron cellPolyhedron(voro::voronoicell_neighbor& cell, const Eigen::Vector3d& site, int index) {
    std::vector<double> flat;
    cell.vertices(site.x(), site.y(), site.z(), flat);
    std::vector<Eigen::Vector3d> vertices;
    for (size_t i = 0; i + 2 < flat.size(); i += 3) vertices.emplace_back(flat[i], flat[i + 1], flat[i + 2]);
    std::vector<int> faceList;
    cell.face_vertices(faceList);
    std::vector<std::vector<int>> faces;
    for (size_t i = 0; i < faceList.size(); i += size_t(faceList[i]) + 1)
        faces.emplace_back(faceList.begin() + long(i) + 1, faceList.begin() + long(i) + 1 + faceList[i]);
    // Orient every face outward: the site lies inside its cell.
    for (auto& f : faces)
        if (geometry::newellNormal(vertices, f).dot(vertices[f[0]] - site) < 0.0) std::reverse(f.begin(), f.end());
    std::vector<int> ids(vertices.size());
    for (size_t i = 0; i < ids.size(); ++i) ids[i] = int(i);
    return geometry::ConvexPolyhedron::create(std::move(vertices), std::move(faces), std::move(ids),
                                              "Voronoi cell " + std::to_string(index));
}

} // namespace

FracturePattern voronoiCellsPattern(const std::vector<Eigen::Vector3d>& sites, const geometry::Aabb& box,
                                    double radius) {
    // About 5 sites per voro++ block is its documented sweet spot.
    const int blocks = std::max(1, int(std::cbrt(double(sites.size()) / 5.0)));
    voro::container container(box.min.x(), box.max.x(), box.min.y(), box.max.y(), box.min.z(), box.max.z(), blocks,
                              blocks, blocks, false, false, false, 8);
    for (size_t i = 0; i < sites.size(); ++i) {
        if (!(sites[i].array() >= box.min.array()).all() || !(sites[i].array() <= box.max.array()).all())
            throw InputError("Voronoi pattern: site " + std::to_string(i) + " lies outside the pattern's box");
        container.put(int(i), sites[i].x(), sites[i].y(), sites[i].z());
    }
    std::vector<std::optional<geometry::ConvexPolyhedron>> bySite(sites.size());
    voro::c_loop_all loop(container);
    voro::voronoicell_neighbor cell;
    if (loop.start()) do {
            if (!container.compute_cell(cell, loop)) continue;
            const int id = loop.pid();
            bySite[size_t(id)] = cellPolyhedron(cell, sites[size_t(id)], id);
        } while (loop.inc());

    FracturePattern pattern;
    pattern.radius = radius;
    for (size_t i = 0; i < sites.size(); ++i)
        if (bySite[i]) { // a site on top of another one has no cell of its own
            pattern.cells.push_back(std::move(*bySite[i]));
            pattern.centres.push_back(sites[i]);
        }
    finishPattern(pattern);
    setBoxDomain(pattern, box); // voro++ cells fill their container
    return pattern;
}

} // namespace shatter::fracture
