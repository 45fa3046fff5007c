#include <shatter/plugin/lattice/ConjugateGradientStep.h>

#include <shatter/plugin/common/CpuFeatures.h>

#include <algorithm>
#include <array>
#include <cmath>

// Not where AVX is on at compile time (-march=native, x86-64-v3): Eigen's packets are then 4
// lanes wide, and the portable path, on Eigen's own packets, is the vector code there.
#if (defined(__x86_64__) || defined(__i386__)) && defined(__GNUC__) && !defined(__clang__) && !defined(__AVX__)
#include <immintrin.h>
#define SHATTER_LATTICE_AVX2 1
#else
#define SHATTER_LATTICE_AVX2 0
#endif

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
// at a second in row order, × 1/m. With `Update`, x_k is first formed as z_k + β x_k and
// stored in `updated` (the direction update, element for element as Eigen forms it; `updated`
// may be x).
template <bool Update>
void scatter(const BlockRows& block, const double* z, double beta, const double* x, double* updated) {
    double* const s = block.sums;
    double* const* const ends = block.ends;
    const double* const n = block.normal;
    using Coordinates = Eigen::Map<Eigen::Vector3d>;
    // (a loop of stores, not a memset call, which callgrind counts byte-wise; the pad lanes are
    // never read)
    for (Eigen::Index i = 0, particles = block.particles; i < particles; ++i) Coordinates(s + kBlockStride * i).setZero();
    // (The row count in a local: Eigen's packet stores may alias anything, so the compiler
    // loaded it from `block` again after every row.)
    for (Eigen::Index k = 0, rows = block.rows; k < rows; ++k) {
        double xk = x[k];
        if constexpr (Update) updated[k] = xk = z[k] + beta * xk;
        const Eigen::Vector3d f = Eigen::Map<const Eigen::Vector3d>(n + 3 * k) * xk;
        Coordinates(ends[2 * k]) += f;
        Coordinates(ends[2 * k + 1]) -= f;
    }
    const double* const w = block.inverseMass;
    for (Eigen::Index i = 0, particles = block.particles; i < particles; ++i) Coordinates(s + kBlockStride * i) *= w[i];
}

// n_k·(s_a − s_b) of row k, after the scatter.
struct RowValue {
    double* const* ends;
    const double* n;
    explicit RowValue(const BlockRows& block) : ends(block.ends), n(block.normal) {}
    double operator()(Eigen::Index k) const {
        using Vector = Eigen::Map<const Eigen::Vector3d>;
        return Vector(n + 3 * k).dot(Vector(ends[2 * k]) - Vector(ends[2 * k + 1]));
    }
};

// multiplyAndDot's packet and element: the rows' values formed and stored in ap, then their p·Ap
// terms added (the values just stored). One definition for both paths (the AVX2 one runs it on
// the rows after its quads): their equal bits rest on it.
struct ProductTerms {
    const RowValue& row;
    const double* p;
    double* ap;
    void operator()(Eigen::Index i, Accumulators<1>& sum) const {
        for (Eigen::Index j = i; j < i + kLanes; ++j) ap[j] = row(j);
        sum.sum[0] = packets::padd(sum.sum[0], packets::pmul(packets::ploadu<Packet>(p + i), packets::ploadu<Packet>(ap + i)));
    }
    void operator()(Eigen::Index i, std::array<double, 1>& sum) const {
        ap[i] = row(i);
        sum[0] += p[i] * ap[i];
    }
};

// The step's packet and element: x += α p, r −= α Ap, z = D r, and the r·r and r·z terms added.
// Shared by both paths, as ProductTerms.
struct StepTerms {
    double alpha;
    Packet a; // alpha in every lane
    const double *pIn, *apIn, *dIn;
    double *xOut, *rOut, *zOut;
    void operator()(Eigen::Index i, Accumulators<2>& sums) const {
        packets::pstoreu(xOut + i, packets::padd(packets::ploadu<Packet>(xOut + i), packets::pmul(a, packets::ploadu<Packet>(pIn + i))));
        const Packet ri = packets::psub(packets::ploadu<Packet>(rOut + i), packets::pmul(a, packets::ploadu<Packet>(apIn + i)));
        packets::pstoreu(rOut + i, ri);
        const Packet zi = packets::pmul(packets::ploadu<Packet>(dIn + i), ri);
        packets::pstoreu(zOut + i, zi);
        sums.sum[0] = packets::padd(sums.sum[0], packets::pmul(ri, ri));
        sums.sum[1] = packets::padd(sums.sum[1], packets::pmul(ri, zi));
    }
    void operator()(Eigen::Index i, std::array<double, 2>& sums) const {
        xOut[i] += alpha * pIn[i];
        rOut[i] -= alpha * apIn[i];
        zOut[i] = dIn[i] * rOut[i];
        sums[0] += rOut[i] * rOut[i];
        sums[1] += rOut[i] * zOut[i];
    }
};

template <bool Update>
double multiplyAndDot(const BlockRows& block, const double* z, double beta, double* p, double* ap) {
    scatter<Update>(block, z, beta, p, p);
    const RowValue row(block);
    const ProductTerms terms{row, p, ap};
    return sumInEigensOrder<1>(block.rows, terms, terms)[0];
}

StepSums stepPortable(double alpha, Eigen::Index n, const double* pIn, const double* apIn, const double* dIn,
                      double* xOut, double* rOut, double* zOut) {
    const StepTerms terms{alpha, packets::pset1<Packet>(alpha), pIn, apIn, dIn, xOut, rOut, zOut};
    const std::array<double, 2> sums = sumInEigensOrder<2>(n, terms, terms);
    return {sums[0], sums[1]};
}

// rowsLookDecided's rows from `first` on, one at a time.
bool rowsLookDecidedFrom(Eigen::Index first, Eigen::Index n, const double* x, const double* lower,
                         const double* upper, const double* rootInverseDiagonal, double reach, bool& beyond) {
    for (Eigen::Index j = first; j < n; ++j) {
        const double distance = std::min(std::abs(x[j] - lower[j]), std::abs(upper[j] - x[j]));
        if (!(distance / rootInverseDiagonal[j] > reach)) return false;
        beyond = beyond || x[j] < lower[j] || x[j] > upper[j];
    }
    return true;
}

} // namespace

#if SHATTER_LATTICE_AVX2
// The AVX2 path: the same operations as the portable one above, 4 doubles an instruction.
// (Defined in a `GCC target` region: lambdas inside a function marked [[gnu::target]] do not
// take its target, so their intrinsics would not compile.)
#pragma GCC push_options
#pragma GCC target("avx2")
namespace {

using Quad = __m256d;

// sumInEigensOrder with the pairs of packets taken 4 elements at a time: one 4-lane
// accumulator whose low 2 lanes are Eigen's first packet accumulator and high 2 lanes its
// second, which are added lane by lane after the pairs, as Eigen adds its two. Then as
// sumInEigensOrder: the packet left over (`packetStep`, 2 lanes), its lanes, the elements left.
template <size_t Sums, class QuadStep, class PacketStep, class ElementStep>
[[gnu::always_inline]] inline std::array<double, Sums> sumInEigensOrderAvx2(Eigen::Index n, QuadStep quadStep,
                                                                            PacketStep packetStep,
                                                                            ElementStep elementStep) {
    static_assert(kLanes == 2, "a quad is a pair of Eigen's packets");
    std::array<double, Sums> sums{};
    if (n == 0) return sums; // Eigen's sum of nothing is +0
    const Eigen::Index pairsEnd = n / 4 * 4, packetsEnd = n / 2 * 2;
    Quad quads[Sums];
    for (size_t s = 0; s < Sums; ++s) quads[s] = _mm256_set1_pd(-0.0); // startedSum()
    for (Eigen::Index i = 0; i < pairsEnd; i += 4) quadStep(i, quads);
    Accumulators<Sums> even;
    for (size_t s = 0; s < Sums; ++s)
        even.sum[s] = _mm_add_pd(_mm256_castpd256_pd128(quads[s]), _mm256_extractf128_pd(quads[s], 1));
    if (packetsEnd > pairsEnd) packetStep(pairsEnd, even);
    for (size_t s = 0; s < Sums; ++s) sums[s] = packets::predux(even.sum[s]);
    for (Eigen::Index i = packetsEnd; i < n; ++i) elementStep(i, sums);
    return sums;
}

// scatter<Update>, 4 doubles an instruction: a row's n_k x_k, and each particle's sum.
template <bool Update>
void scatterAvx2(const BlockRows& block, const double* z, double beta, const double* x, double* updated) {
    double* const s = block.sums;
    double* const* const ends = block.ends;
    const double* const n = block.normal;
    Quad zero = _mm256_setzero_pd();
    // (Unrolled, as the scale below: the loop's own add, compare and jump were half of it.)
#pragma GCC unroll 4
    for (Eigen::Index i = 0, particles = block.particles; i < particles; ++i) {
        // (An empty asm that "changes" the zero: GCC made this loop a memset call, whose `rep
        // stosb` callgrind counts byte by byte, 224 M "instructions" in wall frames 1-7.)
        asm("" : "+x"(zero));
        _mm256_storeu_pd(s + kBlockStride * i, zero);
    }
    auto row = [&](Eigen::Index k, Quad xk) {
        // (Lane 3 is the next row's n_x, or the pad after the last row: it goes into the sums' pad lanes.)
        const Quad f = _mm256_mul_pd(_mm256_loadu_pd(n + 3 * k), xk);
        double* const sa = ends[2 * k];
        _mm256_storeu_pd(sa, _mm256_add_pd(_mm256_loadu_pd(sa), f));
        double* const sb = ends[2 * k + 1];
        _mm256_storeu_pd(sb, _mm256_sub_pd(_mm256_loadu_pd(sb), f));
    };
    const Eigen::Index rows = block.rows, quadsEnd = rows / 4 * 4;
    const Quad b = _mm256_set1_pd(beta);
    for (Eigen::Index k = 0; k < quadsEnd; k += 4) {
        Quad xs = _mm256_loadu_pd(x + k);
        if constexpr (Update) {
            xs = _mm256_add_pd(_mm256_loadu_pd(z + k), _mm256_mul_pd(b, xs));
            _mm256_storeu_pd(updated + k, xs);
        }
        row(k, _mm256_permute4x64_pd(xs, 0x00));
        row(k + 1, _mm256_permute4x64_pd(xs, 0x55));
        row(k + 2, _mm256_permute4x64_pd(xs, 0xAA));
        row(k + 3, _mm256_permute4x64_pd(xs, 0xFF));
    }
    for (Eigen::Index k = quadsEnd; k < rows; ++k) {
        double xk = x[k];
        if constexpr (Update) updated[k] = xk = z[k] + beta * xk;
        row(k, _mm256_set1_pd(xk));
    }
    const double* const w = block.inverseMass;
#pragma GCC unroll 4
    for (Eigen::Index i = 0, particles = block.particles; i < particles; ++i) {
        double* const si = s + kBlockStride * i;
        _mm256_storeu_pd(si, _mm256_mul_pd(_mm256_loadu_pd(si), _mm256_broadcast_sd(w + i)));
    }
}

// The gather's values of rows k..k+3: per row v = (s_a − s_b) ∘ n, then (v_x + v_y) + v_z as
// Eigen's dot of 3-vectors adds them (the pad lane is never added).
struct RowQuad {
    double* const* ends;
    const double* n;
    explicit RowQuad(const BlockRows& block) : ends(block.ends), n(block.normal) {}
    Quad product(Eigen::Index k) const {
        const Quad d = _mm256_sub_pd(_mm256_loadu_pd(ends[2 * k]), _mm256_loadu_pd(ends[2 * k + 1]));
        return _mm256_mul_pd(d, _mm256_loadu_pd(n + 3 * k)); // (lane 3 is never added)
    }
    Quad operator()(Eigen::Index k) const {
        const Quad v0 = product(k), v1 = product(k + 1), v2 = product(k + 2), v3 = product(k + 3);
        // [x0 + y0, x1 + y1, z0 + pad0, z1 + pad1] and [x0, x1, z0, z1], and the same of rows 2, 3
        const Quad h01 = _mm256_hadd_pd(v0, v1), h23 = _mm256_hadd_pd(v2, v3);
        const Quad u01 = _mm256_unpacklo_pd(v0, v1), u23 = _mm256_unpacklo_pd(v2, v3);
        // [x + y of rows 0-3] + [z of rows 0-3]
        return _mm256_add_pd(_mm256_permute2f128_pd(h01, h23, 0x20), _mm256_permute2f128_pd(u01, u23, 0x31));
    }
};

template <bool Update>
double multiplyAndDotAvx2(const BlockRows& block, const double* z, double beta, double* p, double* ap) {
    scatterAvx2<Update>(block, z, beta, p, p);
    const RowQuad quad(block);
    const RowValue row(block);
    auto quadStep = [&](Eigen::Index i, Quad* sum) {
        const Quad values = quad(i);
        _mm256_storeu_pd(ap + i, values);
        sum[0] = _mm256_add_pd(sum[0], _mm256_mul_pd(_mm256_loadu_pd(p + i), values));
    };
    const ProductTerms terms{row, p, ap};
    return sumInEigensOrderAvx2<1>(block.rows, quadStep, terms, terms)[0];
}

void multiplyBlockAvx2(const BlockRows& block, const double* x, double* y) {
    scatterAvx2<false>(block, nullptr, 0.0, x, nullptr);
    const RowQuad quad(block);
    const RowValue row(block);
    const Eigen::Index quadsEnd = block.rows / 4 * 4;
    for (Eigen::Index k = 0; k < quadsEnd; k += 4) _mm256_storeu_pd(y + k, quad(k));
    for (Eigen::Index k = quadsEnd; k < block.rows; ++k) y[k] = row(k);
}

StepSums stepAvx2(double alpha, Eigen::Index n, const double* pIn, const double* apIn, const double* dIn,
                  double* xOut, double* rOut, double* zOut) {
    const Quad a4 = _mm256_set1_pd(alpha);
    auto quadStep = [&](Eigen::Index i, Quad* sums) {
        _mm256_storeu_pd(xOut + i, _mm256_add_pd(_mm256_loadu_pd(xOut + i), _mm256_mul_pd(a4, _mm256_loadu_pd(pIn + i))));
        const Quad ri = _mm256_sub_pd(_mm256_loadu_pd(rOut + i), _mm256_mul_pd(a4, _mm256_loadu_pd(apIn + i)));
        _mm256_storeu_pd(rOut + i, ri);
        const Quad zi = _mm256_mul_pd(_mm256_loadu_pd(dIn + i), ri);
        _mm256_storeu_pd(zOut + i, zi);
        sums[0] = _mm256_add_pd(sums[0], _mm256_mul_pd(ri, ri));
        sums[1] = _mm256_add_pd(sums[1], _mm256_mul_pd(ri, zi));
    };
    const StepTerms terms{alpha, packets::pset1<Packet>(alpha), pIn, apIn, dIn, xOut, rOut, zOut};
    const std::array<double, 2> sums = sumInEigensOrderAvx2<2>(n, quadStep, terms, terms);
    return {sums[0], sums[1]};
}

// multiplyIndexedRows on AVX2: scatterAvx2 and multiplyBlockAvx2 with the ends formed from the
// particle numbers, and the normals' 4th lane loaded only where a row follows (the system's
// normals have no pad after the last row, so the rows after the last whole quad but one load 3
// lanes, masked).
void multiplyIndexedAvx2(const IndexedRows& m, const double* x, double* y, double* acceleration) {
    double* const s = m.sums;
    const int* const a = m.a;
    const int* const b = m.b;
    const double* const n = m.normal;
    const Eigen::Index rows = m.rows, particles = m.particles;
    const __m256i three = _mm256_set_epi64x(0, -1, -1, -1); // lanes x, y, z
    Quad zero = _mm256_setzero_pd();
#pragma GCC unroll 4
    for (Eigen::Index i = 0; i < particles; ++i) {
        asm("" : "+x"(zero)); // (not a memset call: see scatterAvx2)
        _mm256_storeu_pd(s + kBlockStride * i, zero);
    }
    auto row = [&](Eigen::Index k, Quad xk, Quad normal) {
        const Quad f = _mm256_mul_pd(normal, xk); // (lane 3 goes into the pad lanes)
        double* const sa = s + kBlockStride * a[k];
        _mm256_storeu_pd(sa, _mm256_add_pd(_mm256_loadu_pd(sa), f));
        double* const sb = s + kBlockStride * b[k];
        _mm256_storeu_pd(sb, _mm256_sub_pd(_mm256_loadu_pd(sb), f));
    };
    // Whole quads whose last row is not the system's last: their 4-lane normal loads stay inside.
    const Eigen::Index quadsEnd = rows > 0 ? (rows - 1) / 4 * 4 : 0;
    for (Eigen::Index k = 0; k < quadsEnd; k += 4) {
        const Quad xs = _mm256_loadu_pd(x + k);
        row(k, _mm256_permute4x64_pd(xs, 0x00), _mm256_loadu_pd(n + 3 * k));
        row(k + 1, _mm256_permute4x64_pd(xs, 0x55), _mm256_loadu_pd(n + 3 * k + 3));
        row(k + 2, _mm256_permute4x64_pd(xs, 0xAA), _mm256_loadu_pd(n + 3 * k + 6));
        row(k + 3, _mm256_permute4x64_pd(xs, 0xFF), _mm256_loadu_pd(n + 3 * k + 9));
    }
    for (Eigen::Index k = quadsEnd; k < rows; ++k) row(k, _mm256_set1_pd(x[k]), _mm256_maskload_pd(n + 3 * k, three));
    const double* const w = m.inverseMass;
#pragma GCC unroll 4
    for (Eigen::Index i = 0; i < particles; ++i) {
        double* const si = s + kBlockStride * i;
        const Quad scaled = _mm256_mul_pd(_mm256_loadu_pd(si), _mm256_broadcast_sd(w + i));
        _mm256_storeu_pd(si, scaled);
        _mm256_maskstore_pd(acceleration + 3 * i, three, scaled);
    }
    // The gather as RowQuad: v = (s_a − s_b) ∘ n per row, then (v_x + v_y) + v_z.
    auto product = [&](Eigen::Index k) {
        const Quad d = _mm256_sub_pd(_mm256_loadu_pd(s + kBlockStride * a[k]), _mm256_loadu_pd(s + kBlockStride * b[k]));
        return _mm256_mul_pd(d, _mm256_loadu_pd(n + 3 * k)); // (lane 3 is never added)
    };
    for (Eigen::Index k = 0; k < quadsEnd; k += 4) {
        const Quad v0 = product(k), v1 = product(k + 1), v2 = product(k + 2), v3 = product(k + 3);
        const Quad h01 = _mm256_hadd_pd(v0, v1), h23 = _mm256_hadd_pd(v2, v3);
        const Quad u01 = _mm256_unpacklo_pd(v0, v1), u23 = _mm256_unpacklo_pd(v2, v3);
        _mm256_storeu_pd(y + k, _mm256_add_pd(_mm256_permute2f128_pd(h01, h23, 0x20), _mm256_permute2f128_pd(u01, u23, 0x31)));
    }
    using Vector = Eigen::Map<const Eigen::Vector3d>;
    for (Eigen::Index k = quadsEnd; k < rows; ++k)
        y[k] = Vector(n + 3 * k).dot(Vector(s + kBlockStride * a[k]) - Vector(s + kBlockStride * b[k]));
}

// rowsLookDecided, 4 rows an instruction: std::min(a, b) is (b < a ? b : a), which is
// vminpd(b, a) (it returns its second operand unless the first is less, NaN included); |v| is v
// with the sign bit cleared, as std::abs; > is the ordered compare (false for NaN).
bool rowsLookDecidedAvx2(Eigen::Index n, const double* x, const double* lower, const double* upper,
                         const double* rootInverseDiagonal, double reach, bool& beyond) {
    const Quad sign = _mm256_set1_pd(-0.0), reaches = _mm256_set1_pd(reach);
    Quad outside = _mm256_setzero_pd();
    const Eigen::Index quadsEnd = n / 4 * 4;
    for (Eigen::Index j = 0; j < quadsEnd; j += 4) {
        const Quad xs = _mm256_loadu_pd(x + j), lows = _mm256_loadu_pd(lower + j), ups = _mm256_loadu_pd(upper + j);
        const Quad below = _mm256_andnot_pd(sign, _mm256_sub_pd(xs, lows));
        const Quad above = _mm256_andnot_pd(sign, _mm256_sub_pd(ups, xs));
        const Quad scaled = _mm256_div_pd(_mm256_min_pd(above, below), _mm256_loadu_pd(rootInverseDiagonal + j));
        if (_mm256_movemask_pd(_mm256_cmp_pd(scaled, reaches, _CMP_GT_OQ)) != 0xF) return false;
        outside = _mm256_or_pd(outside, _mm256_or_pd(_mm256_cmp_pd(xs, lows, _CMP_LT_OQ), _mm256_cmp_pd(xs, ups, _CMP_GT_OQ)));
    }
    beyond = beyond || _mm256_movemask_pd(outside) != 0;
    return rowsLookDecidedFrom(quadsEnd, n, x, lower, upper, rootInverseDiagonal, reach, beyond);
}

} // namespace
#pragma GCC pop_options
#endif

KernelPath fastestKernelPath() {
    static const KernelPath path = kernelPathAvailable(KernelPath::Avx2) && !portablePathForced("SHATTER_LATTICE_KERNEL")
                                       ? KernelPath::Avx2
                                       : KernelPath::Portable;
    return path;
}

bool kernelPathAvailable(KernelPath path) {
    if (path == KernelPath::Portable) return true;
#if SHATTER_LATTICE_AVX2
    return path == KernelPath::Avx2 && processorRunsAvx2();
#else
    return false;
#endif
}

void multiplyBlock(const BlockRows& block, const double* x, double* y, KernelPath path) {
#if SHATTER_LATTICE_AVX2
    if (path == KernelPath::Avx2) return multiplyBlockAvx2(block, x, y);
#endif
    (void)path;
    scatter<false>(block, nullptr, 0.0, x, nullptr);
    const RowValue row(block);
    for (Eigen::Index k = 0; k < block.rows; ++k) y[k] = row(k);
}

void multiplyIndexedRows(const IndexedRows& m, const double* x, double* y, double* acceleration, KernelPath path) {
#if SHATTER_LATTICE_AVX2
    if (path == KernelPath::Avx2) return multiplyIndexedAvx2(m, x, y, acceleration);
#endif
    (void)path;
    // Raw pointers held in locals: through the vectors, every store into the sums made the
    // compiler load each vector's data pointer again (6 loads of 32 instructions per row).
    using Coordinates = Eigen::Map<Eigen::Vector3d>;
    const int* const ends[2] = {m.a, m.b};
    const double* const n = m.normal;
    double* const s = acceleration;
    for (Eigen::Index i = 0; i < m.particles; ++i) Coordinates(s + 3 * i).setZero();
    for (Eigen::Index k = 0; k < m.rows; ++k) {
        const Eigen::Vector3d f = Eigen::Map<const Eigen::Vector3d>(n + 3 * k) * x[k];
        Coordinates(s + 3 * ends[0][k]) += f;
        Coordinates(s + 3 * ends[1][k]) -= f;
    }
    const double* const w = m.inverseMass;
    for (Eigen::Index i = 0; i < m.particles; ++i) Coordinates(s + 3 * i) *= w[i];
    using Vector = Eigen::Map<const Eigen::Vector3d>;
    for (Eigen::Index k = 0; k < m.rows; ++k)
        y[k] = Vector(n + 3 * k).dot(Vector(s + 3 * ends[0][k]) - Vector(s + 3 * ends[1][k]));
}

bool rowsLookDecided(Eigen::Index n, const double* x, const double* lower, const double* upper,
                     const double* rootInverseDiagonal, double reach, bool& beyond, KernelPath path) {
#if SHATTER_LATTICE_AVX2
    if (path == KernelPath::Avx2) return rowsLookDecidedAvx2(n, x, lower, upper, rootInverseDiagonal, reach, beyond);
#endif
    (void)path;
    return rowsLookDecidedFrom(0, n, x, lower, upper, rootInverseDiagonal, reach, beyond);
}

double multiplyDirection(const BlockRows& block, const double* z, double beta, double* p, double* ap, KernelPath path) {
#if SHATTER_LATTICE_AVX2
    if (path == KernelPath::Avx2)
        return z ? multiplyAndDotAvx2<true>(block, z, beta, p, ap) : multiplyAndDotAvx2<false>(block, nullptr, 0.0, p, ap);
#endif
    (void)path;
    return z ? multiplyAndDot<true>(block, z, beta, p, ap) : multiplyAndDot<false>(block, nullptr, 0.0, p, ap);
}

StepSums conjugateGradientStep(double alpha, const Eigen::VectorXd& p, const Eigen::VectorXd& ap,
                               const Eigen::VectorXd& inverseDiagonal, Eigen::VectorXd& x, Eigen::VectorXd& r,
                               Eigen::VectorXd& z, KernelPath path) {
    const Eigen::Index n = r.size();
    z.resize(n);
#if SHATTER_LATTICE_AVX2
    if (path == KernelPath::Avx2) return stepAvx2(alpha, n, p.data(), ap.data(), inverseDiagonal.data(), x.data(), r.data(), z.data());
#endif
    (void)path;
    return stepPortable(alpha, n, p.data(), ap.data(), inverseDiagonal.data(), x.data(), r.data(), z.data());
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
