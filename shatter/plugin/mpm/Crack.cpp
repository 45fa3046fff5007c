#include <shatter/plugin/mpm/Crack.h>

namespace shatter::mpm {

Vec2 Crack::tipDirection(int tip) const {
    const size_t n = points.size();
    const Vec2 d = tip == 0 ? Vec2(points[0] - points[1]) : Vec2(points[n - 1] - points[n - 2]);
    return d.normalized();
}

void Crack::extend(int tip, const Vec2& p) {
    if (tip == 0) {
        points.insert(points.begin(), p);
        above.insert(above.begin(), Vec2::Zero());
        below.insert(below.begin(), Vec2::Zero());
    } else {
        points.push_back(p);
        above.push_back(Vec2::Zero());
        below.push_back(Vec2::Zero());
    }
}

} // namespace shatter::mpm
