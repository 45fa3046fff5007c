#include <shatter/plugin/lattice/ConjugateGradientStep.h>

namespace shatter::lattice {

namespace {

namespace packets = Eigen::internal;
// Eigen's packet for dynamic vectors of doubles (2 lanes with SSE2), the one its sums use.
using Packet = packets::packet_traits<double>::type;
constexpr Eigen::Index kLanes = packets::packet_traits<double>::size;
// With one lane (vectorization off) Eigen sums element after element, an order this pass
// does not follow.
static_assert(kLanes >= 2, "conjugateGradientStep follows Eigen's vectorized sums");

// −0 is the identity of floating-point addition (−0 + v is v for every v, ±0 included), so an
// accumulator started at −0 holds, after its first add, exactly what Eigen's started at the
// first packet holds.
Packet startedSum() { return packets::pset1<Packet>(-0.0); }

} // namespace

StepSums conjugateGradientStep(double alpha, const Eigen::VectorXd& p, const Eigen::VectorXd& ap,
                               const Eigen::VectorXd& inverseDiagonal, Eigen::VectorXd& x, Eigen::VectorXd& r,
                               Eigen::VectorXd& z) {
    const Eigen::Index n = r.size();
    z.resize(n);
    if (n == 0) return {}; // Eigen's sum of nothing is +0
    const double* const pIn = p.data();
    const double* const apIn = ap.data();
    const double* const dIn = inverseDiagonal.data();
    double* const xOut = x.data();
    double* const rOut = r.data();
    double* const zOut = z.data();
    const Packet a = packets::pset1<Packet>(alpha);
    // Updates the packet at i and adds its r² and r z to the accumulators.
    auto step = [&](Eigen::Index i, Packet& squares, Packet& products) {
        packets::pstoreu(xOut + i, packets::padd(packets::ploadu<Packet>(xOut + i), packets::pmul(a, packets::ploadu<Packet>(pIn + i))));
        const Packet ri = packets::psub(packets::ploadu<Packet>(rOut + i), packets::pmul(a, packets::ploadu<Packet>(apIn + i)));
        packets::pstoreu(rOut + i, ri);
        const Packet zi = packets::pmul(packets::ploadu<Packet>(dIn + i), ri);
        packets::pstoreu(zOut + i, zi);
        squares = packets::padd(squares, packets::pmul(ri, ri));
        products = packets::padd(products, packets::pmul(ri, zi));
    };
    // Eigen's redux (LinearVectorizedTraversal): packets 0 and 1 of each pair of packets in two
    // accumulators, those added, then the packet left over, then its lanes, then the elements.
    const Eigen::Index pairsEnd = n / (2 * kLanes) * (2 * kLanes), packetsEnd = n / kLanes * kLanes;
    Packet squares0 = startedSum(), squares1 = startedSum(), products0 = startedSum(), products1 = startedSum();
    for (Eigen::Index i = 0; i < pairsEnd; i += 2 * kLanes) {
        step(i, squares0, products0);
        step(i + kLanes, squares1, products1);
    }
    squares0 = packets::padd(squares0, squares1);
    products0 = packets::padd(products0, products1);
    if (packetsEnd > pairsEnd) step(pairsEnd, squares0, products0);
    StepSums sums{packets::predux(squares0), packets::predux(products0)};
    for (Eigen::Index i = packetsEnd; i < n; ++i) {
        xOut[i] += alpha * pIn[i];
        rOut[i] -= alpha * apIn[i];
        zOut[i] = dIn[i] * rOut[i];
        sums.residual += rOut[i] * rOut[i];
        sums.preconditioned += rOut[i] * zOut[i];
    }
    return sums;
}

} // namespace shatter::lattice
