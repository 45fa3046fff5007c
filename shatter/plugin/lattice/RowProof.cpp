#include <shatter/plugin/lattice/RowProof.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>

namespace shatter::lattice {

namespace {

template <bool Decide>
RowProof sums(size_t rows, const double* r, const double* x, const double* d, const double* root, const SafeRange& safe) {
    namespace packets = Eigen::internal;
    using Packet = packets::packet_traits<double>::type;
    constexpr size_t lanes = size_t(packets::packet_traits<double>::size);
    const double *const lower = safe.lower.data(), *const upper = safe.upper.data();
    const double *const breakLower = safe.breakLower.data(), *const breakUpper = safe.breakUpper.data();
    RowProof out;
    Packet room = packets::pset1<Packet>(INFINITY), beyond = packets::pset1<Packet>(0.0);
    const size_t packetsEnd = rows / lanes * lanes;
    for (size_t k = 0; k < packetsEnd; k += lanes) {
        const Packet rk = packets::ploadu<Packet>(r + k), xk = packets::ploadu<Packet>(x + k);
        double terms[lanes];
        packets::pstoreu(terms, packets::pdiv(packets::pmul(rk, rk), packets::ploadu<Packet>(d + k)));
        for (size_t lane = 0; lane < lanes; ++lane) out.scaled += terms[lane];
        const Packet slack = packets::pmin(packets::psub(xk, packets::ploadu<Packet>(lower + k)),
                                           packets::psub(packets::ploadu<Packet>(upper + k), xk));
        room = packets::pmin(room, packets::pmul(slack, packets::ploadu<Packet>(root + k)));
        if constexpr (Decide)
            beyond = packets::por(beyond, packets::por(packets::pcmp_lt(xk, packets::ploadu<Packet>(breakLower + k)),
                                                       packets::pcmp_lt(packets::ploadu<Packet>(breakUpper + k), xk)));
    }
    double rooms[lanes], beyondLanes[lanes];
    packets::pstoreu(rooms, room);
    packets::pstoreu(beyondLanes, beyond);
    for (size_t lane = 0; lane < lanes; ++lane) {
        out.room = std::min(out.room, rooms[lane]);
        out.beyond = out.beyond || std::bit_cast<std::uint64_t>(beyondLanes[lane]) != 0; // a true lane is all ones
    }
    for (size_t k = packetsEnd; k < rows; ++k) {
        out.scaled += r[k] * r[k] / d[k];
        out.room = std::min(out.room, std::min(x[k] - lower[k], upper[k] - x[k]) * root[k]);
        if constexpr (Decide) out.beyond = out.beyond || x[k] < breakLower[k] || x[k] > breakUpper[k];
    }
    return out;
}

} // namespace

OutsideProof outsideProof(size_t rows, const char* skip, const double* r, const double* x, const double* d,
                          const double* root, const double* breakLower, const double* breakUpper) {
    namespace packets = Eigen::internal;
    using Packet = packets::packet_traits<double>::type;
    constexpr size_t lanes = size_t(packets::packet_traits<double>::size);
    OutsideProof out;
    Packet room = packets::pset1<Packet>(INFINITY), beyond = packets::pset1<Packet>(0.0);
    const size_t packetsEnd = rows / lanes * lanes;
    for (size_t k = 0; k < packetsEnd; k += lanes) {
        // All ones (a NaN) in the lanes of skipped rows.
        std::int64_t skipBits[lanes];
        for (size_t lane = 0; lane < lanes; ++lane) skipBits[lane] = -std::int64_t(skip[k + lane] != 0);
        double skipLanes[lanes];
        std::memcpy(skipLanes, skipBits, sizeof skipLanes);
        const Packet skipped = packets::ploadu<Packet>(skipLanes);
        const Packet rk = packets::ploadu<Packet>(r + k), xk = packets::ploadu<Packet>(x + k);
        const Packet lower = packets::ploadu<Packet>(breakLower + k), upper = packets::ploadu<Packet>(breakUpper + k);
        const Packet square = packets::pmul(rk, rk);
        double squares[lanes], terms[lanes];
        packets::pstoreu(squares, packets::pandnot(square, skipped));
        packets::pstoreu(terms, packets::pandnot(packets::pdiv(square, packets::ploadu<Packet>(d + k)), skipped));
        for (size_t lane = 0; lane < lanes; ++lane) {
            out.scaled += terms[lane];
            out.squared += squares[lane];
        }
        const Packet distance = packets::pmin(packets::pabs(packets::psub(xk, lower)), packets::pabs(packets::psub(upper, xk)));
        room = packets::pmin(room, packets::por(packets::pmul(distance, packets::ploadu<Packet>(root + k)), skipped));
        beyond = packets::por(beyond, packets::pandnot(packets::por(packets::pcmp_lt(xk, lower), packets::pcmp_lt(upper, xk)),
                                                       skipped));
    }
    double rooms[lanes], beyondLanes[lanes];
    packets::pstoreu(rooms, room);
    packets::pstoreu(beyondLanes, beyond);
    for (size_t lane = 0; lane < lanes; ++lane) {
        out.room = std::min(out.room, rooms[lane]);
        out.beyond = out.beyond || std::bit_cast<std::uint64_t>(beyondLanes[lane]) != 0;
    }
    for (size_t k = packetsEnd; k < rows; ++k) {
        if (skip[k]) continue;
        out.scaled += r[k] * r[k] / d[k];
        out.squared += r[k] * r[k];
        out.room = std::min(out.room, std::min(std::abs(x[k] - breakLower[k]), std::abs(breakUpper[k] - x[k])) * root[k]);
        out.beyond = out.beyond || x[k] < breakLower[k] || x[k] > breakUpper[k];
    }
    return out;
}

RowProof rowProof(size_t rows, const double* r, const double* x, const double* d, const double* root,
                  const SafeRange& safe) {
    return safe.breakLower.empty() ? sums<false>(rows, r, x, d, root, safe) : sums<true>(rows, r, x, d, root, safe);
}

} // namespace shatter::lattice
