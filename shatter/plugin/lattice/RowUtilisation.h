#pragma once
// The break and weakening checks' pass over a system's rows (FractureAnalysis), a packet of
// rows at a time.
#include <shatter/plugin/lattice/BreakingRules.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace shatter::lattice {

// Calls found(row, u) for each row, in row order, whose utilisation u = utilisation(strength,
// λ, ratio) is not below `onset` (NaN included) or is above 1: the rows the plain loop over
// every row picks. Each lane forms u by utilisation's operations (−λ or λ / ratio, then
// force / strength, or ∞ / 0 where the strength is not positive), so u has its bits; most
// packets hold no such row and cost one test. Returns the largest u, std::max(most, u) over
// the rows in order, as the plain loop forms it: per lane, then over the lanes, which can
// differ from the loop only where the largest u is ±0 (a tie of zeros of either sign), so then
// (no row carries a load) the loop forms it again.
template <class Found>
double scanUtilisation(size_t rows, const double* strengths, const double* lambdas, double ratio, double onset,
                       double most, Found&& found) {
    namespace packets = Eigen::internal;
    using Packet = packets::packet_traits<double>::type;
    constexpr size_t lanes = size_t(packets::packet_traits<double>::size);
    const Packet zero = packets::pset1<Packet>(0.0), one = packets::pset1<Packet>(1.0);
    const Packet ratios = packets::pset1<Packet>(ratio), onsets = packets::pset1<Packet>(onset);
    const Packet infinity = packets::pset1<Packet>(INFINITY), every = packets::ptrue(zero);
    const size_t packetsEnd = rows / lanes * lanes;
    const double start = most;
    Packet largest = packets::pset1<Packet>(most);
    for (size_t k = 0; k < packetsEnd; k += lanes) {
        const Packet lambda = packets::ploadu<Packet>(lambdas + k), strength = packets::ploadu<Packet>(strengths + k);
        const Packet force =
            packets::pselect(packets::pcmp_lt(lambda, zero), packets::pnegate(lambda), packets::pdiv(lambda, ratios));
        const Packet u = packets::pselect(packets::pcmp_lt(zero, strength), packets::pdiv(force, strength),
                                          packets::pselect(packets::pcmp_lt(zero, force), infinity, zero));
        largest = packets::pmax(largest, u); // std::max(largest, u) lane by lane
        const Packet picked = packets::por(packets::pandnot(every, packets::pcmp_lt(u, onsets)), packets::pcmp_lt(one, u));
        if (!packets::predux_any(picked)) continue;
        double values[lanes];
        packets::pstoreu(values, u);
        for (size_t lane = 0; lane < lanes; ++lane)
            if (!(values[lane] < onset) || values[lane] > 1.0) found(k + lane, values[lane]);
    }
    double values[lanes];
    packets::pstoreu(values, largest);
    for (size_t lane = 0; lane < lanes; ++lane) most = std::max(most, values[lane]);
    for (size_t k = packetsEnd; k < rows; ++k) {
        const double u = utilisation(strengths[k], lambdas[k], ratio);
        most = std::max(most, u);
        if (!(u < onset) || u > 1.0) found(k, u);
    }
    if (!(most > 0.0)) { // a zero's sign (or NaN): the loop's own order
        most = start;
        for (size_t k = 0; k < rows; ++k) most = std::max(most, utilisation(strengths[k], lambdas[k], ratio));
    }
    return most;
}

} // namespace shatter::lattice
