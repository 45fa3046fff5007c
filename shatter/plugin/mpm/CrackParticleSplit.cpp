#include <shatter/plugin/mpm/CrackParticleSplit.h>

#include <algorithm>
#include <cmath>

namespace shatter::mpm {

namespace {

// Part of segment a→b inside `box` as parameters [t0, t1] (Liang-Barsky); false if none.
bool clipSegment(const Vec2& a, const Vec2& b, const Box& box, double& t0, double& t1) {
    t0 = 0;
    t1 = 1;
    const Vec2 d = b - a;
    for (int axis = 0; axis < 2; ++axis) {
        if (d[axis] == 0) {
            if (a[axis] < box.min[axis] || a[axis] > box.max[axis]) return false;
            continue;
        }
        double lo = (box.min[axis] - a[axis]) / d[axis], hi = (box.max[axis] - a[axis]) / d[axis];
        if (lo > hi) std::swap(lo, hi);
        t0 = std::max(t0, lo);
        t1 = std::min(t1, hi);
        if (t0 > t1) return false;
    }
    return true;
}

bool strictlyInside(const Vec2& p, const Box& box) {
    return p.x() > box.min.x() && p.x() < box.max.x() && p.y() > box.min.y() && p.y() < box.max.y();
}

// The chord where crack `points` crosses `box` whole: entry and exit on its outline. False
// when the crack misses the box, ends inside it, or enters it more than once.
bool chordThrough(const std::vector<Vec2>& points, const Box& box, Vec2& entry, Vec2& exit) {
    if (strictlyInside(points.front(), box) || strictlyInside(points.back(), box)) return false;
    int first = -1, last = -1;
    for (size_t k = 0; k + 1 < points.size(); ++k) {
        double t0, t1;
        if (!clipSegment(points[k], points[k + 1], box, t0, t1)) {
            if (first >= 0 && last < 0) last = int(k) - 1; // left the box
            continue;
        }
        if (last >= 0) return false; // entered a second time
        if (first < 0) {
            first = int(k);
            entry = points[k] + t0 * (points[k + 1] - points[k]);
        }
        exit = points[k] + t1 * (points[k + 1] - points[k]);
    }
    return first >= 0 && (exit - entry).norm() > 1e-9 * (box.max - box.min).norm();
}

struct Part {
    double area = 0;
    Vec2 centroid = Vec2::Zero();
};

// Area and centroid of the part of `box` on the left of the line a→b (left: true) or right.
Part sideOfBox(const Box& box, const Vec2& a, const Vec2& b, bool left) {
    const Vec2 corners[4] = {box.min, Vec2(box.max.x(), box.min.y()), box.max, Vec2(box.min.x(), box.max.y())};
    std::vector<Vec2> poly; // the square clipped by the half-plane (one Sutherland-Hodgman pass)
    for (int k = 0; k < 4; ++k) {
        const Vec2 p = corners[k], q = corners[(k + 1) % 4];
        const double sp = (left ? 1 : -1) * orient(a, b, p), sq = (left ? 1 : -1) * orient(a, b, q);
        if (sp >= 0) poly.push_back(p);
        if ((sp > 0 && sq < 0) || (sp < 0 && sq > 0)) poly.push_back(p + (q - p) * (sp / (sp - sq)));
    }
    Part part;
    double twiceArea = 0;
    Vec2 weighted = Vec2::Zero();
    for (size_t k = 0; k < poly.size(); ++k) {
        const Vec2& p = poly[k];
        const Vec2& q = poly[(k + 1) % poly.size()];
        const double cross = p.x() * q.y() - q.x() * p.y();
        twiceArea += cross;
        weighted += cross * (p + q);
    }
    part.area = 0.5 * twiceArea;
    if (part.area > 0) part.centroid = weighted / (3 * twiceArea);
    return part;
}

} // namespace

size_t splitParticlesAtCracks(const std::vector<Crack>& cracks, double h, Particles& particles, double minimumShare) {
    const size_t n = particles.size();
    size_t split = 0;
    for (const Crack& crack : cracks) {
        Box bounds{crack.points.front(), crack.points.front()};
        for (const Vec2& p : crack.points) {
            bounds.min = bounds.min.cwiseMin(p);
            bounds.max = bounds.max.cwiseMax(p);
        }
        bounds.min -= Vec2::Constant(h);
        bounds.max += Vec2::Constant(h);
        for (size_t p = 0; p < n; ++p) {
            const Vec2 centre = particles.x0[p];
            if (!bounds.contains(centre)) continue;
            const Box square{centre - Vec2::Constant(0.5 * h), centre + Vec2::Constant(0.5 * h)};
            Vec2 entry, exit;
            if (!chordThrough(crack.points, square, entry, exit)) continue;
            const Part above = sideOfBox(square, entry, exit, true), below = sideOfBox(square, entry, exit, false);
            const double whole = above.area + below.area;
            if (std::min(above.area, below.area) < minimumShare * whole) continue;
            const double mass = particles.mass[p], volume = particles.volume0[p];
            particles.add(above.centroid, particles.v[p], mass * above.area / whole, volume * above.area / whole,
                          particles.material[p], particles.body[p]);
            particles.x[p] = particles.x0[p] = below.centroid;
            particles.mass[p] = mass * below.area / whole;
            particles.volume0[p] = volume * below.area / whole;
            ++split;
        }
    }
    return split;
}

} // namespace shatter::mpm
