#include <shatter/plugin/mpm/CrackSetup.h>

#include <cmath>

namespace shatter::mpm {

std::vector<Vec2> resamplePath(const std::vector<Vec2>& path, double step) {
    std::vector<Vec2> out;
    double carried = 0; // arc length since the last emitted point
    for (size_t k = 0; k + 1 < path.size(); ++k) {
        const Vec2 a = path[k], b = path[k + 1];
        const double length = (b - a).norm();
        double s = step - carried;
        while (s < length - 1e-9 * step) {
            out.push_back(a + (b - a) * (s / length));
            s += step;
        }
        carried = length - (s - step);
    }
    if (out.empty() || (out.back() - path.back()).norm() > 1e-9 * step) out.push_back(path.back());
    return out;
}

namespace {

std::vector<Vec2> subdivide(const std::vector<Vec2>& points, double maxLength) {
    std::vector<Vec2> out{points.front()};
    for (size_t k = 0; k + 1 < points.size(); ++k) {
        const Vec2 a = points[k], b = points[k + 1];
        const int pieces = std::max(1, int(std::ceil((b - a).norm() / maxLength - 1e-9)));
        for (int i = 1; i <= pieces; ++i) out.push_back(a + (b - a) * (double(i) / pieces));
    }
    return out;
}

} // namespace

std::vector<Crack> buildCracks(const Scene& scene) {
    const double growth = scene.fracture.growthCells * scene.grid.dx;
    std::vector<Crack> cracks;
    for (const CrackSpec& spec : scene.cracks) {
        Crack c;
        c.points = subdivide(spec.points, growth);
        c.above.assign(c.points.size(), Vec2::Zero());
        c.below.assign(c.points.size(), Vec2::Zero());
        c.tips[0].active = spec.tips == TipSelection::Both || spec.tips == TipSelection::Start;
        c.tips[1].active = spec.tips == TipSelection::Both || spec.tips == TipSelection::End;
        for (int t = 0; t < 2; ++t) c.tips[size_t(t)].propagates = spec.propagate && c.tips[size_t(t)].active;
        if (!spec.guide.empty()) {
            // The guide belongs to the active tip nearest to its first point.
            int tip = c.tips[1].active ? 1 : 0;
            if (c.tips[0].active && c.tips[1].active &&
                (spec.guide.front() - c.points.front()).norm() < (spec.guide.front() - c.points.back()).norm())
                tip = 0;
            std::vector<Vec2> path{c.tipPosition(tip)};
            path.insert(path.end(), spec.guide.begin(), spec.guide.end());
            const auto resampled = resamplePath(path, growth);
            c.tips[size_t(tip)].guide.assign(resampled.begin(), resampled.end());
        }
        cracks.push_back(std::move(c));
    }
    return cracks;
}

} // namespace shatter::mpm
