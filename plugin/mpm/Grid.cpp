#include "plugin/mpm/Grid.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace shatter::mpm {

void Grid::reset(const Box& bounds, double cellSize, int padCells, int fieldCount, bool withCrackData,
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
        node[f].assign(size, Node{});
        displacement[f].assign(withCrackData ? size : 0, Vec2::Zero());
    }
    crackNormal.assign(withCrackData ? n : 0, Vec2::Zero());
    fixedNode.assign(n, 0);
}

} // namespace shatter::mpm
