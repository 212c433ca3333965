// The FE's values of one test at the measured steps and points (docs/theory.md §7), with their derivatives
// with respect to the identified coefficients: shared by the objective and by synthetic data.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "tricot/fem/locate.hpp"
#include "tricot/fem/model.hpp"
#include "tricot/fem/solver.hpp"
#include "tricot/ident/experiment.hpp"

namespace tricot::ident::detail {

/// Values per step and point, with ∂/∂J (rows as the values) when asked.
struct Prediction {
  Eigen::VectorXd edge_displacement, edge_force;      // per step
  Eigen::MatrixXd dedge_displacement_dc, dedge_force_dc;  // steps × parameters
  Eigen::MatrixXd U, V;                               // steps × points
  Eigen::MatrixXd dU_dc, dV_dc;                       // (step · points + point) × parameters
};

/// The data's points located in the model's reference mesh. Throws InputError (key
/// `experiment.<test>.points`) saying how many are outside and naming the first.
std::vector<fem::Location> locate_points(const fem::TestModel& model, const TestData& data);

/// Fills `out` from a converged simulation of `model` for the steps and points of `data`
/// (`reference` = locate_points()). `coefficients` (law coefficient index per parameter) asks for
/// the derivatives; nullptr = values only. False with `message` when a point leaves the deformed
/// mesh (incremental data) or the FE gave no sensitivities.
bool predict(const fem::TestModel& model, const TestData& data, const std::vector<fem::Location>& reference,
             const fem::SimulationResult& sim, const std::vector<int>* coefficients, Prediction& out,
             std::string& message);

/// Field values stacked as GroupKind says: step-major, points inside; uv interleaves u and v.
Eigen::VectorXd stack(const Eigen::MatrixXd& F);
Eigen::VectorXd stack_uv(const Eigen::MatrixXd& U, const Eigen::MatrixXd& V);

}  // namespace tricot::ident::detail
