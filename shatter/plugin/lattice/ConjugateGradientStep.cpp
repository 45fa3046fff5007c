#include <shatter/plugin/lattice/ConjugateGradientStep.h>

#include <array>
#include <cmath>

namespace shatter::lattice {

namespace {

namespace packets = Eigen::internal;
// Eigen's packet for dynamic vectors of doubles (2 lanes with SSE2), the one its sums use.
using Packet = packets::packet_traits<double>::type;
constexpr Eigen::Index kLanes = packets::packet_traits<double>::size;
// With one lane (vectorization off) Eigen sums element after element, an order these passes
// do not follow.
static_assert(kLanes >= 2, "conjugateGradientStep follows Eigen's vectorized sums");

// −0 is the identity of floating-point addition (−0 + v is v for every v, ±0 included), so an
// accumulator started at −0 holds, after its first add, exactly what Eigen's started at the
// first packet holds.
Packet startedSum() { return packets::pset1<Packet>(-0.0); }

// One accumulator per sum (a plain array: as a template argument, the packet type's vector
// attributes would be dropped, which GCC warns of).
template <size_t Sums>
struct Accumulators {
    Packet sum[Sums];
};

// `Sums` sums over n elements added in the order Eigen's redux (LinearVectorizedTraversal) adds
// a dynamic vector: packets 0 and 1 of each pair of packets in two accumulators, those added,
// then the packet left over, then its lanes, then the elements after the last whole packet.
// `packetStep(i, accumulators)` handles the packet at i and adds its terms to each
// accumulator; `elementStep(i, sums)` handles element i and adds its terms to each sum.
template <size_t Sums, class PacketStep, class ElementStep>
std::array<double, Sums> sumInEigensOrder(Eigen::Index n, PacketStep packetStep, ElementStep elementStep) {
    std::array<double, Sums> sums{};
    if (n == 0) return sums; // Eigen's sum of nothing is +0
    const Eigen::Index pairsEnd = n / (2 * kLanes) * (2 * kLanes), packetsEnd = n / kLanes * kLanes;
    Accumulators<Sums> even, odd;
    for (size_t s = 0; s < Sums; ++s) even.sum[s] = odd.sum[s] = startedSum();
    for (Eigen::Index i = 0; i < pairsEnd; i += 2 * kLanes) {
        packetStep(i, even);
        packetStep(i + kLanes, odd);
    }
    for (size_t s = 0; s < Sums; ++s) even.sum[s] = packets::padd(even.sum[s], odd.sum[s]);
    if (packetsEnd > pairsEnd) packetStep(pairsEnd, even);
    for (size_t s = 0; s < Sums; ++s) sums[s] = packets::predux(even.sum[s]);
    for (Eigen::Index i = packetsEnd; i < n; ++i) elementStep(i, sums);
    return sums;
}

// The product's first passes: every particle's sum from zero, + n_k x_k at a first end and −
// at a second in row order, × 1/m per coordinate. With `Update`, x_k is first formed as
// z_k + β x_k and stored in `updated` (the direction update, element for element as Eigen
// forms it; `updated` may be x).
template <bool Update>
void scatter(const BlockRows& block, const double* z, double beta, const double* x, double* updated) {
    const int* const endA = block.a;
    const int* const endB = block.b;
    const Eigen::Vector3d* const n = block.normal;
    for (Eigen::Index i = 0; i < block.particles; ++i) block.sums[i].setZero(); // (a loop of stores, not a memset call)
    // The sums' coordinates, read as one array of doubles (Vector3d is 3 doubles, no padding; a
    // vector of doubles instead would be cleared by memset, which callgrind counts byte-wise).
    static_assert(sizeof(Eigen::Vector3d) == 3 * sizeof(double));
    double* const s = reinterpret_cast<double*>(block.sums);
    using Coordinates = Eigen::Map<Eigen::Vector3d>;
    // (The row count in a local: Eigen's packet stores may alias anything, so the compiler
    // loaded it from `block` again after every row.)
    for (Eigen::Index k = 0, rows = block.rows; k < rows; ++k) {
        double xk = x[k];
        if constexpr (Update) updated[k] = xk = z[k] + beta * xk;
        const Eigen::Vector3d f = n[k] * xk;
        Coordinates(s + endA[k]) += f;
        Coordinates(s + endB[k]) -= f;
    }
    const double* const w = block.inverseMass;
    for (Eigen::Index i = 0, coordinates = 3 * block.particles; i < coordinates; ++i) s[i] *= w[i];
}

// n_k·(s_a − s_b) of row k, after the scatter.
struct RowValue {
    const int* endA;
    const int* endB;
    const Eigen::Vector3d* n;
    const double* s;
    explicit RowValue(const BlockRows& block)
        : endA(block.a), endB(block.b), n(block.normal), s(reinterpret_cast<const double*>(block.sums)) {}
    double operator()(Eigen::Index k) const {
        using Acceleration = Eigen::Map<const Eigen::Vector3d>;
        return n[k].dot(Acceleration(s + endA[k]) - Acceleration(s + endB[k]));
    }
};

template <bool Update>
double multiplyAndDot(const BlockRows& block, const double* z, double beta, double* p, double* ap) {
    scatter<Update>(block, z, beta, p, p);
    const RowValue row(block);
    // Each packet's rows formed, then their p·Ap terms added (the values just stored).
    auto packetStep = [&](Eigen::Index i, Accumulators<1>& sum) {
        for (Eigen::Index j = i; j < i + kLanes; ++j) ap[j] = row(j);
        sum.sum[0] = packets::padd(sum.sum[0], packets::pmul(packets::ploadu<Packet>(p + i), packets::ploadu<Packet>(ap + i)));
    };
    auto elementStep = [&](Eigen::Index i, std::array<double, 1>& sum) {
        ap[i] = row(i);
        sum[0] += p[i] * ap[i];
    };
    return sumInEigensOrder<1>(block.rows, packetStep, elementStep)[0];
}

} // namespace

void multiplyBlock(const BlockRows& block, const double* x, double* y) {
    scatter<false>(block, nullptr, 0.0, x, nullptr);
    const RowValue row(block);
    for (Eigen::Index k = 0; k < block.rows; ++k) y[k] = row(k);
}

double multiplyDirection(const BlockRows& block, const double* z, double beta, double* p, double* ap) {
    return z ? multiplyAndDot<true>(block, z, beta, p, ap) : multiplyAndDot<false>(block, nullptr, 0.0, p, ap);
}

StepSums conjugateGradientStep(double alpha, const Eigen::VectorXd& p, const Eigen::VectorXd& ap,
                               const Eigen::VectorXd& inverseDiagonal, Eigen::VectorXd& x, Eigen::VectorXd& r,
                               Eigen::VectorXd& z) {
    const Eigen::Index n = r.size();
    z.resize(n);
    const double* const pIn = p.data();
    const double* const apIn = ap.data();
    const double* const dIn = inverseDiagonal.data();
    double* const xOut = x.data();
    double* const rOut = r.data();
    double* const zOut = z.data();
    const Packet a = packets::pset1<Packet>(alpha);
    // Updates the packet at i and adds its r² and r z to the accumulators.
    auto packetStep = [&](Eigen::Index i, Accumulators<2>& sums) {
        packets::pstoreu(xOut + i, packets::padd(packets::ploadu<Packet>(xOut + i), packets::pmul(a, packets::ploadu<Packet>(pIn + i))));
        const Packet ri = packets::psub(packets::ploadu<Packet>(rOut + i), packets::pmul(a, packets::ploadu<Packet>(apIn + i)));
        packets::pstoreu(rOut + i, ri);
        const Packet zi = packets::pmul(packets::ploadu<Packet>(dIn + i), ri);
        packets::pstoreu(zOut + i, zi);
        sums.sum[0] = packets::padd(sums.sum[0], packets::pmul(ri, ri));
        sums.sum[1] = packets::padd(sums.sum[1], packets::pmul(ri, zi));
    };
    auto elementStep = [&](Eigen::Index i, std::array<double, 2>& sums) {
        xOut[i] += alpha * pIn[i];
        rOut[i] -= alpha * apIn[i];
        zOut[i] = dIn[i] * rOut[i];
        sums[0] += rOut[i] * rOut[i];
        sums[1] += rOut[i] * zOut[i];
    };
    const std::array<double, 2> sums = sumInEigensOrder<2>(n, packetStep, elementStep);
    return {sums[0], sums[1]};
}

double residualAndNorm(const Eigen::VectorXd& b, const Eigen::VectorXd& ax, Eigen::VectorXd& r) {
    const Eigen::Index n = b.size();
    r.resize(n);
    const double* const bIn = b.data();
    const double* const axIn = ax.data();
    double* const rOut = r.data();
    auto packetStep = [&](Eigen::Index i, Accumulators<1>& sum) {
        const Packet ri = packets::psub(packets::ploadu<Packet>(bIn + i), packets::ploadu<Packet>(axIn + i));
        packets::pstoreu(rOut + i, ri);
        sum.sum[0] = packets::padd(sum.sum[0], packets::pmul(ri, ri));
    };
    auto elementStep = [&](Eigen::Index i, std::array<double, 1>& sum) {
        rOut[i] = bIn[i] - axIn[i];
        sum[0] += rOut[i] * rOut[i];
    };
    return std::sqrt(sumInEigensOrder<1>(n, packetStep, elementStep)[0]);
}

} // namespace shatter::lattice
