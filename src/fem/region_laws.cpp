// One law per region of the mesh (see region_laws.hpp).
#include "tricot/fem/region_laws.hpp"

#include "tricot/core/error.hpp"

namespace tricot::fem {

RegionLaws::RegionLaws(std::vector<std::unique_ptr<Law>> laws, std::vector<std::string> prefixes,
                       std::vector<int> law_of_region)
    : laws_(std::move(laws)), prefixes_(std::move(prefixes)), law_of_region_(std::move(law_of_region)) {
  if (laws_.empty() || laws_.size() != prefixes_.size())
    throw InputError(Location{"", 0, "law.region"}, "one name per region law", std::to_string(prefixes_.size()),
                     std::to_string(laws_.size()));
  for (int k : law_of_region_)
    if (k < 0 || static_cast<size_t>(k) >= laws_.size())
      throw InputError(Location{"", 0, "law.region"}, "a region takes a law that is not there", std::to_string(k),
                       "0 to " + std::to_string(laws_.size() - 1));
  for (const auto& l : laws_) {
    offset_.push_back(count_);
    count_ += static_cast<int>(l->coefficients().size());
  }
}

RegionLaws::RegionLaws(const RegionLaws& other)
    : Law(other), prefixes_(other.prefixes_), law_of_region_(other.law_of_region_), offset_(other.offset_),
      count_(other.count_) {
  for (const auto& l : other.laws_) laws_.push_back(l->clone());
}

std::vector<std::string> RegionLaws::coefficient_names() const {
  std::vector<std::string> names;
  for (size_t r = 0; r < laws_.size(); ++r)
    for (const std::string& n : laws_[r]->coefficient_names())
      names.push_back(prefixes_[r].empty() ? n : prefixes_[r] + "." + n);
  return names;
}

Eigen::VectorXd RegionLaws::coefficients() const {
  Eigen::VectorXd c(count_);
  for (size_t r = 0; r < laws_.size(); ++r) {
    const Eigen::VectorXd cr = laws_[r]->coefficients();
    c.segment(offset_[r], cr.size()) = cr;
  }
  return c;
}

void RegionLaws::set_coefficients(const Eigen::VectorXd& c) {
  if (c.size() != count_)
    throw InputError(Location{"", 0, "law"}, "wrong number of coefficients for the region laws",
                     std::to_string(c.size()), std::to_string(count_));
  for (size_t r = 0; r < laws_.size(); ++r)
    laws_[r]->set_coefficients(c.segment(offset_[r], laws_[r]->coefficients().size()));
}

bool RegionLaws::linear_in_coefficients() const {
  for (const auto& l : laws_)
    if (!l->linear_in_coefficients()) return false;
  return true;
}

void RegionLaws::evaluate(const LawInput& in, const LawRequest& req, LawOutput& out) const {
  const size_t r = static_cast<size_t>(law_index(in.region));
  laws_[r]->evaluate(in, req, out);
  if (!req.sensitivities) return;
  std::vector<Mat2> own = std::move(out.dP_dc);
  out.dP_dc.assign(static_cast<size_t>(count_), Mat2::Zero());
  for (size_t k = 0; k < own.size(); ++k) out.dP_dc[static_cast<size_t>(offset_[r]) + k] = own[k];
}

}  // namespace tricot::fem
