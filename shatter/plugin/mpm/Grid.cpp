#include <shatter/plugin/mpm/Grid.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace shatter::mpm {

void Grid::resize(const Box& bounds, double cellSize, int padCells, int fieldCount, bool withCrackData,
                  size_t maxNodes) {
    dx = cellSize;
    invDx = 1 / cellSize;
    const double i0 = std::floor(bounds.min.x() * invDx) - padCells, j0 = std::floor(bounds.min.y() * invDx) - padCells;
    const double i1 = std::ceil(bounds.max.x() * invDx) + padCells, j1 = std::ceil(bounds.max.y() * invDx) + padCells;
    const double count = (i1 - i0 + 1) * (j1 - j0 + 1);
    if (!std::isfinite(count) || count > double(maxNodes)) {
        std::ostringstream s;
        s << "the particles spread over [" << bounds.min.x() << ", " << bounds.max.x() << "] x [" << bounds.min.y()
          << ", " << bounds.max.y() << "] m, which needs more than " << maxNodes
          << " grid nodes: the simulation became unstable or a body flew away";
        throw std::runtime_error(s.str());
    }
    origin = Vec2(i0 * dx, j0 * dx);
    nx = int(i1 - i0) + 1;
    ny = int(j1 - j0) + 1;
    fields = fieldCount;
    const size_t n = nodeCount();
    for (int f = 0; f < maxFields; ++f) {
        const size_t size = f < fields ? n : 0;
        node[f].resize(size);
        // Vec2's default constructor leaves it uninitialised: new entries are set to zero.
        displacement[f].resize(withCrackData ? size : 0, Vec2::Zero());
    }
    crackNormal.resize(withCrackData ? n : 0, Vec2::Zero());
    fixedNode.resize(n);
}

void Grid::clearField0(size_t first, size_t last) {
    std::fill(node[0].begin() + long(first), node[0].begin() + long(last), Node{});
    std::fill(fixedNode.begin() + long(first), fixedNode.begin() + long(last), 0);
}

void Grid::clearCrackData(const NodeRange& range) {
    for (int j = std::max(range.j0, 0); j <= std::min(range.j1, ny - 1); ++j) {
        const long a = long(index(std::max(range.i0, 0), j)), b = long(index(std::min(range.i1, nx - 1), j)) + 1;
        if (b <= a) continue;
        for (int f = 0; f < fields; ++f) {
            if (f > 0) std::fill(node[f].begin() + a, node[f].begin() + b, Node{});
            if (!displacement[f].empty())
                std::fill(displacement[f].begin() + a, displacement[f].begin() + b, Vec2::Zero());
        }
        if (!crackNormal.empty()) std::fill(crackNormal.begin() + a, crackNormal.begin() + b, Vec2::Zero());
    }
}

} // namespace shatter::mpm
