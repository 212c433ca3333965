// Eq. (1) scaling of the data groups (docs/theory.md §2).
#include "tricot/ident/groups.hpp"

#include <cmath>
#include <string>

#include "tricot/core/error.hpp"

namespace tricot::ident {

const char* to_string(GroupKind k) {
  switch (k) {
    case GroupKind::edge_displacement: return "edge_displacement";
    case GroupKind::edge_force: return "edge_force";
    case GroupKind::field_u: return "field_u";
    case GroupKind::field_v: return "field_v";
    case GroupKind::field_uv: return "field_uv";
  }
  return "?";
}

const DataGroup& ScaledResiduals::add(const std::string& name, GroupKind kind, int test, const Eigen::VectorXd& y_exp,
                                      double weight, double sigma) {
  const Location where{"", 0, "data." + name};
  if (y_exp.size() == 0) throw InputError(where, "empty data group");
  if (!y_exp.allFinite()) throw InputError(where, "non-finite data");
  if (!(weight >= 0) || !std::isfinite(weight))
    throw InputError(where, "weight out of range", std::to_string(weight), ">= 0");
  if (!(sigma >= 0) || !std::isfinite(sigma))
    throw InputError(where, "sigma out of range", std::to_string(sigma), ">= 0");
  DataGroup g;
  g.name = name;
  g.kind = kind;
  g.test = test;
  g.offset = size();
  g.size = static_cast<int>(y_exp.size());
  g.weight = weight;
  g.sigma = sigma > 0 && !fixed_;
  g.scale = fixed_      ? 1.0
            : sigma > 0 ? sigma
                        : std::sqrt(y_exp.squaredNorm() / g.size);  // docs/theory.md §2 [choice]: RMS
  if (!(g.scale > 0)) throw InputError(where, "all data are zero, so the group has no scale: give its sigma");
  if (!std::isfinite(g.scale))  // the sum of squares overflowed: the group would silently weigh 0
    throw InputError(where, "the group's RMS overflows",
                     "largest |value| " + format_number(y_exp.cwiseAbs().maxCoeff()),
                     "values whose squares sum to a finite number");
  const Eigen::Index n0 = measured_.size();
  measured_.conservativeResize(n0 + g.size);
  measured_.tail(g.size) = y_exp;
  factor_.conservativeResize(n0 + g.size);
  factor_.tail(g.size).setConstant(fixed_ ? std::sqrt(weight) : std::sqrt(weight / g.size) / g.scale);
  row_weight_.conservativeResize(n0 + g.size);
  row_weight_.tail(g.size).setOnes();
  groups_.push_back(g);
  return groups_.back();
}

const DataGroup& ScaledResiduals::add(const std::string& name, GroupKind kind, int test, const Eigen::VectorXd& y_exp,
                                      double weight, const Eigen::VectorXd& sigma_per_value) {
  const Location where{"", 0, "data." + name};
  if (fixed_) throw InputError(where, "a σ per value and fixed weights do not mix", "fixed weights", "scaled groups");
  if (sigma_per_value.size() != y_exp.size())
    throw InputError(where, "one sigma per value", std::to_string(sigma_per_value.size()),
                     std::to_string(y_exp.size()));
  for (Eigen::Index i = 0; i < sigma_per_value.size(); ++i)
    if (!(sigma_per_value(i) > 0) || !std::isfinite(sigma_per_value(i)))
      throw InputError(where, "sigma of value " + std::to_string(i) + " out of range",
                       format_number(sigma_per_value(i)), "> 0");
  const double rms = std::sqrt(sigma_per_value.squaredNorm() / double(sigma_per_value.size()));
  add(name, kind, test, y_exp, weight, rms);
  DataGroup& g = groups_.back();
  factor_.segment(g.offset, g.size) = sigma_per_value.cwiseInverse() * std::sqrt(weight / g.size);
  return g;
}

Eigen::VectorXd ScaledResiduals::residuals(const Eigen::VectorXd& y) const {
  return factor_.cwiseProduct(y - measured_);
}

void ScaledResiduals::scale_rows(Eigen::MatrixXd& dy_dJ) const { dy_dJ = factor_.asDiagonal() * dy_dJ; }

double ScaledResiduals::chi_square(const Eigen::VectorXd& r) const {
  double chi2 = 0;
  for (const DataGroup& g : groups_) {
    if (!g.sigma || !(g.weight > 0) || r.size() < g.offset + g.size) return NAN;
    chi2 += g.size / g.weight * r.segment(g.offset, g.size).squaredNorm();
  }
  return chi2;
}

Eigen::VectorXd ScaledResiduals::sigma_variance() const {
  for (const DataGroup& g : groups_)
    if (!g.sigma) return {};
  Eigen::VectorXd var(size());
  for (const DataGroup& g : groups_) var.segment(g.offset, g.size).setConstant(g.weight / g.size);
  return var.cwiseProduct(row_weight_);
}

void ScaledResiduals::weight_rows(const DataGroup& g, const Eigen::VectorXd& omega) {
  const Location where{"", 0, "data." + g.name};
  if (omega.size() != g.size)
    throw InputError(where, "one weight per value", std::to_string(omega.size()), std::to_string(g.size));
  if (!omega.allFinite() || !(omega.minCoeff() >= 0))
    throw InputError(where, "row weights out of range", "", "finite, >= 0");
  factor_.segment(g.offset, g.size).array() *= omega.array().sqrt();
  row_weight_.segment(g.offset, g.size).array() *= omega.array();
}

}  // namespace tricot::ident
