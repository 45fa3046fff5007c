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

// Splits particle p's square `square` (reference frame) along the chord entry→exit when both
// parts reach `minimumShare`: the "below" part keeps index p, the "above" part is appended
// with the same state. `toCurrent` maps a reference point of the square to where it is now.
template <class ToCurrent>
bool splitParticle(Particles& particles, size_t p, const Box& square, const Vec2& entry, const Vec2& exit,
                   double minimumShare, const ToCurrent& toCurrent) {
    const Part above = sideOfBox(square, entry, exit, true), below = sideOfBox(square, entry, exit, false);
    const double whole = above.area + below.area;
    if (std::min(above.area, below.area) < minimumShare * whole) return false;
    const double mass = particles.mass[p], volume = particles.volume0[p];
    particles.add(toCurrent(above.centroid), particles.v[p], mass * above.area / whole, volume * above.area / whole,
                  particles.material[p], particles.body[p]);
    const size_t q = particles.size() - 1;
    particles.x0[q] = above.centroid;
    particles.C[q] = particles.C[p];
    particles.Fe[q] = particles.Fe[p];
    particles.Fp[q] = particles.Fp[p];
    particles.fixed[q] = particles.fixed[p];
    particles.x[p] = toCurrent(below.centroid);
    particles.x0[p] = below.centroid;
    particles.mass[p] = mass * below.area / whole;
    particles.volume0[p] = volume * below.area / whole;
    return true;
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
            split += splitParticle(particles, p, square, entry, exit, minimumShare, [](const Vec2& X) { return X; });
        }
    }
    return split;
}

size_t splitParticlesAtGrowth(const Crack& crack, int tip, double h, Particles& particles, double minimumShare) {
    const size_t n = crack.points.size();
    if (n < 2) return 0;
    const Vec2 to = crack.tipPosition(tip), from = tip == 0 ? crack.points[1] : crack.points[n - 2];
    // The crack near the step, in the polyline's order (its left is "above"); the squares
    // the step can complete a crossing of lie within a cell of it.
    const size_t kept = std::min<size_t>(n, 6);
    const std::vector<Vec2> near(tip == 0 ? crack.points.begin() : crack.points.end() - long(kept),
                                 tip == 0 ? crack.points.begin() + long(kept) : crack.points.end());
    const size_t count = particles.size();
    size_t split = 0;
    for (size_t p = 0; p < count; ++p) {
        // Parts of a split square (less than the whole, the seeding's h²) are not split again.
        if (particles.volume0[p] < (1 - minimumShare) * h * h) continue;
        const Vec2 d = to - from, x = particles.x[p];
        const double u = std::clamp((x - from).dot(d) / d.squaredNorm(), 0.0, 1.0);
        if ((x - (from + u * d)).squaredNorm() > h * h) continue;
        // The square is the particle's in the reference configuration; the crack is taken
        // there through the particle's deformation gradient (affine over one particle).
        const Mat2 F = particles.Fe[p] * particles.Fp[p];
        const Mat2 Finv = F.inverse();
        const Vec2 X0 = particles.x0[p];
        std::vector<Vec2> local;
        for (const Vec2& c : near) local.push_back(X0 + Finv * (c - x));
        const Box square{X0 - Vec2::Constant(0.5 * h), X0 + Vec2::Constant(0.5 * h)};
        Vec2 entry, exit;
        if (!chordThrough(local, square, entry, exit)) continue;
        split += splitParticle(particles, p, square, entry, exit, minimumShare,
                               [&](const Vec2& X) { return Vec2(x + F * (X - X0)); });
    }
    return split;
}

} // namespace shatter::mpm
