#include "demos/runner/BodyColour.h"

#include <cmath>
#include <cstdint>

namespace shatter::demo {

Rgb bodyColour(const std::string& name) {
    std::uint32_t h = 2166136261u;
    for (unsigned char c : name) h = (h ^ c) * 16777619u;
    const double hue = (h % 3600) / 600.0; // sextant in [0, 6)
    const double s = 0.50, v = 0.90;
    const double f = hue - std::floor(hue), p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
    switch (int(hue)) {
    case 0: return {v, t, p};
    case 1: return {q, v, p};
    case 2: return {p, v, t};
    case 3: return {p, q, v};
    case 4: return {t, p, v};
    default: return {v, p, q};
    }
}

Rgb crackColour() { return {0.93, 0.90, 0.83}; }

} // namespace shatter::demo
