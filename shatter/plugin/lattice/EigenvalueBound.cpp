#include <shatter/plugin/lattice/EigenvalueBound.h>

#include <Eigen/SparseCholesky>

#include <algorithm>
#include <limits>
#include <vector>

namespace shatter::lattice {

double scaledEigenvalueLowerBound(const ConstraintSystem& system) {
    const int n = system.rowCount();
    if (n == 0) return 0.0;
    Eigen::SparseMatrix<double> a = system.assemble();
    const Eigen::VectorXd scale = a.diagonal().cwiseSqrt().cwiseInverse();
    a = scale.asDiagonal() * a * scale.asDiagonal();
    const Eigen::SparseMatrix<double> identity = [&] {
        Eigen::SparseMatrix<double> i(n, n);
        i.setIdentity();
        return i;
    }();
    // Â - σI has a Cholesky factor exactly when σ < λ_min(Â) (Â's diagonal is 1, so λ_min ≤ 1).
    // In floating point, a factorisation that succeeds proves Â + E - σI positive definite for
    // an E with |E_ij| ≤ γ_c (|L||Lᵀ|)_ij ≤ γ_c, γ_c = c·u/(1 - c·u), c the longest row of L
    // (the inner products that make row k of L run over that row's entries)
    // (Demmel's bound; the rows of |L| have norm √Â_ii ≤ 1). So ‖E‖ ≤ n·γ_c (row sums), and
    // forming Â and Â - σI adds a few units of rounding per entry. The bound keeps 0.9σ and
    // requires n·γ_c to be below the tenth left as margin.
    Eigen::SimplicialLLT<Eigen::SparseMatrix<double>> llt;
    llt.analyzePattern(a);
    for (double sigma = 0.5; sigma >= 1.0 / 4096.0; sigma *= 0.5) {
        llt.factorize(a - sigma * identity);
        if (llt.info() != Eigen::Success) continue;
        const auto& factor = llt.matrixL().nestedExpression(); // column-major: count entries by row
        std::vector<Eigen::Index> perRow(size_t(n), 0);
        for (Eigen::Index k = 0; k < factor.outerIndexPtr()[factor.outerSize()]; ++k) ++perRow[size_t(factor.innerIndexPtr()[k])];
        const Eigen::Index longest = *std::max_element(perRow.begin(), perRow.end());
        const double cu = double(longest + 8) * std::numeric_limits<double>::epsilon();
        return n * cu / (1.0 - cu) < 0.1 * sigma ? 0.9 * sigma : 0.0;
    }
    return 0.0;
}

} // namespace shatter::lattice
