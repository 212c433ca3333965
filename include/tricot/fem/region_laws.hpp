// Several materials in one specimen (docs/theory.md §5.2): one law per region of the mesh (a lesion in
// healthy skin, a seam in a knit). Each quadrature point evaluates the law of its element's region
// (LawInput::region, Mesh::region); the coefficients are the laws' in order, those of a named region's
// law prefixed "<region>.", so that a project identifies some of them and keeps the others fixed.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "tricot/fem/law.hpp"

namespace tricot::fem {

class RegionLaws : public Law {
 public:
  /// Region r (an index into Mesh::region_names) takes laws[law_of_region[r]]; law k's coefficients are
  /// named prefixes[k] + "." + its own ("" = no prefix: the specimen's own law, which the regions
  /// that no other law names share). At least one law, one prefix per law, every index valid.
  RegionLaws(std::vector<std::unique_ptr<Law>> laws, std::vector<std::string> prefixes, std::vector<int> law_of_region);
  RegionLaws(const RegionLaws& other);
  RegionLaws& operator=(const RegionLaws&) = delete;

  std::string name() const override { return "regions"; }
  std::vector<std::string> coefficient_names() const override;
  Eigen::VectorXd coefficients() const override;
  void set_coefficients(const Eigen::VectorXd& c) override;
  bool linear_in_coefficients() const override;
  /// The law of in.region (law 0 for a region out of range: a mesh without regions); dP_dc
  /// has every law's slots, zero outside that law's.
  void evaluate(const LawInput& in, const LawRequest& req, LawOutput& out) const override;
  std::unique_ptr<Law> clone() const override { return std::make_unique<RegionLaws>(*this); }

  /// The law that region `region` takes.
  const Law& law(int region) const { return *laws_.at(static_cast<size_t>(law_index(region))); }

 private:
  std::vector<std::unique_ptr<Law>> laws_;
  std::vector<std::string> prefixes_;
  std::vector<int> law_of_region_;
  int law_index(int region) const {
    return region >= 0 && static_cast<size_t>(region) < law_of_region_.size()
               ? law_of_region_[static_cast<size_t>(region)]
               : 0;
  }
  std::vector<int> offset_;  ///< first coefficient of each law
  int count_ = 0;
};

}  // namespace tricot::fem
