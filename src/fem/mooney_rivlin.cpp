// Incompressible Mooney–Rivlin membrane (see mooney_rivlin.hpp, docs/theory.md §5).
#include "tricot/fem/mooney_rivlin.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <limits>

#include "invalid_state.hpp"
#include "tricot/core/error.hpp"

namespace tricot::fem {
namespace {

double ipow(double x, int n) {
  double r = 1;
  for (int k = 0; k < n; ++k) r *= x;
  return r;
}

std::string term_name(const MooneyRivlinTerm& t) {
  std::string n = "C";
  n += std::to_string(t.i);
  n += std::to_string(t.j);
  return n;
}

/// ∂W/∂I1, ∂W/∂I2 and the second derivatives, at x1 = I1 − 3, x2 = I2 − 3.
struct EnergyDerivatives {
  double W1 = 0, W2 = 0, W11 = 0, W12 = 0, W22 = 0;
};

/// The derivatives of one term with C = 1 (the basis of ∂P/∂C_ij).
EnergyDerivatives term_derivatives(const MooneyRivlinTerm& t, double x1, double x2) {
  EnergyDerivatives d;
  const int i = t.i, j = t.j;
  if (i >= 1) d.W1 = i * ipow(x1, i - 1) * ipow(x2, j);
  if (j >= 1) d.W2 = j * ipow(x1, i) * ipow(x2, j - 1);
  if (i >= 2) d.W11 = i * (i - 1) * ipow(x1, i - 2) * ipow(x2, j);
  if (i >= 1 && j >= 1) d.W12 = i * j * ipow(x1, i - 1) * ipow(x2, j - 1);
  if (j >= 2) d.W22 = j * (j - 1) * ipow(x1, i) * ipow(x2, j - 2);
  return d;
}

EnergyDerivatives derivatives(const std::vector<MooneyRivlinTerm>& terms, double I1, double I2) {
  // Powers of x1 = I1 − 3 and x2 = I2 − 3 up to the largest exponent (9), shared by every term.
  double p1[10], p2[10];
  p1[0] = p2[0] = 1;
  for (int k = 1; k < 10; ++k) p1[k] = p1[k - 1] * (I1 - 3), p2[k] = p2[k - 1] * (I2 - 3);
  EnergyDerivatives sum;
  for (const auto& t : terms) {
    const int i = t.i, j = t.j;
    if (i >= 1) sum.W1 += t.C * i * p1[i - 1] * p2[j];
    if (j >= 1) sum.W2 += t.C * j * p1[i] * p2[j - 1];
    if (i >= 2) sum.W11 += t.C * i * (i - 1) * p1[i - 2] * p2[j];
    if (i >= 1 && j >= 1) sum.W12 += t.C * i * j * p1[i - 1] * p2[j - 1];
    if (j >= 2) sum.W22 += t.C * j * (j - 1) * p1[i] * p2[j - 2];
  }
  return sum;
}

}  // namespace

MooneyRivlin::MooneyRivlin(std::vector<MooneyRivlinTerm> terms) : terms_(std::move(terms)) {
  // Keys: the config's (`[law.mooney_rivlin]` terms, values), so that no caller renames them.
  for (std::size_t k = 0; k < terms_.size(); ++k) {
    const auto& t = terms_[k];
    const std::string name = term_name(t);
    if (t.i < 0 || t.i > 9 || t.j < 0 || t.j > 9 || (t.i == 0 && t.j == 0))
      throw InputError(Location{"", 0, "law.mooney_rivlin.terms"},
                       "bad Mooney–Rivlin exponents of term " + std::to_string(k + 1),
                       "(" + std::to_string(t.i) + ", " + std::to_string(t.j) + ")", "0–9 each, not both 0");
    if (!std::isfinite(t.C))
      throw InputError(Location{"", 0, "law.mooney_rivlin.values"}, name + " is not a finite number",
                       std::to_string(t.C), "a finite N/mm");
    for (std::size_t m = 0; m < k; ++m)
      if (terms_[m].i == t.i && terms_[m].j == t.j)
        throw InputError(Location{"", 0, "law.mooney_rivlin.terms"}, "coefficient given twice", name,
                         "each C<i><j> once");
  }
}

std::vector<std::string> MooneyRivlin::coefficient_names() const {
  std::vector<std::string> n;
  for (const auto& t : terms_) n.push_back(term_name(t));
  return n;
}

Eigen::VectorXd MooneyRivlin::coefficients() const {
  Eigen::VectorXd c(terms_.size());
  for (std::size_t k = 0; k < terms_.size(); ++k) c(k) = terms_[k].C;
  return c;
}

void MooneyRivlin::set_coefficients(const Eigen::VectorXd& c) {
  if (c.size() != static_cast<Eigen::Index>(terms_.size()))
    throw InputError(Location{"", 0, "law.mooney_rivlin"}, "wrong number of Mooney–Rivlin coefficients",
                     std::to_string(c.size()), std::to_string(terms_.size()));
  for (std::size_t k = 0; k < terms_.size(); ++k) terms_[k].C = c(k);
}

// docs/theory.md §5. With C₂ = FᵀF, J2 = det C₂ and C₂⁻¹:
//   ∂I1/∂C₂ = G1 = I − C₂⁻¹/J2,   ∂I2/∂C₂ = G2 = I/J2 + (J2 − tr C₂/J2) C₂⁻¹,
//   S₂ = 2 (W1 G1 + W2 G2),  P = F S₂.
// Tangent in closed form: dS₂ = 𝕃 : dC₂ with
//   𝕃/2 = G1⊗(W11 G1 + W12 G2) + G2⊗(W12 G1 + W22 G2) + c C₂⁻¹⊗C₂⁻¹ − (W2/J2)(I⊗C₂⁻¹ + C₂⁻¹⊗I) + β C₂⁻¹⊙C₂⁻¹,
//   c = W1/J2 + W2 (J2 + tr C₂/J2),  β = W1/J2 − W2 (J2 − tr C₂/J2),  (X⊙X)[dC] = X dC X,
// and dC₂ = dFᵀF + FᵀdF, so that A_ijkl = δ_ik S_lj + 2 Σ (F X)_ij (F Y)_kl over the X⊗Y terms
// + 2β [(F C₂⁻¹)_il (F C₂⁻¹)_kj + (F C₂⁻¹ Fᵀ)_ik C₂⁻¹_lj].
void MooneyRivlin::evaluate(const LawInput& in, const LawRequest& req, LawOutput& out) const {
  const Mat2& F = in.F;
  const double detF = F.determinant();
  if (detail::invalid_state(detF, req, terms_.size(), out)) return;
  const Mat2 I = Mat2::Identity();
  const Mat2 C = F.transpose() * F;
  const double J2 = detF * detF;
  const double trC = C.trace();
  const Mat2 Ci = C.inverse();
  const double I1 = trC + 1 / J2;
  const double I2 = trC / J2 + J2;
  const Mat2 G1 = I - Ci / J2;
  const Mat2 G2 = I / J2 + (J2 - trC / J2) * Ci;
  const EnergyDerivatives d = derivatives(terms_, I1, I2);
  const Mat2 FCi = F * Ci;
  const Mat2 FG1 = F - FCi / J2, FG2 = F / J2 + (J2 - trC / J2) * FCi;
  const Mat2 S = 2 * (d.W1 * G1 + d.W2 * G2);
  out.P = 2 * (d.W1 * FG1 + d.W2 * FG2);
  out.lambda3 = 1 / detF;

  if (req.tangent) {
    const Vec4 g1 = flatten(FG1), g2 = flatten(FG2), ci = flatten(FCi), f = flatten(F);
    const double c = d.W1 / J2 + d.W2 * (J2 + trC / J2), beta = d.W1 / J2 - d.W2 * (J2 - trC / J2);
    Mat4& A = out.A;
    A.noalias() = g1 * (4 * (d.W11 * g1 + d.W12 * g2)).transpose();
    A.noalias() += g2 * (4 * (d.W12 * g1 + d.W22 * g2)).transpose();
    A.noalias() += (4 * c) * ci * ci.transpose();
    A.noalias() -= (4 * d.W2 / J2) * (f * ci.transpose() + ci * f.transpose());
    const Mat2 B = FCi * F.transpose();
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j)
        for (int k = 0; k < 2; ++k)
          for (int l = 0; l < 2; ++l)
            A(2 * i + j, 2 * k + l) +=
                2 * beta * (FCi(i, l) * FCi(k, j) + B(i, k) * Ci(l, j)) + (i == k ? S(l, j) : 0.0);
  }
  if (req.sensitivities) {
    out.dP_dc.resize(terms_.size());
    for (std::size_t k = 0; k < terms_.size(); ++k) {
      const EnergyDerivatives b = term_derivatives(terms_[k], I1 - 3, I2 - 3);
      out.dP_dc[k] = 2 * (b.W1 * FG1 + b.W2 * FG2);
    }
  } else {
    out.dP_dc.clear();
  }
}

std::vector<MooneyRivlinTerm> paper_mooney_rivlin_terms() {
  return {{1, 0, 0.1}, {2, 0, -0.025}, {2, 1, 0.015}, {0, 3, 0.01}};
}

// docs/theory.md §5 closed forms, principal stretches (λ1, λ2, λ3) with λ1λ2λ3 = 1.
double mooney_rivlin_nominal_stress(const std::vector<MooneyRivlinTerm>& terms, HomogeneousMode mode, double lambda) {
  const double l = lambda;
  switch (mode) {
    case HomogeneousMode::uniaxial: {
      const EnergyDerivatives d = derivatives(terms, l * l + 2 / l, 2 * l + 1 / (l * l));
      return 2 * (l - 1 / (l * l)) * (d.W1 + d.W2 / l);
    }
    case HomogeneousMode::equibiaxial: {
      const EnergyDerivatives d = derivatives(terms, 2 * l * l + std::pow(l, -4), std::pow(l, 4) + 2 / (l * l));
      return 2 * (l - std::pow(l, -5)) * (d.W1 + l * l * d.W2);
    }
    case HomogeneousMode::pure_shear: {
      const double I = l * l + 1 + 1 / (l * l);
      const EnergyDerivatives d = derivatives(terms, I, I);
      return 2 * (l - std::pow(l, -3)) * (d.W1 + d.W2);
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace tricot::fem
