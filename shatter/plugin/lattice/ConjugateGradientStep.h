#pragma once
// The passes of one conjugate-gradient iteration over a block of constraint rows, fused: the
// direction's update with its product and p·Ap, and the vector updates after the step length.
// Each gives exactly the bits of the plain Eigen expressions it replaces.
#include <Eigen/Core>

namespace shatter::lattice {

// ‖r‖² and rᵀz after the step.
struct StepSums {
    double residual = 0.0;       // rᵀr
    double preconditioned = 0.0; // rᵀz
};

// Which code runs the block products and the step: the build's own target (SSE2 on x86-64),
// or, where the processor has it, AVX2 (4 doubles an instruction; chosen at run time, so the
// default build stays portable). The AVX2 path is compiled by GCC on x86 only, and not when AVX
// is on at compile time (-march=native: Eigen's own packets are then 4 wide). AVX2 does not include FMA, so no multiply and add are fused:
// both paths do the same IEEE operations in the same order per value and per sum, and give
// the same bits (tested).
enum class KernelPath { Portable, Avx2 };
// Avx2 where the processor has it, else Portable; decided at the first call. The environment
// variable SHATTER_LATTICE_KERNEL=portable forces Portable (the tests run the solver suites so,
// since on an AVX2 host the default run never takes that path).
KernelPath fastestKernelPath();
bool kernelPathAvailable(KernelPath path);

// x += α p; r −= α Ap; z = D⁻¹ ∘ r; then ‖r‖² and r·z, with exactly the bits of those five
// Eigen expressions evaluated one after the other (`x += alpha * p; r -= alpha * ap;
// r.squaredNorm(); z = inverseDiagonal.cwiseProduct(r); r.dot(z)`), in one pass over the
// vectors instead of five: the element-wise values are the same products and sums, and the two
// sums are added in the order Eigen's reduction adds a dynamic vector (two packet accumulators
// over pairs of packets, then an odd packet, the packet's lanes, the odd elements).
// CG's region solves spent a third of their own instructions in those passes.
// p, ap, inverseDiagonal, x, r and z have one size; z is resized to it.
StepSums conjugateGradientStep(double alpha, const Eigen::VectorXd& p, const Eigen::VectorXd& ap,
                               const Eigen::VectorXd& inverseDiagonal, Eigen::VectorXd& x, Eigen::VectorXd& r,
                               Eigen::VectorXd& z, KernelPath path = fastestKernelPath());

// r = b − ax, then ‖r‖, with exactly the bits of `r = b - ax; r.norm()` (the sum of squares in
// Eigen's order, as above), in one pass instead of two: a solve's measure of its residual after
// each round. b and ax have one size; r is resized to it and may not be either of them.
double residualAndNorm(const Eigen::VectorXd& b, const Eigen::VectorXd& ax, Eigen::VectorXd& r);

// Doubles a block keeps per particle sum: x, y, z and a pad lane that is never read, so one
// AVX2 register holds a particle's sum.
constexpr Eigen::Index kBlockStride = 4;

// A block of constraint rows (ConstraintSystem's copy of a region's rows), A = J M⁻¹ Jᵀ over
// them: each row's two ends (`ends[2k]`, `ends[2k + 1]`) as the address of their particle's sum
// (sums + kBlockStride × block particle; as an int offset, the scatter formed each end's address
// with one more instruction, a `lea`, 2 a row), its normal (3 doubles a row, and one more double after the
// last row: the AVX2 path loads 4 a row; the 4th is never read into a result), the
// particles' inverse masses, and their sums (kBlockStride doubles a particle), which a
// product leaves holding M⁻¹ Jᵀ x in x, y and z.
struct BlockRows {
    double* const* ends = nullptr;
    const double* normal = nullptr;
    Eigen::Index rows = 0;
    const double* inverseMass = nullptr;
    double* sums = nullptr;
    Eigen::Index particles = 0;
};

// y = A x (`rows` values each) in multiplyRows' operations and order (ConstraintSystem::multiply), so its
// bits: each particle's sum from zero, + n_k x_k at a first end and − at a second in row order,
// × the particle's 1/m, then n_k·(s_a − s_b) per row (Eigen's order: (d_x + d_y) + d_z of the products).
void multiplyBlock(const BlockRows& block, const double* x, double* y, KernelPath path = fastestKernelPath());

// The whole system's rows (ConstraintSystem::multiply): row k between particles a[k] and b[k],
// its normal (3 doubles a row, no pad), the particles' inverse masses; `sums` is scratch of
// kBlockStride doubles a particle that the AVX2 path uses (the portable one does not read it).
struct IndexedRows {
    const int* a = nullptr;
    const int* b = nullptr;
    const double* normal = nullptr;
    Eigen::Index rows = 0;
    const double* inverseMass = nullptr;
    Eigen::Index particles = 0;
    double* sums = nullptr;
};

// y = A x (`rows` values) and `acceleration` = M⁻¹ Jᵀ x (3 doubles a particle), in
// multiplyBlock's operations and order, so its bits (each particle's sum from zero, + n_k x_k at
// a first end and − at a second in row order, × 1/m, then n_k·(s_a − s_b) per row). The AVX2
// path runs multiplyBlock's kernel on the particle numbers: 52 M instructions of the Spot's
// frame 13 were this product on the plain path.
void multiplyIndexedRows(const IndexedRows& rows, const double* x, double* y, double* acceleration,
                         KernelPath path = fastestKernelPath());

// CG's new direction and its product: p = z + βp, then Ap and p·Ap, with exactly the bits of
// `p = z + beta * p; multiplyBlock(p, ap); p.dot(ap)` (the dot in Eigen's order, as above), in
// two passes over the rows instead of four: the product's scatter reads p in row order, so it
// forms p there, and its gather adds p·Ap as it forms Ap. With `z` null, p is taken as it is
// (CG's first direction, p = z already). p, z and ap hold `rows` values.
double multiplyDirection(const BlockRows& block, const double* z, double beta, double* p, double* ap,
                         KernelPath path = fastestKernelPath());

// Region CG's check whether its rows look decided (ConstraintSystem::solveRegion): whether on
// every row j the distance of x_j to the nearer end of its break range (lower_j, upper_j),
// `std::min(std::abs(x_j − lower_j), std::abs(upper_j − x_j))`, divided by
// rootInverseDiagonal_j, is above `reach` (false for NaN); the same divisions and comparisons
// as that plain loop, so the same answer. When it is true, `beyond` is also set if some x_j lies
// outside its range (x_j < lower_j or x_j > upper_j); when false, `beyond` is left as anything.
bool rowsLookDecided(Eigen::Index n, const double* x, const double* lower, const double* upper,
                     const double* rootInverseDiagonal, double reach, bool& beyond,
                     KernelPath path = fastestKernelPath());

} // namespace shatter::lattice
