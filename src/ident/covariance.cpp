// Gauss–Newton covariance and identifiability (docs/theory.md §8), through the SVD of the Jacobian in
// relative units so that a badly scaled problem does not lose digits in SᵀS.
#include "tricot/ident/covariance.hpp"

#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>

namespace tricot::ident {

namespace {
// Singular values below this fraction of the largest count as zero (the data cannot see them).
constexpr double kRankTolerance = 1e-12;
}  // namespace

Uncertainty uncertainty(const Eigen::MatrixXd& S, const Eigen::VectorXd& r, const Eigen::VectorXd& J,
                        const Eigen::VectorXd& scale, const Eigen::VectorXd& variance) {
  const Eigen::Index N = S.rows(), n = S.cols();
  const double inf = std::numeric_limits<double>::infinity();
  Uncertainty u;
  Eigen::VectorXd D(n);  // relative units: δJ_k = D_k · δz_k
  for (Eigen::Index k = 0; k < n; ++k) D(k) = J(k) != 0 ? std::abs(J(k)) : scale(k);
  const Eigen::MatrixXd S_rel = S * D.asDiagonal();
  // Σ and V are those of R in S_rel = Q R (U is never needed: the sandwich below is written with V).
  // The SVD of the n × n R avoids JacobiSVD's preconditioner on the tall S_rel, which crashed (a write
  // to address 0) for the 19 215 × 14 Jacobian of the campaign with the stability barrier (issue 12)
  // and for the 31 310 × 6 of the cruciform with per-point σ.
  Eigen::MatrixXd R(0, n);
  if (N > n) {
    // R by QR of blocks of at most kBlock rows, each stacked under the last R (a tall-skinny QR): no
    // Householder vector longer than kBlock + n, below Eigen's stack-allocation limit of 16 384
    // doubles; the crash was in the heap branch of a longer one.
    constexpr Eigen::Index kBlock = 8192;
    for (Eigen::Index start = 0; start < N; start += kBlock) {
      const Eigen::Index rows = std::min(kBlock, N - start);
      Eigen::MatrixXd stacked(R.rows() + rows, n);
      stacked << R, S_rel.middleRows(start, rows);
      const Eigen::Index keep = std::min(n, stacked.rows());
      R = Eigen::HouseholderQR<Eigen::MatrixXd>(stacked).matrixQR().topRows(keep).triangularView<Eigen::Upper>();
    }
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(N > n ? R : S_rel, Eigen::ComputeThinV);
  u.singular_values = svd.singularValues();
  const double smax = n > 0 ? u.singular_values(0) : 0, smin = n > 0 ? u.singular_values(n - 1) : 0;
  u.full_rank = smin > kRankTolerance * smax && smax > 0;
  u.condition_number = u.full_rank ? smax / smin : inf;
  if (n > 0) {
    u.least_identifiable = svd.matrixV().col(n - 1);
    Eigen::Index big;
    u.least_identifiable.cwiseAbs().maxCoeff(&big);
    if (u.least_identifiable(big) < 0) u.least_identifiable = -u.least_identifiable;
  }

  // (S_relᵀ S_rel)⁺ = V Σ⁻² Vᵀ over the non-zero singular values.
  const Eigen::MatrixXd& V = svd.matrixV();
  Eigen::VectorXd inv(n);
  for (Eigen::Index k = 0; k < n; ++k)
    inv(k) = u.singular_values(k) > kRankTolerance * smax && smax > 0 ? 1 / u.singular_values(k) : 0;
  Eigen::MatrixXd cov_rel, shape;  // shape: cov_rel up to a factor, for the correlation when σ̂² = 0
  if (variance.size() == N && N > 0) {
    // Sandwich: (SᵀS)⁺ Sᵀ diag(var) S (SᵀS)⁺, with (SᵀS)⁺ = V Σ⁻² Vᵀ (= V Σ⁻¹ Uᵀ diag(var) U Σ⁻¹ Vᵀ).
    u.from_sigma = true;
    u.sigma2 = 1;
    const Eigen::MatrixXd P = V * inv.cwiseAbs2().asDiagonal() * V.transpose();
    const Eigen::MatrixXd meat = S_rel.transpose() * variance.asDiagonal() * S_rel;  // n × n
    cov_rel = P * meat * P;
    shape = cov_rel;
  } else {
    u.sigma2 = N > n ? r.squaredNorm() / static_cast<double>(N - n) : std::numeric_limits<double>::quiet_NaN();
    shape = V * inv.cwiseAbs2().asDiagonal() * V.transpose();
    cov_rel = u.sigma2 * shape;
  }
  u.covariance = D.asDiagonal() * cov_rel * D.asDiagonal();
  u.std_error = u.covariance.diagonal().cwiseMax(0).cwiseSqrt();
  // A parameter with a component along an unseen direction has no finite error.
  for (Eigen::Index j = 0; j < n; ++j)
    if (inv(j) == 0)
      for (Eigen::Index k = 0; k < n; ++k)
        if (std::abs(V(k, j)) > 1e-8) u.std_error(k) = inf;
  u.correlation.resize(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index k = 0; k < n; ++k)
      u.correlation(i, k) = std::isfinite(u.std_error(i)) && std::isfinite(u.std_error(k))
                                ? shape(i, k) / std::sqrt(shape(i, i) * shape(k, k))
                                : std::numeric_limits<double>::quiet_NaN();
  return u;
}

}  // namespace tricot::ident
