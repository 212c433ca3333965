// FE state → VTU grid (io::VtuGrid): the deformed mesh, the displacement at the nodes, and per
// element the Cauchy stress and the Green–Lagrange strain averaged over its Gauss points.
#pragma once

#include <Eigen/Core>

#include "tricot/fem/law.hpp"
#include "tricot/fem/mesh.hpp"
#include "tricot/io/vtu.hpp"

namespace tricot::project {

/// Points at x = X + u (z = 0); point data `displacement` (u_x, u_y, 0) [mm]; cell data
/// `cauchy_stress` σ [N/mm, force per current width; row-major 3×3, σ_i3 = 0] and
/// `green_lagrange_strain` E [row-major 3×3, E33 = (λ3² − 1)/2 from the law's plane-stress λ3], both
/// averaged over the element's Gauss points with their area weights. A Gauss point where the law
/// fails (an inverted element) gives NaN.
io::VtuGrid fem_vtu_grid(const fem::Mesh& mesh, const Eigen::VectorXd& u, const fem::Law& law,
                         double material_angle_deg);

}  // namespace tricot::project
