// Identifiability report and optimal test design (docs/theory.md §8, beyond the paper).
#include "tricot/ident/identifiability.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>

#include "tricot/core/error.hpp"

namespace tricot::ident {

namespace {

constexpr double kRidge = 1e-12;  // relative regularisation of a singular M (rank only, not values)

Eigen::VectorXd relative_units(const Eigen::VectorXd& J, const Eigen::VectorXd& scale) {
  Eigen::VectorXd D(J.size());
  for (Eigen::Index k = 0; k < J.size(); ++k) D(k) = J(k) != 0 ? std::abs(J(k)) : scale(k);
  return D;
}

/// M⁻¹ through the eigen-decomposition; +inf on the diagonal along null directions.
Eigen::VectorXd inverse_diagonal(const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>& es) {
  const Eigen::VectorXd& l = es.eigenvalues();
  const Eigen::MatrixXd& V = es.eigenvectors();
  const double lmax = l.size() ? l(l.size() - 1) : 0;
  Eigen::VectorXd d = Eigen::VectorXd::Zero(l.size());
  for (Eigen::Index j = 0; j < l.size(); ++j) {
    if (!(l(j) > kRidge * lmax)) {
      for (Eigen::Index k = 0; k < l.size(); ++k)
        if (std::abs(V(k, j)) > 1e-8) d(k) = std::numeric_limits<double>::infinity();
      continue;
    }
    d += V.col(j).cwiseAbs2() / l(j);
  }
  return d;
}

}  // namespace

void IdentifiabilityOptions::validate() const {
  if (!(pinned_relative_error > 0))  // the open end, first so that the message says so
    throw InputError(Location{"", 0, "identifiability.pinned_relative_error"}, "out of range",
                     format_number(pinned_relative_error), "> 0");
  check_ranges(*this);
  if (!(sigma2 > 0) || !std::isfinite(sigma2))
    throw InputError(Location{"", 0, "identifiability.sigma2"}, "out of range", format_number(sigma2), "> 0");
}

const char* to_string(DesignCriterion c) { return c == DesignCriterion::d_optimal ? "d_optimal" : "a_optimal"; }

IdentifiabilityReport identifiability(const Eigen::MatrixXd& S, const Eigen::VectorXd& J, const Eigen::VectorXd& scale,
                                      const std::vector<std::vector<int>>& rows_of_test,
                                      const IdentifiabilityOptions& options) {
  options.validate();
  if (S.cols() != J.size() || scale.size() != J.size())
    throw InputError(Location{"", 0, "identifiability.jacobian"}, "the Jacobian's columns, J and scale disagree",
                     std::to_string(S.cols()) + ", " + std::to_string(J.size()) + ", " + std::to_string(scale.size()),
                     "one column and one scale per coefficient");
  for (const auto& rows : rows_of_test)
    for (int i : rows)
      if (i < 0 || i >= S.rows())
        throw InputError(Location{"", 0, "identifiability.rows"}, "a test's row is outside the Jacobian",
                         std::to_string(i), "0 to " + std::to_string(S.rows() - 1));
  const Eigen::VectorXd D = relative_units(J, scale);
  const Eigen::MatrixXd A = S * D.asDiagonal();
  const Eigen::MatrixXd M = A.transpose() * A;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(M);
  IdentifiabilityReport r;
  const Eigen::Index n = M.rows();
  r.relative_std_error = (options.sigma2 * inverse_diagonal(es)).cwiseSqrt();
  for (Eigen::Index k = 0; k < n; ++k) r.pinned.push_back(r.relative_std_error(k) < options.pinned_relative_error);
  if (n > 0) {
    r.smallest_eigenvalue = es.eigenvalues()(0), r.largest_eigenvalue = es.eigenvalues()(n - 1);
    r.least_identifiable = es.eigenvectors().col(0);
    Eigen::Index big;
    r.least_identifiable.cwiseAbs().maxCoeff(&big);
    if (r.least_identifiable(big) < 0) r.least_identifiable = -r.least_identifiable;
  }
  const double tr = M.trace();
  const double weak = n > 0 ? r.least_identifiable.dot(M * r.least_identifiable) : 0;
  for (const auto& rows : rows_of_test) {
    double t = 0, w = 0;
    for (int i : rows) {
      const Eigen::VectorXd a = A.row(i).transpose();
      t += a.squaredNorm();
      if (n > 0) w += std::pow(a.dot(r.least_identifiable), 2);
    }
    r.trace_share.push_back(tr > 0 ? t / tr : 0);
    r.weak_direction_share.push_back(weak > 0 ? w / weak : 0);
  }
  return r;
}

DesignSuggestion suggest_test(const Eigen::MatrixXd& S, const Eigen::VectorXd& J, const Eigen::VectorXd& scale,
                              const std::vector<DesignCandidate>& candidates, DesignCriterion criterion) {
  if (candidates.empty())
    throw InputError(Location{"", 0, "design.candidates"}, "no candidate test", "0", "at least one");
  for (const auto& c : candidates)
    if (c.S.cols() != S.cols())
      throw InputError(Location{"", 0, "design.candidates"},
                       "candidate '" + c.name + "' has the wrong number of columns", std::to_string(c.S.cols()),
                       std::to_string(S.cols()));
  if (S.cols() != J.size() || scale.size() != J.size())
    throw InputError(Location{"", 0, "design.jacobian"}, "the Jacobian's columns, J and scale disagree",
                     std::to_string(S.cols()) + ", " + std::to_string(J.size()) + ", " + std::to_string(scale.size()),
                     "one column and one scale per coefficient");
  const Eigen::VectorXd D = relative_units(J, scale);
  const Eigen::MatrixXd A = S * D.asDiagonal();
  const Eigen::MatrixXd M = A.transpose() * A;
  const Eigen::Index n = M.rows();
  const Eigen::MatrixXd ridge = kRidge * std::max(M.trace(), 1e-300) * Eigen::MatrixXd::Identity(n, n);
  auto worst = [&](const Eigen::MatrixXd& Mi) {
    return std::sqrt(inverse_diagonal(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Mi)).maxCoeff());
  };
  DesignSuggestion s;
  s.worst_std_error_now = worst(M);
  double best = 0;
  for (size_t c = 0; c < candidates.size(); ++c) {
    const Eigen::MatrixXd Ac = candidates[c].S * D.asDiagonal();
    const Eigen::MatrixXd Mc = M + Ac.transpose() * Ac;
    Eigen::LDLT<Eigen::MatrixXd> ldlt(Mc);
    const Eigen::VectorXd piv = ldlt.vectorD();
    if (!(piv.minCoeff() > kRidge * std::max(piv.cwiseAbs().maxCoeff(), 1e-300))) ldlt.compute(Mc + ridge);  // singular
    double score;
    if (criterion == DesignCriterion::d_optimal) {
      score = ldlt.vectorD().array().abs().log().sum();
    } else {
      score = ldlt.solve(Eigen::MatrixXd::Identity(n, n)).trace();
    }
    s.score.push_back(score);
    s.worst_std_error_with.push_back(worst(Mc));
    const bool better = criterion == DesignCriterion::d_optimal ? score > best : score < best;
    if (s.best < 0 || better) s.best = static_cast<int>(c), best = score;
  }
  return s;
}

}  // namespace tricot::ident
