#include <shatter/plugin/lattice/TetGenerators.h>

#include <shatter/plugin/common/InputError.h>
#include <shatter/plugin/lattice/Random.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

namespace shatter::lattice {

namespace {

void require(bool ok, const std::string& name, const std::string& problem) {
    if (!ok) throw InputError(name + ": " + problem);
}

void checkOptions(const GeneratorOptions& o, const std::string& name) {
    require(std::isfinite(o.jitter) && o.jitter >= 0.0 && o.jitter <= 0.2, name,
            "jitter must be in [0, 0.2] (fraction of a cell), got " + std::to_string(o.jitter));
}

void checkLength(double v, const std::string& name, const char* what) {
    std::ostringstream msg;
    msg << what << " must be positive and finite, got " << v << " m";
    require(std::isfinite(v) && v > 0.0, name, msg.str());
}

void checkCount(int v, int most, const std::string& name, const char* what) {
    require(v >= 1 && v <= most, name,
            std::string(what) + " must be in [1, " + std::to_string(most) + "], got " + std::to_string(v));
}

// Orders a tet's corners for positive volume (the generators build them on exact grids,
// where the sign is never in doubt).
Tet oriented(const std::vector<Eigen::Vector3d>& nodes, Tet t) {
    const Eigen::Vector3d& a = nodes[t[0]];
    if ((nodes[t[1]] - a).dot((nodes[t[2]] - a).cross(nodes[t[3]] - a)) < 0) std::swap(t[1], t[2]);
    return t;
}

// Moves node coordinates by up to `jitter` cells along the axes where `movable` says so.
void applyJitter(std::vector<Eigen::Vector3d>& nodes, const std::vector<Eigen::Vector3d>& cellSize,
                 const std::vector<Eigen::Vector3d>& movable, const GeneratorOptions& o) {
    if (o.jitter == 0.0) return;
    Random random(o.seed);
    for (size_t i = 0; i < nodes.size(); ++i)
        for (int a = 0; a < 3; ++a) {
            const double d = random.uniform(-o.jitter, o.jitter) * cellSize[i][a];
            nodes[i][a] += movable[i][a] * d;
        }
}

TetMesh finish(std::string name, std::vector<Eigen::Vector3d> nodes, std::vector<Tet> tets) {
    return makeTetMesh(std::move(name), std::move(nodes), std::move(tets));
}

} // namespace

TetMesh tetBox(const Eigen::Vector3d& extent, const Eigen::Vector3i& cells, const GeneratorOptions& options) {
    const std::string name = options.name.empty() ? "box" : options.name;
    checkOptions(options, name);
    for (int a = 0; a < 3; ++a) {
        checkLength(extent[a], name, "extent");
        checkCount(cells[a], 200, name, "cells per axis");
    }
    const Eigen::Vector3i n = cells.array() + 1;
    auto id = [&](int i, int j, int k) { return (k * n.y() + j) * n.x() + i; };
    const Eigen::Vector3d h = extent.cwiseQuotient(cells.cast<double>());
    std::vector<Eigen::Vector3d> nodes, size, movable;
    for (int k = 0; k < n.z(); ++k)
        for (int j = 0; j < n.y(); ++j)
            for (int i = 0; i < n.x(); ++i) {
                nodes.push_back(Eigen::Vector3d(i, j, k).cwiseProduct(h) - 0.5 * extent);
                size.push_back(h);
                const Eigen::Vector3i c(i, j, k);
                Eigen::Vector3d m;
                for (int a = 0; a < 3; ++a) m[a] = (c[a] == 0 || c[a] == cells[a]) ? 0.0 : 1.0;
                movable.push_back(m);
            }
    // Kuhn: the six monotone paths from corner 000 to 111, one per axis order.
    static const std::array<std::array<int, 3>, 6> orders = {
        {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
    std::vector<Tet> tets;
    tets.reserve(size_t(cells.prod()) * 6);
    for (int k = 0; k < cells.z(); ++k)
        for (int j = 0; j < cells.y(); ++j)
            for (int i = 0; i < cells.x(); ++i)
                for (const auto& order : orders) {
                    Eigen::Vector3i c(i, j, k);
                    Tet t;
                    t[0] = id(c.x(), c.y(), c.z());
                    for (int s = 0; s < 3; ++s) {
                        ++c[order[s]];
                        t[s + 1] = id(c.x(), c.y(), c.z());
                    }
                    tets.push_back(oriented(nodes, t));
                }
    applyJitter(nodes, size, movable, options);
    return finish(name, std::move(nodes), std::move(tets));
}

TetMesh tetSlab(double sizeX, double sizeZ, double thickness, double cellSize, int layers,
                const GeneratorOptions& options) {
    const std::string name = options.name.empty() ? "slab" : options.name;
    checkLength(sizeX, name, "size x");
    checkLength(sizeZ, name, "size z");
    checkLength(thickness, name, "thickness");
    checkLength(cellSize, name, "cell size");
    checkCount(layers, 200, name, "layers");
    const Eigen::Vector3i cells(std::max(1, int(std::lround(sizeX / cellSize))), layers,
                                std::max(1, int(std::lround(sizeZ / cellSize))));
    GeneratorOptions o = options;
    o.name = name;
    return tetBox(Eigen::Vector3d(sizeX, thickness, sizeZ), cells, o);
}

namespace {

// A disc of `rings` rings of nodes around the centre (ring r has 6r nodes, spaced evenly from
// angle 0), triangulated band by band by zipping neighbouring rings together by angle.
struct Disc {
    std::vector<Eigen::Vector2d> points;
    std::vector<bool> outer;
    std::vector<std::array<int, 3>> triangles; // any winding: the tets are oriented afterwards
};

Disc makeDisc(double radius, int rings) {
    Disc d;
    d.points.push_back(Eigen::Vector2d::Zero());
    d.outer.push_back(false);
    std::vector<int> first{0}, count{1};
    for (int r = 1; r <= rings; ++r) {
        first.push_back(int(d.points.size()));
        count.push_back(6 * r);
        for (int k = 0; k < 6 * r; ++k) {
            const double angle = 2.0 * M_PI * k / (6.0 * r);
            d.points.emplace_back(radius * r / rings * std::cos(angle), radius * r / rings * std::sin(angle));
            d.outer.push_back(r == rings);
        }
    }
    for (int r = 1; r <= rings; ++r) {
        // Zip the inner ring (r-1) and the outer ring (r) together by angle.
        const int ni = count[r - 1], no = count[r];
        int i = r == 1 ? ni : 0, o = 0; // the centre is a single node: only the outer ring advances
        auto inner = [&](int k) { return first[r - 1] + (k % ni); };
        auto outerId = [&](int k) { return first[r] + (k % no); };
        while (i < ni || o < no) {
            const double ai = double(i + 1) / ni, ao = double(o + 1) / no;
            if (o < no && (ao <= ai || i >= ni)) {
                d.triangles.push_back({inner(i), outerId(o), outerId(o + 1)});
                ++o;
            } else {
                d.triangles.push_back({inner(i), outerId(o), inner(i + 1)});
                ++i;
            }
        }
    }
    return d;
}

// The three tets of prism (a, b, c) below (a', b', c') = +offset, split by the
// smallest-index rule: each quad face is cut by the diagonal through its smallest node.
void splitPrism(std::array<int, 3> tri, int offset, const std::vector<Eigen::Vector3d>& nodes, std::vector<Tet>& tets) {
    std::sort(tri.begin(), tri.end());
    const int a = tri[0], b = tri[1], c = tri[2];
    const int a2 = a + offset, b2 = b + offset, c2 = c + offset;
    tets.push_back(oriented(nodes, {a, b, c, c2}));
    tets.push_back(oriented(nodes, {a, b, b2, c2}));
    tets.push_back(oriented(nodes, {a, a2, b2, c2}));
}

} // namespace

TetMesh tetCylinder(double radius, double height, int rings, int layers, const GeneratorOptions& options) {
    const std::string name = options.name.empty() ? "cylinder" : options.name;
    checkOptions(options, name);
    checkLength(radius, name, "radius");
    checkLength(height, name, "height");
    checkCount(rings, 100, name, "rings");
    checkCount(layers, 200, name, "layers");
    const Disc disc = makeDisc(radius, rings);
    const int perLayer = int(disc.points.size());
    const double ringStep = radius / rings, layerStep = height / layers;
    std::vector<Eigen::Vector3d> nodes, size, movable;
    for (int l = 0; l <= layers; ++l)
        for (int p = 0; p < perLayer; ++p) {
            nodes.emplace_back(disc.points[p].x(), -0.5 * height + l * layerStep, disc.points[p].y());
            size.emplace_back(ringStep, layerStep, ringStep);
            const double inPlane = disc.outer[p] ? 0.0 : 1.0;
            movable.emplace_back(inPlane, (l == 0 || l == layers) ? 0.0 : 1.0, inPlane);
        }
    std::vector<Tet> tets;
    tets.reserve(disc.triangles.size() * 3 * size_t(layers));
    for (int l = 0; l < layers; ++l)
        for (auto tri : disc.triangles) {
            for (int& v : tri) v += l * perLayer;
            splitPrism(tri, perLayer, nodes, tets);
        }
    applyJitter(nodes, size, movable, options);
    return finish(name, std::move(nodes), std::move(tets));
}

} // namespace shatter::lattice
